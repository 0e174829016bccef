//! Noise by example on a real photograph: the gravel texture of `../shared/testdata/textures/`
//! (skipped with a printed reason when that folder is absent), fitted with J = 50, L = 4.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use ndarray::Array2;
use spectex_model::LrpNoise;
use spectex_model::random::{Prng, cell_hash};
use spectex_model::window::{kaiser_bessel, window_radial_energy};
use spectex_sampling::{FitOptions, fit_image, stratify};
use spectex_spectrum::{Fft2, welch_psd};
use std::f64::consts::PI;

/// The shared gravel photograph as a grey channel in [0, 1], or `None` with a printed reason.
fn gravel() -> Option<Array2<f64>> {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures"
    );
    if !std::path::Path::new(dir).is_dir() {
        eprintln!("skipping: ../shared/testdata/textures is absent");
        return None;
    }
    let path = format!("{dir}/skimage_gravel.png");
    let img = spectex_testkit::image_files::open(&path)
        .unwrap_or_else(|e| panic!("{path}: {e}"))
        .to_luma32f();
    let (w, h) = img.dimensions();
    Some(Array2::from_shape_fn((h as usize, w as usize), |(y, x)| {
        f64::from(img.get_pixel(x as u32, y as u32).0[0])
    }))
}

fn options() -> FitOptions {
    FitOptions {
        budget: 50,
        strata: 4,
        seed: 2014,
        ..FitOptions::default()
    }
}

#[test]
fn gravel_fit_keeps_budget_tables_frequencies_and_variance() {
    let Some(image) = gravel() else { return };
    let psd = welch_psd(image.view(), &mut Fft2::new()).unwrap();
    let t = psd.nrows();
    let welch_variance = (psd.sum() - psd[[0, 0]]) / (t * t) as f64;
    let model = fit_image(image.view(), &options()).unwrap();
    let plan = stratify(psd.view(), &options()).unwrap();

    println!(
        "gravel {}×{}: T = {t}, Welch variance {welch_variance:.6e}, δ₀ = {:.6}",
        image.nrows(),
        image.ncols(),
        plan.shrink_unit
    );
    println!("level  E_S          |S|    J_S  Δ_S      δ_bins   pieces thin   eroded  points  A_S");
    for s in &plan.strata {
        println!(
            "{:<6} {:<12.5e} {:<6} {:<4} {:<8.3} {:<8.3} {:<6} {:<6} {:<7} {:<7} {:.5e}",
            s.level,
            s.energy,
            s.bins.len(),
            s.cosines,
            s.window_width,
            s.shrink_bins,
            s.components,
            s.thin_components,
            s.eroded.len(),
            s.points.len(),
            s.amplitude
        );
    }

    model.validate().unwrap();
    assert_eq!(model.budget(), 50, "Σ_S J_S");
    assert_eq!(
        plan.strata.iter().map(|s| s.cosines).sum::<usize>(),
        50,
        "Σ_S J_S in the plan"
    );
    assert!((model.mean as f64 - image.mean().unwrap()).abs() < 1e-6);
    for (s, stratum) in model.strata.iter().enumerate() {
        for (j, table) in stratum.sub_strata.iter().enumerate() {
            assert!(!table.is_empty(), "stratum {s}, table {j} is empty");
            for f in table {
                assert!(
                    f.iter().all(|v| (-0.5..=0.5).contains(v)),
                    "stratum {s}, table {j}: frequency {f:?} outside [−½, ½]"
                );
            }
        }
    }
    let energy: f64 = plan.strata.iter().map(|s| s.energy).sum();
    assert!(
        (energy - welch_variance).abs() <= 1e-9 * welch_variance,
        "Σ E_S = {energy}, Welch variance {welch_variance}"
    );
    let c = window_radial_energy();
    let variance: f64 = plan
        .strata
        .iter()
        .map(|s| PI * s.cosines as f64 * s.amplitude * s.amplitude * c)
        .sum();
    assert!(
        (variance - welch_variance).abs() <= 1e-9 * welch_variance,
        "Σ π J_S A_S² c = {variance}, Welch variance {welch_variance}"
    );
    let stored: f64 = model
        .strata
        .iter()
        .map(|s| PI * s.cosines() as f64 * f64::from(s.amplitude).powi(2) * c)
        .sum();
    // fit_image scales Welch's shape to the image's own variance (`exemplar_psd`), computed
    // here directly.
    let mean = image.mean().unwrap();
    let pixel_variance = image.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / image.len() as f64;
    assert!(
        (stored - pixel_variance).abs() <= 1e-6 * pixel_variance,
        "model variance {stored}, image variance {pixel_variance}"
    );
}

#[test]
fn gravel_fit_is_the_same_for_any_thread_count() {
    let Some(image) = gravel() else { return };
    let fit = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| fit_image(image.view(), &options()).unwrap())
    };
    assert_eq!(fit(1), fit(3));
}

/// A direct transcription of Eqs. (1)–(2) as `spectex_model::LrpNoise` documents the model (each
/// lattice point draws one entry of each table and a phase): the noise's spatial variance over a large area matches the
/// exemplar's. Statistical, so the tolerance is loose; it catches a wrong amplitude unit
/// (a factor `Δ_S²` or 2) by far.
#[test]
fn evaluated_gravel_model_has_the_exemplar_variance() {
    let Some(image) = gravel() else { return };
    let model = fit_image(image.view(), &options()).unwrap();
    let psd = welch_psd(image.view(), &mut Fft2::new()).unwrap();
    let t = psd.nrows();
    let want = (psd.sum() - psd[[0, 0]]) / (t * t) as f64;
    let (mut sum, mut sum2, mut count) = (0.0, 0.0, 0.0);
    for y in (0..1536).step_by(6) {
        for x in (0..1536).step_by(6) {
            let v = evaluate(&model, x as f64 + 0.5, y as f64 + 0.5);
            sum += v;
            sum2 += v * v;
            count += 1.0;
        }
    }
    let mean = sum / count;
    let variance = sum2 / count - mean * mean;
    println!("evaluated variance {variance:.5e}, exemplar (Welch) {want:.5e}");
    assert!(
        (variance / want - 1.0).abs() < 0.15,
        "evaluated variance {variance} vs exemplar {want}"
    );
    assert!((mean - f64::from(model.mean)).abs() < 0.1 * want.sqrt() + 0.01);
}

fn evaluate(model: &LrpNoise, x: f64, y: f64) -> f64 {
    let mut n = f64::from(model.mean);
    for (s, stratum) in model.strata.iter().enumerate() {
        let delta = f64::from(stratum.window_width);
        let (cx, cy) = ((x / delta).floor() as i32, (y / delta).floor() as i32);
        // Every lattice point within the window's support 1.5·Δ_S.
        for iy in cy - 1..=cy + 2 {
            for ix in cx - 1..=cx + 2 {
                let (px, py) = (f64::from(ix) * delta, f64::from(iy) * delta);
                let (dx, dy) = (x - px, y - py);
                let w = kaiser_bessel((dx * dx + dy * dy).sqrt() / delta);
                if w == 0.0 {
                    continue;
                }
                let mut prng = Prng::new(cell_hash(ix, iy, s as u32, model.seed));
                for table in &stratum.sub_strata {
                    let f = table[prng.next_u32() as usize % table.len()];
                    let phase = prng.next_f64();
                    let turns = f64::from(f[0]) * dx + f64::from(f[1]) * dy + phase;
                    n += w * f64::from(stratum.amplitude) * (2.0 * PI * turns).cos();
                }
            }
        }
    }
    n
}
