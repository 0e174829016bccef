//! `spectex fit` and `spectex synth`: an LRP noise or a texture model fitted to an example
//! image (Gilet et al. 2014, §4 and §5), a Gabor noise by example (Galerne et al. 2012,
//! `--method gabor`) or tiling and blending (Heitz & Neyret 2018, `--method tiling`), written
//! as a model file or rendered.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use ndarray::Axis;
use spectex_model::tiling::{Blend, TilingTexture};
use spectex_model::{Fit, LrpNoise, Model, TextureModel};
use spectex_sampling::tiling::TilingOptions;
use spectex_sampling::{FitMethod, FitOptions, GaborFit, GaborFitOptions, TextureOptions};

use crate::args::RenderArgs;
use crate::io;
use crate::model_file::write_fitted_model;
use crate::noise::{arg_of, model_of};
use crate::render::render_to_file;

/// Options shared by every command that fits a model to an example.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// The model fitted: `lrp` (Local Random-Phase noise, or a texture with --structure …;
    /// Gilet et al. 2014), `gabor` (Gabor noise by example, Galerne et al. 2012: a sparse sum
    /// of Gaussians fitted to the power spectrum; a colour example is fitted by its luminance
    /// 0.2126 R + 0.7152 G + 0.0722 B) or `tiling` (tiling and blending, Heitz & Neyret 2018:
    /// the exemplar's histogram and shapes kept).
    #[arg(long, value_enum, default_value_t = MethodArg::Lrp)]
    method: MethodArg,
    /// Gabor by example: candidate frequencies every 1/n cycles per pixel (n from 4 to 48;
    /// the Gaussians' bandwidth is √π/n).
    #[arg(long, value_name = "n", default_value_t = GaborFitOptions::DEFAULT_GRID)]
    grid: u32,
    /// Gabor by example: the L1 penalty λ as a share of the strongest correlation, in [0, 1)
    /// (0: plain non-negative least squares; larger keeps fewer Gaussians).
    #[arg(long, default_value_t = GaborFitOptions::DEFAULT_SPARSITY)]
    sparsity: f64,
    /// Gabor by example: mean impulses per kernel footprint (0.01 to 1000; the cost per pixel
    /// is 9/π of it).
    #[arg(long, default_value_t = GaborFitOptions::DEFAULT_IMPULSES_PER_KERNEL)]
    impulses_per_kernel: f32,
    /// Gabor by example: bandwidths, 1 to 4 (1: one bandwidth on the --grid; each further one
    /// halves the spacing and the bandwidth near the zero frequency, and the model is the sum
    /// of one noise per bandwidth sharing the impulses per kernel).
    #[arg(long, default_value_t = GaborFitOptions::DEFAULT_BANDWIDTHS)]
    bandwidths: u32,
    /// Tiling: side of the lattice's triangles, pixels (default: a sixth of the exemplar's
    /// smaller side; at most half of it).
    #[arg(long, value_name = "PX")]
    tile: Option<f32>,
    /// Tiling: `variance` (Heitz & Neyret's histogram-preserving blend) or `hex` (Mikkelsen
    /// 2022's hex-tiling: sharpened linear blend of rotated tiles).
    #[arg(long, value_enum, default_value_t = BlendArg::Variance)]
    blend: BlendArg,
    /// Tiling, hex blend: the weights' exponent γ (1 to 32).
    #[arg(long, value_name = "γ", default_value_t = TilingTexture::DEFAULT_SHARPNESS)]
    sharpness: u32,
    /// Tiling, hex blend: largest rotation of a tile, turns (0 to 0.5).
    #[arg(long, value_name = "TURNS", default_value_t = 0.0)]
    rotation: f32,
    /// Cosine budget J: cosines per lattice point over all strata (1 to 1024).
    #[arg(long, default_value_t = FitOptions::DEFAULT_BUDGET)]
    budget: u32,
    /// Number of strata L (1 to 64, at most J; the paper uses 4).
    #[arg(long, default_value_t = FitOptions::DEFAULT_STRATA)]
    strata: u32,
    /// How the strata become cosines: `spectrum` (equal-energy sub-strata drawn in proportion to
    /// the power, matching the exemplar's spectrum) or `paper` (Gilet et al. 2014 §4.3 as
    /// printed, to reproduce its figures).
    #[arg(long, value_enum, default_value_t = arg_of(&METHODS, &FitOptions::DEFAULT_METHOD))]
    fit: FitArg,
    /// Seed of the fit (k-means seeding) and of the model's random phases.
    #[arg(long, default_value_t = FitOptions::DEFAULT_SEED)]
    seed: u32,
    /// Texture by example: share r of the exemplar's energy whose phases are kept (0 to 1;
    /// the paper's §5; 0.1–0.35 keeps structure, 1 reproduces the exemplar periodically).
    #[arg(long, value_name = "r", default_value_t = TextureOptions::DEFAULT_STRUCTURE)]
    structure: f64,
    /// Distort the structure by turbulence of this scale, pixels (0 to 1e4; about the size of
    /// the texture's features).
    #[arg(long, value_name = "σ", default_value_t = TextureOptions::DEFAULT_TURBULENCE)]
    turbulence: f64,
    /// Shift blocks of half the structure's period at random, to break its periodicity.
    #[arg(long)]
    random_placement: bool,
    /// Take the structure from the raw exemplar block instead of its periodic component.
    #[arg(long)]
    raw_structure: bool,
}

