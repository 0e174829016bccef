//! Combinations' fuzz strategy and CPU cost bound: every operation over models without warps or
//! combinations inside.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::combine::{
    Combine as Combination, CombineOp, MAX_STOPS, MAX_TABLE_KNOTS, RampStop,
};

use super::{FuzzKind, level, model};
use crate::strategy::{Odds, f32_in, list, u32_in};

/// A combination of models without warps or combinations inside (their nesting is the warp
/// strategy's and the limits cases'): every operation, operand counts around its arity with
/// the odds, parameters inside and beyond their limits.
pub fn combine(o: Odds) -> BoxedStrategy<Combination> {
    let stop = (level(o), level(o), level(o), level(o)).prop_map(|(at, r, g, b)| RampStop {
        at,
        colour: [r, g, b],
    });
    let op = prop_oneof![
        Just(CombineOp::Add),
        Just(CombineOp::Multiply),
        Just(CombineOp::Min),
        Just(CombineOp::Max),
        Just(CombineOp::Mix),
        (level(o), level(o)).prop_map(|(a, b)| CombineOp::Smoothstep {
            edges: [a.min(b), a.max(b)]
        }),
        (level(o), level(o), u32_in(0, 8, o)).prop_map(|(offset, step, folds)| {
            CombineOp::AbsFold {
                offset,
                step,
                folds,
            }
        }),
        f32_in(-100.0, 100.0, o).prop_map(|gain| CombineOp::SinFold { gain }),
        (
            level(o),
            f32_in(0.01, 10.0, o),
            list(level(o), 2, 8, MAX_TABLE_KNOTS, o)
        )
            .prop_map(|(d0, span, table)| CombineOp::Histogram {
                domain: [d0, d0 + span],
                table,
            }),
        list(stop.boxed(), 1, 4, MAX_STOPS, o).prop_map(|mut stops| {
            stops.sort_by(|a, b| a.at.total_cmp(&b.at));
            CombineOp::Ramp { stops }
        }),
    ];
    op.prop_flat_map(move |op| {
        let (lo, hi) = op.arity();
        let count = if o.bad > 0 {
            (lo.saturating_sub(1)..=hi + 1).boxed()
        } else {
            (lo..=hi.min(3)).boxed()
        };
        let op = op.clone();
        count.prop_flat_map(move |n| {
            let op = op.clone();
            proptest::collection::vec(model(o, 0), n).prop_map(move |operands| Combination {
                op: op.clone(),
                operands,
            })
        })
    })
    .boxed()
}

impl FuzzKind for spectex_model::Combine {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        combine(o).prop_map(Model::Combine).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for spectex_model::Combine {
    /// A combination costs its operands' costs: along any path at most 8 combinations and 8
    /// warps nest (`MAX_COMBINE_DEPTH`, `MAX_WARP_DEPTH`), each with at most 8 (3) operands, so
    /// at most `8^16` leaves at the largest leaf cost (a texture's).
    const MAX_COST: f64 =
        2.814_749_767_106_56e14 * <spectex_model::TextureModel as crate::cpu::CostBound>::MAX_COST;
}
