//! The f32 scalar functions every evaluator shares: cosine and sine of an angle in turns
//! (reduced exactly first), `atan2` in turns, `exp`, and the Kaiser–Bessel window, written with
//! plain `*` and `+` only (no FMA, no libm), so every SIMD level the compiler picks gives the same
//! bits; `shaders/common.wgsl` twins them coefficient for coefficient. They live here, with the
//! randomness contract, because host code of both evaluators (and phasor noise's kernel process)
//! calls them; `spectex_cpu::math` re-exports this module.
//!
//! `clippy.toml` bans the raw `f32::cos/sin/exp` in this crate; this module is the one place
//! that defines their replacements.

/// `1.5·2²³`: adding and subtracting it rounds an `f32` of magnitude below 2²² to the nearest
/// integer (ties to even) with two exact IEEE operations — no `round()` library call, which
/// without SSE4.1 would block vectorisation.
const ROUND_MAGIC: f32 = 12_582_912.0;

/// `t − round(t)`, in `[−0.5, 0.5]`, for `|t| < 2²²`.
#[inline(always)]
#[must_use]
pub fn fract_turns(t: f32) -> f32 {
    t - ((t + ROUND_MAGIC) - ROUND_MAGIC)
}

/// Minimax coefficients of `cos(2πb)` in `x = b²` on `b ∈ [0, ¼]`, degree 4 in `x` (8 in `b`)
/// with the constant pinned to 1 (so `cos_turns(0) = 1` exactly), rounded once to f32.
///
/// Fitted in f64 by Lawson's iteratively reweighted least squares on 200 001 points of `[0, ¼]`
/// (`python3` + numpy, 500 iterations); the equioscillating error of the f64 polynomial is
/// 5.3e-8, below half an f32 ulp of 1. The degree-12 Taylor series it replaces had 6.9e-9 but
/// two more Horner steps (4 of ≈ 24 vector instructions per cosine in the LRP inner loop);
/// evaluated in f32 both are ≈ 1.5–2e-7, dominated by rounding.
pub const COS_TURNS: [f32; 5] = [1.0, -19.739_182, 64.935_22, -85.254_01, 56.340_71];

/// `cos(2π·t)` for an angle `t` in turns (`|t| < 2²²`), absolute error below 2e-7.
///
/// The angle is reduced to `r ∈ [−½, ½]` exactly, folded to `b = min(|r|, ½ − |r|) ∈ [0, ¼]`
/// (with a sign flip for the second branch: `cos(2π(½ − b)) = −cos(2πb)`), and the minimax
/// polynomial [`COS_TURNS`] in `b²` is evaluated by Horner's rule.
#[inline(always)]
#[must_use]
pub fn cos_turns(t: f32) -> f32 {
    let a = fract_turns(t).abs();
    let far = a > 0.25;
    let b = if far { 0.5 - a } else { a };
    let x = b * b;
    let mut p = COS_TURNS[4];
    p = p * x + COS_TURNS[3];
    p = p * x + COS_TURNS[2];
    p = p * x + COS_TURNS[1];
    p = p * x + COS_TURNS[0];
    if far { -p } else { p }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    // The other test modules of this file, so that `unit_tests::math` names every body.
    use super::*;
    pub use super::{atan_tests::*, exp_tests::*, window_tests::*};

    pub fn fract_turns_is_exact() {
        for t in [0.0f32, 0.25, 0.5, -0.5, 1.75, -3.2, 1000.1, 123_456.7] {
            let r = fract_turns(t);
            assert!((-0.5..=0.5).contains(&r), "{t} -> {r}");
            // t − r must be an integer and r exactly representable: compare in f64.
            let n = f64::from(t) - f64::from(r);
            assert_eq!(n, n.round(), "{t}");
        }
    }

    /// Against f64 `cos` over a dense sweep of turns, including large arguments.
    pub fn cos_turns_matches_f64_cos() {
        let mut worst = 0.0f64;
        for i in -200_000..=200_000 {
            let t = i as f32 * 1.37e-5 + (i % 7) as f32 * 100.0;
            let want = (2.0 * std::f64::consts::PI * f64::from(fract_turns(t))).cos();
            worst = worst.max((f64::from(cos_turns(t)) - want).abs());
        }
        assert!(worst < 2e-7, "worst error {worst:e}");
        assert_eq!(cos_turns(0.0), 1.0);
        assert!((cos_turns(0.5) + 1.0).abs() < 1e-7);
    }
}

/// Minimax fit of the Kaiser–Bessel window of [`crate::window::kaiser_bessel`] as
/// `w = u^{3/2}·P(u)` with `u = 1 − r²/2.25 ∈ [0, 1]`: the coefficients of `P`, degree 7.
///
/// Why this form: with `(z/2)² = q = (3π/2)²·u`, `I₃(z) = q^{3/2} Σ q^m/(m!(m+3)!)`, so the window
/// is `u^{3/2}` times an entire function of `u`, which a low-degree polynomial fits closely (the
/// series itself needs 16 terms at `u = 1`). Fitted in f64 by `scripts/minimax.py` (Lawson's
/// iteratively reweighted least squares, absolute error): 5.1e-8 in f64, 2.8e-7 evaluated in f32.
pub const KB_POLY: [f32; 8] = [
    0.017_600_192,
    0.098_341_09,
    0.212_476_86,
    0.290_033_43,
    0.155_061_08,
    0.205_698_98,
    -0.027_654_441,
    0.048_442_75,
];

