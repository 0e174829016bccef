//! The tolerances of a CPU–GPU comparison, derived per model from the number of terms a pixel
//! sums, their amplitudes and the accuracy of the f32 functions both sides evaluate.
//!
//! Both evaluators compute the same f32 formulas (cosine in turns by one polynomial, the
//! Kaiser–Bessel window by one polynomial, `exp` by one polynomial) from bit-identical integer
//! draws. They may still differ because a GPU compiler may contract `a·b + c` into an FMA and
//! reassociate (WGSL cannot forbid either), and the GPU's `cos`/`exp` builtins are not used but
//! its arithmetic rounding may differ. Each constant below bounds one such source for one term;
//! a pixel's bound is the sum over its terms.

use spectex_model::{
    FixedCosine, GaborNoise, LrpNoise, Model, Stratum, TextureModel, WaveletNoise,
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
        Model::Wavelet(m) => Some(wavelet(m)),
        Model::Texture(m) => texture(m)
            .into_iter()
            .max_by(|a, b| a.max_abs.total_cmp(&b.max_abs)),
        #[allow(unreachable_patterns)] // reason: `Model` is non_exhaustive for other crates
        _ => None,
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

/// LRP (Gilet et al. 2014, Eq. 1–2): per stratum, 9 lattice points × `J_S` cosines of
/// amplitude `A_S` times a window ≤ 1. Per term: the cosine's error from its phase (the offset
/// to a lattice point is at most `1.5·√2·Δ_S`, so `|f·p| ≤ |f|_max·2.13·Δ_S` turns, plus the
/// phase ≤ 1), [`COS_ABS_ERROR`] and [`WINDOW_ABS_ERROR`], on each side (factor 2).
#[must_use]
pub fn lrp(m: &LrpNoise) -> Tolerance {
    let mut bound = 0.0;
    let mut magnitude = 0.0;
    for s in &m.strata {
        let f_max = s
            .sub_strata
            .iter()
            .flatten()
            .map(|f| f64::from(f[0]).hypot(f64::from(f[1])))
            .fold(0.0, f64::max);
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
    let tau = std::f64::consts::TAU;
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
                let n = f64::from(2 * m.period / s.blocks);
                let delta = f64::from(m.period / s.blocks);
                let k1 = |c: &FixedCosine| {
                    f64::from(c.frequency[0].unsigned_abs() + c.frequency[1].unsigned_abs())
                };
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
                let slope = tau * g_max / n + weights_slope;
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

#[cfg(test)]
mod tests {
    use super::*;
    use spectex_model::{Orientation, Stratum};

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
}
