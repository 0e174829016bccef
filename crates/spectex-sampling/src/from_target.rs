//! LRP noise from a spectral target with documented defaults, the route of `spectex noise
//! ring|lobe|band|fractal`: `LrpFromTarget::new(target).std_dev(0.1).seed(3).build()?`.

use spectex_model::{DEFAULT_MEAN, DEFAULT_SEED, DEFAULT_STD_DEV, LrpNoise, SpectralTarget};

use crate::SamplingError;
use crate::fit::{DEFAULT_TARGET_GRID, FitOptions, fit_target};
use crate::stratify::Partition;

/// Builds an [`LrpNoise`] whose power spectrum follows a [`SpectralTarget`]: the target sampled
/// on a grid and fitted by [`fit_target`], then given a mean. `build()` validates everything
/// first.
///
/// ```
/// use spectex_model::SpectralTarget;
/// use spectex_sampling::LrpFromTarget;
///
/// // Isotropic noise of one scale (Gilet et al. 2014, Fig. 10): power on a ring.
/// let ring = SpectralTarget::Ring { radius: 0.0625, width: 0.005 };
/// let noise = LrpFromTarget::new(ring).budget(6).seed(3).build()?;
/// assert_eq!((noise.budget(), noise.mean, noise.seed), (6, 0.5, 3));
/// # Ok::<(), spectex_sampling::SamplingError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct LrpFromTarget {
    target: SpectralTarget,
    budget: Option<u32>,
    strata: Option<u32>,
    partition: Option<Partition>,
    seed: u32,
    std_dev: f32,
    mean: f32,
    grid: usize,
}

impl LrpFromTarget {
    /// Cosines per lattice point (`J`) for a target of one scale or direction (ring, lobes,
    /// band, sums of them): few cosines already give its look (the paper's Fig. 10 uses 3).
    pub const DEFAULT_BUDGET: u32 = 10;
    /// Strata for such a target: one, its power being one bump.
    pub const DEFAULT_STRATA: u32 = 1;
    /// Cosines per lattice point for a 1/f^β fractal: its power spans decades of frequency.
    pub const FRACTAL_BUDGET: u32 = 48;
    /// Strata of a 1/f^β fractal, cut in equal spans of log power ([`Partition::LogPower`]):
    /// enough that each holds about one octave of frequencies (the CLI's `classic_fidelity`
    /// tests measure the radial slope this gives).
    pub const FRACTAL_STRATA: u32 = 12;
    /// Standard deviation of the noise around its mean.
    pub const DEFAULT_STD_DEV: f32 = DEFAULT_STD_DEV;
    /// The constant added.
    pub const DEFAULT_MEAN: f32 = DEFAULT_MEAN;
    /// Seed of the fit (k-means seeding) and of the model's random phases.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;

    /// LRP noise of `target`'s spectrum with every option at its default: for a
    /// [`SpectralTarget::Fractal`], [`Self::FRACTAL_BUDGET`] cosines in [`Self::FRACTAL_STRATA`]
    /// strata of equal log-power spans; for every other target [`Self::DEFAULT_BUDGET`] cosines
    /// in [`Self::DEFAULT_STRATA`] stratum of equal energy ([`Partition::EqualEnergy`]); the
    /// target sampled on a [`DEFAULT_TARGET_GRID`]² grid.
    pub fn new(target: SpectralTarget) -> Self {
        Self {
            target,
            budget: None,
            strata: None,
            partition: None,
            seed: Self::DEFAULT_SEED,
            std_dev: Self::DEFAULT_STD_DEV,
            mean: Self::DEFAULT_MEAN,
            grid: DEFAULT_TARGET_GRID,
        }
    }

    /// `J`, cosines per lattice point over all strata, `1..=1024`.
    pub fn budget(mut self, budget: u32) -> Self {
        self.budget = Some(budget);
        self
    }

    /// `L`, the number of strata, `1..=64` and at most the budget.
    pub fn strata(mut self, strata: u32) -> Self {
        self.strata = Some(strata);
        self
    }

    /// How the target's power range is cut into strata.
    pub fn partition(mut self, partition: Partition) -> Self {
        self.partition = Some(partition);
        self
    }

    /// The seed of the fit and of the model.
    pub fn seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// The standard deviation of the noise, `(0, 1e6]`.
    pub fn std_dev(mut self, std_dev: f32) -> Self {
        self.std_dev = std_dev;
        self
    }

    /// The constant added, `[−1e9, 1e9]`.
    pub fn mean(mut self, mean: f32) -> Self {
        self.mean = mean;
        self
    }

    /// Side of the grid the target is sampled on, a power of two in `8..=4096`.
    pub fn grid(mut self, grid: usize) -> Self {
        self.grid = grid;
        self
    }

