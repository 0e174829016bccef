//! Phasor noise (Tricard, Efremov, Zanni, Neyret, Martínez & Lefebvre 2019) on the CPU, in 2D and
//! on slices of 3D.
//!
//! # The sum
//!
//! At a point `p`, `𝒢(p) = Σ_j a(p − x_j)·exp(i·2π(f_j·(p − x_j) + ψ_j))` over the impulses `x_j` within
//! the kernel radius `r` ([`PhasorNoise::kernel_radius`]), with `a(d) = exp(−π b²|d|²)` and the
//! frequency vector `f_j = F(x_j)·u_j` in cycles per pixel (Eqs. 10, 15). Space is cut into cells
//! of side `r` (squares, or cubes in 3D), so the impulses that reach `p` lie in the 3×3 (3×3×3)
//! cells around `p`'s cell. All arithmetic after locating `p` is f32 in cell units:
//! `d = (u − s) − o` for the point's offset `u ∈ [0, 1]` in its cell, the neighbour step
//! `s ∈ {−1, 0, 1}` and the impulse's offset `o` in its own cell, so precision does not depend
//! on how far from the origin the window is. An impulse contributes when `s·|d|² < 1`:
//! `g = exp_poly(−ln 20·s·|d|²)` (`π b_min² r² = ln 20`, `s = (b_j/b_min)²`, 1 for a constant
//! bandwidth, when `s·|d|²` is exactly `|d|²`), `t = f·d + ψ` in turns (with `f` in turns
//! per cell), `re += g·cos_turns(t)`, `im += g·sin_turns(t)`, in the order: cell layers `s_z`,
//! rows `s_y`, columns `s_x` ascending, impulses in draw order.
//!
//! The phase offset `ψ_j`, uniform per impulse, is not in the paper's Eq. (5) but is standard in
//! Gabor noise: it makes every term's mean exactly 0, so `𝒢` is circularly symmetric and the
//! phase `φ` exactly uniform. Without it the mean of a term is the truncated kernel's Fourier
//! transform at `F`, whose side lobes (from the cut at 5% of the peak) are not negligible: a
//! PWM profile of duty 25% then came out 25.5% white at `F = 0.05`, `b = 0.02`, and 24.8% at
//! `b = 0.01` (measured), where the paper's Fig. 16 has 25.007%.
//!
//! Then `I = √(re² + im²)` (Eq. 8), `φ = atan2_turns(im, re)` in turns (Eq. 9), and the output is
//! `f(φ)` for the profile `f` (Eq. 4), `φ`, `I`, or `im = I·sin φ` (Gabor noise, Eq. 13).
//!
//! # Kernels
//!
//! Which impulses each cell holds, and their frequency vectors and phase offsets, are
//! [`spectex_model::phasor_kernels`] (the randomness contract, shared with the GPU evaluator).
//!
//! # Evaluation order
//!
//! A row of pixels is evaluated kernel by kernel ([`PhasorEvaluator::eval_rows`]): every impulse
//! of the cell rows the output row needs, in the contract's order (cell layers, rows, columns
//! ascending, impulses in draw order), adds its term to the pixels of its chord of the row,
//! 8 (16 with AVX-512) consecutive pixels at a time, with the AVX2 and AVX-512 copies of the
//! lane code chosen at run time. Each lane computes its own pixel's `d` from its own cell and
//! offset exactly as the per-pixel sum does, and its term is added only where that pixel's sum
//! adds it (its cell a neighbour of the impulse's, `s·|d|² < 1`); elsewhere the lane adds an
//! exact `+0`, which leaves a sum unchanged (a sum that starts at `+0` is never `−0`). So every
//! pixel adds the same terms in the same order as [`PhasorEvaluator::eval_rows_reference`], the
//! pixel-by-pixel sum kept as the reference, whatever the SIMD level, tiling or chord: the
//! chord only skips lanes whose terms are masked anyway. An impulse whose row offset alone puts
//! it out of reach of the row (`s·(d_y² + d_z²) ≥ 1`, which bounds `s·|d|²` from below after
//! rounding too) is skipped whole.
//!
//! # Determinism
//!
//! Every pixel is a pure function of (model, position): any tiling and any thread count give the
//! same bits. Impulse draws are cached per band of rows, which changes nothing but speed.

