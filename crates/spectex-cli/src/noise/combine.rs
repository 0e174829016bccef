//! `spectex noise combine OP`: a combination of models (survey §4.1–4.2,
//! `spectex_model::combine`): add, multiply, min, max, mix, smoothstep, the survey's fold, a
//! sine fold, histogram matching to an exemplar and colour ramps, over model files or built-in
//! operands; written as a model (`--model`) and rendered.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::{Args, Subcommand, ValueEnum};
use spectex_model::combine::{Combine, CombineOp, RampStop, histogram_table};
use spectex_model::voronoi::{VoronoiNoise, VoronoiOutput};
use spectex_model::{ClassicNoise, Model, ModelError, Window};

use crate::args::RenderArgs;
use crate::model_file::{read_model, write_model};
use crate::render::render_to_file;

/// The `spectex noise` subcommands of combinations.
#[derive(Debug, Subcommand)]
pub(super) enum Noise {
    /// A combination of models (survey §4.1–4.2): add, multiply, min, max, mix, smoothstep,
    /// fold, sin-fold, histogram matching, colour ramp.
    Combine(CombineArgs),
}

/// Runs one of them.
pub(super) fn noise(noise: &Noise) -> Result<()> {
    match noise {
        Noise::Combine(args) => run(args),
    }
}

/// The operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum OpArg {
    /// Sum of the operands.
    Add,
    /// Product of the operands.
    Multiply,
    /// Smallest operand.
    Min,
    /// Largest operand.
    Max,
    /// a + (b − a)·t of three operands.
    Mix,
    /// Hermite step between --edges (a threshold when equal).
    Smoothstep,
    /// The survey's fold (§4.1.1): --folds times |v − max/(folds + 1)| after moving the
    /// minimum to 0 (both measured on a 256² render at the origin).
    Fold,
    /// sin(2π·gain·v).
    SinFold,
    /// Histogram matching to --exemplar (§4.1.2): a 256-knot table fitted from a 256² render
    /// at the origin.
    Histogram,
    /// A grey operand to RGB through --stops.
    Ramp,
}

/// The options of `spectex noise combine`.
#[derive(Debug, Args)]
pub(crate) struct CombineArgs {
    /// The operation.
    #[arg(value_enum, default_value = "add")]
    op: OpArg,
    /// An operand (.json, any kind), repeated in order; default: a Perlin fBm, then a
    /// Voronoi F1, then the fBm reseeded, as many as the operation takes.
    #[arg(long = "operand", value_name = "MODEL")]
    operands: Vec<PathBuf>,
    /// Smoothstep edges E0,E1.
    #[arg(
        long,
        value_name = "E0,E1",
        default_value_t = edges_text(Combine::DEFAULT_EDGES),
        allow_hyphen_values = true
    )]
    edges: String,
    /// Folds of the survey's fold (0 to 32).
    #[arg(long, default_value_t = Combine::DEFAULT_FOLDS)]
    folds: u32,
    /// Cycles per unit of the operand for sin-fold.
    #[arg(long, default_value_t = Combine::DEFAULT_SIN_GAIN, allow_hyphen_values = true)]
    gain: f32,
    /// The exemplar whose grey histogram `histogram` matches (PNG/JPEG); default: the
    /// built-in exemplar.
    #[arg(long, value_name = "IMAGE")]
    exemplar: Option<PathBuf>,
    /// Ramp stops AT:RRGGBB, comma-separated in increasing AT (default: a bark ramp).
    #[arg(
        long,
        value_name = "AT:HEX,…",
        default_value_t = stops_text(&Combine::DEFAULT_RAMP_STOPS)
    )]
    stops: String,
    /// Also write the model to this .json file (render it again with `spectex render`).
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// The built-in operands, in order.
fn default_operand(k: usize) -> Result<Model> {
    let fbm = ClassicNoise::fbm().build().map_err(|e| anyhow!("{e}"))?;
    Ok(match k {
        1 => Model::from(
            VoronoiNoise::builder()
                .output(VoronoiOutput::F1)
                .build()
                .map_err(|e| anyhow!("{e}"))?,
        ),
        0 => Model::Classic(fbm),
        _ => Model::Classic(fbm).reseeded(k as u32),
    })
}

/// Smoothstep edges as `--edges` reads them, `E0,E1`.
fn edges_text(edges: [f32; 2]) -> String {
    format!("{},{}", edges[0], edges[1])
}

/// Ramp stops as `--stops` reads them, `AT:RRGGBB,…` (each channel back to its byte).
fn stops_text(stops: &[RampStop]) -> String {
    let byte = |v: f32| (v * 255.0).round() as u8;
    stops
        .iter()
        .map(|s| {
            let [r, g, b] = s.colour.map(byte);
            format!("{}:{r:02x}{g:02x}{b:02x}", s.at)
        })
        .collect::<Vec<_>>()
        .join(",")
}

