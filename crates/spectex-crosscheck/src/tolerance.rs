//! The tolerances of a CPU–GPU comparison, derived per model from the number of terms a pixel
//! sums, their amplitudes and the accuracy of the f32 functions both sides evaluate.
//!
//! Both evaluators compute the same f32 formulas (cosine in turns by one polynomial, the
//! Kaiser–Bessel window by one polynomial, `exp` by one polynomial) from bit-identical integer
//! draws. They may still differ because a GPU compiler may contract `a·b + c` into an FMA and
//! reassociate (WGSL cannot forbid either), and the GPU's `cos`/`exp` builtins are not used but
//! its arithmetic rounding may differ. Each constant below bounds one such source for one term;
//! a pixel's bound is the sum over its terms.

use spectex_model::classic::{
    Basis, ClassicNoise, FractalKind, Metric, SIMPLEX2_R2, SIMPLEX2_SCALE, SIMPLEX3_R2,
    SIMPLEX3_SCALE, WORLEY_MAX_RING,
};
use spectex_model::{
    FixedCosine, GABOR_TRUNCATION, GaborNoise, LrpNoise, MAX_WARP, Model, PHASOR_TRUNCATION,
    PhasorNoise, PhasorOutput, Stratum, TextureModel, Warp, WaveletNoise,
};

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

/// Absolute error of the Kaiser–Bessel window `w(r) ∈ [0, 1]` on either side: `u^{3/2}·P(u)`
/// with `P` an 8-coefficient Horner polynomial in `u ∈ [0, 1]` whose partial values stay ≤ 1
/// (14 roundings), `u·√u·p` (3 roundings), and `u = 1 − r²/2.25` (2 roundings, amplified by
/// `dw/du ≤ 3`: 6): ≤ 23 roundings of magnitude ≤ 1, `24·2⁻²⁴ ≈ 1.43e-6`, rounded up to 1.5e-6.
pub const WINDOW_ABS_ERROR: f64 = 1.5e-6;

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

/// Absolute error of one texture weight on either side: a placement tap's `ω` or a structure
/// block's `h(t_x)·h(t_y)`, all in `[0, 1]`. Each axis factor is `½ ± ½·cos_turns(·)`
/// ([`COS_ABS_ERROR`] halved) and a product; the placement weights are then scaled by
/// `1/√Σω²`, where `Σω²` is 4 fused-or-not products and sums of values ≤ 1 (≤ 8 roundings) and
/// WGSL bounds `sqrt` to 3 ulps and the division to 2.5 ulps (the CPU rounds each once): about
/// `2·0.5e-6 + 16·2⁻²⁴ ≈ 2e-6` per side, so 4e-6 for the difference of the two sides.
pub const TEXTURE_WEIGHT_ABS_ERROR: f64 = 4e-6;

/// `Σ|ω|` over a pixel's placement taps: at most 4 taps with `Σω² = 1`, so `Σ|ω| ≤ √4 = 2`
/// (Cauchy–Schwarz); 1 without random placement.
pub const PLACEMENT_TAP_SUM: f64 = 2.0;

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

/// The tolerance of a model, or `None` for a kind without a derivation.
#[must_use]
pub fn tolerance(model: &Model) -> Option<Tolerance> {
    match model {
        Model::Lrp(m) => Some(lrp(m)),
        Model::Gabor(m) => Some(gabor(m)),
        Model::Classic(m) => Some(classic(m)),
        Model::Wavelet(m) => Some(wavelet(m)),
        Model::Texture(m) => texture(m)
            .into_iter()
            .max_by(|a, b| a.max_abs.total_cmp(&b.max_abs)),
        Model::Warp(m) => warp(m),
        Model::Phasor(_) => None,
    }
}

/// Roundings of one wavelet band per axis on either side: the B-spline weights `(1−f)²/2`,
/// `f²/2` and `1 − w₀ − w₂` (at most 4 roundings each, values ≤ 1), and the axis's weighted sum
/// of 3 values (3 products and 2 sums, which an FMA may fuse): 9 per axis.
pub const WAVELET_AXIS_ROUNDINGS: f64 = 9.0;

/// Wavelet noise (Cook & DeRose 2005; `spectex_model::wavelet`). Both sides read the same f32
/// tile at the same indices and f32 fractions (located on the host by one function). Per band
/// `b`, the value `a_b · Σ w T` has magnitude at most `|a_b| · max|T|` (the weights of each axis
/// sum to 1 and are non-negative), computed with [`WAVELET_AXIS_ROUNDINGS`] per axis over `d`
/// axes plus the product by `a_b` and the accumulation (2): each side is within
/// `(9d + 2)·u·|a_b|·max|T|` of the exact value, so the two sides within twice that; the final
/// `mean + acc` and the band order add [`SUMMATION_ROUNDINGS`] of `|mean| + Σ|a_b|·max|T|`.
#[must_use]
pub fn wavelet(m: &WaveletNoise) -> Tolerance {
    let u = F32_UNIT_ROUNDOFF;
    let peak = m
        .tile()
        .values
        .iter()
        .fold(0.0f64, |a, &v| a.max(f64::from(v).abs()));
    let per_band = 2.0 * (WAVELET_AXIS_ROUNDINGS * f64::from(m.dimensions) + 2.0) * u;
    let bands: f64 = m
        .bands()
        .iter()
        .map(|b| f64::from(b.amplitude).abs() * peak)
        .sum();
    let magnitude = f64::from(m.mean).abs() + bands;
    Tolerance::from_max(per_band * bands + SUMMATION_ROUNDINGS * u * magnitude)
}

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

