//! Fidelity of LRP noise by example, measured on renders (Gilet et al. 2014, §4); Fig. 10 (LRP
//! against Gabor noise on a ring) is measured by `spectex-reproduce`'s `lrp::ring_comparison`.
//! Prints the tables reported in closing notes; asserts what the paper claims in a form that
//! cannot pass by accident. Uses `../shared/testdata/textures/` and skips
//! with a printed reason when it is absent.
//!
//! `cargo test --release -p spectex-cli --test it fidelity:: -- --include-ignored --nocapture --skip _fidelity::`
//! prints the tables.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stdout,
    reason = "the measured tables are the point of these tests"
)]

use ndarray::{Array2, Axis};
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_sampling::{FitMethod, FitOptions, fit_image};
use spectex_spectrum::{Fft2, mean_variance, welch_psd_with_block};

pub(crate) fn shared_grey(name: &str) -> Option<Array2<f64>> {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures"
    );
    if !std::path::Path::new(dir).is_dir() {
        println!("skipping {name}: ../shared/testdata/textures is absent");
        return None;
    }
    let img = spectex_testkit::image_files::open(format!("{dir}/{name}"))
        .unwrap()
        .to_luma32f();
    let (w, h) = img.dimensions();
    Some(Array2::from_shape_fn((h as usize, w as usize), |(y, x)| {
        f64::from(img.get_pixel(x as u32, y as u32).0[0])
    }))
}

/// A `side`² render at (3000, −7000), periodic with period `side`×`side` when `periodic`; and the
/// seconds it took.
fn render(model: &Model, side: usize, periodic: bool) -> (Array2<f64>, f64) {
    let eval = if periodic {
        let period = spectex_model::Period::new(side as u32, side as u32).unwrap();
        Evaluator::periodic(model, period).unwrap()
    } else {
        Evaluator::new(model).unwrap()
    };
    let start = std::time::Instant::now();
    let v = eval
        .render(&Window::new(side, side).at([3.0e3, -7.0e3], 1.0))
        .unwrap();
    let seconds = start.elapsed().as_secs_f64();
    (
        Array2::from_shape_vec((side, side), v.into_iter().map(f64::from).collect()).unwrap(),
        seconds,
    )
}

/// Mean and variance of the model from 512² samples 1031.3 pixels apart (a 528 000-pixel
/// square), farther apart than the widest window (`4T` = 1024 pixels at most): independent
/// samples, so the estimate's relative error is about √(2/512²) ≈ 0.3% (samples 37.3 pixels
/// apart were correlated through a height map's 512-pixel windows: ±2% measured),
/// where a 1024² render of a height map dominated by periods of 100+ pixels has only a few
/// hundred independent patches (≈ 7% error on the variance, measured up to 23%).
fn sparse_mean_var(model: &Model) -> (f64, f64) {
    let eval = Evaluator::new(model).unwrap();
    let v = eval
        // Point samples (`Filter::Off`): the model's own moments, not a minified render's.
        .render(
            &Window::new(512, 512)
                .at([-5.0e3, 9.0e3], 1031.3)
                .filtered(spectex_cpu::Filter::Off),
        )
        .unwrap();
    let a = Array2::from_shape_vec((512, 512), v.into_iter().map(f64::from).collect()).unwrap();
    mean_var(&a)
}

fn mean_var(a: &Array2<f64>) -> (f64, f64) {
    mean_variance(a.view())
}

fn shape_distance(a: &Array2<f64>, b: &Array2<f64>) -> f64 {
    spectex_spectrum::shape_distance(a.view(), b.view())
}

/// The distances a stationary Gaussian field with exactly the exemplar's spectrum measures at
/// `side`² ([`SEEDS`] fields), by the same Welch estimate: an independent estimate of the floor
/// any stationary random field of that spectrum sits on at this render size, made without the
/// code under test. Each field is white noise filtered in the frequency domain on a `2·side`²
/// periodic grid by the square root of the exemplar's sharpened spectrum
/// ([`spectex_sampling::exemplar_target`], nearest bin), cropped to `side`² so that it is not
/// periodic over the render. A height map's power at periods of 100+ pixels is a few
/// independent patches of a 1024² render, so even this field's distance spreads widely.
fn gaussian_reference(
    ex: &Array2<f64>,
    psd: &Array2<f64>,
    side: usize,
    fft: &mut Fft2<f64>,
) -> Vec<f64> {
    let (target, _) = spectex_sampling::exemplar_target(ex.view(), FitMethod::Spectrum).unwrap();
    (1..=SEEDS)
        .map(|seed| {
            let img = gaussian_field(&target, side, seed, fft);
            let psd_r = welch_psd_with_block(img.view(), 256, fft).unwrap();
            shape_distance(&psd_r, psd)
        })
        .collect()
}