    /// The options the fit runs with: those given, the rest at the target's defaults.
    #[must_use]
    pub fn options(&self) -> FitOptions {
        let fractal = matches!(self.target, SpectralTarget::Fractal { .. });
        let (budget, strata, partition) = if fractal {
            (
                Self::FRACTAL_BUDGET,
                Self::FRACTAL_STRATA,
                Partition::LogPower,
            )
        } else {
            (
                Self::DEFAULT_BUDGET,
                Self::DEFAULT_STRATA,
                Partition::EqualEnergy,
            )
        };
        FitOptions {
            budget: self.budget.unwrap_or(budget),
            strata: self.strata.unwrap_or(strata),
            seed: self.seed,
            partition: self.partition.unwrap_or(partition),
            ..FitOptions::default()
        }
    }

    /// The fitted noise, `mean + n` with `n` of variance `std_dev²`.
    ///
    /// # Errors
    /// [`SamplingError::OutOfRange`] naming `std_dev`, `mean`, `budget`, `strata` or `grid`,
    /// [`SamplingError::Target`] for an invalid target, or as [`fit_target`].
    pub fn build(self) -> Result<LrpNoise, SamplingError> {
        if !(self.std_dev.is_finite() && self.std_dev > 0.0 && self.std_dev <= 1e6) {
            return Err(SamplingError::OutOfRange {
                parameter: "std_dev",
                value: f64::from(self.std_dev),
                range: "(0, 1e6]",
            });
        }
        if !(self.mean.is_finite() && self.mean.abs() <= 1e9) {
            return Err(SamplingError::OutOfRange {
                parameter: "mean",
                value: f64::from(self.mean),
                range: "[-1e9, 1e9]",
            });
        }
        let variance = f64::from(self.std_dev).powi(2);
        let mut noise = fit_target(&self.target, variance, self.grid, &self.options())?;
        noise.mean = self.mean;
        noise.validate().map_err(SamplingError::Model)?;
        Ok(noise)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod tests {
    #![allow(
        clippy::unwrap_used,
        reason = "a test fails loudly on the first unexpected None or Err"
    )]

    use super::*;

    fn ring() -> SpectralTarget {
        SpectralTarget::Ring {
            radius: 0.0625,
            width: 0.005,
        }
    }

    pub fn defaults_are_the_documented_constants_and_fit_target_with_them() {
        let built = LrpFromTarget::new(ring()).build().unwrap();
        let options = FitOptions {
            budget: 10,
            strata: 1,
            seed: 0,
            partition: Partition::EqualEnergy,
            ..FitOptions::default()
        };
        // The standard deviation is an f32 (0.15 as the CLI's --contrast), squared in f64.
        let variance = f64::from(0.15f32).powi(2);
        let mut direct = fit_target(&ring(), variance, 256, &options).unwrap();
        direct.mean = 0.5;
        assert_eq!(built, direct);

        let fractal = SpectralTarget::Fractal {
            beta: 1.5,
            angle: 0.0,
            spread: None,
            min_frequency: 1.0 / 128.0,
        };
        let options = LrpFromTarget::new(fractal).options();
        assert_eq!(
            (options.budget, options.strata, options.partition),
            (48, 12, Partition::LogPower)
        );
    }

    pub fn given_options_replace_the_defaults() {
        let options = LrpFromTarget::new(ring())
            .budget(6)
            .strata(2)
            .partition(Partition::LogPower)
            .seed(9)
            .options();
        assert_eq!(
            (
                options.budget,
                options.strata,
                options.partition,
                options.seed
            ),
            (6, 2, Partition::LogPower, 9)
        );
        let noise = LrpFromTarget::new(ring()).budget(6).strata(2).mean(-1.0);
        let noise = noise.build().unwrap();
        assert_eq!(
            (noise.budget(), noise.strata.len(), noise.mean),
            (6, 2, -1.0)
        );
    }

    pub fn invalid_options_name_the_parameter() {
        let parameter = |b: LrpFromTarget| match b.build() {
            Err(SamplingError::OutOfRange { parameter, .. }) => parameter,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            parameter(LrpFromTarget::new(ring()).std_dev(0.0)),
            "std_dev"
        );
        assert_eq!(
            parameter(LrpFromTarget::new(ring()).std_dev(f32::NAN)),
            "std_dev"
        );
        assert_eq!(
            parameter(LrpFromTarget::new(ring()).mean(f32::INFINITY)),
            "mean"
        );
        assert_eq!(parameter(LrpFromTarget::new(ring()).budget(0)), "budget");
        assert_eq!(parameter(LrpFromTarget::new(ring()).grid(100)), "grid");
        let bad = SpectralTarget::Ring {
            radius: 0.9,
            width: 0.005,
        };
        assert!(matches!(
            LrpFromTarget::new(bad).build(),
            Err(SamplingError::Target(_))
        ));
        assert!(matches!(
            LrpFromTarget::new(ring()).budget(2).strata(3).build(),
            Err(SamplingError::StrataExceedBudget { .. })
        ));
    }
}
