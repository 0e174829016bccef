//! Stochastic subdivision against independent references: a naive whole-grid subdivision (the
//! midpoint rule or the 4-point stencil level by level over a whole block of the lattice, in
//! f64, with its own copy of the hashed displacements) equals the pointwise evaluation at and
//! between lattice points, near the origin and far away; the variance of level-`ℓ` increments
//! against `a²·2^(−2Hℓ)` within a sampling tolerance; the structure function's slope against
//! `2H`; the row kernel's block cache against its uncached reference path.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_cpu::subdivision::SubdivisionEvaluator;
use spectex_cpu::{Evaluator, RowKernel, Window};
use spectex_model::Model;
use spectex_model::random::{Prng, cell_hash};
use spectex_model::subdivision::{Stencil, StochasticSubdivision};

fn model(stencil: Stencil, levels: u32, hurst: f32, cell_size: f32) -> StochasticSubdivision {
    let m = StochasticSubdivision {
        seed: 11,
        cell_size,
        levels,
        hurst,
        amplitude: 1.0,
        mean: 0.25,
        stencil,
    };
    m.validate().unwrap();
    m
}

fn render(m: &StochasticSubdivision, window: &Window) -> Vec<f32> {
    Evaluator::new(&Model::Subdivision(m.clone()))
        .unwrap()
        .render(window)
        .unwrap()
}

/// The displacement of global level-`l` lattice point `g` (`g = c·2^l + k`), written from the
/// module doc's formula with Euclidean division (not the model's `normalise`).
fn displacement(m: &StochasticSubdivision, l: u32, g: [i64; 2]) -> f64 {
    const SUBD: u32 = 0x5355_4244;
    let side = 1i64 << l;
    let c = g.map(|v| v.div_euclid(side) as i32);
    let k = g.map(|v| v.rem_euclid(side) as i32);
    let bits = cell_hash(k[0], k[1], SUBD + l, cell_hash(c[0], c[1], SUBD, m.seed));
    let sum: u32 = bits.to_le_bytes().iter().map(|&b| u32::from(b)).sum();
    let sigma = f64::from(m.amplitude) * 2f64.powf(-f64::from(m.hurst) * f64::from(l));
    sigma * (f64::from(sum) - 510.0) / 21_845f64.sqrt()
}

/// The 1D rule: `(parent index, weight)` pairs giving level index `g` from its parents.
fn rule(stencil: Stencil, g: i64) -> Vec<(i64, f64)> {
    if g % 2 == 0 {
        return vec![(g / 2, 1.0)];
    }
    let (lo, hi) = ((g - 1).div_euclid(2), (g + 1).div_euclid(2));
    match stencil {
        Stencil::Midpoint => vec![(lo, 0.5), (hi, 0.5)],
        Stencil::Cubic => vec![
            (lo - 1, -1.0 / 16.0),
            (lo, 9.0 / 16.0),
            (hi, 9.0 / 16.0),
            (hi + 1, -1.0 / 16.0),
        ],
    }
}

/// A square block of one level: values at global indices `lo..lo + n` per axis.
struct Grid {
    lo: [i64; 2],
    n: usize,
    v: Vec<f64>,
}

impl Grid {
    fn at(&self, g: [i64; 2]) -> f64 {
        let (x, y) = ((g[0] - self.lo[0]) as usize, (g[1] - self.lo[1]) as usize);
        assert!(
            x < self.n && y < self.n,
            "{g:?} outside the grid from {:?}",
            self.lo
        );
        self.v[y * self.n + x]
    }
}

