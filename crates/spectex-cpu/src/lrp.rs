//! Local Random-Phase noise on the CPU (Gilet et al. 2014, Eqs. 1–2).
//!
//! For each stratum `S` the lattice has period `Δ_S`; lattice point `(cx, cy)` sits at
//! `(cx·Δ_S, cy·Δ_S)`. Its random draws follow the randomness contract with `layer` = the
//! stratum's index: `Prng::new(cell_hash(cx, cy, s, seed))`, then for each cosine `j < J_S` in
//! order: the table index `next_u32() mod len_j` (uniform up to a bias below `len/2³²`) and
//! the phase `next_f32()` in turns. A pixel at `x` sums, over the lattice points within
//! `1.5·Δ_S`, `A_S · w(|x − x_i|/Δ_S) · Σ_j cos(2π(f_ij·(x − x_i) + φ_ij))`.
//!
//! The cosine's argument is taken relative to the lattice point, `f·(x − x_i)` rather than the
//! paper's `f·x`: since `φ` is uniform and independent of everything else, the two define the
//! same random field, and the relative form keeps every argument below `1.5·Δ_S·|f|` turns, so
//! a window at `(10⁷, 10⁷)` is as precise as one at the origin (DESIGN invariant 2).
//!
//! Evaluation runs over 8 consecutive pixels at a time with per-lane accumulators, which the
//! compiler vectorises; on x86-64 an AVX2 copy of the same code is chosen at run time. Both
//! are built from plain `*`, `+` and `sqrt` only (no FMA), so they produce identical bits.
//! Each pixel adds its lattice points' contributions in ascending `(cy, cx)` order whatever
//! 8-pixel group it falls in (contributions outside the window's support are exactly `+0`),
//! so any tiling of a window gives the same bits.

use spectex_model::LrpNoise;
use spectex_model::random::{Prng, cell_hash};

use crate::math::{cos_turns, kaiser_bessel_r2};
use spectex_model::Window;

/// Pixels evaluated together.
const LANES: usize = 8;
/// Lanes of the AVX-512 path: one 512-bit register of f32.
const WIDE_LANES: usize = 16;

struct PreparedStratum {
    delta: f64,
    inv_delta: f64,
    inv_delta2: f32,
    amplitude: f32,
    layer: u32,
    /// Concatenated frequency tables.
    table_x: Vec<f32>,
    table_y: Vec<f32>,
    /// `(start, len)` of each sub-stratum's table.
    tables: Vec<(u32, u32)>,
}

/// A validated LRP model, prepared for evaluation.
pub struct LrpEvaluator {
    seed: u32,
    mean: f32,
    strata: Vec<PreparedStratum>,
    simd: Simd,
}

/// The instruction set a row is evaluated with. Every level runs the same per-lane arithmetic
/// (plain `*` and `+`, no FMA), so the output bits are the same; wider levels evaluate more
/// pixels per instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Simd {
    /// Whatever the default target allows (SSE2 on x86-64), 8 lanes.
    Portable,
    /// AVX2, 8 lanes in one register.
    Avx2,
    /// AVX-512F, 16 lanes in one register.
    Avx512,
}

impl Simd {
    /// The widest level this CPU reports at run time.
    fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Self::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Self::Avx2;
            }
        }
        Self::Portable
    }
}

/// The random draws of the lattice points near one output row, for one stratum.
struct RowLattice {
    /// First lattice column and row held.
    cx0: i64,
    cy0: i64,
    cols: usize,
    rows: usize,
    j: usize,
    /// Per lattice point, per cosine: frequency x, frequency y, phase (turns).
    fx: Vec<f32>,
    fy: Vec<f32>,
    phase: Vec<f32>,
}

