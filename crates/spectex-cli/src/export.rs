//! `spectex export MODEL.json --wgsl OUT`: the model as one self-contained WGSL module for
//! a fragment shader (`spectex_gpu::export`), written atomically.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use spectex_gpu::export::{ExportOptions, wgsl_module};

use crate::io::write_text_atomically;
use crate::model_file::read_model;

/// Arguments of `spectex export`.
#[derive(Debug, Args)]
pub struct ExportCommand {
    /// Model file (JSON, from `spectex fit`, `noise … --model`, …).
    model: PathBuf,
    /// Output WGSL module: `fn spectex_sample(p: vec2<f32>)` and `spectex_sample_cell`.
    #[arg(long, value_name = "OUT.wgsl")]
    wgsl: PathBuf,
    /// The plane z (model pixels) on which a 3D model is exported; 2D models ignore it.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    z: f64,
}

/// Runs `spectex export`.
///
/// # Errors
/// An unreadable or invalid model, a kind the exporter does not cover, or an unwritable output.
#[allow(clippy::print_stdout)] // reason: the command's result summary
pub fn export(cmd: &ExportCommand) -> Result<()> {
    let model = read_model(&cmd.model)?;
    let module = wgsl_module(&model, &ExportOptions { z: cmd.z })
        .with_context(|| format!("cannot export {}", cmd.model.display()))?;
    write_text_atomically(&cmd.wgsl, &module)?;
    println!(
        "wrote {} ({} model, {} bytes of WGSL)",
        cmd.wgsl.display(),
        model.kind(),
        module.len()
    );
    Ok(())
}
