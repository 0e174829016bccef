//! Models at each limit `spectex-model` validates and one step past it, built directly (some
//! are too large for a strategy to draw element by element): the longest lists, the deepest
//! nesting, the costliest valid model of each kind. A valid one must render in bounded time; an
//! invalid one must be refused naming the field.

use spectex_model::classic::{
    Basis, FeaturePoints, Fractal, FractalKind, MAX_OCTAVES, Metric, Worley,
};
use spectex_model::texture::{MAX_PERIOD, MAX_STRUCTURE_COSINES};
use spectex_model::warp::MAX_WARP_DEPTH;
use spectex_model::wavelet::{MAX_BANDS, MAX_TILE_2D, MAX_TILE_3D};
use spectex_model::{
    ClassicNoise, ColourBasis, Field, FixedCosine, GaborNoise, Harmonic, LrpNoise, MAX_COSINES,
    MAX_FIELD_SIDE, MAX_PROFILE_SAMPLES, MAX_STRATA, MAX_TABLE, Model, Orientation, PhasorNoise,
    PhasorOrientation, PhasorOutput, Profile, Stratum, Structure, TextureChannel, TextureModel,
    Turbulence, Warp, WaveletNoise,
};

/// One limit case.
#[derive(Debug, Clone)]
pub struct LimitCase {
    /// What it probes.
    pub name: String,
    /// The model.
    pub model: Model,
    /// Whether validation must accept it.
    pub valid: bool,
}

fn case(name: &str, model: Model, valid: bool) -> LimitCase {
    LimitCase {
        name: name.to_owned(),
        model,
        valid,
    }
}

fn stratum(cosines: usize, table: usize) -> Stratum {
    Stratum {
        window_width: 0.5,
        amplitude: 1e9,
        sub_strata: vec![
            (0..table)
                .map(|k| [((k % 1000) as f32 / 1000.0) - 0.5, 0.5])
                .collect();
            cosines
        ],
    }
}

fn lrp(strata: usize, cosines: usize, table: usize) -> Model {
    Model::Lrp(LrpNoise {
        seed: 1,
        mean: 1e9,
        strata: vec![stratum(cosines, table); strata],
    })
}

fn phasor(bandwidth: Field, impulses: f32, profile: Profile, dimensions: u8) -> Model {
    Model::Phasor(PhasorNoise {
        seed: 2,
        dimensions,
        bandwidth,
        frequency: Field::constant(0.5),
        orientation: PhasorOrientation::Coherent {
            spread: std::f32::consts::PI,
            bandwidth_ratio: 0.05,
        },
        impulses_per_kernel: impulses,
        profile,
        output: PhasorOutput::Profiled,
        mean: 0.0,
        amplitude: 1e9,
    })
}

fn blend(depth: usize) -> Profile {
    if depth == 0 {
        Profile::Sine
    } else {
        Profile::Blend {
            a: Box::new(blend(depth - 1)),
            b: Box::new(Profile::Sawtooth),
            weight: Field::constant(0.5),
        }
    }
}

fn grey_texture(period: u32, blocks: u32, cosines_per_block: usize) -> Model {
    let n = (2 * period / blocks) as i32;
    let cosine = FixedCosine {
        frequency: [n / 2, -n / 2 + 1],
        amplitude: 1e9,
        phase: 1.0,
    };
    Model::Texture(TextureModel {
        seed: 3,
        period,
        channels: vec![TextureChannel {
            seed: 4,
            mean: 0.0,
            strata: Vec::new(),
            structure: Some(Structure {
                blocks,
                cosines: vec![vec![cosine; cosines_per_block]; (blocks * blocks) as usize],
            }),
        }],
        colour: None,
        turbulence: None,
        random_placement: true,
    })
}

/// The costliest texture: three channels of 64 strata of 1024 cosines, 4 structure blocks of
/// 1024 cosines each, turbulence of 64 strata of 1024 cosines.
fn costliest_texture() -> Model {
    let cosine = FixedCosine {
        frequency: [1, 1],
        amplitude: 1.0,
        phase: 0.5,
    };
    let strata = vec![stratum(MAX_COSINES, 1); MAX_STRATA];
    let channel = |seed| TextureChannel {
        seed,
        mean: 0.5,
        strata: strata.clone(),
        structure: Some(Structure {
            blocks: 2,
            cosines: vec![vec![cosine; MAX_COSINES]; 4],
        }),
    };
    Model::Texture(TextureModel {
        seed: 5,
        period: 8,
        channels: vec![channel(6), channel(7), channel(8)],
        colour: Some(ColourBasis {
            mean: [1e9; 3],
            basis: [[1e3; 3]; 3],
        }),
        turbulence: Some(Turbulence {
            sigma: 1e6,
            seeds: [9, 10],
            strata,
            centre: 1e9,
        }),
        random_placement: true,
    })
}

