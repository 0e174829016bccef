//! `spectex export MODEL.json --wgsl OUT [--tables OUT.bin]`: the model as one WGSL module for
//! a fragment shader (`spectex_gpu::export`), self-contained or with its tables in a storage
//! buffer written beside it, every file written atomically.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use spectex_gpu::GpuError;
use spectex_gpu::export::{
    DEFAULT_BINDING, DEFAULT_GROUP, ExportOptions, MAX_TABLE_BYTES, TableStorage, export as build,
};

use crate::io::{write_bytes_atomically, write_text_atomically};
use crate::model_file::read_model;

/// Arguments of `spectex export`.
#[derive(Debug, Args)]
pub struct ExportCommand {
    /// Model file (JSON, from `spectex fit`, `noise … --model`, …).
    model: PathBuf,
    /// Output WGSL module: `fn spectex_sample(p: vec2<f32>)` and `spectex_sample_cell`.
    #[arg(long, value_name = "OUT.wgsl")]
    wgsl: PathBuf,
    /// Write the model's tables to this binary file (little-endian 32-bit words, layout in the
    /// module's header) for a read-only storage buffer the module declares, instead of WGSL
    /// constants. Needed above 65536 bytes of tables (fitted LRP models, wavelet tiles).
    #[arg(long, value_name = "OUT.bin")]
    tables: Option<PathBuf>,
    /// Bind group of the tables' storage buffer (with --tables).
    #[arg(long, default_value_t = DEFAULT_GROUP, requires = "tables")]
    group: u32,
    /// Binding of the tables' storage buffer in its group (with --tables).
    #[arg(long, default_value_t = DEFAULT_BINDING, requires = "tables")]
    binding: u32,
    /// The plane z (model pixels) on which a 3D model is exported; 2D models ignore it.
    #[arg(long, default_value_t = crate::args::DEFAULT_Z, allow_hyphen_values = true)]
    z: f64,
}

/// Runs `spectex export`.
///
/// # Errors
/// An unreadable or invalid model, a kind the exporter does not cover, tables too large for
/// constants without `--tables`, or an unwritable output.
#[allow(clippy::print_stdout)] // reason: the command's result summary
pub fn export(cmd: &ExportCommand) -> Result<()> {
    let model = read_model(&cmd.model)?;
    let tables = match cmd.tables {
        Some(_) => TableStorage::Buffer {
            group: cmd.group,
            binding: cmd.binding,
        },
        None => TableStorage::Constants,
    };
    let exported = match build(&model, &ExportOptions { z: cmd.z, tables }) {
        Err(GpuError::LimitsExceeded { value, .. }) if cmd.tables.is_none() => bail!(
            "cannot export {}: its tables take {value} bytes, over the {MAX_TABLE_BYTES} a \
             self-contained module holds as constants; add --tables OUT.bin to put them in a \
             storage buffer",
            cmd.model.display()
        ),
        other => other.with_context(|| format!("cannot export {}", cmd.model.display()))?,
    };
    // The tables first: a module is never left without the buffer it declares.
    if let Some(path) = &cmd.tables {
        write_bytes_atomically(path, &exported.tables)?;
    }
    write_text_atomically(&cmd.wgsl, &exported.wgsl)?;
    match &cmd.tables {
        Some(path) => println!(
            "wrote {} ({} model, {} bytes of WGSL) and {} ({} bytes of tables for \
             @group({}) @binding({}))",
            cmd.wgsl.display(),
            model.kind(),
            exported.wgsl.len(),
            path.display(),
            exported.tables.len(),
            cmd.group,
            cmd.binding
        ),
        None => println!(
            "wrote {} ({} model, {} bytes of WGSL)",
            cmd.wgsl.display(),
            model.kind(),
            exported.wgsl.len()
        ),
    }
    Ok(())
}
