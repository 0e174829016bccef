//! LRP noise (Gilet et al. 2014, Eq. 1–2): its tolerance and regularity, and the slope of the
//! Kaiser–Bessel window they rest on.

use spectex_model::{LrpNoise, Stratum};

use super::{
    COS_ABS_ERROR, CheckKind, F32_UNIT_ROUNDOFF, PHASE_ROUNDINGS, Regularity, SUMMATION_ROUNDINGS,
    Tolerance,
};

/// Absolute error of the Kaiser–Bessel window `w(r) ∈ [0, 1]` on either side: `u^{3/2}·P(u)`
/// with `P` an 8-coefficient Horner polynomial in `u ∈ [0, 1]` whose partial values stay ≤ 1
/// (14 roundings), `u·√u·p` (3 roundings), and `u = 1 − r²/2.25` (2 roundings, amplified by
/// `dw/du ≤ 3`: 6): ≤ 23 roundings of magnitude ≤ 1, `24·2⁻²⁴ ≈ 1.43e-6`, rounded up to 1.5e-6.
pub const WINDOW_ABS_ERROR: f64 = 1.5e-6;

/// The largest `|f|` in a stratum's tables, cycles per pixel.
fn max_frequency(s: &Stratum) -> f64 {
    s.sub_strata
        .iter()
        .flatten()
        .map(|f| f64::from(f[0]).hypot(f64::from(f[1])))
        .fold(0.0, f64::max)
}

/// LRP (Gilet et al. 2014, Eq. 1–2): per stratum, 9 lattice points × `J_S` cosines of
/// amplitude `A_S` times a window ≤ 1. Per term: the cosine's error from its phase (the offset
/// to a lattice point is at most `1.5·√2·Δ_S`, so `|f·p| ≤ |f|_max·2.13·Δ_S` turns, plus the
/// phase ≤ 1), [`COS_ABS_ERROR`] and [`WINDOW_ABS_ERROR`], on each side (factor 2).
#[must_use]
pub fn lrp(m: &LrpNoise) -> Tolerance {
    let mut bound = 0.0;
    let mut magnitude = 0.0;
    for s in &m.strata {
        let f_max = max_frequency(s);
        let turns = f_max * 2.13 * f64::from(s.window_width) + 1.0;
        let phase = std::f64::consts::TAU * PHASE_ROUNDINGS * F32_UNIT_ROUNDOFF * turns;
        let per_term = 2.0 * (phase + COS_ABS_ERROR + WINDOW_ABS_ERROR);
        let terms = 9.0 * s.sub_strata.len() as f64;
        let amplitude = f64::from(s.amplitude).abs();
        bound += amplitude * terms * per_term;
        magnitude += amplitude * terms;
    }
    magnitude += f64::from(m.mean).abs();
    Tolerance::from_max(bound + SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * magnitude)
}

/// Largest `|dw/dy|` of the Kaiser–Bessel window `w(y)` (`y` in window widths), by central
/// differences of the f64 definition on 3000 steps of its support, plus 1% for the grid.
#[must_use]
pub fn kaiser_bessel_slope() -> f64 {
    let (n, h) = (3000, spectex_model::window::WINDOW_SUPPORT / 3000.0);
    let w = spectex_model::window::kaiser_bessel;
    (1..n)
        .map(|i| {
            let y = i as f64 * h;
            ((w(y + h) - w(y - h)) / (2.0 * h)).abs()
        })
        .fold(0.0, f64::max)
        * 1.01
}

impl CheckKind for LrpNoise {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![lrp(self)])
    }

    fn regularity(&self) -> Option<Regularity> {
        let (m, tau) = (self, std::f64::consts::TAU);
        // Per stratum, 9 lattice points × J_S cosines of amplitude A_S: the window's slope
        // over Δ_S and the cosine's 2π|f|.
        let kb = kaiser_bessel_slope();
        let (mut slope, mut magnitude, mut cell) = (0.0, f64::from(m.mean).abs(), 0.0f64);
        for s in &m.strata {
            let f_max = max_frequency(s);
            let delta = f64::from(s.window_width);
            let terms = 9.0 * s.sub_strata.len() as f64 * f64::from(s.amplitude).abs();
            slope += terms * (kb / delta + tau * f_max);
            magnitude += terms;
            cell = cell.max(delta);
        }
        Some(Regularity {
            slope,
            jump: 0.0,
            magnitude,
            cell,
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// The window falls from 1 to 0 over 1.5 widths, so its steepest slope is above 1/1.5;
    /// numerically it is ≈ 1.27 (the f64 window's own values, not a fitted constant).
    pub fn kaiser_bessel_slope_is_plausible() {
        let k = kaiser_bessel_slope();
        assert!(k > 1.0 / 1.5 && k < 2.0, "{k}");
    }

    /// The bound grows linearly with the amplitude and with the number of cosines.
    pub fn lrp_bound_scales_with_amplitude_and_terms() {
        let model = |amplitude: f32, cosines: usize| LrpNoise {
            seed: 0,
            mean: 0.0,
            strata: vec![Stratum {
                window_width: 10.0,
                amplitude,
                sub_strata: vec![vec![[0.1, 0.2]]; cosines],
            }],
        };
        let a = lrp(&model(0.1, 4)).max_abs;
        assert!((lrp(&model(0.2, 4)).max_abs / a - 2.0).abs() < 1e-12);
        assert!((lrp(&model(0.1, 8)).max_abs / a - 2.0).abs() < 1e-12);
        assert!(a > 0.0 && a < 1e-3, "{a}");
    }
}
