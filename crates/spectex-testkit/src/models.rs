//! Structure-aware random models of every kind, for fuzzing: each field drawn around and beyond
//! its valid range ([`crate::strategy`]), lists empty, typical or one past their limit, profiles
//! and warps nested up to and past their depth limits.
//!
//! Each kind declares its strategy as its [`FuzzKind`]; [`KIND_STRATEGIES`] collects them
//! through `spectex_model::for_each_kind!`, so a new kind without a strategy does not compile.

use std::sync::LazyLock;

use proptest::prelude::*;
use spectex_model::classic::{
    Basis, FeaturePoints, Fractal, FractalKind, MAX_OCTAVES, Metric, WORLEY_MAX_POINTS, Worley,
};
use spectex_model::combine::{
    Combine as Combination, CombineOp, MAX_STOPS, MAX_TABLE_KNOTS, RampStop,
};
use spectex_model::islamic::{IslamicOutput, IslamicPattern, Motif, Tiling};
use spectex_model::matrix::{MAX_ENTRY, MAX_RINGS, MatrixSource, MatrixTransform};
use spectex_model::subdivision::{MAX_LEVELS, Stencil, StochasticSubdivision};
use spectex_model::texton::{Combine, MAX_DENSITY, MAX_REACH, Placement, Spot, TextonNoise};
use spectex_model::texture::{MAX_CHANNELS, MAX_PERIOD};
use spectex_model::voronoi::{MAX_PALETTE, VoronoiNoise, VoronoiOutput};
use spectex_model::warp::{MAX_STRENGTH, MAX_WARP_DEPTH};
use spectex_model::wavelet::{MAX_BANDS, MAX_TILE_2D, MAX_TILE_3D, MIN_TILE};
use spectex_model::{
    ClassicNoise, ColourBasis, Field, FixedCosine, GaborNoise, Harmonic, LrpNoise, MAX_COSINES,
    MAX_FIELD_SIDE, MAX_PROFILE_SAMPLES, MAX_STRATA, Model, ModelKind, Orientation, PhasorNoise,
    PhasorOrientation, PhasorOutput, Profile, Stratum, Structure, TextureChannel, TextureModel,
    Turbulence, Warp, WaveletNoise,
};

use crate::strategy::{Odds, f32_in, f32_inside, list, odds, u32_from, u32_in};

/// A model-producing strategy for one kind, given the case's odds and how many warps may still
/// nest inside it.
pub type KindStrategy = fn(Odds, usize) -> BoxedStrategy<Model>;

/// What the kit generates of one kind: its structure-aware strategy. Every kind implements it
/// (the collection below goes through `spectex_model::for_each_kind!`, so a kind without one
/// does not compile).
pub trait FuzzKind: ModelKind {
    /// Models of the kind, given the case's odds and how many warps may still nest inside.
    fn strategy(o: Odds, depth: usize) -> BoxedStrategy<Model>;
}

impl FuzzKind for LrpNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        lrp(o).prop_map(Model::Lrp).boxed()
    }
}

impl FuzzKind for GaborNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        gabor(o).prop_map(Model::Gabor).boxed()
    }
}

impl FuzzKind for PhasorNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        phasor(o).prop_map(Model::Phasor).boxed()
    }
}

impl FuzzKind for TextureModel {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        texture(o).prop_map(Model::Texture).boxed()
    }
}

impl FuzzKind for ClassicNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        classic(o).prop_map(Model::Classic).boxed()
    }
}

impl FuzzKind for Warp {
    fn strategy(o: Odds, depth: usize) -> BoxedStrategy<Model> {
        warp(o, depth).prop_map(Model::Warp).boxed()
    }
}

impl FuzzKind for WaveletNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        wavelet(o).prop_map(Model::Wavelet).boxed()
    }
}

impl FuzzKind for TextonNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        texton(o).prop_map(Model::Texton).boxed()
    }
}

impl FuzzKind for VoronoiNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        voronoi(o).prop_map(Model::Voronoi).boxed()
    }
}

impl FuzzKind for spectex_model::Combine {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        combine(o).prop_map(Model::Combine).boxed()
    }
}

impl FuzzKind for IslamicPattern {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        islamic(o).prop_map(Model::Islamic).boxed()
    }
}

impl FuzzKind for MatrixTransform {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        matrix(o).prop_map(Model::Matrix).boxed()
    }
}

