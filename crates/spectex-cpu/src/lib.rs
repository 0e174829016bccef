//! The CPU reference evaluator: evaluates `spectex-model` models at any continuous position,
//! parallel over rows, bit-identical for any thread count and any tiling of the window.
//!
//! Depends on `spectex-model` only, so a game can evaluate a fitted model with these two crates.
//!
//! ```
//! use spectex_model::{LrpNoise, Model, Stratum};
//! use spectex_cpu::{Evaluator, Window};
//!
//! let model = Model::Lrp(LrpNoise {
//!     seed: 1,
//!     mean: 0.5,
//!     strata: vec![Stratum {
//!         window_width: 16.0,
//!         amplitude: 0.1,
//!         sub_strata: vec![vec![[0.1, 0.0], [0.0, 0.1]]; 4],
//!     }],
//! });
//! let eval = Evaluator::new(&model).unwrap();
//! let window = Window::new(64, 32).at([1.0e7, 1.0e7], 0.5);
//! let pixels = eval.render(&window).unwrap();
//! assert_eq!(pixels.len(), 64 * 32);
//! // Tiles are invisible: a tile evaluates exactly the same values.
//! let tile = eval.render(&window.tile(8, 4, 16, 16)).unwrap();
//! assert_eq!(tile[0].to_bits(), pixels[4 * 64 + 8].to_bits());
//! ```

/// The f32 functions both evaluators share, defined once in `spectex-model`.
pub use spectex_model::math;
mod periodic;

// One module per kind (`<kind>.rs`: its `CpuKind` and `RowKernel`), declared from the one list
// of kinds.
spectex_model::for_each_kind!(pub mod);

/// The unit tests' bodies, one module per source module (`pub mod tests` behind this feature),
/// run by `tests/it/unit.rs`: a unit-test harness would compile the crate a second time.
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod unit_tests {
    pub use crate::classic::table_tests as classic_tables;
    pub use crate::combine::tests as combine;
    pub use crate::gabor::tests as gabor;
    pub use crate::islamic::tests as islamic;
    pub use crate::texton::tests as texton;
    pub use crate::tiling::tests as tiling;
    pub use crate::voronoi::tests as voronoi;
}

use rayon::prelude::*;
use spectex_model::{Model, ModelError, ModelKind, Period};

pub use classic::ClassicEvaluator;
pub use gabor::GaborEvaluator;
pub use lrp::LrpEvaluator;
pub use phasor::PhasorEvaluator;
/// The window type is `spectex-model`'s, shared with the GPU evaluator.
pub use spectex_model::{Filter, MAX_POSITION, MAX_WINDOW_PIXELS, MAX_WINDOW_SIDE, Window};
pub use texture::TextureEvaluator;
pub use warp::WarpEvaluator;
pub use wavelet::WaveletEvaluator;

