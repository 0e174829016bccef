//! The builder of [`LrpNoise`] from strata written by hand. An LRP noise usually comes from a
//! spectrum instead: `spectex_sampling::LrpFromTarget` builds one from a [`SpectralTarget`]
//! (ring, lobes, band, 1/f^β fractal, …) and `spectex_sampling::fit_image` from an example
//! image; both return an `LrpNoise`.
//!
//! [`SpectralTarget`]: crate::SpectralTarget

use crate::Model;
use crate::defaults::{DEFAULT_MEAN, DEFAULT_SEED};
use crate::error::ModelError;
use crate::lrp::{LrpNoise, Stratum};

impl LrpNoise {
    /// Seed unless [`LrpNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// The constant added unless [`LrpNoiseBuilder::mean`] is given.
    pub const DEFAULT_MEAN: f32 = DEFAULT_MEAN;

    /// An LRP noise of these strata (more with [`LrpNoiseBuilder::stratum`]).
    ///
    /// ```
    /// use spectex_model::{LrpNoise, Stratum};
    ///
    /// // Four cosines per lattice point, each drawn from a small table of frequencies near
    /// // 1/8 cycle per pixel, on a 24-pixel lattice.
    /// let ring = Stratum {
    ///     window_width: 24.0,
    ///     amplitude: 0.05,
    ///     sub_strata: vec![vec![[0.125, 0.0], [0.0, 0.125], [0.088, 0.088], [0.088, -0.088]]; 4],
    /// };
    /// let noise = LrpNoise::from_strata(vec![ring]).seed(5).build()?;
    /// assert_eq!((noise.budget(), noise.mean), (4, 0.5));
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn from_strata(strata: Vec<Stratum>) -> LrpNoiseBuilder {
        LrpNoiseBuilder {
            seed: Self::DEFAULT_SEED,
            mean: Self::DEFAULT_MEAN,
            strata,
        }
    }
}

/// Builds an [`LrpNoise`]; start from [`LrpNoise::from_strata`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct LrpNoiseBuilder {
    seed: u32,
    mean: f32,
    strata: Vec<Stratum>,
}

impl LrpNoiseBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// The constant added to the noise.
    pub fn mean(mut self, mean: f32) -> Self {
        self.mean = mean;
        self
    }

    /// One more stratum (the strata's spectra should be disjoint).
    pub fn stratum(mut self, stratum: Stratum) -> Self {
        self.strata.push(stratum);
        self
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first field outside its
    /// range (`lrp.strata` for none or more than 64, `lrp.strata[0].window_width`, …).
    pub fn build(self) -> Result<LrpNoise, ModelError> {
        let noise = LrpNoise {
            seed: self.seed,
            mean: self.mean,
            strata: self.strata,
        };
        noise.validate()?;
        Ok(noise)
    }
}

impl From<LrpNoise> for Model {
    fn from(noise: LrpNoise) -> Self {
        Self::Lrp(noise)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    fn stratum(window_width: f32) -> Stratum {
        Stratum {
            window_width,
            amplitude: 0.1,
            sub_strata: vec![vec![[0.1, 0.0]]; 2],
        }
    }

    pub fn defaults_and_strata_in_order() {
        let noise = LrpNoise::from_strata(vec![stratum(8.0)])
            .stratum(stratum(16.0))
            .build()
            .expect("valid");
        assert_eq!((noise.seed, noise.mean), (0, 0.5));
        let widths: Vec<f32> = noise.strata.iter().map(|s| s.window_width).collect();
        assert_eq!(widths, [8.0, 16.0]);
        assert_eq!(Model::from(noise.clone()), Model::Lrp(noise));
    }

    pub fn invalid_settings_name_the_field() {
        match LrpNoise::from_strata(Vec::new()).build() {
            Err(ModelError::Length { field, len, .. }) => {
                assert_eq!((field.as_str(), len), ("lrp.strata", 0))
            }
            other => panic!("{other:?}"),
        }
        match LrpNoise::from_strata(vec![stratum(0.25)]).build() {
            Err(ModelError::OutOfRange { field, .. }) => {
                assert_eq!(field, "lrp.strata[0].window_width");
            }
            other => panic!("{other:?}"),
        }
        match LrpNoise::from_strata(vec![stratum(8.0)])
            .mean(f32::NAN)
            .build()
        {
            Err(ModelError::OutOfRange { field, .. }) => assert_eq!(field, "lrp.mean"),
            other => panic!("{other:?}"),
        }
    }
}