/// Texture by example (Gilet et al. 2014, §5–6; `spectex_model::texture`): one tolerance per
/// output component (1 grey, 3 RGB). Per channel:
/// - the random-phase strata, an LRP noise with the channel's mean: [`lrp`] (0 without strata:
///   both sides output the mean exactly);
/// - the structure: per block `B`, each cosine `A cos 2π((k·u)/N + φ)` with `|u| ≤ N/2`, so the
///   phase is at most `|k|₁/2 + 1` turns, rounded [`PHASE_ROUNDINGS`] times, plus
///   [`COS_ABS_ERROR`], on each side, and the block sum's [`SUMMATION_ROUNDINGS`]: `e_B`. The
///   4 blocks' weights sum to 1, each off by [`TEXTURE_WEIGHT_ABS_ERROR`] times `S = max Σ_B A`;
///   the taps weigh the structure by [`PLACEMENT_TAP_SUM`] at most, with 4 more weights:
///   `2·max e_B + 12·W·S`;
/// - the turbulence: its strata are LRP noises (the sum of `|n_S|` is 1-Lipschitz in each), so
///   the displacement differs by at most `δd = σ·Σ_S lrp(S)` plus 2 roundings of `|d|`; the
///   structure's slope along an axis is at most `2π·max_B Σ A|k|_∞/N` (the cosines) plus
///   `π·S/Δ_R` (the blend weights, `|h'| ≤ π/(2Δ_R)`, two per axis; none when `b = 1`), so the
///   taps add `Σ|ω|·2·slope·δd` over the two axes;
/// - the channel's values (mean, strata, `2S`) summed with [`SUMMATION_ROUNDINGS`].
///
/// The colour basis adds `Σ_c |B_ic|·E_c` and the summation of its row. On lavapipe the strata
/// and the displacement are bit-identical to the CPU (the LRP path), so what is measured is the
/// structure's rounding alone; the turbulence term keeps the bound valid on drivers where the
/// LRP renders differ in the last bits.
#[must_use]
pub fn texture(m: &TextureModel) -> Vec<Tolerance> {
    let u = F32_UNIT_ROUNDOFF;
    let strata_magnitude = |strata: &[Stratum]| -> f64 {
        strata
            .iter()
            .map(|s| f64::from(s.amplitude).abs() * 9.0 * s.sub_strata.len() as f64)
            .sum()
    };
    let displacement = m.turbulence.as_ref().map_or(0.0, |t| {
        let sigma = f64::from(t.sigma).abs();
        let strata: f64 = t
            .strata
            .iter()
            .enumerate()
            .map(|(s, st)| {
                lrp(&LrpNoise {
                    seed: t.seed(0, s),
                    mean: 0.0,
                    strata: vec![st.clone()],
                })
                .max_abs
            })
            .sum();
        let largest = sigma * (strata_magnitude(&t.strata) + f64::from(t.centre).abs());
        sigma * strata + 2.0 * u * largest
    });
    // (bound, magnitude) per channel.
    let channels: Vec<(f64, f64)> = m
        .channels
        .iter()
        .map(|ch| {
            let mut magnitude = f64::from(ch.mean).abs() + strata_magnitude(&ch.strata);
            let mut bound = if ch.strata.is_empty() {
                0.0
            } else {
                lrp(&LrpNoise {
                    seed: ch.seed,
                    mean: ch.mean,
                    strata: ch.strata.clone(),
                })
                .max_abs
            };
            if let Some(s) = &ch.structure {
                let StructureBounds {
                    error: e_max,
                    sum: s_max,
                    slope,
                } = structure_bounds(m.period, s);
                bound += PLACEMENT_TAP_SUM * e_max
                    + 12.0 * TEXTURE_WEIGHT_ABS_ERROR * s_max
                    + PLACEMENT_TAP_SUM * 2.0 * slope * displacement;
                magnitude += PLACEMENT_TAP_SUM * s_max;
            }
            (bound + SUMMATION_ROUNDINGS * u * magnitude, magnitude)
        })
        .collect();
    match &m.colour {
        None => channels
            .iter()
            .map(|&(bound, _)| Tolerance::from_max(bound))
            .collect(),
        Some(c) => (0..3)
            .map(|i| {
                let (mut bound, mut magnitude) = (0.0, f64::from(c.mean[i]).abs());
                for (k, &(e, v)) in channels.iter().enumerate() {
                    let b = f64::from(c.basis[i][k]).abs();
                    bound += b * e;
                    magnitude += b * v;
                }
                Tolerance::from_max(bound + SUMMATION_ROUNDINGS * u * magnitude)
            })
            .collect(),
    }
}

/// Bounds of one channel's structure `n_R` ([`texture`]): the rounding error `e_B` of its
/// worst block, the largest `Σ A` of a block (`|n_R| ≤` it: the block weights are a partition of
/// unity), and its slope along an axis, `2π·max_B Σ A|k|_∞/N` (the cosines) plus `π·S/Δ_R` (the
/// blend weights, `|h'| ≤ π/(2Δ_R)`, two per axis; none when `b = 1`).
struct StructureBounds {
    error: f64,
    sum: f64,
    slope: f64,
}

fn structure_bounds(period: u32, s: &spectex_model::Structure) -> StructureBounds {
    let u = F32_UNIT_ROUNDOFF;
    let tau = std::f64::consts::TAU;
    let n = f64::from(2 * period / s.blocks);
    let delta = f64::from(period / s.blocks);
    let k1 =
        |c: &FixedCosine| f64::from(c.frequency[0].unsigned_abs() + c.frequency[1].unsigned_abs());
    let kmax = |c: &FixedCosine| {
        f64::from(
            c.frequency[0]
                .unsigned_abs()
                .max(c.frequency[1].unsigned_abs()),
        )
    };
    let (mut e_max, mut s_max, mut g_max) = (0.0f64, 0.0f64, 0.0f64);
    for block in &s.cosines {
        let a: f64 = block.iter().map(|c| f64::from(c.amplitude)).sum();
        let e: f64 = block
            .iter()
            .map(|c| {
                let turns = k1(c) / 2.0 + 1.0;
                let phase = tau * PHASE_ROUNDINGS * u * turns;
                f64::from(c.amplitude) * 2.0 * (phase + COS_ABS_ERROR)
            })
            .sum::<f64>()
            + SUMMATION_ROUNDINGS * u * a;
        let g: f64 = block.iter().map(|c| f64::from(c.amplitude) * kmax(c)).sum();
        e_max = e_max.max(e);
        s_max = s_max.max(a);
        g_max = g_max.max(g);
    }
    let weights_slope = if s.blocks == 1 {
        0.0
    } else {
        std::f64::consts::PI * s_max / delta
    };
    StructureBounds {
        error: e_max,
        sum: s_max,
        slope: tau * g_max / n + weights_slope,
    }
}

/// Gabor noise (Lagae et al. 2009): impulses of the 3×3 cells around a pixel, each `K·w`
/// (|w| ≤ 1) times a Gaussian ≤ 1 times a cosine. The count is Poisson of mean `9λ`
/// (λ impulses per cell); we bound it by `9λ + 6√(9λ) + 6`, which a Poisson variable exceeds
/// with probability below 1e-9, so over the ≤ 10⁵ pixels of a cross-check window no pixel is
/// expected to exceed it. Per impulse: the cosine's phase error (offsets within 2 cells, so
/// `|F₀·d| ≤ 2.83·F₀·r` turns; an isotropic direction adds two cosines of error
/// [`COS_ABS_ERROR`] times that many turns), [`COS_ABS_ERROR`], [`EXP_REL_ERROR`], on each side.
#[must_use]
pub fn gabor(m: &GaborNoise) -> Tolerance {
    let lambda = 9.0 * m.impulses_per_cell();
    let count = lambda + 6.0 * lambda.sqrt() + 6.0;
    let turns = 2.83 * f64::from(m.frequency) * m.kernel_radius();
    let phase = std::f64::consts::TAU
        * (PHASE_ROUNDINGS * F32_UNIT_ROUNDOFF * (turns + 1.0) + 2.0 * COS_ABS_ERROR * turns);
    let per_term = 2.0 * (phase + COS_ABS_ERROR + EXP_REL_ERROR);
    let k = f64::from(m.amplitude).abs();
    let magnitude = k * count + f64::from(m.mean).abs();
    Tolerance::from_max(k * count * per_term + SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * magnitude)
}

