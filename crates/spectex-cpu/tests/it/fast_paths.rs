//! The fast paths against the slow, obviously correct paths they replaced, bit for bit, over
//! every `testdata/models/*.json`: the phasor row kernel against the per-pixel sum at every
//! SIMD level, warps (their base at a band's displaced positions in its lanes) against point
//! by point, `eval_points` against one-pixel windows, and uneven bands of rows and thread
//! counts against a whole render. The kit's invariance harness checks tilings and thread
//! counts of every model as well; these tests compare with the reference path, not with
//! hashes the code under test produced.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_cpu::classic::ClassicEvaluator;
use spectex_cpu::tiling::TilingEvaluator;
use spectex_cpu::{Evaluator, PhasorEvaluator, RowKernel, Window};
use spectex_model::Model;
use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric, Worley,
};
use spectex_testkit::invariance::{Case, minified_window, testdata_cases, tile_window};

/// Windows near and far, zoomed in and out (one minified, which the phasor and LRP kernels
/// evaluate pixel by pixel), at fractional scales.
fn windows() -> Vec<(&'static str, Window)> {
    vec![
        ("near", Window::new(128, 96).at([-3141.5, 2718.25], 1.0)),
        ("far", tile_window()),
        ("zoomed in", Window::new(80, 24).at([123.4, -56.7], 0.05)),
        ("coarse", Window::new(72, 20).at([-2.0e6 + 0.7, 4.0e5], 7.3)),
        ("minified", minified_window()),
    ]
}

