//! The cross-check suite: every model in `testdata/models/*.json`, rendered on the CPU and the
//! GPU at the origin, at `(10⁷, 10⁷)` and at a fractional scale, compared within the model's
//! derived tolerances (phasor models pixel by pixel, phases on the circle:
//! `crates/spectex-crosscheck/src/tolerance/phasor.rs`; colour textures component by
//! component). Prints one `crosscheck:` line per model (what
//! `cargo xtask verify` shows) and one per window; on a failure, images and reports go to
//! `target/crosscheck/`. Each model is checked on the plane its kind chooses
//! (`CheckKind::check_plane`: 3D classic noises off their lattice planes).
//!
//! Skips with a printed reason when no GPU adapter exists, unless `SPECTEX_REQUIRE_GPU=1`.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stdout,
    reason = "the per-model lines are the suite's report"
)]

use std::path::PathBuf;

use spectex_crosscheck::{check_model, standard_windows};

use crate::common::gpu_or_skip;

/// Environment variable naming a file to which the suite also writes its `crosscheck:` lines, for
/// `cargo xtask ci` and `verify` to print after the test run (libtest shows a passing test's
/// output only with `--nocapture`).
const SUMMARY_ENV: &str = "SPECTEX_CROSSCHECK_SUMMARY";

fn model_files() -> Vec<PathBuf> {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models"
    ));
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_shipped_model_agrees_on_cpu_and_gpu() {
    let files = model_files();
    assert!(
        files.len() >= 10,
        "testdata/models should hold the LRP (2 fitted, ring), Gabor (2), phasor (5), texture and \
         classic cases"
    );
    let Some(context) = gpu_or_skip("cross-check") else {
        return;
    };
    let adapter = context.adapter_name();
    let mut failed = Vec::new();
    let mut summary = String::new();
    for file in &files {
        let case = file.file_stem().unwrap().to_string_lossy().into_owned();
        let model = spectex_model::from_json(&std::fs::read_to_string(file).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let outcomes = check_model(&context, &case, &model, &standard_windows())
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        let worst_max = outcomes
            .iter()
            .map(|(_, o)| o.comparison.max_abs)
            .fold(0.0, f64::max);
        let worst_mean = outcomes
            .iter()
            .map(|(_, o)| o.comparison.mean_abs)
            .fold(0.0, f64::max);
        // A colour texture has one tolerance per component: report the largest.
        let tolerance = outcomes
            .iter()
            .map(|(_, o)| o.tolerance)
            .max_by(|a, b| a.max_abs.total_cmp(&b.max_abs))
            .unwrap();
        let passed = outcomes.iter().all(|(_, o)| o.passed());
        let line = format!(
            "crosscheck: {case:<20} on {adapter}: max error {worst_max:.2e}, mean error \
             {worst_mean:.2e}, tolerance {:.2e} (mean {:.2e}): {}",
            tolerance.max_abs,
            tolerance.mean_abs,
            if passed { "pass" } else { "FAIL" }
        );
        println!("{line}");
        summary.push_str(&line);
        summary.push('\n');
        for (window, outcome) in &outcomes {
            println!("    {window}: {}", outcome.summary());
            if !outcome.passed() {
                failed.push(format!("{case} {}: {}", window.name, outcome.summary()));
            }
        }
    }
    if let Some(path) = std::env::var_os(SUMMARY_ENV) {
        std::fs::write(&path, &summary)
            .unwrap_or_else(|e| panic!("{SUMMARY_ENV}={}: {e}", path.display()));
    }
    assert!(
        failed.is_empty(),
        "{} window(s) failed; images and reports in target/crosscheck/:\n{}",
        failed.len(),
        failed.join("\n")
    );
}

/// The texture's structure at footprints past its block side (Δ_R = 8 in
/// `texture-synthetic-grey`): mipmap levels 0.6 (between levels 0 and 1), 2 (the top, one mean)
/// and a blend of 1 and 2, on both evaluators — the standard minified window (scale 4) reads
/// level 0 only.
#[test]
fn minified_texture_structures_agree_across_mipmap_levels() {
    use spectex_crosscheck::{CaseWindow, Verdict};
    let Some(context) = gpu_or_skip("cross-check") else {
        return;
    };
    let file = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models/texture-synthetic-grey.json"
    ));
    let model = spectex_model::from_json(&std::fs::read_to_string(file).unwrap()).unwrap();
    let windows: Vec<CaseWindow> = [("mip-0.6", 12.0), ("mip-1.6", 24.5), ("mip-2", 40.0)]
        .into_iter()
        .map(|(name, scale)| CaseWindow {
            name,
            width: 48,
            height: 40,
            offset: [-3.25, 17.5],
            scale,
        })
        .collect();
    let outcomes = check_model(&context, "texture-synthetic-grey", &model, &windows).unwrap();
    for (w, o) in &outcomes {
        println!("{w}: max {:.2e}", o.comparison.max_abs);
        assert!(matches!(o.verdict, Verdict::Pass), "{w}: {:?}", o.verdict);
    }
}

