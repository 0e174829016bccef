//! The shrink distance δ of §4.3: the radius holding a given share (75%) of the scaled window's
//! spectral energy, from the Hankel transform of the Kaiser–Bessel window.
//!
//! With `W(x) = w(|x|)` the 2D window of width 1 (support radius 1.5), its Fourier transform is
//! radial, `Ŵ(ρ) = 2π ∫₀^1.5 r·w(r)·J₀(2πρr) dr` (a Hankel transform), and the window of width
//! `Δ`, `W(x/Δ)`, has transform `Δ²·Ŵ(Δf)`. The share of its energy within radius `δ`,
//! `∫_{|f|<δ} |Δ²Ŵ(Δf)|² df / ∫ |Δ²Ŵ(Δf)|² df`, becomes `F(Δδ)` after the change of variable
//! `u = Δf`, where `F(u) = ∫₀^u 2πρ Ŵ(ρ)² dρ / ∫₀^∞ 2πρ Ŵ(ρ)² dρ` does not depend on `Δ`. So
//! the δ of a stratum is `δ₀/Δ_S` cycles per pixel, `δ₀ = F⁻¹(coverage)` computed once, and
//! `δ₀·T/Δ_S` frequency bins of a `T × T` spectrum. By Parseval the denominator is
//! `∫|W|² = 2π ∫₀^1.5 r·w²(r) dr = 2π · 0.1126` (the constant of Eq. 3).
//!
//! Quadrature: with `r = 1.5·sin θ` the window becomes `I₃(3π cos θ)/I₃(3π)`, analytic in `θ`
//! (the `(1 − r²/2.25)^{3/2}` edge of `w` disappears), so composite Gauss–Legendre rules
//! converge fast in both integrals.

use spectex_model::window::{WINDOW_SUPPORT, kaiser_bessel, window_radial_energy};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// The Bessel function of the first kind of order 0, `J₀(x)`.
///
/// For `|x| < 12` its power series `Σ_m (−1)^m (x/2)^{2m} / (m!)²` (largest term below 5·10³, so
/// cancellation costs under 1e-12 absolute); beyond, Hankel's asymptotic expansion
/// `√(2/(πx))·(P cos(x − π/4) − Q sin(x − π/4))` with `P`, `Q` summed to 20 terms, whose
/// truncation error at `x = 12` is about 1e-12 and falls quickly with `x`. Tested against the
/// integral `J₀(x) = (1/π)∫₀^π cos(x sin θ) dθ` and its tabulated zeros.
#[must_use]
pub fn bessel_j0(x: f64) -> f64 {
    let x = x.abs();
    if x < 12.0 {
        let q = -0.25 * x * x;
        let (mut term, mut sum) = (1.0f64, 1.0f64);
        for m in 1..80 {
            term *= q / (m * m) as f64;
            sum += term;
            if term.abs() < 1e-17 * sum.abs().max(1e-300) && m > 4 {
                break;
            }
        }
        sum
    } else {
        // a_k = (−1)^k (1²·3²···(2k−1)²) / (k!·8^k); P = Σ (−1)^k a_{2k}/x^{2k},
        // Q = Σ (−1)^k a_{2k+1}/x^{2k+1}. Each term t_k = a_k / x^k is formed recursively.
        let (mut p, mut q) = (1.0f64, 0.0f64);
        let mut t = 1.0f64;
        for k in 1..=20usize {
            let odd = (2 * k - 1) as f64;
            t *= -(odd * odd) / (8.0 * k as f64 * x);
            match k % 4 {
                1 => q += t,
                2 => p -= t,
                3 => q -= t,
                _ => p += t,
            }
        }
        let omega = x - FRAC_PI_4;
        (2.0 / (PI * x)).sqrt() * (p * omega.cos() - q * omega.sin())
    }
}

/// Nodes and weights of the `n`-point Gauss–Legendre rule on `[−1, 1]` (Newton's method on the
/// Legendre polynomial from Tricomi's initial guesses). Exact for polynomials of degree `2n − 1`.
#[must_use]
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut rule = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            // P_n(x) by the three-term recurrence, and P_n'(x).
            let (mut p0, mut p1) = (1.0f64, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pn_1 = if n <= 1 { 1.0 } else { p0 };
            derivative = n as f64 * (x * pn - pn_1) / (x * x - 1.0);
            let dx = pn / derivative;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        rule.push((x, 2.0 / ((1.0 - x * x) * derivative * derivative)));
    }
    rule
}

/// Points of the Gauss–Legendre rule used on every panel.
const PANEL_POINTS: usize = 16;