use spectex_model::phasor_kernels::{Impulse, PhasorKernels};
use spectex_model::{
    Field, FieldGrid, NEG_LN_20, Period, PhasorNoise, PhasorOrientation, PhasorOutput, Profile,
    Window,
};

use crate::lrp::Simd;
use crate::math::{atan2_turns, cos_turns, exp_poly, sin_turns};

/// Pixels evaluated together by the portable and AVX2 paths.
const LANES: usize = 8;
/// Pixels evaluated together by the AVX-512 path (one 512-bit register of f32).
const WIDE_LANES: usize = 16;

/// Cell units added to an impulse's chord before it is turned into pixels: far more than the
/// f32 rounding of a lane's `d` (below 10⁻⁶ cell units), so the chord holds every pixel the
/// impulse reaches; lanes outside it are masked exactly anyway.
const CHORD_MARGIN: f64 = 0.01;

/// A phasor noise model prepared for evaluation at a fixed `z` (ignored by 2D models).
#[derive(Debug, Clone)]
pub struct PhasorEvaluator {
    model: PhasorNoise,
    kernels: PhasorKernels,
    z: f64,
    /// The Fourier series of the profile's `Samples` leaves, depth first, for minified renders
    /// ([`spectex_model::filter::samples_series`]).
    series: Vec<Vec<f32>>,
    simd: Simd,
}

/// The impulses of one row of cells `(j, k)`, per column from `i0`.
#[derive(Debug)]
struct CellRow {
    j: i32,
    k: i32,
    i0: i32,
    columns: Vec<Vec<Impulse>>,
}

/// The kernel cells and offsets of a row's first and last pixels (`None` when either lies out
/// of the position range).
type RowColumns = Option<((i32, f32), (i32, f32))>;

impl PhasorEvaluator {
    /// Prepares `model` (assumed validated) for evaluation on the plane `z` (pixels).
    #[must_use]
    pub fn new(model: &PhasorNoise, z: f64) -> Self {
        Self::with_kernels(model, z, PhasorKernels::new(model))
    }

    /// Prepares `model` made periodic with `period` ([`PhasorKernels::new_periodic`]: cells
    /// fitted to the period and hashed modulo it).
    ///
    /// # Errors
    /// [`spectex_model::ModelError::Period`] when it has no periodic form with `period`.
    pub fn new_periodic(
        model: &PhasorNoise,
        z: f64,
        period: Period,
    ) -> Result<Self, spectex_model::ModelError> {
        PhasorKernels::new_periodic(model, period).map(|k| Self::with_kernels(model, z, k))
    }

