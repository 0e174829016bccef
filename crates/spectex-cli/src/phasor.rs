//! `spectex phasor` (a phasor noise model from flags, rendered) and `spectex slices` (the layers
//! of a 3D model for additive manufacturing).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use ndarray::Array3;
use spectex_cpu::{Evaluator, Window};
use spectex_model::{
    Field, Harmonic, Model, PhasorNoise, PhasorOrientation, PhasorOutput, Profile,
};

use crate::args::RenderArgs;
use crate::io;
use crate::model_file::{read_model, write_model};
use crate::progress::progress_bar;
use crate::render::render_to_file;

/// The oscillation profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ProfileKind {
    /// sin φ, the phasor sine wave.
    Sine,
    /// Pulse-width modulation: 1 for the first `--duty` of each period, else 0.
    Square,
    /// Triangle wave in phase with the sine.
    Triangle,
    /// Sawtooth rising over each period.
    Sawtooth,
}

/// What is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OutputKind {
    /// The profiled noise.
    Profiled,
    /// The phase φ in turns (shown as 0.5 + φ).
    Phase,
    /// The intensity I of the complex Gabor noise.
    Intensity,
    /// The Gabor noise I·sin φ of the same kernels (shown as 0.5 + 0.5·G/3).
    Gabor,
}

/// `spectex phasor`.
#[derive(Debug, Args)]
pub struct PhasorCommand {
    /// Kernel frequency F, cycles per pixel (0 < F ≤ 0.5).
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_FREQUENCY)]
    frequency: f32,
    /// Gaussian bandwidth b per pixel: kernels exp(−π b² |x|²), cut at 5% of their peak.
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_BANDWIDTH)]
    bandwidth: f32,
    /// Greyscale image grading the frequency from --frequency (black) to --frequency-max
    /// (white), stretched over the output (read at each kernel's centre).
    #[arg(long, value_name = "IMAGE")]
    frequency_image: Option<PathBuf>,
    /// Frequency at white in --frequency-image.
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_FREQUENCY_MAX)]
    frequency_max: f32,
    /// Greyscale image grading the bandwidth from --bandwidth (black) to --bandwidth-max
    /// (white): wider kernels, longer coherent stripes where it is dark.
    #[arg(long, value_name = "IMAGE")]
    bandwidth_image: Option<PathBuf>,
    /// Bandwidth at white in --bandwidth-image.
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_BANDWIDTH_MAX)]
    bandwidth_max: f32,
    /// Mean impulses per kernel footprint (0.01 to 200).
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_IMPULSES_PER_KERNEL)]
    impulses: f32,
    /// Kernel direction, degrees from x (the bi-lobe case). Default 0 unless another
    /// orientation option is given.
    #[arg(long, allow_hyphen_values = true, conflicts_with_all = ["isotropic", "coherent", "two_lobes", "orientation_image"])]
    angle: Option<f32>,
    /// Independent uniform directions.
    #[arg(long, conflicts_with_all = ["coherent", "two_lobes", "orientation_image"])]
    isotropic: bool,
    /// The locally coherent isotropic direction field of §3.2.2 (ω_f = 2.4, b_f = b/2).
    #[arg(long, conflicts_with_all = ["two_lobes", "orientation_image"])]
    coherent: bool,
    /// Two bi-lobes, A,B in degrees (§3.2.1; reversed B beyond 90° apart).
    #[arg(long, value_name = "A,B", value_parser = parse_pair, allow_hyphen_values = true, conflicts_with = "orientation_image")]
    two_lobes: Option<[f32; 2]>,
    /// Greyscale image whose gradient steers the kernels (along its iso-lines), stretched over
    /// the output (Fig. 14).
    #[arg(long, value_name = "IMAGE")]
    orientation_image: Option<PathBuf>,
    /// Oscillation profile.
    #[arg(long, value_enum, default_value = "sine")]
    profile: ProfileKind,
    /// Duty cycle of the square profile, in [0, 1].
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_DUTY)]
    duty: f32,
    /// Greyscale image giving the duty cycle (its grey level), stretched over the output.
    #[arg(long, value_name = "IMAGE")]
    duty_image: Option<PathBuf>,
    /// Additive profile instead: harmonics K:WEIGHT[:PHASE_DEG],… (Fig. 13), e.g. 1:1,3:0.33,5:0.2.
    #[arg(long, value_name = "LIST", value_parser = parse_harmonics)]
    harmonics: Option<HarmonicList>,
    /// What to write.
    #[arg(long, value_enum, default_value = "profiled")]
    output_kind: OutputKind,
    /// A 3D model (evaluate its plane --z; see `spectex slices` for layers).
    #[arg(long)]
    three_d: bool,
    /// Seed.
    #[arg(long, default_value_t = PhasorNoise::DEFAULT_SEED)]
    seed: u32,
    /// Also write the model to this .json file.
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

