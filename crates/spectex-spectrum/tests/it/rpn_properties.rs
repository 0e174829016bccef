//! Properties of Random Phase Noise, on real photographs from `../shared/testdata/textures/`
//! (skipped with a printed reason when that folder is absent) and on small synthetic images.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use ndarray::{Array2, Array3, ArrayView2, Axis, s};
use num_complex::Complex64;
use spectex_model::random::{Prng, cell_hash};
use spectex_spectrum::periodic::periodic_spectrum_packed;
use spectex_spectrum::rpn::{dft, gaussian_white_noise};
use spectex_spectrum::{
    Fft2, NoiseKind, Rpn, RpnOptions, SpectrumError, extended_spot, periodic_smooth,
    random_phase_field, rpn, transition,
};

/// A shared test texture as `(channel, row, column)` in [0, 1], or `None` with a printed reason.
fn shared(name: &str) -> Option<Array3<f64>> {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures"
    );
    let path = format!("{dir}/{name}");
    if !std::path::Path::new(dir).is_dir() {
        eprintln!("skipping {name}: ../shared/testdata/textures is absent");
        return None;
    }
    let img = spectex_testkit::image_files::open(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let rgb = img.color().has_color();
    if rgb {
        let im = img.to_rgb32f();
        let (w, h) = im.dimensions();
        Some(Array3::from_shape_fn(
            (3, h as usize, w as usize),
            |(c, y, x)| f64::from(im.get_pixel(x as u32, y as u32).0[c]),
        ))
    } else {
        let im = img.to_luma32f();
        let (w, h) = im.dimensions();
        Some(Array3::from_shape_fn(
            (1, h as usize, w as usize),
            |(_, y, x)| f64::from(im.get_pixel(x as u32, y as u32).0[0]),
        ))
    }
}

/// Small synthetic colour samples: correlated channels, a ramp (non-periodic) and noise, with
/// odd and even sides.
fn synthetic(channels: usize, h: usize, w: usize, seed: u32) -> Array3<f64> {
    let mut prng = Prng::new(cell_hash(h as i32, w as i32, 5, seed));
    let base = Array2::from_shape_fn((h, w), |(y, x)| {
        prng.next_f64() + 0.3 * ((x as f64 * 0.7).sin() + (y as f64 * 0.3).cos()) + 0.01 * x as f64
    });
    Array3::from_shape_fn((channels, h, w), |(c, y, x)| {
        0.2 + (0.5 + 0.2 * c as f64) * base[[y, x]] + 0.05 * c as f64 * prng.next_f64()
    })
}

fn cases() -> Vec<(String, Array3<f64>)> {
    let mut v = vec![
        ("synthetic 3×37×50".to_string(), synthetic(3, 37, 50, 1)),
        ("synthetic 1×16×16".to_string(), synthetic(1, 16, 16, 2)),
        ("synthetic 2×2×2".to_string(), synthetic(2, 2, 2, 3)),
        ("synthetic 4×33×20".to_string(), synthetic(4, 33, 20, 4)),
    ];
    for name in ["embark_ts_water_1.jpg", "skimage_gravel.png"] {
        if let Some(img) = shared(name) {
            v.push((name.to_string(), img));
        }
    }
    v
}

fn channel(a: &Array3<f64>, c: usize) -> ArrayView2<'_, f64> {
    a.index_axis(Axis(0), c)
}

