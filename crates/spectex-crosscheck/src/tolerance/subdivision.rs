//! Stochastic subdivision (`spectex_model::subdivision`): both evaluators find the same lattice
//! points and the same integer displacements (bit-identical hashes); the CPU sums in f64 and
//! rounds once to f32, the GPU sums in f32. The tolerance is a forward error bound of the f32
//! sums over the `L + 1` levels.
//!
//! With `u = 2⁻²⁴`, `δ_ℓ = σ_ℓ·510/√21845` (the largest displacement of level `ℓ`), `g` the
//! stencil's `Σ|w|` per axis (1 for the midpoint rule, 1.25 for `(−1, 9, 9, −1)/16`), `S = g²`,
//! `n` its taps (2 or 4) and `M_ℓ = S·M_{ℓ−1} + δ_ℓ` the bound on a level-`ℓ` value (`M₀ =
//! δ₀`), the GPU's error `e_ℓ` on a level-`ℓ` value obeys
//!
//! ```text
//! e₀ = 2u·δ₀                                   (the scale rounded to f32, the product)
//! e_ℓ = S·e_{ℓ−1} + 4n·u·S·M_{ℓ−1} + 2u·δ_ℓ + u·M_ℓ
//! ```
//!
//! (each pass along x then y is a sum of `n` weighted terms: at most `2n − 1` roundings of
//! `g·M`; the displacement rounds twice, the sum once). The final interpolation adds `4n·u·S·M_L`
//! for its sums and `2g·Σ|Δw|·M_L` for its f32 weights (bilinear `1 − u`: one rounding, `Σ|Δw|
//! ≤ 2u`; Catmull–Rom: at most 8 roundings of terms whose magnitudes sum to 2, 5, 4 and 1 per
//! weight, `Σ|Δw| ≤ 96u`), and the mean's addition and the CPU's final rounding `u` each of
//! the magnitude `|mean| + S·M_L`. A contracted product-add on the GPU only removes roundings.

use spectex_model::subdivision::{BYTE_SUM_MEAN, Stencil, StochasticSubdivision};

use super::{CheckKind, F32_UNIT_ROUNDOFF, Regularity, Tolerance};

/// `(g, n)`: `Σ|w|` per axis of the stencil's weights and its taps.
fn stencil(m: &StochasticSubdivision) -> (f64, f64) {
    match m.stencil {
        Stencil::Midpoint => (1.0, 2.0),
        Stencil::Cubic => (1.25, 4.0),
    }
}

/// `(M_L, e_L)`: the bound on the finest values and the GPU's error on them (module docs).
fn levels(m: &StochasticSubdivision) -> (f64, f64) {
    let u = F32_UNIT_ROUNDOFF;
    let (g, n) = stencil(m);
    let s = g * g;
    let peak = f64::from(BYTE_SUM_MEAN);
    let (mut big_m, mut e) = (0.0f64, 0.0f64);
    for (l, scale) in m.level_scales().iter().enumerate() {
        let delta = scale.abs() * peak;
        if l == 0 {
            big_m = delta;
            e = 2.0 * u * delta;
        } else {
            let next = s * big_m + delta;
            e = s * e + 4.0 * n * u * s * big_m + 2.0 * u * delta + u * next;
            big_m = next;
        }
    }
    (big_m, e)
}

/// `|mean| + S·M_L`, the largest value.
fn magnitude(m: &StochasticSubdivision) -> f64 {
    let (g, _) = stencil(m);
    f64::from(m.mean).abs() + g * g * levels(m).0
}

/// The bound of the module docs.
#[must_use]
pub fn subdivision(m: &StochasticSubdivision) -> Tolerance {
    let u = F32_UNIT_ROUNDOFF;
    let (g, n) = stencil(m);
    let s = g * g;
    let (big_m, e) = levels(m);
    let weights = match m.stencil {
        Stencil::Midpoint => 2.0 * u,
        Stencil::Cubic => 96.0 * u,
    };
    let final_sum = s * e + 4.0 * n * u * s * big_m + 2.0 * g * weights * big_m;
    Tolerance::from_max(final_sum + 2.0 * u * magnitude(m))
}

impl CheckKind for StochasticSubdivision {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![subdivision(self)])
    }

    /// Continuous: within a finest cell of side `h = C/2^L` the value is the final
    /// interpolation of values bounded by `M_L`, whose derivative along an axis is at most
    /// `Σ|w'|·g·M_L/h` (`Σ|w'| ≤ 2` for bilinear weights, `≤ 3` for Catmull–Rom's, reached at
    /// `u = ½`); both axes together give `√2` times that.
    fn regularity(&self) -> Option<Regularity> {
        let (g, _) = stencil(self);
        let (big_m, _) = levels(self);
        let derivative = match self.stencil {
            Stencil::Midpoint => 2.0,
            Stencil::Cubic => 3.0,
        };
        let h = f64::from(self.cell_size) / f64::from(1u32 << self.levels);
        Some(Regularity {
            slope: std::f64::consts::SQRT_2 * derivative * g * big_m / h,
            jump: 0.0,
            magnitude: magnitude(self),
            cell: f64::from(self.cell_size),
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn catmull_rom_derivative_weights_sum_to_at_most_three() {
        let mut largest = 0.0f64;
        for i in 0..=1000 {
            let u = f64::from(i) / 1000.0;
            let d = [
                0.5 * (-3.0 * u * u + 4.0 * u - 1.0),
                0.5 * (9.0 * u * u - 10.0 * u),
                0.5 * (-9.0 * u * u + 8.0 * u + 1.0),
                0.5 * (3.0 * u * u - 2.0 * u),
            ];
            largest = largest.max(d.iter().map(|v| v.abs()).sum());
        }
        assert!((largest - 3.0).abs() < 1e-12, "max Σ|w'| = {largest}");
    }

    pub fn the_bound_grows_with_levels_and_amplitude() {
        let mut m = StochasticSubdivision::midpoint();
        let a = subdivision(&m).max_abs;
        m.levels += 4;
        let b = subdivision(&m).max_abs;
        m.amplitude *= 10.0;
        let c = subdivision(&m).max_abs;
        assert!(a < b && b < c, "{a} {b} {c}");
        // The midpoint default (L = 7, a = 0.1, H = ½) stays far below a grey level.
        assert!(a < 1e-5, "{a}");
    }
}
