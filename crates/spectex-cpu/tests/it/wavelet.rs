//! Wavelet noise on the CPU against its definition: a slow f64 transcription of the paper's
//! `WNoise`/`WMultibandNoise` over the model's tile, the B-spline weights at integer and
//! half-integer sample positions, exact periodicity with the tile (at the origin and at 10⁷),
//! 3D slices, and bit-identity across tilings and thread counts.

#![allow(clippy::unwrap_used, reason = "tests fail loudly")]

use spectex_cpu::wavelet::WaveletEvaluator;
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::wavelet::{WaveletNoise, WaveletTile};

fn model(dimensions: u32, tile_size: u32, cell_size: f32, bands: Vec<f32>) -> WaveletNoise {
    let m = WaveletNoise {
        seed: 5,
        dimensions,
        tile_size,
        cell_size,
        bands,
        amplitude: 0.7,
        mean: 0.25,
    };
    m.validate().unwrap();
    m
}

/// Tile value at integer sample coordinates (any sign), periodic.
fn at(tile: &WaveletTile, i: i64, j: i64, k: i64) -> f64 {
    let n = tile.side as i64;
    let (i, j, k) = (i.rem_euclid(n), j.rem_euclid(n), k.rem_euclid(n));
    let k = if tile.dimensions == 3 { k } else { 0 };
    f64::from(tile.values[((k * n + j) * n + i) as usize])
}

/// The paper's `WNoise` in f64: `mid = ⌈p − ½⌉`, `t = mid − (p − ½)`, weights `t²/2`,
/// `1 − …`, `(1 − t)²/2` on `mid − 1, mid, mid + 1`.
fn paper_weights(p: f64) -> (i64, [f64; 3]) {
    let mid = (p - 0.5).ceil();
    let t = mid - (p - 0.5);
    let w0 = t * t / 2.0;
    let w2 = (1.0 - t) * (1.0 - t) / 2.0;
    (mid as i64, [w0, 1.0 - w0 - w2, w2])
}

/// `mean + Σ_b a_b WNoise(p_b + o_b)` in f64, with the tile and bands of the model, and the
/// sum of `|a_b · weight · value|` (for the rounding bound).
fn reference(m: &WaveletNoise, tile: &WaveletTile, x: f64, y: f64, z: f64) -> (f64, f64) {
    let mut sum = f64::from(m.mean);
    let mut magnitude = f64::from(m.mean).abs();
    for band in m.bands() {
        let (mx, wx) = paper_weights(x / band.side);
        let (my, wy) = paper_weights(y / band.side);
        let (mz, wz) = if m.dimensions == 3 {
            paper_weights(z / band.side)
        } else {
            (0, [0.0, 1.0, 0.0])
        };
        let o = band.offset.map(i64::from);
        for c in 0..3 {
            for b in 0..3 {
                for a in 0..3 {
                    let v = at(
                        tile,
                        mx + a as i64 - 1 + o[0],
                        my + b as i64 - 1 + o[1],
                        mz + c as i64 - 1 + o[2],
                    );
                    let term = f64::from(band.amplitude) * wx[a] * wy[b] * wz[c] * v;
                    sum += term;
                    magnitude += term.abs();
                }
            }
        }
    }
    (sum, magnitude)
}

#[test]
fn matches_the_papers_wnoise_in_f64() {
    let cases = [
        model(2, 32, 8.0, vec![1.0]),
        model(2, 18, 12.5, vec![1.0, -0.5, 0.25]),
        model(3, 16, 6.0, vec![0.5, 1.0]),
    ];
    for m in &cases {
        let tile = m.tile();
        for &z in &[0.0, 17.3] {
            let eval = WaveletEvaluator::new(m, z);
            for &(x0, y0) in &[(0.0, 0.0), (1.0e7, -1.0e7), (-33.3, 101.7)] {
                for s in 0..40 {
                    let (x, y) = (x0 + 0.731 * f64::from(s), y0 + 0.377 * f64::from(s * s));
                    let (want, magnitude) = reference(m, &tile, x, y, z);
                    let got = f64::from(eval.eval(x, y));
                    // f32 fraction (½ ulp of a value < 1), weights (≈ 4 roundings), products and
                    // the 3 + 3 (+ 3) + bands sums: well under 64 roundings of the magnitude.
                    let bound = 64.0 * f64::from(f32::EPSILON) * magnitude;
                    assert!(
                        (got - want).abs() <= bound,
                        "{m:?} at ({x}, {y}, {z}): {got} vs {want} (bound {bound})"
                    );
                }
            }
        }
    }
}