fn panel_rule() -> &'static [(f64, f64)] {
    static RULE: std::sync::OnceLock<Vec<(f64, f64)>> = std::sync::OnceLock::new();
    RULE.get_or_init(|| gauss_legendre(PANEL_POINTS))
}

/// `∫_a^b f` by the composite Gauss–Legendre rule on `panels` equal panels.
fn integrate(a: f64, b: f64, panels: usize, mut f: impl FnMut(f64) -> f64) -> f64 {
    let rule = panel_rule();
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * h;
        for &(x, w) in rule {
            sum += w * f(mid + 0.5 * h * x);
        }
    }
    0.5 * h * sum
}

/// `Ŵ(ρ) = 2π ∫₀^1.5 r·w(r)·J₀(2πρr) dr`, the 2D Fourier transform of the window `w(|x|)` of
/// width 1 at radial frequency `ρ` (cycles per window width). `Ŵ(0) = ∫ W`.
#[must_use]
pub fn window_spectrum(rho: f64) -> f64 {
    let s = WINDOW_SUPPORT;
    // r = s·sin θ: r dr = s² sin θ cos θ dθ. The J₀ argument 2πρs·sin θ makes about 1.5ρ
    // oscillations on [0, π/2]; a panel per half oscillation keeps the rule converged.
    let panels = 2 + (3.0 * rho.abs()).ceil() as usize;
    let integral = integrate(0.0, FRAC_PI_2, panels, |theta| {
        let (sin, cos) = theta.sin_cos();
        sin * cos * kaiser_bessel(s * sin) * bessel_j0(2.0 * PI * rho * s * sin)
    });
    2.0 * PI * s * s * integral
}

/// `∫₀^radius 2πρ·Ŵ(ρ)² dρ`: the window's spectral energy within `radius` (cycles per window
/// width). Tends to `∫|W|² = 2π·∫₀^1.5 r·w² dr` as the radius grows (Parseval).
#[must_use]
pub fn window_spectrum_energy(radius: f64) -> f64 {
    if radius <= 0.0 || radius.is_nan() {
        return 0.0;
    }
    let panels = (radius * 8.0).ceil().max(1.0) as usize;
    integrate(0.0, radius, panels, |rho| {
        2.0 * PI * rho * window_spectrum(rho).powi(2)
    })
}

/// `∫|W|² = 2π·∫₀^1.5 r·w²(r) dr ≈ 2π·0.1126`, the window's total energy (its spectral energy
/// by Parseval), from [`window_radial_energy`].
#[must_use]
pub fn window_energy() -> f64 {
    2.0 * PI * window_radial_energy()
}

/// Smallest share of the window's energy accepted as `coverage`.
pub const MIN_COVERAGE: f64 = 0.05;
/// Largest share of the window's energy accepted as `coverage`.
pub const MAX_COVERAGE: f64 = 0.99;

/// `δ₀`: the radius (in cycles per window width) within which the share `coverage` of the
/// window's spectral energy lies, so that the shrink distance of a stratum of window width
/// `Δ_S` is `δ₀/Δ_S` cycles per pixel (§4.3: "S is shrunk by a constant δ defined such that at
/// least 75% of the scaled window energy |Δ_S ŵ(Δ_S f)|² is within [−δ; δ]"; the paper's
/// interval is read as a disc, the window being radial).
///
/// Solved by bisection on `F(δ₀) = coverage` (module docs) to 1e-13 relative, with the
/// Parseval total as the denominator. `coverage` is clamped to
/// `[`[`MIN_COVERAGE`]`, `[`MAX_COVERAGE`]`]`; δ₀(0.75) ≈ 0.41194. Results are cached per
/// coverage (the last 16).
#[must_use]
pub fn shrink_unit(coverage: f64) -> f64 {
    // The bisection costs ~10 ms; a fit asks for the same few coverages again and again.
    static CACHE: std::sync::Mutex<Vec<(u64, f64)>> = std::sync::Mutex::new(Vec::new());
    let coverage = if coverage.is_nan() {
        0.75
    } else {
        coverage.clamp(MIN_COVERAGE, MAX_COVERAGE)
    };
    let key = coverage.to_bits();
    if let Ok(cache) = CACHE.lock()
        && let Some(&(_, delta0)) = cache.iter().find(|(k, _)| *k == key)
    {
        return delta0;
    }
    let delta0 = solve_shrink_unit(coverage);
    if let Ok(mut cache) = CACHE.lock() {
        if cache.len() >= 16 {
            cache.remove(0);
        }
        cache.push((key, delta0));
    }
    delta0
}

