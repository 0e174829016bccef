//! Builders of [`ClassicNoise`] with documented defaults, read as sentences:
//! `ClassicNoise::fbm().octaves(6).seed(3).build()?`.
//!
//! A single basis ([`ClassicNoise::perlin`], …) builds a [`ClassicNoiseBuilder`]; a fractal sum
//! ([`ClassicNoise::fbm`], …, or [`ClassicNoiseBuilder::fractal`]) a [`FractalNoiseBuilder`],
//! which alone has octaves, lacunarity and gain, so a setting that a noise would not use cannot
//! be written. `build()` validates ([`ClassicNoise::validate`]); after it, evaluation cannot fail
//! on the model's parameters. The defaults are the `spectex noise perlin|simplex|value|fbm|worley`
//! flags' defaults.

use crate::Model;
use crate::classic::{Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric, Worley};
use crate::defaults::{DEFAULT_SEED, Levels};
use crate::error::ModelError;

impl ClassicNoise {
    /// Seed unless [`ClassicNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// A plane (2) unless [`ClassicNoiseBuilder::dimensions`] is given.
    pub const DEFAULT_DIMENSIONS: u32 = 2;
    /// Side of a lattice cell of the first octave, pixels.
    pub const DEFAULT_CELL_SIZE: f32 = 32.0;
    /// Octaves of a fractal sum: with the default cell and lacunarity the sixth octave's cell
    /// is 1 pixel (32/2⁵), the finest that validation accepts.
    pub const DEFAULT_OCTAVES: u32 = 6;
    /// Frequency ratio between octaves.
    pub const DEFAULT_LACUNARITY: f32 = 2.0;
    /// Amplitude ratio between octaves (`λ^{−H}` with `H = 1`: the classic fBm).
    pub const DEFAULT_GAIN: f32 = 0.5;
    /// Musgrave's `offset` of the ridged multifractal (his examples' value).
    pub const DEFAULT_RIDGE_OFFSET: f32 = 1.0;
    /// Musgrave's weighting `gain` of the ridged multifractal (his examples' value).
    pub const DEFAULT_RIDGE_WEIGHT_GAIN: f32 = 2.0;

    /// Improved Perlin gradient noise, one octave.
    ///
    /// ```
    /// use spectex_model::ClassicNoise;
    ///
    /// let noise = ClassicNoise::perlin().cell_size(16.0).seed(7).build()?;
    /// assert_eq!((noise.cell_size, noise.seed, noise.octaves()), (16.0, 7, 1));
    /// // Mapped from about [−1, 1] into [0, 1] unless a mean or amplitude is given.
    /// assert_eq!((noise.mean, noise.amplitude), (0.5, 0.5));
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn perlin() -> ClassicNoiseBuilder {
        Self::builder(Basis::Gradient)
    }

    /// Simplex noise, one octave.
    pub fn simplex() -> ClassicNoiseBuilder {
        Self::builder(Basis::Simplex)
    }

    /// Value noise, one octave.
    pub fn value() -> ClassicNoiseBuilder {
        Self::builder(Basis::Value)
    }

    /// Kensler, Knoll & Shirley's better gradient noise, one octave (standard deviation ¼,
    /// mapped into `[0, 1]` by `0.5 + 0.5·v` like the other lattice noises).
    pub fn kensler() -> ClassicNoiseBuilder {
        Self::builder(Basis::Kensler)
    }

    /// Worley cellular noise `F₁` (Euclidean, one point per cell: [`Worley::default`]), one
    /// octave; [`ClassicNoiseBuilder::worley`] sets another combination.
    ///
    /// ```
    /// use spectex_model::ClassicNoise;
    /// use spectex_model::classic::{Metric, Worley};
    ///
    /// // F₂ − F₁ under the Manhattan distance: cell borders.
    /// let cells = ClassicNoise::worley()
    ///     .worley(Worley { metric: Metric::Manhattan, coefficients: [-1.0, 1.0, 0.0, 0.0], ..Worley::default() })
    ///     .build()?;
    /// assert_eq!(cells.mean, 0.0);
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn worley() -> ClassicNoiseBuilder {
        Self::builder(Basis::Worley(Worley::default()))
    }

