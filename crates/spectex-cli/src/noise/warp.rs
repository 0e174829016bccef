//! `spectex noise warp`: domain warping ([`spectex_model::warp`]) of a model file (or a
//! built-in fBm) by a displacement model (or a built-in zero-mean fBm), written as a model
//! (`--model`) and rendered on `--device cpu|gpu|auto`.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::{Args, Subcommand};
use spectex_model::{Model, ModelError, Warp, WarpBuilder};

use crate::args::RenderArgs;
use crate::model_file::{read_model, write_model};
use crate::render::render_to_file;

/// The `spectex noise` subcommands of domain warping.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Domain warping: --base evaluated at p + strength·(x(p), y(p)) for the --by (x) and
    /// --by-y models (built-in fBms by default).
    Warp(WarpArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Warp(args) => run(args),
    }
}

/// The options of `spectex noise warp`.
#[derive(Debug, Args)]
pub struct WarpArgs {
    /// The model to warp (.json, any kind; written by `spectex fit`, `noise … --model`, …);
    /// default: a Perlin fBm in [0, 1] with 64-pixel cells.
    #[arg(long, value_name = "MODEL")]
    base: Option<PathBuf>,
    /// The x displacement before --strength (.json, one value per pixel, ideally of mean 0);
    /// default: a zero-mean Perlin fBm with 64-pixel cells.
    #[arg(long, value_name = "MODEL")]
    by: Option<PathBuf>,
    /// The y displacement (.json); default: --by's model with every seed in it (nested
    /// models' too) plus 1.
    #[arg(long, value_name = "MODEL")]
    by_y: Option<PathBuf>,
    /// Pixels of displacement per unit of the displacement models (−65536 to 65536);
    /// displacements are clamped to ±65536 pixels.
    #[arg(long, default_value_t = Warp::DEFAULT_STRENGTH, allow_hyphen_values = true)]
    strength: f32,
    /// Seed of the built-in displacement (x uses it, y the next one).
    #[arg(long, default_value_t = Warp::DEFAULT_SEED)]
    seed: u32,
    /// Also write the warp model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// `spectex noise warp`.
pub(crate) fn run(args: &WarpArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let warp = builder(args)?.build().map_err(|e| match &e {
        ModelError::OutOfRange { field, .. } if field == "warp.strength" => {
            anyhow!("{e}; set --strength within it")
        }
        ModelError::Length { field, .. } if field.starts_with("warp.x") => {
            anyhow!("{e}; give --by a grey model")
        }
        ModelError::Length { field, .. } if field.starts_with("warp.y") => {
            anyhow!("{e}; give --by-y a grey model")
        }
        _ => anyhow!("{e}; check --base, --by and --by-y"),
    })?;
    let model = Model::from(warp);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}

/// The flags as a builder, with the model files read in the order base, x, y: the built-in
/// fBms where a file is not given, and y = x with every seed plus one without `--by-y`.
pub fn builder(args: &WarpArgs) -> Result<WarpBuilder> {
    let mut builder = Warp::builder().seed(args.seed).strength(args.strength);
    if let Some(path) = &args.base {
        builder = builder.base(read_model(path)?);
    }
    if let Some(path) = &args.by {
        builder = builder.by(read_model(path)?);
    }
    if let Some(path) = &args.by_y {
        builder = builder.by_y(read_model(path)?);
    }
    Ok(builder)
}
