//! `spectex noise perlin|simplex|value|kensler|fbm|worley`: the classic pointwise noises of
//! `spectex_model::classic` from flags, written as a model (`--model`) and rendered.

use anyhow::Result;
use clap::{Args, Subcommand};
use spectex_model::classic::{Basis, ClassicNoise, FeaturePoints, FractalKind, Metric, Worley};
use spectex_model::{Model, ModelError};

use super::{arg_of, model_of};
use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of the classic noises.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Improved Perlin gradient noise (Perlin 2002), 2D or 3D (sliced at --z).
    Perlin(ClassicArgs),
    /// Simplex noise (Perlin 2001, Gustavson 2005), 2D or 3D.
    Simplex(ClassicArgs),
    /// Value noise: random lattice values with quintic interpolation, 2D or 3D.
    Value(ClassicArgs),
    /// Better gradient noise (Kensler, Knoll & Shirley 2008): xor hash, radial kernel of
    /// radius 2 cells, 2D or 3D.
    Kensler(ClassicArgs),
    /// Fractal sum over octaves (fBm, turbulence, ridged multifractal) of a basis.
    Fbm(FbmArgs),
    /// Worley cellular noise C1·F1 + C2·F2 + C3·F3 + C4·F4 (Worley 1996), 2D or 3D.
    Worley(WorleyNoiseArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Perlin(args) => run(Basis::Gradient, None, args),
        Noise::Simplex(args) => run(Basis::Simplex, None, args),
        Noise::Value(args) => run(Basis::Value, None, args),
        Noise::Kensler(args) => run(Basis::Kensler, None, args),
        Noise::Fbm(args) => fbm(args),
        Noise::Worley(args) => worley(args),
    }
}

/// What every classic noise kind shares.
#[derive(Debug, Args)]
pub struct ClassicArgs {
    /// Side of a lattice cell (of the first octave), pixels (1 to 1e6).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_CELL_SIZE)]
    cell: f32,
    /// 2 (a plane) or 3 (a volume sliced at --z).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_DIMENSIONS)]
    dims: u32,
    /// Seed.
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_SEED)]
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
pub struct WorleyArgs {
    /// Distance between a point and the feature points.
    #[arg(long, value_enum, default_value_t = arg_of(&METRICS, &Worley::DEFAULT_METRIC))]
    metric: MetricArg,
    /// C1,C2,C3,C4 of C1·F1 + C2·F2 + C3·F3 + C4·F4 (each in [-1000, 1000]); -1,1,0,0 is F2 − F1.
    #[arg(long, value_name = "C1,C2,C3,C4", default_value_t = Coefficients(Worley::DEFAULT_COEFFICIENTS), value_parser = parse_coefficients, allow_hyphen_values = true)]
    coefficients: Coefficients,
    /// Feature points in every cell (1 to 16).
    #[arg(long, default_value_t = Worley::DEFAULT_POINTS_PER_CELL)]
    points: u32,
    /// A Poisson number of feature points per cell with this mean (0.5 to 4), instead of --points.
    #[arg(long)]
    poisson: Option<f32>,
}

/// The distance of Worley noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum MetricArg {
    /// √(Σ δ²).
    Euclidean,
    /// Σ |δ|.
    Manhattan,
    /// max |δ|.
    Chebyshev,
}

/// The metrics by name, for the conversions both ways.
const METRICS: [(MetricArg, Metric); 3] = [
    (MetricArg::Euclidean, Metric::Euclidean),
    (MetricArg::Manhattan, Metric::Manhattan),
    (MetricArg::Chebyshev, Metric::Chebyshev),
];

/// The basis of a fractal sum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum BasisArg {
    /// Improved Perlin gradient noise.
    Perlin,
    /// Simplex noise.
    Simplex,
    /// Value noise.
    Value,
    /// Kensler's better gradient noise.
    Kensler,
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
pub struct FractalArgs {
    /// The basis summed over octaves.
    #[arg(long, value_enum, default_value = "perlin")]
    basis: BasisArg,
    /// How octaves are combined.
    #[arg(long, value_enum, default_value = "fbm")]
    sum: SumArg,
    /// Number of octaves (1 to 16, keeping the finest cell at least 1 pixel).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_OCTAVES)]
    octaves: u32,
    /// Frequency ratio between octaves (1 to 16).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_LACUNARITY)]
    lacunarity: f32,
    /// Amplitude ratio between octaves (0 to 2).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_GAIN)]
    gain: f32,
    /// Musgrave's offset of the ridged multifractal (0 to 4).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_RIDGE_OFFSET)]
    ridge_offset: f32,
    /// Musgrave's weighting gain of the ridged multifractal (0 to 16).
    #[arg(long, default_value_t = ClassicNoise::DEFAULT_RIDGE_WEIGHT_GAIN)]
    weight_gain: f32,
}

