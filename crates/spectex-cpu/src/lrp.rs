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
//! Evaluation goes lattice point by lattice point: along an output row, a point touches only the
//! pixels of its support's chord (`|x − x_i| < 1.5·Δ_S`), evaluated 8 (16 with AVX-512)
//! consecutive pixels at a time with per-lane accumulators, which the compiler vectorises; on
//! x86-64 AVX2 and AVX-512 copies of the same code are chosen at run time. All are built from
//! plain `*`, `+` and `sqrt` only (no FMA), so they produce identical bits. Each pixel adds its
//! lattice points' contributions in ascending `(cy, cx)` order whatever group of lanes it falls
//! in (pixels outside a point's support that share its group get exactly `+0`), so any tiling of
//! a window gives the same bits. The draws of a lattice row are made once per band of output
//! rows ([`LrpEvaluator::eval_rows`]) and the row-constant part of each cosine's argument,
//! `f_y·dy + φ`, once per output row.
//!
//! **Minified renders** (a window with a [`footprint`](Window::footprint)): each table entry's
//! cosine is multiplied by its gain ([`spectex_model::filter::component_gain`], LRP §6's
//! frequency clamping with the box filter's attenuation in band), its spread being the window's
//! bandwidth over `Δ_S`. A stratum whose every gain is 0 is skipped whole (its draws are never
//! made: nothing of it reaches a pixel). The gains are computed once per footprint and kept. An
//! unfiltered render runs the loop without the multiplication, so it keeps its bits.

use spectex_model::period::wrap;
use spectex_model::random::{Prng, cell_hash};
use spectex_model::{LrpNoise, Period};

use std::sync::{Arc, Mutex};

use crate::math::{cos_turns, kaiser_bessel_r2};
use spectex_model::Window;
use spectex_model::filter::lrp_gains;

/// Pixels evaluated together.
const LANES: usize = 8;
/// Lanes of the AVX-512 path: one 512-bit register of f32.
const WIDE_LANES: usize = 16;

struct PreparedStratum {
    /// Lattice period along x (`Δ_S`, or the side fitted to a period).
    delta: f64,
    inv_delta: f64,
    /// `1/Δ_x²`.
    inv_delta2: f32,
    /// Lattice period along y: `delta` unless fitted to a period of another height.
    delta_y: f64,
    inv_delta_y: f64,
    /// `(Δ_x/Δ_y)²`, which scales `dy²` so that `r² = (dx² + dy²·aspect2)/Δ_x²` is the
    /// window's elliptic radius: exactly 1 (and then without effect on any bit) for a square
    /// lattice.
    aspect2: f32,
    /// Lattice points per period along x and y, for a periodic model: the point `(cx, cy)`
    /// draws the randomness of `(cx mod n_x, cy mod n_y)`.
    cells: Option<[i64; 2]>,
    amplitude: f32,
    layer: u32,
    /// Concatenated frequency tables.
    table_x: Vec<f32>,
    table_y: Vec<f32>,
    /// `(start, len)` of each sub-stratum's table.
    tables: Vec<(u32, u32)>,
}

/// The gain of every table entry, per stratum, at one footprint (`None` for a stratum whose
/// gains are all 0: it is skipped).
type StratumGains = Vec<Option<Vec<f32>>>;

/// A validated LRP model, prepared for evaluation.
pub struct LrpEvaluator {
    /// The model, for the gains of a footprint.
    model: LrpNoise,
    seed: u32,
    mean: f32,
    strata: Vec<PreparedStratum>,
    simd: Simd,
    /// The gains of the last footprint rendered (its bits), shared by the bands of a render.
    gains: Mutex<Option<(u64, Arc<StratumGains>)>>,
}

/// The instruction set a row is evaluated with. Every level runs the same per-lane arithmetic
/// (plain `*` and `+`, no FMA), so the output bits are the same; wider levels evaluate more
/// pixels per instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Simd {
    /// Whatever the default target allows (SSE2 on x86-64), 8 lanes.
    Portable,
    /// AVX2, 8 lanes in one register.
    Avx2,
    /// AVX-512F, 16 lanes in one register.
    Avx512,
}