/// `--method`: which model a fit makes. A new method is one more value here and one more arm
/// in [`fit_example`] (and in `Fitted`, how it is written and summarised).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum MethodArg {
    /// Local Random-Phase noise or texture (Gilet et al. 2014).
    Lrp,
    /// Gabor noise by example (Galerne et al. 2012).
    Gabor,
    /// Tiling and blending (Heitz & Neyret 2018).
    Tiling,
}

/// `--fit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum FitArg {
    Spectrum,
    Paper,
}

/// `--blend`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum BlendArg {
    Variance,
    Hex,
}

/// The fit methods by name, for the conversions both ways.
const METHODS: [(FitArg, FitMethod); 2] = [
    (FitArg::Spectrum, FitMethod::Spectrum),
    (FitArg::Paper, FitMethod::Paper),
];

impl FitArgs {
    pub fn options(&self) -> FitOptions {
        FitOptions {
            budget: self.budget,
            strata: self.strata,
            seed: self.seed,
            method: self.method(),
            ..FitOptions::default()
        }
    }

    fn method(&self) -> FitMethod {
        model_of(&METHODS, &self.fit)
    }

    /// The fit recorded in the model file (LRP's only).
    fn recorded(&self) -> Option<Fit> {
        match (self.method, self.fit) {
            (MethodArg::Tiling | MethodArg::Gabor, _) => None,
            (MethodArg::Lrp, FitArg::Spectrum) => Some(Fit::Spectrum),
            (MethodArg::Lrp, FitArg::Paper) => Some(Fit::Paper),
        }
    }

    /// The options of `--method tiling`.
    pub fn tiling_options(&self) -> TilingOptions {
        TilingOptions {
            tile: self.tile,
            blend: match self.blend {
                BlendArg::Variance => Blend::Variance,
                BlendArg::Hex => Blend::Hex {
                    sharpness: self.sharpness,
                    rotation: self.rotation,
                },
            },
            seed: self.seed,
        }
    }

    pub fn texture_options(&self) -> TextureOptions {
        TextureOptions {
            fit: self.options(),
            structure: self.structure,
            turbulence: self.turbulence,
            random_placement: self.random_placement,
            periodic: !self.raw_structure,
            ..TextureOptions::default()
        }
    }

    /// The options of a Gabor noise by example.
    fn gabor_options(&self) -> GaborFitOptions {
        GaborFitOptions {
            grid: self.grid,
            sparsity: self.sparsity,
            impulses_per_kernel: self.impulses_per_kernel,
            seed: self.seed,
            bandwidths: self.bandwidths,
            ..GaborFitOptions::default()
        }
    }

