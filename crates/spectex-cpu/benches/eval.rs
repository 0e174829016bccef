//! Criterion benches of CPU evaluation in Mpix/s: LRP with J = 3, 10, 50 over 4 strata (the
//! periods a 512² exemplar's fit gives: Δ_S = 4.5, 9, 16, 28 pixels), 1 thread and all threads.
//!
//! Phasor noise in 2D and on a 3D slice (`phasor_eval`).
//!
//! Minified LRP (`lrp_minified`): J = 50 at scale 4, filtered (the default, faded cosines
//! multiplied by their gains, strata faded whole skipped) against point-sampled
//! (`Filter::Off`), 1 thread: the filtering's cost as a ratio within one run.
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

/// Phasor noise, 2D and a 3D slice: `spectex_model::fixtures::phasor_pwm` (PWM profile) with
/// aligned (bi-lobe), coherent isotropic and (3D) isotropic directions.
fn bench_phasor(c: &mut Criterion) {
    use spectex_model::fixtures::phasor_pwm;
    use spectex_model::{Field, PhasorOrientation};
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("phasor_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    let threads = rayon::current_num_threads();
    for (name, dimensions, orientation) in [
        (
            "2d_aligned",
            2,
            PhasorOrientation::Aligned {
                angle: Field::constant(0.5),
            },
        ),
        (
            "2d_coherent",
            2,
            PhasorOrientation::Coherent {
                spread: 2.4,
                bandwidth_ratio: 0.5,
            },
        ),
        ("3d_isotropic", 3, PhasorOrientation::Isotropic),
    ] {
        let model = Model::Phasor(phasor_pwm(dimensions, orientation));
        let eval = Evaluator::new_at_z(&model, 17.5).expect("valid model");
        group.bench_function(format!("{name}_{threads}_threads"), |b| {
            b.iter(|| eval.render(black_box(&window)))
        });
    }
    group.finish();
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

criterion_group!(benches, bench, bench_phasor, bench_minified);
criterion_main!(benches);
