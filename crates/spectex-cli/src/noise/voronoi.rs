//! `spectex noise voronoi`: Voronoi diagrams (survey §2.6, `spectex_model::voronoi`) from flags:
//! the cell ID, F1, the border distance, F2 − F1, or colours from a palette or an image, with
//! optional Lloyd relaxation; in 2D or 3D (`--dims 3`, the solid diagram sliced at `--z`);
//! written as a model (`--model`) and rendered.

use anyhow::{Result, bail};
use clap::{Args, Subcommand, ValueEnum};
use spectex_model::Model;
use spectex_model::voronoi::{MAX_IMAGE_SIDE, VoronoiNoise, VoronoiOutput};

use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of Voronoi diagrams.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Voronoi diagrams (survey §2.6): cell ID, F1, exact border distance, F2 − F1, or colours
    /// from a palette or an image; optional Lloyd relaxation.
    Voronoi(VoronoiArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Voronoi(args) => run(args),
    }
}

/// What a pixel shows.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum OutputArg {
    /// The cell's ID, uniform in [0, 1).
    Id,
    /// The distance to the nearest seed (cell units).
    F1,
    /// The exact distance to the cell's border (cell units).
    Border,
    /// Worley's F2 − F1 (cell units).
    #[value(name = "f2-f1")]
    F2F1,
    /// A colour per cell from --palette (a built-in one by default).
    Palette,
}

/// The options of `spectex noise voronoi`.
#[derive(Debug, Args)]
pub(crate) struct VoronoiArgs {
    /// Lattice cell side, pixels (1 to 4096): one seed per cell.
    #[arg(long, value_name = "PX", default_value_t = VoronoiNoise::DEFAULT_CELL_SIZE)]
    cell: f32,
    /// 2 (seeds in the plane) or 3 (seeds in space, the diagram sliced at --z; no --lloyd or
    /// --image).
    #[arg(long, visible_alias = "dimensions", default_value_t = VoronoiNoise::DEFAULT_DIMENSIONS)]
    dims: u32,
    /// Jitter of the seeds in cells, 0 (regular grid) to 1 (anywhere in the cell).
    #[arg(long, default_value_t = VoronoiNoise::DEFAULT_JITTER)]
    jitter: f32,
    /// Lloyd relaxation iterations (0 to 16), run per block of --block cells.
    #[arg(long, default_value_t = VoronoiNoise::DEFAULT_LLOYD_ITERATIONS)]
    lloyd: u32,
    /// Side of a relaxation block, cells (1 to 16).
    #[arg(long, default_value_t = VoronoiNoise::DEFAULT_LLOYD_BLOCK)]
    block: u32,
    /// What a pixel shows (default: the model's, the cell ID).
    #[arg(long, value_enum)]
    show: Option<OutputArg>,
    /// Palette colours as hex RGB (e.g. 264653,2a9d8f,e9c46a), for --show palette.
    #[arg(long, value_name = "HEX,…", value_delimiter = ',')]
    palette: Vec<String>,
    /// Colour each cell by this image's texel under its seed (PNG/JPEG, at most 1024 per
    /// side, stored in the model; the image repeats over the plane), instead of --show.
    #[arg(long, value_name = "IMAGE", conflicts_with = "show")]
    image: Option<std::path::PathBuf>,
    /// Seed.
    #[arg(long, default_value_t = VoronoiNoise::DEFAULT_SEED)]
    seed: u32,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

fn parse_hex(s: &str) -> Result<[f32; 3]> {
    let t = s.trim().trim_start_matches('#');
    if t.len() != 6 || !t.chars().all(|c| c.is_ascii_hexdigit()) {
        bail!("--palette entry '{s}' is not a hex colour RRGGBB (for example 2a9d8f)");
    }
    let byte = |k: usize| u8::from_str_radix(&t[k..k + 2], 16).map(|b| f32::from(b) / 255.0);
    Ok([byte(0)?, byte(2)?, byte(4)?])
}

/// An RGB image's texels (a grey one repeated in the three channels).
fn image_output(path: &std::path::Path) -> Result<VoronoiOutput> {
    let (loaded, name) = crate::io::load_input(Some(path))?;
    let (c, h, w) = loaded.pixels.dim();
    if w > MAX_IMAGE_SIDE as usize || h > MAX_IMAGE_SIDE as usize {
        bail!(
            "Voronoi image {name} is {w}×{h}; at most {MAX_IMAGE_SIDE} pixels per side are \
             accepted, resize it"
        );
    }
    let texels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let v = |k: usize| loaded.pixels[[k.min(c - 1), y, x]] as f32;
            [v(0), v(1), v(2)]
        })
        .collect();
    Ok(VoronoiOutput::Image {
        width: w as u32,
        height: h as u32,
        texels,
    })
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("cell_size", "--cell"),
        ("dimensions", "--dims"),
        ("jitter", "--jitter"),
        ("lloyd_iterations", "--lloyd"),
        ("lloyd_block", "--block"),
        ("palette", "--palette"),
        ("image", "--image"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the Voronoi options", |(_, flag)| flag)
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &VoronoiArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let builder = VoronoiNoise::builder()
        .seed(args.seed)
        .dimensions(args.dims)
        .cell_size(args.cell)
        .jitter(args.jitter)
        .lloyd_iterations(args.lloyd)
        .lloyd_block(args.block);
    let builder = match (&args.image, args.show) {
        (Some(path), _) => builder.output(image_output(path)?),
        (None, None) => builder,
        (None, Some(OutputArg::Id)) => builder.output(VoronoiOutput::CellId),
        (None, Some(OutputArg::F1)) => builder.output(VoronoiOutput::F1),
        (None, Some(OutputArg::Border)) => builder.output(VoronoiOutput::Border),
        (None, Some(OutputArg::F2F1)) => builder.output(VoronoiOutput::F2MinusF1),
        // No --palette: the model's default palette.
        (None, Some(OutputArg::Palette)) => builder.palette(
            args.palette
                .iter()
                .map(|s| parse_hex(s))
                .collect::<Result<_>>()?,
        ),
    };
    let model = builder.build().map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}
