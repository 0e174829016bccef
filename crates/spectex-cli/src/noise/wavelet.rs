//! `spectex noise wavelet`: wavelet noise (Cook & DeRose 2005, `spectex_model::wavelet`) from
//! flags, written as a model (`--model`) and rendered.

use anyhow::Result;
use clap::{Args, Subcommand};
use spectex_model::{Model, WaveletNoise, WaveletNoiseBuilder};

use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of wavelet noise.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Wavelet noise (Cook & DeRose 2005): a band-limited tile summed over octave bands, 2D or 3D.
    Wavelet(WaveletArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Wavelet(args) => run(args),
    }
}

/// The options of `spectex noise wavelet`.
#[derive(Debug, Args)]
pub struct WaveletArgs {
    /// Side of the periodic noise tile, samples: even, 16 to 256 in 2D, 16 to 64 in 3D
    /// (default 128 in 2D, 32 in 3D).
    #[arg(long, value_name = "N")]
    tile: Option<u32>,
    /// Pixels per tile sample of the first (coarsest) band (1 to 1e6).
    #[arg(long, value_name = "PX", default_value_t = WaveletNoise::DEFAULT_CELL_SIZE)]
    cell: f32,
    /// Weights of the bands W1,W2,… (1 to 16); band b has 2^b times the first one's frequency.
    #[arg(long, value_name = "W1,W2,…", default_value_t = Bands(WaveletNoise::DEFAULT_BANDS.to_vec()), value_parser = parse_bands, allow_hyphen_values = true)]
    bands: Bands,
    /// 2 (a plane) or 3 (a volume sliced at --z).
    #[arg(long, default_value_t = WaveletNoise::DEFAULT_DIMENSIONS)]
    dims: u32,
    /// Seed.
    #[arg(long, default_value_t = WaveletNoise::DEFAULT_SEED)]
    seed: u32,
    /// Standard deviation of the noise (the bands are normalised by √Σw²).
    #[arg(long, default_value_t = WaveletNoise::DEFAULT_AMPLITUDE, allow_hyphen_values = true)]
    amplitude: f32,
    /// Constant added.
    #[arg(long, default_value_t = WaveletNoise::DEFAULT_MEAN, allow_hyphen_values = true)]
    mean: f32,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// Band weights as parsed from `--bands` (and written so, for a default).
#[derive(Debug, Clone)]
pub(crate) struct Bands(Vec<f32>);

impl std::fmt::Display for Bands {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let weights: Vec<String> = self.0.iter().map(f32::to_string).collect();
        write!(f, "{}", weights.join(","))
    }
}

fn parse_bands(s: &str) -> Result<Bands, String> {
    s.split(',')
        .map(|w| w.trim().parse::<f32>())
        .collect::<Result<Vec<_>, _>>()
        .map(Bands)
        .map_err(|_| {
            format!("'{s}' is not a list of band weights; write W1,W2,…, for example 1,0.5,0.25")
        })
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("tile_size", "--tile"),
        ("cell_size", "--cell"),
        ("bands", "--bands (or --cell)"),
        ("dimensions", "--dims"),
        ("amplitude", "--amplitude"),
        ("mean", "--mean"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the noise options", |(_, flag)| flag)
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &WaveletArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let model = builder(args).build().map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}

/// The flags as a builder (the tile side of the dimensions without `--tile`).
pub fn builder(args: &WaveletArgs) -> WaveletNoiseBuilder {
    let builder = WaveletNoise::builder()
        .seed(args.seed)
        .dimensions(args.dims)
        .cell_size(args.cell)
        .bands(args.bands.0.clone())
        .amplitude(args.amplitude)
        .mean(args.mean);
    match args.tile {
        Some(tile) => builder.tile_size(tile),
        None => builder,
    }
}
