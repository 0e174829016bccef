//! The classic pointwise noises (gradient, simplex, value, Kensler, Worley) and their fractal sums
//! on the CPU; the definitions and the randomness contract are in [`spectex_model::classic`].
//! Kensler noise's 4×4 (4×4×4) stencil runs one lane at a time (`kensler`: no per-row tables).
//!
//! Every pixel is independent: a row is evaluated `L` consecutive pixels at a time (8 lanes, or
//! 16 or 32 with AVX-512: `ClassicEvaluator::avx512_lanes`; 3D gradient, value and simplex
//! noise through the hand-written kernels of `avx512`), the basis and dimension as constants of
//! the row loop, every octave of a group of lanes before the next group, with the lattice
//! hashes computed in the lanes (wrapping `u32` arithmetic vectorises). Positions are built per
//! lane in f64 exactly as [`Window::x`] builds them, divided by the octave's cell side and split
//! into an `i32` cell and an f32 offset by the round-to-nearest magic constant (two exact IEEE
//! operations, no `floor` library call, so the portable build vectorises too). All f32 arithmetic
//! is plain `*`, `+`, `sqrt`, selects and sign-bit flips, so the AVX2, AVX-512 and portable copies
//! of the row give the same bits, and any tiling of a window gives the same bits (a pixel never
//! depends on its neighbours).
//!
//! What depends only on a lattice column of a row is computed once per row and octave, in
//! tables the lanes read by column (a register permute with AVX2 and AVX-512): gradient and value
//! noise's corners (the gradient's dot product folded into a mask, a sign and a constant), simplex
//! noise's keys of its skewed rows (planes), Worley noise's feature points for a fixed count. A
//! row of cells 32 pixels wide then hashes each cell once instead of once per pixel; the tables
//! hold the very integers and floats the lanes would compute, so the bits do not change, and
//! [`ClassicEvaluator::eval_rows_reference`] keeps the per-pixel path they are tested against.
//! Gradient and value octaves with cells under a pixel (a table would be longer than the row),
//! simplex and Worley octaves with cells under 2 pixels, Poisson counts and batches of points
//! hash in the lanes. Lane code is written as one simple loop per step over arrays of `L`
//! lanes, so that the compiler vectorises each step at the full width.
//!
//! A row's tables live in buffers this thread reuses from row to row (a table of one-pixel
//! cells is as long as the row). A bench-only relaxed evaluator (`ClassicEvaluator::set_relaxed`,
//! only with the `relaxed` feature, which no model selects) splits positions in f32 and fuses
//! multiply-adds, to measure what those two guarantees cost.
//!
//! A minified render (a window with a [`footprint`](Window::footprint)) fades each octave as
//! [`spectex_model::filter::classic_fade`] says (turbulence and ridged toward their expected
//! values, fBm of Worley distances toward their mean) and skips the basis of the octaves faded
//! to 0.
//!
//! Worley noise evaluates the 3×3 (3×3×3) cells around the point in the lanes and keeps the
//! four smallest distances with a min/max insertion network; a lane whose needed `F_n` exceeds
//! the distance to the unsearched cells is redone by `worley_search`, which searches ring after
//! ring with the same arithmetic (the four smallest of a set do not depend on the visiting order,
//! so both paths agree bit for bit wherever the 3×3 search suffices).
//!
//! This module holds the evaluator, its public API and the SIMD dispatch; the rest is split by
//! seam: `lanes` (lane widths, cell splits, `Fetch` by index or permute), `cache` (per-thread
//! buffers and kept hashes), `tables` (the per-row lattice tables), `lattice` (gradient, value
//! and Kensler noise), `simplex`, `worley`, `fractal` (the octave loop and fractal sums),
//! `relaxed` (the bench-only path) and `avx512` (the hand-written kernels).
//!
//! ```
//! use spectex_cpu::classic::ClassicEvaluator;
//! use spectex_model::classic::{Basis, ClassicNoise};
//!
//! let model = ClassicNoise {
//!     seed: 1,
//!     dimensions: 2,
//!     cell_size: 16.0,
//!     basis: Basis::Gradient,
//!     fractal: None,
//!     amplitude: 1.0,
//!     mean: 0.0,
//! };
//! model.validate()?;
//! let eval = ClassicEvaluator::new(&model, 0.0);
//! // Gradient noise vanishes at lattice points.
//! assert_eq!(eval.eval(48.0, -16.0), 0.0);
//! # Ok::<(), spectex_model::ModelError>(())
//! ```

use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, FractalKind, Metric, WORLEY_MAX_RING,
};
use spectex_model::filter::{BasisStatistics, OctaveFade};
use spectex_model::random::{cell_hash, layer_key, row_key};
use spectex_model::{Period, Window};

use crate::lrp::Simd;