impl Simd {
    /// The widest level this CPU reports at run time.
    pub(crate) fn detect() -> Self {
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

    /// The portable level (`false`) or AVX2 where the CPU has it (`true`): what an
    /// evaluator's `set_avx2` selects for tests comparing the code paths.
    pub(crate) fn up_to_avx2(enabled: bool) -> Self {
        if enabled && Self::detect() != Self::Portable {
            Self::Avx2
        } else {
            Self::Portable
        }
    }

    /// The widest level the CPU has, or the one below AVX-512 when `!enabled`: what an
    /// evaluator's `set_avx512` selects.
    pub(crate) fn with_avx512(enabled: bool) -> Self {
        match Self::detect() {
            Self::Avx512 if !enabled => Self::Avx2,
            level => level,
        }
    }
}

/// The random draws of one lattice row of one stratum, for the lattice columns a window needs.
struct LatticeRow {
    cy: i64,
    /// Per lattice point, per cosine: frequency x, frequency y, phase (turns), and the gain of
    /// a minified render (empty when unfiltered).
    fx: Vec<f32>,
    fy: Vec<f32>,
    phase: Vec<f32>,
    gain: Vec<f32>,
}

/// The lattice rows of one stratum that the current output row needs, kept from row to row while
/// a band of rows is evaluated (a lattice row serves every output row within `1.5·Δ_S` of it).
struct StratumLattice {
    /// First lattice column held, and how many.
    cx0: i64,
    cols: usize,
    /// Cosines per lattice point.
    j: usize,
    /// Held rows, in ascending `cy`.
    rows: Vec<LatticeRow>,
}

/// Lattice rows no longer held, kept per thread for their buffers: a minified render evaluates
/// pixel by pixel, each pixel drawing a few rows of its own (a few dozen buffers a pixel), and
/// allocating and freeing them was a quarter of its time. A row taken from here is cleared before
/// it is filled, so nothing of its past reaches a pixel.
const SPARE_ROWS: usize = 64;
/// The most draws a spare row's buffers may hold (a pixel's own rows hold a few dozen).
const SPARE_DRAWS: usize = 1024;

thread_local! {
    static SPARE: std::cell::RefCell<Vec<LatticeRow>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl LatticeRow {
    /// An empty row `cy` with room for `n` draws (and their gains when `filtered`), from the
    /// thread's spare rows when it has one.
    fn empty(cy: i64, n: usize, filtered: bool) -> Self {
        let spare = SPARE.with(|s| s.borrow_mut().pop());
        let mut row = spare.unwrap_or(Self {
            cy,
            fx: Vec::new(),
            fy: Vec::new(),
            phase: Vec::new(),
            gain: Vec::new(),
        });
        row.cy = cy;
        for v in [&mut row.fx, &mut row.fy, &mut row.phase, &mut row.gain] {
            v.clear();
        }
        for v in [&mut row.fx, &mut row.fy, &mut row.phase] {
            v.reserve(n);
        }
        if filtered {
            row.gain.reserve(n);
        }
        row
    }

    /// Gives a small row's buffers back to the thread's spare rows (up to [`SPARE_ROWS`] of
    /// at most [`SPARE_DRAWS`] draws: at most 1 MiB a thread); a wide row's are freed.
    fn recycle(self) {
        if self.fx.capacity() > SPARE_DRAWS {
            return;
        }
        SPARE.with(|s| {
            let mut spare = s.borrow_mut();
            if spare.len() < SPARE_ROWS {
                spare.push(self);
            }
        });
    }
}

impl Drop for StratumLattice {
    fn drop(&mut self) {
        for row in self.rows.drain(..) {
            row.recycle();
        }
    }
}

impl StratumLattice {
    /// An empty cache for the columns whose support reaches `x_min..=x_max`.
    fn new(s: &PreparedStratum, x_min: f64, x_max: f64) -> Self {
        let cx0 = ((x_min * s.inv_delta) - 1.5).floor() as i64;
        let cx1 = ((x_max * s.inv_delta) + 1.5).ceil() as i64;
        Self {
            cx0,
            cols: (cx1 - cx0 + 1) as usize,
            j: s.tables.len(),
            rows: Vec::new(),
        }
    }

    /// Holds exactly the lattice rows whose support may reach row `y`, drawing the missing ones.
    fn update(&mut self, s: &PreparedStratum, seed: u32, y: f64, gains: Option<&[f32]>) {
        let cy0 = ((y * s.inv_delta_y) - 1.5).floor() as i64;
        let cy1 = ((y * s.inv_delta_y) + 1.5).ceil() as i64;
        let mut i = 0;
        while i < self.rows.len() {
            if (cy0..=cy1).contains(&self.rows[i].cy) {
                i += 1;
            } else {
                self.rows.remove(i).recycle();
            }
        }
        for cy in cy0..=cy1 {
            if self.rows.iter().any(|r| r.cy == cy) {
                continue;
            }
            let mut row = LatticeRow::empty(cy, self.cols * self.j, gains.is_some());
            for cx in self.cx0..self.cx0 + self.cols as i64 {
                let (hx, hy) = match s.cells {
                    None => (cx, cy),
                    Some([nx, ny]) => (wrap(cx, nx), wrap(cy, ny)),
                };
                let mut prng = Prng::new(cell_hash(hx as i32, hy as i32, s.layer, seed));
                for &(start, len) in &s.tables {
                    let k = (start + prng.next_u32() % len) as usize;
                    row.fx.push(s.table_x[k]);
                    row.fy.push(s.table_y[k]);
                    row.phase.push(prng.next_f32());
                    if let Some(g) = gains {
                        row.gain.push(g[k]);
                    }
                }
            }
            self.rows.push(row);
        }
        self.rows.sort_unstable_by_key(|r| r.cy);
    }
}

impl LrpEvaluator {
    /// Prepares a model (already validated by `spectex-model`).
    #[must_use]
    pub fn new(model: &LrpNoise) -> Self {
        Self::prepare(model, None)
    }

    /// Prepares a model made exactly periodic with `period` (any period: each stratum's lattice
    /// is fitted to it, [`Period::fit_lattice`], and its points hashed modulo the period).
    ///
    /// The cosines need no snapping of their frequencies to multiples of `1/period`: each is
    /// evaluated relative to its own lattice point (`f·(x − x_i)`, see the module doc), so a
    /// lattice point one period away, which draws the same frequency and phase, adds the same
    /// term shifted by exactly one period — the field is periodic whatever the frequencies.
    /// Nor does the spectrum ask for it: a periodic field's spectrum lives on multiples of
    /// `1/period`, and each windowed cosine already spreads over a band `≈ 1/Δ_S` wide, many
    /// such multiples, so snapping would move each cosine by at most `1/(2·period)` within a
    /// blur of `1/Δ_S` and change nothing measurable (the fidelity test checks the spectrum).
    #[must_use]
    pub fn new_periodic(model: &LrpNoise, period: Period) -> Self {
        Self::prepare(model, Some(period))
    }

    fn prepare(model: &LrpNoise, period: Option<Period>) -> Self {
        let strata = model
            .strata
            .iter()
            .enumerate()
            .map(|(s, st)| {
                let nominal = f64::from(st.window_width);
                let (delta, delta_y, cells) = match period {
                    None => (nominal, nominal, None),
                    Some(p) => {
                        let fitted = p.fit_lattice(nominal);
                        (fitted.side[0], fitted.side[1], Some(fitted.cells))
                    }
                };
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
                    delta_y,
                    inv_delta_y: 1.0 / delta_y,
                    aspect2: ((delta / delta_y) * (delta / delta_y)) as f32,
                    cells,
                    amplitude: st.amplitude,
                    layer: s as u32,
                    table_x,
                    table_y,
                    tables,
                }
            })
            .collect();
        Self {
            model: model.clone(),
            seed: model.seed,
            mean: model.mean,
            strata,
            simd: Simd::detect(),
            gains: Mutex::new(None),
        }
    }

    /// The gains of every table entry at footprint `side` (computed once per footprint).
    fn gains_at(&self, side: f64) -> Arc<StratumGains> {
        let mut cache = self
            .gains
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((bits, gains)) = cache.as_ref()
            && *bits == side.to_bits()
        {
            return Arc::clone(gains);
        }
        let gains: StratumGains = lrp_gains(&self.model, side)
            .into_iter()
            .map(|g| g.iter().any(|&v| v > 0.0).then_some(g))
            .collect();
        let gains = Arc::new(gains);
        *cache = Some((side.to_bits(), Arc::clone(&gains)));
        gains
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
        self.simd = Simd::up_to_avx2(enabled);
    }

    /// Uses AVX-512 when the CPU has it (`true`, the default), else the level below; for tests
    /// comparing the code paths. Returns whether AVX-512 is in use.
    #[doc(hidden)]
    pub fn set_avx512(&mut self, enabled: bool) -> bool {
        self.simd = Simd::with_avx512(enabled);
        self.simd == Simd::Avx512
    }

    /// Evaluates one row of `window` (row index `row`) into `out` (`window.width` values).
    pub fn eval_row(&self, window: &Window, row: usize, out: &mut [f32]) {
        self.eval_rows(window, row, out);
    }

    /// Evaluates consecutive rows of `window`, from row `first`, into `out` (a whole number of
    /// rows of `window.width` values). The lattice draws are shared between the rows; the values
    /// are the same bits as row by row.
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let gains = window.footprint().map(|side| self.gains_at(side));
        self.eval_rows_with(window, first, out, gains.as_deref().map(Vec::as_slice));
    }

