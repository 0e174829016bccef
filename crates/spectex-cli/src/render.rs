//! Rendering a model into an image file: the window and output flags every rendering command
//! shares ([`RenderArgs`]), `spectex render`, and the progress bar.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use spectex_cpu::{Evaluator, Filter, Window};
use spectex_model::{Model, Period};

use crate::args::RenderArgs;
use crate::device;
use crate::io;
use crate::model_file::read_model_file;

/// Arguments of `spectex render`.
#[derive(Debug, Args)]
pub struct RenderCommand {
    /// Model file (.json) written by `spectex fit` or `spectex noise --model`.
    model: PathBuf,
    #[command(flatten)]
    render: RenderArgs,
}

/// `spectex render`: periodic with `--periodic`, else with the period the file records.
pub fn render(cmd: &RenderCommand) -> Result<()> {
    let file = read_model_file(&cmd.model)?;
    render_to_file_with_period(
        &file.model,
        file.period,
        &cmd.render,
        crate::args::DEFAULT_SIZE,
    )
}

/// Renders `model` as `args` says (`default_size` unless `--size`), showing progress on a
/// terminal, and writes the image.
pub(crate) fn render_to_file(
    model: &Model,
    args: &RenderArgs,
    default_size: (usize, usize),
) -> Result<()> {
    render_to_file_with_period(model, None, args, default_size)
}

/// [`render_to_file`] of a model periodic with `--periodic`'s period or else `file_period`.
pub(crate) fn render_to_file_with_period(
    model: &Model,
    file_period: Option<Period>,
    args: &RenderArgs,
    default_size: (usize, usize),
) -> Result<()> {
    let format = io::check_output(&args.output, args.bit_depth)?;
    let (width, height) = args.size.unwrap_or(default_size);
    let period = args.period((width, height))?.or(file_period);
    let window = Window::new(width, height)
        .at(args.offset.unwrap_or([0.0, 0.0]), args.scale)
        .filtered(filter_flag(args.no_filter));
    if let Some(region) = crate::stream::plan(&args.stream, (width, height), format)? {
        return crate::stream::render(model, period, args, &window, format, &region);
    }
    window
        .validate()
        .map_err(|e| anyhow!("{e}; check --size, --offset and --scale"))?;
    let eval = match period {
        None => Evaluator::new_at_z(model, args.z).map_err(|e| anyhow!("{e}; check --z"))?,
        Some(p) => Evaluator::periodic_at_z(model, args.z, p)
            .map_err(|e| anyhow!("--periodic: {e}; check --periodic and --z"))?,
    };
    let mut samples = io::Samples::new(format, width, height, eval.output_channels())?;
    let rendered = device::render(
        model,
        args.z,
        &window,
        args.device,
        &eval,
        period,
        &mut samples,
    )?;
    let report = io::save_samples(&args.output, samples, format, rendered.clipped)?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "wrote {} ({width}×{height} on the {}, {:.1} evaluations per pixel, {})",
            args.output.display(),
            rendered.device,
            eval.cost_per_pixel(),
            rendered.speed(width * height)
        );
    }
    crate::progress::note_clipping(report);
    Ok(())
}

/// The window filter of `--no-filter`.
pub(crate) fn filter_flag(no_filter: bool) -> Filter {
    if no_filter {
        Filter::Off
    } else {
        Filter::Pixel
    }
}