/// Difference between the two sides' `fade(t) = t³(t(6t − 15) + 10)`, `t ∈ [0, 1]`, from
/// identical `t`: a compiler may contract `t·6 − 15` (skipping a rounding of `|6t| ≤ 6`) and
/// `(·)·t + 10` (skipping one of a product `≤ 15`); the difference then passes through products
/// by `t ≤ 1` and `t³ ≤ 1`, which round alike on both sides up to a unit roundoff of the result
/// (≤ 1): `(6 + 15 + 1)·2⁻²⁴`, rounded up to `24·2⁻²⁴`.
pub const FADE_ABS_ERROR: f64 = 24.0 * F32_UNIT_ROUNDOFF;

/// Error of a simplex corner offset (cell units, per coordinate) between the two sides. The CPU
/// rounds the f64 offset to f32 once (`1·2⁻²⁴` of a value below 1). The GPU builds the skewed
/// fraction from 2 (2D) or 3 (3D) per-axis f32 fractions, each rounded from f64 (`≤ 2⁻²⁴`), summed
/// (≤ 2 roundings of values below 3: `6·2⁻²⁴`), so the fraction is within `9·2⁻²⁴`; the offset
/// `x₀ = f_x − (Σf)·G` adds `3·9·2⁻²⁴·G ≤ 5·2⁻²⁴` (G ≤ 0.22) and 3 roundings of values ≤ 3;
/// each corner's `(x₀ − i₁) + G` rounds twice more on each side (values ≤ 1.5: `6·2⁻²⁴`). In all
/// `≤ 1 + 9 + 5 + 9 + 6 = 30` unit roundoffs, rounded up to 32.
pub const SIMPLEX_OFFSET_ERROR: f64 = 32.0 * F32_UNIT_ROUNDOFF;

/// Rounding difference of one simplex corner term `max(0, r² − |δ|²)⁴ (g·δ)` from identical
/// `δ`: contracting the squared norm skips up to 2 roundings of values ≤ 1 and the subtraction
/// rounds a value ≤ 0.6 (`Δt ≤ 3·2⁻²⁴`), amplified by `d(t⁴)/dt = 4t³ ≤ 0.87` and `|g·δ| ≤ √2·0.78`
/// (`≤ 4·2⁻²⁴`), plus the final products' roundings of a value ≤ 0.2: `5·2⁻²⁴`.
pub const SIMPLEX_TERM_ERROR: f64 = 5.0 * F32_UNIT_ROUNDOFF;

/// Relative error of WGSL's `sqrt` (the spec inherits it from `1/inverseSqrt`: 2 + 2.5 ulps,
/// one ulp being at most `2·2⁻²⁴` relative) plus the CPU's correctly rounded one: `10 + 1` unit
/// roundoffs, and 1 more for a contracted `dx² + dy² (+ dz²)` (2 skipped roundings relative to
/// the squared distance, halved by the square root): 12.
pub const WORLEY_SQRT_ROUNDINGS: f64 = 12.0;

/// The largest Worley distance kept, cell units (`WORLEY_MAX_RING + 1`).
const WORLEY_CAP: f64 = (WORLEY_MAX_RING + 1) as f64;

/// `max |basis|` and `L`, a bound on the norm of its gradient (per cell unit), of simplex noise
/// in `d` dimensions: `d + 1` kernels `(r² − s)⁴ (g·δ)`, `s = |δ|²`, `|g| ≤ √2` (Perlin's
/// cube-edge gradients), times the output scale. `(r² − s)⁴√s` peaks at `s = r²/9`; the
/// kernel's gradient norm is at most `√2 (r² − s)³ (r² + 7s)`, which peaks at `s = r²/14`.
fn simplex_bounds(three_d: bool) -> (f64, f64) {
    let (r2, scale, corners) = if three_d {
        (f64::from(SIMPLEX3_R2), f64::from(SIMPLEX3_SCALE), 4.0)
    } else {
        (f64::from(SIMPLEX2_R2), f64::from(SIMPLEX2_SCALE), 3.0)
    };
    let s = r2 / 9.0;
    let value = (r2 - s).powi(4) * s.sqrt();
    let s = r2 / 14.0;
    let slope = (r2 - s).powi(3) * (r2 + 7.0 * s);
    let k = scale * corners * std::f64::consts::SQRT_2;
    (k * value, k * slope)
}

