//! The fuzz strategy and CPU cost bound of textures by example: structures, channels of LRP
//! strata, colour bases, turbulence and placement.

use proptest::prelude::*;
use spectex_model::texture::{MAX_CHANNELS, MAX_PERIOD};
use spectex_model::{
    ColourBasis, FixedCosine, MAX_COSINES, MAX_STRATA, Model, Structure, TextureChannel,
    TextureModel, Turbulence,
};

use super::lrp::stratum;
use super::{FuzzKind, level, seed};
use crate::strategy::{Odds, f32_in, list, u32_from};

/// A structure of `blocks × blocks` blocks for period `period` (frequencies within
/// `(−N/2, N/2]`, `N = 2·period/blocks`, with the odds one past it).
fn structure(period: u32, o: Odds) -> BoxedStrategy<Structure> {
    let mut typical: Vec<u32> = [1, 2, 4].into_iter().filter(|&b| b <= period).collect();
    if typical.is_empty() {
        typical.push(1);
    }
    u32_from(&typical, &[3, period * 2], o)
        .prop_flat_map(move |blocks| {
            let n = if blocks == 0 {
                2
            } else {
                (2 * period / blocks.min(period).max(1)).max(2) as i32
            };
            let half = n / 2;
            let outside = if o.bad > 0 { 1 } else { 0 };
            let frequency = prop_oneof![
                8 => -half + 1..=half,
                outside => Just(half + 1),
                outside => any::<i32>(),
            ];
            let cosine = (
                [frequency.clone(), frequency],
                f32_in(0.0, 1e9, o),
                f32_in(0.0, 1.0, o),
            )
                .prop_map(|(frequency, amplitude, phase)| FixedCosine {
                    frequency,
                    amplitude,
                    phase,
                });
            // A block count the limits reject early is given one list; the others get one per
            // block, with the odds one list too many.
            let lists = if blocks == 0 || blocks > 16 {
                1
            } else {
                let wanted = (blocks * blocks) as usize;
                if o.bad > 0 && blocks % 2 == 1 && blocks > 1 {
                    wanted + 1
                } else {
                    wanted
                }
            };
            proptest::collection::vec(list(cosine.boxed(), 0, 3, MAX_COSINES, o), lists)
                .prop_map(move |cosines| Structure { blocks, cosines })
        })
        .boxed()
}

fn channel(period: u32, o: Odds) -> BoxedStrategy<TextureChannel> {
    (
        seed(),
        level(o),
        list(stratum(o), 0, 2, MAX_STRATA, o),
        proptest::option::of(structure(period, o)),
    )
        .prop_map(|(seed, mean, strata, structure)| TextureChannel {
            seed,
            mean,
            strata,
            structure,
        })
        .boxed()
}

/// A texture: period a power of two (usually small), 1 grey or 3 colour channels (with the odds
/// a count or basis that does not match), turbulence and placement or not.
pub fn texture(o: Odds) -> BoxedStrategy<TextureModel> {
    let period = u32_from(
        &[2, 4, 8, 16, 32, 64, MAX_PERIOD],
        &[3, 12, MAX_PERIOD * 2],
        o,
    );
    let colour = (
        [level(o), level(o), level(o)],
        [
            [
                f32_in(-1e3, 1e3, o),
                f32_in(-1e3, 1e3, o),
                f32_in(-1e3, 1e3, o),
            ],
            [
                f32_in(-1e3, 1e3, o),
                f32_in(-1e3, 1e3, o),
                f32_in(-1e3, 1e3, o),
            ],
            [
                f32_in(-1e3, 1e3, o),
                f32_in(-1e3, 1e3, o),
                f32_in(-1e3, 1e3, o),
            ],
        ],
    )
        .prop_map(|(mean, basis)| ColourBasis { mean, basis });
    let turbulence = (
        f32_in(0.0, 1e6, o),
        [seed(), seed()],
        list(stratum(o), 1, 2, MAX_STRATA, o),
        level(o),
    )
        .prop_map(|(sigma, seeds, strata, centre)| Turbulence {
            sigma,
            seeds,
            strata,
            centre,
        });
    let channel_count = u32_from(&[1, 3], &[0, 2, MAX_CHANNELS as u32 + 1], o);
    (
        seed(),
        period,
        channel_count,
        any::<bool>(),
        proptest::option::of(turbulence),
        any::<bool>(),
    )
        .prop_flat_map(
            move |(seed, period, channels, flip_colour, turbulence, random_placement)| {
                // Periods that are not powers of two are rejected before the channels are read.
                let channel_period = if period.is_power_of_two() && period <= MAX_PERIOD {
                    period
                } else {
                    2
                };
                let count = (channels as usize).min(MAX_CHANNELS + 1);
                let wants_colour = (count == 3) != (flip_colour && o.bad > 0);
                (
                    proptest::collection::vec(channel(channel_period, o), count),
                    if wants_colour {
                        colour.clone().prop_map(Some).boxed()
                    } else {
                        Just(None).boxed()
                    },
                )
                    .prop_map(move |(channels, colour)| TextureModel {
                        seed,
                        period,
                        channels,
                        colour,
                        turbulence: turbulence.clone(),
                        random_placement,
                    })
            },
        )
        .boxed()
}

impl FuzzKind for TextureModel {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        texture(o).prop_map(Model::Texture).boxed()
    }
}

/// One channel's or one turbulence axis's strata: `9(J_S + 1)` calls for each of 64 strata.
#[cfg(feature = "cpu")]
const STRATA_MAX_COST: f64 = 9.0 * (MAX_COSINES as f64 + 1.0) * MAX_STRATA as f64;

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for TextureModel {
    /// Three channels of strata and a structure (4 blocks of 1024 cosines), and two turbulence
    /// axes.
    const MAX_COST: f64 =
        MAX_CHANNELS as f64 * (STRATA_MAX_COST + 4.0 * MAX_COSINES as f64) + 2.0 * STRATA_MAX_COST;
}