/// The Kaiser–Bessel window as a function of `r² = (|x − x_i| / Δ)²`, in f32: `u^{3/2}·P(u)`
/// with `u = 1 − r²/2.25` and `P` = [`KB_POLY`] by Horner's rule; exactly 0 for `r² ≥ 2.25`.
/// One `sqrt` (exact in IEEE) and plain `*` and `+`.
#[inline(always)]
#[must_use]
pub fn kaiser_bessel_r2(r2: f32) -> f32 {
    let inside = 1.0 - r2 * (1.0 / 2.25);
    let u = inside.max(0.0);
    let mut p = KB_POLY[7];
    let mut m = 7;
    while m > 0 {
        m -= 1;
        p = p * u + KB_POLY[m];
    }
    let w = u * u.sqrt() * p;
    if inside > 0.0 { w } else { 0.0 }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod window_tests {
    use super::*;

    /// The f32 window against the f64 definition in spectex-model.
    pub fn window_matches_the_model_definition() {
        let mut worst = 0.0f64;
        for i in 0..=3000 {
            let r = i as f64 * 0.0005;
            let want = crate::window::kaiser_bessel(r);
            let got = f64::from(kaiser_bessel_r2((r * r) as f32));
            worst = worst.max((got - want).abs());
        }
        // The fit's 5.1e-8 plus f32 rounding (2.8e-7 measured by scripts/minimax.py).
        assert!(worst < 4e-7, "worst error {worst:e}");
        assert_eq!(kaiser_bessel_r2(2.25), 0.0);
        assert_eq!(kaiser_bessel_r2(9.0), 0.0);
        assert!((kaiser_bessel_r2(0.0) - 1.0).abs() < 1e-6);
    }

    /// `P(1)` is the window at the centre, 1 by definition; the fit is not constrained to it.
    pub fn window_is_one_at_the_centre() {
        let centre = kaiser_bessel_r2(0.0);
        assert!(
            (centre - 1.0).abs() <= 3.0 * f32::EPSILON,
            "w(0) = {centre}"
        );
    }
}

/// High part of `ln 2` with nine trailing zero bits, so `n · LN2_HI` is exact for `|n| < 512`
/// (Cody & Waite's two-constant reduction).
const LN2_HI: f32 = 0.693_145_75;
/// `ln 2 − LN2_HI`.
const LN2_LO: f32 = 1.428_606_8e-6;
/// Taylor coefficients `1/k!`, k = 0..7, of `e^f` on `|f| ≤ ln 2 / 2` (truncation error below
/// `0.347⁸/8! · e^0.347 < 8e-9` relative).
const EXP_TAYLOR: [f32; 8] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
];
/// Inputs are clamped to `[EXP_MIN, EXP_MAX]` so that `2ⁿ` is always a normal `f32`.
const EXP_MIN: f32 = -87.0;
/// See [`EXP_MIN`].
const EXP_MAX: f32 = 88.0;

