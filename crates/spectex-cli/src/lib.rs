//! The `spectex` command: Random Phase Noise synthesis and spectral analysis of textures.
//!
//! A thin layer over the library crates: it parses arguments, reads and writes images, and turns
//! every failure into one `error: …` line that says what to do, with exit status 1.
//!
//! The command's code is this library, and `src/main.rs` only calls [`main`], so that the code is
//! compiled once for the program, the integration tests and the benches. Its unit tests are in
//! the crate's one test binary (`tests/it/unit/`), not in a unit-test harness of their own (which
//! would compile the whole command a second time); the modules and items they reach are `pub`
//! and `#[doc(hidden)]`, not an API.

mod analyze;
#[doc(hidden)]
pub mod args;
mod assemble;
mod device;
#[doc(hidden)]
pub mod exemplar;
mod export;
#[doc(hidden)]
pub mod fit;
mod interrupt;
#[doc(hidden)]
pub mod io;
mod model_file;
#[doc(hidden)]
pub mod noise;
#[doc(hidden)]
pub mod phasor;
mod progress;
mod relight;
mod render;
mod sheet;
mod simulate;
#[doc(hidden)]
pub mod stream;
mod view;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use spectex_spectrum::{NoiseKind, Rpn, RpnOptions};

use crate::args::parse_size;
use crate::io::{BitDepth, load_input};
use crate::progress::note_clipping;