    /// [`eval_rows`](Self::eval_rows) with the gains of the window's footprint (`None`:
    /// unfiltered).
    fn eval_rows_with(
        &self,
        window: &Window,
        first: usize,
        out: &mut [f32],
        gains: Option<&[Option<Vec<f32>>]>,
    ) {
        let width = window.width;
        if width == 0 {
            return;
        }
        // The strata evaluated: all, or those a minified render keeps, with their gains.
        let active: Vec<(&PreparedStratum, Option<&[f32]>)> = match gains {
            None => self.strata.iter().map(|s| (s, None)).collect(),
            Some(g) => self
                .strata
                .iter()
                .zip(g)
                .filter_map(|(s, g)| g.as_deref().map(|g| (s, Some(g))))
                .collect(),
        };
        let (x_first, x_last) = (window.x(0), window.x(width - 1));
        let (x_min, x_max) = (x_first.min(x_last), x_first.max(x_last));
        let mut lattices: Vec<StratumLattice> = active
            .iter()
            .map(|(s, _)| StratumLattice::new(s, x_min, x_max))
            .collect();
        // A minified row: each pixel alone (`crate::eval_if_minified`), judged by the stratum
        // of most lattice columns.
        let columns = lattices.iter().map(|l| l.cols as u64).max().unwrap_or(0);
        if crate::eval_if_minified(window, first, out, (columns, 0), |w, f, o| {
            self.eval_rows_with(w, f, o, gains);
        }) {
            return;
        }
        // One stratum's row, padded so that a full group of lanes may be written past its end.
        let mut sum = vec![0.0f32; width + WIDE_LANES];
        let mut offsets = Vec::new();
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let y = window.y(first + r);
            line.fill(0.0);
            for (&(s, g), lattice) in active.iter().zip(&mut lattices) {
                lattice.update(s, self.seed, y, g);
                sum.fill(0.0);
                let filtered = g.is_some();
                #[cfg(target_arch = "x86_64")]
                match (self.simd, filtered) {
                    #[allow(unsafe_code)]
                    // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F.
                    (Simd::Avx512, false) => unsafe {
                        stratum_row_avx512::<false>(s, lattice, window, y, &mut sum, &mut offsets)
                    },
                    #[allow(unsafe_code)]
                    // SAFETY: as above.
                    (Simd::Avx512, true) => unsafe {
                        stratum_row_avx512::<true>(s, lattice, window, y, &mut sum, &mut offsets)
                    },
                    #[allow(unsafe_code)]
                    // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
                    (Simd::Avx2, false) => unsafe {
                        stratum_row_avx2::<false>(s, lattice, window, y, &mut sum, &mut offsets)
                    },
                    #[allow(unsafe_code)]
                    // SAFETY: as above.
                    (Simd::Avx2, true) => unsafe {
                        stratum_row_avx2::<true>(s, lattice, window, y, &mut sum, &mut offsets)
                    },
                    (Simd::Portable, false) => {
                        stratum_row::<LANES, false>(s, lattice, window, y, &mut sum, &mut offsets);
                    }
                    (Simd::Portable, true) => {
                        stratum_row::<LANES, true>(s, lattice, window, y, &mut sum, &mut offsets);
                    }
                }
                #[cfg(not(target_arch = "x86_64"))]
                if filtered {
                    stratum_row::<LANES, true>(s, lattice, window, y, &mut sum, &mut offsets);
                } else {
                    stratum_row::<LANES, false>(s, lattice, window, y, &mut sum, &mut offsets);
                }
                for (o, a) in line.iter_mut().zip(&sum) {
                    *o += s.amplitude * a;
                }
            }
            for v in line.iter_mut() {
                *v += self.mean;
            }
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
fn stratum_row_avx2<const FILTERED: bool>(
    s: &PreparedStratum,
    lattice: &StratumLattice,
    window: &Window,
    y: f64,
    sum: &mut [f32],
    offsets: &mut Vec<f32>,
) {
    stratum_row::<LANES, FILTERED>(s, lattice, window, y, sum, offsets);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn stratum_row_avx512<const FILTERED: bool>(
    s: &PreparedStratum,
    lattice: &StratumLattice,
    window: &Window,
    y: f64,
    sum: &mut [f32],
    offsets: &mut Vec<f32>,
) {
    stratum_row::<WIDE_LANES, FILTERED>(s, lattice, window, y, sum, offsets);
}

/// Adds one stratum's windowed cosine sums along row `y` to `sum` (the window's width plus at
/// least `L` values, zero on entry; values past the width are scratch).
///
/// Lattice point by lattice point, in ascending `(cy, cx)`: each point adds to the pixels of its
/// support's chord of the row only, `L` consecutive pixels at a time. Pixels outside the support
/// that share a group get an exact `+0` (the window is exactly 0 there), so every pixel sums the
/// same non-zero terms in the same order whatever group it falls in: any tiling of a window, and
/// any lane count, gives the same bits. A chord of at most `L/4` pixels (a minified row) is
/// added pixel by pixel with the point's cosines in the lanes ([`chord_pixel`]): the same
/// operations again. `inline(always)` so that each SIMD wrapper compiles its own copy; the
/// arithmetic is the same in all. `FILTERED`: each cosine is multiplied by its gain (a
/// minified render); without it the loop is exactly the unfiltered one.
#[inline(always)]
fn stratum_row<const L: usize, const FILTERED: bool>(
    s: &PreparedStratum,
    lattice: &StratumLattice,
    window: &Window,
    y: f64,
    sum: &mut [f32],
    offsets: &mut Vec<f32>,
) {
    let width = sum.len() - WIDE_LANES;
    let j = lattice.j;
    let support = 1.5 * s.delta;
    for row in &lattice.rows {
        let dy64 = y - row.cy as f64 * s.delta_y;
        let dy = dy64 as f32;
        let dy2 = dy * dy * s.aspect2;
        // Rows beyond the support contribute exactly 0 to every pixel: skip them.
        if dy2 * s.inv_delta2 >= 2.25 {
            continue;
        }
        // Half the chord of the support along this row.
        let dyx = dy64 * (s.delta / s.delta_y);
        let half = (support * support - dyx * dyx).max(0.0).sqrt();
        // The part of each cosine's argument that is constant along the row: `f_y·dy + φ`.
        offsets.clear();
        offsets.extend(row.fy.iter().zip(&row.phase).map(|(&fy, &ph)| fy * dy + ph));
        for col in 0..lattice.cols {
            let cx = lattice.cx0 + col as i64;
            let lx = cx as f64 * s.delta;
            let Some((i_lo, i_hi)) = support_span(window, width, lx, half, dy2, s.inv_delta2)
            else {
                continue;
            };
            let base = col * j;
            let (fxs, cs) = (&row.fx[base..base + j], &offsets[base..base + j]);
            let gs = if FILTERED {
                &row.gain[base..base + j]
            } else {
                &[][..]
            };
            // A chord of a few pixels (a minified row, where a point's support spans a pixel
            // or two): lanes over the point's cosines, pixel by pixel, instead of a group of
            // pixel lanes mostly past the chord.
            if (i_hi - i_lo + 1) * 4 <= L {
                for i in i_lo..=i_hi {
                    sum[i] += chord_pixel::<L, FILTERED>(window.x(i), lx, dy2, s, fxs, cs, gs);
                }
                continue;
            }
            let mut start = i_lo;
            while start <= i_hi {
                let mut dx = [0.0f32; L];
                let mut r2 = [0.0f32; L];
                for lane in 0..L {
                    dx[lane] = (window.x(start + lane) - lx) as f32;
                    r2[lane] = (dx[lane] * dx[lane] + dy2) * s.inv_delta2;
                }
                let mut w = [0.0f32; L];
                for lane in 0..L {
                    w[lane] = kaiser_bessel_r2(r2[lane]);
                }
                let mut acc = [0.0f32; L];
                if FILTERED {
                    for ((&fx, &c), &g) in fxs.iter().zip(cs).zip(gs) {
                        for lane in 0..L {
                            acc[lane] += g * cos_turns(fx * dx[lane] + c);
                        }
                    }
                } else {
                    for (&fx, &c) in fxs.iter().zip(cs) {
                        for lane in 0..L {
                            acc[lane] += cos_turns(fx * dx[lane] + c);
                        }
                    }
                }
                let out = &mut sum[start..start + L];
                for lane in 0..L {
                    out[lane] += w[lane] * acc[lane];
                }
                start += L;
            }
        }
    }
}

/// What one lattice point adds to the pixel at `x` ([`stratum_row`]'s `w·acc` for that
/// pixel): the point's cosines `L` at a time in lanes, then summed in their order, so each
/// operation is the one the pixel's lane performs there (the same bits).
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "one point's row slices and the row's terms"
)]
fn chord_pixel<const L: usize, const FILTERED: bool>(
    x: f64,
    lx: f64,
    dy2: f32,
    s: &PreparedStratum,
    fxs: &[f32],
    cs: &[f32],
    gs: &[f32],
) -> f32 {
    let dx = (x - lx) as f32;
    let r2 = (dx * dx + dy2) * s.inv_delta2;
    let w = kaiser_bessel_r2(r2);
    let mut acc = 0.0f32;
    for (k, (fx, c)) in fxs.chunks(L).zip(cs.chunks(L)).enumerate() {
        let mut lanes = [0.0f32; L];
        let (mut fxl, mut cl, mut gl) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
        fxl[..fx.len()].copy_from_slice(fx);
        cl[..c.len()].copy_from_slice(c);
        if FILTERED {
            gl[..fx.len()].copy_from_slice(&gs[k * L..][..fx.len()]);
        }
        for lane in 0..L {
            let t = cos_turns(fxl[lane] * dx + cl[lane]);
            lanes[lane] = if FILTERED { gl[lane] * t } else { t };
        }
        for t in &lanes[..fx.len()] {
            acc += t;
        }
    }
    w * acc
}

/// `r²/Δ²` of pixel `i` from a lattice point at `lx`, in f32 exactly as the lanes compute it.
#[inline(always)]
fn lane_r2(window: &Window, i: usize, lx: f64, dy2: f32, inv_delta2: f32) -> f32 {
    let dx = (window.x(i) - lx) as f32;
    (dx * dx + dy2) * inv_delta2
}

/// The pixels of a row (indices below `width`) that may lie inside the support of the lattice
/// point at `lx`, whose support's chord on this row is `lx ± half`: `None` when there are none.
///
/// The estimate from `half` is then widened until the first pixel outside it on each side has
/// an f32 `r²` of at least 2.25 (a window of exactly 0). The f32 `r²` never decreases as `|x − lx|`
/// grows (every step of it rounds monotonically), so no pixel outside the span can have a
/// non-zero window, whatever the scale: the span is exact, not a guess with a margin.
#[inline(always)]
fn support_span(
    window: &Window,
    width: usize,
    lx: f64,
    half: f64,
    dy2: f32,
    inv_delta2: f32,
) -> Option<(usize, usize)> {
    let (x0, inv_scale) = (window.x(0), 1.0 / window.scale);
    let last = (width - 1) as f64;
    let lo = ((lx - half - x0) * inv_scale).floor().clamp(0.0, last) as usize;
    let hi = ((lx + half - x0) * inv_scale).ceil().clamp(0.0, last) as usize;
    let (mut lo, mut hi) = (lo, hi);
    while lo > 0 && lane_r2(window, lo - 1, lx, dy2, inv_delta2) < 2.25 {
        lo -= 1;
    }
    while hi + 1 < width && lane_r2(window, hi + 1, lx, dy2, inv_delta2) < 2.25 {
        hi += 1;
    }
    // Trim pixels that are outside on the f32 test too (the span only needs to cover the rest).
    while lo <= hi && lane_r2(window, lo, lx, dy2, inv_delta2) >= 2.25 {
        lo += 1;
    }
    while hi >= lo && hi > 0 && lane_r2(window, hi, lx, dy2, inv_delta2) >= 2.25 {
        hi -= 1;
    }
    (lo <= hi && lane_r2(window, lo, lx, dy2, inv_delta2) < 2.25).then_some((lo, hi))
}

impl crate::CpuKind for LrpNoise {
    /// The bench case: LRP noise of J = 50 cosines over 4 strata (`spectex_model::fixtures`), the speed the project tracks.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Built(spectex_model::Model::Lrp(
            spectex_model::fixtures::lrp_four_strata(50),
        ))
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(LrpEvaluator::new(self)))
    }

    fn cpu_kernel_periodic(
        &self,
        _z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(LrpEvaluator::new_periodic(self, period)))
    }
}

impl crate::RowKernel for LrpEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.cosines_per_pixel() as f64
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        LrpEvaluator::eval_rows(self, window, first, out);
    }
}