    /// Fractional Brownian motion of Perlin noise, [`Self::DEFAULT_OCTAVES`] octaves
    /// (`.basis(…)` sums another basis).
    ///
    /// ```
    /// use spectex_model::{ClassicNoise, Model};
    ///
    /// let noise = ClassicNoise::fbm().octaves(4).seed(3).build()?;
    /// assert_eq!(noise.octaves(), 4);
    /// let model: Model = noise.into(); // what the evaluators take
    /// assert_eq!(model.kind(), "classic");
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn fbm() -> FractalNoiseBuilder {
        Self::perlin().fractal(FractalKind::Fbm)
    }

    /// Turbulence (`Σ gain^o |n_o|`) of Perlin noise.
    pub fn turbulence() -> FractalNoiseBuilder {
        Self::perlin().fractal(FractalKind::Turbulence)
    }

    /// Musgrave's ridged multifractal of Perlin noise, with his example's offset and weighting
    /// gain ([`Self::DEFAULT_RIDGE_OFFSET`], [`Self::DEFAULT_RIDGE_WEIGHT_GAIN`]).
    pub fn ridged() -> FractalNoiseBuilder {
        Self::perlin().fractal(FractalKind::Ridged {
            offset: Self::DEFAULT_RIDGE_OFFSET,
            weight_gain: Self::DEFAULT_RIDGE_WEIGHT_GAIN,
        })
    }

    /// One octave of `basis`, every other field at its default.
    pub fn builder(basis: Basis) -> ClassicNoiseBuilder {
        ClassicNoiseBuilder {
            seed: Self::DEFAULT_SEED,
            dimensions: Self::DEFAULT_DIMENSIONS,
            cell_size: Self::DEFAULT_CELL_SIZE,
            basis,
            mean: None,
            amplitude: None,
        }
    }

    /// The mean and amplitude a builder uses unless given: they map the noise's usual range
    /// into `[0, 1]`. Lattice noises (gradient, simplex, value) lie in about `[−1, 1]`, and so
    /// does their fBm with gain ½: `0.5 + 0.5·v`. Worley's `F₁` and turbulence are non-negative
    /// and of order 1: `v` as it is. An fBm of Worley noise (`Σ ½^o F₁`, below 2) and a ridged
    /// sum with offset 1 and gain ½ (below 2): `0.5·v`.
    #[must_use]
    pub fn default_levels(basis: &Basis, sum: Option<FractalKind>) -> Levels {
        let worley = matches!(basis, Basis::Worley(_));
        let (mean, amplitude) = match sum {
            None if worley => (0.0, 1.0),
            None => (0.5, 0.5),
            Some(FractalKind::Fbm) if worley => (0.0, 0.5),
            Some(FractalKind::Fbm) => (0.5, 0.5),
            Some(FractalKind::Turbulence) => (0.0, 1.0),
            Some(FractalKind::Ridged { .. }) => (0.0, 0.5),
        };
        Levels { mean, amplitude }
    }
}

impl Worley {
    /// The distance of [`Worley::default`].
    pub const DEFAULT_METRIC: Metric = Metric::Euclidean;
    /// `F₁` alone: the distance to the nearest feature point.
    pub const DEFAULT_COEFFICIENTS: [f32; 4] = [1.0, 0.0, 0.0, 0.0];
    /// Feature points per cell of [`Worley::default`]: one (the jittered grid of most
    /// libraries).
    pub const DEFAULT_POINTS_PER_CELL: u32 = 1;
}

impl Default for Worley {
    /// `F₁` under the Euclidean distance, one feature point per cell (the `spectex noise
    /// worley` defaults).
    fn default() -> Self {
        Self {
            metric: Self::DEFAULT_METRIC,
            coefficients: Self::DEFAULT_COEFFICIENTS,
            points: FeaturePoints::Fixed(Self::DEFAULT_POINTS_PER_CELL),
        }
    }
}

/// Builds a single-octave [`ClassicNoise`]; start from [`ClassicNoise::perlin`],
/// [`ClassicNoise::simplex`], [`ClassicNoise::value`], [`ClassicNoise::worley`] or
/// [`ClassicNoise::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct ClassicNoiseBuilder {
    seed: u32,
    dimensions: u32,
    cell_size: f32,
    basis: Basis,
    mean: Option<f32>,
    amplitude: Option<f32>,
}

/// Builds a fractal sum over octaves of a basis; start from [`ClassicNoise::fbm`],
/// [`ClassicNoise::turbulence`], [`ClassicNoise::ridged`] or [`ClassicNoiseBuilder::fractal`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct FractalNoiseBuilder {
    noise: ClassicNoiseBuilder,
    fractal: Fractal,
}

