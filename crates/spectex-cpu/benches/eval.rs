//! Criterion benches of CPU evaluation in Mpix/s: LRP with J = 3, 10, 50 over 4 strata (the
//! periods a 512² exemplar's fit gives: Δ_S = 4.5, 9, 16, 28 pixels), 1 thread and all threads.
//!
//! Phasor noise in 2D and on a 3D slice (`phasor_eval`) and domain warping (`warp_eval`), each
//! against the reference path it replaced in the same run (`Evaluator::render_reference`).
//!
//! Minified LRP (`lrp_minified`): J = 50 at scale 4, filtered (the default, faded cosines
//! multiplied by their gains, strata faded whole skipped) against point-sampled
//! (`Filter::Off`), 1 thread: the filtering's cost as a ratio within one run.
//!
//! Every kind (`kinds`): one model of each, built here or read from `testdata/models/` (and
//! classic Kensler noise in 2D and as a 3D fBm), 256², 1 thread and all threads, and the phasor,
//! warp and classic reference paths beside them; `cargo xtask bench` turns it into a table and a chart. With
//! `SPECTEX_BENCH_DIR` set, the group writes each kind's evaluations per pixel and pixels per
//! render to `kinds.tsv` there.
//!
//! `cargo bench -p spectex-cpu --bench eval`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spectex_cpu::{Evaluator, Filter, Window};
use spectex_model::Model;
use spectex_model::fixtures::lrp_four_strata;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("lrp_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    let threads = rayon::current_num_threads();
    for budget in [3usize, 10, 50] {
        let eval = Evaluator::new(&Model::Lrp(lrp_four_strata(budget))).expect("valid model");
        let single = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        group.bench_function(format!("J{budget}_1_thread"), |b| {
            b.iter(|| single.install(|| eval.render(black_box(&window))))
        });
        group.bench_function(format!("J{budget}_{threads}_threads"), |b| {
            b.iter(|| eval.render(black_box(&window)))
        });
    }
    group.finish();
}

/// The `spectex phasor` model with every flag at its default (`F = 0.05`, `b = 0.02`, 32
/// impulses per kernel, aligned along x: 92 kernels per pixel in 2D) and the given profile and
/// dimensions; the CLI's own mean and amplitude.
fn default_phasor(dimensions: u8, profile: spectex_model::Profile) -> Model {
    Model::Phasor(
        spectex_model::PhasorNoise::builder()
            .dimensions(dimensions)
            .profile(profile)
            .build()
            .expect("valid model"),
    )
}

/// Every profile of `spectex phasor --profile` (the square at its default duty of ½) and an
/// additive one (`--harmonics 1:1,3:0.33,5:0.2`).
fn phasor_profiles() -> Vec<(&'static str, spectex_model::Profile)> {
    use spectex_model::{Harmonic, Profile};
    let harmonic = |k, weight| Harmonic {
        k,
        weight,
        phase: 0.0,
    };
    vec![
        ("sine", Profile::Sine),
        ("square", Profile::square(0.5)),
        ("triangle", Profile::Triangle),
        ("sawtooth", Profile::Sawtooth),
        (
            "harmonics",
            Profile::Harmonics {
                terms: vec![harmonic(1, 1.0), harmonic(3, 0.33), harmonic(5, 0.2)],
            },
        ),
    ]
}

