//! `spectex fit`, `render`, `synth` and `noise`: procedural models (LRP and Gabor noise) fitted
//! from an example or built from a spectrum, and rendered at any window.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Subcommand};
use ndarray::{Array2, Array3, Axis};
use spectex_cpu::{Evaluator, Window};
use spectex_model::{GaborNoise, Model, Orientation, SpectralTarget};
use spectex_sampling::{FitOptions, Partition, TextureOptions};

use crate::classic::{ClassicArgs, FractalArgs, WorleyArgs};
use crate::io::{self, BitDepth};
use spectex_model::classic::Basis;

/// Options shared by every command that fits an LRP model.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// Cosine budget J: cosines per lattice point over all strata (1 to 1024).
    #[arg(long, default_value_t = 50)]
    budget: u32,
    /// Number of strata L (1 to 64, at most J; the paper uses 4).
    #[arg(long, default_value_t = 4)]
    strata: u32,
    /// Seed of the fit (k-means seeding) and of the model's random phases.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Texture by example: share r of the exemplar's energy whose phases are kept (0 to 1;
    /// the paper's §5; 0.1–0.35 keeps structure, 1 reproduces the exemplar periodically).
    #[arg(long, value_name = "r", default_value_t = 0.0)]
    structure: f64,
    /// Distort the structure by turbulence of this scale, pixels (0 to 1e4; about the size of
    /// the texture's features).
    #[arg(long, value_name = "σ", default_value_t = 0.0)]
    turbulence: f64,
    /// Shift blocks of half the structure's period at random, to break its periodicity.
    #[arg(long)]
    random_placement: bool,
    /// Take the structure from the raw exemplar block instead of its periodic component.
    #[arg(long)]
    raw_structure: bool,
}

impl FitArgs {
    fn options(&self) -> FitOptions {
        FitOptions {
            budget: self.budget,
            strata: self.strata,
            seed: self.seed,
            ..FitOptions::default()
        }
    }

    pub(crate) fn texture_options(&self) -> TextureOptions {
        TextureOptions {
            fit: self.options(),
            structure: self.structure,
            turbulence: self.turbulence,
            random_placement: self.random_placement,
            periodic: !self.raw_structure,
            ..TextureOptions::default()
        }
    }

    /// Whether the texture model (rather than plain LRP noise) is asked for.
    fn wants_texture(&self) -> bool {
        self.structure > 0.0 || self.turbulence > 0.0 || self.random_placement
    }
}

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
}

/// Which evaluator renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    /// spectex-cpu: same bytes for any thread count.
    Cpu,
    /// spectex-gpu: within the cross-checked tolerances of the CPU.
    Gpu,
    /// The GPU when an adapter exists, else the CPU.
    Auto,
}

/// Parses `X,Y`.
fn parse_offset(s: &str) -> Result<[f64; 2], String> {
    let err = || format!("'{s}' is not an offset; write X,Y, for example 1e7,1e7 or -20.5,3");
    let (x, y) = s.split_once(',').ok_or_else(err)?;
    let x: f64 = x.trim().parse().map_err(|_| err())?;
    let y: f64 = y.trim().parse().map_err(|_| err())?;
    Ok([x, y])
}

/// Arguments of `spectex fit`.
#[derive(Debug, Args)]
pub struct FitCommand {
    /// Example image; the built-in exemplar if omitted.
    input: Option<PathBuf>,
    /// Model file to write (.json).
    #[arg(short, long, value_name = "MODEL")]
    output: PathBuf,
    #[command(flatten)]
    fit: FitArgs,
}

/// Arguments of `spectex render`.
#[derive(Debug, Args)]
pub struct RenderCommand {
    /// Model file (.json) written by `spectex fit` or `spectex noise --model`.
    model: PathBuf,
    #[command(flatten)]
    render: RenderArgs,
}

/// Arguments of `spectex synth`.
#[derive(Debug, Args)]
pub struct SynthCommand {
    /// Example image; the built-in exemplar if omitted.
    input: Option<PathBuf>,
    #[command(flatten)]
    fit: FitArgs,
    #[command(flatten)]
    render: RenderArgs,
}