/// One stationary Gaussian field of `side`² with the spectrum `target` (a Welch-block grid of
/// power, zero frequency first): white noise (Box–Muller on the PRNG seeded with `seed·7919`)
/// filtered on a `2·side`² periodic grid by the square root of the target's nearest bin, cropped
/// to `side`² so that it is not periodic over the render.
pub(crate) fn gaussian_field(
    target: &Array2<f64>,
    side: usize,
    seed: u32,
    fft: &mut Fft2<f64>,
) -> Array2<f64> {
    use num_complex::Complex64;
    let t = target.nrows() as f64;
    let n = 2 * side;
    let mut prng = spectex_model::random::Prng::new(seed.wrapping_mul(7919));
    let mut field = Array2::from_shape_fn((n, n), |_| {
        // Box–Muller.
        let (u1, u2) = (prng.next_f64().max(1e-300), prng.next_f64());
        let g = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
        Complex64::new(g, 0.0)
    });
    fft.forward(&mut field);
    let nearest = |k: usize| {
        let f = spectex_spectrum::signed_frequency(k, n);
        ((f * t).round() as i64).rem_euclid(t as i64) as usize
    };
    for ((y, x), v) in field.indexed_iter_mut() {
        let bin = [nearest(y), nearest(x)];
        let p = if bin == [0, 0] { 0.0 } else { target[bin] };
        *v *= p.max(0.0).sqrt();
    }
    fft.inverse(&mut field);
    Array2::from_shape_fn((side, side), |(y, x)| field[[y, x]].re)
}

/// Seeds each fit is rendered with: one render's spectrum at the lowest frequencies is a few
/// independent patches (a height map's power lies at periods of 100+ pixels), so single-seed
/// distances spread by ±0.02–0.06 (standard deviations measured over these 8 seeds); the means
/// over 8 seeds are what is compared.
const SEEDS: u32 = 8;

/// Noise by example on the four stochastic shared textures: the spectrum fit (the default) at
/// J = 10, 50, 100 and the paper's fit at J = 50, each rendered at 1024² with [`SEEDS`] seeds
/// and measured by an independent Welch estimate (T = 256) against the exemplar's. Asserted, the
/// bounds of issue 16 on the means over the seeds: at J = 50 at most 0.15 on each exemplar; from
/// J = 10 to 50 to 100 falling or flat within 0.01; mean and variance within 2% at J = 50 (for
/// seeds 1 and 2 here: a 512² sparse sample of the model costs about three dense 1024² renders;
/// every seed in [`noise_by_example_full_table`]); the paper's fit further from the spectrum than
/// the spectrum fit. Single seeds are printed (max), not asserted: on the height maps even the
/// Gaussian field's single seeds pass 0.15.
///
/// Issue 17, seamless output, measured on the same fits: each J = 50 fit is also rendered
/// periodically (period 1024×1024, the same window), and the spectral distance of the periodic
/// renders is at most 0.02 more than the plain renders'. What the period changes is systematic:
/// the fitted `Δ_S` (`1024/n` instead of the nominal side) and the wrapped seams move the
/// *expected* spectrum, so the distance compared is that of the spectrum averaged over the
/// [`SEEDS`] renders (the plain and the periodic render from the same fit). Single-render
/// distances are no use here: on the height maps they spread by ±0.05 per seed, and moving a
/// stratum's `Δ_S` reshuffles which lattice point covers which pixel, so a plain and a periodic
/// render of one seed are not paired either (measured on dirt over 16 seeds: the paired
/// differences spread by 0.045, the 16-seed means of single distances 0.152 plain and 0.162
/// periodic, +0.010 within that noise). Averaging 8 spectra first, the differences measured on
/// seeds 1–8 and 9–16 were gravel +0.002 and 0.000, sand −0.014 and +0.006, grass −0.001 and
/// 0.000, dirt +0.006 and −0.010 (at the window's origin, before the spectrum fit's exact Welch
/// sharpening). One-sided: the period may bring the spectrum closer.
#[test]
fn noise_by_example_matches_the_exemplar_spectrum() {
    noise_by_example(Depth::Ci);
}