/// The whole-grid subdivision: level 0 over `n0 × n0` coarse points from `lo0`, then every
/// level over the whole block its parent covers (less a margin of 2 for the stencil), each
/// point the rule's weighted sum of its parents plus its displacement when new.
fn whole_grid(m: &StochasticSubdivision, lo0: [i64; 2], n0: usize) -> Grid {
    let mut grid = Grid {
        lo: lo0,
        n: n0,
        v: (0..n0 * n0)
            .map(|i| displacement(m, 0, [lo0[0] + (i % n0) as i64, lo0[1] + (i / n0) as i64]))
            .collect(),
    };
    for l in 1..=m.levels {
        let lo = grid.lo.map(|v| 2 * v + 4);
        let n = 2 * grid.n - 8;
        let mut v = vec![0.0; n * n];
        for y in 0..n {
            for x in 0..n {
                let g = [lo[0] + x as i64, lo[1] + y as i64];
                let mut s = 0.0;
                for (py, wy) in rule(m.stencil, g[1]) {
                    for (px, wx) in rule(m.stencil, g[0]) {
                        s += wx * wy * grid.at([px, py]);
                    }
                }
                if g[0] % 2 != 0 || g[1] % 2 != 0 {
                    s += displacement(m, l, g);
                }
                v[y * n + x] = s;
            }
        }
        grid = Grid { lo, n, v };
    }
    grid
}

/// The final interpolation at `g + u` (finest units) from the grid: bilinear or Catmull–Rom.
fn interpolate(m: &StochasticSubdivision, grid: &Grid, g: [i64; 2], u: [f64; 2]) -> f64 {
    let weights = |t: f64| -> Vec<(i64, f64)> {
        match m.stencil {
            Stencil::Midpoint => vec![(0, 1.0 - t), (1, t)],
            Stencil::Cubic => vec![
                (-1, (-t * t * t + 2.0 * t * t - t) / 2.0),
                (0, (3.0 * t * t * t - 5.0 * t * t + 2.0) / 2.0),
                (1, (-3.0 * t * t * t + 4.0 * t * t + t) / 2.0),
                (2, (t * t * t - t * t) / 2.0),
            ],
        }
    };
    let mut s = 0.0;
    for (dy, wy) in weights(u[1]) {
        for (dx, wx) in weights(u[0]) {
            s += wx * wy * grid.at([g[0] + dx, g[1] + dy]);
        }
    }
    s
}

/// Compares a render of `width × width` pixels at finest-lattice spacing `step` (finest units,
/// a power of two or a fraction of one) from global finest index `start` with the whole grid.
fn compare_with_whole_grid(m: &StochasticSubdivision, start: [i64; 2], sub: f64) {
    let fine = f64::from(m.cell_size) / f64::from(1u32 << m.levels);
    let width = 24usize;
    // Coarse points around the window, with margins for every level's stencil.
    let coarse = |g: i64| g.div_euclid(1 << m.levels);
    let lo0 = [coarse(start[0]) - 6, coarse(start[1]) - 6];
    let span = (width as f64 * sub) as i64 / (1 << m.levels) + 14;
    let grid = whole_grid(m, lo0, span as usize);
    let window =
        Window::new(width, width).at([start[0] as f64 * fine, start[1] as f64 * fine], fine * sub);
    let out = render(m, &window);
    for j in 0..width {
        for i in 0..width {
            let pos = [
                start[0] as f64 + i as f64 * sub,
                start[1] as f64 + j as f64 * sub,
            ];
            let g = pos.map(|p| p.floor() as i64);
            let u = [pos[0] - g[0] as f64, pos[1] - g[1] as f64];
            let expected = f64::from(m.mean) + interpolate(m, &grid, g, u);
            let got = f64::from(out[j * width + i]);
            // The render rounds its f64 value to f32 once (half an ulp); the sums differ from
            // the whole grid's only in f64 rounding order (1e-15 of values of order 1, so
            // 1e-12 absolute is far above it).
            let ulp = expected.abs() * 2f64.powi(-24) + 1e-12;
            assert!(
                (got - expected).abs() <= ulp,
                "{:?} L={} at finest {pos:?}: render {got}, whole grid {expected}",
                m.stencil,
                m.levels
            );
        }
    }
}