/// Arguments of `spectex noise`.
#[derive(Debug, Args)]
pub struct NoiseCommand {
    #[command(subcommand)]
    kind: NoiseKind,
}

/// The continuous spectra of the paper's Fig. 3 and Fig. 10, Gabor noise for comparison, the
/// survey's 1/f^β fractal spectra, and the classic pointwise noises.
#[derive(Debug, Subcommand)]
enum NoiseKind {
    /// Isotropic noise whose power lies on a ring of radius F (Fig. 10).
    Ring {
        /// Ring radius, cycles per pixel.
        #[arg(long, default_value_t = 0.0625)]
        radius: f32,
        /// Gaussian half-width of the ring, cycles per pixel.
        #[arg(long, default_value_t = 0.005)]
        width: f32,
        #[command(flatten)]
        common: NoiseArgs,
    },
    /// Anisotropic noise: two Gaussian lobes at ±F in direction ANGLE (Fig. 3).
    Lobe {
        /// Distance of the lobes from the origin, cycles per pixel.
        #[arg(long, default_value_t = 0.1)]
        frequency: f32,
        /// Direction, degrees.
        #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
        angle: f32,
        /// Standard deviation of each lobe, cycles per pixel.
        #[arg(long, default_value_t = 0.01)]
        width: f32,
        #[command(flatten)]
        common: NoiseArgs,
    },
    /// Band-pass noise: constant power for MIN ≤ |f| ≤ MAX.
    Band {
        /// Inner radius, cycles per pixel.
        #[arg(long, default_value_t = 0.05)]
        min: f32,
        /// Outer radius, cycles per pixel.
        #[arg(long, default_value_t = 0.1)]
        max: f32,
        #[command(flatten)]
        common: NoiseArgs,
    },
    /// Gabor noise by sparse convolution (Lagae et al. 2009), for comparison with LRP noise.
    Gabor {
        /// Kernel frequency F₀, cycles per pixel.
        #[arg(long, default_value_t = 0.0625)]
        frequency: f32,
        /// Gaussian bandwidth a, per pixel.
        #[arg(long, default_value_t = 0.05)]
        bandwidth: f32,
        /// Orientation in degrees; omit for isotropic noise.
        #[arg(long, allow_hyphen_values = true)]
        angle: Option<f32>,
        /// Mean number of impulses per kernel footprint.
        #[arg(long, default_value_t = 32.0)]
        impulses: f32,
        #[command(flatten)]
        common: NoiseArgs,
    },
    /// A random-phase 1/f^β fractal with the survey's angular term (Eq. (8)), as LRP noise:
    /// continuous and infinite; --contrast is the RMS roughness.
    Fractal {
        /// β, the roll-off of the magnitude spectrum (0 to 4): the power falls as f^(−2β).
        #[arg(long, default_value_t = 1.5)]
        beta: f32,
        /// θ₀, the dominant direction of the frequencies, degrees.
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        angle: f32,
        /// σ, the angular standard deviation, degrees (isotropic if omitted).
        #[arg(long)]
        spread: Option<f32>,
        /// Lowest frequency with power, cycles per pixel (1/8192 to 0.25).
        #[arg(long, default_value_t = 1.0 / 128.0)]
        min_frequency: f32,
        #[command(flatten)]
        common: NoiseArgs,
    },
    /// Improved Perlin gradient noise (Perlin 2002), 2D or 3D (sliced at --z).
    Perlin {
        #[command(flatten)]
        classic: ClassicArgs,
    },
    /// Simplex noise (Perlin 2001, Gustavson 2005), 2D or 3D.
    Simplex {
        #[command(flatten)]
        classic: ClassicArgs,
    },
    /// Value noise: random lattice values with quintic interpolation, 2D or 3D.
    Value {
        #[command(flatten)]
        classic: ClassicArgs,
    },
    /// Fractal sum over octaves (fBm, turbulence, ridged multifractal) of a basis.
    Fbm {
        #[command(flatten)]
        fractal: FractalArgs,
        #[command(flatten)]
        worley: WorleyArgs,
        #[command(flatten)]
        classic: ClassicArgs,
    },
    /// Domain warping: --base evaluated at p + strength·(x(p), y(p)) for the --by (x) and
    /// --by-y models (built-in fBms by default).
    Warp {
        #[command(flatten)]
        warp: crate::warp::WarpArgs,
    },
    /// Worley cellular noise C1·F1 + C2·F2 + C3·F3 + C4·F4 (Worley 1996), 2D or 3D.
    Worley {
        #[command(flatten)]
        worley: WorleyArgs,
        #[command(flatten)]
        classic: ClassicArgs,
    },
    /// Wavelet noise (Cook & DeRose 2005): a band-limited tile summed over octave bands, 2D or 3D.
    Wavelet {
        #[command(flatten)]
        wavelet: crate::wavelet::WaveletArgs,
    },
}

