//! The builder of [`PhasorNoise`], with the `spectex phasor` defaults:
//! `PhasorNoise::builder().profile(Profile::square(0.25)).build()?`.

use crate::Model;
use crate::defaults::{DEFAULT_SEED, Levels};
use crate::error::ModelError;
use crate::phasor::{
    COHERENT_BANDWIDTH_RATIO, COHERENT_SPREAD, Field, PhasorNoise, PhasorOrientation, PhasorOutput,
    Profile,
};

impl PhasorNoise {
    /// Seed unless [`PhasorNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// A plane (2) unless [`PhasorNoiseBuilder::dimensions`] is given.
    pub const DEFAULT_DIMENSIONS: u8 = 2;
    /// `F`, cycles per pixel: stripes 20 pixels apart.
    pub const DEFAULT_FREQUENCY: f32 = 0.05;
    /// `b`, per pixel: kernels of radius `√(ln 20/π)/b`, about 49 pixels, each spanning about
    /// five periods of the default frequency.
    pub const DEFAULT_BANDWIDTH: f32 = 0.02;
    /// Impulses per kernel footprint.
    pub const DEFAULT_IMPULSES_PER_KERNEL: f32 = 32.0;
    /// Direction of the kernels (the bi-lobe case along x) unless another orientation is given.
    pub const DEFAULT_ANGLE: f32 = 0.0;
    /// Frequency at white of a frequency image (`spectex phasor --frequency-image`), cycles
    /// per pixel: twice [`Self::DEFAULT_FREQUENCY`], an octave of grading.
    pub const DEFAULT_FREQUENCY_MAX: f32 = 0.1;
    /// Bandwidth at white of a bandwidth image (`spectex phasor --bandwidth-image`), per pixel:
    /// twice [`Self::DEFAULT_BANDWIDTH`].
    pub const DEFAULT_BANDWIDTH_MAX: f32 = 0.04;
    /// Duty cycle of a square profile: equal light and dark.
    pub const DEFAULT_DUTY: f32 = 0.5;

    /// A phasor noise with every field at its default: sine stripes along x, written in
    /// `[0, 1]`; set what differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::{PhasorNoise, PhasorOrientation, Profile};
    ///
    /// // The paper's pulse-width-modulated labyrinth (Fig. 14 without the control images).
    /// let noise = PhasorNoise::builder()
    ///     .orientation(PhasorOrientation::coherent())
    ///     .profile(Profile::square(0.25))
    ///     .seed(2)
    ///     .build()?;
    /// // The square profile is already in [0, 1]: written as it is.
    /// assert_eq!((noise.mean, noise.amplitude), (0.0, 1.0));
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> PhasorNoiseBuilder {
        PhasorNoiseBuilder {
            seed: Self::DEFAULT_SEED,
            dimensions: Self::DEFAULT_DIMENSIONS,
            bandwidth: Field::constant(Self::DEFAULT_BANDWIDTH),
            frequency: Field::constant(Self::DEFAULT_FREQUENCY),
            orientation: PhasorOrientation::Aligned {
                angle: Field::constant(Self::DEFAULT_ANGLE),
            },
            impulses_per_kernel: Self::DEFAULT_IMPULSES_PER_KERNEL,
            profile: Profile::Sine,
            output: PhasorOutput::default(),
            mean: None,
            amplitude: None,
        }
    }

    /// The mean and amplitude a builder uses unless given (those of `spectex phasor`): they
    /// show the output in `[0, 1]`. A profile in `[−1, 1]` (sine, triangle, sawtooth) is
    /// centred on ½ and scaled by ½; the square profile (0 or 1) is written as it is; the
    /// phase in turns, `(−½, ½]`, is shifted by ½; the Gabor noise `I·sin φ` is centred on ½ and
    /// the intensity `I ≥ 0` left at 0, both scaled by 1/6 (so `±3` and `[0, 6]` map onto
    /// `[0, 1]`).
    #[must_use]
    pub fn default_levels(output: PhasorOutput, profile: &Profile) -> Levels {
        let (mean, amplitude) = match output {
            PhasorOutput::Profiled if matches!(profile, Profile::Square { .. }) => (0.0, 1.0),
            PhasorOutput::Profiled => (0.5, 0.5),
            PhasorOutput::Phase => (0.5, 1.0),
            PhasorOutput::Intensity => (0.0, 1.0 / 6.0),
            PhasorOutput::Gabor => (0.5, 1.0 / 6.0),
        };
        Levels { mean, amplitude }
    }
}

impl PhasorOrientation {
    /// The paper's locally coherent isotropic direction field (§3.2.2): spread
    /// [`COHERENT_SPREAD`], bandwidth ratio [`COHERENT_BANDWIDTH_RATIO`].
    #[must_use]
    pub fn coherent() -> Self {
        Self::Coherent {
            spread: COHERENT_SPREAD,
            bandwidth_ratio: COHERENT_BANDWIDTH_RATIO,
        }
    }
}

impl Profile {
    /// Pulse-width modulation with a constant duty cycle in `[0, 1]`.
    #[must_use]
    pub fn square(duty: f32) -> Self {
        Self::Square {
            duty: Field::constant(duty),
        }
    }
}

/// Builds a [`PhasorNoise`]; start from [`PhasorNoise::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct PhasorNoiseBuilder {
    seed: u32,
    dimensions: u8,
    bandwidth: Field,
    frequency: Field,
    orientation: PhasorOrientation,
    impulses_per_kernel: f32,
    profile: Profile,
    output: PhasorOutput,
    mean: Option<f32>,
    amplitude: Option<f32>,
}

