//! The one place the Python builders get their defaults: each builder's default model, made by
//! `spectex-model`'s own builder for that kind (its `DEFAULT_` constants, which the `spectex
//! noise` flags default to as well). The Python functions' signatures are generated from these
//! models' fields at import, so a default changed in `spectex-model` changes here and in Python
//! with nothing else to edit.

use spectex_model::classic::{Basis, FractalKind, Worley};
use spectex_model::{
    ClassicNoise, GaborNoise, IslamicPattern, MatrixTransform, Model, ModelError, PhasorNoise,
    SpectralTarget, StochasticSubdivision, TextonNoise, VoronoiNoise, WaveletNoise,
};

/// Every builder: its name (the Python function's) and what it makes, for docstrings.
pub(crate) const BUILDERS: &[(&str, &str)] = &[
    (
        "perlin",
        "improved Perlin gradient noise (Perlin 2002); octaves=… makes its fBm",
    ),
    ("simplex", "simplex noise (Perlin 2001, Gustavson 2005)"),
    (
        "value",
        "value noise: random lattice values, quintic interpolation",
    ),
    (
        "kensler",
        "Kensler, Knoll & Shirley's better gradient noise",
    ),
    (
        "worley",
        "Worley cellular noise C1·F1 + C2·F2 + C3·F3 + C4·F4",
    ),
    (
        "fbm",
        "fractional Brownian motion: Σ gainᵒ·n over octaves of a basis",
    ),
    (
        "turbulence",
        "turbulence: Σ gainᵒ·|n| over octaves of a basis",
    ),
    ("ridged", "Musgrave's ridged multifractal of a basis"),
    (
        "gabor",
        "Gabor noise by sparse convolution (Lagae et al. 2009)",
    ),
    ("phasor", "phasor noise (Tricard et al. 2019)"),
    ("wavelet", "wavelet noise (Cook & DeRose 2005)"),
    (
        "voronoi",
        "Voronoi diagrams: cell IDs, distances, borders, colours",
    ),
    ("texton", "texton placement and spot noise"),
    ("islamic", "Islamic star patterns on regular tilings"),
    (
        "subdivision",
        "stochastic subdivision (midpoint displacement)",
    ),
    (
        "matrix",
        "matrix transformation: a source on a torus moved by an integer matrix (survey §2.4)",
    ),
];

/// The spectral targets an LRP noise is fitted to (`spectex noise ring|lobe|band|fractal`,
/// through `spectex_sampling::LrpFromTarget`): the Python function's name and what it makes.
pub(crate) const TARGETS: &[(&str, &str)] = &[
    (
        "ring",
        "LRP noise whose power lies on a ring of radius ``radius`` (Gilet et al. 2014, Fig. 10)",
    ),
    (
        "lobe",
        "anisotropic LRP noise: two Gaussian lobes at ±``frequency`` in the direction ``angle`` \
         (Gilet et al. 2014, Fig. 3)",
    ),
    (
        "band",
        "LRP noise of a band-pass annulus: power 1 for ``min`` ≤ |f| ≤ ``max``",
    ),
    (
        "fractal",
        "LRP noise of a 1/f^β fractal spectrum (the texture survey's Eq. 8); ``spread`` makes \
         it anisotropic",
    ),
];

/// The target of `spectex noise NAME` with every parameter at the command's default, its
/// angles in radians (the model's unit), converted from the command's degrees as the command
/// converts them; `None` for an unknown name.
pub(crate) fn default_target(name: &str) -> Option<SpectralTarget> {
    type T = SpectralTarget;
    Some(match name {
        "ring" => T::Ring {
            radius: T::DEFAULT_RING_RADIUS,
            width: T::DEFAULT_RING_WIDTH,
        },
        "lobe" => T::Lobes {
            frequency: T::DEFAULT_LOBE_FREQUENCY,
            angle: T::DEFAULT_LOBE_ANGLE_DEGREES.to_radians(),
            width: T::DEFAULT_LOBE_WIDTH,
        },
        "band" => T::Band {
            min: T::DEFAULT_BAND_MIN,
            max: T::DEFAULT_BAND_MAX,
        },
        "fractal" => T::Fractal {
            beta: T::DEFAULT_FRACTAL_BETA,
            angle: T::DEFAULT_FRACTAL_ANGLE_DEGREES.to_radians(),
            spread: None,
            min_frequency: T::DEFAULT_FRACTAL_MIN_FREQUENCY,
        },
        _ => return None,
    })
}

