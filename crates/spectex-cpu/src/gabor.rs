//! Gabor noise by sparse convolution (Lagae, Lefebvre, Drettakis & Dutré 2009), evaluated at any
//! continuous position on the CPU: a Poisson process of impulses on a grid of cells, each impulse
//! a weighted, truncated Gabor kernel.
//!
//! # The model
//!
//! `n(x) = mean + Σ_k w_k · g_k(x − x_k)` with the kernel (Eq. (1) of Lagae et al.)
//! `g(d) = K · exp(−π a² |d|²) · cos(2π F₀ ω·d)`, truncated to 0 where `|d| ≥ r`,
//! `r = √(−ln 0.05 / π) / a` ([`GaborNoise::kernel_radius`]). The plane is cut into square cells
//! of side `r`, so every impulse within `r` of a point lies in the 3×3 cells around the point's
//! cell. Cell `(i, j)` holds a Poisson number of impulses with mean
//! `λ = impulses_per_kernel / π` ([`GaborNoise::impulses_per_cell`]).
//!
//! # Randomness contract (Gabor: layer 0 per grid cell)
//!
//! The impulses of cell `(i, j)` (signed `i32` cell coordinates, cell `(i, j)` covering
//! `[i·r, (i+1)·r) × [j·r, (j+1)·r)` pixels) come from
//! `Prng::new(cell_hash(i, j, GABOR_LAYER = 0, seed))`, drawn in this fixed order with
//! `u = next_f32()` (uniform in `[0, 1)`, built from integer bits):
//!
//! 1. **Count** by Knuth's multiplication method, in f32: multiply uniforms `p ← p·u` (starting
//!    at `p = 1`) until `p < exp(−λ)`; the count is the number of factors minus one. For
//!    `λ ≥ 64` the threshold `exp(−λ)` is not a normal f32, so `λ = 64·m + ρ` is split
//!    (`m = ⌊λ/64⌋`): after each multiplication, while `m > 0` and `p < exp(−64)`, set
//!    `p ← p·exp(64)` and `m ← m − 1`; stop when `m = 0` and `p < exp(−ρ)`. (For `λ < 64`,
//!    i.e. `impulses_per_kernel < 201`, this is plain Knuth.) The constants are `f64`
//!    exponentials rounded to f32. The count is capped at `N_max = ⌊4λ + 32⌋`: at most `N_max`
//!    uniforms are drawn for the count, and when the cap is reached the count is `N_max` (the
//!    probability is below 1e-33 for every valid λ).
//! 2. **Per impulse**, in order: `x` offset `u₁`, `y` offset `u₂` (cell units, so the impulse is
//!    at `((i + u₁)·r, (j + u₂)·r)` pixels), weight `w = 2u₃ − 1` (exact in f32), and only for
//!    [`Orientation::Isotropic`] the direction `u₄`: the angle in turns is `τ = τ_min + u₄·span`
//!    (f32 operations), where `τ_min = frac(min / 2π)` and `span = (max − min) / 2π` are computed
//!    in f64 and rounded to f32; the frequency vector is `F₀r·(cos_turns(τ), cos_turns(τ − ¼))`.
//!    (The anisotropic vector `F₀r·(cos angle, sin angle)` is computed in f64 and rounded.)
//!    For [`Orientation::Spectrum`] (Gabor noise by example) the fourth draw `u₄` picks the
//!    component `k` = the number of entries `≤ u₄` of the table
//!    [`spectex_model::cumulative_weights`] (at most `n − 1`), and the vector is
//!    `r·f_k`, each coordinate computed in f64 and rounded to f32.
//!
//! # Precision (invariant 2 of docs/ARCHITECTURE.md)
//!
//! A position `x` in pixels (f64) becomes `p = x / r`, the cell `⌊p⌋` (i32) and the local offset
//! `p − ⌊p⌋` in f64 (exact), rounded to f32. All per-impulse arithmetic is then in f32 in cell
//! units, where offsets between the point and an impulse are below 2: the result is as precise at
//! `(10⁷, 10⁷)` as at the origin. The usable range is `|x|, |y| < (2³¹ − 2)·r` pixels (for
//! `a = 0.05`, `r ≈ 19.5` px, about 4·10¹⁰ px); a coordinate outside it, or NaN, evaluates to
//! `mean`. The phase is `F₀r·ω·d` in turns, reduced by [`cos_turns`]; its f32 rounding error grows
//! with `F₀r` (the number of kernel periods per cell), ≈ `2⁻²³·F₀r` turns.
//!
//! # Evaluation order (what makes [`GaborEvaluator::eval_row`] bit-identical to `eval`)
//!
//! For the point's cell `(i, j)` and local offset `(uₓ, u_y)`, the three cell columns
//! `s = −1, 0, 1` are summed separately: column `i + s` lists the impulses of cells
//! `(i+s, j−1)`, `(i+s, j)`, `(i+s, j+1)` in draw order, keeping only those with
//! `d_y² < 1` where `d_y = (u_y − t) − o_y` for the cell's row offset `t ∈ {−1, 0, 1}`; the
//! `k`-th kept impulse is added to accumulator `k mod 8`, and the column sum is
//! `((a₀+a₁)+(a₂+a₃))+((a₄+a₅)+(a₆+a₇))`. The value is `mean + ((c₋₁ + c₀) + c₁)`. One impulse
//! contributes `[d² < 1] · ((K·w)·exp_poly(−ln 20 · d²))·cos_turns(f_x·d_x + f_y·d_y)` with
//! `d_x = (uₓ − s) − o_x`, `d² = d_x·d_x + d_y·d_y` and `(f_x, f_y) = F₀r·ω` (`π a² r² = ln 20`
//! exactly). A masked term is `+0.0`, and an accumulator that starts at `+0.0` never becomes
//! `−0.0`, so padding lanes with masked terms changes no bit.
//!
//! `eval_row` is the fast path (it draws each cell once per row and runs the kernel loop eight
//! lanes wide); `eval` redraws the nine cells for every point and is several times slower.
//!
//! ```
//! use spectex_cpu::gabor::GaborEvaluator;
//! use spectex_model::{GaborNoise, Orientation};
//!
//! let model = GaborNoise {
//!     seed: 7,
//!     mean: 0.5,
//!     amplitude: 1.0,
//!     bandwidth: 0.05,
//!     frequency: 0.0625,
//!     orientation: Orientation::Anisotropic { angle: 0.3 },
//!     impulses_per_kernel: 16.0,
//! };
//! model.validate()?;
//! let gabor = GaborEvaluator::new(&model);
//! let mut row = [0.0f32; 64];
//! gabor.eval_row(10.5, -32.0, 1.0, &mut row);
//! assert_eq!(row[40].to_bits(), gabor.eval(8.0, 10.5).to_bits());
//! # Ok::<(), spectex_model::ModelError>(())
//! ```

