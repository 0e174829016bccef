//! `spectex noise gabor`: Gabor noise by sparse convolution (Lagae et al. 2009) from flags, its
//! amplitude chosen for `--contrast` by `GaborNoise::unit_std_dev`.

use anyhow::{Result, anyhow};
use clap::{Args, Subcommand};
use spectex_model::{GaborNoise, GaborNoiseBuilder, Model};

use super::NoiseArgs;
use crate::io;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of Gabor noise.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Gabor noise by sparse convolution (Lagae et al. 2009), for comparison with LRP noise.
    Gabor(GaborArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Gabor(args) => run(args),
    }
}

/// The options of `spectex noise gabor`.
#[derive(Debug, Args)]
pub struct GaborArgs {
    /// Kernel frequency F₀, cycles per pixel.
    #[arg(long, default_value_t = GaborNoise::DEFAULT_FREQUENCY)]
    frequency: f32,
    /// Gaussian bandwidth a, per pixel.
    #[arg(long, default_value_t = GaborNoise::DEFAULT_BANDWIDTH)]
    bandwidth: f32,
    /// Orientation in degrees; omit for isotropic noise.
    #[arg(long, allow_hyphen_values = true)]
    angle: Option<f32>,
    /// Mean number of impulses per kernel footprint.
    #[arg(long, default_value_t = GaborNoise::DEFAULT_IMPULSES_PER_KERNEL)]
    impulses: f32,
    #[command(flatten)]
    common: NoiseArgs,
}

/// `spectex noise gabor`.
pub(super) fn run(args: &GaborArgs) -> Result<()> {
    let common = &args.common;
    io::check_output(&common.render.output, common.render.bit_depth)?;
    common.check_contrast()?;
    let noise = builder(args)
        .build()
        .map_err(|e| anyhow!("{e}; check the gabor options"))?;
    let model = Model::from(noise);
    if let Some(path) = &common.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &common.render, crate::args::DEFAULT_SIZE)
}

/// The flags as a builder (isotropic directions without `--angle`).
pub fn builder(args: &GaborArgs) -> GaborNoiseBuilder {
    let builder = GaborNoise::builder()
        .seed(args.common.seed)
        .mean(args.common.mean)
        .std_dev(args.common.contrast)
        .bandwidth(args.bandwidth)
        .frequency(args.frequency)
        .impulses_per_kernel(args.impulses);
    match args.angle {
        Some(degrees) => builder.angle(degrees.to_radians()),
        None => builder,
    }
}
