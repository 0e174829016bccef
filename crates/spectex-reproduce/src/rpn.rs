//! Galerne, Gousseau & Morel (IPOL), Random Phase Noise: the modulus kept exactly, the colour
//! phase differences kept (no false colours), the variance through the spot extension, the
//! periodic component and its smooth part, and the cost in FFT equivalents.

use ndarray::{Array2, Array3, ArrayView2, Axis};
use num_complex::Complex64;
use spectex_spectrum::periodic::periodic_spectrum_packed;
use spectex_spectrum::{
    Fft2, Rpn, RpnOptions, interior_laplacian, mean_variance, periodic_laplacian, periodic_smooth,
    random_phase_field, rpn,
};

use crate::plot::{bar_plot, grey_png_auto, planes_png, spectrum_png};
use crate::table1::best_of;
use crate::{Context, Effort, Expect, Panel, Result, Session, grey};

pub(crate) fn reproduce(s: &mut Session<'_>) -> Result<()> {
    let mut exemplars = vec![("built-in".to_owned(), crate::builtin_exemplar()?)];
    if s.effort() != Effort::Tiny
        && let Some(img) = s.shared_texture("embark_ts_water_1.jpg")?
    {
        exemplars.push(("embark_ts_water_1.jpg".to_owned(), img));
    }
    s.step("modulus and phase differences");
    same_size(s, &exemplars)?;
    s.step("spot extension");
    extension(s, &exemplars)?;
    s.step("periodic + smooth decomposition");
    periodic(s, &exemplars[exemplars.len() - 1].1)?;
    s.step("cost in FFT equivalents");
    cost(s)
}

