//! Texture by example (Gilet et al. 2014, §5–6; `spectex_model::texture`): its tolerance per
//! output component and its regularity, from its strata's LRP bounds ([`super::lrp`]), its
//! structure's cosines and blend weights, its turbulence and its placement taps.

use spectex_model::{FixedCosine, LrpNoise, Model, Stratum, TextureModel};

use super::lrp::lrp;
use super::{
    COS_ABS_ERROR, CheckKind, F32_UNIT_ROUNDOFF, PHASE_ROUNDINGS, Regularity, SUMMATION_ROUNDINGS,
    Tolerance, regularity,
};

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

impl CheckKind for TextureModel {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(texture(self))
    }

    fn regularity(&self) -> Option<Regularity> {
        Some(texture_regularity(self))
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::tolerance::tests::check_slope_on_fine_render;
    use crate::tolerance::tolerance;

    /// The slope bound of a texture holds on a fine CPU render (see
    /// [`check_slope_on_fine_render`]).
    pub fn texture_slope_bound_holds_on_a_fine_render() {
        let grey = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../testdata/models/texture-synthetic-grey.json"
        ))
        .unwrap();
        // The texture's bound sums the worst case of every one of its strata's 9·J cosines and of
        // the turbulence's: valid, and measured 100× the steepest step on this model.
        check_slope_on_fine_render("texture", &spectex_model::from_json(&grey).unwrap(), 150.0);
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
    pub fn texture_bound_per_component() {
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
}