#[doc(hidden)]
#[derive(Debug, Parser)]
#[command(
    name = "spectex",
    version,
    about = "Spectral procedural texture synthesis: Random Phase Noise and spectral analysis.",
    after_help = "Examples:\n  spectex rpn -o out.png                      # the built-in exemplar, same size\n  spectex rpn gravel.png -o big.exr --size 2048x2048 --seed 7\n  spectex analyze gravel.png -o gravel-analysis/"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Synthesise a texture by Random Phase Noise (Galerne, Gousseau & Morel).
    #[command(
        after_help = "Examples:\n  spectex rpn -o out.png\n  spectex rpn sample.jpg -o out.png --size 1024x768 --seed 3\n  spectex rpn sample.png -o out.exr --adsn        # keep values outside [0, 1]\n\nThe output keeps the sample's mean and, at the sample's size, the modulus of its periodic\ncomponent's spectrum; a larger output uses the spot extension with a = 0.1 and keeps the\nsample's variance. All colour channels share one random phase, so no false colours appear."
    )]
    Rpn(RpnArgs),
    /// Write the spectral analyses of an image into a directory.
    #[command(
        after_help = "Examples:\n  spectex analyze -o analysis/\n  spectex analyze sample.png -o analysis/ --format exr\n\nWrites periodic.png and smooth.png (Moisan's decomposition; smooth is shown as 0.5 + s),\nlog_spectrum.png and log_spectrum_periodic.png (centred ln(1 + |DFT|) of the luminance,\nbefore and after removing the smooth component), welch_psd.png and variance_spectrum.png\n(centred, log scale over 6 decades), and radial_profile.csv (Welch power per ring, one column\nper channel). With --format exr the spectra are written as raw 32-bit float values instead."
    )]
    Analyze(AnalyzeArgs),
    /// Fit a Local Random-Phase noise model (Gilet et al. 2014, §4) or, with --method gabor, a
    /// Gabor noise by example (Galerne et al. 2012) to an example image.
    #[command(
        after_help = "Examples:\n  spectex fit -o model.json\n  spectex fit gravel.png -o gravel.json --budget 100 --strata 4 --seed 3\n  spectex fit gravel.png -o gravel-gabor.json --method gabor --grid 32 --sparsity 0.01\n\nThe example's Welch power spectrum is split into L strata of equal energy, each sampled by\nJ/L cosines per lattice point (k-means sub-strata of the eroded stratum).\n\nTexture by example (Gilet et al. 2014, §5): --structure r keeps the phases of the\nhighest-energy frequencies holding the share r of the energy (r = 0.1 to 0.35 keeps structure;\n1 reproduces the exemplar periodically), --turbulence σ distorts that structure by σ pixels,\n--random-placement shifts half-period blocks at random. Colour examples are decorrelated by\nPCA and fitted channel by channel.\n\nGabor noise by example (--method gabor): the Welch power spectrum as a sparse non-negative\nsum of Gaussians centred every 1/n cycles per pixel (--grid n, --sparsity); each impulse draws\nits frequency in proportion to the weights. Colour examples are fitted by their luminance."
    )]
    Fit(fit::FitCommand),
    /// Render a model file at any window: size, offset (anywhere, even 1e7,1e7) and scale.
    #[command(
        after_help = "Examples:\n  spectex render model.json -o out.png --size 1024x1024\n  spectex render model.json -o far.exr --offset 1e7,1e7 --scale 0.5"
    )]
    Render(render::RenderCommand),
    /// Fit an LRP noise or texture model to an example and render it (fit + render in one step).
    #[command(
        after_help = "Examples:\n  spectex synth -o out.png\n  spectex synth gravel.png -o big.png --budget 50 --size 2048x2048\n  spectex synth brick.png -o brick.png --structure 0.2 --turbulence 4 --random-placement\n\nColour examples give colour textures (PCA channels); --structure, --turbulence and\n--random-placement make a texture model as in `spectex fit`."
    )]
    Synth(fit::SynthCommand),
    /// Noise from a continuous spectrum (ring, lobe, band) as LRP noise, or Gabor noise.
    #[command(
        after_help = "Examples:\n  spectex noise ring --radius 0.0625 --budget 3 -o ring.png\n  spectex noise lobe --frequency 0.1 --angle 30 --budget 10 -o lobe.png\n  spectex noise band --min 0.05 --max 0.1 -o band.png --model band.json\n  spectex noise gabor --frequency 0.0625 --impulses 27 -o gabor.png\n  spectex noise warp --base model.json --by band.json --strength 24 -o warped.png"
    )]
    Noise(noise::NoiseCommand),
    /// Phasor noise (Tricard et al. 2019): high-contrast oscillations with a chosen profile.
    #[command(
        after_help = "Examples:\n  spectex phasor -o stripes.png --angle 30\n  spectex phasor -o pwm.png --profile square --duty 0.25 --coherent\n  spectex phasor -o tiles.png --profile square --duty-image grey.png --orientation-image grey.png\n  spectex phasor -o wood.png --harmonics 1:1,2:0.5,3:0.33 --model wood.json\n  spectex phasor -o graded.png --frequency-image grey.png --bandwidth-image grey.png\n  spectex phasor -o phase.png --output-kind phase --two-lobes 0,60\n  spectex phasor -o slab.png --three-d --isotropic --z 12.5 --model slab.json"
    )]
    Phasor(Box<phasor::PhasorCommand>),
    /// Write the layers of a 3D model as images for additive manufacturing.
    #[command(
        after_help = "Examples:\n  spectex slices slab.json --z-range 0,64 --layers 65 -o layers/\n\nLayers are layer_00000.png, layer_00001.png, … in z order; layers.csv lists layer,z,file."
    )]
    Slices(phasor::SlicesCommand),
    /// Contact sheets of texture by example: exemplar | r = 0 | 0.1 | 0.2 | 0.35.
    #[command(
        after_help = "Examples:\n  spectex sheet -o sheets/\n  spectex sheet brick.png gravel.png -o sheets/ --turbulence 4\n  spectex sheet water.jpg -o sheets/ --ratios 0,0.2,0.35,1 --no-placement\n\nEach panel is a render of the exemplar's size at (1e4, -2e4), shown at --panel pixels. Panels\nwith r > 0 use random placement (unless --no-placement) and --turbulence. Prints a table of\nthe fits: |R|, J_R, blocks, stored cosines, special-function calls per pixel, and for colour\nexemplars the share of pixels farther than 0.1 (RGB) from every exemplar colour."
    )]
    Sheet(sheet::SheetCommand),
    /// Shade a height map under a directional light, or write its normal map.
    #[command(
        after_help = "Examples:\n  spectex relight height.png -o lit.png --light 135,45 --strength 16\n  spectex relight height.png -o normals.png --normals --periodic\n\nThe surface is z = strength · value (pixels); normals by central differences, wrapping around\nthe borders with --periodic (for tiling textures), one-sided there otherwise. The normal map\nstores (n + 1)/2 with +y up the image (OpenGL convention)."
    )]
    Relight(relight::RelightCommand),
    /// Join the tiles of a `--tiles C×R` render into one tiled OpenEXR.
    #[command(
        after_help = "Examples:\n  spectex render model.json --size 8192x8192 --tiles 4x4 --tile-index 5 -o tile-5.exr\n  spectex assemble tile-*.exr -o whole.exr\n\nEach tile records its place in its data window; the tiles must be of one render and cover\nits image exactly once. Memory holds one band of rows of the image, not the image."
    )]
    Assemble(assemble::AssembleCommand),
    /// Export a model as a self-contained WGSL module for a fragment shader.
    #[command(
        after_help = "Examples:\n  spectex export model.json --wgsl model.wgsl\n\nThe module defines fn spectex_sample(p: vec2<f32>) -> f32 (vec3<f32> for colour models):\nthe model at p in model pixels, as `spectex render` computes it (pixel (i, j) of a render at\n--offset o --scale s is spectex_sample(o + (i, j)·s)), and spectex_sample_cell(cell, offset)\nfor positions far from the origin. Its header comment documents both."
    )]
    Export(export::ExportCommand),
    /// Whole-grid simulations: reaction–diffusion and cellular automata, on a torus.
    #[command(
        after_help = "Examples:\n  spectex simulate gray-scott -o maze.png\n  spectex simulate gray-scott --preset spots --size 512x512 -o spots.png --frames frames/ --every 500\n  spectex simulate gray-scott --feed 0.03 --kill 0.06 --steps 20000 -o custom.png --save-params gs.json\n  spectex simulate file gs.json -o again.png --seed 2\n  spectex simulate swift-hohenberg --wavelength 16 -o stripes.png\n  spectex simulate life --rule B36/S23 -o highlife.png\n  spectex simulate elementary --rule 110 --single -o rule110.png\n  spectex simulate cyclic --states 14 --threshold 1 --neighbourhood von-neumann --steps 1000 -o cca.png\n\nAll grids wrap around (torus). --gpu steps on the GPU (Gray-Scott and the automata):\nautomata give the same cells as the CPU; Gray-Scott the same equations in f32, equal to the\nCPU within rounding for the first steps and statistically after many."
    )]
    Simulate(simulate::SimulateCommand),
    /// Show a model (or the fit of an image) in the browser: pan, zoom, tweak, download.
    #[command(
        after_help = "Examples:\n  spectex view testdata/models/lrp-ring.json --open\n  spectex view gravel.png --port 8081\n\nServes one page on 127.0.0.1 (--host to change): an infinite, zoomable view whose tiles are\nthe bytes `spectex render` writes for the same window, a panel of the model's parameters,\nand for an image its fit, the exemplar and both spectra. Offline: nothing is fetched."
    )]
    View(view::ViewCommand),
}

