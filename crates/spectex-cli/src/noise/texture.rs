//! Texture by example has no `spectex noise` subcommand: it is fitted to an exemplar (`spectex fit --structure`, `spectex
//! synth`), not built from flags. Its empty list is what the
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