use spectex_model::grid::locate_cell as locate;
use spectex_model::random::{Prng, cell_hash_in_row, layer_key, row_key};
use spectex_model::{GaborNoise, NEG_LN_20, Orientation, Period, Window, pick_component};

use crate::math::{cos_turns, exp_poly};

/// The randomness-contract layer of Gabor impulses: `cell_hash(i, j, GABOR_LAYER, seed)` seeds
/// the impulses of grid cell `(i, j)`.
pub const GABOR_LAYER: u32 = 0;

/// Chunk of λ by which the Poisson count is renormalised: `exp(−64) ≈ 1.6e-28`, times the
/// smallest non-zero uniform `2⁻²⁴`, is still a normal f32.
pub const POISSON_CHUNK: f64 = 64.0;

/// Impulses are processed in blocks of this many lanes (one accumulator per lane).
const LANES: usize = 8;

/// Gabor noise ready to evaluate: the model's constants in the units the kernel loop uses.
#[derive(Debug, Clone)]
pub struct GaborEvaluator {
    /// `mean` of the model.
    mean: f32,
    /// `K`.
    amplitude: f32,
    /// Kernel radius and cell side `r`, pixels.
    radius: f64,
    /// `λ`, mean impulses per cell.
    lambda: f64,
    /// `layer_key(GABOR_LAYER, seed)`.
    layer_key: u32,
    /// Knuth threshold `exp(−ρ)` once the chunks are used up.
    poisson_threshold: f32,
    /// Number of `exp(64)` renormalisations, `⌊λ / 64⌋`.
    poisson_chunks: u32,
    /// `exp(64)` rounded to f32.
    chunk_up: f32,
    /// `exp(−64)` rounded to f32.
    chunk_down: f32,
    /// `N_max = ⌊4λ + 32⌋`.
    max_impulses: u32,
    /// `F₀·r`, cycles per cell.
    frequency_cells: f32,
    /// How each impulse gets its frequency vector.
    direction: Direction,
    /// Cells per period along x and y of a periodic noise: cell `(i, j)` draws the impulses of
    /// `(i mod n_x, j mod n_y)`.
    cells: Option<[i64; 2]>,
}