fn classic(octaves: u32, dimensions: u32, basis: Basis) -> Model {
    Model::Classic(ClassicNoise {
        seed: 11,
        dimensions,
        cell_size: 2f32.powi(MAX_OCTAVES as i32 - 1),
        basis,
        fractal: Some(Fractal {
            kind: FractalKind::Ridged {
                offset: 4.0,
                weight_gain: 16.0,
            },
            octaves,
            lacunarity: 2.0,
            gain: 2.0,
        }),
        amplitude: 1e9,
        mean: -1e9,
    })
}

fn wavelet(dimensions: u32, tile_size: u32, bands: usize) -> Model {
    Model::Wavelet(WaveletNoise {
        seed: 12,
        dimensions,
        tile_size,
        cell_size: 2f32.powi(MAX_BANDS as i32 - 1),
        bands: vec![1e3; bands],
        amplitude: 1e9,
        mean: 1e9,
    })
}

/// A warp of `depth` levels whose every slot nests the next level: `3^depth` leaves.
fn full_warp_tree(depth: usize) -> Model {
    if depth == 0 {
        return spectex_model::fixtures::constant(0.25);
    }
    let sub = full_warp_tree(depth - 1);
    Model::Warp(Warp {
        base: Box::new(sub.clone()),
        x: Box::new(sub.clone()),
        y: Box::new(sub),
        strength: 65_536.0,
    })
}

/// A chain of `depth` warps nesting through `base`, over an LRP noise.
fn warp_chain(depth: usize) -> Model {
    let mut model = lrp(1, 4, 3);
    for _ in 0..depth {
        model = Model::Warp(Warp {
            base: Box::new(model),
            x: Box::new(spectex_model::fixtures::constant(1e9)),
            y: Box::new(spectex_model::fixtures::constant(-1e9)),
            strength: -65_536.0,
        });
    }
    model
}

/// Poisson textons of density 8 whose largest radius at the largest scale is `reach` cells;
/// the spot a 1024 × 1024 image, or a Gaussian.
fn texton(reach: f32, image: bool) -> Model {
    let side = spectex_model::texton::MAX_IMAGE_SIDE;
    Model::Texton(spectex_model::TextonNoise {
        seed: 14,
        cell_size: 1.0,
        placement: spectex_model::texton::Placement::Poisson {
            density: spectex_model::texton::MAX_DENSITY,
        },
        spot: if image {
            spectex_model::texton::Spot::Image {
                width: side,
                height: side,
                values: (0..side * side)
                    .map(|k| (k % 251) as f32 * 3.98e6)
                    .collect(),
            }
        } else {
            spectex_model::texton::Spot::Gaussian
        },
        radii: [reach / spectex_model::texton::MAX_SCALE, 1e-3],
        rotation: [-1e4, 1e4],
        scale: [1e-3, spectex_model::texton::MAX_SCALE],
        intensity: [-1e9, 1e9],
        combine: spectex_model::texton::Combine::Sum,
        mean: 1e9,
    })
}