impl FuzzKind for StochasticSubdivision {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        subdivision(o).prop_map(Model::Subdivision).boxed()
    }
}

/// One strategy per model kind, by [`spectex_model::ModelKind::NAME`], in the order of
/// [`Model`]'s variants: what each kind declares as its [`FuzzKind`].
pub static KIND_STRATEGIES: LazyLock<Vec<(&'static str, KindStrategy)>> = LazyLock::new(|| {
    let mut strategies: Vec<(&'static str, KindStrategy)> = Vec::new();
    spectex_model::for_each_kind!(types: K => {
        strategies.push((<K as ModelKind>::NAME, <K as FuzzKind>::strategy));
    });
    strategies
});

/// Warps nested at most in generated models: two past [`MAX_WARP_DEPTH`], so the limit itself
/// and what lies beyond it are both drawn.
pub const MAX_GENERATED_WARP_DEPTH: usize = MAX_WARP_DEPTH + 2;

/// A model of any kind (every kind equally often), with the odds drawn per case.
pub fn any_model() -> BoxedStrategy<Model> {
    odds()
        .prop_flat_map(|o| model(o, MAX_GENERATED_WARP_DEPTH))
        .boxed()
}

/// A model of any kind with odds `o`, nesting at most `depth` warps.
pub fn model(o: Odds, depth: usize) -> BoxedStrategy<Model> {
    let kinds: Vec<BoxedStrategy<Model>> = KIND_STRATEGIES
        .iter()
        .filter(|(name, _)| depth > 0 || (*name != "warp" && *name != "combine"))
        .map(|(_, strategy)| strategy(o, depth))
        .collect();
    proptest::strategy::Union::new(kinds).boxed()
}

/// A model of the kind named `kind` (a [`spectex_model::KIND_NAMES`] entry), or `None`.
pub fn model_of_kind(kind: &str, o: Odds) -> Option<BoxedStrategy<Model>> {
    KIND_STRATEGIES
        .iter()
        .find(|(name, _)| *name == kind)
        .map(|(_, strategy)| strategy(o, MAX_GENERATED_WARP_DEPTH))
}

fn seed() -> BoxedStrategy<u32> {
    prop_oneof![any::<u32>(), Just(0u32), Just(u32::MAX)].boxed()
}

/// A mean or gain: valid in `[−1e9, 1e9]`, usually near `[−1, 1]`.
fn level(o: Odds) -> BoxedStrategy<f32> {
    f32_in(-1e9, 1e9, o)
}

/// An angle in radians, valid in `[−1000, 1000]`.
fn angle(o: Odds) -> BoxedStrategy<f32> {
    f32_in(-1e3, 1e3, o)
}

// ---------------------------------------------------------------------------------------------
// LRP noise.

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

// ---------------------------------------------------------------------------------------------
// Gabor noise.

/// A Gabor noise (bandwidth `[0.001, 10]`, frequency `[0, 0.5]`, impulses `[0.01, 1000]`).
pub fn gabor(o: Odds) -> BoxedStrategy<GaborNoise> {
    // Two independent angles are out of order half the time: only with the odds.
    let unordered = if o.bad > 0 { 1 } else { 0 };
    let orientation = prop_oneof![
        2 => angle(o).prop_map(|angle| Orientation::Anisotropic { angle }),
        2 => (angle(o), f32_in(0.0, 7.0, o)).prop_map(|(min, span)| Orientation::Isotropic {
            min,
            max: min + span,
        }),
        unordered => (angle(o), angle(o)).prop_map(|(min, max)| Orientation::Isotropic { min, max }),
    ];
    (
        seed(),
        level(o),
        f32_in(0.0, 1e9, o),
        f32_in(1e-3, 10.0, o),
        f32_in(0.0, 0.5, o),
        orientation,
        f32_in(0.01, 1000.0, o),
    )
        .prop_map(
            |(seed, mean, amplitude, bandwidth, frequency, orientation, impulses_per_kernel)| {
                GaborNoise {
                    seed,
                    mean,
                    amplitude,
                    bandwidth,
                    frequency,
                    orientation,
                    impulses_per_kernel,
                }
            },
        )
        .boxed()
}

// ---------------------------------------------------------------------------------------------
// Phasor noise.