/// Rows evaluated together by one task: the LRP evaluator draws each lattice row once per band
/// instead of once per output row. Values do not depend on it.
const BAND_ROWS: usize = 16;

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CpuError {
    /// The model failed validation.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A window parameter is out of range.
    #[error("window {parameter} = {value} is outside its valid range {range}")]
    Window {
        /// Which parameter.
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
    /// The output buffer has the wrong length.
    #[error("output buffer has {len} values; the window needs {needed}")]
    Buffer {
        /// Length given.
        len: usize,
        /// Length needed.
        needed: usize,
    },
}

impl From<spectex_model::WindowError> for CpuError {
    fn from(e: spectex_model::WindowError) -> Self {
        Self::Window {
            parameter: e.parameter,
            value: e.value,
            range: e.range,
        }
    }
}

/// Cell (or lattice) columns per pixel beyond which a row is *minified*: a kernel that draws
/// every column between a row's ends would do work and allocate memory growing with the row's
/// extent rather than its pixels (a 64-pixel row at scale 1e6 spans 10⁸ columns), while a
/// pixel alone needs only a few columns around its own.
const SPARSE_COLUMNS_PER_PIXEL: u64 = 4;

/// Whether a row of `width` pixels whose cells span `columns` columns (plus `reach` columns a
/// kernel reads beyond each end) is minified (see [`SPARSE_COLUMNS_PER_PIXEL`]).
pub(crate) fn is_minified(columns: u64, reach: u64, width: usize) -> bool {
    columns > SPARSE_COLUMNS_PER_PIXEL * width as u64 + 8 + 2 * reach
}

/// Evaluates rows `first..` of `window` into `out` (one value per pixel) pixel by pixel, each
/// through `eval_rows` on its one-pixel window: the same bits as a render of the whole rows
/// (tiles are invisible), with only each pixel's own cells drawn. The minified-row path of
/// the kernels that share cell columns along a row.
pub(crate) fn eval_pixel_by_pixel(
    window: &Window,
    first: usize,
    out: &mut [f32],
    eval_rows: impl Fn(&Window, usize, &mut [f32]),
) {
    for (r, line) in out.chunks_exact_mut(window.width).enumerate() {
        for (i, v) in line.iter_mut().enumerate() {
            eval_rows(&window.tile(i, first + r, 1, 1), 0, std::slice::from_mut(v));
        }
    }
}

/// The minified-row prologue the kernels that share cell columns along a row have in common:
/// when a row whose cells span `columns` columns (plus `reach` read beyond each end) is
/// minified ([`is_minified`]), evaluates rows `first..` of `window` pixel by pixel through
/// `eval_rows` ([`eval_pixel_by_pixel`]) and returns `true`; otherwise leaves `out` alone and
/// returns `false`, and the caller runs its row kernel.
pub(crate) fn eval_if_minified(
    window: &Window,
    first: usize,
    out: &mut [f32],
    (columns, reach): (u64, u64),
    eval_rows: impl Fn(&Window, usize, &mut [f32]),
) -> bool {
    let minified = is_minified(columns, reach, window.width);
    if minified {
        eval_pixel_by_pixel(window, first, out, eval_rows);
    }
    minified
}

/// The one-pixel window at `p`, through which a point is evaluated ([`Evaluator::eval_point`]):
/// its pixel lies at `p[0] + 0.0·1.0`, `p[1] + 0.0·1.0` (which is `p` but for the sign of a
/// zero), the positions a batch of points must reproduce bit for bit.
#[must_use]
pub fn point_window(p: [f64; 2]) -> Window {
    Window::new(1, 1).at(p, 1.0)
}

/// A model kind's CPU kernel: what [`Evaluator`] runs for it. Each kind implements it in its
/// own module; the per-kind evaluators ([`LrpEvaluator`], …) are these kernels.
///
/// A kernel must give a pixel the same bits whatever window, band of rows or thread evaluates
/// it (invariants 3 and 4 of `docs/ARCHITECTURE.md`).
pub trait RowKernel: Send + Sync {
    /// Values per pixel (interleaved): 1, or 3 for colour.
    fn output_channels(&self) -> usize {
        1
    }

    /// Kernel, cosine or lattice evaluations per pixel, for reports and benches.
    fn cost_per_pixel(&self) -> f64;

    /// Evaluates consecutive rows of `window` from row `first` into `out` (whole rows of
    /// `window.width · output_channels()` values).
    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]);

    /// [`eval_rows`](Self::eval_rows) by the kind's slow, obviously correct path where it has
    /// a faster one (the same bits): what tests compare the fast path with and benches measure
    /// it against. Kinds with one path need not implement it.
    #[doc(hidden)]
    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval_rows(window, first, out);
    }

    /// Evaluates the model at arbitrary positions `points` (pixels) into `out`
    /// (`output_channels()` values per point): the same bits as a one-pixel window at each
    /// point ([`Evaluator::eval_point`]). A warp evaluates its base at its displaced positions
    /// through this. The default goes point by point; a kind whose pixels are independent
    /// evaluates them in its lanes.
    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let channels = self.output_channels();
        for (p, v) in points.iter().zip(out.chunks_exact_mut(channels)) {
            self.eval_rows(&point_window(*p), 0, v);
        }
    }

    /// Checks what [`Window::validate`] cannot know: a kind whose positions reach beyond the
    /// window (a warp) checks that they stay in range.
    ///
    /// # Errors
    /// [`CpuError::Window`] naming the parameter.
    fn check_window(&self, window: &Window) -> Result<(), CpuError> {
        let _ = window;
        Ok(())
    }
}