impl FractalArgs {
    /// How the octaves are combined, with the ridged sum's parameters.
    fn sum(&self) -> FractalKind {
        match self.sum {
            SumArg::Fbm => FractalKind::Fbm,
            SumArg::Turbulence => FractalKind::Turbulence,
            SumArg::Ridged => FractalKind::Ridged {
                offset: self.ridge_offset,
                weight_gain: self.weight_gain,
            },
        }
    }
}

/// The options of `spectex noise fbm`.
#[derive(Debug, Args)]
pub struct FbmArgs {
    #[command(flatten)]
    pub fractal: FractalArgs,
    #[command(flatten)]
    pub worley: WorleyArgs,
    #[command(flatten)]
    pub classic: ClassicArgs,
}

/// The options of `spectex noise worley`.
#[derive(Debug, Args)]
pub struct WorleyNoiseArgs {
    #[command(flatten)]
    pub worley: WorleyArgs,
    #[command(flatten)]
    pub classic: ClassicArgs,
}

/// `C1,C2,C3,C4` as parsed from `--coefficients` (and written so, for a default).
#[derive(Debug, Clone, Copy)]
pub struct Coefficients([f32; 4]);

impl std::fmt::Display for Coefficients {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [a, b, c, d] = self.0;
        write!(f, "{a},{b},{c},{d}")
    }
}

fn parse_coefficients(s: &str) -> Result<Coefficients, String> {
    let err = || format!("'{s}' is not four coefficients; write C1,C2,C3,C4, for example -1,1,0,0");
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| err())?;
    v.try_into().map(Coefficients).map_err(|_| err())
}

pub fn worley_basis(args: &WorleyArgs) -> Basis {
    Basis::Worley(Worley {
        metric: model_of(&METRICS, &args.metric),
        coefficients: args.coefficients.0,
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
pub(crate) fn run(basis: Basis, fractal: Option<&FractalArgs>, args: &ClassicArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let model = build(basis, fractal, args).map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}

/// The noise the flags describe, through `ClassicNoise`'s builders: the mean and amplitude
/// default to `ClassicNoise::default_levels` of the basis and the sum.
pub fn build(
    basis: Basis,
    fractal: Option<&FractalArgs>,
    args: &ClassicArgs,
) -> Result<ClassicNoise, ModelError> {
    let mut builder = ClassicNoise::builder(basis)
        .seed(args.seed)
        .dimensions(args.dims)
        .cell_size(args.cell);
    if let Some(amplitude) = args.amplitude {
        builder = builder.amplitude(amplitude);
    }
    if let Some(mean) = args.mean {
        builder = builder.mean(mean);
    }
    match fractal {
        None => builder.build(),
        Some(f) => builder
            .fractal(f.sum())
            .octaves(f.octaves)
            .lacunarity(f.lacunarity)
            .gain(f.gain)
            .build(),
    }
}

/// `spectex noise fbm`.
pub(crate) fn fbm(args: &FbmArgs) -> Result<()> {
    run(fbm_basis(args), Some(&args.fractal), &args.classic)
}

/// The basis `--basis` names (Worley with the Worley options).
pub fn fbm_basis(args: &FbmArgs) -> Basis {
    match args.fractal.basis {
        BasisArg::Perlin => Basis::Gradient,
        BasisArg::Simplex => Basis::Simplex,
        BasisArg::Value => Basis::Value,
        BasisArg::Kensler => Basis::Kensler,
        BasisArg::Worley => worley_basis(&args.worley),
    }
}

/// `spectex noise worley`.
pub(crate) fn worley(args: &WorleyNoiseArgs) -> Result<()> {
    run(worley_basis(&args.worley), None, &args.classic)
}
