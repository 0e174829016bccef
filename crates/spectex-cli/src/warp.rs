//! `spectex noise warp`: domain warping ([`spectex_model::warp`]) of a model file (or a
//! built-in fBm) by a displacement model (or a built-in zero-mean fBm), written as a model
//! (`--model`) and rendered on `--device cpu|gpu|auto`.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use spectex_model::classic::{Basis, ClassicNoise, Fractal, FractalKind};
use spectex_model::{Model, ModelError, Warp};

use crate::procedural::{RenderArgs, read_model, render_to_file, write_model};

/// The options of `spectex noise warp`.
#[derive(Debug, Args)]
pub(crate) struct WarpArgs {
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
    #[arg(long, default_value_t = 16.0, allow_hyphen_values = true)]
    strength: f32,
    /// Seed of the built-in displacement (x uses it, y the next one).
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Also write the warp model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// A Perlin fBm of 5 octaves on 64-pixel cells: `mean + amplitude·fBm`.
fn fbm(seed: u32, amplitude: f32, mean: f32) -> Model {
    Model::Classic(ClassicNoise {
        seed,
        dimensions: 2,
        cell_size: 64.0,
        basis: Basis::Gradient,
        fractal: Some(Fractal {
            kind: FractalKind::Fbm,
            octaves: 5,
            lacunarity: 2.0,
            gain: 0.5,
        }),
        amplitude,
        mean,
    })
}

/// `spectex noise warp`.
pub(crate) fn run(args: &WarpArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let base = match &args.base {
        Some(path) => read_model(path)?,
        None => fbm(args.seed.wrapping_add(1_000), 0.5, 0.5),
    };
    let x = match &args.by {
        Some(path) => read_model(path)?,
        None => fbm(args.seed, 1.0, 0.0),
    };
    let y = match &args.by_y {
        Some(path) => read_model(path)?,
        None => x.reseeded(1),
    };
    let model = Model::Warp(Warp {
        base: Box::new(base),
        x: Box::new(x),
        y: Box::new(y),
        strength: args.strength,
    });
    model.validate().map_err(|e| match &e {
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
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, (512, 512))
}