#[test]
fn lattice_points_equal_a_whole_grid_subdivision() {
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        for (levels, hurst) in [(0, 0.5), (1, 0.2), (3, 0.5), (5, 0.9)] {
            let m = model(stencil, levels, hurst, 16.0);
            let far = 1_000_003i64 << levels;
            for start in [[0, 0], [-37, 5], [far, -far + 3]] {
                compare_with_whole_grid(&m, start, 1.0);
            }
        }
    }
}

#[test]
fn between_lattice_points_the_texture_interpolates_the_finest_level() {
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        let m = model(stencil, 4, 0.6, 32.0);
        for start in [[3, -9], [(77_777i64 << 4) + 5, 12]] {
            compare_with_whole_grid(&m, start, 0.375);
        }
    }
}

/// Sample variance of level-`l` increments `V_l(q) − I(V_{l−1})(q)` at new points `q`: the
/// texture with `l` levels minus the texture with `l − 1` levels at the level-`l` lattice
/// points (an interpolating stencil's value there is `I(V_{l−1})(q)`), over `batches` windows.
fn increment_variance(stencil: Stencil, hurst: f32, l: u32) -> (f64, usize) {
    let mut fine = model(stencil, l, hurst, 256.0);
    fine.mean = 0.0;
    let mut coarse = fine.clone();
    coarse.levels = l - 1;
    let spacing = 256.0 / f64::from(1u32 << l);
    let (mut sum2, mut count) = (0.0, 0usize);
    for b in 0..12 {
        // Windows starting on coarse points (multiples of 256 pixels), one pixel per level-l
        // point: pixel (i, j) is level-l point off + (i, j).
        let start = [f64::from(b) * 256.0 * 397.0, -f64::from(b) * 256.0 * 131.0];
        let window = Window::new(64, 64).at(start, spacing);
        let (a, c) = (render(&fine, &window), render(&coarse, &window));
        let off = start.map(|s| (s / spacing) as i64);
        for j in 0..64usize {
            for i in 0..64usize {
                if (off[0] + i as i64) % 2 == 0 && (off[1] + j as i64) % 2 == 0 {
                    continue;
                }
                let d = f64::from(a[j * 64 + i]) - f64::from(c[j * 64 + i]);
                sum2 += d * d;
                count += 1;
            }
        }
    }
    (sum2 / count as f64, count)
}

#[test]
fn level_increments_have_variance_two_to_the_minus_two_h_l() {
    // The displacements are independent with mean 0 and variance σ² exactly (four uniform
    // bytes), so their mean square over N points has relative standard deviation
    // √((κ − 1)/N), κ = 3 − 6/(5·4) = 2.7 the kurtosis of a sum of four uniforms; 5 standard
    // deviations of it bound the test's false-failure rate below 1e-6 per case.
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        for hurst in [0.25f32, 0.8] {
            for l in [1u32, 3, 6] {
                let (v, n) = increment_variance(stencil, hurst, l);
                let expected = 2f64.powf(-2.0 * f64::from(hurst) * f64::from(l));
                let tol = 5.0 * (1.7 / n as f64).sqrt();
                assert!(
                    (v / expected - 1.0).abs() <= tol,
                    "{stencil:?} H={hurst} level {l}: variance {v:.5}, 2^(−2Hℓ) = {expected:.5} \
                     (N = {n}, relative tolerance {tol:.4})"
                );
            }
        }
    }
}

/// `E[(f(p + h·e_x) − f(p))²]` over `batches × per` random points `p`, per batch.
fn structure_function(m: &StochasticSubdivision, h: f64, batches: usize, per: usize) -> Vec<f64> {
    let eval = Evaluator::new(&Model::Subdivision(m.clone())).unwrap();
    let mut rng = Prng::new(0x5eed);
    let extent = 64.0 * f64::from(m.cell_size);
    (0..batches)
        .map(|_| {
            let mut points = Vec::with_capacity(2 * per);
            for _ in 0..per {
                let p = [rng.next_f64() * extent, rng.next_f64() * extent];
                points.extend([p, [p[0] + h, p[1]]]);
            }
            let mut v = vec![0.0f32; 2 * per];
            eval.eval_points(&points, &mut v);
            let s: f64 = v
                .chunks_exact(2)
                .map(|d| (f64::from(d[1]) - f64::from(d[0])).powi(2))
                .sum();
            s / per as f64
        })
        .collect()
}

