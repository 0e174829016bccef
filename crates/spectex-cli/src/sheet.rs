//! `spectex sheet`: contact sheets of texture by example (the paper's Fig. 6 and Fig. 14): for
//! each exemplar, one image `exemplar | r = 0 | r = 0.1 | r = 0.2 | r = 0.35` (the shares are
//! options), each panel a render of the exemplar's size far from the origin, plus a table of what
//! each fit kept and, for colour exemplars, the share of false colours.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use ndarray::{Array3, s};
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_sampling::{FitOptions, TextureOptions, false_colour_fraction, fit_texture};

use crate::io;

/// Arguments of `spectex sheet`.
/// The shares `r` of the panels after the exemplar unless `--ratios` is given: noise by
/// example, then the paper's range of kept structure (Fig. 8: 0.1 to 0.35).
const DEFAULT_RATIOS: [f64; 4] = [0.0, 0.1, 0.2, 0.35];

/// The side of a panel unless `--panel` is given, pixels.
const DEFAULT_PANEL: usize = 256;

#[derive(Debug, Args)]
pub struct SheetCommand {
    /// Exemplar images; the built-in exemplar if none.
    inputs: Vec<PathBuf>,
    /// Directory to write `<name>_sheet.png` into (created if missing).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Shares r of the panels after the exemplar, comma-separated, each in [0, 1].
    #[arg(long, value_delimiter = ',', default_values_t = DEFAULT_RATIOS)]
    ratios: Vec<f64>,
    /// Cosine budget J (1 to 1024).
    #[arg(long, default_value_t = FitOptions::DEFAULT_BUDGET)]
    budget: u32,
    /// Turbulence σ in pixels for the panels with r > 0 (0 for none).
    #[arg(long, default_value_t = TextureOptions::DEFAULT_TURBULENCE)]
    turbulence: f64,
    /// No random placement in the panels with r > 0.
    #[arg(long)]
    no_placement: bool,
    /// Seed.
    #[arg(long, default_value_t = FitOptions::DEFAULT_SEED)]
    seed: u32,
    /// Side of each panel in the sheet, pixels (16 to 2048; renders are resampled to it).
    #[arg(long, default_value_t = DEFAULT_PANEL)]
    panel: usize,
}

/// Distance in RGB (`[0, 1]`) beyond which a pixel's colour counts as false.
const FALSE_COLOUR_DISTANCE: f64 = 0.1;
/// Gap between panels, pixels.
const GAP: usize = 6;

/// `spectex sheet`.
pub fn sheet(cmd: &SheetCommand) -> Result<()> {
    if cmd.ratios.is_empty() || cmd.ratios.iter().any(|r| !(0.0..=1.0).contains(r)) {
        bail!(
            "--ratios {:?}: give one or more shares r in [0, 1], comma-separated",
            cmd.ratios
        );
    }
    if !(16..=2048).contains(&cmd.panel) {
        bail!("--panel {} is outside 16..=2048 pixels", cmd.panel);
    }
    let base = TextureOptions {
        fit: FitOptions {
            budget: cmd.budget,
            seed: cmd.seed,
            ..FitOptions::default()
        },
        turbulence: cmd.turbulence,
        ..TextureOptions::default()
    };
    base.validate()
        .map_err(|e| anyhow!("{e}; check --budget and --turbulence"))?;
    std::fs::create_dir_all(&cmd.output).with_context(|| {
        format!(
            "cannot create '{}'; check the path and permissions",
            cmd.output.display()
        )
    })?;
    let inputs: Vec<Option<&Path>> = if cmd.inputs.is_empty() {
        vec![None]
    } else {
        cmd.inputs.iter().map(|p| Some(p.as_path())).collect()
    };
    #[allow(clippy::print_stdout)] // reason: the command's report
    {
        println!(
            "| exemplar | r | turbulence σ | placement | T | J_R | blocks | |R| (ch 0) | stored cosines | special calls/px | false colours |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
    }
    for input in inputs {
        let (loaded, name) = io::load_input(input)?;
        let stem = input.and_then(|p| p.file_stem()).map_or_else(
            || "builtin".to_owned(),
            |s| s.to_string_lossy().into_owned(),
        );
        let ex = loaded.pixels;
        let (nc, h, w) = ex.dim();
        let mut panels = vec![resample(&ex, cmd.panel)];
        for &r in &cmd.ratios {
            let options = TextureOptions {
                structure: r,
                turbulence: if r > 0.0 { cmd.turbulence } else { 0.0 },
                random_placement: r > 0.0 && !cmd.no_placement,
                ..base
            };
            let (model, report) = fit_texture(ex.view(), &options)
                .with_context(|| format!("cannot fit {name} with r = {r}"))?;
            let stored: usize = model
                .channels
                .iter()
                .filter_map(|c| c.structure.as_ref())
                .map(spectex_model::Structure::total_cosines)
                .sum();
            let calls = model.special_calls_per_pixel();
            let model = Model::Texture(model);
            let eval = Evaluator::new(&model).map_err(|e| anyhow!("internal: {e}"))?;
            let window = Window::new(w, h).at([1.0e4, -2.0e4], 1.0);
            let values = eval.render(&window).map_err(|e| anyhow!("{e}"))?;
            let out = Array3::from_shape_fn((nc, h, w), |(c, y, x)| {
                f64::from(values[(y * w + x) * nc + c])
            });
            let false_colours = if nc == 3 {
                format!(
                    "{:.2}%",
                    100.0 * false_colour_fraction(ex.view(), out.view(), FALSE_COLOUR_DISTANCE)
                )
            } else {
                "—".to_owned()
            };
            let ch = &report.channels[0];
            #[allow(clippy::print_stdout)] // reason: the command's report
            {
                println!(
                    "| {stem} | {r} | {} | {} | {} | {} | {} | {} | {stored} | {calls} | {false_colours} |",
                    options.turbulence,
                    if options.random_placement {
                        "yes"
                    } else {
                        "no"
                    },
                    report.period,
                    ch.structure_cosines,
                    ch.blocks,
                    ch.region_bins,
                );
            }
            panels.push(resample(&out, cmd.panel));
        }
        let n = panels.len();
        let side = cmd.panel;
        let mut sheet = Array3::from_elem((nc, side, n * side + (n - 1) * GAP), 1.0);
        for (k, p) in panels.iter().enumerate() {
            let x0 = k * (side + GAP);
            sheet.slice_mut(s![.., .., x0..x0 + side]).assign(p);
        }
        let path = cmd.output.join(format!("{stem}_sheet.png"));
        let format = io::check_output(&path, io::BitDepth::Eight)?;
        io::save(&path, &sheet, format)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// Box-filtered (down) or nearest (up) resampling of the top-left square to `side × side`.
fn resample(img: &Array3<f64>, side: usize) -> Array3<f64> {
    let (nc, h, w) = img.dim();
    let src = h.min(w);
    Array3::from_shape_fn((nc, side, side), |(c, y, x)| {
        let (y0, y1) = (
            y * src / side,
            ((y + 1) * src / side).max(y * src / side + 1),
        );
        let (x0, x1) = (
            x * src / side,
            ((x + 1) * src / side).max(x * src / side + 1),
        );
        let block = img.slice(s![c, y0..y1, x0..x1]);
        block.mean().unwrap_or(0.0)
    })
}