/// How a model kind (a [`ModelKind`] of `spectex-model`) builds its CPU kernel.
pub trait CpuKind: ModelKind {
    /// The model of this kind that `cargo xtask bench kinds` and the `kinds` group of
    /// `benches/eval.rs` measure (collected for every kind by [`bench_models`]).
    fn bench_model() -> BenchModel;

    /// The kernel of a **validated** model on the plane `z` (ignored by 2D models).
    ///
    /// # Errors
    /// A nested model that cannot be prepared.
    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn RowKernel>, CpuError>;

    /// The kernel of a **validated** model made periodic with `period`, a period it accepts
    /// ([`ModelKind::check_period`]): a periodic function of the position (cells hashed modulo
    /// the period); [`Evaluator::periodic`] reduces positions before it. The default is for
    /// kinds without a periodic form: the model layer's refusal.
    ///
    /// # Errors
    /// [`CpuError::Model`] with [`ModelError::Period`].
    fn cpu_kernel_periodic(&self, z: f64, period: Period) -> Result<Box<dyn RowKernel>, CpuError> {
        let _ = z;
        self.check_period(period)?;
        Err(CpuError::Model(ModelError::Period {
            period: period.to_string(),
            kind: Self::NAME,
            requirement: "the CPU evaluator has no periodic kernel for it".into(),
        }))
    }
}

/// A kind's bench case ([`CpuKind::bench_model`]).
#[derive(Debug, Clone)]
#[allow(
    clippy::large_enum_variant,
    reason = "one value per kind, made once per bench run"
)]
pub enum BenchModel {
    /// A model built in code.
    Built(Model),
    /// A model file of the repository's `testdata/models/`, by name, which the bench reads: a
    /// library that embedded files from outside its crate could not be packaged (`cargo
    /// package`, a Python sdist).
    Testdata(&'static str),
}

/// Every kind's bench case ([`CpuKind::bench_model`]), by kind name, in the order of
/// `Model`'s variants.
#[must_use]
pub fn bench_models() -> Vec<(&'static str, BenchModel)> {
    let mut models = Vec::new();
    spectex_model::for_each_kind!(types: K => {
        models.push((<K as ModelKind>::NAME, <K as CpuKind>::bench_model()));
    });
    models
}

/// A model prepared for evaluation. Building it validates the model; rendering can then fail
/// only on a bad window.
pub struct Evaluator {
    kind: &'static str,
    kernel: Box<dyn RowKernel>,
}

impl std::fmt::Debug for Evaluator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Evaluator")
            .field("kind", &self.kind)
            .finish_non_exhaustive()
    }
}

/// The kernel of a validated model: the one dispatch over model kinds in this crate (every kind
/// implements [`CpuKind`]), with [`kind_kernel_periodic`].
pub(crate) fn kind_kernel(model: &Model, z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
    spectex_model::for_each_kind!(model, m: K => <K as CpuKind>::cpu_kernel(m, z))
}

/// The periodic kernel of a validated model that accepts `period` (positions not reduced: a
/// periodic function for [`Evaluator::periodic`] or a warp to evaluate).
pub(crate) fn kind_kernel_periodic(
    model: &Model,
    z: f64,
    period: Period,
) -> Result<Box<dyn RowKernel>, CpuError> {
    spectex_model::for_each_kind!(model, m: K => <K as CpuKind>::cpu_kernel_periodic(m, z, period))
}

impl Evaluator {
    /// Validates and prepares `model`.
    ///
    /// # Errors
    /// [`CpuError::Model`] naming the first invalid field.
    pub fn new(model: &Model) -> Result<Self, CpuError> {
        Self::new_at_z(model, 0.0)
    }

    /// Validates and prepares `model` for the plane `z` (pixels): 3D models are evaluated on
    /// that slice, 2D models ignore it.
    ///
    /// # Errors
    /// [`CpuError::Model`] naming the first invalid field, or [`CpuError::Window`] for a `z`
    /// that is not finite or beyond [`MAX_POSITION`].
    pub fn new_at_z(model: &Model, z: f64) -> Result<Self, CpuError> {
        Self::prepare(model, z, None)
    }