/// The classic noises (`spectex_model::classic`): both sides evaluate the same f32 formulas from
/// bit-identical hashes and feature points. Per octave, a bound `e` on the difference of the
/// basis and a bound `N` on `|basis|`:
/// - **gradient / value** (`d` = 2 or 3 lerp levels): the host hands the GPU the CPU's own f32
///   offsets, and a corner value is one addition of them (or an exact lattice value), so corners
///   agree bit for bit. A level `a + s(b − a)` adds `|b − a|·`[`FADE_ABS_ERROR`] and 2 roundings
///   of values ≤ `|b − a|` (a contracted product) and ≤ `N` (the sum): with `|b − a| ≤ 2N`,
///   `e = d·(2N·FADE + 4N·2⁻²⁴)`; `N = 2` for gradients (`|g·δ| ≤ |δ_u| + |δ_v| ≤ 2`), 1 for values.
/// - **simplex**: the GPU forms the offsets from per-axis skew parts, so they differ by
///   [`SIMPLEX_OFFSET_ERROR`] per coordinate, worth `L·√d·SIMPLEX_OFFSET_ERROR` with `L` the
///   noise's Lipschitz bound ([`simplex_bounds`]), plus `(d + 1)` corners'
///   [`SIMPLEX_TERM_ERROR`] and the 3 sums, times the output scale. A near-tie in the choice of
///   the skewed cell or of the simplex in it can make the two sides use different simplices: in
///   2D, `r² = ½` equals the squared distance from a corner to the opposite edge, so each
///   kernel vanishes there and the noise is continuous; in 3D, Gustavson's `r² = 0.6` exceeds the
///   squared corner-to-face distance ½, so the noise jumps by up to `scale·(0.6 − ½)⁴·|g·δ|`,
///   `|g·δ| ≤ √2·√½ = 1`, for the corner that leaves and the one that enters: `2·32·10⁻⁴`.
///   Such ties are not rare on a pixel grid: where `x − y` is a multiple of the cell side,
///   `x₀ = y₀` exactly, and the two sides' roundings break the tie differently (measured on
///   lavapipe: `1.04·10⁻³` at amplitude ½ in `testdata/models/classic-simplex-3d.json`).
/// - **Worley**: offsets and feature points are bit-identical; Manhattan and Chebyshev distances
///   are sums, `abs` and `max` only, so they agree exactly; a Euclidean distance differs by
///   [`WORLEY_SQRT_ROUNDINGS`] relative. `F_n`, the `n`-th smallest distance, is 1-Lipschitz in
///   the largest change of any one distance, so a near-tie between candidates may swap which
///   point is nearest but moves `F_n` no more than the distances move; so does a search that
///   stops one ring earlier or later on a near-tie with the ring's gap (the points beyond lie at
///   least the gap away). Distances are at most `7` cells, so
///   `e = Σ|C_k|·7·(WORLEY_SQRT_ROUNDINGS + 4)·2⁻²⁴` (4: the contracted, rounded sum of
///   `C_k F_k`), `N = 7·Σ|C_k|`.
///
/// The fractal sum: fBm and turbulence add `gain^o·e_o` (`|·|` is 1-Lipschitz). Ridged:
/// `s_o = (offset − |n_o|)²·clamp(w·s_{o−1}, 0, 1)` with `|offset − |n|| ≤ A = max(offset,
/// N − offset)`, so `e'_o = 2A·e_o + A²·w·e'_{o−1}`, and the sum adds `gain^o·e'_o`. Then
/// `|amplitude|` times the sum, plus [`SUMMATION_ROUNDINGS`] of the magnitudes
/// `|mean| + |amplitude|·Σ gain^o·N_o` (the accumulation, a contracted `w·n + acc`, the last
/// `mean + amplitude·acc`).
#[must_use]
pub fn classic(m: &ClassicNoise) -> Tolerance {
    let u = F32_UNIT_ROUNDOFF;
    let three_d = m.dimensions == 3;
    let d = f64::from(m.dimensions);
    let (e, n) = match &m.basis {
        Basis::Gradient | Basis::Value => {
            let n = if m.basis == Basis::Gradient { 2.0 } else { 1.0 };
            (d * (2.0 * n * FADE_ABS_ERROR + 4.0 * n * u), n)
        }
        Basis::Simplex => {
            let (n, lipschitz) = simplex_bounds(three_d);
            let (scale, corners) = if three_d {
                (f64::from(SIMPLEX3_SCALE), 4.0)
            } else {
                (f64::from(SIMPLEX2_SCALE), 3.0)
            };
            let seam = if three_d {
                2.0 * scale * (f64::from(SIMPLEX3_R2) - 0.5).powi(4)
            } else {
                0.0
            };
            let e = lipschitz * d.sqrt() * SIMPLEX_OFFSET_ERROR
                + scale * (corners * SIMPLEX_TERM_ERROR + 3.0 * u * n / scale)
                + seam;
            (e, n)
        }
        Basis::Worley(w) => {
            let c: f64 = w.coefficients.iter().map(|c| f64::from(*c).abs()).sum();
            let per_distance = if w.metric == Metric::Euclidean {
                WORLEY_SQRT_ROUNDINGS
            } else {
                0.0
            };
            (c * WORLEY_CAP * (per_distance + 4.0) * u, c * WORLEY_CAP)
        }
    };
    let (sum, magnitude) = octave_sum(m, n, |_| e);
    let amplitude = f64::from(m.amplitude).abs();
    Tolerance::from_max(
        amplitude * sum
            + SUMMATION_ROUNDINGS * u * (f64::from(m.mean).abs() + amplitude * magnitude),
    )
}