/// The frequency vector of the impulses, in cycles per cell unit.
#[derive(Debug, Clone)]
enum Direction {
    /// One vector for every impulse.
    Fixed { fx: f32, fy: f32 },
    /// Angle in turns `τ_min + u·span`, drawn per impulse.
    Random { t_min: f32, span: f32 },
    /// Component drawn per impulse from a cumulative table (module doc, step 2).
    Table {
        /// `r·f_k`, cycles per cell unit.
        vectors: Vec<[f32; 2]>,
        /// [`spectex_model::cumulative_weights`].
        cumulative: Vec<f32>,
    },
}

/// One impulse, reduced to what the kernel loop needs for a given row offset: the row part of
/// the offset is folded in once (`dy2`, `py`).
#[derive(Debug, Clone, Copy)]
struct RowImpulse {
    /// `o_x`, the impulse's x offset in its cell.
    ox: f32,
    /// `f_x`, turns per cell unit along x.
    fx: f32,
    /// `d_y²`.
    dy2: f32,
    /// `f_y·d_y`, turns.
    py: f32,
    /// `K·w`.
    kw: f32,
}

/// Eight impulses, structure-of-arrays, so the kernel loop runs lane-parallel.
#[derive(Debug, Clone, Copy)]
struct Block {
    ox: [f32; LANES],
    fx: [f32; LANES],
    dy2: [f32; LANES],
    py: [f32; LANES],
    kw: [f32; LANES],
}

impl Block {
    /// A block of masked impulses (`d_y² = 4` makes `d² ≥ 1`, so each contributes `+0.0`).
    const EMPTY: Self = Self {
        ox: [0.0; LANES],
        fx: [0.0; LANES],
        dy2: [4.0; LANES],
        py: [0.0; LANES],
        kw: [0.0; LANES],
    };
}

/// The kept impulses of one cell column for one row, in contract order.
#[derive(Debug, Clone, Default)]
struct Column {
    /// Which cell column this is; `None` before the first fill.
    cell: Option<i32>,
    blocks: Vec<Block>,
}

impl Column {
    fn clear(&mut self, cell: i32) {
        self.cell = Some(cell);
        self.blocks.clear();
    }

    fn push(&mut self, k: usize, imp: RowImpulse) {
        let lane = k % LANES;
        if lane == 0 {
            self.blocks.push(Block::EMPTY);
        }
        if let Some(b) = self.blocks.last_mut() {
            b.ox[lane] = imp.ox;
            b.fx[lane] = imp.fx;
            b.dy2[lane] = imp.dy2;
            b.py[lane] = imp.py;
            b.kw[lane] = imp.kw;
        }
    }

    /// The column sum for `uxs = uₓ − s`: lane `k mod 8` accumulates the `k`-th impulse.
    #[inline]
    fn sum(&self, uxs: f32) -> f32 {
        let mut acc = [0.0f32; LANES];
        for b in &self.blocks {
            for l in 0..LANES {
                acc[l] += kernel_term(uxs, b.ox[l], b.fx[l], b.dy2[l], b.py[l], b.kw[l]);
            }
        }
        reduce(&acc)
    }
}

/// One impulse's contribution at `d_x = uxs − ox` (see the module doc): 0 beyond the radius.
#[inline(always)]
fn kernel_term(uxs: f32, ox: f32, fx: f32, dy2: f32, py: f32, kw: f32) -> f32 {
    let dx = uxs - ox;
    let d2 = dx * dx + dy2;
    let gauss = exp_poly(NEG_LN_20 * d2);
    let wave = cos_turns(fx * dx + py);
    let v = kw * gauss * wave;
    if d2 < 1.0 { v } else { 0.0 }
}