/// The bases a fractal sum takes, by their Python name.
pub(crate) const BASES: &[&str] = &["perlin", "simplex", "value", "kensler", "worley"];

fn basis(name: &str) -> Option<Basis> {
    Some(match name {
        "perlin" => Basis::Gradient,
        "simplex" => Basis::Simplex,
        "value" => Basis::Value,
        "kensler" => Basis::Kensler,
        "worley" => Basis::Worley(Worley::default()),
        _ => return None,
    })
}

/// The default model of builder `name`; `variant` is a fractal sum's basis (`"perlin"` unless
/// given) or, for a single basis, `"fractal"` for its fBm (the builder that has octaves).
/// `None` for an unknown name or variant.
pub(crate) fn default_model(
    name: &str,
    variant: Option<&str>,
) -> Option<Result<Model, ModelError>> {
    let sum = match name {
        "fbm" => Some(FractalKind::Fbm),
        "turbulence" => Some(FractalKind::Turbulence),
        "ridged" => Some(FractalKind::Ridged {
            offset: ClassicNoise::DEFAULT_RIDGE_OFFSET,
            weight_gain: ClassicNoise::DEFAULT_RIDGE_WEIGHT_GAIN,
        }),
        _ => None,
    };
    if let Some(sum) = sum {
        let b = basis(variant.unwrap_or("perlin"))?;
        return Some(
            ClassicNoise::builder(b)
                .fractal(sum)
                .build()
                .map(Model::from),
        );
    }
    if let Some(b) = basis(name) {
        let builder = ClassicNoise::builder(b);
        return match variant {
            None => Some(builder.build().map(Model::from)),
            Some("fractal") => Some(builder.fractal(FractalKind::Fbm).build().map(Model::from)),
            Some(_) => None,
        };
    }
    if variant.is_some() {
        return None;
    }
    Some(match name {
        "gabor" => GaborNoise::builder().build().map(Model::from),
        "phasor" => PhasorNoise::builder().build().map(Model::from),
        "wavelet" => WaveletNoise::builder().build().map(Model::from),
        "voronoi" => VoronoiNoise::builder().build().map(Model::from),
        "texton" => TextonNoise::builder().build().map(Model::from),
        "islamic" => IslamicPattern::builder().build().map(Model::from),
        "subdivision" => StochasticSubdivision::builder().build().map(Model::from),
        "matrix" => MatrixTransform::builder().build().map(Model::from),
        _ => return None,
    })
}

/// `target`'s variant name (as in a model file) and parameters in the order `SpectralTarget`
/// defines them, an absent optional one (the fractal's `spread`) as `None`. Only the targets of
/// [`TARGETS`] have builders; a sum or a discrete target has no parameters here.
pub(crate) fn target_parameters(
    target: &SpectralTarget,
) -> (&'static str, Vec<(&'static str, Option<f32>)>) {
    type T = SpectralTarget;
    match *target {
        T::Ring { radius, width } => (
            "ring",
            vec![("radius", Some(radius)), ("width", Some(width))],
        ),
        T::Lobes {
            frequency,
            angle,
            width,
        } => (
            "lobes",
            vec![
                ("frequency", Some(frequency)),
                ("angle", Some(angle)),
                ("width", Some(width)),
            ],
        ),
        T::Band { min, max } => ("band", vec![("min", Some(min)), ("max", Some(max))]),
        T::Fractal {
            beta,
            angle,
            spread,
            min_frequency,
        } => (
            "fractal",
            vec![
                ("beta", Some(beta)),
                ("angle", Some(angle)),
                ("spread", spread),
                ("min_frequency", Some(min_frequency)),
            ],
        ),
        T::Sum { .. } => ("sum", Vec::new()),
        T::Discrete { .. } => ("discrete", Vec::new()),
    }
}