#[test]
fn structure_function_slope_is_two_h() {
    // Midpoint displacement with σ_ℓ ∝ 2^(−Hℓ): at a lag h = C·2^(−j), levels coarser than j
    // contribute ∝ h²·Σ_{ℓ<j} 2^{2(1−H)ℓ} and finer ones ∝ Σ_{ℓ>j} 2^(−2Hℓ), both ∝ h^{2H}
    // up to the truncation of the sums at ℓ = 0 and ℓ = L: relative corrections
    // 2^(−2(1−H)j) and 2^(−2H(L−j)). The slope log₂(D(2h)/D(h)) is 2H within the log of
    // those corrections at the two lags, plus 4 standard errors of the estimate (from 16
    // independent batches of points).
    let levels = 16;
    for (stencil, hurst) in [
        (Stencil::Midpoint, 0.3f32),
        (Stencil::Midpoint, 0.5),
        (Stencil::Cubic, 0.5),
        (Stencil::Midpoint, 0.7),
    ] {
        let m = model(stencil, levels, hurst, 4096.0);
        let h = f64::from(hurst);
        for j in [7i32, 8] {
            let lag = 4096.0 * 2f64.powi(-j);
            let batches = 16;
            let coarse = structure_function(&m, 2.0 * lag, batches, 400);
            let fine = structure_function(&m, lag, batches, 400);
            let slopes: Vec<f64> = coarse
                .iter()
                .zip(&fine)
                .map(|(a, b)| (a / b).log2())
                .collect();
            let mean = slopes.iter().sum::<f64>() / batches as f64;
            let var = slopes.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (batches - 1) as f64;
            // The ratio of the pooled means is the estimate; its standard error is about that
            // of the batch slopes' mean.
            let pooled = (coarse.iter().sum::<f64>() / fine.iter().sum::<f64>()).log2();
            let stat = 4.0 * (var / batches as f64).sqrt();
            let correction = |jj: f64| {
                2f64.powf(-2.0 * (1.0 - h) * jj) + 2f64.powf(-2.0 * h * (f64::from(levels) - jj))
            };
            let jj = f64::from(j);
            let bias = ((1.0 + correction(jj - 1.0)) * (1.0 + correction(jj))).log2();
            assert!(
                (pooled - 2.0 * h).abs() <= stat + bias,
                "{stencil:?} H={hurst} lags {lag}, {}: slope {pooled:.4}, 2H = {} (statistical \
                 {stat:.4} + truncation {bias:.4})",
                2.0 * lag,
                2.0 * h
            );
        }
    }
}

#[test]
fn the_block_cache_gives_the_uncached_bits() {
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        for (levels, cell) in [(0, 8.0), (4, 37.5), (9, 300.0), (16, 4096.0)] {
            let m = model(stencil, levels, 0.4, cell);
            let eval = SubdivisionEvaluator::new(&m);
            for window in [
                Window::new(70, 9).at([-13.3, 7.9], 0.61),
                Window::new(33, 5).at([1.0e7 + 0.3, -2.5e6], 3.7),
                Window::new(20, 4).at([5.0, 5.0], 0.001),
            ] {
                let mut fast = vec![0.0f32; window.width * window.height];
                let mut reference = fast.clone();
                eval.eval_rows(&window, 0, &mut fast);
                eval.eval_rows_reference(&window, 0, &mut reference);
                for (i, (a, b)) in fast.iter().zip(&reference).enumerate() {
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "{stencil:?} L={levels}: pixel {i}"
                    );
                }
            }
        }
    }
}