/// What every `noise` kind shares.
#[derive(Debug, Args)]
struct NoiseArgs {
    /// Cosine budget J of the LRP model (ignored by gabor) [default: 10; fractal: 48].
    #[arg(long)]
    budget: Option<u32>,
    /// Number of strata L of the LRP model (ignored by gabor) [default: 1; fractal: 12, cut
    /// in equal spans of log power].
    #[arg(long)]
    strata: Option<u32>,
    /// Seed.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Standard deviation of the noise around its mean.
    #[arg(long, default_value_t = 0.15)]
    contrast: f32,
    /// Mean of the noise.
    #[arg(long, default_value_t = 0.5)]
    mean: f32,
    /// Also write the model to this .json file.
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

/// Grid on which a continuous spectrum is sampled before stratification.
const TARGET_GRID: usize = 256;

/// The luminance of a loaded image (colour exemplars are fitted on it until the colour issue).
pub(crate) fn luminance(img: &Array3<f64>, name: &str) -> Array2<f64> {
    if img.dim().0 == 1 {
        return img.index_axis(Axis(0), 0).to_owned();
    }
    eprintln!("note: {name} is in colour; its Rec. 709 luminance is used");
    let w = [0.2126, 0.7152, 0.0722];
    let mut y = Array2::zeros((img.dim().1, img.dim().2));
    for (c, wc) in w.iter().enumerate() {
        y.scaled_add(*wc, &img.index_axis(Axis(0), c));
    }
    y
}

fn fit_example(input: Option<&Path>, fit: &FitArgs) -> Result<(Model, (usize, usize))> {
    // Options first: a bad --budget or --structure is reported before any input is read.
    fit.texture_options()
        .validate()
        .map_err(|e| anyhow!("{e}; check --budget, --strata, --structure and --turbulence"))?;
    let (loaded, name) = crate::load_input(input)?;
    let (channels, h, w) = loaded.pixels.dim();
    if channels == 1 && !fit.wants_texture() {
        let grey = loaded.pixels.index_axis(Axis(0), 0);
        let model = spectex_sampling::fit_image(grey, &fit.options())
            .with_context(|| format!("cannot fit {name}"))?;
        return Ok((Model::Lrp(model), (w, h)));
    }
    // `io` has dropped any alpha channel: 1 or 3 channels remain.
    let (model, report) =
        spectex_sampling::fit_texture(loaded.pixels.view(), &fit.texture_options())
            .with_context(|| format!("cannot fit {name}"))?;
    if fit.structure > 0.0 {
        for (c, ch) in report.channels.iter().enumerate() {
            eprintln!(
                "note: channel {c}: R holds {:.1}% of the energy in {} frequencies; n_R uses J_R = {} \
                 cosines in {}×{} blocks (mean deviation {:.5}), strata {} cosines",
                100.0 * ch.region_energy,
                ch.region_bins,
                ch.structure_cosines,
                ch.blocks,
                ch.blocks,
                ch.structure_error,
                ch.strata_cosines
            );
        }
    }
    Ok((Model::Texture(model), (w, h)))
}

pub(crate) fn write_model(path: &Path, model: &Model) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("json") {
        bail!("model file '{}' must end in .json", path.display());
    }
    let text = spectex_model::to_json(model).context("internal: the fitted model is invalid")?;
    io::write_text_atomically(path, &text)
}

