//! Gabor noise's fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::{GaborNoise, MAX_GABOR_COMPONENTS, Model, Orientation};

use super::{FuzzKind, angle, level, seed};
use crate::strategy::{Odds, f32_in, list};

/// A Gabor noise (bandwidth `[0.001, 10]`, frequency `[0, 0.5]`, impulses `[0.01, 1000]`).
pub fn gabor(o: Odds) -> BoxedStrategy<GaborNoise> {
    // Two independent angles are out of order half the time: only with the odds.
    let unordered = if o.bad > 0 { 1 } else { 0 };
    let orientation = prop_oneof![
        2 => angle(o).prop_map(|angle| Orientation::Anisotropic { angle }),
        2 => (angle(o), f32_in(0.0, 7.0, o)).prop_map(|(min, span)| Orientation::Isotropic {
            min,
            max: min + span,
        }),
        unordered => (angle(o), angle(o)).prop_map(|(min, max)| Orientation::Isotropic { min, max }),
        2 => spectrum(o),
    ];
    (
        seed(),
        level(o),
        f32_in(0.0, 1e9, o),
        f32_in(1e-3, 10.0, o),
        f32_in(0.0, 0.5, o),
        orientation,
        f32_in(0.01, 1000.0, o),
    )
        .prop_map(
            |(seed, mean, amplitude, bandwidth, frequency, orientation, impulses_per_kernel)| {
                GaborNoise {
                    seed,
                    mean,
                    amplitude,
                    bandwidth,
                    frequency,
                    orientation,
                    impulses_per_kernel,
                }
            },
        )
        .boxed()
}

/// A Gabor noise by example's table: 1 to 24 components (up to [`MAX_GABOR_COMPONENTS`] + 1
/// with the odds), coordinates in `[-0.35, 0.35]` (so `|f| < 0.5`) and weights in `[0, 1e30]`;
/// a valid case whose weights all drew 0 gets a first weight of 1 (the sum must be positive),
/// and with the odds a weight may go missing (lengths differ).
fn spectrum(o: Odds) -> BoxedStrategy<Orientation> {
    let component = (
        f32_in(-0.35, 0.35, o),
        f32_in(-0.35, 0.35, o),
        f32_in(0.0, 1e30, o),
    )
        .boxed();
    let drop_one = if o.bad > 0 { 1 } else { 0 };
    (
        list(component, 1, 24, MAX_GABOR_COMPONENTS, o),
        prop_oneof![8 => Just(false), drop_one => Just(true)],
    )
        .prop_map(move |(components, drop_one)| {
            let frequencies: Vec<[f32; 2]> = components.iter().map(|c| [c.0, c.1]).collect();
            let mut weights: Vec<f32> = components.iter().map(|c| c.2).collect();
            if o.bad == 0
                && let Some(first) = weights.first_mut()
                && components.iter().all(|c| c.2 == 0.0)
            {
                *first = 1.0;
            }
            if drop_one {
                weights.pop();
            }
            Orientation::Spectrum {
                frequencies,
                weights,
            }
        })
        .boxed()
}

impl FuzzKind for GaborNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        gabor(o).prop_map(Model::Gabor).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for GaborNoise {
    /// `9λ` kernels, `λ = impulses_per_kernel/π` per cell with `impulses_per_kernel ≤ 1000`
    /// (`GaborNoise::validate`). A spectrum adds per impulse one search of at most 1024
    /// entries (ten comparisons), not another kernel.
    const MAX_COST: f64 = 9.0 * 1000.0 / std::f64::consts::PI;
}
