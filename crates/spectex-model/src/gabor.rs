//! Gabor noise by sparse convolution (Lagae et al. 2009): Poisson-distributed impulses per grid
//! cell, each a truncated Gaussian times a cosine.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_level, check_range};

/// Fraction of the kernel's peak at which the Gaussian is truncated (Lagae et al. use 0.05):
/// the kernel radius is `r = √(−ln 0.05 / π) / a` and the grid cell size equals `r`.
pub const GABOR_TRUNCATION: f64 = 0.05;

/// `−ln 20 = ln 0.05`, rounded to f32: the Gaussian's exponent at the truncation radius, so on a
/// grid of cells of side `r` the kernel is `exp(NEG_LN_20·d²)` for `d` in cell units (`π a² r² =
/// ln 20`). Shared by Gabor and phasor noise (same truncation).
pub const NEG_LN_20: f32 = -2.995_732_3;

/// Orientation of the kernels' frequency vector.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Orientation {
    /// All kernels share one direction, `angle` in radians from the x axis.
    Anisotropic {
        /// Angle of the frequency vector, radians.
        angle: f32,
    },
    /// Each impulse draws its direction uniformly in `[min, max]` radians (`[0, 2π]` is fully
    /// isotropic).
    Isotropic {
        /// Smallest angle, radians.
        min: f32,
        /// Largest angle, radians.
        max: f32,
    },
}

/// A Gabor noise: `n(x) = mean + Σ_i w_i · K·exp(−π a²|x − x_i|²)·cos(2π F₀ ω_i·(x − x_i))`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaborNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// Constant added to the noise.
    pub mean: f32,
    /// `K`, the kernel magnitude.
    pub amplitude: f32,
    /// `a`, the Gaussian bandwidth, in 1/pixels.
    pub bandwidth: f32,
    /// `F₀`, the kernel frequency, in cycles per pixel.
    pub frequency: f32,
    /// Direction of the frequency vector.
    pub orientation: Orientation,
    /// Mean number of impulses per kernel footprint (`λ·π r²`, Lagae's "number of impulses per
    /// kernel").
    pub impulses_per_kernel: f32,
}

impl GaborNoise {
    /// Kernel radius `r = √(−ln t / π) / a` for the truncation `t` = [`GABOR_TRUNCATION`].
    #[must_use]
    pub fn kernel_radius(&self) -> f64 {
        (-GABOR_TRUNCATION.ln() / std::f64::consts::PI).sqrt() / f64::from(self.bandwidth)
    }

    /// Mean impulses per grid cell of side `r`: `impulses_per_kernel / π`.
    #[must_use]
    pub fn impulses_per_cell(&self) -> f64 {
        f64::from(self.impulses_per_kernel) / std::f64::consts::PI
    }

    /// Checks every number.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_level(|| "gabor.mean".into(), self.mean)?;
        check_range(
            || "gabor.amplitude".into(),
            f64::from(self.amplitude),
            0.0,
            1e9,
            "[0, 1e9]",
        )?;
        check_range(
            || "gabor.bandwidth".into(),
            f64::from(self.bandwidth),
            1e-3,
            10.0,
            "[0.001, 10] per pixel",
        )?;
        check_range(
            || "gabor.frequency".into(),
            f64::from(self.frequency),
            0.0,
            0.5,
            "[0, 0.5] cycles per pixel",
        )?;
        check_range(
            || "gabor.impulses_per_kernel".into(),
            f64::from(self.impulses_per_kernel),
            0.01,
            1000.0,
            "[0.01, 1000]",
        )?;
        match self.orientation {
            Orientation::Anisotropic { angle } => check_range(
                || "gabor.orientation.anisotropic.angle".into(),
                f64::from(angle),
                -1e3,
                1e3,
                "[-1000, 1000] radians",
            ),
            Orientation::Isotropic { min, max } => {
                check_range(
                    || "gabor.orientation.isotropic.min".into(),
                    f64::from(min),
                    -1e3,
                    1e3,
                    "[-1000, 1000] radians",
                )?;
                check_range(
                    || "gabor.orientation.isotropic.max".into(),
                    f64::from(max),
                    f64::from(min),
                    1e3,
                    "[min, 1000] radians",
                )
            }
        }
    }
}

impl crate::ModelKind for GaborNoise {
    const NAME: &'static str = "gabor";

    fn validate(&self) -> Result<(), ModelError> {
        GaborNoise::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}