pub(crate) fn read_model(path: &Path) -> Result<Model> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        anyhow!(
            "cannot open model '{}': {e}; check the path",
            path.display()
        )
    })?;
    spectex_model::from_json(&text).map_err(|e| {
        anyhow!(
            "model '{}' is not usable: {e}; write it with `spectex fit` or fix that field",
            path.display()
        )
    })
}

/// Renders `model` as `args` says, showing progress on a terminal, and writes the image.
pub(crate) fn render_to_file(
    model: &Model,
    args: &RenderArgs,
    default_size: (usize, usize),
) -> Result<()> {
    let format = io::check_output(&args.output, args.bit_depth)?;
    let (width, height) = args.size.unwrap_or(default_size);
    let window = Window::new(width, height).at(args.offset.unwrap_or([0.0, 0.0]), args.scale);
    window
        .validate()
        .map_err(|e| anyhow!("{e}; check --size, --offset and --scale"))?;
    let eval = Evaluator::new_at_z(model, args.z).map_err(|e| anyhow!("{e}; check --z"))?;
    // Timed from the render itself: device start-up and shader compilation are not evaluation.
    let (pixels, used, seconds) = match gpu_for(args.device)? {
        Some(context) => {
            let gpu = spectex_gpu::GpuEvaluator::new_at_z(&context, model, args.z)
                .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            let start = std::time::Instant::now();
            let pixels = gpu
                .render(&window)
                .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            let seconds = start.elapsed().as_secs_f64();
            (pixels, format!("GPU {}", context.adapter_name()), seconds)
        }
        None => {
            let start = std::time::Instant::now();
            let mut pixels = vec![0.0f32; width * height * eval.output_channels()];
            let bar = progress_bar(height as u64, "rendering");
            eval.render_into(&window, &mut pixels, &|_| bar.inc(1))
                .map_err(|e| anyhow!("{e}"))?;
            bar.finish_and_clear();
            (pixels, "CPU".to_owned(), start.elapsed().as_secs_f64())
        }
    };
    let channels = pixels.len() / (width * height).max(1);
    let image = Array3::from_shape_fn((channels, height, width), |(c, y, x)| {
        f64::from(pixels[(y * width + x) * channels + c])
    });
    let report = io::save(&args.output, &image, format)?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "wrote {} ({width}×{height} on the {used}, {:.1} evaluations per pixel, {:.2} Mpix/s)",
            args.output.display(),
            eval.cost_per_pixel(),
            (width * height) as f64 / seconds.max(1e-9) / 1e6
        );
    }
    crate::note_clipping(report);
    Ok(())
}

