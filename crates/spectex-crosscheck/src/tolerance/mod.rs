//! The tolerances of a CPU–GPU comparison, derived per model from the number of terms a pixel
//! sums, their amplitudes and the accuracy of the f32 functions both sides evaluate.
//!
//! Both evaluators compute the same f32 formulas (cosine in turns by one polynomial, the
//! Kaiser–Bessel window by one polynomial, `exp` by one polynomial) from bit-identical integer
//! draws. They may still differ because a GPU compiler may contract `a·b + c` into an FMA and
//! reassociate (WGSL cannot forbid either), and the GPU's `cos`/`exp` builtins are not used but
//! its arithmetic rounding may differ. Each error constant (below, or in the module of the one
//! kind that uses it) bounds one such source for one term; a pixel's bound is the sum over its
//! terms.
//!
//! How a kind is judged is its [`CheckKind`] implementation, in the kind's own module below
//! (one file per kind, next to the derivation of its bounds and their tests); [`check_kind`] is
//! the one dispatch over kinds in this crate. This module holds what the kinds share: the
//! [`Tolerance`] and [`Regularity`] types, the error constants of the f32 functions several
//! kinds evaluate, and the impulse count and Gaussian slope of the sparse-convolution kinds.
//! Nothing here uses another module of the crate, and no kind module uses anything above it.

use spectex_model::Model;

// One module per kind (`<kind>.rs`: its `CheckKind` and the derivation of its bounds), declared
// from the one list of kinds.
spectex_model::for_each_kind!(pub mod);

/// Single-precision unit roundoff, `2⁻²⁴`.
pub const F32_UNIT_ROUNDOFF: f64 = 5.960_464_477_539_063e-8;

/// Error of a phase in turns, relative to its magnitude: the phase `f·p + φ` is two products and
/// two sums in f32; fused or not, each step rounds once more or once less, so at most 4 unit
/// roundoffs of the largest intermediate.
pub const PHASE_ROUNDINGS: f64 = 4.0;

/// Absolute error of `cos_turns` on either side after argument reduction: the minimax
/// polynomial's own error (5.3e-8 on [0, ¼] turn, see `spectex_model::math`) plus its
/// evaluation in 4 Horner steps, each a product and a sum that an FMA may or may not round; a
/// step's rounding (relative to values ≤ 86) is scaled by the powers of `b² ≤ 1/16` after it, so
/// together they stay below `8·2⁻²⁴`: `≈ 5.3e-7`, rounded up to 1e-6 (the bound the GPU
/// contract tests use).
pub const COS_ABS_ERROR: f64 = 1e-6;

/// Relative error of `exp_poly` (Gabor's Gaussian) on either side: degree-7 Taylor on
/// `|f| ≤ ½ ln 2` (truncation 2e-9) plus 8 Horner steps and the two-part range reduction:
/// `≈ 20·2⁻²⁴ = 1.2e-6`, plus the argument `−π a² d²`'s own rounding (3 roundings of a value
/// ≤ 3): `≈ 2e-6` in all, rounded up to 3e-6.
pub const EXP_REL_ERROR: f64 = 3e-6;

/// Per-pixel summation: terms are accumulated in 8 lanes then a tree (CPU) or serially (GPU);
/// the two orders differ by at most `n` roundings of the running sum for `n` terms, bounded by
/// `n·2⁻²⁴·Σ|term|`; we count the summed magnitude once with 64 roundings (n ≤ 64 per lane or
/// per stratum tree level in every model we ship).
pub const SUMMATION_ROUNDINGS: f64 = 64.0;

/// A mean absolute error above this fraction of the max bound is a systematic shift, not
/// rounding: rounding errors of independent terms add like a random walk (√n), so their mean
/// magnitude is far below the worst-case sum of `n` bounds.
pub const MEAN_FRACTION: f64 = 0.25;

/// Tolerances of one model's comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Bound on `|cpu − gpu|` at any pixel.
    pub max_abs: f64,
    /// Bound on the mean of `|cpu − gpu|`: `MEAN_FRACTION · max_abs`.
    pub mean_abs: f64,
}