impl PhasorNoiseBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// 2 for images, 3 for volumes (evaluated slice by slice).
    pub fn dimensions(mut self, dimensions: u8) -> Self {
        self.dimensions = dimensions;
        self
    }

    /// `F`, the same everywhere, `[0, 0.5]` cycles per pixel.
    pub fn frequency(self, frequency: f32) -> Self {
        self.frequency_field(Field::constant(frequency))
    }

    /// `F` graded over space (read at each kernel's centre).
    pub fn frequency_field(mut self, frequency: Field) -> Self {
        self.frequency = frequency;
        self
    }

    /// `b`, the same everywhere, `[0.001, 1]` per pixel.
    pub fn bandwidth(self, bandwidth: f32) -> Self {
        self.bandwidth_field(Field::constant(bandwidth))
    }

    /// `b` graded over space.
    pub fn bandwidth_field(mut self, bandwidth: Field) -> Self {
        self.bandwidth = bandwidth;
        self
    }

    /// Every kernel along `angle` radians from the x axis.
    pub fn angle(self, angle: f32) -> Self {
        self.orientation(PhasorOrientation::Aligned {
            angle: Field::constant(angle),
        })
    }

    /// How the kernels' directions are chosen.
    pub fn orientation(mut self, orientation: PhasorOrientation) -> Self {
        self.orientation = orientation;
        self
    }

    /// Mean impulses per kernel footprint, `[0.01, 200]`.
    pub fn impulses_per_kernel(mut self, impulses_per_kernel: f32) -> Self {
        self.impulses_per_kernel = impulses_per_kernel;
        self
    }

    /// The oscillation profile.
    pub fn profile(mut self, profile: Profile) -> Self {
        self.profile = profile;
        self
    }

    /// What is written: the profiled noise, its phase, intensity or Gabor noise.
    pub fn output(mut self, output: PhasorOutput) -> Self {
        self.output = output;
        self
    }

    /// The constant added (default: [`PhasorNoise::default_levels`]).
    pub fn mean(mut self, mean: f32) -> Self {
        self.mean = Some(mean);
        self
    }

    /// The factor applied to the output (default: [`PhasorNoise::default_levels`]).
    pub fn amplitude(mut self, amplitude: f32) -> Self {
        self.amplitude = Some(amplitude);
        self
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first field outside its
    /// range (`phasor.frequency.value`, `phasor.profile.square.duty.value`, …).
    pub fn build(self) -> Result<PhasorNoise, ModelError> {
        let levels = PhasorNoise::default_levels(self.output, &self.profile);
        let noise = PhasorNoise {
            seed: self.seed,
            dimensions: self.dimensions,
            bandwidth: self.bandwidth,
            frequency: self.frequency,
            orientation: self.orientation,
            impulses_per_kernel: self.impulses_per_kernel,
            profile: self.profile,
            output: self.output,
            mean: self.mean.unwrap_or(levels.mean),
            amplitude: self.amplitude.unwrap_or(levels.amplitude),
        };
        noise.validate()?;
        Ok(noise)
    }
}

impl From<PhasorNoise> for Model {
    fn from(noise: PhasorNoise) -> Self {
        Self::Phasor(noise)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn defaults_are_the_documented_constants() {
        let noise = PhasorNoise::builder().build().expect("defaults are valid");
        let expected = PhasorNoise {
            seed: 0,
            dimensions: 2,
            bandwidth: Field::constant(0.02),
            frequency: Field::constant(0.05),
            orientation: PhasorOrientation::Aligned {
                angle: Field::constant(0.0),
            },
            impulses_per_kernel: 32.0,
            profile: Profile::Sine,
            output: PhasorOutput::Profiled,
            mean: 0.5,
            amplitude: 0.5,
        };
        assert_eq!(noise, expected);
    }

    pub fn levels_show_every_output_in_the_unit_interval() {
        let levels = |output, profile: Profile| {
            let noise = PhasorNoise::builder()
                .output(output)
                .profile(profile)
                .build();
            let noise = noise.expect("valid");
            (noise.mean, noise.amplitude)
        };
        assert_eq!(
            levels(PhasorOutput::Profiled, Profile::square(0.3)),
            (0.0, 1.0)
        );
        assert_eq!(
            levels(PhasorOutput::Profiled, Profile::Triangle),
            (0.5, 0.5)
        );
        assert_eq!(levels(PhasorOutput::Phase, Profile::Sine), (0.5, 1.0));
        assert_eq!(
            levels(PhasorOutput::Intensity, Profile::Sine),
            (0.0, 1.0 / 6.0)
        );
        assert_eq!(
            levels(PhasorOutput::Gabor, Profile::square(0.3)),
            (0.5, 1.0 / 6.0)
        );
        let given = PhasorNoise::builder().mean(0.1).amplitude(2.0).build();
        let given = given.expect("valid");
        assert_eq!((given.mean, given.amplitude), (0.1, 2.0));
    }

    pub fn invalid_settings_name_the_field() {
        let cases = [
            (
                PhasorNoise::builder().frequency(0.9).build(),
                "phasor.frequency.value",
            ),
            (
                PhasorNoise::builder().bandwidth(0.0).build(),
                "phasor.bandwidth.value",
            ),
            (
                PhasorNoise::builder().dimensions(4).build(),
                "phasor.dimensions",
            ),
            (
                PhasorNoise::builder().profile(Profile::square(1.5)).build(),
                "phasor.profile.square.duty.value",
            ),
            (
                PhasorNoise::builder().impulses_per_kernel(500.0).build(),
                "phasor.impulses_per_kernel",
            ),
            (
                PhasorNoise::builder().angle(f32::NAN).build(),
                "phasor.orientation.aligned.angle.value",
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
