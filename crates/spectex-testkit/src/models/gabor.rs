//! Gabor noise's fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::{GaborNoise, Model, Orientation};

use super::{FuzzKind, angle, level, seed};
use crate::strategy::{Odds, f32_in};

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

impl FuzzKind for GaborNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        gabor(o).prop_map(Model::Gabor).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for GaborNoise {
    /// `9λ` kernels, `λ = impulses_per_kernel/π` per cell with `impulses_per_kernel ≤ 1000`
    /// (`GaborNoise::validate`).
    const MAX_COST: f64 = 9.0 * 1000.0 / std::f64::consts::PI;
}