fn parse_pair(s: &str) -> Result<[f32; 2]> {
    let parts: Vec<&str> = s.split(',').collect();
    match parts.as_slice() {
        [a, b] => match (a.trim().parse::<f32>(), b.trim().parse::<f32>()) {
            (Ok(a), Ok(b)) => Ok([a, b]),
            _ => bail!("--edges '{s}' is not two numbers; write E0,E1, for example 0.2,0.3"),
        },
        _ => bail!("--edges '{s}' is not two numbers; write E0,E1, for example 0.2,0.3"),
    }
}

fn parse_stops(s: &str) -> Result<Vec<RampStop>> {
    s.split(',')
        .map(|stop| {
            let bad =
                || anyhow!("--stops entry '{stop}' is not AT:RRGGBB (for example 0.5:6b4226)");
            let (at, hex) = stop.split_once(':').ok_or_else(bad)?;
            let at: f32 = at.trim().parse().map_err(|_| bad())?;
            let t = hex.trim().trim_start_matches('#');
            if t.len() != 6 || !t.chars().all(|c| c.is_ascii_hexdigit()) {
                return Err(bad());
            }
            let byte =
                |k: usize| u8::from_str_radix(&t[k..k + 2], 16).map(|b| f32::from(b) / 255.0);
            Ok(RampStop {
                at,
                colour: [byte(0)?, byte(2)?, byte(4)?],
            })
        })
        .collect()
}

/// The operand's values on the 256² window at the origin (CPU), for the fitted operations.
fn sample(model: &Model) -> Result<Vec<f32>> {
    let eval = spectex_cpu::Evaluator::new(model).map_err(|e| anyhow!("{e}"))?;
    if eval.output_channels() != 1 {
        bail!("this operation needs a grey operand; the one given has colour");
    }
    eval.render(&Window::new(256, 256))
        .map_err(|e| anyhow!("{e}"))
}

/// The operation from the flags, fitted on `operands[0]` where it needs to be.
fn operation(args: &CombineArgs, operands: &[Model]) -> Result<CombineOp> {
    Ok(match args.op {
        OpArg::Add => CombineOp::Add,
        OpArg::Multiply => CombineOp::Multiply,
        OpArg::Min => CombineOp::Min,
        OpArg::Max => CombineOp::Max,
        OpArg::Mix => CombineOp::Mix,
        OpArg::Smoothstep => CombineOp::Smoothstep {
            edges: parse_pair(&args.edges)?,
        },
        OpArg::SinFold => CombineOp::SinFold { gain: args.gain },
        OpArg::Ramp => CombineOp::Ramp {
            stops: parse_stops(&args.stops)?,
        },
        OpArg::Fold => {
            let v = sample(&operands[0])?;
            let lo = v.iter().copied().fold(f32::INFINITY, f32::min);
            let hi = v.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            CombineOp::AbsFold {
                offset: lo,
                step: (hi - lo) / (args.folds as f32 + 1.0),
                folds: args.folds,
            }
        }
        OpArg::Histogram => {
            let (loaded, name) = crate::io::load_input(args.exemplar.as_deref())?;
            let grey = crate::io::grey(&loaded.pixels, &name);
            let exemplar: Vec<f32> = grey.iter().map(|&g| g as f32).collect();
            let (domain, table) = histogram_table(&sample(&operands[0])?, &exemplar, 256)
                .ok_or_else(|| {
                    anyhow!(
                        "the operand is constant on the 256² window at the origin; nothing to match"
                    )
                })?;
            CombineOp::Histogram { domain, table }
        }
    })
}

/// Builds the model, writes it if asked, and renders it.
pub(crate) fn run(args: &CombineArgs) -> Result<()> {
    crate::io::check_output(&args.render.output, args.render.bit_depth)?;
    let arity = match args.op {
        OpArg::Add | OpArg::Multiply | OpArg::Min | OpArg::Max => 2,
        OpArg::Mix => 3,
        _ => 1,
    };
    let operands: Vec<Model> = if args.operands.is_empty() {
        (0..arity).map(default_operand).collect::<Result<_>>()?
    } else {
        args.operands
            .iter()
            .map(|p| read_model(p))
            .collect::<Result<_>>()?
    };
    let op = operation(args, &operands)?;
    let combine = Combine::builder()
        .op(op)
        .operands(operands)
        .build()
        .map_err(|e| match &e {
            ModelError::Length { field, .. } if field.starts_with("combine.operands") => {
                anyhow!("{e}; give --operand that many times")
            }
            _ => anyhow!("{e}; check the operation's flags and the operands"),
        })?;
    let model = Model::Combine(combine);
    if let Some(path) = &args.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &args.render, crate::args::DEFAULT_SIZE)
}