#[test]
fn integer_and_half_integer_positions_weigh_the_b_spline_knots() {
    let m = model(2, 32, 8.0, vec![1.0]);
    let tile = m.tile();
    let eval = WaveletEvaluator::new(&m, 0.0);
    let band = m.bands()[0];
    let o = band.offset.map(i64::from);
    let a = f64::from(band.amplitude);
    for (i, j) in [(0i64, 0i64), (5, 31), (-7, 12), (1_250_000, -3)] {
        // At the sample itself (p = k): weights ⅛, ¾, ⅛ along each axis.
        let (x, y) = (8.0 * i as f64, 8.0 * j as f64);
        let mut want = 0.0;
        for (dj, wj) in [(-1, 0.125), (0, 0.75), (1, 0.125)] {
            for (di, wi) in [(-1, 0.125), (0, 0.75), (1, 0.125)] {
                want += wi * wj * at(&tile, i + di + o[0], j + dj + o[1], 0);
            }
        }
        let got = f64::from(eval.eval(x, y)) - f64::from(m.mean);
        assert!(
            (got - a * want).abs() < 1e-5,
            "({i}, {j}): {got} vs {}",
            a * want
        );
        // Half-way between samples k and k + 1: weights ½, ½.
        let (x, y) = (x + 4.0, y + 4.0);
        let mut want = 0.0;
        for dj in 0..2 {
            for di in 0..2 {
                want += 0.25 * at(&tile, i + di + o[0], j + dj + o[1], 0);
            }
        }
        let got = f64::from(eval.eval(x, y)) - f64::from(m.mean);
        assert!(
            (got - a * want).abs() < 1e-5,
            "({i}, {j}) + ½: {got} vs {}",
            a * want
        );
    }
}

#[test]
fn periodic_with_the_tile_exactly() {
    // cell 8 = 2³ and bands at 8/2^b: every division is exact, so a shift by n·cell pixels moves
    // every band by a whole number of tiles and the bits repeat.
    for m in [
        model(2, 32, 8.0, vec![1.0, 0.5, 0.25, 0.125]),
        model(3, 16, 8.0, vec![1.0, 0.7]),
    ] {
        let period = f64::from(m.tile_size) * f64::from(m.cell_size);
        let eval = WaveletEvaluator::new(&m, 3.5);
        let shifted_z = WaveletEvaluator::new(&m, 3.5 + period);
        for &(x, y) in &[(0.0, 0.0), (3.125, -77.75), (1.0e7 + 0.5, 1.0e7 - 0.25)] {
            let v = eval.eval(x, y).to_bits();
            assert_eq!(v, eval.eval(x + period, y).to_bits(), "x at ({x}, {y})");
            assert_eq!(
                v,
                eval.eval(x, y - 3.0 * period).to_bits(),
                "y at ({x}, {y})"
            );
            assert_eq!(v, shifted_z.eval(x, y).to_bits(), "z at ({x}, {y})");
        }
    }
}

#[test]
fn renders_equal_eval_and_are_identical_for_any_tiling_and_thread_count() {
    for m in [
        model(2, 64, 5.5, vec![1.0, 0.5, 0.25]),
        model(3, 32, 7.0, vec![1.0, 1.0]),
    ] {
        let eval = Evaluator::new_at_z(&Model::Wavelet(m.clone()), 11.0).unwrap();
        let direct = WaveletEvaluator::new(&m, 11.0);
        // Wider than one column chunk (512), at 10⁷ and a fractional scale.
        let window = Window::new(600, 40).at([1.0e7 - 0.3, -2.5e6], 0.37);
        let full = eval.render(&window).unwrap();
        for (j, i) in [(0, 0), (17, 513), (39, 599)] {
            let v = direct.eval(window.x(i), window.y(j));
            assert_eq!(full[j * 600 + i].to_bits(), v.to_bits(), "({i}, {j})");
        }
        let tile = eval.render(&window.tile(250, 3, 333, 21)).unwrap();
        for j in 0..21 {
            for i in 0..333 {
                assert_eq!(
                    tile[j * 333 + i].to_bits(),
                    full[(j + 3) * 600 + i + 250].to_bits()
                );
            }
        }
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| eval.render(&window).unwrap());
        let four = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap()
            .install(|| eval.render(&window).unwrap());
        assert!(
            one.iter()
                .zip(&full)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        assert!(
            four.iter()
                .zip(&full)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }
}

#[test]
fn sample_mean_and_variance_follow_mean_and_amplitude() {
    // One full period of every band (n·cell = 256 px), sampled 1 px apart: the mean of the
    // tile's noise is 0 up to the analysis filter's DC gain, and its mean square is 1 (the
    // exact normalisation) up to the Riemann sum of the B-spline products over 8 samples per
    // cell, which is within 0.5% of their integral.
    let m = model(2, 32, 8.0, vec![1.0, 1.0, 1.0]);
    let eval = Evaluator::new(&Model::Wavelet(m.clone())).unwrap();
    let v = eval.render(&Window::new(256, 256)).unwrap();
    let count = v.len() as f64;
    let mean = v.iter().map(|&x| f64::from(x)).sum::<f64>() / count;
    let var = v
        .iter()
        .map(|&x| (f64::from(x) - mean).powi(2))
        .sum::<f64>()
        / count;
    assert!((mean - 0.25).abs() < 0.02, "mean {mean}");
    let sigma2 = 0.7f64 * 0.7;
    // Three bands of unit variance that are nearly uncorrelated (disjoint octaves).
    assert!(
        (var / sigma2 - 1.0).abs() < 0.1,
        "variance {var} vs {sigma2}"
    );
}
