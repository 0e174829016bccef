//! Criterion benches of the classic noises against the crates people use today, in one process:
//! `noise` (noise-rs 0.9) and `fastnoise-lite` 1.1, at 1024², 1 thread and all threads, with a
//! lattice cell of 32 pixels (frequency 1/32) for every library.
//!
//! Cases: Perlin 2D (ours: improved gradient noise), simplex 2D (noise-rs `Simplex`,
//! fastnoise-lite `OpenSimplex2`), fBm of Perlin with 6 octaves (lacunarity 2, gain ½), and
//! cellular F1 (Euclidean, one jittered point per cell).
//!
//! `cargo bench -p spectex-cpu --bench classic`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fastnoise_lite::{
    CellularDistanceFunction, CellularReturnType, FastNoiseLite, FractalType, NoiseType,
};
use noise::{Fbm, MultiFractal, NoiseFn, Perlin, Simplex, Worley};
use rayon::prelude::*;
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::classic::{Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric};
use std::hint::black_box;

/// A reference library's noise at a pixel position.
type PixelNoise<'a> = &'a (dyn Fn(f64, f64) -> f32 + Sync);

const SIDE: usize = 1024;
const CELL: f64 = 32.0;

fn ours(basis: Basis, octaves: Option<u32>) -> Evaluator {
    let model = ClassicNoise {
        seed: 1,
        dimensions: 2,
        cell_size: CELL as f32,
        basis,
        fractal: octaves.map(|octaves| Fractal {
            kind: FractalKind::Fbm,
            octaves,
            lacunarity: 2.0,
            gain: 0.5,
        }),
        amplitude: 1.0,
        mean: 0.0,
    };
    Evaluator::new(&Model::Classic(model)).expect("valid model")
}

/// Fills a 1024² image row by row with `f(x, y)` in pixels, on the current rayon pool.
fn fill(out: &mut [f32], f: &(dyn Fn(f64, f64) -> f32 + Sync)) {
    out.par_chunks_mut(SIDE).enumerate().for_each(|(y, row)| {
        for (x, v) in row.iter_mut().enumerate() {
            *v = f(x as f64, y as f64);
        }
    });
}

fn fastnoise(noise_type: NoiseType) -> FastNoiseLite {
    let mut n = FastNoiseLite::with_seed(1);
    n.set_noise_type(Some(noise_type));
    n.set_frequency(Some((1.0 / CELL) as f32));
    n
}

fn bench(c: &mut Criterion) {
    let window = Window::new(SIDE, SIDE);
    let mut group = c.benchmark_group("classic");
    group.throughput(Throughput::Elements((SIDE * SIDE) as u64));
    group.sample_size(10);
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let all = rayon::ThreadPoolBuilder::new().build().expect("pool");
    let pools = [
        ("1_thread".to_owned(), &single),
        (format!("{}_threads", all.current_num_threads()), &all),
    ];
    let cellular = || {
        Basis::Worley(spectex_model::classic::Worley {
            metric: Metric::Euclidean,
            coefficients: [1.0, 0.0, 0.0, 0.0],
            points: FeaturePoints::Fixed(1),
        })
    };
    let ours_cases = [
        ("perlin", ours(Basis::Gradient, None)),
        ("simplex", ours(Basis::Simplex, None)),
        ("fbm6", ours(Basis::Gradient, Some(6))),
        ("cellular_f1", ours(cellular(), None)),
    ];
    let k = 1.0 / CELL;
    let perlin = Perlin::new(1);
    let simplex = Simplex::new(1);
    let fbm: Fbm<Perlin> = Fbm::new(1)
        .set_octaves(6)
        .set_lacunarity(2.0)
        .set_persistence(0.5);
    let fl_perlin = fastnoise(NoiseType::Perlin);
    let fl_simplex = fastnoise(NoiseType::OpenSimplex2);
    let mut fl_fbm = fastnoise(NoiseType::Perlin);
    fl_fbm.set_fractal_type(Some(FractalType::FBm));
    fl_fbm.set_fractal_octaves(Some(6));
    fl_fbm.set_fractal_lacunarity(Some(2.0));
    fl_fbm.set_fractal_gain(Some(0.5));
    let mut fl_cell = fastnoise(NoiseType::Cellular);
    fl_cell.set_cellular_distance_function(Some(CellularDistanceFunction::Euclidean));
    fl_cell.set_cellular_return_type(Some(CellularReturnType::Distance));
    fl_cell.set_cellular_jitter(Some(1.0));
    let theirs: [(&str, &str, PixelNoise<'_>); 6] = [
        ("perlin", "noise-rs", &|x, y| {
            perlin.get([x * k, y * k]) as f32
        }),
        ("perlin", "fastnoise-lite", &|x, y| {
            fl_perlin.get_noise_2d(x as f32, y as f32)
        }),
        ("simplex", "noise-rs", &|x, y| {
            simplex.get([x * k, y * k]) as f32
        }),
        ("simplex", "fastnoise-lite", &|x, y| {
            fl_simplex.get_noise_2d(x as f32, y as f32)
        }),
        ("fbm6", "noise-rs", &|x, y| fbm.get([x * k, y * k]) as f32),
        ("fbm6", "fastnoise-lite", &|x, y| {
            fl_fbm.get_noise_2d(x as f32, y as f32)
        }),
    ];
    let mut out = vec![0.0f32; SIDE * SIDE];
    for (threads, pool) in &pools {
        for (case, eval) in &ours_cases {
            group.bench_function(BenchmarkId::new(format!("{case}/spectex"), threads), |b| {
                b.iter(|| pool.install(|| eval.render_into(black_box(&window), &mut out, &|_| {})))
            });
            for (name, library, f) in &theirs {
                if name == case {
                    group.bench_function(
                        BenchmarkId::new(format!("{case}/{library}"), threads),
                        |b| b.iter(|| pool.install(|| fill(&mut out, *f))),
                    );
                }
            }
            if *case == "cellular_f1" {
                // noise-rs `Worley` is not `Send`: one per rayon task.
                group.bench_function(BenchmarkId::new("cellular_f1/noise-rs", threads), |b| {
                    b.iter(|| {
                        pool.install(|| {
                            out.par_chunks_mut(SIDE).enumerate().for_each_init(
                                || Worley::new(1),
                                |worley, (y, row)| {
                                    for (x, v) in row.iter_mut().enumerate() {
                                        *v = worley.get([x as f64 * k, y as f64 * k]) as f32;
                                    }
                                },
                            );
                        })
                    })
                });
                group.bench_function(
                    BenchmarkId::new("cellular_f1/fastnoise-lite", threads),
                    |b| {
                        b.iter(|| {
                            pool.install(|| {
                                fill(&mut out, &|x, y| fl_cell.get_noise_2d(x as f32, y as f32))
                            })
                        })
                    },
                );
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