    /// Validates and prepares `model` made exactly periodic with `period`
    /// (`spectex_model::period`): `f(x + W, y) = f(x, y + H) = f(x, y)` bit for bit, so a
    /// `2W × 2H` render is its `W × H` render repeated 2 × 2, and the tiles join seamlessly.
    ///
    /// # Errors
    /// As [`new`](Self::new), or [`CpuError::Model`] with [`ModelError::Period`] for a period
    /// the model cannot take (what it needs is in the message).
    pub fn periodic(model: &Model, period: Period) -> Result<Self, CpuError> {
        Self::prepare(model, 0.0, Some(period))
    }

    /// [`periodic`](Self::periodic) on the plane `z` (3D models: periodic in x and y).
    ///
    /// # Errors
    /// As [`periodic`](Self::periodic) and [`new_at_z`](Self::new_at_z).
    pub fn periodic_at_z(model: &Model, z: f64, period: Period) -> Result<Self, CpuError> {
        Self::prepare(model, z, Some(period))
    }

    /// The kind's periodic kernel alone, without the reduction of positions modulo the period:
    /// the periodic *function*, equal one period apart only up to rounding. For tests that
    /// check the seams (the cells' hashing modulo the period) rather than the reduction.
    ///
    /// # Errors
    /// As [`periodic`](Self::periodic).
    #[doc(hidden)]
    pub fn periodic_unreduced(model: &Model, period: Period) -> Result<Self, CpuError> {
        model.validate()?;
        model.check_period(period)?;
        Ok(Self {
            kind: model.kind(),
            kernel: kind_kernel_periodic(model, 0.0, period)?,
        })
    }

    /// [`new_at_z`](Self::new_at_z), periodic when `period` is given.
    ///
    /// # Errors
    /// As [`periodic_at_z`](Self::periodic_at_z).
    pub fn with_period(model: &Model, z: f64, period: Option<Period>) -> Result<Self, CpuError> {
        Self::prepare(model, z, period)
    }

    fn prepare(model: &Model, z: f64, period: Option<Period>) -> Result<Self, CpuError> {
        model.validate()?;
        if let Some(p) = period {
            model.check_period(p)?;
        }
        if !(z.is_finite() && z.abs() <= MAX_POSITION) {
            return Err(CpuError::Window {
                parameter: "z",
                value: z,
                range: "finite, |z| ≤ 2³⁰ pixels",
            });
        }
        let kernel = match period {
            None => kind_kernel(model, z)?,
            Some(period) => Box::new(periodic::PeriodicKernel {
                inner: kind_kernel_periodic(model, z, period)?,
                period,
            }),
        };
        Ok(Self {
            kind: model.kind(),
            kernel,
        })
    }