/// The basis as a const parameter of the row loop (`B`), beside its dimension (`D3`): each
/// basis and dimension gets its own loop, so that LLVM allocates its registers for that basis
/// alone (one loop holding every basis kept the lane arrays of each on the stack, and a kernel
/// added for one basis slowed the others).
const GRADIENT: u8 = 0;
const VALUE: u8 = 1;
const SIMPLEX: u8 = 2;
const KENSLER: u8 = 3;
const WORLEY: u8 = 4;

/// `$self.$method::<$g…, B, D3>($arg…)` with the evaluator's basis and dimension as the
/// constants `B` and `D3`: `$g2` are the leading generic arguments of 2D bases, `$wide3` those
/// of 3D gradient, value and simplex noise (the AVX-512 row's two-register kernels), `$g3`
/// those of the other 3D bases; one list `$g` serves all three.
macro_rules! by_basis {
    ($self:ident.$method:ident, [$($g:tt),*], ($($arg:expr),*)) => {
        by_basis!($self.$method, [$($g),*], [$($g),*], [$($g),*], ($($arg),*))
    };
    ($self:ident.$method:ident, [$($g2:tt),*], [$($g3:tt),*], [$($wide3:tt),*], ($($arg:expr),*)) => {
        match (&$self.basis, $self.three_d) {
            (Basis::Gradient, false) => $self.$method::<$($g2,)* GRADIENT, false>($($arg),*),
            (Basis::Gradient, true) => $self.$method::<$($wide3,)* GRADIENT, true>($($arg),*),
            (Basis::Value, false) => $self.$method::<$($g2,)* VALUE, false>($($arg),*),
            (Basis::Value, true) => $self.$method::<$($wide3,)* VALUE, true>($($arg),*),
            (Basis::Simplex, false) => $self.$method::<$($g2,)* SIMPLEX, false>($($arg),*),
            (Basis::Simplex, true) => $self.$method::<$($wide3,)* SIMPLEX, true>($($arg),*),
            (Basis::Kensler, false) => $self.$method::<$($g2,)* KENSLER, false>($($arg),*),
            (Basis::Kensler, true) => $self.$method::<$($g3,)* KENSLER, true>($($arg),*),
            (Basis::Worley(_), false) => $self.$method::<$($g2,)* WORLEY, false>($($arg),*),
            (Basis::Worley(_), true) => $self.$method::<$($g3,)* WORLEY, true>($($arg),*),
        }
    };
}

#[cfg(target_arch = "x86_64")]
mod avx512;
mod cache;
mod fractal;
mod lanes;
mod lattice;
mod relaxed;
mod simplex;
mod tables;
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub use tables::tests as table_tests;
mod worley;

use fractal::{Octave, RowOctave};
use lanes::{Indexed, LANES, WIDE_LANES, WIDER_LANES, locate};
#[cfg(target_arch = "x86_64")]
use lanes::{Permute8, Permute16, Permute32};
use worley::WorleyParams;

/// A classic noise ready to evaluate.
#[derive(Debug, Clone)]
pub struct ClassicEvaluator {
    /// The model, for the octave weights of a footprint.
    model: ClassicNoise,
    three_d: bool,
    basis: Basis,
    worley: Option<WorleyParams>,
    kind: Option<FractalKind>,
    octaves: Vec<Octave>,
    amplitude: f32,
    mean: f32,
    simd: Simd,
    /// Bench only ([`set_relaxed`](Self::set_relaxed), the `relaxed` feature): the f32 cell
    /// split and FMA.
    #[cfg(feature = "relaxed")]
    relaxed: bool,
    /// The basis's statistics for a minified render's fade, measured on first use (a Worley
    /// basis's take milliseconds).
    statistics: std::sync::OnceLock<BasisStatistics>,
}

impl ClassicEvaluator {
    /// Prepares a validated `model` on the plane `z` (ignored in 2D).
    #[must_use]
    pub fn new(model: &ClassicNoise, z: f64) -> Self {
        Self::prepare(model, z, None)
    }

    /// Prepares a validated `model` that accepts `period` ([`ClassicNoise::check_period`]:
    /// every octave's cell divides it) made periodic: each octave's lattice coordinates are
    /// wrapped modulo its cells per period where they enter the hash.
    #[must_use]
    pub fn new_periodic(model: &ClassicNoise, z: f64, period: Period) -> Self {
        Self::prepare(model, z, Some(period))
    }

