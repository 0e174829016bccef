//! Phasor noise's fuzz strategy and CPU cost bound: fields (constant, ramp, image), profiles
//! nested past their limit, every orientation mode and output.

use proptest::prelude::*;
use spectex_model::{
    Field, Harmonic, MAX_FIELD_SIDE, MAX_PROFILE_SAMPLES, Model, PhasorNoise, PhasorOrientation,
    PhasorOutput, Profile,
};

use super::{FuzzKind, angle, level, seed};
use crate::strategy::{Odds, f32_in, f32_inside, list, u32_from, u32_in};

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

impl FuzzKind for PhasorNoise {
    fn strategy(o: Odds, _depth: usize) -> BoxedStrategy<Model> {
        phasor(o).prop_map(Model::Phasor).boxed()
    }
}

#[cfg(feature = "cpu")]
impl crate::cpu::CostBound for PhasorNoise {
    /// `27λ` kernels in 3D, `λ < 64` impulses per cell (`PhasorNoise::validate`), each with
    /// `27λ` more for a coherent direction.
    const MAX_COST: f64 = 27.0 * 64.0 * (1.0 + 27.0 * 64.0);
}
