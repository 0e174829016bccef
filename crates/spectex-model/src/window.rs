//! The Kaiser–Bessel window of LRP noise (Gilet et al. 2014, §3.6), defined once for every
//! evaluator.
//!
//! `w(y) = I₃(3π·√(1 − (y/1.5)²)) / I₃(3π)` for `|y| ≤ 1.5`, and 0 beyond, where `I₃` is the
//! modified Bessel function of the first kind of order 3,
//! `I₃(z) = Σ_{m≥0} (z/2)^{2m+3} / (m!·(m+3)!)`.
//!
//! **Which series.** §3.6 prints the denominator as `m!(m+2)!` and truncates at `m ≤ 4`. Neither
//! reproduces the paper's own constant `∫₀^∞ r·w²(r) dr ≈ 0.1126` (§4.3, Eq. 3): computed
//! numerically, `m!(m+2)!` with 5 terms gives 0.1179, `m!(m+3)!` with 5 terms 0.1234, and the
//! printed series summed to convergence 0.1049. The true `I₃` (denominator `m!(m+3)!`) summed
//! to convergence gives 0.11259 — the paper's value to four digits — so that is the definition
//! used here, with [`BESSEL_TERMS`] terms (the omitted tail is below 1e-9 of the sum for every
//! argument in `[0, 3π]`). The test `window_integral_matches_the_paper` checks 0.1126.

/// Terms of the `I₃` series kept: enough that the tail is below 1e-9 relative on `[0, 3π]`.
pub const BESSEL_TERMS: usize = 16;

/// Support radius of the window, in units of the window width Δ: `w(y) = 0` for `|y| ≥ 1.5`.
pub const WINDOW_SUPPORT: f64 = 1.5;

/// `Σ_{m<BESSEL_TERMS} q^m / (m!·(m+3)!)`, so that `I₃(z) = (z/2)³ · series(q)` with `q = (z/2)²`.
#[must_use]
pub fn bessel_i3_series(q: f64) -> f64 {
    // Horner from the highest term down; coefficients c_m = 1/(m!(m+3)!).
    let mut coefficients = [0.0f64; BESSEL_TERMS];
    let mut c = 1.0 / 6.0; // m = 0: 1/(0!·3!)
    for (m, slot) in coefficients.iter_mut().enumerate() {
        *slot = c;
        c /= ((m + 1) * (m + 4)) as f64;
    }
    coefficients.iter().rev().fold(0.0, |acc, &c| acc * q + c)
}

/// The modified Bessel function `I₃(z)` (series definition above).
#[must_use]
pub fn bessel_i3(z: f64) -> f64 {
    let h = z / 2.0;
    h * h * h * bessel_i3_series(h * h)
}

/// The Kaiser–Bessel window `w(y)` of §3.6, with `w(0) = 1` and `w(±1.5) = 0`.
#[must_use]
pub fn kaiser_bessel(y: f64) -> f64 {
    let t = y / WINDOW_SUPPORT;
    let inside = 1.0 - t * t;
    if inside <= 0.0 {
        return 0.0;
    }
    let z = 3.0 * std::f64::consts::PI * inside.sqrt();
    bessel_i3(z) / bessel_i3(3.0 * std::f64::consts::PI)
}

/// `∫₀^1.5 r·w²(r) dr`, the constant of Eq. (3), by composite Simpson's rule on 4096 intervals.
#[must_use]
pub fn window_radial_energy() -> f64 {
    radial_energy_of(kaiser_bessel)
}

