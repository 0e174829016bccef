//! `spectex noise perlin|simplex|value|fbm|worley`: the classic pointwise noises of
//! `spectex_model::classic` from flags, written as a model (`--model`) and rendered.

use anyhow::{Result, anyhow};
use clap::Args;
use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric, Worley,
};
use spectex_model::{Model, ModelError};

use crate::procedural::{RenderArgs, render_to_file, write_model};

/// What every classic noise kind shares.
#[derive(Debug, Args)]
pub(crate) struct ClassicArgs {
    /// Side of a lattice cell (of the first octave), pixels (1 to 1e6).
    #[arg(long, default_value_t = 32.0)]
    cell: f32,
    /// 2 (a plane) or 3 (a volume sliced at --z).
    #[arg(long, default_value_t = 2)]
    dims: u32,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Factor applied to the noise (default: one that maps its usual range into [0, 1]).
    #[arg(long, allow_hyphen_values = true)]
    amplitude: Option<f32>,
    /// Constant added after the factor (default: as for --amplitude).
    #[arg(long, allow_hyphen_values = true)]
    mean: Option<f32>,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// Worley's options.
#[derive(Debug, Args)]
pub(crate) struct WorleyArgs {
    /// Distance between a point and the feature points.
    #[arg(long, value_enum, default_value = "euclidean")]
    metric: MetricArg,
    /// C1,C2,C3,C4 of C1·F1 + C2·F2 + C3·F3 + C4·F4 (each in [-1000, 1000]); -1,1,0,0 is F2 − F1.
    #[arg(long, value_name = "C1,C2,C3,C4", default_value = "1,0,0,0", value_parser = parse_coefficients, allow_hyphen_values = true)]
    coefficients: [f32; 4],
    /// Feature points in every cell (1 to 16).
    #[arg(long, default_value_t = 1)]
    points: u32,
    /// A Poisson number of feature points per cell with this mean (0.5 to 4), instead of --points.
    #[arg(long)]
    poisson: Option<f32>,
}

/// The distance of Worley noise.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub(crate) enum MetricArg {
    /// √(Σ δ²).
    Euclidean,
    /// Σ |δ|.
    Manhattan,
    /// max |δ|.
    Chebyshev,
}

/// The basis of a fractal sum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum BasisArg {
    /// Improved Perlin gradient noise.
    Perlin,
    /// Simplex noise.
    Simplex,
    /// Value noise.
    Value,
    /// Worley cellular noise (with the Worley options).
    Worley,
}

/// How the octaves are summed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum SumArg {
    /// Fractional Brownian motion: Σ gainᵒ·n.
    Fbm,
    /// Turbulence: Σ gainᵒ·|n|.
    Turbulence,
    /// Musgrave's ridged multifractal.
    Ridged,
}

/// The fractal options.
#[derive(Debug, Args)]
pub(crate) struct FractalArgs {
    /// The basis summed over octaves.
    #[arg(long, value_enum, default_value = "perlin")]
    basis: BasisArg,
    /// How octaves are combined.
    #[arg(long, value_enum, default_value = "fbm")]
    sum: SumArg,
    /// Number of octaves (1 to 16, keeping the finest cell at least 1 pixel).
    #[arg(long, default_value_t = 6)]
    octaves: u32,
    /// Frequency ratio between octaves (1 to 16).
    #[arg(long, default_value_t = 2.0)]
    lacunarity: f32,
    /// Amplitude ratio between octaves (0 to 2).
    #[arg(long, default_value_t = 0.5)]
    gain: f32,
    /// Musgrave's offset of the ridged multifractal (0 to 4).
    #[arg(long, default_value_t = 1.0)]
    ridge_offset: f32,
    /// Musgrave's weighting gain of the ridged multifractal (0 to 16).
    #[arg(long, default_value_t = 2.0)]
    weight_gain: f32,
}

fn parse_coefficients(s: &str) -> Result<[f32; 4], String> {
    let err = || format!("'{s}' is not four coefficients; write C1,C2,C3,C4, for example -1,1,0,0");
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| err())?;
    v.try_into().map_err(|_| err())
}

fn worley(args: &WorleyArgs) -> Basis {
    Basis::Worley(Worley {
        metric: match args.metric {
            MetricArg::Euclidean => Metric::Euclidean,
            MetricArg::Manhattan => Metric::Manhattan,
            MetricArg::Chebyshev => Metric::Chebyshev,
        },
        coefficients: args.coefficients,
        points: match args.poisson {
            Some(mean) => FeaturePoints::Poisson(mean),
            None => FeaturePoints::Fixed(args.points),
        },
    })
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("cell_size", "--cell"),
        ("dimensions", "--dims"),
        ("amplitude", "--amplitude"),
        ("mean", "--mean"),
        ("coefficients", "--coefficients"),
        ("points.fixed", "--points"),
        ("points.poisson", "--poisson"),
        ("octaves", "--octaves"),
        ("lacunarity", "--lacunarity"),
        ("weight_gain", "--weight-gain"),
        ("ridged.offset", "--ridge-offset"),
        ("gain", "--gain"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the noise options", |(_, flag)| flag)
}

/// Builds the model of a classic noise kind, writes it if asked, and renders it.
pub(crate) fn run(
    basis: Basis,
    fractal: Option<&FractalArgs>,
    default_amplitude_mean: (f32, f32),
    args: &ClassicArgs,
) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let model = ClassicNoise {
        seed: args.seed,
        dimensions: args.dims,
        cell_size: args.cell,
        basis,
        fractal: fractal.map(|f| Fractal {
            kind: match f.sum {
                SumArg::Fbm => FractalKind::Fbm,
                SumArg::Turbulence => FractalKind::Turbulence,
                SumArg::Ridged => FractalKind::Ridged {
                    offset: f.ridge_offset,
                    weight_gain: f.weight_gain,
                },
            },
            octaves: f.octaves,
            lacunarity: f.lacunarity,
            gain: f.gain,
        }),
        amplitude: args.amplitude.unwrap_or(default_amplitude_mean.0),
        mean: args.mean.unwrap_or(default_amplitude_mean.1),
    };
    model.validate().map_err(|e| match &e {
        ModelError::OutOfRange { field, .. } => anyhow!("{e}; set {} within it", flag(field)),
        _ => anyhow!("{e}"),
    })?;
    let model = Model::Classic(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, (512, 512))
}

/// The basis a fractal sums, and the default (amplitude, mean) mapping its usual range into
/// [0, 1]: lattice noises lie in about [−1, 1] and their fBm with gain ½ in about [−1, 1] too;
/// turbulence and Worley's F₁ are non-negative and of order 1; a ridged sum with offset 1 and
/// gain ½ stays below 2.
pub(crate) fn fractal_basis(f: &FractalArgs, w: &WorleyArgs) -> (Basis, (f32, f32)) {
    let basis = match f.basis {
        BasisArg::Perlin => Basis::Gradient,
        BasisArg::Simplex => Basis::Simplex,
        BasisArg::Value => Basis::Value,
        BasisArg::Worley => worley(w),
    };
    let scale = match (f.sum, f.basis) {
        (SumArg::Fbm, BasisArg::Worley) => (0.5, 0.0),
        (SumArg::Fbm, _) => (0.5, 0.5),
        (SumArg::Turbulence, _) => (1.0, 0.0),
        (SumArg::Ridged, _) => (0.5, 0.0),
    };
    (basis, scale)
}

/// Worley's basis and its default (amplitude, mean).
pub(crate) fn worley_basis(w: &WorleyArgs) -> (Basis, (f32, f32)) {
    (worley(w), (1.0, 0.0))
}