    /// Whether the texture model (rather than plain LRP noise) is asked for.
    pub fn wants_texture(&self) -> bool {
        self.structure > 0.0 || self.turbulence > 0.0 || self.random_placement
    }
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

/// What a fit gives: plain LRP noise (a grey exemplar without texture options), a texture, or
/// a Gabor noise by example.
enum Fitted {
    Noise(LrpNoise),
    Texture(TextureModel),
    Tiling(TilingTexture),
    Gabor(Box<GaborFit>, Model),
}

impl Fitted {
    fn to_model(&self) -> Model {
        match self {
            Self::Noise(noise) => noise.clone().into(),
            Self::Texture(texture) => texture.clone().into(),
            Self::Tiling(tiling) => tiling.clone().into(),
            Self::Gabor(_, model) => model.clone(),
        }
    }
}

/// Fits the example (the built-in exemplar if `input` is `None`) by `--method`; also returns
/// its size.
fn fit_example(input: Option<&Path>, fit: &FitArgs) -> Result<(Fitted, (usize, usize))> {
    match fit.method {
        MethodArg::Lrp => fit_lrp(input, fit),
        MethodArg::Gabor => fit_gabor(input, fit),
        MethodArg::Tiling => fit_tiling(input, fit),
    }
}

/// `--method gabor`: the luminance of the example (its only channel when grey).
fn fit_gabor(input: Option<&Path>, fit: &FitArgs) -> Result<(Fitted, (usize, usize))> {
    if fit.wants_texture() {
        return Err(anyhow!(
            "--structure, --turbulence and --random-placement make an LRP texture; they cannot \
             be used with --method gabor"
        ));
    }
    let options = fit.gabor_options();
    options.validate().map_err(|e| {
        anyhow!("{e}; check --grid, --sparsity, --impulses-per-kernel and --bandwidths")
    })?;
    let (loaded, name) = io::load_input(input)?;
    let (channels, h, w) = loaded.pixels.dim();
    let grey = if channels >= 3 {
        // Rec. 709 luminance of the (non-linear) values, as the exemplar is read.
        ndarray::Array2::from_shape_fn((h, w), |(y, x)| {
            0.2126 * loaded.pixels[[0, y, x]]
                + 0.7152 * loaded.pixels[[1, y, x]]
                + 0.0722 * loaded.pixels[[2, y, x]]
        })
    } else {
        loaded.pixels.index_axis(Axis(0), 0).to_owned()
    };
    let fitted = spectex_sampling::fit_gabor(grey.view(), &options)
        .with_context(|| format!("cannot fit {name}"))?;
    let model = fitted
        .model()
        .with_context(|| format!("cannot fit {name}"))?;
    Ok((Fitted::Gabor(Box::new(fitted), model), (w, h)))
}

/// `--method tiling`: the example's grey or RGB channels (an alpha channel is refused).
fn fit_tiling(input: Option<&Path>, fit: &FitArgs) -> Result<(Fitted, (usize, usize))> {
    let (loaded, name) = io::load_input_as_is(input)?;
    let (_, h, w) = loaded.pixels.dim();
    if loaded.dropped_alpha {
        bail!(
            "{name} has an alpha channel; tiling by example tiles grey or RGB exemplars: \
             flatten or remove the alpha channel first"
        );
    }
    let model = spectex_sampling::tiling::fit_tiling(loaded.pixels.view(), &fit.tiling_options())
        .with_context(|| {
        format!("cannot fit {name} (check --tile, --sharpness and --rotation)")
    })?;
    Ok((Fitted::Tiling(model), (w, h)))
}

/// `--method lrp`: LRP noise for a grey example, a texture for a colour one or with texture
/// options.
fn fit_lrp(input: Option<&Path>, fit: &FitArgs) -> Result<(Fitted, (usize, usize))> {
    // Options first: a bad --budget or --structure is reported before any input is read.
    fit.texture_options()
        .validate()
        .map_err(|e| anyhow!("{e}; check --budget, --strata, --structure and --turbulence"))?;
    let (loaded, name) = io::load_input(input)?;
    let (channels, h, w) = loaded.pixels.dim();
    if channels == 1 && !fit.wants_texture() {
        let grey = loaded.pixels.index_axis(Axis(0), 0);
        let model = spectex_sampling::fit_image(grey, &fit.options())
            .with_context(|| format!("cannot fit {name}"))?;
        return Ok((Fitted::Noise(model), (w, h)));
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
    Ok((Fitted::Texture(model), (w, h)))
}

/// `spectex fit`.
pub fn fit(cmd: &FitCommand) -> Result<()> {
    let (fitted, _) = fit_example(cmd.input.as_deref(), &cmd.fit)?;
    write_fitted_model(&cmd.output, &fitted.to_model(), cmd.fit.recorded())?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    match &fitted {
        Fitted::Gabor(fit, _) => {
            let bandwidths: Vec<String> = fit
                .noises
                .iter()
                .map(|g| format!("{:.4}", g.bandwidth))
                .collect();
            let cost: f64 = fit.noises.iter().map(|g| 9.0 * g.impulses_per_cell()).sum();
            println!(
                "wrote {} (Gabor noise by example, {} of {} Gaussians, coarsest grid 1/{}, \
                 bandwidths a = {}, relative residual {:.3}, {:.1} kernel evaluations per pixel)",
                cmd.output.display(),
                fit.components,
                fit.candidates,
                fit.grid,
                bandwidths.join(", "),
                fit.relative_residual,
                cost
            );
        }
        Fitted::Noise(m) => {
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
        Fitted::Tiling(m) => {
            println!(
                "wrote {} (tiling and blending, {} channel(s), {}×{} exemplar, triangles of {} px, {} blend, {} mip levels)",
                cmd.output.display(),
                m.channels,
                m.width,
                m.height,
                m.tile,
                match m.blend {
                    Blend::Variance => "variance-preserving",
                    Blend::Hex { .. } => "hex",
                },
                m.level_count()
            );
        }
        Fitted::Texture(m) => {
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

/// `spectex synth`.
pub fn synth(cmd: &SynthCommand) -> Result<()> {
    io::check_output(&cmd.render.output, cmd.render.bit_depth)?;
    let (fitted, size) = fit_example(cmd.input.as_deref(), &cmd.fit)?;
    render_to_file(&fitted.to_model(), &cmd.render, size)
}
