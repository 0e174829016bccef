//! Texton noise's fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::texton::{Combine, MAX_DENSITY, MAX_REACH, Placement, Spot, TextonNoise};

use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, u32_in};

/// A texton noise: grid or Poisson placement, ellipsoid, Gaussian or a small image (sometimes
/// with a texel count that does not match its sides), ranges drawn inside and beyond their
/// limits; without the odds the cell is widened so the texton reaches at most 3 cells.
pub fn texton(o: Odds) -> BoxedStrategy<TextonNoise> {
    let placement = prop_oneof![
        f32_in(0.0, 1.0, o).prop_map(|jitter| Placement::Grid { jitter }),
        f32_in(0.01, MAX_DENSITY, o).prop_map(|density| Placement::Poisson { density }),
    ];
    let image = (u32_in(1, 6, o), u32_in(1, 6, o)).prop_flat_map(move |(width, height)| {
        let n = (width as usize * height as usize).min(64);
        let len = prop_oneof![8 => Just(n), 1 => Just(n + 1), 1 => Just(n.saturating_sub(1))];
        len.prop_flat_map(move |len| {
            proptest::collection::vec(f32_in(-2.0, 2.0, o), len).prop_map(move |values| {
                Spot::Image {
                    width,
                    height,
                    values,
                }
            })
        })
    });
    let spot = prop_oneof![Just(Spot::Ellipsoid), Just(Spot::Gaussian), image];
    let pair = |lo: f32, hi: f32| (f32_in(lo, hi, o), f32_in(lo, hi, o)).prop_map(|(a, b)| [a, b]);
    (
        seed(),
        f32_in(1.0, 4096.0, o),
        placement,
        spot,
        pair(0.5, 64.0),
        pair(-2.0, 2.0),
        pair(0.05, 2.0),
        (level(o), level(o)).prop_map(|(a, b)| [a, b]),
        prop_oneof![Just(Combine::Sum), Just(Combine::Max)],
        level(o),
    )
        .prop_map(
            move |(
                seed,
                cell,
                placement,
                spot,
                radii,
                rotation,
                scale,
                intensity,
                combine,
                mean,
            )| {
                let mut cell_size = cell;
                if o.bad == 0 {
                    // The texton's reach, `max(a, b)·max s / C`, within MAX_REACH cells.
                    let reach = radii[0].max(radii[1]) * scale[0].max(scale[1]);
                    cell_size = cell_size.max((reach / MAX_REACH as f32) * 1.01).min(4096.0);
                }
                TextonNoise {
                    seed,
                    cell_size,
                    placement,
                    spot,
                    radii,
                    rotation,
                    scale,
                    intensity,
                    combine,
                    mean,
                }
            },
        )
        .boxed()
}

impl FuzzKind for TextonNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        texton(o).prop_map(Model::Texton).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for TextonNoise {
    /// Textons visited per pixel: `(2·MAX_REACH + 1)²` cells of at most `MAX_TEXTONS_PER_CELL`.
    const MAX_COST: f64 = ((2 * MAX_REACH + 1)
        * (2 * MAX_REACH + 1)
        * spectex_model::texton::MAX_TEXTONS_PER_CELL) as f64;
}
