//! `spectex noise texton`: texton placement / spot noise (survey §2.3, §3.1.5,
//! `spectex_model::texton`) from flags, written as a model (`--model`) and rendered.

use anyhow::Result;
use clap::{Args, Subcommand, ValueEnum};
use spectex_model::Model;
use spectex_model::texton::{Combine, MAX_IMAGE_SIDE, Spot, TextonNoise};

use super::{arg_of, model_of};
use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of texton noise.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Texton placement / spot noise (survey §2.3): ellipsoids, Gaussian spots or an image
    /// placed on a jittered grid or at Poisson points, rotated, scaled, summed or maxed.
    Texton(TextonArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Texton(args) => run(args),
    }
}

/// The texton's shape.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum SpotArg {
    /// The ellipsoid of the survey's Eq. (6): √(1 − ρ²).
    Ellipsoid,
    /// A Gaussian spot truncated at 5% of its peak.
    Gaussian,
}

/// How overlapping textons combine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum CombineArg {
    /// The addition rule.
    Sum,
    /// The maximum rule (over a canvas of 0).
    Max,
}

impl From<SpotArg> for Spot {
    fn from(spot: SpotArg) -> Self {
        match spot {
            SpotArg::Ellipsoid => Self::Ellipsoid,
            SpotArg::Gaussian => Self::Gaussian,
        }
    }
}

/// The rules by name, for the conversions both ways.
const COMBINES: [(CombineArg, Combine); 2] = [
    (CombineArg::Sum, Combine::Sum),
    (CombineArg::Max, Combine::Max),
];

/// The options of `spectex noise texton`.
#[derive(Debug, Args)]
pub(crate) struct TextonArgs {
    /// Cell side, pixels (1 to 4096): one texton per cell on the grid, or --density per cell.
    #[arg(long, value_name = "PX", default_value_t = TextonNoise::DEFAULT_CELL_SIZE)]
    cell: f32,
    /// Grid jitter in cells, 0 (regular grid) to 1 (the survey's random grid).
    #[arg(long, default_value_t = TextonNoise::DEFAULT_JITTER, conflicts_with = "density")]
    jitter: f32,
    /// Poisson placement with this mean number of textons per cell (0 to 8), instead of a grid.
    #[arg(long)]
    density: Option<f32>,
    /// The texton's shape (default: the model's, an ellipsoid).
    #[arg(long, value_enum)]
    spot: Option<SpotArg>,
    /// A grey image as the texton (PNG/JPEG, at most 1024 per side), instead of --spot.
    #[arg(long, value_name = "IMAGE", conflicts_with = "spot")]
    image: Option<std::path::PathBuf>,
    /// Semi-axes A,B of the texton, pixels (each texton is scaled by a draw from --scale).
    #[arg(long, value_name = "A,B", default_value_t = Pair(TextonNoise::DEFAULT_RADII), value_parser = parse_pair)]
    radii: Pair,
    /// Range of the rotation, turns (0,1: every direction).
    #[arg(long, value_name = "LO,HI", default_value_t = Pair(TextonNoise::DEFAULT_ROTATION), value_parser = parse_pair, allow_hyphen_values = true)]
    rotation: Pair,
    /// Range of each texton's scale (each above 0, at most 16; --scale is the render's).
    #[arg(long, value_name = "LO,HI", default_value_t = Pair(TextonNoise::DEFAULT_SCALE), value_parser = parse_pair)]
    texton_scale: Pair,
    /// Range of the textons' weights (their height).
    #[arg(long, value_name = "LO,HI", default_value_t = Pair(TextonNoise::DEFAULT_INTENSITY), value_parser = parse_pair, allow_hyphen_values = true)]
    intensity: Pair,
    /// How overlapping textons combine.
    #[arg(long, value_enum, default_value_t = arg_of(&COMBINES, &TextonNoise::DEFAULT_COMBINE))]
    combine: CombineArg,
    /// Constant added.
    #[arg(long, default_value_t = TextonNoise::DEFAULT_MEAN, allow_hyphen_values = true)]
    mean: f32,
    /// Seed.
    #[arg(long, default_value_t = TextonNoise::DEFAULT_SEED)]
    seed: u32,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// Two numbers as parsed from `A,B` (and written so, for a default).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pair([f32; 2]);

impl std::fmt::Display for Pair {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{}", self.0[0], self.0[1])
    }
}

fn parse_pair(s: &str) -> Result<Pair, String> {
    let parts: Vec<&str> = s.split(',').collect();
    match parts.as_slice() {
        [a, b] => match (a.trim().parse::<f32>(), b.trim().parse::<f32>()) {
            (Ok(a), Ok(b)) => Ok(Pair([a, b])),
            _ => Err(format!(
                "'{s}' is not two numbers; write A,B, for example 0.5,1"
            )),
        },
        _ => Err(format!(
            "'{s}' is not two numbers; write A,B, for example 0.5,1"
        )),
    }
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("cell_size", "--cell"),
        ("jitter", "--jitter"),
        ("density", "--density"),
        ("spot.image", "--image"),
        ("radii", "--radii (or --cell, --texton-scale)"),
        ("rotation", "--rotation"),
        ("scale", "--texton-scale"),
        ("intensity", "--intensity"),
        ("mean", "--mean"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the texton options", |(_, flag)| flag)
}

/// A grey image (its luminance) as the texton, at most [`MAX_IMAGE_SIDE`] texels per side.
fn image_spot(path: &std::path::Path) -> Result<Spot> {
    let (loaded, name) = crate::io::load_input(Some(path))?;
    let grey = crate::io::grey(&loaded.pixels, &name);
    let (h, w) = grey.dim();
    if w > MAX_IMAGE_SIDE as usize || h > MAX_IMAGE_SIDE as usize {
        anyhow::bail!(
            "texton image {name} is {w}×{h}; at most {MAX_IMAGE_SIDE} pixels per side are \
             accepted, resize it"
        );
    }
    Ok(Spot::Image {
        width: w as u32,
        height: h as u32,
        values: grey.iter().map(|&g| g as f32).collect(),
    })
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &TextonArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let builder = TextonNoise::builder()
        .seed(args.seed)
        .cell_size(args.cell)
        .radii(args.radii.0)
        .rotation(args.rotation.0)
        .scale(args.texton_scale.0)
        .intensity(args.intensity.0)
        .combine(model_of(&COMBINES, &args.combine))
        .mean(args.mean);
    let builder = match args.density {
        Some(density) => builder.poisson(density),
        None => builder.jitter(args.jitter),
    };
    let builder = match (&args.image, args.spot) {
        (Some(path), _) => builder.spot(image_spot(path)?),
        (None, Some(spot)) => builder.spot(spot.into()),
        (None, None) => builder,
    };
    let model = builder.build().map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}