impl LrpEvaluator {
    /// Prepares a model (already validated by `spectex-model`).
    #[must_use]
    pub fn new(model: &LrpNoise) -> Self {
        let strata = model
            .strata
            .iter()
            .enumerate()
            .map(|(s, st)| {
                let delta = f64::from(st.window_width);
                let mut table_x = Vec::new();
                let mut table_y = Vec::new();
                let mut tables = Vec::new();
                for t in &st.sub_strata {
                    tables.push((table_x.len() as u32, t.len() as u32));
                    table_x.extend(t.iter().map(|f| f[0]));
                    table_y.extend(t.iter().map(|f| f[1]));
                }
                PreparedStratum {
                    delta,
                    inv_delta: 1.0 / delta,
                    inv_delta2: (1.0 / (delta * delta)) as f32,
                    amplitude: st.amplitude,
                    layer: s as u32,
                    table_x,
                    table_y,
                    tables,
                }
            })
            .collect();
        Self {
            seed: model.seed,
            mean: model.mean,
            strata,
            simd: Simd::detect(),
        }
    }

    /// Cosine evaluations per pixel, counted as the paper does: `9·Σ_S J_S`.
    #[must_use]
    pub fn cosines_per_pixel(&self) -> usize {
        9 * self.strata.iter().map(|s| s.tables.len()).sum::<usize>()
    }

    /// Forces the portable path (`false`) or AVX2 when the CPU has it (`true`); for tests
    /// comparing the code paths.
    #[doc(hidden)]
    pub fn set_avx2(&mut self, enabled: bool) {
        self.simd = if enabled && Simd::detect() != Simd::Portable {
            Simd::Avx2
        } else {
            Simd::Portable
        };
    }

    /// Uses AVX-512 when the CPU has it (`true`, the default), else the level below; for tests
    /// comparing the code paths. Returns whether AVX-512 is in use.
    #[doc(hidden)]
    pub fn set_avx512(&mut self, enabled: bool) -> bool {
        self.simd = Simd::detect();
        if !enabled && self.simd == Simd::Avx512 {
            self.simd = Simd::Avx2;
        }
        self.simd == Simd::Avx512
    }

    /// Draws of the lattice points whose support reaches row `y` between `x_min` and `x_max`.
    fn row_lattice(&self, s: &PreparedStratum, y: f64, x_min: f64, x_max: f64) -> RowLattice {
        let cy0 = ((y * s.inv_delta) - 1.5).floor() as i64;
        let cy1 = ((y * s.inv_delta) + 1.5).ceil() as i64;
        let cx0 = ((x_min * s.inv_delta) - 1.5).floor() as i64;
        let cx1 = ((x_max * s.inv_delta) + 1.5).ceil() as i64;
        let (rows, cols) = ((cy1 - cy0 + 1) as usize, (cx1 - cx0 + 1) as usize);
        let j = s.tables.len();
        let n = rows * cols * j;
        let (mut fx, mut fy, mut phase) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for cy in cy0..=cy1 {
            for cx in cx0..=cx1 {
                let mut prng = Prng::new(cell_hash(cx as i32, cy as i32, s.layer, self.seed));
                for &(start, len) in &s.tables {
                    let k = (start + prng.next_u32() % len) as usize;
                    fx.push(s.table_x[k]);
                    fy.push(s.table_y[k]);
                    phase.push(prng.next_f32());
                }
            }
        }
        RowLattice {
            cx0,
            cy0,
            cols,
            rows,
            j,
            fx,
            fy,
            phase,
        }
    }

    /// Evaluates one row of `window` (row index `row`) into `out` (`window.width` values).
    pub fn eval_row(&self, window: &Window, row: usize, out: &mut [f32]) {
        let y = window.y(row);
        let (x_first, x_last) = (window.x(0), window.x(window.width.saturating_sub(1)));
        let (x_min, x_max) = (x_first.min(x_last), x_first.max(x_last));
        out.fill(0.0);
        for s in &self.strata {
            let lattice = self.row_lattice(s, y, x_min, x_max);
            #[cfg(target_arch = "x86_64")]
            match self.simd {
                #[allow(unsafe_code)]
                // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
                Simd::Avx512 => unsafe { stratum_row_avx512(s, &lattice, window, y, out) },
                #[allow(unsafe_code)]
                // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
                Simd::Avx2 => unsafe { stratum_row_avx2(s, &lattice, window, y, out) },
                Simd::Portable => stratum_row::<LANES>(s, &lattice, window, y, out),
            }
            #[cfg(not(target_arch = "x86_64"))]
            stratum_row::<LANES>(s, &lattice, window, y, out);
        }
        for v in out.iter_mut() {
            *v += self.mean;
        }
    }

