//! Gabor noise by sparse convolution (Lagae et al. 2009): Poisson-distributed impulses per grid
//! cell, each a truncated Gaussian times a cosine.
//!
//! # Randomness contract (layer 0)
//!
//! Cell `(i, j)` seeds its PRNG with `cell_hash(i, j, 0, seed)` and draws a Poisson count, then
//! per impulse its offsets, weight and (isotropic) direction.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_level, check_range};

pub(crate) mod builder;
pub use builder::GaborNoiseBuilder;

/// How far a periodic Gabor noise's kernel radius (so its bandwidth) may move to tile the
/// period: 25%, a bandwidth still within a quarter of the model's.
pub const GABOR_PERIOD_TOLERANCE: f64 = 0.25;
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

    /// The kernel radius (and cell side) of this noise made periodic with `period`: `g / m`
    /// with `g` the largest side dividing both `W` and `H` ([`crate::Period::common_side`]) and
    /// `m = max(1, round(g / r))`, so that square cells tile the period; `None` when that
    /// moves `r` (and the bandwidth `a ∝ 1/r`) by more than [`GABOR_PERIOD_TOLERANCE`].
    #[must_use]
    pub fn periodic_radius(&self, period: crate::Period) -> Option<f64> {
        let r = self.kernel_radius();
        let g = f64::from(period.common_side());
        let fitted = g / crate::period::cells_in(g, r) as f64;
        ((fitted / r - 1.0).abs() <= GABOR_PERIOD_TOLERANCE).then_some(fitted)
    }

    /// Mean impulses per grid cell of side `r`: `impulses_per_kernel / π`.
    #[must_use]
    pub fn impulses_per_cell(&self) -> f64 {
        f64::from(self.impulses_per_kernel) / std::f64::consts::PI
    }

    /// Standard deviation of this noise's kernel sum with `K = 1` (the value is
    /// `mean + amplitude·n`, so `amplitude = σ / unit_std_dev()` gives the standard deviation
    /// `σ`).
    ///
    /// By Campbell's theorem the variance of a Poisson sparse convolution is the impulse
    /// density `λ = impulses_per_kernel/(πr²)` times `E[w²] = 1/3` (weights uniform in
    /// `[−1, 1]`) times `∫ e^{−2πa²|x|²} cos²(2πF₀ ω·x) dx` over the kernel's disc of radius
    /// `r` ([`Self::kernel_radius`]). The integral does not depend on the direction `ω` (the
    /// disc and the Gaussian are rotation-invariant), so it is taken along `x`, by the midpoint
    /// rule on a 400 × 400 grid over the disc's bounding square (about 10⁻⁶ from the exact
    /// value; a test compares it with a polar integration).
    #[must_use]
    pub fn unit_std_dev(&self) -> f64 {
        let r = self.kernel_radius();
        let a = f64::from(self.bandwidth);
        let f = f64::from(self.frequency);
        let n = 400;
        let h = 2.0 * r / n as f64;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (-r + (i as f64 + 0.5) * h, -r + (j as f64 + 0.5) * h);
                let d2 = x * x + y * y;
                if d2 <= r * r {
                    let c = (2.0 * std::f64::consts::PI * f * x).cos();
                    integral += (-2.0 * std::f64::consts::PI * a * a * d2).exp() * c * c * h * h;
                }
            }
        }
        let density = f64::from(self.impulses_per_kernel) / (std::f64::consts::PI * r * r);
        (density * integral / 3.0).sqrt()
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
    const PERIODIC: bool = true;

    /// A period whose common side (the gcd of `W` and `H`) holds a whole number of cells of
    /// about the kernel radius ([`GaborNoise::periodic_radius`]).
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        if self.periodic_radius(period).is_some() {
            return Ok(());
        }
        Err(ModelError::Period {
            period: period.to_string(),
            kind: "gabor",
            requirement: format!(
                "its kernel radius {:.2} pixels must become a divisor of gcd(W, H) = {} within \
                 25%; take a period whose sides share a large common divisor (a square one, or \
                 multiples of {})",
                self.kernel_radius(),
                period.common_side(),
                self.kernel_radius().ceil()
            ),
        })
    }

    const NAME: &'static str = "gabor";

    fn validate(&self) -> Result<(), ModelError> {
        GaborNoise::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// `J₀(z) = (1/π) ∫₀^π cos(z sin t) dt` by Simpson's rule.
    fn bessel_j0(z: f64) -> f64 {
        let n = 256;
        let h = PI / f64::from(n);
        let sum: f64 = (0..=n)
            .map(|k| {
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * (z * (f64::from(k) * h).sin()).cos()
            })
            .sum();
        sum * h / 3.0 / PI
    }

    /// The variance with `K = 1` integrated in polar coordinates, independently of the
    /// Cartesian grid of `unit_std_dev`: the angular integral of `cos²(2πFρ cos θ)` is
    /// `π(1 + J₀(4πFρ))`, and the radial one runs over `[0, r]` by Simpson's rule.
    fn polar_variance(g: &GaborNoise) -> f64 {
        let r = g.kernel_radius();
        let a = f64::from(g.bandwidth);
        let f = f64::from(g.frequency);
        let n = 2000;
        let h = r / f64::from(n);
        let integrand = |rho: f64| {
            (-2.0 * PI * a * a * rho * rho).exp() * rho * PI * (1.0 + bessel_j0(4.0 * PI * f * rho))
        };
        let integral: f64 = (0..=n)
            .map(|k| {
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * integrand(f64::from(k) * h)
            })
            .sum::<f64>()
            * h
            / 3.0;
        f64::from(g.impulses_per_kernel) / (PI * r * r) * integral / 3.0
    }

    fn noise(bandwidth: f32, frequency: f32, impulses_per_kernel: f32) -> GaborNoise {
        GaborNoise {
            seed: 0,
            mean: 0.0,
            amplitude: 1.0,
            bandwidth,
            frequency,
            orientation: Orientation::Isotropic {
                min: 0.0,
                max: std::f32::consts::TAU,
            },
            impulses_per_kernel,
        }
    }

    pub fn unit_std_dev_matches_a_polar_integration() {
        for (a, f, n) in [
            (0.05, 0.0625, 32.0),
            (0.05, 0.0, 16.0),
            (0.02, 0.01, 8.0),
            (0.2, 0.4, 100.0),
            (0.01, 0.005, 1.0),
        ] {
            let g = noise(a, f, n);
            let grid = g.unit_std_dev();
            let polar = polar_variance(&g).sqrt();
            let rel = (grid / polar - 1.0).abs();
            assert!(
                rel < 1e-4,
                "a = {a}, F0 = {f}, N = {n}: grid {grid}, polar {polar}, rel {rel:e}"
            );
        }
    }

    pub fn unit_std_dev_at_zero_frequency_has_a_closed_form() {
        // F₀ = 0: ∫_disc e^{−2πa²|x|²} dx = (1 − e^{−2πa²r²})/(2a²) and πa²r² = ln 20, so
        // the variance is λ/3 · (1 − 1/400)/(2a²) with λ = N/(πr²).
        let g = noise(0.05, 0.0, 16.0);
        let (a, r) = (f64::from(g.bandwidth), g.kernel_radius());
        let closed = (16.0 / (PI * r * r) / 3.0 * (1.0 - 1.0 / 400.0) / (2.0 * a * a)).sqrt();
        let rel = (g.unit_std_dev() / closed - 1.0).abs();
        assert!(
            rel < 1e-4,
            "grid {} closed form {closed}, rel {rel:e}",
            g.unit_std_dev()
        );
    }
}
