//! `spectex noise islamic`: Islamic star patterns (survey §2.7, `spectex_model::islamic`) from
//! flags: a tiling, a contact angle or a star `{n/d}`, and the output; written as a model
//! (`--model`) and rendered.

use anyhow::Result;
use clap::{Args, Subcommand, ValueEnum};
use spectex_model::Model;
use spectex_model::islamic::{IslamicOutput, IslamicPattern, Tiling};

use super::{arg_of, model_of};
use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of Islamic patterns.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Islamic star patterns (survey §2.7): Hankin contact-angle rosettes or {n/d} stars on
    /// the square, hexagonal, 4.8.8 or 3.12.12 tiling, as line bands, signed distance or
    /// filled regions.
    Islamic(IslamicArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Islamic(args) => run(args),
    }
}

/// The tiling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum TilingArg {
    /// Squares (4.4.4.4).
    Square,
    /// Hexagons (6.6.6).
    Hexagonal,
    /// Octagons and squares.
    #[value(name = "4.8.8")]
    OctagonSquare,
    /// Dodecagons and triangles.
    #[value(name = "3.12.12")]
    DodecagonTriangle,
}

/// What a pixel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ShowArg {
    /// Anti-aliased line bands of --width pixels.
    Band,
    /// The signed distance to the lines, pixels (negative inside the stars).
    Distance,
    /// The stars' regions filled (even–odd), anti-aliased.
    Filled,
}

/// The tilings by name, for the conversions both ways.
const TILINGS: [(TilingArg, Tiling); 4] = [
    (TilingArg::Square, Tiling::Square),
    (TilingArg::Hexagonal, Tiling::Hexagonal),
    (TilingArg::OctagonSquare, Tiling::OctagonSquare),
    (TilingArg::DodecagonTriangle, Tiling::DodecagonTriangle),
];

/// The outputs by name, for the conversions both ways.
const OUTPUTS: [(ShowArg, IslamicOutput); 3] = [
    (ShowArg::Band, IslamicOutput::Band),
    (ShowArg::Distance, IslamicOutput::Distance),
    (ShowArg::Filled, IslamicOutput::Filled),
];

/// The options of `spectex noise islamic`.
#[derive(Debug, Args)]
pub(crate) struct IslamicArgs {
    /// The tiling.
    #[arg(long, value_enum, default_value_t = arg_of(&TILINGS, &IslamicPattern::DEFAULT_TILING))]
    tiling: TilingArg,
    /// Hankin's contact angle in degrees (1 to 89): the rays leave each edge midpoint at this
    /// angle to the edge.
    #[arg(long, value_name = "DEG", default_value_t = IslamicPattern::DEFAULT_CONTACT_ANGLE, conflicts_with = "star")]
    angle: f32,
    /// Draw the star polygon {n/d} on each n-gon's edge midpoints instead (d from 1 to 5,
    /// at most (n − 1)/2 per polygon).
    #[arg(long, value_name = "D")]
    star: Option<u32>,
    /// Lattice period, pixels (4 to 4096).
    #[arg(long, value_name = "PX", default_value_t = IslamicPattern::DEFAULT_CELL_SIZE)]
    cell: f32,
    /// Line band width, pixels (0 to the period).
    #[arg(long, value_name = "PX", default_value_t = IslamicPattern::DEFAULT_LINE_WIDTH)]
    width: f32,
    /// What a pixel shows.
    #[arg(long, value_enum, default_value_t = arg_of(&OUTPUTS, &IslamicPattern::DEFAULT_OUTPUT))]
    show: ShowArg,
    /// Rotation of the pattern, degrees (-360 to 360).
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = IslamicPattern::DEFAULT_ROTATION,
        allow_hyphen_values = true
    )]
    rotation: f32,
    /// Offset of the pattern, pixels, as X,Y (each within ±1e9; default: none).
    #[arg(long, value_name = "X,Y", value_parser = parse_shift, allow_hyphen_values = true)]
    shift: Option<[f32; 2]>,
    /// Seed (chooses the pattern's phase, a translation within one period).
    #[arg(long, default_value_t = IslamicPattern::DEFAULT_SEED)]
    seed: u32,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// Parses `X,Y` (two numbers; their range is the model's to check).
fn parse_shift(s: &str) -> Result<[f32; 2], String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [x, y] = parts.as_slice() else {
        return Err(format!(
            "'{s}' is not X,Y (two numbers, for example -3,5.5)"
        ));
    };
    let num = |v: &str| {
        v.trim()
            .parse::<f32>()
            .map_err(|_| format!("'{v}' in '{s}' is not a number"))
    };
    Ok([num(x)?, num(y)?])
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("cell_size", "--cell"),
        ("line_width", "--width"),
        ("rotation", "--rotation"),
        ("offset", "--shift"),
        ("angle", "--angle"),
        ("step", "--star"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the islamic options", |(_, flag)| flag)
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &IslamicArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let builder = IslamicPattern::builder()
        .seed(args.seed)
        .tiling(model_of(&TILINGS, &args.tiling))
        .cell_size(args.cell)
        .line_width(args.width)
        .output(model_of(&OUTPUTS, &args.show))
        .rotation(args.rotation);
    let builder = match args.star {
        Some(step) => builder.star(step),
        None => builder.contact_angle(args.angle),
    };
    let builder = match args.shift {
        Some(shift) => builder.offset(shift),
        None => builder,
    };
    let model = builder.build().map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}
