//! Criterion benches of the classic noises against the crates people use today, in one process:
//! `noise` (noise-rs 0.9) and `fastnoise-lite` 1.1, at 1024², 1 thread and all threads, with a
//! lattice cell of 32 pixels (frequency 1/32) for every library.
//!
//! Cases: Perlin 2D (ours: improved gradient noise), simplex 2D (noise-rs `Simplex`,
//! fastnoise-lite `OpenSimplex2`), fBm of Perlin with 6 octaves (lacunarity 2, gain ½), and
//! cellular F1 (Euclidean, one jittered point per cell).
//!
//! The `grid` group is the grid FastNoiseSIMD is measured on (`benches/fastnoisesimd.py`): a
//! 2048² slice of 3D noise at z = 7 pixels and the same 2048² window of 2D noise, cell 32, one
//! thread; Perlin, value, simplex, cellular F1 and fBm of Perlin (6 octaves), each lattice
//! noise's reference path beside it (`*_reference`, every hash in the lanes). Timed by the
//! render thread's CPU time, not the wall clock, so that other work on a shared machine does
//! not count (`cpu_time`), as FastNoiseSIMD's side is (`time.thread_time`). The cost of the
//! guarantees (`*_exact` against `*_relaxed`, both through `ClassicEvaluator::eval_rows` over
//! the whole window): the bench-only relaxed evaluator splits positions into cells in f32 and
//! fuses multiply-adds, as f32 SIMD libraries do (skipped where the CPU has no AVX2 and FMA).
//! `cargo xtask bench classic` runs it and FastNoiseSIMD in one invocation and writes the
//! ratio table.
//!
//! `cargo bench -p spectex-cpu --bench classic`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fastnoise_lite::{
    CellularDistanceFunction, CellularReturnType, FastNoiseLite, FractalType, NoiseType,
};
use noise::{Fbm, MultiFractal, NoiseFn, Perlin, Simplex, Worley};
use rayon::prelude::*;
use spectex_cpu::classic::ClassicEvaluator;
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::classic::{Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// A reference library's noise at a pixel position.
type PixelNoise<'a> = &'a (dyn Fn(f64, f64) -> f32 + Sync);

/// The window side of the library comparison (benchmarking; 64 in a test pass).
fn side() -> usize {
    spectex_testkit::bench::side(1024)
}
const CELL: f64 = 32.0;

fn ours(basis: Basis, octaves: Option<u32>) -> Evaluator {
    Evaluator::new(&Model::Classic(classic(basis, octaves, 2))).expect("valid model")
}

/// The noise of a case: `basis`, fBm of `octaves` (lacunarity 2, gain ½) or none, cell 32.
fn classic(basis: Basis, octaves: Option<u32>, dimensions: u32) -> ClassicNoise {
    ClassicNoise {
        seed: 1,
        dimensions,
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
    }
}

/// Side of the `grid` group's window.
fn grid() -> usize {
    spectex_testkit::bench::side(2048)
}
/// The plane of the 3D slices, pixels.
const GRID_Z: f64 = 7.0;

/// The CPU time of the calling thread, where the platform reports it (Linux:
/// `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`, exact to the nanosecond, unlike
/// `/proc/thread-self/schedstat`, which lags by up to a scheduler tick).
#[cfg(target_os = "linux")]
fn thread_cpu_time() -> Option<Duration> {
    /// `struct timespec` on 64-bit Linux.
    #[repr(C)]
    struct Timespec {
        seconds: i64,
        nanoseconds: i64,
    }
    #[allow(unsafe_code)]
    // SAFETY (of the declaration): the C library's `int clock_gettime(clockid_t, struct
    // timespec *)`, `clockid_t` being `int` on Linux.
    unsafe extern "C" {
        fn clock_gettime(clock: i32, time: *mut Timespec) -> i32;
    }
    /// `CLOCK_THREAD_CPUTIME_ID` (`<time.h>`).
    const THREAD_CPU_TIME: i32 = 3;
    if cfg!(not(target_pointer_width = "64")) {
        return None;
    }
    let mut time = Timespec {
        seconds: 0,
        nanoseconds: 0,
    };
    #[allow(unsafe_code)]
    // SAFETY: `clock_gettime` writes one `struct timespec` (two 64-bit fields on 64-bit Linux,
    // the layout of `Timespec`) through a pointer to a live, writable value, and reads nothing
    // else.
    let status = unsafe { clock_gettime(THREAD_CPU_TIME, &raw mut time) };
    (status == 0).then(|| {
        Duration::from_secs(time.seconds.unsigned_abs())
            + Duration::from_nanos(time.nanoseconds.unsigned_abs())
    })
}

/// The CPU time of the calling thread: not reported on this platform.
#[cfg(not(target_os = "linux"))]
fn thread_cpu_time() -> Option<Duration> {
    None
}

/// `iters` runs of `f` on the one thread of `pool`, timed by that thread's CPU time (wall-clock
/// time where the platform has no per-thread clock): machines shared with other builds slow the
/// wall clock, not the CPU time a render takes.
fn cpu_time<T>(pool: &rayon::ThreadPool, iters: u64, mut f: impl FnMut() -> T + Send) -> Duration {
    pool.install(|| {
        let (cpu, wall) = (thread_cpu_time(), Instant::now());
        for _ in 0..iters {
            black_box(f());
        }
        match (cpu, thread_cpu_time()) {
            (Some(start), Some(end)) => end.saturating_sub(start),
            _ => wall.elapsed(),
        }
    })
}

/// FastNoiseSIMD's grid (see the module doc): `grid/{case}_{3d,2d}[_reference]`, 1 thread.
fn bench_grid(c: &mut Criterion) {
    let window = Window::new(grid(), grid());
    let mut group = c.benchmark_group("grid");
    group.throughput(Throughput::Elements((grid() * grid()) as u64));
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let cellular = Basis::Worley(spectex_model::classic::Worley {
        metric: Metric::Euclidean,
        coefficients: [1.0, 0.0, 0.0, 0.0],
        points: FeaturePoints::Fixed(1),
    });
    let cases = [
        ("perlin", Basis::Gradient, None, true),
        ("value", Basis::Value, None, true),
        ("simplex", Basis::Simplex, None, false),
        ("kensler", Basis::Kensler, None, false),
        ("cellular", cellular, None, false),
        ("fbm6", Basis::Gradient, Some(6), true),
    ];
    let mut out = vec![0.0f32; grid() * grid()];
    for dimensions in [3, 2] {
        for (case, basis, octaves, reference) in &cases {
            let noise = classic(basis.clone(), *octaves, dimensions);
            let model = Model::Classic(noise.clone());
            let eval = Evaluator::new_at_z(&model, GRID_Z).expect("valid model");
            let id = format!("{case}_{dimensions}d");
            group.bench_function(id.as_str(), |b| {
                b.iter_custom(|iters| {
                    cpu_time(&single, iters, || {
                        eval.render_into(black_box(&window), &mut out, &|_| {})
                    })
                })
            });
            if *reference {
                group.bench_function(format!("{id}_reference"), |b| {
                    b.iter_custom(|iters| {
                        cpu_time(&single, iters, || eval.render_reference(black_box(&window)))
                    })
                });
            }
            // What the guarantees cost: the same noise by the kind's own evaluator, exact and
            // with the bench-only f32 split and FMA (`ClassicEvaluator::set_relaxed`).
            let exact = ClassicEvaluator::new(&noise, GRID_Z);
            let mut relaxed = exact.clone();
            if relaxed.set_relaxed(true) {
                for (suffix, eval) in [("exact", &exact), ("relaxed", &relaxed)] {
                    group.bench_function(format!("{id}_{suffix}"), |b| {
                        b.iter_custom(|iters| {
                            cpu_time(&single, iters, || {
                                eval.eval_rows(black_box(&window), 0, &mut out);
                            })
                        })
                    });
                }
            }
        }
    }
    group.finish();
}

/// Fills a 1024² image row by row with `f(x, y)` in pixels, on the current rayon pool.
fn fill(out: &mut [f32], f: &(dyn Fn(f64, f64) -> f32 + Sync)) {
    out.par_chunks_mut(side()).enumerate().for_each(|(y, row)| {
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
    let window = Window::new(side(), side());
    let mut group = c.benchmark_group("classic");
    group.throughput(Throughput::Elements((side() * side()) as u64));
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
    let mut out = vec![0.0f32; side() * side()];
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
                            out.par_chunks_mut(side()).enumerate().for_each_init(
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

criterion_group!(benches, bench, bench_grid);
criterion_main!(benches);