/// A [`Field`] whose values are valid in `[lo, hi]`: a constant, a ramp (gradients small enough
/// to stay in range over `RAMP_EXTENT`, or anything in `[−1000, 1000]`), or a small image.
pub fn field(lo: f32, hi: f32, o: Odds) -> BoxedStrategy<Field> {
    // A ramp stays valid when Σ|g|·1e4 ≤ (hi − lo)/2 around a centred value (and a gradient
    // is valid up to 1000 per pixel).
    let gentle = ((hi - lo) / 1e5).min(1e3);
    let steep = if o.bad > 0 { 1 } else { 0 };
    let gradient = prop_oneof![
        4 => [f32_inside(-gentle, gentle), f32_inside(-gentle, gentle), f32_inside(-gentle, gentle)],
        steep => [f32_in(-1e3, 1e3, o), f32_in(-1e3, 1e3, o), f32_in(-1e3, 1e3, o)],
    ];
    let centre = lo + (hi - lo) / 2.0;
    let ramp_value = prop_oneof![3 => Just(centre), steep => f32_in(lo, hi, o)];
    prop_oneof![
        3 => f32_in(lo, hi, o).prop_map(|value| Field::Constant { value }),
        2 => (ramp_value, gradient).prop_map(|(value, gradient)| Field::Linear { value, gradient }),
        2 => image_field(lo, hi, o),
    ]
    .boxed()
}

/// An image field of up to 5×5 samples (with the odds: no samples, a side past 4096, grey
/// levels outside `[0, 1]`, a sample count that does not match).
fn image_field(lo: f32, hi: f32, o: Odds) -> BoxedStrategy<Field> {
    let side = u32_in(1, 5, o).prop_map(|s| s as usize);
    let huge = if o.bad > 0 { 1 } else { 0 };
    let side_or_huge = prop_oneof![
        9 => side,
        huge => Just(MAX_FIELD_SIDE + 1),
    ];
    (
        side_or_huge.clone(),
        side_or_huge,
        any::<bool>(),
        f32_in(1e-3, 1e6, o),
        f32_in(lo, hi, o),
        f32_in(lo, hi, o),
    )
        .prop_flat_map(move |(width, height, mismatch, pixel_size, min, max)| {
            // Only small images are filled: a side past the limit is rejected before its
            // samples are read, so one sample stands for them.
            let count = if width * height > 64 {
                1
            } else if mismatch && o.bad > 0 {
                width * height + 1
            } else {
                width * height
            };
            proptest::collection::vec(f32_in(0.0, 1.0, o), count).prop_map(move |grey| {
                Field::Image {
                    width,
                    height,
                    grey,
                    pixel_size,
                    min,
                    max,
                }
            })
        })
        .boxed()
}

/// A phasor bandwidth, per pixel in `[0.001, 1]`: a field over any range with the odds, else
/// one whose largest value is at most 1.5 times its smallest (a wider range multiplies the
/// impulses drawn per cell by its ratio squared or cubed, past the limit of 64).
fn bandwidth(o: Odds) -> BoxedStrategy<Field> {
    if o.bad > 0 {
        return field(1e-3, 1.0, o);
    }
    (f32_inside(1e-3, 0.6), 1.0f32..1.5, image_field(0.0, 1.0, o))
        .prop_flat_map(|(b, ratio, image)| {
            let Field::Image {
                width,
                height,
                grey,
                pixel_size,
                ..
            } = image
            else {
                return Just(Field::constant(b)).boxed();
            };
            prop_oneof![
                Just(Field::constant(b)),
                Just(Field::Linear {
                    value: b * (1.0 + ratio) / 2.0,
                    gradient: [b * (ratio - 1.0) / 7e4, 0.0, -b * (ratio - 1.0) / 7e4],
                }),
                Just(Field::Image {
                    width,
                    height,
                    grey,
                    pixel_size,
                    min: b,
                    max: b * ratio,
                }),
            ]
            .boxed()
        })
        .boxed()
}

