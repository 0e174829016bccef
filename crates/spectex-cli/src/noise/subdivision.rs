//! `spectex noise subdivision`: stochastic subdivision (survey §3.1.7,
//! `spectex_model::subdivision`) from flags: Fournier et al.'s midpoint displacement or the
//! smoother 4-point stencil, `--levels` halvings of `--cell`, roughness `--hurst`; written as a
//! model (`--model`) and rendered.

use anyhow::Result;
use clap::{Args, Subcommand, ValueEnum};
use spectex_model::Model;
use spectex_model::subdivision::{Stencil, StochasticSubdivision};

use super::{arg_of, model_of};
use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of stochastic subdivision.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Stochastic subdivision (survey §3.1.7): midpoint displacement (Fournier et al. 1982)
    /// or a smoother 4-point stencil (after Lewis 1987), each displacement hashed from its
    /// level and lattice point, so infinite and tile-invariant.
    Subdivision(SubdivisionArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Subdivision(args) => run(args),
    }
}

/// How a level interpolates its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum StencilArg {
    /// Fournier et al.: edge midpoints average their ends, centres their four corners
    /// (bilinear between the finest points).
    Midpoint,
    /// The 4-point stencil (−1, 9, 9, −1)/16 after Lewis (Catmull–Rom between the finest
    /// points): smoother, no creases along the coarse lattice.
    Cubic,
}

/// The stencils by name, for the conversions both ways.
const STENCILS: [(StencilArg, Stencil); 2] = [
    (StencilArg::Midpoint, Stencil::Midpoint),
    (StencilArg::Cubic, Stencil::Cubic),
];

/// The options of `spectex noise subdivision`.
#[derive(Debug, Args)]
pub(crate) struct SubdivisionArgs {
    /// Coarse lattice side, pixels (1 to 4096).
    #[arg(long, value_name = "PX", default_value_t = StochasticSubdivision::DEFAULT_CELL_SIZE)]
    cell: f32,
    /// Subdivision levels (0 to 16): the finest lattice side is cell/2^levels.
    #[arg(long, default_value_t = StochasticSubdivision::DEFAULT_LEVELS)]
    levels: u32,
    /// Hurst exponent H in [0, 1]: level ℓ's displacements have standard deviation
    /// amplitude·2^(−Hℓ) (small H: rough, large H: smooth).
    #[arg(long, default_value_t = StochasticSubdivision::DEFAULT_HURST)]
    hurst: f32,
    /// Standard deviation of the coarse (level 0) values.
    #[arg(long, default_value_t = StochasticSubdivision::DEFAULT_AMPLITUDE, allow_hyphen_values = true)]
    amplitude: f32,
    /// Constant added to the texture.
    #[arg(long, default_value_t = StochasticSubdivision::DEFAULT_MEAN, allow_hyphen_values = true)]
    mean: f32,
    /// The interpolation rule.
    #[arg(long, value_enum, default_value_t = arg_of(&STENCILS, &StochasticSubdivision::DEFAULT_STENCIL))]
    stencil: StencilArg,
    /// Seed.
    #[arg(long, default_value_t = StochasticSubdivision::DEFAULT_SEED)]
    seed: u32,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("cell_size", "--cell"),
        ("levels", "--levels"),
        ("hurst", "--hurst"),
        ("amplitude", "--amplitude"),
        ("mean", "--mean"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the subdivision options", |(_, flag)| flag)
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &SubdivisionArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let model = StochasticSubdivision::builder()
        .seed(args.seed)
        .cell_size(args.cell)
        .levels(args.levels)
        .hurst(args.hurst)
        .amplitude(args.amplitude)
        .mean(args.mean)
        .stencil(model_of(&STENCILS, &args.stencil))
        .build()
        .map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}