    /// The model kind's name ([`ModelKind::NAME`]).
    #[must_use]
    pub fn kind(&self) -> &'static str {
        self.kind
    }

    /// Values per pixel: 3 for a colour texture (interleaved RGB), else 1.
    #[must_use]
    pub fn output_channels(&self) -> usize {
        self.kernel.output_channels()
    }

    /// Evaluates one row of `window` into `out` (`window.width ·`
    /// [`output_channels`](Self::output_channels) values).
    pub fn eval_row(&self, window: &Window, row: usize, out: &mut [f32]) {
        self.eval_rows(window, row, out);
    }

    /// Evaluates consecutive rows of `window` from row `first` into `out` (whole rows of
    /// `window.width ·` [`output_channels`](Self::output_channels) values): the same bits as
    /// row by row, with the work a band of rows shares done once.
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        if window.width * self.output_channels() == 0 {
            return;
        }
        self.kernel.eval_rows(window, first, out);
    }

    /// Evaluates the model at one position `p` (pixels) into `out`
    /// ([`output_channels`](Self::output_channels) values): a one-pixel window at `p`, so the
    /// same bits as any render whose pixel lies at `p`.
    pub fn eval_point(&self, p: [f64; 2], out: &mut [f32]) {
        self.eval_rows(&point_window(p), 0, out);
    }

    /// Evaluates the model at each position of `points` (pixels) into `out`
    /// ([`output_channels`](Self::output_channels) values per point): the same bits as
    /// [`eval_point`](Self::eval_point) point by point, in the kind's lanes where it has them.
    pub fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        if self.output_channels() == 0 {
            return;
        }
        self.kernel.eval_points(points, out);
    }

    /// [`eval_rows`](Self::eval_rows) by the kind's reference path
    /// ([`RowKernel::eval_rows_reference`]).
    #[doc(hidden)]
    pub fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        if window.width * self.output_channels() == 0 {
            return;
        }
        self.kernel.eval_rows_reference(window, first, out);
    }

    /// [`render`](Self::render) by the kind's reference path
    /// ([`RowKernel::eval_rows_reference`]), in parallel the same way: the speed and bits the
    /// fast paths are compared with.
    ///
    /// # Errors
    /// [`CpuError::Window`] for a window out of range.
    #[doc(hidden)]
    pub fn render_reference(&self, window: &Window) -> Result<Vec<f32>, CpuError> {
        window.validate()?;
        let mut out = vec![0.0f32; window.width * window.height * self.output_channels()];
        self.render_bands(window, &mut out, &|_| {}, true)?;
        Ok(out)
    }

    /// Renders `window` row-major into a new buffer
    /// ([`output_channels`](Self::output_channels) interleaved values per pixel).
    ///
    /// # Errors
    /// [`CpuError::Window`] for a window out of range.
    pub fn render(&self, window: &Window) -> Result<Vec<f32>, CpuError> {
        window.validate()?;
        let mut out = vec![0.0f32; window.width * window.height * self.output_channels()];
        self.render_into(window, &mut out, &|_| {})?;
        Ok(out)
    }

    /// Renders `window` into `out`, in parallel over rows, calling `progress(rows_done)` as rows
    /// complete (from any thread; rows finish in any order, values do not depend on it).
    ///
    /// # Errors
    /// A window out of range or a buffer of the wrong length.
    pub fn render_into(
        &self,
        window: &Window,
        out: &mut [f32],
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<(), CpuError> {
        self.render_bands(window, out, progress, false)
    }

    /// [`render_into`](Self::render_into), by the reference path when `reference`.
    fn render_bands(
        &self,
        window: &Window,
        out: &mut [f32],
        progress: &(dyn Fn(usize) + Sync),
        reference: bool,
    ) -> Result<(), CpuError> {
        self.check_window(window)?;
        let channels = self.output_channels();
        let needed = window.width * window.height * channels;
        if out.len() != needed {
            return Err(CpuError::Buffer {
                len: out.len(),
                needed,
            });
        }
        if needed == 0 {
            return Ok(());
        }
        let done = std::sync::atomic::AtomicUsize::new(0);
        out.par_chunks_mut(window.width * channels * BAND_ROWS)
            .enumerate()
            .for_each(|(band, lines)| {
                if reference {
                    self.eval_rows_reference(window, band * BAND_ROWS, lines);
                } else {
                    self.eval_rows(window, band * BAND_ROWS, lines);
                }
                let rows = lines.len() / (window.width * channels);
                let n = done.fetch_add(rows, std::sync::atomic::Ordering::Relaxed) + rows;
                progress(n);
            });
        Ok(())
    }

    /// Checks what [`render_into`](Self::render_into) checks of `window` before it evaluates
    /// its rows: its range, and what the kind needs of it (a warp's displaced positions in
    /// range). For callers that evaluate a window's rows themselves
    /// ([`eval_rows`](Self::eval_rows)).
    ///
    /// # Errors
    /// [`CpuError::Window`] for a window out of range, or whose displaced positions (a warp's)
    /// would be.
    pub fn check_window(&self, window: &Window) -> Result<(), CpuError> {
        window.validate()?;
        self.kernel.check_window(window)
    }

    /// Kernel or cosine evaluations per pixel, for reports.
    #[must_use]
    pub fn cost_per_pixel(&self) -> f64 {
        self.kernel.cost_per_pixel()
    }
}