/// A profile, blends nested up to 6 deep (the limit is 4).
pub fn profile(o: Odds) -> BoxedStrategy<Profile> {
    let harmonic = (u32_in(1, 1024, o), f32_in(-1e6, 1e6, o), angle(o))
        .prop_map(|(k, weight, phase)| Harmonic { k, weight, phase });
    let leaf = prop_oneof![
        Just(Profile::Sine),
        Just(Profile::Triangle),
        Just(Profile::Sawtooth),
        field(0.0, 1.0, o).prop_map(|duty| Profile::Square { duty }),
        list(f32_in(-1e6, 1e6, o), 2, 6, MAX_PROFILE_SAMPLES, o)
            .prop_map(|values| Profile::Samples { values }),
        list(harmonic.boxed(), 1, 4, MAX_PROFILE_SAMPLES, o)
            .prop_map(|terms| Profile::Harmonics { terms }),
    ];
    leaf.prop_recursive(6, 12, 2, move |inner| {
        (inner.clone(), inner, field(-1e9, 1e9, o)).prop_map(|(a, b, weight)| Profile::Blend {
            a: Box::new(a),
            b: Box::new(b),
            weight,
        })
    })
    .boxed()
}

/// A phasor noise, 2D or 3D, with every orientation mode, profile and output.
pub fn phasor(o: Odds) -> BoxedStrategy<PhasorNoise> {
    let orientation = prop_oneof![
        field(-1e3, 1e3, o).prop_map(|angle| PhasorOrientation::Aligned { angle }),
        (
            prop_oneof![4 => image_field(0.0, 1.0, o), usize::from(o.bad > 0) as u32 => field(0.0, 1.0, o)],
            angle(o)
        )
            .prop_map(|(image, offset)| PhasorOrientation::Gradient { image, offset }),
        (angle(o), angle(o))
            .prop_map(|(angle_a, angle_b)| PhasorOrientation::TwoLobes { angle_a, angle_b }),
        Just(PhasorOrientation::Isotropic),
        (f32_in(0.0, std::f32::consts::PI, o), f32_in(0.05, 4.0, o)).prop_map(
            |(spread, bandwidth_ratio)| PhasorOrientation::Coherent {
                spread,
                bandwidth_ratio,
            }
        ),
    ];
    let output = prop_oneof![
        Just(PhasorOutput::Profiled),
        Just(PhasorOutput::Phase),
        Just(PhasorOutput::Intensity),
        Just(PhasorOutput::Gabor),
    ];
    let dimensions = u32_from(&[2, 3], &[1, 4, 255], o).prop_map(|d| d as u8);
    (
        (seed(), dimensions, bandwidth(o), field(0.0, 0.5, o)),
        (orientation, f32_in(0.01, 200.0, o), profile(o), output),
        (level(o), level(o)),
    )
        .prop_map(
            |(
                (seed, dimensions, bandwidth, frequency),
                (orientation, impulses_per_kernel, profile, output),
                (mean, amplitude),
            )| PhasorNoise {
                seed,
                dimensions,
                bandwidth,
                frequency,
                orientation,
                impulses_per_kernel,
                profile,
                output,
                mean,
                amplitude,
            },
        )
        .boxed()
}

// ---------------------------------------------------------------------------------------------
// Texture by example.

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

// ---------------------------------------------------------------------------------------------
// Classic noises.

/// A classic noise: every basis (Worley with every metric and point process), with or without
/// every kind of fractal sum.
pub fn classic(o: Odds) -> BoxedStrategy<ClassicNoise> {
    let metric = prop_oneof![
        Just(Metric::Euclidean),
        Just(Metric::Manhattan),
        Just(Metric::Chebyshev),
    ];
    let coefficient = prop_oneof![
        2 => Just(0.0f32),
        3 => f32_in(-1e3, 1e3, o),
    ];
    let points = prop_oneof![
        u32_in(1, WORLEY_MAX_POINTS, o).prop_map(FeaturePoints::Fixed),
        f32_in(0.5, 4.0, o).prop_map(FeaturePoints::Poisson),
    ];
    let worley = (
        metric,
        [
            coefficient.clone(),
            coefficient.clone(),
            coefficient.clone(),
            coefficient,
        ],
        points,
    )
        .prop_map(|(metric, coefficients, points)| {
            Basis::Worley(Worley {
                metric,
                coefficients,
                points,
            })
        });
    let basis = prop_oneof![
        Just(Basis::Gradient),
        Just(Basis::Simplex),
        Just(Basis::Value),
        Just(Basis::Kensler),
        worley,
    ];
    let kind = prop_oneof![
        Just(FractalKind::Fbm),
        Just(FractalKind::Turbulence),
        (f32_in(0.0, 4.0, o), f32_in(0.0, 16.0, o)).prop_map(|(offset, weight_gain)| {
            FractalKind::Ridged {
                offset,
                weight_gain,
            }
        }),
    ];
    let fractal = (
        kind,
        u32_in(1, MAX_OCTAVES, o),
        f32_in(1.0, 16.0, o),
        f32_in(0.0, 2.0, o),
    )
        .prop_map(|(kind, octaves, lacunarity, gain)| Fractal {
            kind,
            octaves,
            lacunarity,
            gain,
        });
    (
        seed(),
        u32_from(&[2, 3], &[1, 4], o),
        f32_in(1.0, 1e6, o),
        basis,
        proptest::option::of(fractal),
        level(o),
        level(o),
    )
        .prop_map(
            move |(seed, dimensions, cell_size, basis, mut fractal, amplitude, mean)| {
                // Without the odds, keep the finest octave's cell at 1 pixel or more.
                if let (Some(f), 0) = (&mut fractal, o.bad) {
                    while f.octaves > 1
                        && f64::from(cell_size) / f64::from(f.lacunarity).powi(f.octaves as i32 - 1)
                            < 1.0
                    {
                        f.octaves -= 1;
                    }
                }
                ClassicNoise {
                    seed,
                    dimensions,
                    cell_size,
                    basis,
                    fractal,
                    amplitude,
                    mean,
                }
            },
        )
        .boxed()
}