/// The settings both builders share, written once: `$($inner)*` reaches the
/// [`ClassicNoiseBuilder`] inside `self`.
macro_rules! shared_setters {
    ($($inner:tt)*) => {
        /// The seed of the randomness contract.
        pub fn seed(mut self, seed: u32) -> Self {
            self$($inner)*.seed = seed;
            self
        }

        /// 2 (a plane) or 3 (a volume, rendered on a plane `z`).
        pub fn dimensions(mut self, dimensions: u32) -> Self {
            self$($inner)*.dimensions = dimensions;
            self
        }

        /// Side of a lattice cell (of the first octave), pixels: at least 1.
        pub fn cell_size(mut self, cell_size: f32) -> Self {
            self$($inner)*.cell_size = cell_size;
            self
        }

        /// The basis function.
        pub fn basis(mut self, basis: Basis) -> Self {
            self$($inner)*.basis = basis;
            self
        }

        /// A Worley basis with these metric, coefficients and points.
        pub fn worley(mut self, worley: Worley) -> Self {
            self$($inner)*.basis = Basis::Worley(worley);
            self
        }

        /// The constant added after the factor (default: [`ClassicNoise::default_levels`]).
        pub fn mean(mut self, mean: f32) -> Self {
            self$($inner)*.mean = Some(mean);
            self
        }

        /// The factor applied to the (fractal) value (default:
        /// [`ClassicNoise::default_levels`]).
        pub fn amplitude(mut self, amplitude: f32) -> Self {
            self$($inner)*.amplitude = Some(amplitude);
            self
        }
    };
}

impl ClassicNoiseBuilder {
    shared_setters!();

    /// Sums the basis over octaves as `sum` says, with [`ClassicNoise::DEFAULT_OCTAVES`],
    /// [`ClassicNoise::DEFAULT_LACUNARITY`] and [`ClassicNoise::DEFAULT_GAIN`].
    pub fn fractal(self, sum: FractalKind) -> FractalNoiseBuilder {
        FractalNoiseBuilder {
            noise: self,
            fractal: Fractal {
                kind: sum,
                octaves: ClassicNoise::DEFAULT_OCTAVES,
                lacunarity: ClassicNoise::DEFAULT_LACUNARITY,
                gain: ClassicNoise::DEFAULT_GAIN,
            },
        }
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the first field outside its range
    /// (`classic.cell_size`, …).
    pub fn build(self) -> Result<ClassicNoise, ModelError> {
        self.finish(None)
    }

    fn finish(self, fractal: Option<Fractal>) -> Result<ClassicNoise, ModelError> {
        let levels = ClassicNoise::default_levels(&self.basis, fractal.as_ref().map(|f| f.kind));
        let noise = ClassicNoise {
            seed: self.seed,
            dimensions: self.dimensions,
            cell_size: self.cell_size,
            basis: self.basis,
            fractal,
            amplitude: self.amplitude.unwrap_or(levels.amplitude),
            mean: self.mean.unwrap_or(levels.mean),
        };
        noise.validate()?;
        Ok(noise)
    }
}

impl FractalNoiseBuilder {
    shared_setters!(.noise);

    /// How octaves are combined (fBm, turbulence, ridged).
    pub fn sum(mut self, sum: FractalKind) -> Self {
        self.fractal.kind = sum;
        self
    }

    /// Number of octaves, 1 to 16, keeping the finest cell (`cell_size / lacunarity^(octaves −
    /// 1)`) at least 1 pixel.
    pub fn octaves(mut self, octaves: u32) -> Self {
        self.fractal.octaves = octaves;
        self
    }

    /// Frequency ratio `λ` between octaves, 1 to 16.
    pub fn lacunarity(mut self, lacunarity: f32) -> Self {
        self.fractal.lacunarity = lacunarity;
        self
    }

