//! The classic noises' fuzz strategy and CPU cost bound: every basis, with or without a fractal
//! sum.

use proptest::prelude::*;
use spectex_model::classic::{
    Basis, FeaturePoints, Fractal, FractalKind, MAX_OCTAVES, Metric, WORLEY_MAX_POINTS, Worley,
};
use spectex_model::{ClassicNoise, Model};

use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, u32_from, u32_in};

/// A classic noise: every basis (Worley with every metric and point process), with or without
/// every kind of fractal sum.
pub fn classic(o: Odds) -> BoxedStrategy<ClassicNoise> {
    let metric = prop_oneof![
        Just(Metric::Euclidean),
        Just(Metric::Manhattan),
        Just(Metric::Chebyshev),
    ];
    let coefficient = prop_oneof![
        2 => Just(0.0f32),
        3 => f32_in(-1e3, 1e3, o),
    ];
    let points = prop_oneof![
        u32_in(1, WORLEY_MAX_POINTS, o).prop_map(FeaturePoints::Fixed),
        f32_in(0.5, 4.0, o).prop_map(FeaturePoints::Poisson),
    ];
    let worley = (
        metric,
        [
            coefficient.clone(),
            coefficient.clone(),
            coefficient.clone(),
            coefficient,
        ],
        points,
    )
        .prop_map(|(metric, coefficients, points)| {
            Basis::Worley(Worley {
                metric,
                coefficients,
                points,
            })
        });
    let basis = prop_oneof![
        Just(Basis::Gradient),
        Just(Basis::Simplex),
        Just(Basis::Value),
        Just(Basis::Kensler),
        worley,
    ];
    let kind = prop_oneof![
        Just(FractalKind::Fbm),
        Just(FractalKind::Turbulence),
        (f32_in(0.0, 4.0, o), f32_in(0.0, 16.0, o)).prop_map(|(offset, weight_gain)| {
            FractalKind::Ridged {
                offset,
                weight_gain,
            }
        }),
    ];
    let fractal = (
        kind,
        u32_in(1, MAX_OCTAVES, o),
        f32_in(1.0, 16.0, o),
        f32_in(0.0, 2.0, o),
    )
        .prop_map(|(kind, octaves, lacunarity, gain)| Fractal {
            kind,
            octaves,
            lacunarity,
            gain,
        });
    (
        seed(),
        u32_from(&[2, 3], &[1, 4], o),
        f32_in(1.0, 1e6, o),
        basis,
        proptest::option::of(fractal),
        level(o),
        level(o),
    )
        .prop_map(
            move |(seed, dimensions, cell_size, basis, mut fractal, amplitude, mean)| {
                // Without the odds, keep the finest octave's cell at 1 pixel or more.
                if let (Some(f), 0) = (&mut fractal, o.bad) {
                    while f.octaves > 1
                        && f64::from(cell_size) / f64::from(f.lacunarity).powi(f.octaves as i32 - 1)
                            < 1.0
                    {
                        f.octaves -= 1;
                    }
                }
                ClassicNoise {
                    seed,
                    dimensions,
                    cell_size,
                    basis,
                    fractal,
                    amplitude,
                    mean,
                }
            },
        )
        .boxed()
}

impl FuzzKind for ClassicNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        classic(o).prop_map(Model::Classic).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for ClassicNoise {
    /// 27 cells (a 3D Worley search's first ring) per octave, at most 16 octaves.
    const MAX_COST: f64 = 27.0 * MAX_OCTAVES as f64;
}