/// The contract's fixed reduction order of the eight lane accumulators.
#[inline(always)]
fn reduce(acc: &[f32; LANES]) -> f32 {
    ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]))
}

/// The row part of a point: its cell row, offset and the three row keys `j − 1, j, j + 1`.
#[derive(Debug, Clone, Copy)]
struct RowContext {
    uy: f32,
    keys: [u32; 3],
}

impl GaborEvaluator {
    /// Precomputes the model's constants. The model is assumed validated
    /// ([`GaborNoise::validate`]); an invalid one gives meaningless values, never a panic or an
    /// endless loop.
    #[must_use]
    pub fn new(model: &GaborNoise) -> Self {
        Self::prepare(model, model.kernel_radius(), None)
    }

    /// Prepares a validated `model` that accepts `period` made periodic: square cells of the
    /// fitted radius [`GaborNoise::periodic_radius`] (the kernel scaled with them: in cell
    /// units nothing changes; `F₀` stays in cycles per pixel), hashed modulo the period.
    #[must_use]
    pub fn new_periodic(model: &GaborNoise, period: Period) -> Self {
        let radius = model
            .periodic_radius(period)
            .unwrap_or_else(|| model.kernel_radius());
        Self::prepare(model, radius, Some(period.cells(radius)))
    }

    fn prepare(model: &GaborNoise, radius: f64, cells: Option<[i64; 2]>) -> Self {
        let lambda = model.impulses_per_cell();
        let chunks = (lambda / POISSON_CHUNK).floor();
        let rest = lambda - chunks * POISSON_CHUNK;
        let frequency_cells = f64::from(model.frequency) * radius;
        let direction = match &model.orientation {
            &Orientation::Anisotropic { angle } => {
                let (sin, cos) = angle_sin_cos(f64::from(angle));
                Direction::Fixed {
                    fx: (frequency_cells * cos) as f32,
                    fy: (frequency_cells * sin) as f32,
                }
            }
            &Orientation::Isotropic { min, max } => {
                let turn = std::f64::consts::TAU;
                Direction::Random {
                    t_min: (f64::from(min) / turn).rem_euclid(1.0) as f32,
                    span: ((f64::from(max) - f64::from(min)) / turn) as f32,
                }
            }
            Orientation::Spectrum {
                frequencies,
                weights,
            } => Direction::Table {
                vectors: frequencies
                    .iter()
                    .map(|f| f.map(|c| (f64::from(c) * radius) as f32))
                    .collect(),
                cumulative: spectex_model::cumulative_weights(weights),
            },
        };
        Self {
            mean: model.mean,
            amplitude: model.amplitude,
            radius,
            lambda,
            layer_key: layer_key(GABOR_LAYER, model.seed),
            poisson_threshold: libm_exp(-rest) as f32,
            poisson_chunks: chunks.min(64.0) as u32,
            chunk_up: libm_exp(POISSON_CHUNK) as f32,
            chunk_down: libm_exp(-POISSON_CHUNK) as f32,
            // Valid models have N_max ≤ 1305; the clamp only bounds the work of invalid ones.
            max_impulses: (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32,
            frequency_cells: frequency_cells as f32,
            direction,
            cells,
        }
    }

    /// The kernel radius `r` (and grid cell side), pixels.
    #[must_use]
    pub fn kernel_radius(&self) -> f64 {
        self.radius
    }

    /// Expected kernel evaluations per pixel, `9λ` (every impulse of the 3×3 cells is visited;
    /// about `π/9` of them are inside the radius), for reports.
    #[must_use]
    pub fn cosines_per_pixel(&self) -> f64 {
        9.0 * self.lambda
    }

    /// The noise at `(x, y)` pixels. Pure: the same inputs give the same bits. Outside the
    /// usable range (module doc, "Precision") or at NaN it is `mean`.
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let (Some((ci, ux)), Some(row)) = (locate(x, self.radius), self.row_context(y)) else {
            return self.mean;
        };
        let mut cols = [0.0f32; 3];
        for (s, col) in (-1..=1).zip(cols.iter_mut()) {
            let uxs = ux - s as f32;
            let mut acc = [0.0f32; LANES];
            let mut k = 0;
            self.column_impulses(ci.wrapping_add(s), &row, |imp| {
                acc[k % LANES] += kernel_term(uxs, imp.ox, imp.fx, imp.dy2, imp.py, imp.kw);
                k += 1;
            });
            *col = reduce(&acc);
        }
        self.mean + ((cols[0] + cols[1]) + cols[2])
    }

