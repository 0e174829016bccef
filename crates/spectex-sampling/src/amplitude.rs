//! The amplitude `A_S` of a stratum's cosines (Gilet et al. 2014, §4.3, Eq. 3), derived for a
//! power spectrum expressed as a density.

use spectex_model::window::window_radial_energy;
use std::f64::consts::PI;

/// `A_S`, the amplitude of every cosine of a stratum, so that the stratum's noise `n_S` has the
/// spatially averaged variance `energy` (`E_S = Σ_{f∈S} P(f)/T²`, both halves counted), with
/// `cosines` (`J_S`) cosines per lattice point:
///
/// `A_S = √(E_S / (π·J_S·c))`, `c = ∫₀^1.5 r·w²(r) dr ≈ 0.1126`.
///
/// **Derivation.** `n_S(x) = Σ_i w(|x − x_i|/Δ) Σ_j A_S cos(2π(f_ij·(x − x_i)) + φ_ij)` over the
/// lattice `x_i ∈ Δ·ℤ²`. Phases are independent and uniform, so the cosines are uncorrelated,
/// each of variance `A_S²/2`, and at a position `x`,
/// `var n_S(x) = J_S·(A_S²/2)·Σ_i w²(|x − x_i|/Δ)`. The lattice sum is `Δ`-periodic; its mean
/// over a cell is `(1/Δ²)∫_{ℝ²} w²(|x|/Δ) dx = 2π∫₀^1.5 r·w²(r) dr = 2π·c` (tested by direct
/// summation), independent of `Δ`. Hence the spatially averaged variance is
/// `J_S·(A_S²/2)·2πc = π·J_S·A_S²·c`; setting it to `E_S` gives the formula.
///
/// **Relation to Eq. (3).** The paper writes `A_S = √E_S · (Δ_S²·J_S·π·∫r w² dr)^{-1/2}` with
/// `E_S = Σ_{f∈S} A²(f)` a plain sum over DFT bins. Its denominator `π·Δ_S²·J_S·A_S²·c` is the
/// energy `∫|n̂|² = ∫|n|²` of *one* local noise (one lattice point's `J_S` windowed cosines
/// over the whole plane; the window covers an area `∝ Δ_S²`): Eq. (3) matches the stratum's
/// energy with the noise's energy per lattice cell, of area `Δ_S²` pixels, so its `A²(f)` must
/// be in units of energy per `Δ_S²` pixels. Here `P` is a density normalised per pixel —
/// `Σ P/T²` is the variance: each of the `T²` bins covers `1/T²` of the frequency plane, so
/// `Σ P/T²` is `∫ P df`, an energy per pixel — and must be matched with the noise's energy per
/// pixel, one local noise's energy divided by the cell area `Δ_S²`: the `Δ_S²` cancels. Put
/// otherwise, Eq. (3) with our `E_S` converted to a per-cell energy, `E_S·Δ_S²`, is this
/// formula; with `E_S` left per pixel it would give the variance `E_S/Δ_S²`, wrong by a factor
/// `Δ_S²` (between 7 and 1250 on the gravel photograph). The `T²` that divides our sum is the
/// bin area of the density; the `Δ_S²` of Eq. (3) is the lattice cell of the energy.
///
/// Returns 0 for no energy or no cosines.
#[must_use]
pub fn amplitude(energy: f64, cosines: usize) -> f64 {
    if energy <= 0.0 || cosines == 0 || energy.is_nan() {
        return 0.0;
    }
    (energy / (PI * cosines as f64 * window_radial_energy())).sqrt()
}

/// The spatially averaged variance of a stratum's noise with `cosines` cosines of amplitude
/// `amplitude`: `π·J_S·A_S²·c`, the inverse of [`amplitude`].
#[must_use]
pub fn stratum_variance(amplitude: f64, cosines: usize) -> f64 {
    PI * cosines as f64 * amplitude * amplitude * window_radial_energy()
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::window::kaiser_bessel;

    /// The mean over a lattice cell of `Σ_i w²(|x − x_i|)` (Δ = 1, lattice ℤ²), by direct
    /// summation on a 400 × 400 midpoint grid of the cell and every lattice point within reach,
    /// equals `2π·∫₀^1.5 r w²(r) dr`.
    pub fn lattice_mean_of_squared_windows_is_two_pi_c() {
        let n = 400;
        let mut total = 0.0;
        for a in 0..n {
            for b in 0..n {
                let (x, y) = ((a as f64 + 0.5) / n as f64, (b as f64 + 0.5) / n as f64);
                for i in -2i32..=3 {
                    for j in -2i32..=3 {
                        let r = ((x - f64::from(i)).powi(2) + (y - f64::from(j)).powi(2)).sqrt();
                        total += kaiser_bessel(r).powi(2);
                    }
                }
            }
        }
        let mean = total / (n * n) as f64;
        let want = 2.0 * PI * window_radial_energy();
        assert!(
            (mean - want).abs() < 1e-6 * want,
            "cell mean of Σ w² = {mean}, 2π·c = {want}"
        );
    }

    /// Monte Carlo over random phases at fixed positions: the variance of `n_S(x)` averaged over
    /// a cell equals `π·J_S·A_S²·c`.
    pub fn amplitude_gives_the_stratum_energy_as_variance() {
        use spectex_model::random::{Prng, cell_hash};
        let (energy, cosines, delta) = (0.37, 5usize, 3.0);
        let a = amplitude(energy, cosines);
        assert!((stratum_variance(a, cosines) - energy).abs() < 1e-15);
        let mut prng = Prng::new(cell_hash(1, 2, 3, 4));
        let trials = 20_000;
        let (mut sum, mut sum2, mut count) = (0.0, 0.0, 0.0);
        for _ in 0..trials {
            // A position in the cell and random frequencies and phases for the 36 nearby points.
            let x = [prng.next_f64() * delta, prng.next_f64() * delta];
            let mut value = 0.0;
            for i in -2i32..=3 {
                for j in -2i32..=3 {
                    let xi = [f64::from(i) * delta, f64::from(j) * delta];
                    let d = [x[0] - xi[0], x[1] - xi[1]];
                    let w = kaiser_bessel((d[0] * d[0] + d[1] * d[1]).sqrt() / delta);
                    for _ in 0..cosines {
                        let f = [prng.next_f64() - 0.5, prng.next_f64() * 0.5];
                        let phase = prng.next_f64();
                        value += w * a * (2.0 * PI * (f[0] * d[0] + f[1] * d[1] + phase)).cos();
                    }
                }
            }
            sum += value;
            sum2 += value * value;
            count += 1.0;
        }
        let mean = sum / count;
        let variance = sum2 / count - mean * mean;
        // Standard error of a variance estimate of a near-Gaussian variable: ≈ √(2/n)·σ².
        let tolerance = 5.0 * (2.0 / count).sqrt() * energy;
        assert!(
            (variance - energy).abs() < tolerance,
            "Monte Carlo variance {variance} vs E_S {energy} (±{tolerance})"
        );
    }
}
