//! Domain warps' fuzz strategy and CPU cost bound: chains of warps nested up to and past their
//! depth limit.

use proptest::prelude::*;
use spectex_model::warp::{MAX_STRENGTH, MAX_WARP_DEPTH};
use spectex_model::{Model, Warp};

use super::{FuzzKind, model};
use crate::strategy::{Odds, f32_in};

/// A warp nesting at most `max_depth` warps (itself included). The depth is drawn first —
/// one most often, and the limit [`MAX_WARP_DEPTH`] and the depths past it as often as all the
/// others together — then built as a chain: one of `base`, `x`, `y` continues it, the other two
/// are models without warps (so a chain of depth `d` holds `2d + 1` models, not `3^d`).
pub fn warp(o: Odds, max_depth: usize) -> BoxedStrategy<Warp> {
    let max_depth = if o.bad > 0 {
        max_depth.max(1)
    } else {
        max_depth.clamp(1, MAX_WARP_DEPTH)
    };
    let depths: Vec<(u32, BoxedStrategy<usize>)> = (1..=max_depth)
        .map(|d| {
            let weight = match d {
                1 => 12,
                d if d >= MAX_WARP_DEPTH => 2,
                _ => 1,
            };
            (weight, Just(d).boxed())
        })
        .collect();
    proptest::strategy::Union::new_weighted(depths)
        .prop_flat_map(move |d| warp_chain(o, d))
        .boxed()
}

/// A warp of exactly `depth` nested warps.
fn warp_chain(o: Odds, depth: usize) -> BoxedStrategy<Warp> {
    let strength = prop_oneof![
        3 => f32_in(-64.0, 64.0, o),
        1 => f32_in(-MAX_STRENGTH, MAX_STRENGTH, o),
    ];
    let chain = if depth > 1 {
        warp_chain(o, depth - 1).prop_map(Model::Warp).boxed()
    } else {
        model(o, 0)
    };
    (0..3usize, chain, model(o, 0), model(o, 0), strength)
        .prop_map(|(slot, chain, a, b, strength)| {
            let (base, x, y) = match slot {
                0 => (chain, a, b),
                1 => (a, chain, b),
                _ => (a, b, chain),
            };
            Warp {
                base: Box::new(base),
                x: Box::new(x),
                y: Box::new(y),
                strength,
            }
        })
        .boxed()
}

impl FuzzKind for Warp {
    fn strategy(o: Odds, depth: usize) -> BoxedStrategy<Model> {
        warp(o, depth).prop_map(Model::Warp).boxed()
    }
}

#[cfg(feature = "cpu")]
const _: () = assert!(6561 == 3usize.pow(MAX_WARP_DEPTH as u32));

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for Warp {
    /// A warp costs its base's and its two displacements' costs, so a tree of warps nested
    /// [`MAX_WARP_DEPTH`] deep costs at most its `3^depth` leaves at the largest leaf cost (a
    /// texture's).
    const MAX_COST: f64 = 6561.0 * <spectex_model::TextureModel as crate::cpu::CostBound>::MAX_COST;
}