/// [`noise_by_example_matches_the_exemplar_spectrum`] with the moments of every seed, next to
/// RPN (1024² by the spot extension) and a stationary Gaussian field of the exemplar's spectrum
/// ([`gaussian_reference`]) measured the same way: the table of the closing notes. The same
/// bounds are asserted, and RPN's mean distance at most 0.15 (RPN keeps the exemplar's spectrum
/// exactly; its distance is the estimate's own noise, 0.054–0.074 measured). Left out of CI for
/// its time (about 4 minutes more on 2 cores):
/// `cargo test --release -p spectex-cli --test it fidelity::noise_by_example -- --include-ignored
/// --nocapture`.
#[test]
#[ignore = "the full table: several minutes; CI runs noise_by_example_matches_the_exemplar_spectrum"]
fn noise_by_example_full_table() {
    noise_by_example(Depth::Full);
}

/// How much of the noise-by-example table a test measures.
#[derive(Clone, Copy, PartialEq)]
enum Depth {
    /// Moments at J = 50 for seeds 1 and 2; no RPN or Gaussian-field references.
    Ci,
    /// Moments at J = 50 for every seed; RPN and Gaussian-field references.
    Full,
}

fn noise_by_example(depth: Depth) {
    let mut fft = Fft2::new();
    let mut failures = Vec::new();
    println!("texture   fit       J    L1 mean (sd, max)        Δmean/σ   var ratio  Mpix/s");
    for name in [
        "skimage_gravel.png",
        "astex_ambientcg_sand_height_512.png",
        "skimage_grass.png",
        "astex_ambientcg_dirt_height_512.png",
    ] {
        let Some(ex) = shared_grey(name) else { return };
        let short = &name[..name.len().min(9)];
        let t = 256;
        let psd = welch_psd_with_block(ex.view(), t, &mut fft).unwrap();
        let (mean, var) = mean_var(&ex);
        if depth == Depth::Full {
            let rpn: Vec<f64> = (1..=SEEDS)
                .map(|seed| {
                    let options = spectex_spectrum::RpnOptions {
                        size: Some((1024, 1024)),
                        seed,
                        ..Default::default()
                    };
                    let out =
                        spectex_spectrum::rpn(ex.clone().insert_axis(Axis(0)).view(), &options)
                            .unwrap();
                    let psd_r =
                        welch_psd_with_block(out.index_axis(Axis(0), 0), t, &mut fft).unwrap();
                    shape_distance(&psd_r, &psd)
                })
                .collect();
            println!("{short:<9} rpn        -  {}", summary(&rpn));
            let mean_rpn = rpn.iter().sum::<f64>() / rpn.len() as f64;
            if mean_rpn > 0.15 {
                failures.push(format!("{name}: RPN mean L1 {mean_rpn:.4} above 0.15"));
            }
            let gaussian = gaussian_reference(&ex, &psd, 1024, &mut fft);
            println!("{short:<9} gaussian   -  {}", summary(&gaussian));
        }
        let mut spectrum_at_50 = f64::NAN;
        // The summed spectra of the J = 50 renders, plain and periodic.
        let mut spectra: [Option<Array2<f64>>; 2] = [None, None];
        let mut previous: Option<(u32, f64)> = None;
        for (method, budget, seeds) in [
            (FitMethod::Spectrum, 10u32, SEEDS),
            (FitMethod::Spectrum, 50, SEEDS),
            (FitMethod::Spectrum, 100, SEEDS),
            (FitMethod::Paper, 50, 1),
        ] {
            let mut distances = Vec::new();
            let mut worst_moments: Option<(f64, f64)> = None;
            let mut pixels_per_second = 0.0;
            for seed in 1..=seeds {
                let options = FitOptions {
                    budget,
                    seed,
                    method,
                    ..FitOptions::default()
                };
                let model = Model::Lrp(fit_image(ex.view(), &options).unwrap());
                let (img, seconds) = render(&model, 1024, false);
                pixels_per_second += (1024.0 * 1024.0) / seconds / f64::from(seeds);
                let psd_r = welch_psd_with_block(img.view(), t, &mut fft).unwrap();
                distances.push(shape_distance(&psd_r, &psd));
                if (method, budget) == (FitMethod::Spectrum, 50) {
                    let (periodic, _) = render(&model, 1024, true);
                    let psd_p = welch_psd_with_block(periodic.view(), t, &mut fft).unwrap();
                    for (sum, psd_r) in spectra.iter_mut().zip([psd_r, psd_p]) {
                        *sum = Some(match sum.take() {
                            None => psd_r,
                            Some(sum) => sum + &psd_r,
                        });
                    }
                }
                // The moments at J = 50, the budget the targets name: a 512² sparse
                // sample costs about three dense renders (each sample draws a lattice
                // neighbourhood of its own), and J = 10 and 100 only enter the falling check.
                if (method, budget) != (FitMethod::Spectrum, 50) || (depth == Depth::Ci && seed > 2)
                {
                    continue;
                }
                let (m_r, v_r) = sparse_mean_var(&model);
                let (dm, vr) = ((m_r - mean) / var.sqrt(), v_r / var);
                let worst = worst_moments.get_or_insert((dm, vr));
                if dm.abs() > worst.0.abs() {
                    worst.0 = dm;
                }
                if (vr - 1.0).abs() > (worst.1 - 1.0).abs() {
                    worst.1 = vr;
                }
                // Mean within 2% of σ, variance within 2%.
                if dm.abs() >= 0.02 {
                    failures.push(format!(
                        "{name} J={budget} seed {seed}: mean {m_r} vs {mean}"
                    ));
                }
                if (vr - 1.0).abs() >= 0.02 {
                    failures.push(format!(
                        "{name} J={budget} seed {seed}: variance {v_r} vs {var}"
                    ));
                }
            }
            let moments = worst_moments.map_or_else(
                || format!("{:>8}  {:>9}", "-", "-"),
                |(dm, vr)| format!("{dm:8.4}  {vr:9.3}"),
            );
            let d = distances.iter().sum::<f64>() / distances.len() as f64;
            println!(
                "{short:<9} {:<8} {budget:>3}  {}  {moments}  {:6.2}",
                method.name(),
                summary(&distances),
                pixels_per_second / 1e6,
            );
            if method == FitMethod::Paper {
                // The paper's procedure stays what it was: far from the spectrum (0.34–0.58
                // measured), which the spectrum fit must beat.
                if d <= spectrum_at_50 {
                    failures.push(format!(
                        "{name}: paper fit {d:.4} not above the spectrum fit {spectrum_at_50:.4}"
                    ));
                }
            } else {
                if budget == 50 {
                    spectrum_at_50 = d;
                    if d > 0.15 {
                        failures.push(format!("{name} J=50: mean L1 {d:.4} above 0.15"));
                    }
                    // Distances of normalised spectra: the sums need no division by the count.
                    let [plain, periodic] = spectra
                        .each_ref()
                        .map(|s| shape_distance(s.as_ref().unwrap(), &psd));
                    println!(
                        "{short:<9} periodic  50  L1 of the mean spectrum: plain {plain:.4}, \
                         periodic {periodic:.4} ({:+.4})",
                        periodic - plain
                    );
                    if periodic - plain > 0.02 {
                        failures.push(format!(
                            "{name}: periodic renders' mean spectrum at L1 {periodic:.4} vs \
                             plain {plain:.4}, more than 0.02 further"
                        ));
                    }
                }
                // Falling, or flat within 0.01, as J grows.
                if let Some((j, before)) = previous
                    && d > before + 0.01
                {
                    failures.push(format!(
                        "{name}: mean L1 {d:.4} at J={budget} above {before:.4} at J={j} + 0.01"
                    ));
                }
                previous = Some((budget, d));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `mean (sd, max)` of the distances.
fn summary(d: &[f64]) -> String {
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let sd = if d.len() > 1 {
        (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    let max = d.iter().copied().fold(f64::MIN, f64::max);
    format!("{mean:7.4} ({sd:.4}, {max:.4})")
}

/// `--fit paper` is the paper's procedure as it was: fitted again from the same photographs,
/// the stored `testdata/models/lrp-gravel.json` and `lrp-sand.json` (J = 12, L = 4, made by the
/// paper fit before the spectrum fit existed) come out identical.
#[test]
fn the_paper_fit_reproduces_the_stored_models() {
    for (file, texture, seed) in [
        ("lrp-gravel", "skimage_gravel.png", 1),
        ("lrp-sand", "astex_ambientcg_sand_height_512.png", 2),
    ] {
        let Some(ex) = shared_grey(texture) else {
            return;
        };
        let path = format!(
            "{}/../../testdata/models/{file}.json",
            env!("CARGO_MANIFEST_DIR")
        );
        let stored = spectex_model::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
        let options = FitOptions {
            budget: 12,
            strata: 4,
            seed,
            method: FitMethod::Paper,
            ..FitOptions::default()
        };
        let fitted = Model::Lrp(fit_image(ex.view(), &options).unwrap());
        assert!(
            fitted == stored,
            "{file}: the paper fit differs from the stored model"
        );
    }
}