/// `e^z` in f32, branch-free, with plain `*` and `+` only (no libm, no FMA), relative error
/// below 1e-6 for `z ∈ [−80, 80]` (measured ≈ 1e-7 by the test below).
///
/// `z` is clamped to `[−87, 88]` first (NaN becomes −87), so the result is always finite and
/// positive. Reduction: `n = round(z / ln 2)` by the `1.5·2²³` trick of [`fract_turns`] (whose
/// bits also give `n` as an integer), `f = (z − n·LN2_HI) − n·LN2_LO ∈ [−ln 2/2, ln 2/2]`, `e^f`
/// by the degree-7 Taylor polynomial in Horner form, and `2ⁿ` assembled from its exponent bits. The Gabor kernel
/// calls it on `[−ln 20, 0]`; everything here is also exact or correctly rounded in WGSL.
#[inline(always)]
#[must_use]
pub fn exp_poly(z: f32) -> f32 {
    // reason: `clamp` keeps NaN, whose bits would reach `2ⁿ`; max/min map NaN to EXP_MIN.
    #[allow(clippy::manual_clamp)]
    let z = z.max(EXP_MIN).min(EXP_MAX);
    let shifted = z * std::f32::consts::LOG2_E + ROUND_MAGIC;
    let n = shifted - ROUND_MAGIC;
    // `shifted` lies in [2²³, 2²⁴), where one unit is one step of the mantissa bits.
    let n_int = shifted.to_bits().wrapping_sub(ROUND_MAGIC.to_bits()) as i32;
    let f = (z - n * LN2_HI) - n * LN2_LO;
    let mut p = EXP_TAYLOR[7];
    p = p * f + EXP_TAYLOR[6];
    p = p * f + EXP_TAYLOR[5];
    p = p * f + EXP_TAYLOR[4];
    p = p * f + EXP_TAYLOR[3];
    p = p * f + EXP_TAYLOR[2];
    p = p * f + EXP_TAYLOR[1];
    p = p * f + EXP_TAYLOR[0];
    let two_n = f32::from_bits(((n_int + 127) as u32) << 23);
    p * two_n
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod exp_tests {
    use super::*;

    /// Against f64 `exp` of the same f32 input: a dense sweep of the Gabor range `[−3.1, 0]`
    /// and a coarser one over `[−80, 80]`.
    pub fn exp_poly_matches_f64_exp() {
        let mut worst = 0.0f64;
        let mut check = |z: f32| {
            let want = f64::from(z).exp();
            let got = f64::from(exp_poly(z));
            worst = worst.max(((got - want) / want).abs());
        };
        for i in 0..=1_000_000 {
            check(-3.1 * i as f32 / 1_000_000.0);
        }
        for i in -400_000..=400_000 {
            check(i as f32 * 2e-4);
        }
        println!("exp_poly: worst relative error {worst:e}");
        assert!(worst < 1e-6, "worst relative error {worst:e}");
        assert_eq!(exp_poly(0.0), 1.0);
    }

    pub fn exp_poly_reduction_constants_and_clamping() {
        let ln2 = f64::from(LN2_HI) + f64::from(LN2_LO);
        assert!((ln2 - std::f64::consts::LN_2).abs() < 1e-13, "{ln2}");
        assert_eq!(LN2_HI.to_bits() & 0x1ff, 0, "n·LN2_HI must be exact");
        // Clamped, finite and positive everywhere, NaN included.
        for z in [
            f32::NEG_INFINITY,
            -1e30,
            -200.0,
            f32::NAN,
            200.0,
            f32::INFINITY,
        ] {
            let v = exp_poly(z);
            assert!(v.is_finite() && v > 0.0, "{z} -> {v}");
        }
    }
}

/// Minimax coefficients of `atan(a)/(2π)` on `a ∈ [0, 1]` as `a·P(a²)`, `P` of degree 7, fitted
/// by `scripts/minimax.py` (5.97e-9 turns in f64, 2.4e-8 turns evaluated in f32).
pub const ATAN_TURNS: [f32; 8] = [
    0.159_154_83,
    -0.053_046_122,
    0.031_745_948,
    -0.022_136_277,
    0.015_346_049,
    -0.008_898_746,
    0.003_479_614_2,
    -0.000_645_309_16,
];

/// `atan2(y, x) / 2π`: the angle of `(x, y)` in turns, in `[−½, ½]`, absolute error below 5e-8
/// turns; `0` at the origin. The ratio `min/max` of the magnitudes (in `[0, 1]`, one correctly
/// rounded division) goes through [`ATAN_TURNS`]; the octant is restored exactly (`¼ − r`,
/// `½ − r`, `−r` are exact or correctly rounded). Plain `*`, `+`, `/` only.
#[inline(always)]
#[must_use]
pub fn atan2_turns(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = if ay > ax { (ax, ay) } else { (ay, ax) };
    let a = if hi > 0.0 { lo / hi } else { 0.0 };
    let s = a * a;
    let mut p = ATAN_TURNS[7];
    let mut k = 7;
    while k > 0 {
        k -= 1;
        p = p * s + ATAN_TURNS[k];
    }
    let mut r = a * p;
    if ay > ax {
        r = 0.25 - r;
    }
    if x < 0.0 {
        r = 0.5 - r;
    }
    if y < 0.0 { -r } else { r }
}

/// `sin(2π·t)` for an angle in turns: [`cos_turns`]`(t − ¼)`.
#[inline(always)]
#[must_use]
pub fn sin_turns(t: f32) -> f32 {
    cos_turns(t - 0.25)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod atan_tests {
    use super::*;

    /// Against f64 `atan2` on a dense set of directions and magnitudes, all four quadrants.
    #[allow(clippy::disallowed_methods, reason = "f64 libm is the reference")]
    pub fn atan2_turns_matches_f64() {
        let mut worst = 0.0f64;
        for i in 0..200_000 {
            let angle = (i as f64 / 200_000.0 - 0.5) * std::f64::consts::TAU;
            for scale in [1e-20f64, 0.3, 7.0, 1e15] {
                let (x, y) = ((scale * angle.cos()) as f32, (scale * angle.sin()) as f32);
                let want = f64::from(y).atan2(f64::from(x)) / std::f64::consts::TAU;
                let mut err = (f64::from(atan2_turns(y, x)) - want).abs();
                err = err.min((err - 1.0).abs()); // ±½ are the same angle
                worst = worst.max(err);
            }
        }
        assert!(worst < 5e-8, "worst error {worst:e} turns");
        assert_eq!(atan2_turns(0.0, 0.0), 0.0);
        assert_eq!(atan2_turns(0.0, 1.0), 0.0);
        assert_eq!(atan2_turns(1.0, 0.0), 0.25);
        assert_eq!(atan2_turns(0.0, -1.0), 0.5);
        assert_eq!(atan2_turns(-1.0, 0.0), -0.25);
    }
}