    /// Amplitude ratio between octaves, 0 to 2.
    pub fn gain(mut self, gain: f32) -> Self {
        self.fractal.gain = gain;
        self
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the first field outside its range
    /// (`classic.fractal.octaves`, …).
    pub fn build(self) -> Result<ClassicNoise, ModelError> {
        self.noise.finish(Some(self.fractal))
    }
}

impl From<ClassicNoise> for Model {
    fn from(noise: ClassicNoise) -> Self {
        Self::Classic(noise)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn defaults_are_the_documented_constants() {
        let fbm = ClassicNoise::fbm().build().expect("defaults are valid");
        let expected = ClassicNoise {
            seed: 0,
            dimensions: 2,
            cell_size: 32.0,
            basis: Basis::Gradient,
            fractal: Some(Fractal {
                kind: FractalKind::Fbm,
                octaves: 6,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude: 0.5,
            mean: 0.5,
        };
        assert_eq!(fbm, expected);
        let ridged = ClassicNoise::ridged().build().expect("defaults are valid");
        assert_eq!(
            ridged.fractal.map(|f| f.kind),
            Some(FractalKind::Ridged {
                offset: 1.0,
                weight_gain: 2.0
            })
        );
        assert_eq!((ridged.mean, ridged.amplitude), (0.0, 0.5));
        let worley = ClassicNoise::worley().build().expect("defaults are valid");
        assert_eq!(
            worley.basis,
            Basis::Worley(Worley {
                metric: Metric::Euclidean,
                coefficients: [1.0, 0.0, 0.0, 0.0],
                points: FeaturePoints::Fixed(1),
            })
        );
        assert_eq!(
            (worley.mean, worley.amplitude, worley.fractal),
            (0.0, 1.0, None)
        );
        for (builder, basis) in [
            (ClassicNoise::perlin(), Basis::Gradient),
            (ClassicNoise::simplex(), Basis::Simplex),
            (ClassicNoise::value(), Basis::Value),
        ] {
            let noise = builder.build().expect("defaults are valid");
            assert_eq!((noise.basis, noise.fractal), (basis, None));
            assert_eq!((noise.mean, noise.amplitude), (0.5, 0.5));
        }
    }

    pub fn levels_follow_basis_and_sum_unless_given() {
        let turbulence = ClassicNoise::turbulence().basis(Basis::Simplex).build();
        let turbulence = turbulence.expect("valid");
        assert_eq!((turbulence.mean, turbulence.amplitude), (0.0, 1.0));
        let worley_fbm = ClassicNoise::fbm().worley(Worley::default()).build();
        let worley_fbm = worley_fbm.expect("valid");
        assert_eq!((worley_fbm.mean, worley_fbm.amplitude), (0.0, 0.5));
        let given = ClassicNoise::fbm().mean(0.25).amplitude(-2.0).build();
        let given = given.expect("valid");
        assert_eq!((given.mean, given.amplitude), (0.25, -2.0));
    }

    pub fn setters_reach_every_field_in_any_order() {
        let a = ClassicNoise::fbm()
            .octaves(4)
            .seed(3)
            .dimensions(3)
            .cell_size(64.0)
            .lacunarity(2.5)
            .gain(0.6)
            .sum(FractalKind::Turbulence)
            .build()
            .expect("valid");
        let b = ClassicNoise::perlin()
            .cell_size(64.0)
            .dimensions(3)
            .seed(3)
            .fractal(FractalKind::Turbulence)
            .gain(0.6)
            .lacunarity(2.5)
            .octaves(4)
            .build()
            .expect("valid");
        assert_eq!(a, b);
        assert_eq!((a.seed, a.dimensions, a.cell_size), (3, 3, 64.0));
        let f = a.fractal.expect("a fractal sum");
        assert_eq!((f.octaves, f.lacunarity, f.gain), (4, 2.5, 0.6));
    }

    pub fn invalid_settings_name_the_field() {
        let cases = [
            (
                ClassicNoise::perlin().cell_size(0.5).build(),
                "classic.cell_size",
            ),
            (
                ClassicNoise::value().dimensions(4).build(),
                "classic.dimensions",
            ),
            (
                ClassicNoise::fbm().octaves(0).build(),
                "classic.fractal.octaves",
            ),
            // 32 px / 2^6 = 0.5 px: finer than a pixel.
            (
                ClassicNoise::fbm().octaves(7).build(),
                "classic.fractal.octaves",
            ),
            (
                ClassicNoise::fbm().gain(f32::NAN).build(),
                "classic.fractal.gain",
            ),
            (
                ClassicNoise::simplex().mean(f32::INFINITY).build(),
                "classic.mean",
            ),
            (
                ClassicNoise::worley()
                    .worley(Worley {
                        points: FeaturePoints::Fixed(17),
                        ..Worley::default()
                    })
                    .build(),
                "classic.basis.worley.points.fixed",
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