    /// `out[i] = eval(x0 + i·dx, y)`, bit for bit, with the impulses of each cell column the row
    /// crosses drawn once (they depend only on the cell). Allocates a few buffers per call,
    /// nothing per pixel.
    pub fn eval_row(&self, y: f64, x0: f64, dx: f64, out: &mut [f32]) {
        self.eval_row_at(y, |i| x0 + i as f64 * dx, out);
    }

    /// Evaluates `out[i] = eval(x(i), y)` along a row whose positions `x(i)` are monotone in `i`
    /// (bit-identical to [`Self::eval`]; a window passes its own position formula so that
    /// every tiling evaluates the same positions).
    pub fn eval_row_at(&self, y: f64, x: impl Fn(usize) -> f64, out: &mut [f32]) {
        let Some(row) = self.row_context(y) else {
            out.fill(self.mean);
            return;
        };
        // Slot `c.rem_euclid(3)` holds column `c`: the three columns a pixel needs never share a
        // slot, and along a monotone row each column is filled once.
        let mut slots: [Column; 3] = Default::default();
        for (i, v) in out.iter_mut().enumerate() {
            let Some((ci, ux)) = locate(x(i), self.radius) else {
                *v = self.mean;
                continue;
            };
            let mut cols = [0.0f32; 3];
            for (s, col) in (-1..=1).zip(cols.iter_mut()) {
                let cell = ci.wrapping_add(s);
                let slot = &mut slots[cell.rem_euclid(3) as usize];
                if slot.cell != Some(cell) {
                    slot.clear(cell);
                    let mut k = 0;
                    self.column_impulses(cell, &row, |imp| {
                        slot.push(k, imp);
                        k += 1;
                    });
                }
                *col = slot.sum(ux - s as f32);
            }
            *v = self.mean + ((cols[0] + cols[1]) + cols[2]);
        }
    }

    fn row_context(&self, y: f64) -> Option<RowContext> {
        let (cj, uy) = locate(y, self.radius)?;
        let key = |t: i32| row_key(self.wrap(cj.wrapping_add(t), 1), self.layer_key);
        Some(RowContext {
            uy,
            keys: [key(-1), key(0), key(1)],
        })
    }

    /// Calls `visit` with each kept impulse of cells `(cell, j−1)`, `(cell, j)`, `(cell, j+1)`
    /// in contract order (those with `d_y² ≥ 1` are skipped: they cannot reach this row).
    #[inline(always)]
    fn column_impulses(&self, cell: i32, row: &RowContext, mut visit: impl FnMut(RowImpulse)) {
        for (t, &key) in (-1..=1).zip(row.keys.iter()) {
            let uyt = row.uy - t as f32;
            let mut prng = Prng::new(cell_hash_in_row(self.wrap(cell, 0), key));
            let count = self.poisson_count(&mut prng);
            for _ in 0..count {
                let ox = prng.next_f32();
                let oy = prng.next_f32();
                let w = 2.0 * prng.next_f32() - 1.0;
                let (fx, fy) = match &self.direction {
                    &Direction::Fixed { fx, fy } => (fx, fy),
                    &Direction::Random { t_min, span } => {
                        let turns = t_min + prng.next_f32() * span;
                        let f = self.frequency_cells;
                        (f * cos_turns(turns), f * cos_turns(turns - 0.25))
                    }
                    Direction::Table {
                        vectors,
                        cumulative,
                    } => {
                        let k = pick_component(cumulative, prng.next_f32());
                        vectors.get(k).map_or((0.0, 0.0), |v| (v[0], v[1]))
                    }
                };
                let dy = uyt - oy;
                let dy2 = dy * dy;
                if dy2 < 1.0 {
                    visit(RowImpulse {
                        ox,
                        fx,
                        dy2,
                        py: fy * dy,
                        kw: self.amplitude * w,
                    });
                }
            }
        }
    }