/// Every limit case: at the limit (valid) and one step past it (invalid).
#[must_use]
pub fn limit_cases() -> Vec<LimitCase> {
    let image = |width: usize, height: usize| Field::Image {
        width,
        height,
        grey: (0..width * height).map(|i| (i % 7) as f32 / 6.0).collect(),
        pixel_size: 1e-3,
        min: 0.02,
        max: 0.02,
    };
    let worley = Basis::Worley(Worley {
        metric: Metric::Chebyshev,
        coefficients: [0.0, 0.0, 0.0, 1e3],
        points: FeaturePoints::Poisson(0.5),
    });
    vec![
        case(
            "lrp: a table of 2^20 frequencies",
            lrp(1, 1, MAX_TABLE),
            true,
        ),
        case("lrp: a table of 2^20 + 1", lrp(1, 1, MAX_TABLE + 1), false),
        case(
            "lrp: 64 strata of 1024 cosines",
            lrp(MAX_STRATA, MAX_COSINES, 1),
            true,
        ),
        case("lrp: 65 strata", lrp(MAX_STRATA + 1, 1, 1), false),
        case("lrp: 1025 cosines", lrp(1, MAX_COSINES + 1, 1), false),
        case(
            "texture: 2^22 structure cosines",
            grey_texture(MAX_PERIOD, 64, MAX_STRUCTURE_COSINES / 4096),
            true,
        ),
        case(
            "texture: 1025 cosines in each of 4096 blocks",
            grey_texture(MAX_PERIOD, 64, MAX_COSINES + 1),
            false,
        ),
        case("texture: the costliest", costliest_texture(), true),
        case(
            "texture: period 8192",
            grey_texture(2 * MAX_PERIOD, 1, 1),
            false,
        ),
        case(
            "phasor: a 4096 × 4096 image field",
            phasor(
                image(MAX_FIELD_SIDE, MAX_FIELD_SIDE),
                30.0,
                Profile::Sine,
                2,
            ),
            true,
        ),
        case(
            "phasor: a 4097 × 1 image field",
            phasor(image(MAX_FIELD_SIDE + 1, 1), 30.0, Profile::Sine, 2),
            false,
        ),
        case(
            "phasor: 3D, 200 impulses per kernel",
            phasor(Field::constant(1.0), 200.0, blend(4), 3),
            true,
        ),
        case(
            "phasor: 5 nested blends",
            phasor(Field::constant(1.0), 30.0, blend(5), 2),
            false,
        ),
        case(
            "phasor: 4096 samples",
            phasor(
                Field::constant(0.5),
                30.0,
                Profile::Samples {
                    values: vec![1e6; MAX_PROFILE_SAMPLES],
                },
                2,
            ),
            true,
        ),
        case(
            "phasor: 4097 harmonics",
            phasor(
                Field::constant(0.5),
                30.0,
                Profile::Harmonics {
                    terms: vec![
                        Harmonic {
                            k: 1024,
                            weight: 1e6,
                            phase: 1e3,
                        };
                        MAX_PROFILE_SAMPLES + 1
                    ],
                },
                2,
            ),
            false,
        ),
        case(
            "phasor: 4096 harmonics of order 1024",
            phasor(
                Field::constant(0.5),
                30.0,
                Profile::Harmonics {
                    terms: vec![
                        Harmonic {
                            k: 1024,
                            weight: 1e6,
                            phase: 1e3,
                        };
                        MAX_PROFILE_SAMPLES
                    ],
                },
                2,
            ),
            true,
        ),
        case(
            "gabor: 1000 impulses per kernel, bandwidth 0.001",
            Model::Gabor(GaborNoise {
                seed: 13,
                mean: 1e9,
                amplitude: 1e9,
                bandwidth: 1e-3,
                frequency: 0.5,
                orientation: Orientation::Isotropic {
                    min: -1e3,
                    max: 1e3,
                },
                impulses_per_kernel: 1000.0,
            }),
            true,
        ),
        case(
            "classic: 16 octaves of 3D Worley F4, Poisson 0.5",
            classic(MAX_OCTAVES, 3, worley.clone()),
            true,
        ),
        case(
            "classic: 17 octaves",
            classic(MAX_OCTAVES + 1, 2, worley),
            false,
        ),
        case(
            "wavelet: 16 bands, 2D tile 256",
            wavelet(2, MAX_TILE_2D, MAX_BANDS),
            true,
        ),
        case(
            "wavelet: 16 bands, 3D tile 64",
            wavelet(3, MAX_TILE_3D, MAX_BANDS),
            true,
        ),
        case("wavelet: 17 bands", wavelet(2, 16, MAX_BANDS + 1), false),
        case("wavelet: 3D tile 66", wavelet(3, MAX_TILE_3D + 2, 1), false),
        case(
            "warp: a full tree 8 deep (6561 leaves)",
            full_warp_tree(MAX_WARP_DEPTH),
            true,
        ),
        case("warp: a chain 8 deep", warp_chain(MAX_WARP_DEPTH), true),
        case(
            "warp: a chain 9 deep",
            warp_chain(MAX_WARP_DEPTH + 1),
            false,
        ),
        case(
            "texton: reach 3, density 8, a 1024 × 1024 image",
            texton(3.0, true),
            true,
        ),
        case("texton: reach 4", texton(3.01, false), false),
    ]
}

/// A model file text nesting `depth` warps through `base` over an LRP noise, written as text
/// (building a model thousands deep would itself recurse that deep): past the JSON reader's
/// recursion limit it must be refused, not overflow the stack.
#[must_use]
pub fn nested_warp_text(depth: usize) -> String {
    let leaf = |m: &Model| serde_json::to_string(m).unwrap_or_default();
    let constant = leaf(&spectex_model::fixtures::constant(0.5));
    let base = leaf(&lrp(1, 2, 2));
    let text = format!(
        "{}{base}{}",
        "{\"warp\":{\"base\":".repeat(depth),
        format!(",\"x\":{constant},\"y\":{constant},\"strength\":2.0}}}}").repeat(depth)
    );
    format!("{{\"schema_version\":1,\"model\":{text}}}")
}
