//! `spectex noise matrix`: matrix transformation (survey §2.4, `spectex_model::matrix`) from
//! flags: a source (built-in rings, or a square grey image) on the N × N torus moved k times by
//! an integer matrix; written as a model (`--model`) and rendered.

use anyhow::{Result, bail};
use clap::{Args, Subcommand};
use spectex_model::Model;
use spectex_model::matrix::{MAX_IMAGE_SIDE, MatrixSource, MatrixTransform};

use crate::args::RenderArgs;
use crate::model_file::write_model;
use crate::render::render_to_file;

/// The `spectex noise` subcommands of matrix transformations.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// Matrix transformation (survey §2.4): a source (built-in rings or a square image) moved
    /// k times by an integer matrix on the N × N torus, e.g. the cat map.
    Matrix(MatrixArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Matrix(args) => run(args),
    }
}

/// The options of `spectex noise matrix`.
#[derive(Debug, Args)]
pub(crate) struct MatrixArgs {
    /// The matrix by rows, a11,a12,a21,a22: Lucas or Fibonacci numbers (or 0) whose determinant
    /// is prime to --torus (default: Arnold's cat map 1,1,1,2).
    #[arg(long, value_name = "A11,A12,A21,A22", value_delimiter = ',', default_values_t = MatrixTransform::DEFAULT_MATRIX.concat())]
    matrix: Vec<u32>,
    /// How many times the map is applied.
    #[arg(long, default_value_t = MatrixTransform::DEFAULT_ITERATIONS)]
    iterations: u64,
    /// N, the torus side and the texture's period, pixels (2 to 4096; an image's side).
    #[arg(long, value_name = "N", default_value_t = MatrixTransform::DEFAULT_SIZE)]
    torus: u32,
    /// Rings of the built-in source, centre to corner (1 to 64).
    #[arg(long, default_value_t = MatrixTransform::DEFAULT_RINGS)]
    rings: u32,
    /// A square grey source image of side N (PNG/JPEG, at most 1024 pixels, stored in the
    /// model; colour images are taken as their first channel), instead of the rings.
    #[arg(long, value_name = "IMAGE", conflicts_with = "rings")]
    image: Option<std::path::PathBuf>,
    /// Factor applied to the source value.
    #[arg(long, default_value_t = MatrixTransform::DEFAULT_AMPLITUDE, allow_hyphen_values = true)]
    amplitude: f32,
    /// Constant added after the factor.
    #[arg(long, default_value_t = MatrixTransform::DEFAULT_MEAN, allow_hyphen_values = true)]
    mean: f32,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<std::path::PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// The image's first channel as texels, and its side.
fn image_source(path: &std::path::Path) -> Result<(u32, MatrixSource)> {
    let (loaded, name) = crate::io::load_input(Some(path))?;
    let (_, h, w) = loaded.pixels.dim();
    if w != h || w > MAX_IMAGE_SIDE as usize || w < 2 {
        bail!(
            "matrix source image {name} is {w}×{h}; it must be square, 2 to {MAX_IMAGE_SIDE} \
             pixels per side (its side is the torus side N)"
        );
    }
    let texels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| loaded.pixels[[0, y, x]] as f32)
        .collect();
    Ok((w as u32, MatrixSource::Image { texels }))
}

/// The command-line flag that sets a model field, for error messages.
fn flag(field: &str) -> &'static str {
    const FLAGS: &[(&str, &str)] = &[
        ("matrix.matrix", "--matrix"),
        ("size", "--torus (or the image's side)"),
        ("rings", "--rings"),
        ("texels", "--image"),
        ("amplitude", "--amplitude"),
        ("mean", "--mean"),
    ];
    FLAGS
        .iter()
        .find(|(f, _)| field.contains(f))
        .map_or("the matrix options", |(_, flag)| flag)
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &MatrixArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let (size, source) = match &args.image {
        Some(path) => image_source(path)?,
        None => (args.torus, MatrixSource::Rings { rings: args.rings }),
    };
    let [a11, a12, a21, a22] = args.matrix[..] else {
        bail!("--matrix takes four integers a11,a12,a21,a22");
    };
    let model = MatrixTransform::builder()
        .matrix([[a11, a12], [a21, a22]])
        .iterations(args.iterations)
        .size(size)
        .source(source)
        .amplitude(args.amplitude)
        .mean(args.mean)
        .build()
        .map_err(super::flag_hint(flag))?;
    let model = Model::from(model);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}