fn dft(a: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> Array2<Complex64> {
    let mut z = a.mapv(|v| Complex64::new(v, 0.0));
    fft.forward(&mut z);
    z
}

/// The DFT of a channel's periodic component (one channel, unpacked).
fn periodic_dft(a: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> Array2<Complex64> {
    periodic_spectrum_packed(a, None, fft)
}

fn same_size(s: &mut Session<'_>, exemplars: &[(String, Array3<f64>)]) -> Result<()> {
    let mut fft = Fft2::new();
    let (mut modulus, mut phase) = (0.0f64, 0.0f64);
    let mut panels = Vec::new();
    for (name, ex) in exemplars {
        let out = rpn(
            ex.view(),
            &RpnOptions {
                seed: 11,
                ..RpnOptions::default()
            },
        )
        .ctx("RPN")?;
        let c = ex.dim().0;
        let want: Vec<_> = (0..c)
            .map(|k| periodic_dft(ex.index_axis(Axis(0), k), &mut fft))
            .collect();
        let got: Vec<_> = (0..c)
            .map(|k| dft(out.index_axis(Axis(0), k), &mut fft))
            .collect();
        for k in 0..c {
            let scale = want[k].iter().map(|z| z.norm()).fold(0.0, f64::max);
            for (a, b) in want[k].iter().zip(got[k].iter()) {
                modulus = modulus.max((a.norm() - b.norm()).abs() / scale);
            }
        }
        for k in 1..c {
            let scale = want[0].iter().map(|z| z.norm()).fold(0.0, f64::max)
                * want[k].iter().map(|z| z.norm()).fold(0.0, f64::max);
            for ((a0, ak), (b0, bk)) in want[0]
                .iter()
                .zip(want[k].iter())
                .zip(got[0].iter().zip(got[k].iter()))
            {
                let w = ak * a0.conj();
                if w.norm() < 1e-6 * scale {
                    continue;
                }
                let g = bk * b0.conj();
                phase = phase.max((g / w).arg().abs());
            }
        }
        let slug: String = name.chars().take_while(|c| *c != '.').collect();
        let (path, file) = s.file(&format!("rpn-{slug}-sample.png"));
        planes_png(&path, ex)?;
        panels.push(Panel {
            file,
            label: format!("sample {name}"),
        });
        let (path, file) = s.file(&format!("rpn-{slug}-rpn.png"));
        planes_png(&path, &out.mapv(|v| v.clamp(0.0, 1.0)))?;
        panels.push(Panel {
            file,
            label: "RPN, same size".into(),
        });
    }
    s.claim(
        "rpn-modulus",
        "RPN algorithm, step 3",
        "RPN adds a random phase to the DFT of the (periodic component of the) sample: the DFT \
         modulus is kept at every frequency (max deviation below 1e-9 of the largest modulus)",
        "exact",
        format!("max |‖Û‖ − ‖P̂‖| / max ‖P̂‖ = {modulus:.1e}"),
        Some("cargo test -p spectex-spectrum same_size_rpn_properties"),
        modulus < 1e-9,
        Expect::Holds,
    );
    s.claim(
        "rpn-colour-phases",
        "RPN of a colour image",
        "\"Adding the same random phase to the original phases of each color channel preserves \
         the phase displacements between channels … without creating false colors\"",
        "phase differences kept",
        if exemplars.iter().any(|e| e.1.dim().0 == 3) {
            format!("max change of a channel-to-channel phase difference: {phase:.1e} rad")
        } else {
            "no colour exemplar".into()
        },
        Some("cargo test -p spectex-spectrum same_size_rpn_properties"),
        phase < 1e-6,
        Expect::Holds,
    );
    s.figure(
        "RPN (same size)",
        "Samples and their same-size Random Phase Noise (seed 11).".into(),
        panels,
        None,
    );
    Ok(())
}

fn extension(s: &mut Session<'_>, exemplars: &[(String, Array3<f64>)]) -> Result<()> {
    let factor = if s.effort() == Effort::Full { 4 } else { 2 };
    let mut worst = 0.0f64;
    let mut rows = Vec::new();
    let mut panels = Vec::new();
    for (name, ex) in exemplars {
        let (c, h, w) = ex.dim();
        let out = rpn(
            ex.view(),
            &RpnOptions {
                seed: 3,
                size: Some((factor * w, factor * h)),
                ..RpnOptions::default()
            },
        )
        .ctx("RPN with the spot extension")?;
        for k in 0..c {
            let (_, v0) = mean_variance(ex.index_axis(Axis(0), k));
            let (_, v1) = mean_variance(out.index_axis(Axis(0), k));
            worst = worst.max((v1 / v0 - 1.0).abs());
            rows.push(format!("{name} channel {k}: {:.4}", v1 / v0));
        }
        let slug: String = name.chars().take_while(|c| *c != '.').collect();
        let (path, file) = s.file(&format!("rpn-{slug}-x{factor}.png"));
        planes_png(&path, &out.mapv(|v| v.clamp(0.0, 1.0)))?;
        panels.push(Panel {
            file,
            label: format!(
                "{name}: RPN {}×{} through the spot extension",
                factor * w,
                factor * h
            ),
        });
    }
    s.claim(
        "rpn-spot-extension-variance",
        "Spot extension technique",
        "\"in order to preserve the variance of the initial spot, the smooth function is \
         normalized so that its L2-norm equals 1\" (output variance within 1% of the sample's)",
        "variance preserved",
        format!("variance ratios {}", rows.join(", ")),
        Some("cargo test -p spectex-spectrum larger_rpn_properties"),
        worst < 0.01,
        Expect::Holds,
    );
    s.figure(
        "Spot extension",
        format!("RPN at {factor}× the sample's size (transition a = 0.1)."),
        panels,
        None,
    );
    Ok(())
}

/// Share of the spectrum's energy (zero frequency excluded) on the two axes `k = 0` or `l = 0`:
/// the "horizontal and vertical waves" a non-periodic image puts there.
fn axis_energy(z: &Array2<Complex64>) -> f64 {
    let (mut axes, mut total) = (0.0, 0.0);
    for ((k, l), v) in z.indexed_iter() {
        if (k, l) == (0, 0) {
            continue;
        }
        let p = v.norm_sqr();
        total += p;
        if k == 0 || l == 0 {
            axes += p;
        }
    }
    axes / total
}

fn periodic(s: &mut Session<'_>, ex: &Array3<f64>) -> Result<()> {
    let mut fft = Fft2::new();
    let h = grey(ex);
    let d = periodic_smooth(h.view(), &mut fft);
    let lap_p = periodic_laplacian(d.periodic.view());
    let lap_h = interior_laplacian(h.view());
    let scale = lap_h.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let lap_err = lap_p
        .iter()
        .zip(lap_h.iter())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / scale;
    let mean_err = (d.periodic.mean().unwrap_or(0.0) - h.mean().unwrap_or(0.0)).abs();
    s.claim(
        "rpn-periodic-component",
        "Avoiding artifacts due to non periodicity",
        "the periodic component solves Δp = Δᵢh with mean(p) = mean(h) (Moisan); to 1e-9",
        "exact",
        format!("max |Δp − Δᵢh| / max |Δᵢh| = {lap_err:.1e}; |mean p − mean h| = {mean_err:.1e}"),
        None,
        lap_err < 1e-9 && mean_err < 1e-9,
        Expect::Holds,
    );
    // The smooth part is harmonic inside: Δ(h − p) = Δh − Δᵢh = 0 away from the border.
    let lap_s = periodic_laplacian(d.smooth.view());
    let (rows, cols) = h.dim();
    let mut inside = 0.0f64;
    for y in 1..rows - 1 {
        for x in 1..cols - 1 {
            inside = inside.max(lap_s[[y, x]].abs());
        }
    }
    let (hz, pz) = (dft(h.view(), &mut fft), dft(d.periodic.view(), &mut fft));
    let (ah, ap) = (axis_energy(&hz), axis_energy(&pz));
    s.claim(
        "rpn-smooth-part",
        "Avoiding artifacts due to non periodicity",
        "the smooth component s = h − p carries the border discontinuity: harmonic inside the \
         image (Δs = 0 away from the border, to 1e-9 of max |Δᵢh|) and holding the spectrum's \
         cross (energy on the axes lower in p than in h)",
        "Δs = 0 inside; cross removed",
        format!(
            "max interior |Δs| / max |Δᵢh| = {:.1e}; energy on the axes: h {:.2}%, p {:.2}%",
            inside / scale,
            100.0 * ah,
            100.0 * ap
        ),
        None,
        inside / scale < 1e-9 && ap < ah,
        Expect::Holds,
    );
    let mut panels = Vec::new();
    for (label, a) in [
        ("h", &h),
        ("periodic p", &d.periodic),
        ("smooth s", &d.smooth),
    ] {
        let slug = label.replace(' ', "-");
        let (path, file) = s.file(&format!("periodic-{slug}.png"));
        grey_png_auto(&path, a.view())?;
        panels.push(Panel {
            file,
            label: label.to_owned(),
        });
    }
    for (label, a) in [("log |ĥ|", &h), ("log |p̂|", &d.periodic)] {
        let slug = if label.contains('h') { "h" } else { "p" };
        let (path, file) = s.file(&format!("periodic-spectrum-{slug}.png"));
        spectrum_png(&path, a.view(), &mut fft)?;
        panels.push(Panel {
            file,
            label: format!("{label} (centred)"),
        });
    }
    s.figure(
        "Periodic + smooth decomposition",
        "The sample's grey level h, its periodic component p and smooth component s, and the \
         log-spectra of h and p: the cross of h's spectrum is gone from p's."
            .into(),
        panels,
        None,
    );
    Ok(())
}

fn cost(s: &mut Session<'_>) -> Result<()> {
    let (n, reps) = match s.effort() {
        Effort::Tiny => (128, 3),
        Effort::Quick => (512, 5),
        Effort::Full => (1024, 10),
    };
    let sample = Array3::from_shape_fn((1, n, n), |(_, y, x)| {
        ((x * 7 + y * 13) % 17) as f64 / 17.0 + 0.01 * y as f64
    });
    let mut fft = Fft2::<f64>::new();
    let mut z = Array2::from_elem((n, n), Complex64::new(0.5, 0.0));
    let one_fft = best_of(reps, || {
        fft.forward(&mut z);
        Ok(())
    })?;
    let options = RpnOptions::default();
    // One synthesiser reused, as the FFT is: its plans and buffers are cached after the warm-up.
    let mut synth = Rpn::new();
    let same = best_of(reps, || {
        std::hint::black_box(synth.synthesize(sample.view(), &options).ctx("RPN")?);
        Ok(())
    })?;
    let small = Array3::from_shape_fn((1, n / 2, n / 2), |(_, y, x)| sample[[0, y, x]]);
    let larger = RpnOptions {
        size: Some((n, n)),
        ..RpnOptions::default()
    };
    let extended = best_of(reps, || {
        std::hint::black_box(synth.synthesize(small.view(), &larger).ctx("RPN")?);
        Ok(())
    })?;
    // The O(N) part the paper does not count: the random phase field alone.
    let phase = best_of(reps, || {
        std::hint::black_box(random_phase_field(n, n, 7));
        Ok(())
    })?;
    let (a, b) = (same / one_fft, extended / one_fft);
    s.claim(
        "rpn-cost",
        "Implementation",
        "same-size RPN \"only uses two calls to the FFT algorithm\"; increased size four (two \
         of the sample's size, two of the output's). Measured: time in FFTs of the output \
         size, same size at most 2.5",
        "2 FFTs (same size); 2 + 2 small (larger)",
        format!(
            "grey {n}²: same size {a:.2} FFTs, from {}² {b:.2} FFTs (one FFT {:.2} ms; the \
             random phase field alone {:.2} FFTs)",
            n / 2,
            one_fft * 1e3,
            phase / one_fft
        ),
        Some("cargo xtask bench"),
        a <= 2.5,
        Expect::Differs(
            "spectex makes the paper's two FFT calls (Rpn::synthesize: one forward FFT in the \
             Poisson solve, one inverse), but the time also counts the O(N) passes the paper \
             leaves out: the interior Laplacian, the random phase field (a hash and a \
             sine/cosine per frequency, measured alone in the ours column), the Poisson \
             division, the spectrum product and the output's allocation and copy"
                .into(),
        ),
    );
    let (path, file) = s.file("rpn-cost.svg");
    bar_plot(
        &path,
        &format!("RPN time in FFTs of {n}² (grey)"),
        "FFT equivalents",
        &[
            ("one FFT".into(), 1.0),
            ("RPN same size".into(), a),
            (format!("RPN from {}²", n / 2), b),
        ],
    )?;
    s.figure(
        "Cost",
        format!("Best of {reps} runs on one grey {n}² image; the unit is one complex 2D FFT of the output size."),
        vec![Panel {
            file,
            label: "time in FFT equivalents".into(),
        }],
        None,
    );
    Ok(())
}