    /// Evaluates the noise at one position (a 1×1 window; the same bits as any render).
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let w = Window::new(1, 1).at([x, y], 1.0);
        let mut out = [0.0f32];
        self.eval_row(&w, 0, &mut out);
        out[0]
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn stratum_row_avx2(
    s: &PreparedStratum,
    lattice: &RowLattice,
    window: &Window,
    y: f64,
    out: &mut [f32],
) {
    stratum_row::<LANES>(s, lattice, window, y, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn stratum_row_avx512(
    s: &PreparedStratum,
    lattice: &RowLattice,
    window: &Window,
    y: f64,
    out: &mut [f32],
) {
    stratum_row::<WIDE_LANES>(s, lattice, window, y, out);
}

/// Adds one stratum's contribution to a row. `inline(always)` so that the AVX2 wrapper compiles
/// its own copy with wider vectors; the arithmetic is the same in both.
#[inline(always)]
fn stratum_row<const L: usize>(
    s: &PreparedStratum,
    lattice: &RowLattice,
    window: &Window,
    y: f64,
    out: &mut [f32],
) {
    let width = out.len();
    let j = lattice.j;
    let mut start = 0;
    while start < width {
        // Positions of the 8 lanes (lanes past the row's end are computed and dropped).
        let mut xs = [0.0f64; L];
        for (lane, x) in xs.iter_mut().enumerate() {
            *x = window.x(start + lane);
        }
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        // Lattice columns with |x/Δ − cx| < 1.5 for some lane: the open interval's integers.
        let cx_lo = ((((lo * s.inv_delta) - 1.5).floor() as i64) + 1).max(lattice.cx0);
        let cx_hi = ((((hi * s.inv_delta) + 1.5).ceil() as i64) - 1)
            .min(lattice.cx0 + lattice.cols as i64 - 1);
        let mut acc_out = [0.0f32; L];
        for row in 0..lattice.rows {
            let cy = lattice.cy0 + row as i64;
            let dy = (y - cy as f64 * s.delta) as f32;
            let dy2 = dy * dy;
            // Rows beyond the support contribute exactly 0 to every lane: skip them.
            if dy2 * s.inv_delta2 >= 2.25 {
                continue;
            }
            for cx in cx_lo..=cx_hi {
                let lx = cx as f64 * s.delta;
                let mut dx = [0.0f32; L];
                let mut r2 = [0.0f32; L];
                for lane in 0..L {
                    dx[lane] = (xs[lane] - lx) as f32;
                    r2[lane] = (dx[lane] * dx[lane] + dy2) * s.inv_delta2;
                }
                // Cheap test before the window polynomial: is any lane inside the support?
                if r2.iter().all(|&v| v >= 2.25) {
                    continue;
                }
                let mut w = [0.0f32; L];
                for lane in 0..L {
                    w[lane] = kaiser_bessel_r2(r2[lane]);
                }
                let base = (row * lattice.cols + (cx - lattice.cx0) as usize) * j;
                let mut acc = [0.0f32; L];
                for k in base..base + j {
                    let fx = lattice.fx[k];
                    let c = lattice.fy[k] * dy + lattice.phase[k];
                    for lane in 0..L {
                        acc[lane] += cos_turns(fx * dx[lane] + c);
                    }
                }
                for lane in 0..L {
                    acc_out[lane] += w[lane] * acc[lane];
                }
            }
        }
        let end = (start + L).min(width);
        for (o, a) in out[start..end].iter_mut().zip(&acc_out) {
            *o += s.amplitude * a;
        }
        start += L;
    }
}