// ---------------------------------------------------------------------------------------------
// Wavelet noise.

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

// ---------------------------------------------------------------------------------------------
// Texton placement.

/// A texton noise: grid or Poisson placement, ellipsoid, Gaussian or a small image (sometimes
/// with a texel count that does not match its sides), ranges drawn inside and beyond their
/// limits; without the odds the cell is widened so the texton reaches at most 3 cells.
pub fn texton(o: Odds) -> BoxedStrategy<TextonNoise> {
    let placement = prop_oneof![
        f32_in(0.0, 1.0, o).prop_map(|jitter| Placement::Grid { jitter }),
        f32_in(0.01, MAX_DENSITY, o).prop_map(|density| Placement::Poisson { density }),
    ];
    let image = (u32_in(1, 6, o), u32_in(1, 6, o)).prop_flat_map(move |(width, height)| {
        let n = (width as usize * height as usize).min(64);
        let len = prop_oneof![8 => Just(n), 1 => Just(n + 1), 1 => Just(n.saturating_sub(1))];
        len.prop_flat_map(move |len| {
            proptest::collection::vec(f32_in(-2.0, 2.0, o), len).prop_map(move |values| {
                Spot::Image {
                    width,
                    height,
                    values,
                }
            })
        })
    });
    let spot = prop_oneof![Just(Spot::Ellipsoid), Just(Spot::Gaussian), image];
    let pair = |lo: f32, hi: f32| (f32_in(lo, hi, o), f32_in(lo, hi, o)).prop_map(|(a, b)| [a, b]);
    (
        seed(),
        f32_in(1.0, 4096.0, o),
        placement,
        spot,
        pair(0.5, 64.0),
        pair(-2.0, 2.0),
        pair(0.05, 2.0),
        (level(o), level(o)).prop_map(|(a, b)| [a, b]),
        prop_oneof![Just(Combine::Sum), Just(Combine::Max)],
        level(o),
    )
        .prop_map(
            move |(
                seed,
                cell,
                placement,
                spot,
                radii,
                rotation,
                scale,
                intensity,
                combine,
                mean,
            )| {
                let mut cell_size = cell;
                if o.bad == 0 {
                    // The texton's reach, `max(a, b)·max s / C`, within MAX_REACH cells.
                    let reach = radii[0].max(radii[1]) * scale[0].max(scale[1]);
                    cell_size = cell_size.max((reach / MAX_REACH as f32) * 1.01).min(4096.0);
                }
                TextonNoise {
                    seed,
                    cell_size,
                    placement,
                    spot,
                    radii,
                    rotation,
                    scale,
                    intensity,
                    combine,
                    mean,
                }
            },
        )
        .boxed()
}

// ---------------------------------------------------------------------------------------------
// Voronoi diagrams.

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

// ---------------------------------------------------------------------------------------------
// Islamic patterns.

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

// ---------------------------------------------------------------------------------------------
// Matrix transformations.

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

// ---------------------------------------------------------------------------------------------
// Stochastic subdivision.

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

// ---------------------------------------------------------------------------------------------
// Combinations.

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

// ---------------------------------------------------------------------------------------------
// Domain warping.

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