    fn with_kernels(model: &PhasorNoise, z: f64, kernels: PhasorKernels) -> Self {
        let mut series = Vec::new();
        samples_series(&model.profile, &mut series);
        Self {
            model: model.clone(),
            z: if kernels.three_d() { z } else { 0.0 },
            kernels,
            series,
            simd: Simd::detect(),
        }
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

    /// Kernel evaluations per pixel (every impulse of the neighbouring cells is visited), for
    /// reports: `9λ` in 2D, `27λ` in 3D. A coherent orientation sums, for each kernel, the
    /// direction process over its own neighbouring cells (the same density): `9λ(1 + 9λ)` and
    /// `27λ(1 + 27λ)`.
    #[must_use]
    pub fn kernels_per_pixel(&self) -> f64 {
        let cells = if self.kernels.three_d() { 27.0 } else { 9.0 };
        let kernels = cells * self.model.impulses_per_cell();
        if matches!(self.model.orientation, PhasorOrientation::Coherent { .. }) {
            kernels * (1.0 + kernels)
        } else {
            kernels
        }
    }

    /// Holds the cell rows `(j + s_y, k + s_z)` for a row of pixels, columns `i0..=i1`.
    fn update_rows(&self, rows: &mut Vec<CellRow>, j: i32, k: i32, i0: i32, i1: i32) {
        let zs: &[i32] = if self.kernels.three_d() {
            &[-1, 0, 1]
        } else {
            &[0]
        };
        let wanted: Vec<(i32, i32)> = zs
            .iter()
            .flat_map(|&sz| (-1..=1).map(move |sy| (j + sy, k + sz)))
            .collect();
        rows.retain(|r| {
            r.i0 == i0 && r.columns.len() == (i1 - i0 + 1) as usize && wanted.contains(&(r.j, r.k))
        });
        for &(cj, ck) in &wanted {
            if rows.iter().any(|r| r.j == cj && r.k == ck) {
                continue;
            }
            let columns = (i0..=i1)
                .map(|ci| {
                    let mut v = Vec::new();
                    self.kernels.draw_cell([ci, cj, ck], &mut v);
                    v
                })
                .collect();
            rows.push(CellRow {
                j: cj,
                k: ck,
                i0,
                columns,
            });
        }
        // Layers then rows ascending: the contract's summation order.
        rows.sort_unstable_by_key(|r| (r.k, r.j));
    }

    /// The prologue of [`eval_rows`](Self::eval_rows) and
    /// [`eval_rows_reference`](Self::eval_rows_reference) (`window.width > 0`): the kernel
    /// columns of the row's first and last pixels (`None` inside when either is out of range),
    /// or `None` when the row is minified and was evaluated pixel by pixel through `eval`
    /// (`crate::eval_if_minified`; a row across the whole position range would also count
    /// columns past i32).
    fn minified_or(
        &self,
        window: &Window,
        first: usize,
        out: &mut [f32],
        eval: impl Fn(&Window, usize, &mut [f32]),
    ) -> Option<RowColumns> {
        let g = &self.kernels;
        let (x_first, x_last) = (window.x(0), window.x(window.width - 1));
        let columns = g.locate(x_first).zip(g.locate(x_last));
        let span = columns.map_or(0, |((c0, _), (c1, _))| {
            (i64::from(c1) - i64::from(c0)).unsigned_abs()
        });
        (!crate::eval_if_minified(window, first, out, (span, 0), eval)).then_some(columns)
    }

    /// Evaluates consecutive rows of `window` from row `first` into `out` (whole rows): kernel
    /// by kernel along each row (see the module doc), the same bits as
    /// [`eval_rows_reference`](Self::eval_rows_reference).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let Some(columns) = self.minified_or(window, first, out, |w, f, o| self.eval_rows(w, f, o))
        else {
            return;
        };
        let g = &self.kernels;
        let z = if g.three_d() {
            g.locate(self.z)
        } else {
            Some((0, 0.0))
        };
        let footprint = window.footprint();
        // Each pixel's cell and offset along x (the same on every row); lanes may run up to a
        // group past the last pixel, into scratch.
        let mut cells = vec![0i32; width + WIDE_LANES];
        let mut offsets = vec![0.0f32; width + WIDE_LANES];
        let mut located = vec![false; width];
        for i in 0..width {
            if let Some((c, u)) = g.locate(window.x(i)) {
                (cells[i], offsets[i], located[i]) = (c, u, true);
            }
        }
        let lanes = Lanes {
            window,
            side: g.side(),
            cells: &cells,
            offsets: &offsets,
        };
        let mut re = vec![0.0f32; width + WIDE_LANES];
        let mut im = vec![0.0f32; width + WIDE_LANES];
        let mut rows = Vec::new();
        // The profile's image fields (and a minified render's frequency) on this window's
        // columns, read row by row: `Field::at`'s values, located once per column and row.
        let fields = self.read_fields(footprint.is_some());
        let xs: Vec<f64> = (0..width).map(|i| window.x(i)).collect();
        let grids: Vec<FieldGrid<'_>> = fields
            .iter()
            .map(|f| FieldGrid::new(f, xs.clone(), self.z))
            .collect();
        let mut values = vec![vec![0.0f64; width]; fields.len()];
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let y = window.y(first + r);
            let (Some(((c0, _), (c1, _))), Some((cj, uy)), Some((ck, uz))) =
                (columns, g.locate(y), z)
            else {
                line.fill(0.0);
                continue;
            };
            self.update_rows(&mut rows, cj, ck, c0 - 1, c1 + 1);
            re.fill(0.0);
            im.fill(0.0);
            let at = RowAt { cj, ck, uy, uz };
            self.sum_row(&rows, &at, &lanes, &mut re, &mut im);
            for (grid, row) in grids.iter().zip(&mut values) {
                grid.row(y, |i, v| row[i] = v);
            }
            for (i, v) in line.iter_mut().enumerate() {
                *v = if located[i] {
                    let mut read = |f: &Field| match fields.iter().position(|g| std::ptr::eq(*g, f))
                    {
                        Some(k) => values[k][i],
                        None => f.at(xs[i], y, self.z),
                    };
                    self.output(re[i], im[i], &mut read, footprint)
                } else {
                    0.0
                };
            }
        }
    }

    /// The image fields [`output`](Self::output) reads at each pixel: a profiled output's duty
    /// cycles and blend weights, and with `minified` its frequency. (Constants and ramps cost
    /// no more per pixel than read from a row.)
    fn read_fields(&self, minified: bool) -> Vec<&Field> {
        fn walk<'p>(profile: &'p Profile, out: &mut Vec<&'p Field>) {
            match profile {
                Profile::Square { duty } => out.push(duty),
                Profile::Blend { a, b, weight } => {
                    out.push(weight);
                    walk(a, out);
                    walk(b, out);
                }
                _ => {}
            }
        }
        let mut fields = Vec::new();
        if self.model.output == PhasorOutput::Profiled {
            walk(&self.model.profile, &mut fields);
            if minified {
                fields.push(&self.model.frequency);
            }
        }
        fields.retain(|f| matches!(f, Field::Image { .. }));
        fields
    }

    /// Adds every impulse of `rows` to the pixels of one output row, at this evaluator's SIMD
    /// level ([`sum_row_lanes`]).
    fn sum_row(
        &self,
        rows: &[CellRow],
        at: &RowAt,
        lanes: &Lanes<'_>,
        re: &mut [f32],
        im: &mut [f32],
    ) {
        let three_d = self.kernels.three_d();
        #[cfg(target_arch = "x86_64")]
        match (self.simd, three_d) {
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
            (Simd::Avx512, false) => unsafe { sum_row_avx512::<false>(rows, at, lanes, re, im) },
            #[allow(unsafe_code)]
            // SAFETY: as above.
            (Simd::Avx512, true) => unsafe { sum_row_avx512::<true>(rows, at, lanes, re, im) },
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
            (Simd::Avx2, false) => unsafe { sum_row_avx2::<false>(rows, at, lanes, re, im) },
            #[allow(unsafe_code)]
            // SAFETY: as above.
            (Simd::Avx2, true) => unsafe { sum_row_avx2::<true>(rows, at, lanes, re, im) },
            (Simd::Portable, false) => sum_row_lanes::<LANES, false>(rows, at, lanes, re, im),
            (Simd::Portable, true) => sum_row_lanes::<LANES, true>(rows, at, lanes, re, im),
        }
        #[cfg(not(target_arch = "x86_64"))]
        if three_d {
            sum_row_lanes::<LANES, true>(rows, at, lanes, re, im);
        } else {
            sum_row_lanes::<LANES, false>(rows, at, lanes, re, im);
        }
    }

    /// [`eval_rows`](Self::eval_rows) pixel by pixel: each pixel sums its neighbouring cells'
    /// impulses alone ([`sum_at`]). The definition the row kernel is tested against, bit for
    /// bit, and the speed it is measured against.
    #[doc(hidden)]
    pub fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let Some(columns) = self.minified_or(window, first, out, |w, f, o| {
            self.eval_rows_reference(w, f, o);
        }) else {
            return;
        };
        let g = &self.kernels;
        let z = if g.three_d() {
            g.locate(self.z)
        } else {
            Some((0, 0.0))
        };
        let footprint = window.footprint();
        let mut rows = Vec::new();
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let y = window.y(first + r);
            let (Some(((c0, _), (c1, _))), Some((cj, uy)), Some((ck, uz))) =
                (columns, g.locate(y), z)
            else {
                line.fill(0.0);
                continue;
            };
            self.update_rows(&mut rows, cj, ck, c0 - 1, c1 + 1);
            for (i, v) in line.iter_mut().enumerate() {
                let x = window.x(i);
                let Some((ci, ux)) = g.locate(x) else {
                    *v = 0.0;
                    continue;
                };
                let (re, im) = sum_at(&rows, ci, cj, ck, [ux, uy, uz]);
                *v = self.output(re, im, &mut |f: &Field| f.at(x, y, self.z), footprint);
            }
        }
    }

    /// The noise at `(x, y)` (and this evaluator's `z`): the same bits as any render.
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let w = Window::new(1, 1).at([x, y], 1.0);
        let mut out = [0.0f32];
        self.eval_rows(&w, 0, &mut out);
        out[0]
    }

    /// The written value at a pixel whose fields `read` gives (`Field::at` there, f64);
    /// `footprint`: a minified render's, which filters the profile's harmonics at `u = F(p)·s`
    /// ([`spectex_model::filter`]'s `filtered_*`).
    fn output(
        &self,
        re: f32,
        im: f32,
        read: &mut dyn FnMut(&Field) -> f64,
        footprint: Option<f64>,
    ) -> f32 {
        let v = match self.model.output {
            PhasorOutput::Intensity => (re * re + im * im).sqrt(),
            PhasorOutput::Gabor => im,
            PhasorOutput::Phase => atan2_turns(im, re),
            PhasorOutput::Profiled => {
                let u = footprint.map(|s| (read(&self.model.frequency) * s) as f32);
                profile(
                    &self.model.profile,
                    re,
                    im,
                    read,
                    u,
                    &mut self.series.iter(),
                )
            }
        };
        self.model.mean + self.model.amplitude * v
    }
}

