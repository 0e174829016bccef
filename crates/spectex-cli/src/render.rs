//! Rendering a model into an image file: the window and output flags every rendering command
//! shares ([`RenderArgs`]), `spectex render`, and the progress bar.

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use spectex_cpu::{Evaluator, Filter, Window};
use spectex_model::{Model, Period};

use crate::device::{self, Device};
use crate::io::{self, BitDepth};
use crate::model_file::read_model_file;

/// Where and how to render.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Output image: .png (clamped to [0, 1]) or .exr (32-bit float, values kept).
    #[arg(short, long, value_name = "OUT")]
    pub(crate) output: PathBuf,
    /// Output size WIDTHxHEIGHT (1 to 65536 per side).
    #[arg(long, value_name = "WxH", value_parser = crate::parse_size)]
    pub(crate) size: Option<(usize, usize)>,
    /// Position of the top-left pixel, X,Y in model pixels (any finite values up to ±2^30).
    #[arg(long, value_name = "X,Y", value_parser = parse_offset, allow_hyphen_values = true)]
    pub(crate) offset: Option<[f64; 2]>,
    /// Model pixels per output pixel (0 < S ≤ 1e6).
    #[arg(long, default_value_t = 1.0)]
    pub(crate) scale: f64,
    /// Point-sample a minified render (--scale > 1) instead of fading out what its pixels cannot
    /// resolve (the default: LRP cosines, fBm octaves … above the output's Nyquist frequency).
    #[arg(long)]
    pub(crate) no_filter: bool,
    /// Bits per channel of a PNG output.
    #[arg(long, value_enum, default_value = "8")]
    pub(crate) bit_depth: BitDepth,
    /// The plane z (model pixels) on which a 3D model is evaluated; 2D models ignore it.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub(crate) z: f64,
    /// Evaluator: the CPU reference, the GPU (wgpu; WGPU_ADAPTER_NAME picks the adapter), or
    /// auto (the GPU when an adapter exists, else the CPU; says which it used).
    #[arg(long, value_enum, default_value = "cpu")]
    pub(crate) device: Device,
    /// Make the texture exactly periodic with period WxH model pixels (seamless tiles: a
    /// 2W×2H render is the W×H one repeated 2×2, bit for bit); bare --periodic takes the
    /// output's extent (--size × --scale). Lattices are hashed modulo the period; LRP lattices
    /// are fitted to it; every fBm octave's cell must divide it. Every kind with a periodic form
    /// renders periodic on the CPU and the GPU.
    #[arg(long, value_name = "WxH", num_args = 0..=1, default_missing_value = "")]
    pub(crate) periodic: Option<String>,
    #[command(flatten)]
    pub(crate) stream: crate::stream::StreamArgs,
}

impl RenderArgs {
    /// The period `--periodic` asks for, for an output of `size` pixels (`None` without it).
    ///
    /// # Errors
    /// A period that is not `WxH` with whole positive sides, or a bare `--periodic` whose
    /// output extent (`--size × --scale`) is not whole.
    pub(crate) fn period(&self, size: (usize, usize)) -> Result<Option<Period>> {
        let Some(text) = self.periodic.as_deref() else {
            return Ok(None);
        };
        let period = if text.is_empty() {
            let extent = [size.0 as f64 * self.scale, size.1 as f64 * self.scale];
            if extent
                .iter()
                .any(|e| e.fract() != 0.0 || *e > f64::from(u32::MAX))
            {
                return Err(anyhow!(
                    "--periodic alone takes the output's extent --size × --scale = {}×{} model \
                     pixels, which is not whole; give the period as --periodic WxH",
                    extent[0],
                    extent[1]
                ));
            }
            Period::new(extent[0] as u32, extent[1] as u32)
        } else {
            Period::parse(text)
        };
        period
            .map(Some)
            .map_err(|e| anyhow!("--periodic: {e}; for example --periodic 256x256"))
    }
}

/// Parses `X,Y`.
fn parse_offset(s: &str) -> Result<[f64; 2], String> {
    let err = || format!("'{s}' is not an offset; write X,Y, for example 1e7,1e7 or -20.5,3");
    let (x, y) = s.split_once(',').ok_or_else(err)?;
    let x: f64 = x.trim().parse().map_err(|_| err())?;
    let y: f64 = y.trim().parse().map_err(|_| err())?;
    Ok([x, y])
}

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
    render_to_file_with_period(&file.model, file.period, &cmd.render, (512, 512))
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
    crate::note_clipping(report);
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

/// A progress bar on stderr when it is a terminal; hidden (and free) when piped.
pub(crate) fn progress_bar(len: u64, what: &'static str) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() || len < 256 {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {eta} left")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(what);
    bar
}
