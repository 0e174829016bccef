//! The one place the Python builders get their defaults: each builder's default model, made by
//! `spectex-model`'s own builder for that kind (its `DEFAULT_` constants, which the `spectex
//! noise` flags default to as well). The Python functions' signatures are generated from these
//! models' fields at import, so a default changed in `spectex-model` changes here and in Python
//! with nothing else to edit.

use spectex_model::classic::{Basis, FractalKind, Worley};
use spectex_model::{
    ClassicNoise, GaborNoise, IslamicPattern, Model, ModelError, PhasorNoise,
    StochasticSubdivision, TextonNoise, VoronoiNoise, WaveletNoise,
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
];

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
        _ => return None,
    })
}
