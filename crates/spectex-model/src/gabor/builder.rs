//! The builder of [`GaborNoise`], with the `spectex noise gabor` defaults:
//! `GaborNoise::builder().frequency(0.1).angle(0.5).build()?`.

use crate::Model;
use crate::defaults::{DEFAULT_MEAN, DEFAULT_SEED, DEFAULT_STD_DEV};
use crate::error::ModelError;
use crate::gabor::{GaborNoise, Orientation};

impl GaborNoise {
    /// Seed unless [`GaborNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// `F₀`, cycles per pixel: a 16-pixel period.
    pub const DEFAULT_FREQUENCY: f32 = 0.0625;
    /// `a`, per pixel: a kernel radius `√(ln 20/π)/a` of about 20 pixels, a little over one
    /// period of `F₀` each side of the centre.
    pub const DEFAULT_BANDWIDTH: f32 = 0.05;
    /// Impulses per kernel footprint (Lagae et al.'s examples use tens: the more impulses, the
    /// closer the sum is to Gaussian).
    pub const DEFAULT_IMPULSES_PER_KERNEL: f32 = 32.0;
    /// Fully isotropic directions, `[0, 2π]`.
    pub const DEFAULT_ORIENTATION: Orientation = Orientation::Isotropic {
        min: 0.0,
        max: std::f32::consts::TAU,
    };
    /// The constant added.
    pub const DEFAULT_MEAN: f32 = DEFAULT_MEAN;
    /// The standard deviation the amplitude is chosen for ([`GaborNoise::unit_std_dev`]).
    pub const DEFAULT_STD_DEV: f32 = DEFAULT_STD_DEV;

    /// A Gabor noise with every field at its default; set what differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::{GaborNoise, Orientation};
    ///
    /// let noise = GaborNoise::builder().frequency(0.1).angle(0.5).std_dev(0.2).build()?;
    /// assert_eq!(noise.orientation, Orientation::Anisotropic { angle: 0.5 });
    /// // The amplitude K is chosen for the standard deviation asked for.
    /// let sigma = f64::from(noise.amplitude) * noise.unit_std_dev();
    /// assert!((sigma - 0.2).abs() < 1e-6);
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> GaborNoiseBuilder {
        GaborNoiseBuilder {
            seed: Self::DEFAULT_SEED,
            mean: Self::DEFAULT_MEAN,
            level: Level::StdDev(Self::DEFAULT_STD_DEV),
            bandwidth: Self::DEFAULT_BANDWIDTH,
            frequency: Self::DEFAULT_FREQUENCY,
            orientation: Self::DEFAULT_ORIENTATION,
            impulses_per_kernel: Self::DEFAULT_IMPULSES_PER_KERNEL,
        }
    }
}

/// How the kernel magnitude `K` is set.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Level {
    /// `K` such that the noise has this standard deviation.
    StdDev(f32),
    /// `K` itself.
    Amplitude(f32),
}

/// Builds a [`GaborNoise`]; start from [`GaborNoise::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct GaborNoiseBuilder {
    seed: u32,
    mean: f32,
    level: Level,
    bandwidth: f32,
    frequency: f32,
    orientation: Orientation,
    impulses_per_kernel: f32,
}