/// A SIMD level by name and how to select it on an evaluator (`false`: the CPU lacks it).
type SimdLevel<E> = (&'static str, fn(&mut E) -> bool);

/// The row kernels whose SIMD level tests choose (`set_avx2`, `set_avx512`).
trait SimdChoice {
    fn set_avx2(&mut self, enabled: bool);
    fn set_avx512(&mut self, enabled: bool) -> bool;
}

impl SimdChoice for PhasorEvaluator {
    fn set_avx2(&mut self, enabled: bool) {
        PhasorEvaluator::set_avx2(self, enabled);
    }
    fn set_avx512(&mut self, enabled: bool) -> bool {
        PhasorEvaluator::set_avx512(self, enabled)
    }
}

impl SimdChoice for TilingEvaluator {
    fn set_avx2(&mut self, enabled: bool) {
        TilingEvaluator::set_avx2(self, enabled);
    }
    fn set_avx512(&mut self, enabled: bool) -> bool {
        TilingEvaluator::set_avx512(self, enabled)
    }
}

/// Portable, AVX2 and AVX-512 (where the CPU has them) for a row kernel.
fn row_kernel_levels<E: SimdChoice>() -> [SimdLevel<E>; 3] {
    [
        ("portable", |e| {
            e.set_avx2(false);
            true
        }),
        ("avx2", |e| {
            e.set_avx2(true);
            true
        }),
        ("avx512", |e| e.set_avx512(true)),
    ]
}

/// The first index where `a` and `b` differ in bits, with both values.
fn first_difference(a: &[f32], b: &[f32]) -> Option<(usize, f32, f32)> {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .position(|(x, y)| x.to_bits() != y.to_bits())
        .map(|i| (i, a[i], b[i]))
}

fn evaluator(case: &Case) -> Evaluator {
    Evaluator::new_at_z(&case.model, case.z).unwrap()
}

#[test]
fn every_model_renders_the_reference_bits() {
    let mut failures = Vec::new();
    for case in testdata_cases() {
        let eval = evaluator(&case);
        for (name, window) in windows() {
            let fast = eval.render(&window).unwrap();
            let reference = eval.render_reference(&window).unwrap();
            if let Some((i, a, b)) = first_difference(&fast, &reference) {
                failures.push(format!(
                    "{} {name}: value {i} is {a:e}, the reference's {b:e}",
                    case.name
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The phasor row kernel on the portable, AVX2 and AVX-512 paths (those the CPU has), each
/// against the per-pixel sum.
#[test]
fn phasor_rows_match_the_per_pixel_sum_at_every_simd_level() {
    let mut compared = 0;
    for case in testdata_cases() {
        let Model::Phasor(m) = &case.model else {
            continue;
        };
        let mut eval = PhasorEvaluator::new(m, case.z);
        compared += compare_rows(&case.name, &mut eval, row_kernel_levels(), &windows());
    }
    assert!(
        compared >= 5 * 2 * windows().len(),
        "{compared} renders compared"
    );
}

/// Noises whose rows read per-row column tables: gradient, value and simplex noise in 2D and
/// 3D, cells that are and are not powers of two (the exact reciprocal and the division), octaves
/// down to cells of one pixel (gradient and value: tables; simplex: hashed in the lanes, and in 3D
/// read from the row's corner table where the cells are wide), and
/// under a pixel in the coarse windows (hashed in the lanes), ridged, at z near and far; and Worley
/// noise with fixed counts of 1 and 3 points, every metric, F1 and F2 − F1, 2D and 3D (the exact
/// search beyond the 3×3 block included).
fn table_models() -> Vec<(String, ClassicNoise, f64)> {
    let mut models = Vec::new();
    for dimensions in [2, 3] {
        for (metric, coefficients, points) in [
            (Metric::Euclidean, [1.0, 0.0, 0.0, 0.0], 1),
            (Metric::Manhattan, [-1.0, 1.0, 0.0, 0.0], 3),
            (Metric::Chebyshev, [0.5, 0.0, 0.25, 1.0], 1),
            (Metric::Euclidean, [0.0, 0.0, 0.0, 1.0], 3),
        ] {
            let model = ClassicNoise {
                seed: 4,
                dimensions,
                cell_size: 24.5,
                basis: Basis::Worley(Worley {
                    metric,
                    coefficients,
                    points: FeaturePoints::Fixed(points),
                }),
                fractal: Some(Fractal {
                    kind: FractalKind::Turbulence,
                    octaves: 4,
                    lacunarity: 2.0,
                    gain: 0.5,
                }),
                amplitude: 1.0,
                mean: 0.0,
            };
            model.validate().unwrap();
            let name = format!("worley {dimensions}D {metric:?} {points} points");
            models.push((name, model, -11.3));
        }
    }
    for (basis, name) in [
        (Basis::Gradient, "gradient"),
        (Basis::Value, "value"),
        (Basis::Simplex, "simplex"),
    ] {
        for dimensions in [2, 3] {
            for (cell, lacunarity, octaves, kind) in [
                (32.0, 2.0, 6, FractalKind::Fbm),
                (13.7, 1.9, 5, FractalKind::Fbm),
                (
                    64.0,
                    2.0,
                    7,
                    FractalKind::Ridged {
                        offset: 1.0,
                        weight_gain: 2.0,
                    },
                ),
            ] {
                for z in [7.0, -3.0e6 - 0.4] {
                    let model = ClassicNoise {
                        seed: 9,
                        dimensions,
                        cell_size: cell,
                        basis: basis.clone(),
                        fractal: Some(Fractal {
                            kind,
                            octaves,
                            lacunarity,
                            gain: 0.5,
                        }),
                        amplitude: 1.0,
                        mean: 0.25,
                    };
                    model.validate().unwrap();
                    models.push((format!("{name} {dimensions}D cell {cell} z {z}"), model, z));
                }
            }
        }
    }
    models
}

/// The tiling kernel's rows (runs of whole-pixel taps copied from the channels' planes, the
/// blend on each SIMD level) against its reference path, pixel by pixel: whole pixels near the
/// origin and at 10⁷, half pixels (every tap read alone), magnified (runs and lone taps
/// alternate), and columns past the usable range (the mean) beside valid ones.
#[test]
fn tiling_rows_match_the_reference_at_every_simd_level() {
    let windows = [
        (
            "whole pixels",
            Window::new(300, 40).at([-517.0, 283.0], 1.0),
        ),
        (
            "whole pixels at 1e7",
            Window::new(257, 9).at([1.0e7, -1.0e7 + 3.0], 1.0),
        ),
        ("half pixels", Window::new(120, 7).at([0.5, 11.0], 1.0)),
        ("magnified", Window::new(150, 12).at([-40.0, 7.0], 0.5)),
        (
            "past the range",
            Window::new(90, 3).at([f64::from(1u32 << 30) - 45.0, 0.0], 1.0),
        ),
    ];
    let mut compared = 0;
    for case in testdata_cases() {
        let Model::Tiling(m) = &case.model else {
            continue;
        };
        let mut eval = TilingEvaluator::new(m, None).unwrap();
        compared += compare_rows(&case.name, &mut eval, row_kernel_levels(), &windows);
    }
    assert!(
        compared >= 2 * 2 * windows.len(),
        "compared {compared} renders"
    );
}

/// The classic evaluator's SIMD levels: portable, AVX2 (where the CPU has it) and the widest.
fn classic_levels() -> [SimdLevel<ClassicEvaluator>; 3] {
    [
        ("portable", |e| {
            e.set_simd(false);
            true
        }),
        ("avx2", |e| e.set_avx2()),
        ("widest", |e| {
            e.set_simd(true);
            true
        }),
    ]
}

/// Renders `m` on the plane `z` over `windows` at every SIMD level the CPU has and panics at
/// the first value that differs in bits from the reference path; the number of renders compared.
fn compare_classic_rows(name: &str, m: &ClassicNoise, z: f64, windows: &[(&str, Window)]) -> usize {
    compare_rows(
        name,
        &mut ClassicEvaluator::new(m, z),
        classic_levels(),
        windows,
    )
}

/// Renders `windows` on `eval`'s fast and reference paths at each of `levels` the CPU has and
/// panics at the first value whose bits differ; the number of renders compared.
fn compare_rows<E: RowKernel>(
    name: &str,
    eval: &mut E,
    levels: [SimdLevel<E>; 3],
    windows: &[(&str, Window)],
) -> usize {
    let mut compared = 0;
    for (level, set) in levels {
        if !set(eval) {
            continue;
        }
        for (window_name, window) in windows {
            let n = window.width * window.height * eval.output_channels();
            let (mut fast, mut reference) = (vec![0.0f32; n], vec![0.0f32; n]);
            eval.eval_rows(window, 0, &mut fast);
            eval.eval_rows_reference(window, 0, &mut reference);
            if let Some((i, a, b)) = first_difference(&fast, &reference) {
                panic!(
                    "{name} on {level}, {window_name}: value {i} is {a:e}, the reference's {b:e}"
                );
            }
            compared += 1;
        }
    }
    compared
}

/// The classic row kernel (lattice hashes from per-row column tables, fetched by register
/// permutes with AVX2 and AVX-512) on every SIMD level the CPU has, against the reference path
/// that hashes every corner in the lanes, for the testdata models and [`table_models`].
#[test]
fn classic_rows_match_the_reference_at_every_simd_level() {
    let mut models: Vec<(String, ClassicNoise, f64)> = table_models();
    for case in testdata_cases() {
        if let Model::Classic(m) = &case.model {
            models.push((case.name.clone(), m.clone(), case.z));
        }
    }
    let mut windows = windows();
    // Rows of cells 32 pixels wide in 2048 columns, a window narrower than the lanes, and one
    // at the origin with the lanes across cell borders at every offset.
    windows.push(("wide", Window::new(2048, 3).at([-1.0e6 - 0.5, 77.0], 1.0)));
    windows.push(("narrow", Window::new(5, 4).at([31.0, -1.0], 1.0)));
    windows.push(("origin", Window::new(100, 8).at([-50.0, -4.0], 1.0)));
    let mut compared = 0;
    for (name, m, z) in &models {
        compared += compare_classic_rows(name, m, *z, &windows);
    }
    assert!(compared >= 80 * 8, "{compared} renders compared");
}

/// Rows longer than the classic row keeps column hashes for (16384 columns: those rows hash
/// theirs afresh) and rows sharing their keys and corner tables with the rows before: 3D
/// gradient and simplex fBm down to cells of a pixel, two seeds, at every SIMD level, against
/// the reference path.
#[test]
fn classic_long_rows_match_the_reference_at_every_simd_level() {
    let windows = [
        ("long", Window::new(16_500, 2).at([-8000.25, 3.0], 1.0)),
        ("tall", Window::new(40, 70).at([5.5, -35.0], 1.0)),
    ];
    // Two seeds one after the other on this thread: a row must not read the tables the other
    // seed's rows kept.
    for (basis, seed) in [
        (Basis::Gradient, 3),
        (Basis::Gradient, 4),
        (Basis::Simplex, 3),
        (Basis::Simplex, 4),
    ] {
        let m = ClassicNoise {
            seed,
            dimensions: 3,
            cell_size: 16.0,
            basis: basis.clone(),
            fractal: Some(Fractal {
                kind: FractalKind::Fbm,
                octaves: 5,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude: 1.0,
            mean: 0.0,
        };
        m.validate().unwrap();
        let name = format!("{basis:?} seed {seed}");
        assert!(compare_classic_rows(&name, &m, 2.5, &windows) > 0);
    }
}

/// Positions a warp may hand its base: fractional, negative, far, and a negative zero (which
/// a one-pixel window turns into a positive one).
fn points() -> Vec<[f64; 2]> {
    let mut points = vec![[-0.0, -0.0], [0.0, -0.0], [1.0e7 + 0.25, -1.0e7 - 0.5]];
    let mut state = 12_345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for k in 0..37 {
        let spread = if k % 3 == 0 { 3.0e6 } else { 500.0 };
        points.push([(next() - 0.5) * spread, (next() - 0.5) * spread]);
    }
    points
}

#[test]
fn points_match_one_pixel_windows() {
    let points = points();
    for case in testdata_cases() {
        let eval = evaluator(&case);
        let nc = eval.output_channels();
        let mut batch = vec![0.0f32; points.len() * nc];
        eval.eval_points(&points, &mut batch);
        for (k, p) in points.iter().enumerate() {
            let mut one = vec![0.0f32; nc];
            eval.eval_point(*p, &mut one);
            if let Some((c, a, b)) = first_difference(&batch[k * nc..(k + 1) * nc], &one) {
                panic!(
                    "{}: point {k} {p:?} channel {c} is {a:e} in a batch, {b:e} alone",
                    case.name
                );
            }
        }
    }
}

/// Classic noises evaluate a batch of points in their lanes: every SIMD level and every batch
/// length (a short last group) gives the one-pixel window's bits.
#[test]
fn classic_points_match_at_every_simd_level() {
    let points = points();
    for case in testdata_cases() {
        let Model::Classic(m) = &case.model else {
            continue;
        };
        let mut eval = ClassicEvaluator::new(m, case.z);
        let alone: Vec<f32> = points.iter().map(|p| eval.eval(p[0], p[1])).collect();
        let widest = eval.set_simd(true);
        let levels = classic_levels();
        for (level, set) in levels {
            if !set(&mut eval) {
                continue;
            }
            for len in [1, 5, widest + 3, points.len()] {
                let mut batch = vec![0.0f32; len];
                eval.eval_points(&points[..len], &mut batch);
                if let Some((i, a, b)) = first_difference(&batch, &alone[..len]) {
                    panic!(
                        "{} on {level}, {len} points: point {i} is {a:e}, alone {b:e}",
                        case.name
                    );
                }
            }
        }
    }
}

/// The phasor and warp kernels over uneven bands of rows and on pools of 1 and 3 threads give
/// the bits of a whole render.
#[test]
fn bands_and_threads_do_not_change_bits() {
    let window = tile_window();
    for case in testdata_cases() {
        if !matches!(case.model, Model::Phasor(_) | Model::Warp(_)) {
            continue;
        }
        let eval = evaluator(&case);
        let whole = eval.render(&window).unwrap();
        let row = window.width * eval.output_channels();
        let mut banded = vec![0.0f32; whole.len()];
        let mut first = 0;
        for rows in [3, 1, 17, 5, 100] {
            let last = (first + rows).min(window.height);
            eval.eval_rows(&window, first, &mut banded[first * row..last * row]);
            first = last;
        }
        assert_eq!(first, window.height);
        if let Some((i, a, b)) = first_difference(&banded, &whole) {
            panic!("{} in bands: value {i} is {a:e}, whole {b:e}", case.name);
        }
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let on_pool = pool.install(|| eval.render(&window)).unwrap();
            if let Some((i, a, b)) = first_difference(&on_pool, &whole) {
                panic!(
                    "{} on {threads} threads: value {i} is {a:e}, default pool {b:e}",
                    case.name
                );
            }
        }
    }
}
