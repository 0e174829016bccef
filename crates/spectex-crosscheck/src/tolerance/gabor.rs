//! Gabor noise (Lagae et al. 2009): its tolerance and regularity.

use spectex_model::{GABOR_TRUNCATION, GaborNoise};

use super::{
    COS_ABS_ERROR, CheckKind, EXP_REL_ERROR, F32_UNIT_ROUNDOFF, PHASE_ROUNDINGS, Regularity,
    SUMMATION_ROUNDINGS, Tolerance, gaussian_slope, impulse_count,
};

/// Gabor noise (Lagae et al. 2009): impulses of the 3×3 cells around a pixel, each `K·w`
/// (|w| ≤ 1) times a Gaussian ≤ 1 times a cosine. The count is Poisson of mean `9λ`
/// (λ impulses per cell); we bound it by `9λ + 6√(9λ) + 6`, which a Poisson variable exceeds
/// with probability below 1e-9, so over the ≤ 10⁵ pixels of a cross-check window no pixel is
/// expected to exceed it. Per impulse: the cosine's phase error (offsets within 2 cells, so
/// `|F₀·d| ≤ 2.83·F₀·r` turns; an isotropic direction adds two cosines of error
/// [`COS_ABS_ERROR`] times that many turns), [`COS_ABS_ERROR`], [`EXP_REL_ERROR`], on each side.
///
/// Gabor noise by example ([`spectex_model::Orientation::Spectrum`]): each impulse's frequency vector is a
/// table entry, so `F₀` becomes the table's largest `|f_k|`
/// ([`GaborNoise::largest_frequency`]), which bounds every impulse's phase the same way; the
/// entries are rounded once on the host and read by both evaluators, so they add no direction
/// error (the isotropic cosines' term is kept all the same: a bound may only be loose).
#[must_use]
pub fn gabor(m: &GaborNoise) -> Tolerance {
    let lambda = 9.0 * m.impulses_per_cell();
    let count = lambda + 6.0 * lambda.sqrt() + 6.0;
    let turns = 2.83 * m.largest_frequency() * m.kernel_radius();
    let phase = std::f64::consts::TAU
        * (PHASE_ROUNDINGS * F32_UNIT_ROUNDOFF * (turns + 1.0) + 2.0 * COS_ABS_ERROR * turns);
    let per_term = 2.0 * (phase + COS_ABS_ERROR + EXP_REL_ERROR);
    let k = f64::from(m.amplitude).abs();
    let magnitude = k * count + f64::from(m.mean).abs();
    Tolerance::from_max(k * count * per_term + SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * magnitude)
}

impl CheckKind for GaborNoise {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![gabor(self)])
    }

    fn regularity(&self) -> Option<Regularity> {
        let (m, tau) = (self, std::f64::consts::TAU);
        // Per impulse (as many as in [`gabor`]): the cosine's 2π|f| (|f| ≤ the largest
        // frequency) and the Gaussian's slope;
        // each kernel is cut at GABOR_TRUNCATION of its peak, where it may enter or leave.
        let terms = f64::from(m.amplitude).abs() * impulse_count(9.0, m.impulses_per_cell());
        Some(Regularity {
            slope: terms * (tau * m.largest_frequency() + gaussian_slope(f64::from(m.bandwidth))),
            jump: terms * GABOR_TRUNCATION,
            magnitude: terms + f64::from(m.mean).abs(),
            cell: m.kernel_radius(),
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::Orientation;

    pub fn gabor_bound_grows_with_impulses() {
        let m = |impulses_per_kernel: f32| GaborNoise {
            seed: 0,
            mean: 0.0,
            amplitude: 1.0,
            bandwidth: 0.05,
            frequency: 0.06,
            orientation: Orientation::Isotropic { min: 0.0, max: 6.0 },
            impulses_per_kernel,
        };
        assert!(gabor(&m(64.0)).max_abs > gabor(&m(8.0)).max_abs);
    }

    /// A spectrum's bound is an anisotropic noise's at its largest `|f|`.
    pub fn gabor_spectrum_bound_is_that_of_its_largest_frequency() {
        let base = GaborNoise {
            seed: 0,
            mean: 0.0,
            amplitude: 1.0,
            bandwidth: 0.05,
            frequency: 0.0,
            orientation: Orientation::Spectrum {
                frequencies: vec![[0.1, 0.0], [0.0, -0.5]],
                weights: vec![1.0, 1.0],
            },
            impulses_per_kernel: 16.0,
        };
        let aniso = GaborNoise {
            frequency: 0.5,
            orientation: Orientation::Anisotropic { angle: 0.0 },
            ..base.clone()
        };
        assert_eq!(gabor(&base).max_abs, gabor(&aniso).max_abs);
    }
}
