//! Matrix transformations' fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::matrix::{MAX_ENTRY, MAX_RINGS, MatrixSource, MatrixTransform};

use super::{FuzzKind, level};
use crate::strategy::{Odds, u32_from, u32_in};

/// A matrix transformation: entries mostly Lucas and Fibonacci numbers (the survey's rule, so
/// that many are valid) and with the odds any `u32`, determinants prime to the side or not,
/// iterations up to far past any period, a ring source on tori up to 512 or a small image
/// (whose texel count may disagree with the side).
pub fn matrix(o: Odds) -> BoxedStrategy<MatrixTransform> {
    let entry = || {
        u32_from(
            &[0, 1, 2, 3, 4, 5, 7, 8, 11, 13, 18, 21],
            &[6, 9, MAX_ENTRY + 1],
            o,
        )
    };
    let rings = (u32_in(2, 512, o), u32_in(1, MAX_RINGS, o))
        .prop_map(|(size, rings)| (size, MatrixSource::Rings { rings }));
    let image = (2u32..=12, level(o), level(o), any::<bool>()).prop_map(|(size, a, b, short)| {
        let n = (size * size) as usize - usize::from(short);
        let texels = (0..n).map(|k| if k % 3 == 0 { a } else { b }).collect();
        (size, MatrixSource::Image { texels })
    });
    (
        [[entry(), entry()], [entry(), entry()]],
        prop_oneof![4 => 0u64..=64, 1 => any::<u64>()],
        prop_oneof![3 => rings, 1 => image],
        level(o),
        level(o),
    )
        .prop_map(
            |(matrix, iterations, (size, source), amplitude, mean)| MatrixTransform {
                matrix,
                iterations,
                size,
                source,
                amplitude,
                mean,
            },
        )
        .boxed()
}

impl FuzzKind for MatrixTransform {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        matrix(o).prop_map(Model::Matrix).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for MatrixTransform {
    /// A matrix transformation reads one source texel per pixel (the map `A·q mod N` is folded
    /// into one matrix on the host, whatever the iteration count).
    const MAX_COST: f64 = 1.0;
}
