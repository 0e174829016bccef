//! Stochastic subdivision's fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::subdivision::{MAX_LEVELS, Stencil, StochasticSubdivision};

use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, u32_in};

/// A stochastic subdivision: cells of 1 to 4096 pixels, 0 to 16 levels (with the odds 17),
/// `H` in `[0, 1]` (with the odds outside), either stencil, any amplitude and mean.
pub fn subdivision(o: Odds) -> BoxedStrategy<StochasticSubdivision> {
    (
        seed(),
        f32_in(1.0, 4096.0, o),
        u32_in(0, MAX_LEVELS, o),
        f32_in(0.0, 1.0, o),
        level(o),
        level(o),
        prop_oneof![Just(Stencil::Midpoint), Just(Stencil::Cubic)],
    )
        .prop_map(
            |(seed, cell_size, levels, hurst, amplitude, mean, stencil)| StochasticSubdivision {
                seed,
                cell_size,
                levels,
                hurst,
                amplitude,
                mean,
                stencil,
            },
        )
        .boxed()
}

impl FuzzKind for StochasticSubdivision {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        subdivision(o).prop_map(Model::Subdivision).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for StochasticSubdivision {
    /// A stochastic subdivision computes at most a 6 × 6 block of lattice values per level, 17
    /// levels (`spectex_cpu::subdivision`: `W²·(L + 1)`, `L ≤ MAX_LEVELS = 16`).
    const MAX_COST: f64 = 36.0 * 17.0;
}
