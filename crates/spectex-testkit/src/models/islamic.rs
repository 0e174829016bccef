//! Islamic patterns' fuzz strategy and CPU cost bound.

use proptest::prelude::*;
use spectex_model::Model;
use spectex_model::islamic::{IslamicOutput, IslamicPattern, Motif, Tiling};

use super::{FuzzKind, seed};
use crate::strategy::{Odds, f32_in, u32_in};

/// An Islamic pattern: every tiling, motif and output, values drawn inside and beyond their
/// limits.
pub fn islamic(o: Odds) -> BoxedStrategy<IslamicPattern> {
    let tiling = prop_oneof![
        Just(Tiling::Square),
        Just(Tiling::Hexagonal),
        Just(Tiling::OctagonSquare),
        Just(Tiling::DodecagonTriangle),
    ];
    let motif = prop_oneof![
        f32_in(1.0, 89.0, o).prop_map(|angle| Motif::Contact { angle }),
        u32_in(1, 5, o).prop_map(|step| Motif::Star { step }),
    ];
    let output = prop_oneof![
        Just(IslamicOutput::Band),
        Just(IslamicOutput::Distance),
        Just(IslamicOutput::Filled),
    ];
    (
        seed(),
        tiling,
        motif,
        f32_in(4.0, 4096.0, o),
        f32_in(0.0, 8.0, o),
        output,
        f32_in(-360.0, 360.0, o),
        (f32_in(-1e9, 1e9, o), f32_in(-1e9, 1e9, o)),
    )
        .prop_map(
            |(seed, tiling, motif, cell_size, line_width, output, rotation, (ox, oy))| {
                IslamicPattern {
                    seed,
                    tiling,
                    motif,
                    cell_size,
                    line_width,
                    output,
                    rotation,
                    offset: [ox, oy],
                }
            },
        )
        .boxed()
}

impl FuzzKind for IslamicPattern {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        islamic(o).prop_map(Model::Islamic).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for IslamicPattern {
    /// Segments an Islamic pattern's pixel visits, at most its table's
    /// (`spectex_model::islamic::MAX_SEGMENTS`, tested there).
    const MAX_COST: f64 = spectex_model::islamic::MAX_SEGMENTS as f64;
}