    /// Cell coordinate `c` along `axis` as it enters the hash (wrapped when periodic).
    #[inline(always)]
    fn wrap(&self, c: i32, axis: usize) -> i32 {
        match self.cells {
            None => c,
            Some(n) => spectex_model::period::wrap(i64::from(c), n[axis]) as i32,
        }
    }

    /// Knuth's multiplication method with renormalisation by `exp(64)` (module doc, step 1).
    fn poisson_count(&self, prng: &mut Prng) -> u32 {
        let mut p = 1.0f32;
        let mut chunks = self.poisson_chunks;
        for k in 0..self.max_impulses {
            p *= prng.next_f32();
            while chunks > 0 && p < self.chunk_down {
                p *= self.chunk_up;
                chunks -= 1;
            }
            if chunks == 0 && p < self.poisson_threshold {
                return k;
            }
        }
        self.max_impulses
    }
}

/// `(sin θ, cos θ)` in f64 for the one anisotropic direction.
// reason: per-model set-up, not per pixel; the GPU receives the resulting f32 vector (the ban
// list names f32 functions only today; the marker keeps this exception if f64 is added).
#[allow(clippy::disallowed_methods)]
fn angle_sin_cos(theta: f64) -> (f64, f64) {
    theta.sin_cos()
}

/// `e^z` in f64 for the Poisson threshold (per-model set-up).
// reason: per-model set-up, not per pixel; the GPU receives the resulting f32.
#[allow(clippy::disallowed_methods)]
fn libm_exp(z: f64) -> f64 {
    z.exp()
}

impl crate::CpuKind for GaborNoise {
    /// The bench case: isotropic Gabor noise (`spectex_model::fixtures`).
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Built(spectex_model::Model::Gabor(
            spectex_model::fixtures::gabor_isotropic(),
        ))
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(GaborEvaluator::new(self)))
    }

    fn cpu_kernel_periodic(
        &self,
        _z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(GaborEvaluator::new_periodic(self, period)))
    }
}