    fn prepare(model: &ClassicNoise, z: f64, period: Option<Period>) -> Self {
        let octaves = (0..model.octaves())
            .map(|o| {
                let side = model.octave_cell(o);
                let pz = z / side;
                let (kz, uz) = locate(pz);
                let zkeys = [-1, 0, 1]
                    .map(|d| layer_key(o, cell_hash(kz.wrapping_add(d), 0, o, model.seed)));
                let inv = 1.0 / side;
                let mantissa = (1u64 << 52) - 1;
                let exact = side.to_bits() & mantissa == 0
                    && inv.to_bits() & mantissa == 0
                    && side.is_normal()
                    && inv.is_normal();
                Octave {
                    side,
                    inv_side: exact.then_some(inv),
                    cells: period.map_or([0, 0], |p| p.cells(side).map(|n| n as i32)),
                    weight: model.octave_weight(o),
                    layer: o,
                    key2: layer_key(o, model.seed),
                    key0: row_key(0, layer_key(o, model.seed)),
                    pz,
                    kz,
                    uz,
                    zkeys,
                    kensler_z: if model.dimensions == 3 {
                        [-1, 0, 1, 2].map(|d| cell_hash(kz.wrapping_add(d), 2, o, model.seed))
                    } else {
                        [0; 4]
                    },
                }
            })
            .collect();
        let worley = match &model.basis {
            Basis::Worley(w) => {
                let cap = (WORLEY_MAX_RING + 1) as f32;
                Some(WorleyParams {
                    metric: w.metric,
                    coefficients: w.coefficients,
                    fixed: match w.points {
                        FeaturePoints::Fixed(n) => Some(n),
                        FeaturePoints::Poisson(_) => None,
                    },
                    cdf: w.points.poisson_cdf().unwrap_or([0.0; 16]),
                    needed: w.needed() - 1,
                    cap: if w.metric == Metric::Euclidean {
                        cap * cap
                    } else {
                        cap
                    },
                })
            }
            _ => None,
        };
        Self {
            model: model.clone(),
            three_d: model.dimensions == 3,
            basis: model.basis.clone(),
            worley,
            kind: model.fractal.as_ref().map(|f| f.kind),
            octaves,
            amplitude: model.amplitude,
            mean: model.mean,
            statistics: std::sync::OnceLock::new(),
            simd: Simd::detect(),
            #[cfg(feature = "relaxed")]
            relaxed: false,
        }
    }

    /// Basis evaluations per pixel (octaves, times the cells searched for Worley), for reports.
    #[must_use]
    pub fn evaluations_per_pixel(&self) -> f64 {
        let per = match (&self.basis, self.three_d) {
            (Basis::Worley(_), false) => 9.0,
            (Basis::Worley(_), true) => 27.0,
            // 16 (64) corners against the gradient basis's 4 (8).
            (Basis::Kensler, false) => 4.0,
            (Basis::Kensler, true) => 8.0,
            _ => 1.0,
        };
        per * self.octaves.len() as f64
    }

    /// Pixels the AVX-512 row evaluates together: 32 (two registers, two independent chains)
    /// for 2D noise and for the hand-written 3D kernels (gradient, value, simplex: `avx512`),
    /// 16 for 3D Kensler and Worley noise, whose larger lane state spilled at 32 (measured on
    /// the grid bench: 2D Perlin 455 -> 515, simplex 248 -> 297 Mpix/s; 3D cellular 60 -> 50 at
    /// 32). Lanes are independent, so the bits are the same at either width.
    fn avx512_lanes(&self) -> usize {
        if self.three_d && matches!(self.basis, Basis::Kensler | Basis::Worley(_)) {
            WIDE_LANES
        } else {
            WIDER_LANES
        }
    }

    /// Forces the portable path (`false`) or the widest level the CPU has (`true`, the
    /// default); for tests comparing the code paths. Returns the level's lane count.
    #[doc(hidden)]
    pub fn set_simd(&mut self, enabled: bool) -> usize {
        self.simd = if enabled {
            Simd::detect()
        } else {
            Simd::Portable
        };
        if self.simd == Simd::Avx512 {
            self.avx512_lanes()
        } else {
            LANES
        }
    }

    /// Forces AVX2 when the CPU has it (for tests comparing the code paths).
    #[doc(hidden)]
    pub fn set_avx2(&mut self) -> bool {
        if Simd::detect() == Simd::Portable {
            return false;
        }
        self.simd = Simd::Avx2;
        true
    }