/// `∫₀^1.5 r·w²(r) dr` for any radial window `w` supported on `[0, 1.5]` (composite Simpson's
/// rule on 4096 intervals): [`window_radial_energy`] for the window used here, and the same
/// integral for the series §3.6 prints, to show what its typo changes.
#[must_use]
pub fn radial_energy_of(w: impl Fn(f64) -> f64) -> f64 {
    const N: usize = 4096;
    let h = WINDOW_SUPPORT / N as f64;
    let f = |r: f64| r * w(r).powi(2);
    let mut sum = f(0.0) + f(WINDOW_SUPPORT);
    for i in 1..N {
        sum += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

/// The per-axis RMS bandwidth of the window's power spectrum, in cycles per pixel for `Δ = 1`:
/// `σ² = ∫ν_x²|ŵ(ν)|² dν / ∫|ŵ|² = ∫|∂_x w|² / (4π² ∫w²)` (Parseval), which for a radial window
/// is `∫ w'(r)² r dr / (8π² ∫ w(r)² r dr)`. A cosine of frequency `f` windowed at width `Δ` spreads
/// its energy around `f` with this standard deviation over `Δ` per axis; the filtering of
/// minified renders ([`crate::filter`]) uses it. ≈ 0.2452. Midpoint rule on 4096 intervals, the
/// derivative by central differences of step 1e-6.
#[must_use]
pub fn window_bandwidth() -> f64 {
    const N: usize = 4096;
    let h = WINDOW_SUPPORT / N as f64;
    let (mut slope, mut energy) = (0.0, 0.0);
    for i in 0..N {
        let r = (i as f64 + 0.5) * h;
        let d = (kaiser_bessel(r + 1e-6) - kaiser_bessel(r - 1e-6)) / 2e-6;
        slope += d * d * r;
        energy += kaiser_bessel(r).powi(2) * r;
    }
    (slope / (8.0 * std::f64::consts::PI.powi(2) * energy)).sqrt()
}

/// The range `(min, max)` of `Σ_i f(w(|x − x_i|/Δ))` over the regular lattice `x_i = iΔ` (§3.4),
/// sampled on a 101×101 grid of one lattice cell (enough: the sum is periodic and smooth). With
/// `f = id` it is the envelope the paper bounds ("varies less than 5%"); with `f = w²` the
/// variance envelope.
#[must_use]
pub fn lattice_envelope(f: impl Fn(f64) -> f64) -> (f64, f64) {
    let n = 100;
    let (mut min, mut max) = (f64::INFINITY, 0.0f64);
    for a in 0..=n {
        for b in 0..=n {
            let (x, y) = (f64::from(a) / f64::from(n), f64::from(b) / f64::from(n));
            let mut sum = 0.0;
            for i in -2..=3 {
                for j in -2..=3 {
                    sum += f(kaiser_bessel((x - f64::from(i)).hypot(y - f64::from(j))));
                }
            }
            min = min.min(sum);
            max = max.max(sum);
        }
    }
    (min, max)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// I₃ against a direct sum of 60 terms computed with explicit factorials.
    pub fn bessel_matches_a_long_direct_sum() {
        for z in [0.0, 0.1, 1.0, 2.5, 5.0, 3.0 * std::f64::consts::PI] {
            let mut want = 0.0;
            let mut fact_m = 1.0f64;
            for m in 0..60 {
                if m > 0 {
                    fact_m *= m as f64;
                }
                let fact_m3: f64 = (1..=m + 3).map(|k| k as f64).product();
                want += (z / 2.0f64).powi(2 * m + 3) / (fact_m * fact_m3);
            }
            let got = bessel_i3(z);
            assert!(
                (got - want).abs() <= 1e-9 * want.max(1e-300),
                "z = {z}: {got} vs {want}"
            );
        }
    }

    /// Eq. (3)'s constant, "≈ 0.1126 for the Kaiser–Bessel window" (§4.3), to four digits.
    pub fn window_integral_matches_the_paper() {
        let e = window_radial_energy();
        assert!((e - 0.1126).abs() < 0.00005, "∫ r w² dr = {e}");
    }

    /// §3.4: on the regular lattice of period Δ, "the envelope varies less than 5%". The
    /// envelope is `Σ_i w(|x − x_i|/Δ)` over the lattice points; measured over a 101×101 grid of
    /// one cell it varies by 3.7% of its maximum. (The variance envelope `Σ_i w²` is not what
    /// the paper bounds: it varies by 59%, i.e. the local standard deviation by up to 36%; see
    /// `variance_envelope_is_not_flat`.)
    pub fn lattice_envelope_varies_less_than_five_percent() {
        let (min, max) = lattice_envelope(|w| w);
        assert!((max - min) / max < 0.05, "envelope from {min} to {max}");
        assert!(
            (max - min) / max > 0.03,
            "the measurement itself: {min} to {max}"
        );
    }

    pub fn variance_envelope_is_not_flat() {
        let (min, max) = lattice_envelope(|w| w * w);
        let v = (max - min) / max;
        assert!((0.55..0.62).contains(&v), "variance envelope varies by {v}");
    }

    /// The bandwidth against a direct 2D estimate: `∫|∂_x w|²` and `∫w²` summed on a Cartesian
    /// grid with forward differences (no radial formula involved).
    pub fn window_bandwidth_matches_a_cartesian_estimate() {
        let n = 600;
        let h = 2.0 * WINDOW_SUPPORT / n as f64;
        let at = |i: usize, j: usize| {
            let (x, y) = (
                -WINDOW_SUPPORT + i as f64 * h,
                -WINDOW_SUPPORT + j as f64 * h,
            );
            kaiser_bessel(x.hypot(y))
        };
        let (mut slope, mut energy) = (0.0, 0.0);
        for i in 0..n {
            for j in 0..n {
                let d = (at(i + 1, j) - at(i, j)) / h;
                slope += d * d;
                energy += at(i, j).powi(2);
            }
        }
        let want = (slope / (4.0 * std::f64::consts::PI.powi(2) * energy)).sqrt();
        let got = window_bandwidth();
        assert!((got - want).abs() < 2e-3, "{got} vs {want}");
        assert!((got - 0.2452).abs() < 1e-4, "{got}");
    }

    pub fn window_shape() {
        assert_eq!(kaiser_bessel(0.0), 1.0);
        assert_eq!(kaiser_bessel(1.5), 0.0);
        assert_eq!(kaiser_bessel(-2.0), 0.0);
        let mut prev = 1.0;
        for i in 1..=150 {
            let v = kaiser_bessel(i as f64 / 100.0);
            assert!(v <= prev && v >= 0.0, "not decreasing at {i}");
            assert_eq!(v, kaiser_bessel(-(i as f64) / 100.0));
            prev = v;
        }
    }
}