/// A per-octave bound `t_o` (an error, a slope or a jump of the basis, `|basis| ≤ n`) carried
/// through the fractal sum: `Σ gain^o·t_o` for fBm and turbulence (`|·|` is 1-Lipschitz);
/// for ridged, `s_o = (offset − |n_o|)²·clamp(w·s_{o−1}, 0, 1)` with `|offset − |n|| ≤ A =
/// max(offset, n − offset)` gives `t'_o = 2A·t_o + A²·w·t'_{o−1}` and `Σ gain^o·t'_o`. Also
/// returns the bound on `Σ gain^o·|term|` (`n`, or `A²` for ridged).
fn octave_sum(m: &ClassicNoise, n: f64, term: impl Fn(u32) -> f64) -> (f64, f64) {
    let (mut sum, mut magnitude, mut previous) = (0.0, 0.0, 0.0);
    for o in 0..m.octaves() {
        let weight = f64::from(m.octave_weight(o)).abs();
        let t = term(o);
        match m.fractal.as_ref().map(|f| f.kind) {
            Some(FractalKind::Ridged {
                offset,
                weight_gain,
            }) => {
                let offset = f64::from(offset);
                let a = offset.max(n - offset);
                let mut carried = 2.0 * a * t;
                if o > 0 {
                    carried += a * a * f64::from(weight_gain) * previous;
                }
                previous = carried;
                sum += weight * carried;
                magnitude += weight * a * a;
            }
            _ => {
                sum += weight * t;
                magnitude += weight * n;
            }
        }
    }
    (sum, magnitude)
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

/// Largest slope `|∂g/∂d|` of a Gaussian `exp(−π b²d²)`: `b·√(2π)·e^{−½}`, per pixel.
fn gaussian_slope(bandwidth: f64) -> f64 {
    bandwidth * (2.0 * std::f64::consts::PI).sqrt() * (-0.5f64).exp()
}

/// A pixel's bound on the impulses of 3×3 (3×3×3) cells of mean `lambda` each, as in
/// [`gabor`]: exceeded with probability below 1e-9.
fn impulse_count(cells: f64, lambda: f64) -> f64 {
    let n = cells * lambda;
    n + 6.0 * n.sqrt() + 6.0
}

/// How a model's value can change when its position moves by `δ` pixels:
/// `|v(p + δ) − v(p)| ≤ slope·|δ| + jump` (`jump` for truncated kernels, which cut at 5% of
/// their peak: any of them may enter or leave the support), with `cell` the grid side over which
/// the GPU relocates a displaced point and `magnitude` a bound on `|v|`. `None` where no bound
/// is derived (phase-based phasor outputs, whose slope is unbounded where `|𝒢| → 0`).
///
/// Wavelet noise: see the derivation in the code (B-spline weights' derivatives).
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

/// [`Regularity`] of `model`, by kind (see there).
#[must_use]
pub fn regularity(model: &Model) -> Option<Regularity> {
    let tau = std::f64::consts::TAU;
    match model {
        Model::Lrp(m) => {
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
        Model::Gabor(m) => {
            let terms = f64::from(m.amplitude).abs() * impulse_count(9.0, m.impulses_per_cell());
            Some(Regularity {
                slope: terms
                    * (tau * f64::from(m.frequency) + gaussian_slope(f64::from(m.bandwidth))),
                jump: terms * GABOR_TRUNCATION,
                magnitude: terms + f64::from(m.mean).abs(),
                cell: m.kernel_radius(),
            })
        }
        Model::Phasor(m) => phasor_regularity(m),
        Model::Classic(m) => Some(classic_regularity(m)),
        Model::Texture(m) => Some(texture_regularity(m)),
        Model::Wavelet(m) => {
            // Quadratic B-spline weights have derivatives −(1 − f), 1 − 2f, f: Σ|w'| ≤ 2, so a
            // band changes by at most 2·max|tile| per sample along an axis (the other axes'
            // weights form a convex combination), √2 of it for the plane; per pixel over the
            // band's sample side c_b, times |a_b|.
            let peak = m
                .tile()
                .values
                .iter()
                .fold(0.0f64, |a, &v| a.max(f64::from(v).abs()));
            let bands = m.bands();
            let slope = bands
                .iter()
                .map(|b| {
                    f64::from(b.amplitude).abs() * 2.0 * std::f64::consts::SQRT_2 * peak / b.side
                })
                .sum();
            let magnitude = bands
                .iter()
                .map(|b| f64::from(b.amplitude).abs() * peak)
                .sum::<f64>()
                + f64::from(m.mean).abs();
            Some(Regularity {
                slope,
                jump: 0.0,
                magnitude,
                cell: bands.iter().map(|b| b.side).fold(0.0, f64::max),
            })
        }
        Model::Warp(w) => {
            // v(p) = b(p + d(p)): moving p by δ moves the base's point by δ + |s|·(slope of x
            // or y)·δ per axis, √2 for the two axes together.
            let b = regularity(&w.base)?;
            let (x, y) = (regularity(&w.x)?, regularity(&w.y)?);
            let s = f64::from(w.strength).abs();
            let spread = 1.0 + std::f64::consts::SQRT_2 * s * x.slope.max(y.slope);
            let jumps = std::f64::consts::SQRT_2 * s * x.jump.max(y.jump);
            Some(Regularity {
                slope: b.slope * spread,
                // A jump of x or y moves the base's point by |s|·jump at most.
                jump: b.jump + b.slope * jumps,
                magnitude: b.magnitude,
                cell: b.cell,
            })
        }
    }
}

/// The classic noises, per octave in cell units (the basis `N` and its gradient norm `L`):
/// - **value**: `∂n/∂x` is a lerp of `fade'(t)·(b − a)` with `fade' ≤ 30/16` and
///   `|b − a| ≤ 2`: 3.75 per axis, `N = 1`;
/// - **gradient**: corner values `g·δ` with `|g·δ| ≤ 2` and `|∂(g·δ)/∂x| = |g_x| ≤ 1`:
///   `1.875·4 + 1 = 8.5` per axis, `N = 2`;
/// - **simplex**: [`simplex_bounds`]; 3D noise also jumps at simplex faces by
///   `2·scale·(0.6 − ½)⁴` (see [`classic`]);
/// - **Worley**: a distance is 1-Lipschitz in the Euclidean and Chebyshev metrics and
///   `√d`-Lipschitz in the Manhattan one, and so is `F_n` (an order statistic) and its cap:
///   `Σ|C_k|` times that, `N = 7·Σ|C_k|`.
///
/// A per-axis bound becomes a gradient norm by `√d`. Octave `o` divides by its cell side
/// `c_o` pixels; fBm and turbulence add `gain^o` times it (`|·|` is 1-Lipschitz); ridged
/// follows `s_o = (offset − |n_o|)²·clamp(w·s_{o−1}, 0, 1)`: `s'_o ≤ 2A·n'_o + A²·w·s'_{o−1}`,
/// jumps alike. Times `|amplitude|`; `cell` is the first octave's side.
fn classic_regularity(m: &ClassicNoise) -> Regularity {
    let d = f64::from(m.dimensions);
    let three_d = m.dimensions == 3;
    let (lipschitz, n, jump) = match &m.basis {
        Basis::Value => (3.75 * d.sqrt(), 1.0, 0.0),
        Basis::Gradient => (8.5 * d.sqrt(), 2.0, 0.0),
        Basis::Simplex => {
            let (n, l) = simplex_bounds(three_d);
            let seam = if three_d {
                2.0 * f64::from(SIMPLEX3_SCALE) * (f64::from(SIMPLEX3_R2) - 0.5).powi(4)
            } else {
                0.0
            };
            (l, n, seam)
        }
        Basis::Worley(w) => {
            let c: f64 = w.coefficients.iter().map(|c| f64::from(*c).abs()).sum();
            let metric = if w.metric == Metric::Manhattan {
                d.sqrt()
            } else {
                1.0
            };
            (c * metric, c * WORLEY_CAP, 0.0)
        }
    };
    let (slope, magnitude) = octave_sum(m, n, |o| lipschitz / m.octave_cell(o));
    let (jumps, _) = octave_sum(m, n, |_| jump);
    let amplitude = f64::from(m.amplitude).abs();
    Regularity {
        slope: amplitude * slope,
        jump: amplitude * jumps,
        magnitude: f64::from(m.mean).abs() + amplitude * magnitude,
        cell: m.octave_cell(0),
    }
}

/// A texture by example, per channel (gradient norms, per pixel):
/// - the strata: the LRP bound of [`regularity`];
/// - the structure at the taps: `Σ|ω| ≤ 2` ([`PLACEMENT_TAP_SUM`]) times `√2·slope_R`
///   ([`structure_bounds`], per axis) times the norm of `∂q/∂p`, `1 + √2·σ·Σ_S L_S` (the
///   turbulence `σ(Σ_S|n_S| − c)` per axis, `|·|` 1-Lipschitz, `L_S` its strata's LRP slopes);
/// - the placement weights (random placement): a cell's axis weight `g = sin²(πa/2)`, `a`
///   crossing `2·PLACEMENT_BLEND` cells of side `P = T/2`, changes by at most `γ = 2π/P` per
///   pixel; the taps' raw weights `w_k` sum to 1 with `Σw² ≥ ¼`, so the normalised
///   `ω_k = w_k/√Σw²` change by at most `γ/√Σw² + w_k·γ/(Σw²)^{3/2} ≤ 2γ + 8w_kγ`, in all
///   `≤ 16γ` per axis, times `|n_R| ≤ S`, `√2` for the norm.
///
/// The colour rows add `Σ_c |B_ic|` of them; the slope is the largest component's. No jumps (the
/// placement is cross-faded, the structure periodic); `cell` the largest grid the GPU relocates
/// on (the placement cell or a stratum's window).
fn texture_regularity(m: &TextureModel) -> Regularity {
    let root2 = std::f64::consts::SQRT_2;
    let lrp_of = |seed: u32, mean: f32, strata: &[Stratum]| {
        regularity(&Model::Lrp(LrpNoise {
            seed,
            mean,
            strata: strata.to_vec(),
        }))
    };
    let p = m.placement_cell();
    let mut cell = p;
    let turbulence = m.turbulence.as_ref().map_or(0.0, |t| {
        f64::from(t.sigma).abs()
            * t.strata
                .iter()
                .filter_map(|st| lrp_of(0, 0.0, std::slice::from_ref(st)))
                .map(|r| {
                    cell = cell.max(r.cell);
                    r.slope
                })
                .sum::<f64>()
    });
    let gamma = std::f64::consts::TAU / p;
    let channels: Vec<(f64, f64)> = m
        .channels
        .iter()
        .map(|ch| {
            let (mut slope, mut magnitude) = (0.0, f64::from(ch.mean).abs());
            if let Some(r) = lrp_of(ch.seed, 0.0, &ch.strata).filter(|_| !ch.strata.is_empty()) {
                slope += r.slope;
                magnitude += r.magnitude;
                cell = cell.max(r.cell);
            }
            if let Some(s) = &ch.structure {
                let b = structure_bounds(m.period, s);
                slope += PLACEMENT_TAP_SUM * root2 * b.slope * (1.0 + root2 * turbulence);
                if m.random_placement {
                    slope += 16.0 * gamma * b.sum * root2;
                }
                magnitude += PLACEMENT_TAP_SUM * b.sum;
            }
            (slope, magnitude)
        })
        .collect();
    let (slope, magnitude) = match &m.colour {
        None => channels
            .iter()
            .fold((0.0f64, 0.0f64), |a, c| (a.0.max(c.0), a.1.max(c.1))),
        Some(c) => (0..3).fold((0.0f64, 0.0f64), |a, i| {
            let row = |k: usize| f64::from(c.basis[i][k]).abs();
            let slope: f64 = channels.iter().enumerate().map(|(k, v)| row(k) * v.0).sum();
            let magnitude: f64 = f64::from(c.mean[i]).abs()
                + channels
                    .iter()
                    .enumerate()
                    .map(|(k, v)| row(k) * v.1)
                    .sum::<f64>();
            (a.0.max(slope), a.1.max(magnitude))
        }),
    };
    Regularity {
        slope,
        jump: 0.0,
        magnitude,
        cell,
    }
}

/// Phasor noise's Gabor (`Im 𝒢`) and intensity (`|𝒢|`) outputs: each kernel changes at most
/// by `2π F_max + gaussian slope` per pixel and jumps by [`PHASOR_TRUNCATION`] at its radius.
fn phasor_regularity(m: &PhasorNoise) -> Option<Regularity> {
    if !matches!(m.output, PhasorOutput::Gabor | PhasorOutput::Intensity) {
        return None;
    }
    let cells = if m.dimensions == 3 { 27.0 } else { 9.0 };
    let terms = f64::from(m.amplitude).abs() * impulse_count(cells, m.impulses_per_cell());
    let slope = std::f64::consts::TAU * m.frequency.range().1.min(0.5)
        + gaussian_slope(m.bandwidth_range().1);
    Some(Regularity {
        slope: terms * slope,
        jump: terms * PHASOR_TRUNCATION,
        magnitude: terms + f64::from(m.mean).abs(),
        cell: m.kernel_radius(),
    })
}

/// The CPU–GPU bound of a model's value wherever a warp may use it: [`tolerance`], and for
/// phasor noise's Gabor and intensity outputs the complex sum's bound
/// ([`crate::phasor::complex_bound`], `√2` of it for the intensity) times the amplitude.
fn value_tolerance(model: &Model) -> Option<f64> {
    match model {
        Model::Phasor(m) => {
            let e = crate::phasor::complex_bound(m) * f64::from(m.amplitude).abs();
            match m.output {
                PhasorOutput::Gabor => Some(e),
                PhasorOutput::Intensity => Some(std::f64::consts::SQRT_2 * e),
                _ => None,
            }
        }
        other => tolerance(other).map(|t| t.max_abs),
    }
}

/// Domain warping (`spectex_model::warp`): `v(p) = b(p + d(p))`. The two sides evaluate the
/// base at points `δ` apart, where per axis
/// - the displacement differs by `|s|·E_{x,y}` (the clamp is 1-Lipschitz; `E` the x or y
///   model's own bound);
/// - `s·v` and, for a displaced warp, the f32 sum of displacements round on the GPU:
///   2 roundings of `|d| ≤ D = min(MAX_WARP, |s|·max|v|)` per warp level;
/// - the GPU relocates the point in f32 (`common.wgsl`, `warp_relocate`): offset plus
///   displacement, the cell shift and the rebuilt offsets, 4 roundings of values up to
///   `D + 3·cell`; the CPU's f64 sum rounds below that.
///
/// so `|δ| ≤ √2·(|s|·max E + 6·u·(D + 3·cell))`. The base's bound, plus its
/// [`Regularity`] over `δ` (`slope·|δ| + jump`), is the warp's largest error. `None` when a
/// sub-model has no derived bound.
///
/// The mean: a truncated kernel's jump shows only at the pixels within `|δ|` of its support's
/// circle (radius `r`, the regularity's `cell`): the annulus `2πr·2|δ|` over the disc `πr²`, a
/// share `4|δ|/r` of the pixels it covers, for kernels at random positions. As `jump` already
/// sums every kernel that can reach a pixel, the jumps add at most `jump·min(1, 4|δ|/r)` to the
/// mean, the smooth part [`MEAN_FRACTION`] of its bound as for every model.
#[must_use]
pub fn warp(w: &Warp) -> Option<Tolerance> {
    let base = value_tolerance(&w.base)?;
    let b = regularity(&w.base)?;
    let (ex, ey) = (value_tolerance(&w.x)?, value_tolerance(&w.y)?);
    let (x, y) = (regularity(&w.x)?, regularity(&w.y)?);
    let s = f64::from(w.strength).abs();
    let reach = f64::from(MAX_WARP) * spectex_model::warp::depth(&Model::Warp(w.clone())) as f64;
    let d = (s * x.magnitude.max(y.magnitude)).min(reach);
    let delta =
        std::f64::consts::SQRT_2 * (s * ex.max(ey) + 6.0 * F32_UNIT_ROUNDOFF * (d + 3.0 * b.cell));
    let smooth = base + b.slope * delta;
    let near = if b.cell > 0.0 {
        (4.0 * delta / b.cell).min(1.0)
    } else {
        1.0
    };
    Some(Tolerance {
        max_abs: smooth + b.jump,
        mean_abs: MEAN_FRACTION * smooth + b.jump * near,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use spectex_model::{Orientation, Stratum};

    /// The window falls from 1 to 0 over 1.5 widths, so its steepest slope is above 1/1.5;
    /// numerically it is ≈ 1.27 (the f64 window's own values, not a fitted constant).
    #[test]
    fn kaiser_bessel_slope_is_plausible() {
        let k = kaiser_bessel_slope();
        assert!(k > 1.0 / 1.5 && k < 2.0, "{k}");
    }

    /// The slope bounds of the classic noises, wavelet noise and a texture hold on fine CPU
    /// renders: along rows and columns sampled every 1/16 pixel, no step changes the value by
    /// more than `slope·step + jump`, and the bound is within a factor (12, or 150 for the
    /// texture) of the steepest step seen (so it is not vacuous).
    #[test]
    fn classic_slope_bounds_hold_on_fine_renders() {
        let model = |basis: Basis, dimensions: u32, fractal: Option<FractalKind>| ClassicNoise {
            seed: 5,
            dimensions,
            cell_size: 8.0,
            basis,
            fractal: fractal.map(|kind| spectex_model::classic::Fractal {
                kind,
                octaves: 3,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude: 0.7,
            mean: 0.1,
        };
        let worley = |metric| {
            Basis::Worley(spectex_model::classic::Worley {
                metric,
                coefficients: [-1.0, 1.0, 0.0, 0.0],
                points: spectex_model::classic::FeaturePoints::Fixed(2),
            })
        };
        let ridged = FractalKind::Ridged {
            offset: 1.0,
            weight_gain: 2.0,
        };
        for (name, m) in [
            ("value", model(Basis::Value, 2, None)),
            ("gradient", model(Basis::Gradient, 2, None)),
            ("gradient 3d", model(Basis::Gradient, 3, None)),
            ("simplex", model(Basis::Simplex, 2, None)),
            (
                "worley manhattan",
                model(worley(Metric::Manhattan), 2, None),
            ),
            (
                "worley euclidean",
                model(worley(Metric::Euclidean), 2, None),
            ),
            ("fbm", model(Basis::Gradient, 2, Some(FractalKind::Fbm))),
            ("ridged", model(Basis::Value, 2, Some(ridged))),
        ] {
            let m = Model::Classic(m);
            check_slope_on_fine_render(name, &m, 12.0);
        }
        let mut wavelet: WaveletNoise = serde_json::from_str(
            r#"{"seed": 3, "dimensions": 2, "tile_size": 32, "cell_size": 6.0,
                "bands": [1.0, 0.5], "amplitude": 0.4, "mean": 0.5}"#,
        )
        .unwrap();
        let grey = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../testdata/models/texture-synthetic-grey.json"
        ))
        .unwrap();
        // The texture's bound sums the worst case of every one of its strata's 9·J cosines and of
        // the turbulence's: valid, and measured 100× the steepest step on this model.
        check_slope_on_fine_render("texture", &spectex_model::from_json(&grey).unwrap(), 150.0);
        check_slope_on_fine_render("wavelet 2d", &Model::Wavelet(wavelet.clone()), 12.0);
        wavelet.dimensions = 3;
        check_slope_on_fine_render("wavelet 3d", &Model::Wavelet(wavelet), 12.0);
    }

    /// Renders `m` every 1/16 pixel and checks its steepest step against [`regularity`]: within
    /// the bound, and the bound within `factor` of it.
    fn check_slope_on_fine_render(name: &str, m: &Model, factor: f64) {
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

    /// A warp's bound is the base's at strength 0 plus the GPU's relocation roundings, and it
    /// grows with the strength; kinds without a derivation give none.
    /// A phasor base's truncation jumps set the warp's largest error but only their share
    /// `4|δ|/r` of the mean: the mean bound is the smooth part's quarter plus that share.
    #[test]
    fn warp_mean_counts_jumps_only_near_kernel_boundaries() {
        let mut phasor = spectex_model::fixtures::phasor_pwm(
            2,
            spectex_model::PhasorOrientation::TwoLobes {
                angle_a: 0.4,
                angle_b: 1.2,
            },
        );
        phasor.output = PhasorOutput::Gabor;
        let lrp = Model::Lrp(LrpNoise {
            seed: 1,
            mean: 0.0,
            strata: vec![Stratum {
                window_width: 10.0,
                amplitude: 0.1,
                sub_strata: vec![vec![[0.1, 0.2]]; 4],
            }],
        });
        let w = Warp {
            base: Box::new(Model::Phasor(phasor.clone())),
            x: Box::new(lrp.clone()),
            y: Box::new(lrp),
            strength: 6.0,
        };
        let t = warp(&w).unwrap();
        let r = regularity(&Model::Phasor(phasor)).unwrap();
        let smooth = t.max_abs - r.jump;
        assert!(r.jump > 0.0 && smooth > 0.0);
        assert!(t.mean_abs > MEAN_FRACTION * smooth);
        assert!(
            t.mean_abs < MEAN_FRACTION * smooth + 0.01 * r.jump,
            "{t:?} {r:?}"
        );
    }

    #[test]
    fn warp_bound_grows_with_strength() {
        let lrp = |seed| {
            Model::Lrp(LrpNoise {
                seed,
                mean: 0.0,
                strata: vec![Stratum {
                    window_width: 10.0,
                    amplitude: 0.1,
                    sub_strata: vec![vec![[0.1, 0.2]]; 4],
                }],
            })
        };
        let w = |strength| Warp {
            base: Box::new(lrp(1)),
            x: Box::new(lrp(2)),
            y: Box::new(lrp(3)),
            strength,
        };
        let base = tolerance(&lrp(1)).unwrap().max_abs;
        let at0 = warp(&w(0.0)).unwrap().max_abs;
        // At strength 0 only the GPU's relocation of the point (a few ulps of 3 cells) is left.
        assert!(at0 > base && at0 < 3.0 * base, "{at0} vs {base}");
        assert!(warp(&w(8.0)).unwrap().max_abs > at0);
        // A classic base: its own bound plus its slope (8.5·√2 per cell of 8 px) times the
        // displacement's error, so it grows with the strength.
        let perlin = Model::Classic(ClassicNoise {
            seed: 0,
            dimensions: 2,
            cell_size: 8.0,
            basis: Basis::Gradient,
            fractal: None,
            amplitude: 1.0,
            mean: 0.0,
        });
        let r = regularity(&perlin).unwrap();
        assert!((r.slope - 8.5 * std::f64::consts::SQRT_2 / 8.0).abs() < 1e-12);
        let classic = |strength| Warp {
            base: Box::new(perlin.clone()),
            ..w(strength)
        };
        let own = tolerance(&perlin).unwrap().max_abs;
        let (a, b) = (warp(&classic(1.0)).unwrap(), warp(&classic(4.0)).unwrap());
        assert!(
            own < a.max_abs && a.max_abs < b.max_abs,
            "{own} {a:?} {b:?}"
        );
    }

    /// The bound grows linearly with the amplitude and with the number of cosines.
    #[test]
    fn lrp_bound_scales_with_amplitude_and_terms() {
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

    /// The wavelet bound is the derivation's sum: for one band of weight 1 and zero mean,
    /// `(2(9d + 2) + 64)·u·amplitude·max|T|`; it scales with the amplitude, grows with `d`, and
    /// a mean adds `64·u·|mean|`.
    #[test]
    fn wavelet_bound_follows_its_derivation() {
        let model = |dimensions: u32, amplitude: f32, mean: f32| WaveletNoise {
            seed: 4,
            dimensions,
            tile_size: 16,
            cell_size: 8.0,
            bands: vec![1.0],
            amplitude,
            mean,
        };
        let m = model(2, 0.5, 0.0);
        let peak = m
            .tile()
            .values
            .iter()
            .fold(0.0f64, |a, &v| a.max(f64::from(v).abs()));
        let want = (2.0 * 20.0 + 64.0) * F32_UNIT_ROUNDOFF * 0.5 * peak;
        assert!((wavelet(&m).max_abs / want - 1.0).abs() < 1e-12);
        let doubled = wavelet(&model(2, 1.0, 0.0)).max_abs;
        assert!((doubled / wavelet(&m).max_abs - 2.0).abs() < 1e-12);
        let with_mean = wavelet(&model(2, 0.5, 3.0)).max_abs - wavelet(&m).max_abs;
        assert!((with_mean - 64.0 * F32_UNIT_ROUNDOFF * 3.0).abs() < 1e-15);
        assert!(wavelet(&model(3, 0.5, 0.0)).max_abs > 0.0);
        assert_eq!(tolerance(&Model::Wavelet(m.clone())), Some(wavelet(&m)));
    }

    /// `2e + e²` is the exact worst case of `Σ|a² − b²|/Σa²` for `b = a·(1 + e)`.
    #[test]
    fn spectral_bound_is_attained_by_a_scaled_signal() {
        let t = Tolerance::from_max(0.01);
        let sigma = 0.1;
        let e = 0.01 / sigma;
        let (a, b) = (1.0f64, 1.0 + e);
        assert!(((b * b - a * a) / (a * a) - t.spectral(sigma)).abs() < 1e-12);
    }

    fn texture_model(amplitude: f32, colour: bool, turbulence: bool) -> TextureModel {
        use spectex_model::{ColourBasis, Structure, TextureChannel, Turbulence};
        let channel = TextureChannel {
            seed: 1,
            mean: 0.5,
            strata: vec![],
            structure: Some(Structure {
                blocks: 2,
                cosines: vec![
                    vec![FixedCosine {
                        frequency: [3, -2],
                        amplitude,
                        phase: 0.25,
                    }];
                    4
                ],
            }),
        };
        TextureModel {
            seed: 0,
            period: 16,
            channels: vec![channel; if colour { 3 } else { 1 }],
            colour: colour.then_some(ColourBasis {
                mean: [0.5; 3],
                basis: [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]],
            }),
            turbulence: turbulence.then(|| Turbulence {
                sigma: 2.0,
                seeds: [1, 2],
                strata: vec![Stratum {
                    window_width: 8.0,
                    amplitude: 0.2,
                    sub_strata: vec![vec![[0.1, 0.2]]; 2],
                }],
                centre: 0.3,
            }),
            random_placement: true,
        }
    }

    /// One tolerance per output component; the structure's part grows with its amplitude, the
    /// colour basis scales a component's bound, and turbulence adds to it.
    #[test]
    fn texture_bound_per_component() {
        let grey = texture(&texture_model(0.1, false, false));
        assert_eq!(grey.len(), 1);
        let louder = texture(&texture_model(0.2, false, false));
        assert!(louder[0].max_abs > grey[0].max_abs);
        assert!(grey[0].max_abs > 0.0 && grey[0].max_abs < 1e-4, "{grey:?}");
        let turbulent = texture(&texture_model(0.1, false, true));
        assert!(turbulent[0].max_abs > grey[0].max_abs);
        let colour = texture(&texture_model(0.1, true, false));
        assert_eq!(colour.len(), 3);
        assert!(colour[1].max_abs > colour[0].max_abs, "{colour:?}");
        assert_eq!(
            tolerance(&Model::Texture(texture_model(0.1, true, false))),
            Some(colour[1])
        );
    }

    #[test]
    fn gabor_bound_grows_with_impulses() {
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

    fn classic_model(basis: Basis, dimensions: u32) -> ClassicNoise {
        ClassicNoise {
            seed: 0,
            dimensions,
            cell_size: 32.0,
            basis,
            fractal: None,
            amplitude: 1.0,
            mean: 0.0,
        }
    }

    /// The simplex bounds against a dense scan of one kernel's value and radial slope.
    #[test]
    fn simplex_bounds_cover_a_scan_of_the_kernel() {
        for (three_d, r2, scale, corners) in [(false, 0.5, 70.0, 3.0), (true, 0.6, 32.0, 4.0)] {
            let (n, l) = simplex_bounds(three_d);
            let (mut vmax, mut smax) = (0.0f64, 0.0f64);
            for k in 0..=100_000 {
                let r = f64::from(k) / 100_000.0 * f64::sqrt(r2);
                let t = r2 - r * r;
                // |g·δ| ≤ √2 r along g; the radial derivative of t⁴·√2·r.
                vmax = vmax.max(t.powi(4) * std::f64::consts::SQRT_2 * r);
                let slope = std::f64::consts::SQRT_2 * (t.powi(4) - 8.0 * r * r * t.powi(3)).abs();
                smax = smax.max(slope);
            }
            assert!(
                (n - scale * corners * vmax).abs() < 1e-6 * n,
                "{n} vs {vmax}"
            );
            assert!(l >= scale * corners * smax * (1.0 - 1e-9), "{l} vs {smax}");
        }
        // 2D simplex noise is known to reach about ±1 with these constants: the bound is above.
        assert!(simplex_bounds(false).0 > 1.0);
    }

    /// Bounds scale with the amplitude, grow with octaves, the 3D simplex seam dominates its
    /// bound, and Manhattan Worley is tighter than Euclidean.
    #[test]
    fn classic_bounds_follow_their_derivation() {
        use spectex_model::classic::{FeaturePoints, Fractal, Worley};
        let g = classic(&classic_model(Basis::Gradient, 2)).max_abs;
        let mut louder = classic_model(Basis::Gradient, 2);
        louder.amplitude = 2.0;
        assert!((classic(&louder).max_abs / g - 2.0).abs() < 1e-12);
        assert!(g > 0.0 && g < 1e-4, "{g}");
        let mut fbm = classic_model(Basis::Gradient, 2);
        fbm.fractal = Some(Fractal {
            kind: FractalKind::Fbm,
            octaves: 4,
            lacunarity: 2.0,
            gain: 0.5,
        });
        let f = classic(&fbm).max_abs;
        assert!(f > g && f < 2.0 * g, "{f} vs {g}");
        let s3 = classic(&classic_model(Basis::Simplex, 3)).max_abs;
        assert!(s3 > 6.4e-3 && s3 < 7e-3, "{s3}");
        let worley = |metric| {
            classic(&classic_model(
                Basis::Worley(Worley {
                    metric,
                    coefficients: [-1.0, 1.0, 0.0, 0.0],
                    points: FeaturePoints::Fixed(1),
                }),
                2,
            ))
            .max_abs
        };
        assert!(worley(Metric::Manhattan) < worley(Metric::Euclidean));
        let mut ridged = classic_model(Basis::Value, 2);
        ridged.fractal = Some(Fractal {
            kind: FractalKind::Ridged {
                offset: 1.0,
                weight_gain: 2.0,
            },
            octaves: 3,
            lacunarity: 2.0,
            gain: 0.5,
        });
        // e'_0 = 2e, e'_1 = 2e + 2e'_0 = 6e, e'_2 = 2e + 2e'_1 = 14e: Σ gain^o e'_o = 2e + 3e + 3.5e.
        let e = 2.0 * (2.0 * FADE_ABS_ERROR + 4.0 * F32_UNIT_ROUNDOFF);
        let sums = SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * (1.0 + 0.5 + 0.25);
        assert!((classic(&ridged).max_abs - (8.5 * e + sums)).abs() < 1e-15);
        assert_eq!(
            tolerance(&Model::Classic(classic_model(Basis::Value, 3))),
            Some(classic(&classic_model(Basis::Value, 3)))
        );
    }
}