    /// Evaluates rows `first..` of `window` into `out` (a whole number of rows).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval_rows_with(window, first, out, true);
    }

    /// [`eval_rows`](Self::eval_rows) with every lattice hash computed in the lanes, pixel by
    /// pixel: the path the per-row tables of the fast path are tested and benched against.
    pub fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval_rows_with(window, first, out, false);
    }

    /// `columns`: read lattice hashes from per-row [`Columns`] tables where the basis allows.
    fn eval_rows_with(&self, window: &Window, first: usize, out: &mut [f32], columns: bool) {
        if window.width == 0 {
            return;
        }
        let fade = self.fade(window);
        for (r, line) in out.chunks_exact_mut(window.width).enumerate() {
            self.eval_row_faded(window, first + r, line, fade.as_ref(), columns);
        }
    }

    /// How a minified render takes each octave ([`spectex_model::filter::classic_fade`]), or
    /// `None`: unfiltered.
    fn fade(&self, window: &Window) -> Option<OctaveFade> {
        let side = window.footprint()?;
        let statistics = self.statistics.get_or_init(|| {
            spectex_model::filter::basis_statistics(&self.model.basis, self.model.dimensions)
        });
        Some(spectex_model::filter::classic_fade(
            &self.model,
            side,
            statistics,
        ))
    }

    /// Evaluates row `row` of `window` into `out` (`window.width` values).
    pub fn eval_row(&self, window: &Window, row: usize, out: &mut [f32]) {
        self.eval_row_faded(window, row, out, self.fade(window).as_ref(), true);
    }

    /// [`eval_row`](Self::eval_row) with the octave fade of a minified render (`None`:
    /// unfiltered).
    /// `columns`: read lattice hashes from per-row [`Columns`] tables where the basis allows.
    fn eval_row_faded(
        &self,
        window: &Window,
        row: usize,
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        let y = window.y(row);
        let rows: Vec<RowOctave> = self.octaves.iter().map(|o| self.row_octave(o, y)).collect();
        #[cfg(all(target_arch = "x86_64", feature = "relaxed"))]
        if self.relaxed {
            #[allow(unsafe_code)]
            // SAFETY: `relaxed` is set only when the CPU reports AVX2 and FMA at run time, and
            // `Simd::Avx512` only when it reports AVX-512F.
            unsafe {
                if self.simd == Simd::Avx512 {
                    self.row_relaxed_avx512(window, &rows, out, w, columns);
                } else {
                    self.row_relaxed(window, &rows, out, w, columns);
                }
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
            Simd::Avx512 => unsafe { self.row_avx512(window, &rows, out, w, columns) },
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
            Simd::Avx2 => unsafe { self.row_avx2(window, &rows, out, w, columns) },
            Simd::Portable => by_basis!(
                self.row,
                [LANES, Indexed, false],
                (window, &rows, out, w, columns)
            ),
        }
        #[cfg(not(target_arch = "x86_64"))]
        by_basis!(
            self.row,
            [LANES, Indexed, false],
            (window, &rows, out, w, columns)
        );
    }

    /// The noise at one position (the same bits as any render).
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let w = Window::new(1, 1).at([x, y], 1.0);
        let mut out = [0.0f32];
        self.eval_row(&w, 0, &mut out);
        out[0]
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn row_avx2(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        by_basis!(
            self.row,
            [LANES, Permute8, false],
            (window, rows, out, w, columns)
        );
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn row_avx512(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        self.row_wide::<false>(window, rows, out, w, columns);
    }

    /// The AVX-512 row at [`avx512_lanes`](Self::avx512_lanes)' width; `inline(always)` into
    /// each AVX-512 wrapper.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn row_wide<const RELAXED: bool>(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        // The widths of `avx512_lanes`.
        by_basis!(
            self.row,
            [WIDER_LANES, Permute32, RELAXED],
            [WIDE_LANES, Permute16, RELAXED],
            [WIDER_LANES, Permute32, RELAXED],
            (window, rows, out, w, columns)
        );
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn points_avx2(&self, points: &[[f64; 2]], out: &mut [f32]) {
        self.points::<LANES>(points, out);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn points_avx512(&self, points: &[[f64; 2]], out: &mut [f32]) {
        self.points::<WIDE_LANES>(points, out);
    }

    /// Evaluates the noise at each of `points` (pixels) into `out` (one value per point), in
    /// the lanes: the same bits as a one-pixel window at each point.
    pub fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let out = &mut out[..points.len()];
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
            Simd::Avx512 => unsafe { self.points_avx512(points, out) },
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
            Simd::Avx2 => unsafe { self.points_avx2(points, out) },
            Simd::Portable => self.points::<LANES>(points, out),
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.points::<LANES>(points, out);
    }
}

impl crate::CpuKind for ClassicNoise {
    /// The bench case: fBm of Perlin noise with the builder's defaults.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Built(spectex_model::Model::Classic(
            ClassicNoise::fbm()
                .build()
                .expect("the builder's defaults are valid"),
        ))
    }

    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(ClassicEvaluator::new(self, z)))
    }

    fn cpu_kernel_periodic(
        &self,
        z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(ClassicEvaluator::new_periodic(self, z, period)))
    }
}

impl crate::RowKernel for ClassicEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.evaluations_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        ClassicEvaluator::eval_rows(self, window, first, out);
    }

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        ClassicEvaluator::eval_rows_reference(self, window, first, out);
    }

    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        ClassicEvaluator::eval_points(self, points, out);
    }
}