/// `Σ` of the module doc at the point of cell `(ci, cj, ck)`, offset `u`.
fn sum_at(rows: &[CellRow], ci: i32, cj: i32, ck: i32, u: [f32; 3]) -> (f32, f32) {
    let (mut re, mut im) = (0.0f32, 0.0f32);
    for row in rows {
        let sy = row.j - cj;
        let sz = row.k - ck;
        let dy = u[1] - sy as f32;
        let dz = u[2] - sz as f32;
        for sx in -1..=1 {
            let Some(column) = usize::try_from(ci + sx - row.i0)
                .ok()
                .and_then(|c| row.columns.get(c))
            else {
                continue;
            };
            let dxs = u[0] - sx as f32;
            for imp in column {
                let d = [dxs - imp.o[0], dy - imp.o[1], dz - imp.o[2]];
                let d2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * imp.sharp;
                if d2 < 1.0 {
                    let g = exp_poly(NEG_LN_20 * d2);
                    let t = imp.f[0] * d[0] + imp.f[1] * d[1] + imp.f[2] * d[2] + imp.psi;
                    re += g * cos_turns(t);
                    im += g * sin_turns(t);
                }
            }
        }
    }
    (re, im)
}

/// The output row's cell and offsets along y and z.
struct RowAt {
    cj: i32,
    ck: i32,
    uy: f32,
    uz: f32,
}

