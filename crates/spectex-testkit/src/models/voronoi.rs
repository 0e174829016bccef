//! Voronoi diagrams' fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::voronoi::{MAX_PALETTE, VoronoiNoise, VoronoiOutput};

use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, list, u32_in};

/// A Voronoi diagram: every output, palettes and small images (sometimes with a texel count
/// that does not match their sides), relaxation at small iteration counts (the limits case
/// takes the largest), 2D and 3D, values drawn inside and beyond their limits.
pub fn voronoi(o: Odds) -> BoxedStrategy<VoronoiNoise> {
    let colour = (level(o), level(o), level(o)).prop_map(|(r, g, b)| [r, g, b]);
    let palette = list(colour.clone().boxed(), 1, 4, MAX_PALETTE, o)
        .prop_map(|colours| VoronoiOutput::Palette { colours });
    let image = (u32_in(1, 6, o), u32_in(1, 6, o)).prop_flat_map(move |(width, height)| {
        let n = (width as usize * height as usize).min(64);
        let len = prop_oneof![8 => Just(n), 1 => Just(n + 1), 1 => Just(n.saturating_sub(1))];
        let colour = colour.clone();
        len.prop_flat_map(move |len| {
            proptest::collection::vec(colour.clone(), len).prop_map(move |texels| {
                VoronoiOutput::Image {
                    width,
                    height,
                    texels,
                }
            })
        })
    });
    let output = prop_oneof![
        Just(VoronoiOutput::CellId),
        Just(VoronoiOutput::F1),
        Just(VoronoiOutput::Border),
        Just(VoronoiOutput::F2MinusF1),
        palette,
        image,
    ];
    (
        seed(),
        f32_in(1.0, 4096.0, o),
        f32_in(0.0, 1.0, o),
        prop_oneof![3 => Just(0u32), 1 => u32_in(0, 2, o)],
        u32_in(1, 6, o),
        output,
        prop_oneof![3 => Just(2u32), 1 => u32_in(2, 3, o)],
    )
        .prop_map(
            |(seed, cell_size, jitter, lloyd_iterations, lloyd_block, output, dimensions)| {
                VoronoiNoise {
                    seed,
                    dimensions,
                    cell_size,
                    jitter,
                    lloyd_iterations,
                    lloyd_block,
                    output,
                }
            },
        )
        .boxed()
}

impl FuzzKind for VoronoiNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        voronoi(o).prop_map(Model::Voronoi).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for VoronoiNoise {
    /// A Voronoi pixel: its search (7 × 7 cells, twice for the border) and, for a one-pixel
    /// window of a relaxed model, the relaxation of the up to 4 blocks its cells touch: `k`
    /// sweeps of `B²` seeds each clipped by 48 bisectors.
    const MAX_COST: f64 = 98.0
        + 4.0
            * spectex_model::voronoi::MAX_LLOYD_ITERATIONS as f64
            * (spectex_model::voronoi::MAX_LLOYD_BLOCK * spectex_model::voronoi::MAX_LLOYD_BLOCK)
                as f64
            * 48.0;
}
