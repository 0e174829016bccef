//! `spectex noise`: procedural noises built from flags, one module per family of subcommands
//! (LRP noise of a continuous spectrum, Gabor, the classic noises, wavelet noise, domain
//! warping, textons, Voronoi diagrams, matrix transformation, stochastic subdivision, combinations), each building its model through `spectex_model`'s builders, writing it if asked
//! (`--model`) and rendering it.

pub mod classic;
mod combine;
pub mod gabor;
mod islamic;
mod matrix;
pub mod spectral;
mod subdivision;
mod texton;
mod voronoi;
pub mod warp;
pub mod wavelet;

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::{Args, Subcommand};
use spectex_model::ModelError;
use spectex_model::classic::Basis;

use crate::args::RenderArgs;

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
    Ring(spectral::RingArgs),
    /// Anisotropic noise: two Gaussian lobes at ±F in direction ANGLE (Fig. 3).
    Lobe(spectral::LobeArgs),
    /// Band-pass noise: constant power for MIN ≤ |f| ≤ MAX.
    Band(spectral::BandArgs),
    /// Gabor noise by sparse convolution (Lagae et al. 2009), for comparison with LRP noise.
    Gabor(gabor::GaborArgs),
    /// A random-phase 1/f^β fractal with the survey's angular term (Eq. (8)), as LRP noise:
    /// continuous and infinite; --contrast is the RMS roughness.
    Fractal(spectral::FractalArgs),
    /// Improved Perlin gradient noise (Perlin 2002), 2D or 3D (sliced at --z).
    Perlin(classic::ClassicArgs),
    /// Simplex noise (Perlin 2001, Gustavson 2005), 2D or 3D.
    Simplex(classic::ClassicArgs),
    /// Value noise: random lattice values with quintic interpolation, 2D or 3D.
    Value(classic::ClassicArgs),
    /// Better gradient noise (Kensler, Knoll & Shirley 2008): xor hash, radial kernel of
    /// radius 2 cells, 2D or 3D.
    Kensler(classic::ClassicArgs),
    /// Fractal sum over octaves (fBm, turbulence, ridged multifractal) of a basis.
    Fbm(classic::FbmArgs),
    /// Domain warping: --base evaluated at p + strength·(x(p), y(p)) for the --by (x) and
    /// --by-y models (built-in fBms by default).
    Warp(warp::WarpArgs),
    /// Worley cellular noise C1·F1 + C2·F2 + C3·F3 + C4·F4 (Worley 1996), 2D or 3D.
    Worley(classic::WorleyNoiseArgs),
    /// Wavelet noise (Cook & DeRose 2005): a band-limited tile summed over octave bands, 2D or 3D.
    Wavelet(wavelet::WaveletArgs),
    /// Texton placement / spot noise (survey §2.3): ellipsoids, Gaussian spots or an image
    /// placed on a jittered grid or at Poisson points, rotated, scaled, summed or maxed.
    Texton(texton::TextonArgs),
    /// Voronoi diagrams (survey §2.6): cell ID, F1, exact border distance, F2 − F1, or colours
    /// from a palette or an image; optional Lloyd relaxation.
    Voronoi(voronoi::VoronoiArgs),
    /// Matrix transformation (survey §2.4): a source (built-in rings or a square image) moved
    /// k times by an integer matrix on the N × N torus, e.g. the cat map.
    Matrix(matrix::MatrixArgs),
    /// Stochastic subdivision (survey §3.1.7): midpoint displacement (Fournier et al. 1982)
    /// or a smoother 4-point stencil (after Lewis 1987), each displacement hashed from its
    /// level and lattice point, so infinite and tile-invariant.
    Subdivision(subdivision::SubdivisionArgs),
    /// A combination of models (survey §4.1–4.2): add, multiply, min, max, mix, smoothstep,
    /// fold, sin-fold, histogram matching, colour ramp.
    Combine(combine::CombineArgs),
    /// Islamic star patterns (survey §2.7): Hankin contact-angle rosettes or {n/d} stars on
    /// the square, hexagonal, 4.8.8 or 3.12.12 tiling, as line bands, signed distance or
    /// filled regions.
    Islamic(islamic::IslamicArgs),
}

