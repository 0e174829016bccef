//! Criterion benches of CPU evaluation in Mpix/s: LRP with J = 3, 10, 50 over 4 strata (the
//! periods a 512² exemplar's fit gives: Δ_S = 4.5, 9, 16, 28 pixels), 1 thread and all threads.
//!
//! `cargo bench -p spectex-cpu --bench eval`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spectex_cpu::{Evaluator, Window};
use spectex_model::random::{Prng, cell_hash};
use spectex_model::{LrpNoise, Model, Stratum};
use std::hint::black_box;

/// A 4-stratum LRP model with `budget` cosines in all, tables of 40 frequencies.
pub fn bench_model(budget: usize) -> Model {
    let mut prng = Prng::new(cell_hash(1, 2, 3, 4));
    let widths = [4.5f32, 9.0, 16.0, 28.0];
    let strata = widths
        .iter()
        .enumerate()
        .map(|(s, &w)| {
            let j = budget / 4 + usize::from(s < budget % 4);
            Stratum {
                window_width: w,
                amplitude: 0.05,
                sub_strata: (0..j.max(1))
                    .map(|_| {
                        (0..40)
                            .map(|_| [prng.next_f32() - 0.5, prng.next_f32() * 0.5])
                            .collect()
                    })
                    .collect(),
            }
        })
        .collect();
    Model::Lrp(LrpNoise {
        seed: 9,
        mean: 0.5,
        strata,
    })
}

fn bench(c: &mut Criterion) {
    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("lrp_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    let threads = rayon::current_num_threads();
    for budget in [3usize, 10, 50] {
        let eval = Evaluator::new(&bench_model(budget)).expect("valid model");
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

criterion_group!(benches, bench);
criterion_main!(benches);