/// Every phasor profile filtered through its Fourier series (sine, triangle, sawtooth, samples,
/// explicit harmonics; the square is in `testdata/models/`) on `phasor-pwm-coherent`'s field,
/// minified at scale 4 (u = 0.24: harmonics up to the second) and at scale 1.5 (up to the
/// sixth), on both evaluators.
#[test]
fn minified_phasor_profiles_agree() {
    use spectex_crosscheck::{CaseWindow, Verdict};
    use spectex_model::{Harmonic, Model, Profile};
    let Some(context) = gpu_or_skip("cross-check") else {
        return;
    };
    let file = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models/phasor-pwm-coherent.json"
    ));
    let base = spectex_model::from_json(&std::fs::read_to_string(file).unwrap()).unwrap();
    let windows: Vec<CaseWindow> = [("scale-4", 4.0), ("scale-1.5", 1.5)]
        .into_iter()
        .map(|(name, scale)| CaseWindow {
            name,
            width: 48,
            height: 40,
            offset: [-3.25, 17.5],
            scale,
        })
        .collect();
    let harmonic = |k, weight, phase| Harmonic { k, weight, phase };
    for (name, profile) in [
        ("sine", Profile::Sine),
        ("triangle", Profile::Triangle),
        ("sawtooth", Profile::Sawtooth),
        (
            "samples",
            Profile::Samples {
                values: vec![0.0, 0.5, 1.0, 0.8, 0.3, 0.0, -0.2, -0.1],
            },
        ),
        (
            "harmonics",
            Profile::Harmonics {
                terms: vec![
                    harmonic(1, 1.0, 0.0),
                    harmonic(3, 0.5, 1.0),
                    harmonic(7, 0.3, 0.5),
                ],
            },
        ),
    ] {
        let mut model = base.clone();
        if let Model::Phasor(p) = &mut model {
            p.profile = profile;
        }
        let outcomes = check_model(&context, name, &model, &windows).unwrap();
        for (w, o) in &outcomes {
            println!("{name} {w}: max {:.2e}", o.comparison.max_abs);
            assert!(
                matches!(o.verdict, Verdict::Pass),
                "{name} {w}: {:?}",
                o.verdict
            );
        }
    }
}

/// Periodic models (issue 17, seamless output): every shipped model of a kind with a periodic
/// form (`spectex_model::PERIODIC_KINDS`) that takes a 96×64, 256×128, 768×768 or 480×320
/// period agrees on the CPU and the GPU within its kind's derived tolerances on the standard
/// windows (each a path of its own on the CPU: whole sub-windows, far positions, points, points
/// with a footprint), and the GPU's own render repeats bit for bit: a window across the seams
/// at the origin equals the same window moved by one period in x, in y and in both (the device
/// evaluates the same reduced positions). Every periodic kind has such a model.
///
/// The repeat is checked on windows of at most 64² pixels across the seams: rendering two whole
/// periods (`2W × 2H`, up to 1536² for a 768² period, against one `W × H` period) took about
/// three quarters of this test's time on lavapipe and only repeats the same exact host
/// reduction at more interior positions. Tiles, fractional offsets and windows moved by many
/// periods: `spectex-gpu`'s `periodic_tiles_and_whole_periods_are_invisible`.
#[test]
fn periodic_models_agree_on_cpu_and_gpu() {
    use spectex_crosscheck::check_model_with_period;
    use spectex_gpu::{GpuEvaluator, GpuWindow};
    use spectex_model::{PERIODIC_KINDS, Period};
    let Some(context) = gpu_or_skip("cross-check") else {
        return;
    };
    let mut failed = Vec::new();
    let mut checked = Vec::new();
    for file in &model_files() {
        let case = file.file_stem().unwrap().to_string_lossy().into_owned();
        let model = spectex_model::from_json(&std::fs::read_to_string(file).unwrap()).unwrap();
        let Some(period) = [(96, 64), (256, 128), (768, 768), (480, 320)]
            .map(|(w, h)| Period::new(w, h).unwrap())
            .into_iter()
            .find(|&p| model.check_period(p).is_ok())
        else {
            continue;
        };
        let name = format!("{case}-periodic");
        let outcomes = check_model_with_period(
            &context,
            &name,
            &model,
            &standard_windows(),
            spectex_crosscheck::tolerance::check_kind(&model).check_plane(),
            Some(period),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        for (window, outcome) in &outcomes {
            println!("{name} {period} {window}: {}", outcome.summary());
            if !outcome.passed() {
                failed.push(format!("{name} {}: {}", window.name, outcome.summary()));
            }
        }
        let gpu = GpuEvaluator::periodic_at_z(&context, &model, 0.0, period).unwrap();
        let c = gpu.output_channels();
        let (w, h) = (period.width as usize, period.height as usize);
        let (a, b) = (w.min(64), h.min(64));
        // Integer positions from x = −29, y = −35: across the seams x = 0 and y = 0.
        let at = [-29.0, -35.0];
        let seams = gpu.render(&GpuWindow::new(a, b).at(at, 1.0)).unwrap();
        assert_eq!(
            seams.len(),
            a * b * c,
            "{name}: one value per pixel and channel"
        );
        for (dx, dy) in [(w, 0), (0, h), (w, h)] {
            let moved = gpu
                .render(&GpuWindow::new(a, b).at([at[0] + dx as f64, at[1] + dy as f64], 1.0))
                .unwrap();
            for (n, (p, q)) in seams.iter().zip(&moved).enumerate() {
                assert_eq!(
                    p.to_bits(),
                    q.to_bits(),
                    "{name} on the GPU: pixel ({}, {}) channel {} moved by ({dx}, {dy})",
                    n / c % a,
                    n / c / a,
                    n % c
                );
            }
        }
        checked.push((case, model.kind()));
    }
    println!("periodic cross-check: {checked:?}");
    let missing: Vec<&&str> = PERIODIC_KINDS
        .iter()
        .filter(|k| !checked.iter().any(|(_, kind)| kind == *k))
        .collect();
    assert!(
        missing.is_empty(),
        "periodic kinds without a case: {missing:?}"
    );
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