/// The GPU to render on, or `None` for the CPU, as `--device` asks.
fn gpu_for(device: Device) -> Result<Option<spectex_gpu::GpuContext>> {
    match device {
        Device::Cpu => Ok(None),
        Device::Gpu => spectex_gpu::GpuContext::new()
            .map(Some)
            .map_err(|e| anyhow!("--device gpu: {e}; or use --device cpu")),
        Device::Auto => match spectex_gpu::GpuContext::new() {
            Ok(context) => Ok(Some(context)),
            Err(e) => {
                eprintln!("note: --device auto: no GPU ({e}); rendering on the CPU");
                Ok(None)
            }
        },
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

/// `spectex fit`.
pub fn fit(cmd: &FitCommand) -> Result<()> {
    let (model, _) = fit_example(cmd.input.as_deref(), &cmd.fit)?;
    write_model(&cmd.output, &model)?;
    if let Model::Lrp(m) = &model {
        #[allow(clippy::print_stdout)] // reason: the command's result summary
        {
            println!(
                "wrote {} (LRP noise, {} strata, J = {}):",
                cmd.output.display(),
                m.strata.len(),
                m.budget()
            );
            for (s, st) in m.strata.iter().enumerate() {
                println!(
                    "  stratum {s}: J_S = {:>3}, Δ_S = {:7.2} px, A_S = {:.5}, {} frequencies",
                    st.cosines(),
                    st.window_width,
                    st.amplitude,
                    st.sub_strata.iter().map(Vec::len).sum::<usize>()
                );
            }
        }
    }
    if let Model::Texture(m) = &model {
        #[allow(clippy::print_stdout)] // reason: the command's result summary
        {
            println!(
                "wrote {} (texture, {} channel(s), period {} px, {} special-function calls per pixel{}{}):",
                cmd.output.display(),
                m.channels.len(),
                m.period,
                m.special_calls_per_pixel(),
                if m.turbulence.is_some() {
                    ", turbulence"
                } else {
                    ""
                },
                if m.random_placement {
                    ", random placement"
                } else {
                    ""
                },
            );
            for (c, ch) in m.channels.iter().enumerate() {
                let (blocks, fixed) = ch
                    .structure
                    .as_ref()
                    .map_or((0, 0), |s| (s.blocks, s.total_cosines()));
                println!(
                    "  channel {c}: {} strata ({} cosines), structure {blocks}×{blocks} blocks, {fixed} fixed cosines stored",
                    ch.strata.len(),
                    ch.strata
                        .iter()
                        .map(spectex_model::Stratum::cosines)
                        .sum::<usize>()
                );
            }
        }
    }
    Ok(())
}

/// `spectex render`.
pub fn render(cmd: &RenderCommand) -> Result<()> {
    let model = read_model(&cmd.model)?;
    render_to_file(&model, &cmd.render, (512, 512))
}

/// `spectex synth`.
pub fn synth(cmd: &SynthCommand) -> Result<()> {
    io::check_output(&cmd.render.output, cmd.render.bit_depth)?;
    let (model, size) = fit_example(cmd.input.as_deref(), &cmd.fit)?;
    render_to_file(&model, &cmd.render, size)
}

/// `spectex noise`.
pub fn noise(cmd: &NoiseCommand) -> Result<()> {
    let (target, common) = match &cmd.kind {
        NoiseKind::Ring {
            radius,
            width,
            common,
        } => (
            Some(SpectralTarget::Ring {
                radius: *radius,
                width: *width,
            }),
            common,
        ),
        NoiseKind::Lobe {
            frequency,
            angle,
            width,
            common,
        } => (
            Some(SpectralTarget::Lobes {
                frequency: *frequency,
                angle: angle.to_radians(),
                width: *width,
            }),
            common,
        ),
        NoiseKind::Band { min, max, common } => (
            Some(SpectralTarget::Band {
                min: *min,
                max: *max,
            }),
            common,
        ),
        NoiseKind::Gabor { common, .. } => (None, common),
        NoiseKind::Fractal {
            beta,
            angle,
            spread,
            min_frequency,
            common,
        } => (
            Some(SpectralTarget::Fractal {
                beta: *beta,
                angle: angle.to_radians(),
                spread: spread.map(f32::to_radians),
                min_frequency: *min_frequency,
            }),
            common,
        ),
        NoiseKind::Perlin { classic } => {
            return crate::classic::run(Basis::Gradient, None, (0.5, 0.5), classic);
        }
        NoiseKind::Simplex { classic } => {
            return crate::classic::run(Basis::Simplex, None, (0.5, 0.5), classic);
        }
        NoiseKind::Value { classic } => {
            return crate::classic::run(Basis::Value, None, (0.5, 0.5), classic);
        }
        NoiseKind::Fbm {
            fractal,
            worley,
            classic,
        } => {
            let (basis, scale) = crate::classic::fractal_basis(fractal, worley);
            return crate::classic::run(basis, Some(fractal), scale, classic);
        }
        NoiseKind::Warp { warp } => return crate::warp::run(warp),
        NoiseKind::Wavelet { wavelet } => return crate::wavelet::run(wavelet),
        NoiseKind::Worley { worley, classic } => {
            let (basis, scale) = crate::classic::worley_basis(worley);
            return crate::classic::run(basis, None, scale, classic);
        }
    };
    io::check_output(&common.render.output, common.render.bit_depth)?;
    if !(common.contrast.is_finite() && common.contrast > 0.0) {
        bail!(
            "--contrast = {} must be a positive number (the noise's standard deviation)",
            common.contrast
        );
    }
    let model = match (target, &cmd.kind) {
        (Some(target), _) => {
            target
                .validate()
                .map_err(|e| anyhow!("{e}; check the spectrum's options"))?;
            // A 1/f^β spectrum spans decades of power: strata of equal log-power spans, enough
            // of them that each holds about one octave of frequencies
            // (`tests/classic_fidelity.rs` measures the slopes this gives).
            let (budget, strata, partition) = match &cmd.kind {
                NoiseKind::Fractal { .. } => (48, 12, Partition::LogPower),
                _ => (10, 1, Partition::EqualEnergy),
            };
            let options = FitOptions {
                budget: common.budget.unwrap_or(budget),
                strata: common.strata.unwrap_or(strata),
                seed: common.seed,
                partition,
                ..FitOptions::default()
            };
            let variance = f64::from(common.contrast).powi(2);
            let mut m = spectex_sampling::fit_target(&target, variance, TARGET_GRID, &options)
                .context("cannot build the noise")?;
            m.mean = common.mean;
            Model::Lrp(m)
        }
        (
            None,
            NoiseKind::Gabor {
                frequency,
                bandwidth,
                angle,
                impulses,
                ..
            },
        ) => {
            let mut g = GaborNoise {
                seed: common.seed,
                mean: common.mean,
                amplitude: 1.0,
                bandwidth: *bandwidth,
                frequency: *frequency,
                orientation: match angle {
                    Some(a) => Orientation::Anisotropic {
                        angle: a.to_radians(),
                    },
                    None => Orientation::Isotropic {
                        min: 0.0,
                        max: std::f32::consts::TAU,
                    },
                },
                impulses_per_kernel: *impulses,
            };
            g.validate()
                .map_err(|e| anyhow!("{e}; check the gabor options"))?;
            g.amplitude = common.contrast / gabor_unit_std(&g) as f32;
            Model::Gabor(g)
        }
        (None, _) => unreachable!("only gabor has no spectral target"),
    };
    if let Some(path) = &common.model {
        write_model(path, &model)?;
    }
    render_to_file(&model, &common.render, (512, 512))
}

/// Standard deviation of a Gabor noise with K = 1 (Lagae et al. 2009): the impulse density
/// `λ = N/(πr²)` times `E[w²] = 1/3` times `∫ e^{−2πa²|x|²} cos²(2πF₀ω·x) dx`, whose
/// truncated integral is computed numerically on the kernel's disc.
fn gabor_unit_std(g: &GaborNoise) -> f64 {
    let r = g.kernel_radius();
    let a = f64::from(g.bandwidth);
    let f = f64::from(g.frequency);
    let n = 400;
    let h = 2.0 * r / n as f64;
    let mut integral = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (-r + (i as f64 + 0.5) * h, -r + (j as f64 + 0.5) * h);
            let d2 = x * x + y * y;
            if d2 <= r * r {
                // Averaged over directions ω the cos² term is ½ + ½·J0-like; with F₀ ≫ a it is ½.
                let c = (2.0 * std::f64::consts::PI * f * x).cos();
                integral += (-2.0 * std::f64::consts::PI * a * a * d2).exp() * c * c * h * h;
            }
        }
    }
    let density = f64::from(g.impulses_per_kernel) / (std::f64::consts::PI * r * r);
    (density * integral / 3.0).sqrt()
}
