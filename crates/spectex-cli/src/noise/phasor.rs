//! Phasor noise has no `spectex noise` subcommand: `spectex phasor` builds it from flags (`crate::phasor`: profiles,
//! fields from images, 3D and its slices), a command of its own since before `noise` grouped
//! the others. Its empty list is what the
//! command line's layer of the kind declares (every kind has one, `for_each_kind!(list)`).

use anyhow::Result;
use clap::Subcommand;

/// No subcommands.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {}

/// Nothing to run.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match *noise {}
}