fn max_abs<'a>(it: impl IntoIterator<Item = &'a f64>) -> f64 {
    it.into_iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// The one-channel spectrum of the periodic component, without channel packing.
fn periodic_spectrum(h: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> Array2<Complex64> {
    periodic_spectrum_packed(h, None, fft)
}

/// Same-size RPN: the output is real, its DFT modulus is the periodic component's at every
/// frequency, its mean is the sample's, and the cross-channel phase differences are kept.
#[test]
fn same_size_rpn_properties() {
    let mut fft = Fft2::new();
    for (label, sample) in cases() {
        let (channels, h, w) = sample.dim();
        let seed = 12_345;
        let out = rpn(
            sample.view(),
            &RpnOptions {
                seed,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(out.dim(), sample.dim(), "{label}");
        let phase = random_phase_field(h, w, seed);
        let spectra: Vec<Array2<Complex64>> = (0..channels)
            .map(|c| periodic_spectrum(channel(&sample, c), &mut fft))
            .collect();
        let out_spectra: Vec<Array2<Complex64>> = (0..channels)
            .map(|c| dft(channel(&out, c), &mut fft))
            .collect();
        for c in 0..channels {
            // Real: the unpacked inverse transform of P̂·e^{iθ} has no imaginary part.
            let mut z = &spectra[c] * &phase;
            fft.inverse_normalized(&mut z);
            let re = max_abs(z.iter().map(|v| &v.re).collect::<Vec<_>>());
            let im = max_abs(z.iter().map(|v| &v.im).collect::<Vec<_>>());
            assert!(
                im <= 1e-9 * re.max(1e-300),
                "{label} channel {c}: imaginary residue {im:e} vs {re:e}"
            );
            // The packed fast path is the same real image.
            let diff = z
                .iter()
                .zip(channel(&out, c).iter())
                .map(|(a, b)| (a.re - b).abs())
                .fold(0.0, f64::max);
            assert!(
                diff <= 1e-12 * re.max(1.0),
                "{label} channel {c}: packed path differs by {diff:e}"
            );
            // Modulus kept at every frequency.
            let scale = max_abs(
                spectra[c]
                    .iter()
                    .map(|v| v.norm())
                    .collect::<Vec<_>>()
                    .iter(),
            );
            for ((idx, a), b) in spectra[c].indexed_iter().zip(out_spectra[c].iter()) {
                let e = (a.norm() - b.norm()).abs();
                assert!(
                    e <= 1e-9 * scale,
                    "{label} channel {c}: modulus differs at {idx:?}: {} vs {}",
                    a.norm(),
                    b.norm()
                );
            }
            // Mean kept.
            let (m0, m1) = (
                channel(&sample, c).mean().unwrap(),
                channel(&out, c).mean().unwrap(),
            );
            assert!(
                (m0 - m1).abs() <= 1e-12 * m0.abs().max(1.0),
                "{label} channel {c}: mean {m1} vs {m0}"
            );
        }
        // No false colours: arg(Û_c · conj Û_0) = arg(P̂_c · conj P̂_0) wherever both are non-negligible.
        for c in 1..channels {
            let scale = spectra[0].iter().map(|v| v.norm()).fold(0.0, f64::max)
                * spectra[c].iter().map(|v| v.norm()).fold(0.0, f64::max);
            for (idx, p) in spectra[c].indexed_iter() {
                let want = p * spectra[0][idx].conj();
                if want.norm() < 1e-6 * scale {
                    continue;
                }
                let got = out_spectra[c][idx] * out_spectra[0][idx].conj();
                let e = (got / got.norm() - want / want.norm()).norm();
                assert!(
                    e < 1e-6,
                    "{label}: phase difference of channel {c} vs 0 changed at {idx:?} by {e:e}"
                );
            }
        }
    }
}

#[test]
fn same_seed_same_bytes_other_seed_other_texture() {
    let sample = synthetic(3, 40, 30, 9);
    let o = |seed| {
        rpn(
            sample.view(),
            &RpnOptions {
                seed,
                ..Default::default()
            },
        )
        .unwrap()
    };
    let (a, b, c) = (o(1), o(1), o(2));
    assert!(
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    );
    assert!(max_abs((&a - &c).iter()) > 1e-3);
}

/// Output bytes do not depend on the thread count (the phase field is filled in parallel).
#[test]
fn output_is_independent_of_thread_count() {
    let sample = synthetic(3, 64, 48, 11);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let opts = RpnOptions {
                    size: Some((100, 90)),
                    seed: 3,
                    ..Default::default()
                };
                (
                    rpn(sample.view(), &opts).unwrap(),
                    rpn(
                        sample.view(),
                        &RpnOptions {
                            kind: NoiseKind::Adsn,
                            ..opts
                        },
                    )
                    .unwrap(),
                )
            })
    };
    let (a, b) = (run(1), run(4));
    assert!(
        a.0.iter()
            .zip(b.0.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    );
    assert!(
        a.1.iter()
            .zip(b.1.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    );
}

fn variance(a: ArrayView2<'_, f64>) -> f64 {
    let m = a.mean().unwrap();
    a.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / a.len() as f64
}

/// Larger output through the spot extension: real, mean exact, sample variance within 1%, and
/// the phase differences between channels those of the extended spot.
#[test]
fn larger_rpn_properties() {
    let mut fft = Fft2::new();
    let mut real_inputs = 0;
    for (label, sample) in cases() {
        let (channels, h, w) = sample.dim();
        if h < 16 {
            continue;
        }
        let (ow, oh) = (w * 2 + 13, h * 3 / 2 + 7);
        let opts = RpnOptions {
            size: Some((ow, oh)),
            seed: 99,
            ..Default::default()
        };
        let out = rpn(sample.view(), &opts).unwrap();
        assert_eq!(out.dim(), (channels, oh, ow), "{label}");
        let mut periodic = Array3::zeros(sample.dim());
        for c in 0..channels {
            periodic
                .slice_mut(s![c, .., ..])
                .assign(&periodic_smooth(channel(&sample, c), &mut fft).periodic);
        }
        let variances: Vec<f64> = (0..channels)
            .map(|c| variance(channel(&sample, c)))
            .collect();
        let spot = extended_spot(periodic.view(), &variances, ow, oh, 0.1);
        let phase = random_phase_field(oh, ow, 99);
        for c in 0..channels {
            let m = channel(&sample, c).mean().unwrap();
            let mut z = &dft(channel(&spot, c), &mut fft) * &phase;
            z[[0, 0]] = Complex64::new(m * (ow * oh) as f64, 0.0);
            fft.inverse_normalized(&mut z);
            let re = max_abs(z.iter().map(|v| &v.re).collect::<Vec<_>>());
            let im = max_abs(z.iter().map(|v| &v.im).collect::<Vec<_>>());
            assert!(
                im <= 1e-9 * re,
                "{label} channel {c}: imaginary residue {im:e}"
            );
            let diff = z
                .iter()
                .zip(channel(&out, c).iter())
                .map(|(a, b)| (a.re - b).abs())
                .fold(0.0, f64::max);
            assert!(
                diff <= 1e-12 * re.max(1.0),
                "{label} channel {c}: packed path differs by {diff:e}"
            );
            let mo = channel(&out, c).mean().unwrap();
            assert!(
                (mo - m).abs() <= 1e-12 * m.abs().max(1.0),
                "{label} channel {c}: mean {mo} vs {m}"
            );
            if !label.starts_with("synthetic") {
                let (vs, vo) = (variance(channel(&sample, c)), variance(channel(&out, c)));
                assert!(
                    (vo / vs - 1.0).abs() < 0.01,
                    "{label} channel {c}: variance {vo} vs sample {vs}"
                );
            }
        }
        if !label.starts_with("synthetic") {
            real_inputs += 1;
        }
    }
    eprintln!("larger_rpn_properties: {real_inputs} real inputs checked for variance");
}

/// The variance is kept within 1% on every shared texture (all are stationary photographs or
/// height maps), at two output sizes.
#[test]
fn larger_rpn_keeps_the_sample_variance_on_shared_textures() {
    let names = [
        "skimage_gravel.png",
        "skimage_grass.png",
        "skimage_brick.png",
        "embark_ts_water_1.jpg",
        "astex_ambientcg_sand_height_512.png",
        "astex_ambientcg_dirt_height_512.png",
        "astex_ambientcg_rock_height_512.png",
        "astex_ambientcg_paving_height_512.png",
    ];
    let mut engine = Rpn::new();
    for name in names {
        let Some(sample) = shared(name) else { continue };
        let (_, h, w) = sample.dim();
        for (ow, oh) in [(w + w / 2, h + h / 3), (2 * w, 2 * h)] {
            let out = engine
                .synthesize(
                    sample.view(),
                    &RpnOptions {
                        size: Some((ow, oh)),
                        seed: 5,
                        ..Default::default()
                    },
                )
                .unwrap();
            for c in 0..sample.dim().0 {
                let (vs, vo) = (variance(channel(&sample, c)), variance(channel(&out, c)));
                assert!(
                    (vo / vs - 1.0).abs() < 0.01,
                    "{name} → {ow}×{oh} channel {c}: variance {vo:.6} vs sample {vs:.6}"
                );
            }
        }
    }
}

/// ADSN shares one white noise across channels: the output spectrum divided by the spot's is the
/// same complex factor for every channel, and the mean is exact.
#[test]
fn adsn_shares_the_noise_between_channels() {
    let sample = synthetic(3, 48, 40, 21);
    let mut fft = Fft2::new();
    let out = rpn(
        sample.view(),
        &RpnOptions {
            kind: NoiseKind::Adsn,
            seed: 4,
            ..Default::default()
        },
    )
    .unwrap();
    let noise = gaussian_white_noise(48, 40, 4);
    let mut nz = dft(noise.view(), &mut fft);
    nz.mapv_inplace(|v| v / (48.0f64 * 40.0).sqrt());
    for c in 0..3 {
        let p = periodic_spectrum_packed(channel(&sample, c), None, &mut fft);
        let u = dft(channel(&out, c), &mut fft);
        let scale = p.iter().map(|v| v.norm()).fold(0.0, f64::max)
            * nz.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for (idx, pv) in p.indexed_iter() {
            if idx == (0, 0) {
                continue;
            }
            let e = (u[idx] - pv * nz[idx]).norm();
            assert!(e < 1e-9 * scale, "channel {c} at {idx:?}: {e:e}");
        }
        let (m0, m1) = (
            channel(&sample, c).mean().unwrap(),
            channel(&out, c).mean().unwrap(),
        );
        assert!((m0 - m1).abs() < 1e-12);
    }
}

#[test]
fn white_noise_is_standard_gaussian() {
    let n = gaussian_white_noise(256, 256, 8);
    let m = n.mean().unwrap();
    let v = variance(n.view());
    // 65536 samples: the standard errors of mean and variance are 0.004 and 0.0055.
    assert!(
        m.abs() < 0.02 && (v - 1.0).abs() < 0.03,
        "mean {m} variance {v}"
    );
    let within_one = n.iter().filter(|x| x.abs() < 1.0).count() as f64 / n.len() as f64;
    assert!(
        (within_one - 0.6827).abs() < 0.01,
        "P(|x|<1) = {within_one}"
    );
}

#[test]
fn phase_field_is_odd_and_unit() {
    for (h, w) in [(1, 1), (2, 2), (4, 6), (5, 7), (8, 3)] {
        let f = random_phase_field(h, w, 17);
        assert_eq!(f[[0, 0]], Complex64::new(1.0, 0.0));
        for ((k, l), v) in f.indexed_iter() {
            let mirror = f[[(h - k) % h, (w - l) % w]];
            assert_eq!(*v, mirror.conj(), "{h}×{w} at ({k}, {l})");
            assert!((v.norm() - 1.0).abs() < 1e-15);
            if ((h - k) % h, (w - l) % w) == (k, l) {
                assert!(
                    v.im == 0.0 && v.re.abs() == 1.0,
                    "self-symmetric ({k}, {l}) is {v}"
                );
            }
        }
    }
    // The phases are uniform: the mean of e^{iθ} over a large field is ~0 and the mean of θ
    // in turns is ~½.
    let f = random_phase_field(128, 128, 3);
    let mean = f.iter().sum::<Complex64>() / f.len() as f64;
    assert!(mean.norm() < 0.02, "mean phase factor {mean}");
}

#[test]
fn transition_function_is_the_normalised_bump_primitive() {
    let a = 0.1;
    assert_eq!(transition(0.0, a), 0.0);
    assert_eq!(transition(1.0, a), 0.0);
    assert_eq!(transition(0.5, a), 1.0);
    assert!((transition(a, a) - 1.0).abs() < 1e-12);
    // The bump is symmetric about a/2, so its primitive is ½ there.
    assert!((transition(a / 2.0, a) - 0.5).abs() < 1e-12);
    let mut prev = 0.0;
    for i in 0..=1000 {
        let t = i as f64 / 1000.0 * a;
        let v = transition(t, a);
        // Simpson sums of two different step sizes make a ratio exact to ~1e-14, not to the ulp.
        assert!(v >= prev - 1e-12, "not monotone at {t}");
        assert!(
            (v - transition(1.0 - t, a)).abs() < 1e-12,
            "not symmetric at {t}"
        );
        prev = v;
    }
    // ψ' is proportional to the bump: compare a central difference with exp(−1/(1 − u²)).
    let bump = |t: f64| {
        let u = 2.0 * t / a - 1.0;
        (-1.0 / (1.0 - u * u)).exp()
    };
    let d = 1e-6;
    let ratio = |t: f64| (transition(t + d, a) - transition(t - d, a)) / (2.0 * d) / bump(t);
    let r0 = ratio(0.05);
    for t in [0.02, 0.03, 0.07, 0.08] {
        assert!((ratio(t) / r0 - 1.0).abs() < 1e-5, "ψ' not ∝ bump at {t}");
    }
}

#[test]
fn bad_inputs_give_typed_errors() {
    let ok = synthetic(3, 8, 8, 1);
    let tiny = Array3::<f64>::zeros((1, 1, 1));
    assert!(matches!(
        rpn(tiny.view(), &RpnOptions::default()),
        Err(SpectrumError::TooSmall { .. })
    ));
    let mut nan = ok.clone();
    nan[[1, 2, 3]] = f64::NAN;
    assert!(matches!(
        rpn(nan.view(), &RpnOptions::default()),
        Err(SpectrumError::NonFinite {
            channel: 1,
            row: 2,
            column: 3,
            ..
        })
    ));
    let smaller = RpnOptions {
        size: Some((4, 20)),
        ..Default::default()
    };
    assert!(matches!(
        rpn(ok.view(), &smaller),
        Err(SpectrumError::TooSmall {
            parameter: "output size",
            ..
        })
    ));
    let huge = RpnOptions {
        size: Some((100_000, 10)),
        ..Default::default()
    };
    assert!(matches!(
        rpn(ok.view(), &huge),
        Err(SpectrumError::TooLarge { .. })
    ));
    let bad_a = RpnOptions {
        transition: 0.0,
        ..Default::default()
    };
    assert!(matches!(
        rpn(
            ok.view(),
            &RpnOptions {
                size: Some((9, 9)),
                ..bad_a
            }
        ),
        Err(SpectrumError::OutOfRange { .. })
    ));
    let five = Array3::<f64>::zeros((5, 8, 8));
    assert!(matches!(
        rpn(five.view(), &RpnOptions::default()),
        Err(SpectrumError::Channels { .. })
    ));
    let msg = rpn(ok.view(), &huge).unwrap_err().to_string();
    assert!(
        msg.contains("output size") && msg.contains("16384"),
        "{msg}"
    );
}