fn parse_pair(s: &str) -> Result<[f32; 2], String> {
    let err = || format!("'{s}' is not a pair; write A,B in degrees, for example 0,45");
    let (a, b) = s.split_once(',').ok_or_else(err)?;
    Ok([
        a.trim().parse().map_err(|_| err())?,
        b.trim().parse().map_err(|_| err())?,
    ])
}

/// The parsed `--harmonics` list (one clap value).
#[derive(Debug, Clone)]
pub struct HarmonicList(Vec<Harmonic>);

fn parse_harmonics(s: &str) -> Result<HarmonicList, String> {
    s.split(',')
        .map(|term| {
            let err = || {
                format!(
                    "'{term}' is not a harmonic; write K:WEIGHT or K:WEIGHT:PHASE_DEG, e.g. 3:0.33"
                )
            };
            let parts: Vec<&str> = term.split(':').map(str::trim).collect();
            if !(2..=3).contains(&parts.len()) {
                return Err(err());
            }
            let k: u32 = parts[0].parse().map_err(|_| err())?;
            let weight: f32 = parts[1].parse().map_err(|_| err())?;
            let phase: f32 = match parts.get(2) {
                Some(p) => p.parse::<f32>().map_err(|_| err())?.to_radians(),
                None => 0.0,
            };
            Ok(Harmonic { k, weight, phase })
        })
        .collect::<Result<_, _>>()
        .map(HarmonicList)
}

/// A greyscale image as a field stretched over an output of `width` pixels.
fn image_field(path: &Path, width: usize, min: f32, max: f32) -> Result<Field> {
    let (loaded, name) = io::load_input(Some(path))?;
    let grey = io::grey(&loaded.pixels, &name);
    let (h, w) = grey.dim();
    if w > spectex_model::MAX_FIELD_SIDE || h > spectex_model::MAX_FIELD_SIDE {
        bail!(
            "control image {name} is {w}×{h}; at most {} pixels per side are accepted, resize it",
            spectex_model::MAX_FIELD_SIDE
        );
    }
    Ok(Field::Image {
        width: w,
        height: h,
        grey: grey.iter().map(|&g| g.clamp(0.0, 1.0) as f32).collect(),
        pixel_size: (width as f64 / w as f64) as f32,
        min,
        max,
    })
}

/// Builds the model the flags describe.
pub fn build(cmd: &PhasorCommand, width: usize) -> Result<PhasorNoise> {
    let orientation = if let Some(path) = &cmd.orientation_image {
        PhasorOrientation::Gradient {
            image: image_field(path, width, 0.0, 1.0)?,
            offset: std::f32::consts::FRAC_PI_2,
        }
    } else if cmd.isotropic {
        PhasorOrientation::Isotropic
    } else if cmd.coherent {
        PhasorOrientation::coherent()
    } else if let Some([a, b]) = cmd.two_lobes {
        PhasorOrientation::TwoLobes {
            angle_a: a.to_radians(),
            angle_b: b.to_radians(),
        }
    } else {
        PhasorOrientation::Aligned {
            angle: Field::constant(cmd.angle.unwrap_or(0.0).to_radians()),
        }
    };
    let profile = match (&cmd.harmonics, cmd.profile) {
        (Some(terms), _) => Profile::Harmonics {
            terms: terms.0.clone(),
        },
        (None, ProfileKind::Sine) => Profile::Sine,
        (None, ProfileKind::Triangle) => Profile::Triangle,
        (None, ProfileKind::Sawtooth) => Profile::Sawtooth,
        (None, ProfileKind::Square) => Profile::Square {
            duty: match &cmd.duty_image {
                Some(path) => image_field(path, width, 0.0, 1.0)?,
                None => Field::constant(cmd.duty),
            },
        },
    };
    let output = match cmd.output_kind {
        OutputKind::Profiled => PhasorOutput::Profiled,
        OutputKind::Phase => PhasorOutput::Phase,
        OutputKind::Intensity => PhasorOutput::Intensity,
        OutputKind::Gabor => PhasorOutput::Gabor,
    };
    let bandwidth = match &cmd.bandwidth_image {
        Some(path) => image_field(path, width, cmd.bandwidth, cmd.bandwidth_max)?,
        None => Field::constant(cmd.bandwidth),
    };
    let frequency = match &cmd.frequency_image {
        Some(path) => image_field(path, width, cmd.frequency, cmd.frequency_max)?,
        None => Field::constant(cmd.frequency),
    };
    // The mean and amplitude default to `PhasorNoise::default_levels`: the output in [0, 1].
    PhasorNoise::builder()
        .seed(cmd.seed)
        .dimensions(if cmd.three_d { 3 } else { 2 })
        .bandwidth_field(bandwidth)
        .frequency_field(frequency)
        .orientation(orientation)
        .impulses_per_kernel(cmd.impulses)
        .profile(profile)
        .output(output)
        .build()
        .map_err(|e| {
            anyhow!(
                "{e}; check --frequency(-max), --bandwidth(-max), --impulses, --duty and the angles"
            )
        })
}

