//! LRP noise's fuzz strategy and CPU cost bound: strata of random tables, the stratum strategy
//! a texture's channels share.

use proptest::prelude::*;
use spectex_model::{LrpNoise, MAX_COSINES, MAX_STRATA, Model, Stratum};

use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, list};

/// A frequency table entry, cycles per pixel, valid in `[−0.5, 0.5]²`.
fn frequency_pair(o: Odds) -> BoxedStrategy<[f32; 2]> {
    [f32_in(-0.5, 0.5, o), f32_in(-0.5, 0.5, o)].boxed()
}

/// One stratum: window width `[0.5, 1e6]` pixels, amplitude `[0, 1e9]`, 1 to 1024 tables.
pub fn stratum(o: Odds) -> BoxedStrategy<Stratum> {
    (
        f32_in(0.5, 1e6, o),
        f32_in(0.0, 1e9, o),
        list(
            list(frequency_pair(o), 1, 4, spectex_model::MAX_TABLE, o),
            1,
            5,
            MAX_COSINES,
            o,
        ),
    )
        .prop_map(|(window_width, amplitude, sub_strata)| Stratum {
            window_width,
            amplitude,
            sub_strata,
        })
        .boxed()
}

/// An LRP noise of 1 to 64 strata.
pub fn lrp(o: Odds) -> BoxedStrategy<LrpNoise> {
    (seed(), level(o), list(stratum(o), 1, 3, MAX_STRATA, o))
        .prop_map(|(seed, mean, strata)| LrpNoise { seed, mean, strata })
        .boxed()
}

impl FuzzKind for LrpNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        lrp(o).prop_map(Model::Lrp).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for LrpNoise {
    /// `9·Σ_S J_S` cosines: 9 lattice points per stratum, at most 64 strata of 1024 cosines.
    const MAX_COST: f64 = 9.0 * MAX_STRATA as f64 * MAX_COSINES as f64;
}
