//! `spectex noise`: procedural noises built from flags, one module per kind holding its
//! subcommands (LRP noise of a continuous spectrum, Gabor, the classic noises, wavelet noise,
//! domain warping, textons, Voronoi diagrams, matrix transformation, stochastic subdivision,
//! combinations, Islamic patterns; none for phasor noise and textures by example), each
//! building its model through `spectex_model`'s builders, writing it if asked (`--model`) and
//! rendering it.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::{Args, Subcommand};
use spectex_model::ModelError;

use crate::args::RenderArgs;

/// Arguments of `spectex noise`.
#[derive(Debug, Args)]
pub struct NoiseCommand {
    #[command(subcommand)]
    kind: NoiseKind,
}

/// One module per kind (`<kind>.rs`: its subcommands as a `Noise` enum, none for a kind another
/// command builds, and `noise` to run them), declared from the one list of kinds, with the
/// enum of every kind's subcommands and the one dispatch over it.
macro_rules! noise_kinds {
    ($($module:ident $Variant:ident $Kind:ty,)*) => {
        $(
            #[doc(hidden)]
            pub mod $module;
        )*

        /// Every kind's subcommands, in the order of the kinds.
        #[derive(Debug, Subcommand)]
        enum NoiseKind {
            $(
                #[command(flatten)]
                $Variant($module::Noise),
            )*
        }

        /// `spectex noise`.
        pub fn noise(cmd: &NoiseCommand) -> Result<()> {
            match &cmd.kind {
                $(NoiseKind::$Variant(noise) => $module::noise(noise),)*
            }
        }
    };
}

spectex_model::for_each_kind!(list: noise_kinds);

/// What the noises of a spectrum (and Gabor noise) share.
#[derive(Debug, Args)]
pub struct NoiseArgs {
    /// Cosine budget J of the LRP model (ignored by gabor) [default: 10; fractal: 48].
    #[arg(long)]
    budget: Option<u32>,
    /// Number of strata L of the LRP model (ignored by gabor) [default: 1; fractal: 12, cut
    /// in equal spans of log power].
    #[arg(long)]
    strata: Option<u32>,
    /// Seed.
    #[arg(long, default_value_t = spectex_model::DEFAULT_SEED)]
    seed: u32,
    /// Standard deviation of the noise around its mean.
    #[arg(long, default_value_t = spectex_model::DEFAULT_STD_DEV)]
    contrast: f32,
    /// Mean of the noise.
    #[arg(long, default_value_t = spectex_model::DEFAULT_MEAN)]
    mean: f32,
    /// Also write the model to this .json file.
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

impl NoiseArgs {
    /// Refuses a `--contrast` that cannot be a standard deviation, before anything is built.
    fn check_contrast(&self) -> Result<()> {
        if !(self.contrast.is_finite() && self.contrast > 0.0) {
            bail!(
                "--contrast = {} must be a positive number (the noise's standard deviation)",
                self.contrast
            );
        }
        Ok(())
    }
}

/// The flag's value naming the model's `value` in `table` (pairs of a clap value enum and the
/// model's enum), e.g. for a flag's default from a kind's `DEFAULT_` constant.
pub(crate) fn arg_of<A: Copy, M: PartialEq>(table: &[(A, M)], value: &M) -> A {
    table
        .iter()
        .find(|(_, m)| m == value)
        .map(|&(a, _)| a)
        .expect("every model value has a flag value")
}

/// The model's value named by `arg` in `table`.
pub(crate) fn model_of<A: PartialEq, M: Copy>(table: &[(A, M)], arg: &A) -> M {
    table
        .iter()
        .find(|(a, _)| a == arg)
        .map(|&(_, m)| m)
        .expect("every flag value names a model value")
}

/// A model's validation error as the command's, naming the flag to change: `flag` maps the
/// error's dotted field to it (a kind module's `flag`).
pub(crate) fn flag_hint(flag: fn(&str) -> &'static str) -> impl Fn(ModelError) -> anyhow::Error {
    move |e| match &e {
        ModelError::OutOfRange { field, .. } | ModelError::Length { field, .. } => {
            anyhow!("{e}; set {} within it", flag(field))
        }
        _ => anyhow!("{e}"),
    }
}