impl Tolerance {
    pub(crate) fn from_max(max_abs: f64) -> Self {
        Self {
            max_abs,
            mean_abs: MEAN_FRACTION * max_abs,
        }
    }

    /// Bound on the relative distance `Σ|P_cpu − P_gpu| / Σ P_cpu` of the two Welch spectra of
    /// renders whose RMS difference is at most `max_abs` and the CPU render's standard deviation
    /// is `sigma`: by Parseval and Cauchy–Schwarz, `Σ|a² − b²| ≤ 2‖a‖‖a − b‖ + ‖a − b‖²`
    /// per frequency summed, so the relative distance is at most `2e + e²` with
    /// `e = max_abs / sigma`. (The Hann window weighs both sides alike.)
    #[must_use]
    pub fn spectral(&self, sigma: f64) -> f64 {
        if sigma <= 0.0 {
            return f64::INFINITY;
        }
        let e = self.max_abs / sigma;
        2.0 * e + e * e
    }
}

/// How a model kind is cross-checked: the tolerance derived for each of its output components,
/// its [`Regularity`] (which a warp over it needs), the plane it is checked on, and its own
/// criterion where comparing each component's errors with its tolerance does not judge it.
/// Every kind struct of `spectex-model` implements it in its own module of
/// [`tolerance`](self); [`check_kind`] reaches it from a [`Model`].
pub trait CheckKind {
    /// The bounds on `|cpu − gpu|` and on its mean for each output component, in the order the
    /// evaluators interleave them; `None` where no bound is derived (a warp of a model without
    /// a [`Regularity`]). A kind judged by its [`own_verdict`](Self::own_verdict) gives the
    /// scale its reports show next to the errors; its own criterion says what is allowed.
    fn tolerances(&self) -> Option<Vec<Tolerance>>;

    /// How the model's value can change when its position moves; `None` where no bound is
    /// derived.
    fn regularity(&self) -> Option<Regularity>;

    /// The bound on `|cpu − gpu|` of the model's value wherever a warp uses it (as its base, x
    /// or y): by default the largest of [`tolerances`](Self::tolerances).
    fn value_bound(&self) -> Option<f64> {
        largest(&self.tolerances()?).map(|t| t.max_abs)
    }

    /// The plane `z` (pixels) on which [`crate::check_model`] checks the model: 0 unless the
    /// kind has a reason to choose another (2D kinds ignore it).
    fn check_plane(&self) -> f64 {
        0.0
    }

    /// Models rendered on both evaluators next to this one, whose renders
    /// [`own_verdict`](Self::own_verdict) reads: none unless the kind has its own criterion.
    fn companions(&self) -> Vec<Model> {
        Vec::new()
    }

    /// The kind's own criterion, for outputs that the generic one (each component's max, mean
    /// and spectral error within its tolerance) cannot judge: the reasons one window fails
    /// (empty when it passes), from the `(cpu, gpu)` renders of the model and then of each of
    /// its [`companions`](Self::companions), rendered with the footprint `footprint` of a
    /// minified window (`spectex_model::Window::footprint`). `None`, the default, selects the
    /// generic criterion.
    fn own_verdict(
        &self,
        renders: &[(Vec<f32>, Vec<f32>)],
        footprint: Option<f64>,
    ) -> Option<Vec<String>> {
        let _ = (renders, footprint);
        None
    }
}

/// The [`CheckKind`] of `model`'s kind: the one dispatch over model kinds in this crate, so a
/// new kind of `spectex-model` that does not implement [`CheckKind`] fails to compile here.
#[must_use]
pub fn check_kind(model: &Model) -> &dyn CheckKind {
    spectex_model::for_each_kind!(model, m: _Kind => m as &dyn CheckKind)
}