/// `spectex phasor`.
pub fn phasor(cmd: &PhasorCommand) -> Result<()> {
    let size = cmd.render.size.unwrap_or(crate::args::DEFAULT_SIZE);
    let model = Model::from(build(cmd, size.0)?);
    if let Some(path) = &cmd.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &cmd.render, crate::args::DEFAULT_SIZE)
}

/// `spectex slices`.
#[derive(Debug, Args)]
pub struct SlicesCommand {
    /// A model file (a 3D phasor model; 2D models give identical layers).
    model: PathBuf,
    /// First and last plane, Z0,Z1 in model pixels.
    #[arg(long, value_name = "Z0,Z1", value_parser = parse_range, allow_hyphen_values = true)]
    z_range: [f64; 2],
    /// Number of layers (1 to 100000), evenly spaced from Z0 to Z1 inclusive.
    #[arg(long)]
    layers: usize,
    /// Output directory (created if missing); gets layer_00000.png … and layers.csv.
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Layer size WIDTHxHEIGHT.
    #[arg(long, value_name = "WxH", value_parser = crate::args::parse_size, default_value = "512x512")]
    size: (usize, usize),
    /// Position of each layer's top-left pixel, X,Y in model pixels.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true, value_parser = parse_range)]
    offset: Option<[f64; 2]>,
    /// Model pixels per output pixel.
    #[arg(long, default_value_t = crate::args::DEFAULT_SCALE)]
    scale: f64,
    /// Point-sample minified layers (--scale > 1) instead of filtering them.
    #[arg(long)]
    no_filter: bool,
}

fn parse_range(s: &str) -> Result<[f64; 2], String> {
    let err = || format!("'{s}' is not a pair of numbers; write A,B, for example 0,64");
    let (a, b) = s.split_once(',').ok_or_else(err)?;
    Ok([
        a.trim().parse().map_err(|_| err())?,
        b.trim().parse().map_err(|_| err())?,
    ])
}

/// Most layers one `slices` call writes.
const MAX_LAYERS: usize = 100_000;

/// `spectex slices`.
pub fn slices(cmd: &SlicesCommand) -> Result<()> {
    if cmd.layers == 0 || cmd.layers > MAX_LAYERS {
        bail!(
            "--layers {} is outside its valid range [1, {MAX_LAYERS}]; give the number of layers to write",
            cmd.layers
        );
    }
    let [z0, z1] = cmd.z_range;
    if !(z0.is_finite() && z1.is_finite()) {
        bail!("--z-range {z0},{z1} must be two finite numbers");
    }
    let model = read_model(&cmd.model)?;
    let (width, height) = cmd.size;
    let window = Window::new(width, height)
        .at(cmd.offset.unwrap_or([0.0, 0.0]), cmd.scale)
        .filtered(crate::render::filter_flag(cmd.no_filter));
    window
        .validate()
        .map_err(|e| anyhow!("{e}; check --size, --offset and --scale"))?;
    std::fs::create_dir_all(&cmd.output).with_context(|| {
        format!(
            "cannot create the output directory '{}'; check the path and permissions",
            cmd.output.display()
        )
    })?;
    let digits = (cmd.layers - 1).max(1).ilog10() as usize + 1;
    let digits = digits.max(5);
    let mut index = String::from("layer,z,file\n");
    let bar = progress_bar(cmd.layers as u64, "slicing");
    let start = std::time::Instant::now();
    for layer in 0..cmd.layers {
        let z = if cmd.layers == 1 {
            z0
        } else {
            z0 + (z1 - z0) * layer as f64 / (cmd.layers - 1) as f64
        };
        let eval = Evaluator::new_at_z(&model, z).map_err(|e| anyhow!("{e}; check --z-range"))?;
        let pixels = eval.render(&window).map_err(|e| anyhow!("{e}"))?;
        let image = Array3::from_shape_fn((1, height, width), |(_, y, x)| {
            f64::from(pixels[y * width + x])
        });
        let name = format!("layer_{layer:0digits$}.png");
        let path = cmd.output.join(&name);
        let format = io::check_output(&path, io::BitDepth::Eight)?;
        io::save(&path, &image, format)?;
        index.push_str(&format!("{layer},{z},{name}\n"));
        bar.inc(1);
    }
    bar.finish_and_clear();
    io::write_text_atomically(&cmd.output.join("layers.csv"), &index)?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "wrote {} layers of {width}×{height} to {} (z from {z0} to {z1}; index layers.csv), {:.2} Mpix/s",
            cmd.layers,
            cmd.output.display(),
            (width * height * cmd.layers) as f64 / start.elapsed().as_secs_f64().max(1e-9) / 1e6
        );
    }
    Ok(())
}
