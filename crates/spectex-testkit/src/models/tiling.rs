//! Tiling-and-blending textures' fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::tiling::{Blend, LUT_ENTRIES, TilingTexture};

use super::{FuzzKind, level};
use crate::strategy::{Odds, f32_in, u32_in};

/// A tiling texture: grey or colour exemplars of 8 to 20 texels a side (with the odds a
/// channel count other than 1 and 3, or a side below the minimum), tiles up to and past what
/// the exemplar holds, both blends with in- and out-of-range parameters, Gaussianised values
/// and tables from a few levels (sorted, or with the odds not), lists whose lengths may
/// disagree with the sides.
pub fn tiling(o: Odds) -> BoxedStrategy<TilingTexture> {
    let blend = prop_oneof![
        2 => Just(Blend::Variance),
        1 => (u32_in(1, 32, o), f32_in(0.0, 0.5, o))
            .prop_map(|(sharpness, rotation)| Blend::Hex { sharpness, rotation }),
    ];
    (
        (any::<u32>(), u32_in(8, 20, o), u32_in(8, 20, o)),
        prop_oneof![4 => Just(1u32), 4 => Just(3u32), 1 => Just(4u32)],
        f32_in(1.0, 6.0, o),
        blend,
        (
            level(o),
            level(o),
            f32_in(-3.0, 3.0, o),
            any::<bool>(),
            any::<bool>(),
        ),
    )
        .prop_map(
            |((seed, width, height), channels, tile, blend, (a, b, g, sorted, short))| {
                let nc = channels as usize;
                let n = ((width.min(64) * height.min(64)) as usize * nc)
                    .saturating_sub(usize::from(short));
                let gaussian = (0..n)
                    .map(|k| {
                        if k % 3 == 0 {
                            g
                        } else {
                            -0.5 * g + (k % 5) as f32 * 0.1
                        }
                    })
                    .collect();
                let lut = (0..nc * LUT_ENTRIES)
                    .map(|k| {
                        let t = (k % LUT_ENTRIES) as f32 / LUT_ENTRIES as f32;
                        if sorted { a + t * 0.5 } else { b - t }
                    })
                    .collect();
                TilingTexture {
                    seed,
                    width,
                    height,
                    channels,
                    tile,
                    blend,
                    gaussian,
                    lut,
                    mean: vec![a; nc],
                    basis: (0..nc * nc)
                        .map(|k| if k % (nc + 1) == 0 { 1.0 } else { b * 0.1 })
                        .collect(),
                }
            },
        )
        .boxed()
}

impl FuzzKind for TilingTexture {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        tiling(o).prop_map(Model::Tiling).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for TilingTexture {
    /// Three bilinear taps a pixel (`RowKernel::cost_per_pixel`), whatever the exemplar.
    const MAX_COST: f64 = 3.0;
}