/// What the noises of a spectrum (and Gabor noise) share.
#[derive(Debug, Args)]
pub struct NoiseArgs {
    /// Cosine budget J of the LRP model (ignored by gabor) [default: 10; fractal: 48].
    #[arg(long)]
    budget: Option<u32>,
    /// Number of strata L of the LRP model (ignored by gabor) [default: 1; fractal: 12, cut
    /// in equal spans of log power].
    #[arg(long)]
    strata: Option<u32>,
    /// Seed.
    #[arg(long, default_value_t = spectex_model::DEFAULT_SEED)]
    seed: u32,
    /// Standard deviation of the noise around its mean.
    #[arg(long, default_value_t = spectex_model::DEFAULT_STD_DEV)]
    contrast: f32,
    /// Mean of the noise.
    #[arg(long, default_value_t = spectex_model::DEFAULT_MEAN)]
    mean: f32,
    /// Also write the model to this .json file.
    #[arg(long, value_name = "MODEL")]
    model: Option<PathBuf>,
    #[command(flatten)]
    render: RenderArgs,
}

impl NoiseArgs {
    /// Refuses a `--contrast` that cannot be a standard deviation, before anything is built.
    fn check_contrast(&self) -> Result<()> {
        if !(self.contrast.is_finite() && self.contrast > 0.0) {
            bail!(
                "--contrast = {} must be a positive number (the noise's standard deviation)",
                self.contrast
            );
        }
        Ok(())
    }
}

/// The flag's value naming the model's `value` in `table` (pairs of a clap value enum and the
/// model's enum), e.g. for a flag's default from a kind's `DEFAULT_` constant.
pub(crate) fn arg_of<A: Copy, M: PartialEq>(table: &[(A, M)], value: &M) -> A {
    table
        .iter()
        .find(|(_, m)| m == value)
        .map(|&(a, _)| a)
        .expect("every model value has a flag value")
}

/// The model's value named by `arg` in `table`.
pub(crate) fn model_of<A: PartialEq, M: Copy>(table: &[(A, M)], arg: &A) -> M {
    table
        .iter()
        .find(|(a, _)| a == arg)
        .map(|&(_, m)| m)
        .expect("every flag value names a model value")
}

/// A model's validation error as the command's, naming the flag to change: `flag` maps the
/// error's dotted field to it (a kind module's `flag`).
pub(crate) fn flag_hint(flag: fn(&str) -> &'static str) -> impl Fn(ModelError) -> anyhow::Error {
    move |e| match &e {
        ModelError::OutOfRange { field, .. } | ModelError::Length { field, .. } => {
            anyhow!("{e}; set {} within it", flag(field))
        }
        _ => anyhow!("{e}"),
    }
}

/// `spectex noise`.
pub fn noise(cmd: &NoiseCommand) -> Result<()> {
    match &cmd.kind {
        NoiseKind::Ring(args) => spectral::ring(args),
        NoiseKind::Lobe(args) => spectral::lobe(args),
        NoiseKind::Band(args) => spectral::band(args),
        NoiseKind::Gabor(args) => gabor::run(args),
        NoiseKind::Fractal(args) => spectral::fractal(args),
        NoiseKind::Perlin(args) => classic::run(Basis::Gradient, None, args),
        NoiseKind::Simplex(args) => classic::run(Basis::Simplex, None, args),
        NoiseKind::Value(args) => classic::run(Basis::Value, None, args),
        NoiseKind::Kensler(args) => classic::run(Basis::Kensler, None, args),
        NoiseKind::Fbm(args) => classic::fbm(args),
        NoiseKind::Warp(args) => warp::run(args),
        NoiseKind::Worley(args) => classic::worley(args),
        NoiseKind::Wavelet(args) => wavelet::run(args),
        NoiseKind::Texton(args) => texton::run(args),
        NoiseKind::Voronoi(args) => voronoi::run(args),
        NoiseKind::Matrix(args) => matrix::run(args),
        NoiseKind::Subdivision(args) => subdivision::run(args),
        NoiseKind::Combine(args) => combine::run(args),
        NoiseKind::Islamic(args) => islamic::run(args),
    }
}