impl GaborNoiseBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// The constant added.
    pub fn mean(mut self, mean: f32) -> Self {
        self.mean = mean;
        self
    }

    /// The standard deviation around the mean, `(0, 1e9]`: `K = σ / unit_std_dev()`
    /// ([`GaborNoise::unit_std_dev`]). Replaces an [`Self::amplitude`] given before.
    pub fn std_dev(mut self, std_dev: f32) -> Self {
        self.level = Level::StdDev(std_dev);
        self
    }

    /// `K`, the kernel magnitude, `[0, 1e9]`. Replaces a [`Self::std_dev`] given before.
    pub fn amplitude(mut self, amplitude: f32) -> Self {
        self.level = Level::Amplitude(amplitude);
        self
    }

    /// `a`, the Gaussian bandwidth, `[0.001, 10]` per pixel.
    pub fn bandwidth(mut self, bandwidth: f32) -> Self {
        self.bandwidth = bandwidth;
        self
    }

    /// `F₀`, the kernel frequency, `[0, 0.5]` cycles per pixel.
    pub fn frequency(mut self, frequency: f32) -> Self {
        self.frequency = frequency;
        self
    }

    /// Every kernel along `angle` radians from the x axis (anisotropic noise).
    pub fn angle(mut self, angle: f32) -> Self {
        self.orientation = Orientation::Anisotropic { angle };
        self
    }

    /// The kernels' directions.
    pub fn orientation(mut self, orientation: Orientation) -> Self {
        self.orientation = orientation;
        self
    }

    /// Gabor noise by example: each impulse draws its frequency vector `frequencies[k]` (cycles
    /// per pixel) with probability `weights[k] / Σ weights` ([`Orientation::Spectrum`]).
    pub fn spectrum(mut self, frequencies: Vec<[f32; 2]>, weights: Vec<f32>) -> Self {
        self.orientation = Orientation::Spectrum {
            frequencies,
            weights,
        };
        self.frequency = 0.0;
        self
    }

    /// Mean impulses per kernel footprint, `[0.01, 1000]`.
    pub fn impulses_per_kernel(mut self, impulses_per_kernel: f32) -> Self {
        self.impulses_per_kernel = impulses_per_kernel;
        self
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the first field outside its range (`gabor.bandwidth`,
    /// …; `gabor.std_dev` for a standard deviation that is not positive, or that needs an
    /// amplitude beyond the model's range).
    pub fn build(self) -> Result<GaborNoise, ModelError> {
        let mut noise = GaborNoise {
            seed: self.seed,
            mean: self.mean,
            amplitude: 1.0,
            bandwidth: self.bandwidth,
            frequency: self.frequency,
            orientation: self.orientation,
            impulses_per_kernel: self.impulses_per_kernel,
        };
        match self.level {
            Level::Amplitude(k) => noise.amplitude = k,
            Level::StdDev(sigma) => {
                if !(sigma.is_finite() && sigma > 0.0) {
                    return Err(ModelError::OutOfRange {
                        field: "gabor.std_dev".into(),
                        value: f64::from(sigma),
                        range: "(0, 1e9]",
                    });
                }
                // `unit_std_dev` needs a valid bandwidth and density.
                noise.validate()?;
                let amplitude = sigma / noise.unit_std_dev() as f32;
                if !(amplitude.is_finite() && amplitude <= 1e9) {
                    return Err(ModelError::OutOfRange {
                        field: "gabor.std_dev".into(),
                        value: f64::from(sigma),
                        range: "(0, 1e9 × unit_std_dev()]: at most a kernel magnitude K of 1e9",
                    });
                }
                noise.amplitude = amplitude;
            }
        }
        noise.validate()?;
        Ok(noise)
    }
}

impl From<GaborNoise> for Model {
    fn from(noise: GaborNoise) -> Self {
        Self::Gabor(noise)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn defaults_are_the_documented_constants() {
        let g = GaborNoise::builder().build().expect("defaults are valid");
        assert_eq!(
            (
                g.seed,
                g.mean,
                g.bandwidth,
                g.frequency,
                g.impulses_per_kernel
            ),
            (0, 0.5, 0.05, 0.0625, 32.0)
        );
        assert_eq!(
            g.orientation,
            Orientation::Isotropic {
                min: 0.0,
                max: std::f32::consts::TAU
            }
        );
        // K = σ / unit_std_dev with σ = 0.15, in f32 as written.
        assert_eq!(g.amplitude, 0.15 / g.unit_std_dev() as f32);
    }

    pub fn amplitude_and_std_dev_replace_each_other() {
        let k = GaborNoise::builder().std_dev(0.3).amplitude(2.0).build();
        assert_eq!(k.expect("valid").amplitude, 2.0);
        let s = GaborNoise::builder().amplitude(2.0).std_dev(0.3).build();
        let s = s.expect("valid");
        assert!((f64::from(s.amplitude) * s.unit_std_dev() - 0.3).abs() < 1e-6);
    }

    pub fn invalid_settings_name_the_field() {
        let cases = [
            (
                GaborNoise::builder().bandwidth(0.0).build(),
                "gabor.bandwidth",
            ),
            (
                GaborNoise::builder().frequency(0.6).build(),
                "gabor.frequency",
            ),
            (GaborNoise::builder().std_dev(-1.0).build(), "gabor.std_dev"),
            (
                GaborNoise::builder().std_dev(f32::NAN).build(),
                "gabor.std_dev",
            ),
            (GaborNoise::builder().std_dev(1e12).build(), "gabor.std_dev"),
            (
                GaborNoise::builder().amplitude(-1.0).build(),
                "gabor.amplitude",
            ),
            (GaborNoise::builder().mean(f32::NAN).build(), "gabor.mean"),
            (
                GaborNoise::builder().impulses_per_kernel(0.0).build(),
                "gabor.impulses_per_kernel",
            ),
            (
                GaborNoise::builder().angle(f32::INFINITY).build(),
                "gabor.orientation.anisotropic.angle",
            ),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
