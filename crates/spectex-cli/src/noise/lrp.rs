//! `spectex noise ring|lobe|band|fractal`: LRP noise whose power spectrum follows a continuous
//! target (the paper's Fig. 10 ring and Fig. 3 lobes, a band-pass annulus, the survey's 1/f^β
//! fractal), fitted by `spectex_sampling::LrpFromTarget`.

use anyhow::{Context, Result, anyhow};
use clap::{Args, Subcommand};
use spectex_model::{Model, SpectralTarget};
use spectex_sampling::LrpFromTarget;

use super::NoiseArgs;
use crate::io;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of LRP noise.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Isotropic noise whose power lies on a ring of radius F (Fig. 10).
    Ring(RingArgs),
    /// Anisotropic noise: two Gaussian lobes at ±F in direction ANGLE (Fig. 3).
    Lobe(LobeArgs),
    /// Band-pass noise: constant power for MIN ≤ |f| ≤ MAX.
    Band(BandArgs),
    /// A random-phase 1/f^β fractal with the survey's angular term (Eq. (8)), as LRP noise:
    /// continuous and infinite; --contrast is the RMS roughness.
    Fractal(FractalArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Ring(args) => ring(args),
        Noise::Lobe(args) => lobe(args),
        Noise::Band(args) => band(args),
        Noise::Fractal(args) => fractal(args),
    }
}

/// The options of `spectex noise ring`.
#[derive(Debug, Args)]
pub struct RingArgs {
    /// Ring radius, cycles per pixel.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_RING_RADIUS)]
    radius: f32,
    /// Gaussian half-width of the ring, cycles per pixel.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_RING_WIDTH)]
    width: f32,
    #[command(flatten)]
    pub common: NoiseArgs,
}

/// The options of `spectex noise lobe`.
#[derive(Debug, Args)]
pub(super) struct LobeArgs {
    /// Distance of the lobes from the origin, cycles per pixel.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_LOBE_FREQUENCY)]
    frequency: f32,
    /// Direction, degrees.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_LOBE_ANGLE_DEGREES, allow_hyphen_values = true)]
    angle: f32,
    /// Standard deviation of each lobe, cycles per pixel.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_LOBE_WIDTH)]
    width: f32,
    #[command(flatten)]
    common: NoiseArgs,
}

/// The options of `spectex noise band`.
#[derive(Debug, Args)]
pub(super) struct BandArgs {
    /// Inner radius, cycles per pixel.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_BAND_MIN)]
    min: f32,
    /// Outer radius, cycles per pixel.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_BAND_MAX)]
    max: f32,
    #[command(flatten)]
    common: NoiseArgs,
}

/// The options of `spectex noise fractal`.
#[derive(Debug, Args)]
pub struct FractalArgs {
    /// β, the roll-off of the magnitude spectrum (0 to 4): the power falls as f^(−2β).
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_FRACTAL_BETA)]
    beta: f32,
    /// θ₀, the dominant direction of the frequencies, degrees.
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_FRACTAL_ANGLE_DEGREES, allow_hyphen_values = true)]
    angle: f32,
    /// σ, the angular standard deviation, degrees (isotropic if omitted).
    #[arg(long)]
    spread: Option<f32>,
    /// Lowest frequency with power, cycles per pixel (1/8192 to 0.25).
    #[arg(long, default_value_t = SpectralTarget::DEFAULT_FRACTAL_MIN_FREQUENCY)]
    min_frequency: f32,
    #[command(flatten)]
    pub common: NoiseArgs,
}

/// `spectex noise ring`.
pub(super) fn ring(args: &RingArgs) -> Result<()> {
    let target = SpectralTarget::Ring {
        radius: args.radius,
        width: args.width,
    };
    run(target, &args.common)
}

/// `spectex noise lobe`.
pub(super) fn lobe(args: &LobeArgs) -> Result<()> {
    let target = SpectralTarget::Lobes {
        frequency: args.frequency,
        angle: args.angle.to_radians(),
        width: args.width,
    };
    run(target, &args.common)
}

/// `spectex noise band`.
pub(super) fn band(args: &BandArgs) -> Result<()> {
    let target = SpectralTarget::Band {
        min: args.min,
        max: args.max,
    };
    run(target, &args.common)
}

/// `spectex noise fractal`.
pub(super) fn fractal(args: &FractalArgs) -> Result<()> {
    let target = SpectralTarget::Fractal {
        beta: args.beta,
        angle: args.angle.to_radians(),
        spread: args.spread.map(f32::to_radians),
        min_frequency: args.min_frequency,
    };
    run(target, &args.common)
}

/// Builds the LRP noise of `target`, writes it if asked, and renders it.
fn run(target: SpectralTarget, common: &NoiseArgs) -> Result<()> {
    io::check_output(&common.render.output, common.render.bit_depth)?;
    common.check_contrast()?;
    target
        .validate()
        .map_err(|e| anyhow!("{e}; check the spectrum's options"))?;
    let model = Model::from(
        builder(target, common)
            .build()
            .context("cannot build the noise")?,
    );
    if let Some(path) = &common.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &common.render, crate::args::DEFAULT_SIZE)
}

/// The flags as a builder: the target's defaults where `--budget` or `--strata` is omitted.
pub fn builder(target: SpectralTarget, common: &NoiseArgs) -> LrpFromTarget {
    let mut builder = LrpFromTarget::new(target)
        .seed(common.seed)
        .std_dev(common.contrast)
        .mean(common.mean);
    if let Some(budget) = common.budget {
        builder = builder.budget(budget);
    }
    if let Some(strata) = common.strata {
        builder = builder.strata(strata);
    }
    builder
}