impl crate::RowKernel for GaborEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.cosines_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        if window.width == 0 {
            return;
        }
        for (r, line) in out.chunks_exact_mut(window.width).enumerate() {
            self.eval_row_at(window.y(first + r), |i| window.x(i), line);
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    fn model(ipk: f32, orientation: Orientation) -> GaborNoise {
        GaborNoise {
            seed: 3,
            mean: 0.0,
            amplitude: 1.0,
            bandwidth: 0.05,
            frequency: 0.0625,
            orientation,
            impulses_per_kernel: ipk,
        }
    }

    const ANISO: Orientation = Orientation::Anisotropic { angle: 0.0 };

    /// The renormalised product stays a normal f32: `exp(−64)` times the smallest non-zero
    /// uniform `2⁻²⁴` is above `f32::MIN_POSITIVE`, and `exp(64)` is finite.
    pub fn poisson_chunk_keeps_products_normal() {
        let g = GaborEvaluator::new(&model(500.0, ANISO));
        assert_eq!(g.poisson_chunks, 2);
        assert!(g.chunk_up.is_finite());
        let smallest = g.chunk_down * (1.0 / 16_777_216.0);
        assert!(smallest.is_normal(), "{smallest:e}");
    }

    /// Mean and variance of the per-cell count against λ (Poisson: both equal λ), across the
    /// plain-Knuth and renormalised regimes; tolerance 5 standard errors of each estimate.
    pub fn poisson_count_has_poisson_moments() {
        for ipk in [0.3f32, 8.0, 64.0, 150.0, 250.0, 1000.0] {
            let g = GaborEvaluator::new(&model(ipk, ANISO));
            let lambda = g.lambda;
            let n = 40_000;
            let (mut s1, mut s2) = (0.0f64, 0.0f64);
            for c in 0..n {
                let mut prng = Prng::new(cell_hash_in_row(c, g.layer_key));
                let k = f64::from(g.poisson_count(&mut prng));
                s1 += k;
                s2 += k * k;
            }
            let mean = s1 / f64::from(n);
            let var = s2 / f64::from(n) - mean * mean;
            let se_mean = (lambda / f64::from(n)).sqrt();
            // Var of the sample variance of a Poisson: (μ4 − σ⁴)/n = (λ + 2λ²)/n.
            let se_var = ((lambda + 2.0 * lambda * lambda) / f64::from(n)).sqrt();
            assert!(
                (mean - lambda).abs() < 5.0 * se_mean,
                "ipk {ipk}: mean {mean} vs λ {lambda}"
            );
            assert!(
                (var - lambda).abs() < 5.0 * se_var,
                "ipk {ipk}: var {var} vs λ {lambda}"
            );
        }
    }

    pub fn count_is_capped_and_the_loop_bounded_for_nonsense_models() {
        let mut m = model(8.0, ANISO);
        m.bandwidth = 0.0;
        m.impulses_per_kernel = f32::NAN;
        let g = GaborEvaluator::new(&m);
        let _ = g.eval(1.0, 2.0); // no panic, no hang
        m.impulses_per_kernel = f32::INFINITY;
        m.bandwidth = 1e-30;
        let g = GaborEvaluator::new(&m);
        assert!(g.max_impulses <= 4096 && g.poisson_chunks <= 64);
        let _ = g.eval(1.0, 2.0);
        let g = GaborEvaluator::new(&model(8.0, ANISO));
        assert_eq!(
            g.max_impulses,
            (4.0 * 8.0 / std::f64::consts::PI + 32.0) as u32
        );
    }

    /// `π a² r² = −ln 0.05` for every bandwidth, so the exponent per squared cell unit is fixed.
    pub fn gaussian_exponent_is_the_truncation_log() {
        assert_eq!(NEG_LN_20, spectex_model::GABOR_TRUNCATION.ln() as f32);
        for a in [0.001f32, 0.05, 3.0] {
            let mut m = model(8.0, ANISO);
            m.bandwidth = a;
            let r = m.kernel_radius();
            let c = std::f64::consts::PI * f64::from(a) * f64::from(a) * r * r;
            assert!((c + f64::from(NEG_LN_20)).abs() < 1e-6, "a = {a}: {c}");
        }
    }

    pub fn locate_splits_cells_and_rejects_out_of_range() {
        assert_eq!(locate(-0.5, 2.0), Some((-1, 0.75)));
        assert_eq!(locate(4.0, 2.0), Some((2, 0.0)));
        assert_eq!(locate(f64::NAN, 2.0), None);
        assert_eq!(locate(3e9, 1.0), None);
        assert_eq!(locate(-3e9, 1.0), None);
        let (c, u) = locate(2_147_483_645.5, 1.0).unwrap();
        assert_eq!((c, u), (2_147_483_645, 0.5));
        let g = GaborEvaluator::new(&model(8.0, ANISO));
        assert_eq!(g.eval(f64::NAN, 0.0), 0.0);
        assert_eq!(g.eval(0.0, 1e300), 0.0);
    }

    pub fn kept_impulses_follow_the_draw_order() {
        // Column 5 of row 0 at u_y = 0.5: every impulse of the three cells with |d_y| < 1,
        // redrawn here from the contract.
        let g = GaborEvaluator::new(&model(20.0, Orientation::Isotropic { min: 0.0, max: 6.0 }));
        let row = g.row_context(0.5 * g.radius).unwrap();
        let mut got = Vec::new();
        g.column_impulses(5, &row, |imp| got.push((imp.ox, imp.kw)));
        let mut want = Vec::new();
        for t in -1..=1 {
            let mut prng = Prng::new(spectex_model::random::cell_hash(5, t, GABOR_LAYER, 3));
            let n = g.poisson_count(&mut prng);
            for _ in 0..n {
                let (ox, oy, w) = (prng.next_f32(), prng.next_f32(), prng.next_f32());
                let _angle = prng.next_f32();
                let dy = (0.5 - t as f32) - oy;
                if dy * dy < 1.0 {
                    want.push((ox, 2.0 * w - 1.0));
                }
            }
        }
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }
}