/// The pixels of a row as the lanes see them: each one's cell and offset along x (padded by a
/// group of lanes of scratch), and the window that places them.
struct Lanes<'a> {
    window: &'a Window,
    /// Cell side, pixels.
    side: f64,
    cells: &'a [i32],
    offsets: &'a [f32],
}

impl Lanes<'_> {
    /// The pixels `lo..=hi` of the row that may lie within `half` cell units of `centre` (cell
    /// units): a superset (by [`CHORD_MARGIN`] and a pixel on each side) of those an impulse
    /// there reaches, or `None`. Every pixel when the window's scale gives no order.
    fn chord(&self, centre: f64, half: f64) -> Option<(usize, usize)> {
        let w = self.window;
        let last = (self.cells.len() - WIDE_LANES - 1) as f64;
        if !(w.scale > 0.0 && w.scale.is_finite()) {
            return Some((0, last as usize));
        }
        let reach = (half + CHORD_MARGIN) * self.side;
        let centre = centre * self.side;
        let index = |x: f64| (x - w.offset[0]) / w.scale - w.x0 as f64;
        let lo = (index(centre - reach).floor() - 1.0).max(0.0);
        let hi = (index(centre + reach).ceil() + 1.0).min(last);
        // NaN (never for a valid window) falls through the comparison to `None`.
        (lo <= hi).then_some((lo as usize, hi as usize))
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn sum_row_avx2<const THREE_D: bool>(
    rows: &[CellRow],
    at: &RowAt,
    lanes: &Lanes<'_>,
    re: &mut [f32],
    im: &mut [f32],
) {
    sum_row_lanes::<LANES, THREE_D>(rows, at, lanes, re, im);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn sum_row_avx512<const THREE_D: bool>(
    rows: &[CellRow],
    at: &RowAt,
    lanes: &Lanes<'_>,
    re: &mut [f32],
    im: &mut [f32],
) {
    sum_row_lanes::<WIDE_LANES, THREE_D>(rows, at, lanes, re, im);
}

/// Adds every impulse of `rows` (in the contract's order) to `re` and `im` of the pixels of its
/// chord, `L` pixels at a time; each lane computes exactly what [`sum_at`] computes for its
/// pixel. `inline(always)` so that each SIMD wrapper compiles its own copy of the same
/// arithmetic (plain `*`, `+`, selects and integer steps). `THREE_D`: a 2D model's `d_z` and
/// `f_z` are exactly 0, so the terms they add (an exact `+0`) are left out.
#[inline(always)]
fn sum_row_lanes<const L: usize, const THREE_D: bool>(
    rows: &[CellRow],
    at: &RowAt,
    lanes: &Lanes<'_>,
    re: &mut [f32],
    im: &mut [f32],
) {
    for row in rows {
        let sy = row.j - at.cj;
        let sz = row.k - at.ck;
        let dy = at.uy - sy as f32;
        let dz = at.uz - sz as f32;
        for (col, column) in row.columns.iter().enumerate() {
            let c = row.i0 + col as i32;
            for imp in column {
                let d1 = dy - imp.o[1];
                let d3 = dz - imp.o[2];
                let (a, b) = (d1 * d1, d3 * d3);
                // `s·|d|²` is at least this on the whole row (rounding is monotonic).
                let across = if THREE_D { a + b } else { a };
                if across * imp.sharp >= 1.0 {
                    continue;
                }
                let half = (1.0 / f64::from(imp.sharp) - f64::from(across))
                    .max(0.0)
                    .sqrt();
                let Some((lo, hi)) = lanes.chord(f64::from(c) + f64::from(imp.o[0]), half) else {
                    continue;
                };
                let (ty, tz) = (imp.f[1] * d1, imp.f[2] * d3);
                let mut start = lo;
                while start <= hi {
                    let cells: &[i32; L] = lanes.cells[start..start + L]
                        .try_into()
                        .unwrap_or_else(|_| unreachable!("the lane slices are L long"));
                    let offsets: &[f32; L] = lanes.offsets[start..start + L]
                        .try_into()
                        .unwrap_or_else(|_| unreachable!("the lane slices are L long"));
                    let mut add_re = [0.0f32; L];
                    let mut add_im = [0.0f32; L];
                    for l in 0..L {
                        let sx = c.wrapping_sub(cells[l]);
                        let neighbour = (-1..=1).contains(&sx);
                        let d0 = (offsets[l] - sx as f32) - imp.o[0];
                        let mut d2 = d0 * d0 + a;
                        if THREE_D {
                            d2 += b;
                        }
                        d2 *= imp.sharp;
                        let g = exp_poly(NEG_LN_20 * d2);
                        let mut t = imp.f[0] * d0 + ty;
                        if THREE_D {
                            t += tz;
                        }
                        t += imp.psi;
                        let on = neighbour && d2 < 1.0;
                        add_re[l] = if on { g * cos_turns(t) } else { 0.0 };
                        add_im[l] = if on { g * sin_turns(t) } else { 0.0 };
                    }
                    for (r, a) in re[start..start + L].iter_mut().zip(add_re) {
                        *r += a;
                    }
                    for (i, a) in im[start..start + L].iter_mut().zip(add_im) {
                        *i += a;
                    }
                    start += L;
                }
            }
        }
    }
}

/// The phase `atan2(im, re)` in turns, in `[0, 1)`.
fn phase01(re: f32, im: f32) -> f32 {
    let phase = atan2_turns(im, re);
    let t = if phase < 0.0 { phase + 1.0 } else { phase };
    if t >= 1.0 { 0.0 } else { t }
}

/// Appends the Fourier series of `shape`'s `Samples` leaves to `out`, depth first (the order
/// [`profile`] reads them in).
fn samples_series(shape: &Profile, out: &mut Vec<Vec<f32>>) {
    match shape {
        Profile::Samples { values } => out.push(spectex_model::filter::samples_series(values)),
        Profile::Blend { a, b, .. } => {
            samples_series(a, out);
            samples_series(b, out);
        }
        Profile::Sine
        | Profile::Square { .. }
        | Profile::Triangle
        | Profile::Sawtooth
        | Profile::Harmonics { .. } => {}
    }
}

/// The profile of the phase at a pixel whose fields `read` gives. The phase is only computed by
/// the profiles that read it (the sine is `im / I` directly). `u`: the local frequency times the footprint of a
/// minified render, which filters every profile's harmonics (`spectex_model::filter`);
/// `series`: the `Samples` leaves' Fourier series, depth first ([`samples_series`]).
fn profile(
    shape: &Profile,
    re: f32,
    im: f32,
    read: &mut dyn FnMut(&Field) -> f64,
    u: Option<f32>,
    series: &mut std::slice::Iter<'_, Vec<f32>>,
) -> f32 {
    use spectex_model::filter;
    match shape {
        Profile::Sine => {
            let i = (re * re + im * im).sqrt();
            let sine = if i > 0.0 { im / i } else { 0.0 };
            u.map_or(sine, |u| filter::filtered_sine(sine, u))
        }
        Profile::Square { duty } => {
            let d = read(duty).clamp(0.0, 1.0) as f32;
            match u {
                Some(u) => filter::filtered_square(phase01(re, im), d, u),
                None if phase01(re, im) < d => 1.0,
                None => 0.0,
            }
        }
        Profile::Triangle => match u {
            Some(u) => filter::filtered_triangle(phase01(re, im), u),
            None => {
                let mut s = phase01(re, im) + 0.25;
                if s >= 1.0 {
                    s -= 1.0;
                }
                1.0 - 4.0 * (s - 0.5).abs()
            }
        },
        Profile::Sawtooth => match u {
            Some(u) => filter::filtered_sawtooth(phase01(re, im), u),
            None => 2.0 * phase01(re, im) - 1.0,
        },
        Profile::Samples { values } => {
            let coefficients = series.next();
            match (u, coefficients) {
                (Some(u), Some(c)) => filter::filtered_samples(c, phase01(re, im), u),
                _ => {
                    let n = values.len();
                    let pos = phase01(re, im) * n as f32;
                    let i = (pos as usize).min(n - 1);
                    let frac = pos - i as f32;
                    values[i] * (1.0 - frac) + values[(i + 1) % n] * frac
                }
            }
        }
        Profile::Harmonics { terms } => {
            let t = phase01(re, im);
            terms
                .iter()
                .map(|h| {
                    let shift = (f64::from(h.phase) / std::f64::consts::TAU) as f32;
                    let term = h.weight * sin_turns(h.k as f32 * t + shift);
                    match u {
                        Some(u) => filter::response_f32(h.k as f32 * u) * term,
                        None => term,
                    }
                })
                .sum()
        }
        Profile::Blend { a, b, weight } => {
            let s = read(weight).clamp(0.0, 1.0) as f32;
            let va = profile(a, re, im, read, u, series);
            let vb = profile(b, re, im, read, u, series);
            (1.0 - s) * va + s * vb
        }
    }
}

impl crate::CpuKind for PhasorNoise {
    /// The bench case: the `spectex phasor` defaults (2D, sine profile).
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Built(spectex_model::Model::Phasor(
            PhasorNoise::builder()
                .build()
                .expect("the builder's defaults are valid"),
        ))
    }

    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(PhasorEvaluator::new(self, z)))
    }

    fn cpu_kernel_periodic(
        &self,
        z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(PhasorEvaluator::new_periodic(self, z, period)?))
    }
}

impl crate::RowKernel for PhasorEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.kernels_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        PhasorEvaluator::eval_rows(self, window, first, out);
    }

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        PhasorEvaluator::eval_rows_reference(self, window, first, out);
    }
}
