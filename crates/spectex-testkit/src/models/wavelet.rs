//! Wavelet noise's fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::wavelet::{MAX_BANDS, MAX_TILE_2D, MAX_TILE_3D, MIN_TILE};
use spectex_model::{Model, WaveletNoise};

use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, list, u32_from};

/// A wavelet noise: 2D or 3D, tile sides even from 16 to the limit (usually small), 1 to 16
/// bands (all zero sometimes).
pub fn wavelet(o: Odds) -> BoxedStrategy<WaveletNoise> {
    let tile = u32_from(
        &[MIN_TILE, 18, 32, 64, MAX_TILE_3D, MAX_TILE_2D],
        &[MIN_TILE - 2, 17, MAX_TILE_2D + 2, MAX_TILE_2D + 1],
        o,
    );
    let weight = prop_oneof![1 => Just(0.0f32), 4 => f32_in(-1e3, 1e3, o)];
    (
        seed(),
        u32_from(&[2, 3], &[1, 4], o),
        tile,
        f32_in(1.0, 1e6, o),
        list(weight.boxed(), 1, 4, MAX_BANDS, o),
        level(o),
        level(o),
    )
        .prop_map(
            move |(seed, dimensions, tile_size, cell_size, mut bands, amplitude, mean)| {
                // Without the odds, keep the finest band's cell at 1 pixel or more and one
                // weight that is not 0.
                if o.bad == 0 {
                    while bands.len() > 1
                        && f64::from(cell_size) / f64::from(1u32 << (bands.len() - 1)) < 1.0
                    {
                        bands.pop();
                    }
                    if bands.iter().all(|&w| w == 0.0) {
                        bands[0] = 1.0;
                    }
                }
                // A 3D tile past the 2D limit's side is rejected; draw 3D tiles within 64 unless
                // the odds say otherwise, so that valid 3D models are common.
                let tile_size = if dimensions == 3 && tile_size > MAX_TILE_3D && o.bad == 0 {
                    MAX_TILE_3D
                } else {
                    tile_size
                };
                WaveletNoise {
                    seed,
                    dimensions,
                    tile_size,
                    cell_size,
                    bands,
                    amplitude,
                    mean,
                }
            },
        )
        .boxed()
}

impl FuzzKind for WaveletNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        wavelet(o).prop_map(Model::Wavelet).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for WaveletNoise {
    /// `3^d` tile samples per band, at most 16 bands.
    const MAX_COST: f64 = 27.0 * MAX_BANDS as f64;
}