/// The largest of `tolerances` (by `max_abs`): the one bound that holds for every component.
fn largest(tolerances: &[Tolerance]) -> Option<Tolerance> {
    tolerances
        .iter()
        .copied()
        .max_by(|a, b| a.max_abs.total_cmp(&b.max_abs))
}

/// The tolerance of a model that holds for every output component (the largest of its
/// kind's [`CheckKind::tolerances`], with their caveat for kinds judged by their own
/// criterion), or `None` where no bound is derived.
#[must_use]
pub fn tolerance(model: &Model) -> Option<Tolerance> {
    largest(&check_kind(model).tolerances()?)
}

/// How a model's value can change when its position moves by `δ` pixels:
/// `|v(p + δ) − v(p)| ≤ slope·|δ| + jump` (`jump` for truncated kernels, which cut at 5% of
/// their peak: any of them may enter or leave the support), with `cell` the grid side over which
/// the GPU relocates a displaced point and `magnitude` a bound on `|v|`. `None` where no bound
/// is derived (phase-based phasor outputs, whose slope is unbounded where `|𝒢| → 0`).
///
/// Each kind derives its own in its [`CheckKind::regularity`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Regularity {
    /// Lipschitz bound away from the jumps, per pixel.
    pub slope: f64,
    /// Largest total jump.
    pub jump: f64,
    /// Largest `|value|`.
    pub magnitude: f64,
    /// Grid side, pixels.
    pub cell: f64,
}

/// [`Regularity`] of `model`, by kind ([`CheckKind::regularity`]).
#[must_use]
pub fn regularity(model: &Model) -> Option<Regularity> {
    check_kind(model).regularity()
}

/// Largest slope `|∂g/∂d|` of a Gaussian `exp(−π b²d²)`: `b·√(2π)·e^{−½}`, per pixel.
fn gaussian_slope(bandwidth: f64) -> f64 {
    bandwidth * (2.0 * std::f64::consts::PI).sqrt() * (-0.5f64).exp()
}

/// A pixel's bound on the impulses of 3×3 (3×3×3) cells of mean `lambda` each, as in
/// [`gabor::gabor`]: exceeded with probability below 1e-9.
fn impulse_count(cells: f64, lambda: f64) -> f64 {
    let n = cells * lambda;
    n + 6.0 * n.sqrt() + 6.0
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// `2e + e²` is the exact worst case of `Σ|a² − b²|/Σa²` for `b = a·(1 + e)`.
    pub fn spectral_bound_is_attained_by_a_scaled_signal() {
        let t = Tolerance::from_max(0.01);
        let sigma = 0.1;
        let e = 0.01 / sigma;
        let (a, b) = (1.0f64, 1.0 + e);
        assert!(((b * b - a * a) / (a * a) - t.spectral(sigma)).abs() < 1e-12);
    }

    /// Renders `m` every 1/16 pixel and checks its steepest step against [`regularity`]: within
    /// the bound, and the bound within `factor` of it (the slope tests of the kinds' modules).
    pub(super) fn check_slope_on_fine_render(name: &str, m: &Model, factor: f64) {
        let r = regularity(m).unwrap();
        let step = 1.0 / 16.0;
        let eval = spectex_cpu::Evaluator::new_at_z(m, 3.3).unwrap();
        let window = spectex_cpu::Window::new(256, 256).at([-37.0, 1.0e6], step);
        let v = eval.render(&window).unwrap();
        let mut steepest = 0.0f64;
        for y in 0..256 {
            for x in 0..256 {
                let here = f64::from(v[y * 256 + x]);
                if x + 1 < 256 {
                    steepest = steepest.max((f64::from(v[y * 256 + x + 1]) - here).abs());
                }
                if y + 1 < 256 {
                    steepest = steepest.max((f64::from(v[(y + 1) * 256 + x]) - here).abs());
                }
            }
        }
        let bound = r.slope * step + r.jump + 1e-6;
        assert!(steepest <= bound, "{name}: step {steepest} > bound {bound}");
        assert!(
            bound < factor * steepest,
            "{name}: bound {bound} vs step {steepest}"
        );
    }
}