#[derive(Debug, Args)]
struct RpnArgs {
    /// Sample image (PNG 8/16-bit grey/RGB/RGBA, or JPEG); the built-in exemplar if omitted.
    input: Option<PathBuf>,
    /// Output image: .png (clamped to [0, 1]) or .exr (32-bit float, values kept exactly).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Output size WIDTHxHEIGHT, each at least the sample's; the sample's size if omitted.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(usize, usize)>,
    /// Seed of the random phase (0 to 4294967295).
    #[arg(long, default_value_t = spectex_model::DEFAULT_SEED)]
    seed: u32,
    /// Asymptotic discrete spot noise (spot convolved with Gaussian white noise) instead of RPN.
    #[arg(long)]
    adsn: bool,
    /// Bits per channel of a PNG output.
    #[arg(long, value_enum, default_value_t = BitDepth::DEFAULT)]
    bit_depth: BitDepth,
}

#[derive(Debug, Args)]
struct AnalyzeArgs {
    /// Image to analyse; the built-in exemplar if omitted.
    input: Option<PathBuf>,
    /// Directory to write into (created if missing).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Image format of the spectra: png (display-mapped, 16-bit) or exr (raw values).
    #[arg(long, value_enum, default_value = "png")]
    format: analyze::SpectraFormat,
}

