//! `spectex noise tiling`: none. A tiling-and-blending texture is made from an exemplar, by
//! `spectex fit --method tiling` or `spectex synth --method tiling`, not from flags.

use anyhow::Result;
use clap::Subcommand;

/// No `spectex noise` subcommand: the kind is fitted from an example image.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {}

/// Runs one of them (there are none).
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match *noise {}
}