/// The bisection of [`shrink_unit`], uncached.
fn solve_shrink_unit(coverage: f64) -> f64 {
    let target = coverage * window_energy();
    let mut hi = 1.0;
    while window_spectrum_energy(hi) < target && hi < 64.0 {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    while hi - lo > 1e-13 * hi {
        let mid = 0.5 * (lo + hi);
        if window_spectrum_energy(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// `J₀(x) = (1/π)∫₀^π cos(x sin θ) dθ` by the trapezoid rule on 4096 intervals: the
    /// integrand is periodic and analytic, so the rule is exact to rounding for `|x| < 2000`.
    fn j0_by_integral(x: f64) -> f64 {
        let n = 4096;
        let sum: f64 = (0..n)
            .map(|i| (x * (PI * i as f64 / n as f64).sin()).cos())
            .sum();
        sum / n as f64
    }

    pub fn bessel_j0_matches_its_integral_representation() {
        for i in 0..=1200 {
            let x = i as f64 * 0.0833;
            let (got, want) = (bessel_j0(x), j0_by_integral(x));
            assert!(
                (got - want).abs() < 2e-12,
                "x = {x}: series/asymptotic {got} vs integral {want}"
            );
        }
        assert_eq!(bessel_j0(0.0), 1.0);
        assert_eq!(bessel_j0(-3.7), bessel_j0(3.7));
    }

    pub fn bessel_j0_vanishes_at_its_tabulated_zeros() {
        // Zeros j_{0,k} from Abramowitz & Stegun, Table 9.5.
        for zero in [
            2.404_825_557_695_773,
            5.520_078_110_286_311,
            8.653_727_912_911_013,
            11.791_534_439_014_281,
            14.930_917_708_487_787,
            18.071_063_967_910_923,
        ] {
            assert!(
                bessel_j0(zero).abs() < 1e-12,
                "J0({zero}) = {}",
                bessel_j0(zero)
            );
        }
    }

    pub fn gauss_legendre_integrates_polynomials_exactly() {
        for n in [1usize, 2, 5, 16] {
            let rule = gauss_legendre(n);
            for degree in 0..2 * n {
                let got: f64 = rule.iter().map(|&(x, w)| w * x.powi(degree as i32)).sum();
                let want = if degree % 2 == 1 {
                    0.0
                } else {
                    2.0 / (degree + 1) as f64
                };
                assert!(
                    (got - want).abs() < 1e-14,
                    "n = {n}, degree {degree}: {got} vs {want}"
                );
            }
        }
    }

    /// `Ŵ(ρ)` against composite Simpson's rule on the original variable `r`, 20000 intervals.
    pub fn window_spectrum_matches_a_direct_hankel_sum() {
        for rho in [0.0, 0.1, 0.37, 0.72, 1.0, 1.9, 3.3, 6.0] {
            let n = 20_000;
            let h = WINDOW_SUPPORT / n as f64;
            let f = |r: f64| r * kaiser_bessel(r) * bessel_j0(2.0 * PI * rho * r);
            let mut sum = f(0.0) + f(WINDOW_SUPPORT);
            for i in 1..n {
                sum += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            let want = 2.0 * PI * sum * h / 3.0;
            let got = window_spectrum(rho);
            assert!(
                (got - want).abs() < 1e-9,
                "ρ = {rho}: Gauss–Legendre {got} vs Simpson {want}"
            );
        }
    }

    /// Parseval: the window's spectral energy out to a large radius equals `∫|W|² = 2π·0.1126`.
    pub fn window_spectral_energy_equals_its_spatial_energy() {
        let spectral = window_spectrum_energy(40.0);
        let spatial = window_energy();
        assert!(
            (spectral - spatial).abs() < 1e-7 * spatial,
            "∫2πρŴ² = {spectral} vs 2π∫rw² = {spatial}"
        );
        assert!((spatial / (2.0 * PI) - 0.1126).abs() < 5e-5);
    }

    pub fn shrink_unit_holds_the_requested_share_of_energy() {
        for coverage in [0.1, 0.5, 0.75, 0.9, 0.99] {
            let delta0 = shrink_unit(coverage);
            let share = window_spectrum_energy(delta0) / window_energy();
            assert!(
                (share - coverage).abs() < 1e-10,
                "coverage {coverage}: δ₀ = {delta0} holds {share}"
            );
        }
        let d = shrink_unit(0.75);
        assert!(shrink_unit(0.5) < d && d < shrink_unit(0.9));
    }
}