fn run_rpn(args: &RpnArgs) -> Result<()> {
    let format = io::check_output(&args.output, args.bit_depth)?;
    let (loaded, name) = load_input(args.input.as_deref())?;
    let sample = &loaded.pixels;
    let options = RpnOptions {
        size: args.size,
        seed: args.seed,
        kind: if args.adsn {
            NoiseKind::Adsn
        } else {
            NoiseKind::RandomPhase
        },
        ..RpnOptions::default()
    };
    let out = Rpn::new()
        .synthesize(sample.view(), &options)
        .with_context(|| format!("cannot synthesise from {name}"))
        .map_err(with_hint)?;
    let report = io::save(&args.output, &out, format)?;
    let (c, h, w) = out.dim();
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "wrote {} ({w}×{h}, {} channel{}, seed {})",
            args.output.display(),
            c,
            if c == 1 { "" } else { "s" },
            args.seed
        );
    }
    note_clipping(report);
    Ok(())
}

/// Adds what to do to the library's sentence-style errors.
fn with_hint(e: anyhow::Error) -> anyhow::Error {
    use spectex_spectrum::SpectrumError as E;
    let hint = match e.downcast_ref::<E>() {
        Some(E::TooSmall {
            parameter: "output size",
            ..
        }) => "; give a --size at least as large as the sample, or omit --size",
        Some(E::TooSmall { .. }) => "; give a larger image",
        Some(E::TooLarge { .. }) => "; give a smaller --size",
        _ => "",
    };
    if hint.is_empty() {
        e
    } else {
        anyhow::anyhow!("{e:#}{hint}")
    }
}

/// Runs the parsed command `cli`: what [`main`] does after parsing, without the exit status (the
/// docs test runs every documented command line through it, in-process).
///
/// # Errors
/// The command's failure, as [`main`] would print it.
#[doc(hidden)]
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Rpn(args) => run_rpn(&args),
        Command::Analyze(args) => {
            let (loaded, name) = load_input(args.input.as_deref())?;
            analyze::run(&loaded.pixels, &name, &args.output, args.format)
        }
        Command::Fit(cmd) => fit::fit(&cmd),
        Command::Render(cmd) => render::render(&cmd),
        Command::Export(cmd) => export::export(&cmd),
        Command::Synth(cmd) => fit::synth(&cmd),
        Command::Noise(cmd) => noise::noise(&cmd),
        Command::Phasor(cmd) => phasor::phasor(&cmd),
        Command::Slices(cmd) => phasor::slices(&cmd),
        Command::Sheet(cmd) => sheet::sheet(&cmd),
        Command::Relight(cmd) => relight::relight(&cmd),
        Command::Assemble(cmd) => assemble::assemble(&cmd),
        Command::Simulate(cmd) => simulate::simulate(&cmd),
        Command::View(cmd) => view::view(&cmd),
    }
}

/// The `spectex` command: parses the process's arguments, runs the command and returns its exit
/// status (1 after printing one `error: …` line).
#[must_use]
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                // Help and version go to stdout with success (missing subcommand: help, exit 1).
                let code = if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                    1
                } else {
                    0
                };
                let _ = e.print();
                return ExitCode::from(code);
            }
            // One line: clap's first line already starts with "error: ".
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("error: invalid arguments");
            eprintln!("{first} (see spectex --help)");
            return ExitCode::from(1);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // A signal's stop keeps its own message and status (130, 143), whatever context
            // the error gathered on the way up.
            if let Some(stop) = e
                .chain()
                .find_map(|cause| cause.downcast_ref::<interrupt::Interrupted>())
            {
                eprintln!("error: {stop}");
                return ExitCode::from(stop.exit_status());
            }
            eprintln!("error: {}", one_line(&e));
            ExitCode::from(1)
        }
    }
}

/// The error and its causes on one line.
fn one_line(e: &anyhow::Error) -> String {
    format!("{e:#}").replace('\n', " ")
}
