//! The builder of [`StochasticSubdivision`], with the `spectex noise subdivision` defaults:
//! `StochasticSubdivision::builder().levels(5).hurst(0.8).build()?`.

use crate::defaults::{DEFAULT_MEAN, DEFAULT_SEED};
use crate::error::ModelError;
use crate::subdivision::{Stencil, StochasticSubdivision};

impl StochasticSubdivision {
    /// Seed unless [`StochasticSubdivisionBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// `C`, the coarse lattice side, pixels: with [`Self::DEFAULT_LEVELS`] the finest lattice
    /// side is 1 pixel (128/2⁷).
    pub const DEFAULT_CELL_SIZE: f32 = 128.0;
    /// `L`, the subdivision levels: down to 1-pixel spacing at the default cell.
    pub const DEFAULT_LEVELS: u32 = 7;
    /// `H = ½`: Brownian roughness (Fournier et al.'s fBm with independent increments).
    pub const DEFAULT_HURST: f32 = 0.5;
    /// `a`, the standard deviation of the coarse values: at `H = ½` the finer levels add about
    /// as much variance again, so the texture's standard deviation is near 0.14, close to the
    /// shared [`crate::DEFAULT_STD_DEV`].
    pub const DEFAULT_AMPLITUDE: f32 = 0.1;
    /// The constant added.
    pub const DEFAULT_MEAN: f32 = DEFAULT_MEAN;
    /// Fournier et al.'s midpoint rule.
    pub const DEFAULT_STENCIL: Stencil = Stencil::Midpoint;

    /// A midpoint-displacement texture with every field at its default (the `DEFAULT_`
    /// constants): seed 0, cells of 128 pixels, 7 levels (finest side 1 pixel), `H = 0.5`
    /// (Brownian), amplitude 0.1 around 0.5. Valid as it is.
    #[must_use]
    pub fn midpoint() -> Self {
        Self {
            seed: Self::DEFAULT_SEED,
            cell_size: Self::DEFAULT_CELL_SIZE,
            levels: Self::DEFAULT_LEVELS,
            hurst: Self::DEFAULT_HURST,
            amplitude: Self::DEFAULT_AMPLITUDE,
            mean: Self::DEFAULT_MEAN,
            stencil: Self::DEFAULT_STENCIL,
        }
    }

    /// A stochastic subdivision with every field at its default ([`Self::midpoint`]); set
    /// what differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::StochasticSubdivision;
    /// use spectex_model::subdivision::Stencil;
    ///
    /// let s = StochasticSubdivision::builder().stencil(Stencil::Cubic).levels(5).build()?;
    /// assert_eq!((s.stencil, s.levels, s.cell_size), (Stencil::Cubic, 5, 128.0));
    /// // Level ℓ's displacements have standard deviation a·2^(−Hℓ): halved per level at H = 1.
    /// let rough = StochasticSubdivision::builder().hurst(1.0).build()?;
    /// assert_eq!(rough.level_scales()[1] * 2.0, rough.level_scales()[0]);
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> StochasticSubdivisionBuilder {
        StochasticSubdivisionBuilder {
            model: Self::midpoint(),
        }
    }
}

/// Builds a [`StochasticSubdivision`]; start from [`StochasticSubdivision::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct StochasticSubdivisionBuilder {
    model: StochasticSubdivision,
}

impl StochasticSubdivisionBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.model.seed = seed;
        self
    }

    /// `C`, the coarse lattice side, `[1, 4096]` pixels.
    pub fn cell_size(mut self, cell_size: f32) -> Self {
        self.model.cell_size = cell_size;
        self
    }

    /// `L`, the subdivision levels, `0..=16`: the finest lattice side is `C/2^L`.
    pub fn levels(mut self, levels: u32) -> Self {
        self.model.levels = levels;
        self
    }

    /// `H`, the roughness exponent, `[0, 1]`: level `ℓ`'s displacements have standard deviation
    /// `amplitude·2^(−Hℓ)` (small: rough, large: smooth).
    pub fn hurst(mut self, hurst: f32) -> Self {
        self.model.hurst = hurst;
        self
    }

    /// `a`, the standard deviation of the coarse (level 0) values, finite, `|a| ≤ 1e9`.
    pub fn amplitude(mut self, amplitude: f32) -> Self {
        self.model.amplitude = amplitude;
        self
    }

    /// The constant added, finite, `|mean| ≤ 1e9`.
    pub fn mean(mut self, mean: f32) -> Self {
        self.model.mean = mean;
        self
    }

    /// The interpolation rule.
    pub fn stencil(mut self, stencil: Stencil) -> Self {
        self.model.stencil = stencil;
        self
    }

    /// The validated texture.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the first field outside its range
    /// (`subdivision.cell_size`, …).
    pub fn build(self) -> Result<StochasticSubdivision, ModelError> {
        self.model.validate()?;
        Ok(self.model)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn defaults_are_the_documented_constants() {
        let s = StochasticSubdivision::builder()
            .build()
            .expect("defaults are valid");
        let expected = StochasticSubdivision {
            seed: 0,
            cell_size: 128.0,
            levels: 7,
            hurst: 0.5,
            amplitude: 0.1,
            mean: 0.5,
            stencil: Stencil::Midpoint,
        };
        assert_eq!(s, expected);
        assert_eq!(StochasticSubdivision::midpoint(), expected);
    }

    pub fn invalid_settings_name_the_field() {
        let b = StochasticSubdivision::builder;
        let cases = [
            (b().cell_size(0.5).build(), "subdivision.cell_size"),
            (b().levels(17).build(), "subdivision.levels"),
            (b().hurst(-0.1).build(), "subdivision.hurst"),
            (b().amplitude(f32::NAN).build(), "subdivision.amplitude"),
            (b().mean(f32::INFINITY).build(), "subdivision.mean"),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