/// Phasor noise, all threads, the row kernel (`rows`) against the pixel-by-pixel sum it
/// replaced (`reference`, [`Evaluator::render_reference`]) in the same run: the `spectex
/// phasor` defaults in 2D and on a 3D slice with every profile, and
/// `spectex_model::fixtures::phasor_pwm` with aligned (bi-lobe), coherent isotropic and (3D)
/// isotropic directions.
fn bench_phasor(c: &mut Criterion) {
    use spectex_model::fixtures::phasor_pwm;
    use spectex_model::{Field, PhasorOrientation};
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("phasor_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_millis(500));
    group.measurement_time(std::time::Duration::from_secs(2));
    let threads = rayon::current_num_threads();
    let mut models = Vec::new();
    for (dims, dimensions) in [("2d", 2), ("3d", 3)] {
        for (name, profile) in phasor_profiles() {
            models.push((
                format!("default_{dims}_{name}"),
                default_phasor(dimensions, profile),
            ));
        }
    }
    for (name, dimensions, orientation) in [
        (
            "pwm_2d_aligned",
            2,
            PhasorOrientation::Aligned {
                angle: Field::constant(0.5),
            },
        ),
        (
            "pwm_2d_coherent",
            2,
            PhasorOrientation::Coherent {
                spread: 2.4,
                bandwidth_ratio: 0.5,
            },
        ),
        ("pwm_3d_isotropic", 3, PhasorOrientation::Isotropic),
    ] {
        models.push((
            name.to_string(),
            Model::Phasor(phasor_pwm(dimensions, orientation)),
        ));
    }
    for (name, model) in &models {
        let eval = Evaluator::new_at_z(model, 17.5).expect("valid model");
        group.bench_function(format!("{name}_reference_{threads}_threads"), |b| {
            b.iter(|| eval.render_reference(black_box(&window)))
        });
        group.bench_function(format!("{name}_rows_{threads}_threads"), |b| {
            b.iter(|| eval.render(black_box(&window)))
        });
    }
    group.finish();
}

/// Domain warping, `spectex warp` with its defaults (a Perlin fBm displaced by two fBms, 5
/// octaves each), 256²: the base at a band's displaced positions in its lanes (`rows`) against
/// point by point through one-pixel windows (`reference`), 1 thread and all threads.
fn bench_warp(c: &mut Criterion) {
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("warp_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_millis(500));
    group.measurement_time(std::time::Duration::from_secs(2));
    let threads = rayon::current_num_threads();
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let model = Model::Warp(spectex_model::Warp::builder().build().expect("valid model"));
    let eval = Evaluator::new(&model).expect("valid model");
    group.bench_function("fbm_by_fbm_reference_1_thread", |b| {
        b.iter(|| single.install(|| eval.render_reference(black_box(&window))))
    });
    group.bench_function("fbm_by_fbm_rows_1_thread", |b| {
        b.iter(|| single.install(|| eval.render(black_box(&window))))
    });
    group.bench_function(format!("fbm_by_fbm_reference_{threads}_threads"), |b| {
        b.iter(|| eval.render_reference(black_box(&window)))
    });
    group.bench_function(format!("fbm_by_fbm_rows_{threads}_threads"), |b| {
        b.iter(|| eval.render(black_box(&window)))
    });
    group.finish();
}

/// A model of `testdata/models/`.
fn testdata(text: &str) -> Model {
    spectex_model::from_json(text).expect("a valid testdata model")
}

/// Every kind's bench case (`CpuKind::bench_model`, collected by `spectex_cpu::bench_models`),
/// as `cargo xtask bench` summarises them, then the reference paths of the kinds that have a
/// faster one (`*_reference`) and Kensler's basis: `(name, model, reference path)`.
fn kinds() -> Vec<(&'static str, Model, bool)> {
    use spectex_model::classic::ClassicNoise;
    let mut kinds: Vec<(&'static str, Model, bool)> = spectex_cpu::bench_models()
        .into_iter()
        .map(|(name, case)| {
            let model = match case {
                spectex_cpu::BenchModel::Built(model) => model,
                spectex_cpu::BenchModel::Testdata(file) => {
                    let path = format!(
                        "{}/../../testdata/models/{file}",
                        env!("CARGO_MANIFEST_DIR")
                    );
                    let text = std::fs::read_to_string(&path)
                        .unwrap_or_else(|e| panic!("reading {path}: {e}"));
                    spectex_model::from_json(&text).expect("testdata models are valid")
                }
            };
            (name, model, false)
        })
        .collect();
    kinds.extend([
        (
            "phasor_reference",
            default_phasor(2, spectex_model::Profile::Sine),
            true,
        ),
        (
            "classic_reference",
            Model::Classic(ClassicNoise::fbm().build().expect("valid model")),
            true,
        ),
        (
            "warp_reference",
            Model::Warp(spectex_model::Warp::builder().build().expect("valid model")),
            true,
        ),
        (
            "kensler",
            testdata(include_str!(
                "../../../testdata/models/classic-kensler-2d.json"
            )),
            false,
        ),
        (
            "kensler_3d_fbm",
            testdata(include_str!(
                "../../../testdata/models/classic-kensler-3d-fbm.json"
            )),
            false,
        ),
    ]);
    kinds
}

/// Every kind at 256², 1 thread and all threads (`{name}_1_thread`, `{name}_all_threads`),
/// briefly: a summary, not a precise measurement.
fn bench_kinds(c: &mut Criterion) {
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("kinds");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    group.warm_up_time(std::time::Duration::from_millis(300));
    group.measurement_time(std::time::Duration::from_secs(1));
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let mut costs = String::from("kind\tevaluations_per_pixel\tpixels\n");
    for (name, model, reference) in kinds() {
        let eval = Evaluator::new(&model).expect("valid model");
        costs.push_str(&format!(
            "{name}\t{}\t{}\n",
            eval.cost_per_pixel(),
            side * side
        ));
        let render = |w: &Window| {
            if reference {
                eval.render_reference(w)
            } else {
                eval.render(w)
            }
        };
        group.bench_function(format!("{name}_1_thread"), |b| {
            b.iter(|| single.install(|| render(black_box(&window))))
        });
        group.bench_function(format!("{name}_all_threads"), |b| {
            b.iter(|| render(black_box(&window)))
        });
    }
    group.finish();
    if let Some(dir) = std::env::var_os("SPECTEX_BENCH_DIR") {
        let dir = std::path::PathBuf::from(dir);
        std::fs::create_dir_all(&dir)
            .and_then(|()| std::fs::write(dir.join("kinds.tsv"), costs))
            .expect("writing kinds.tsv");
    }
}

/// LRP J = 50 over 4 strata at scale 4, filtered and point-sampled, 1 thread.
fn bench_minified(c: &mut Criterion) {
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 4.0);
    let mut group = c.benchmark_group("lrp_minified");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    let eval = Evaluator::new(&Model::Lrp(lrp_four_strata(50))).expect("valid model");
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    for (name, filter) in [("filtered", Filter::Pixel), ("point_sampled", Filter::Off)] {
        let w = window.filtered(filter);
        group.bench_function(format!("J50_scale4_{name}_1_thread"), |b| {
            b.iter(|| single.install(|| eval.render(black_box(&w))))
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    bench,
    bench_phasor,
    bench_warp,
    bench_minified,
    bench_kinds
);
criterion_main!(benches);
