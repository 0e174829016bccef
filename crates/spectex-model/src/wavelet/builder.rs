//! The builder of [`WaveletNoise`], with the `spectex noise wavelet` defaults:
//! `WaveletNoise::builder().bands(vec![1.0, 0.5, 0.25]).build()?`.

use crate::Model;
use crate::defaults::{DEFAULT_MEAN, DEFAULT_SEED, DEFAULT_STD_DEV};
use crate::error::ModelError;
use crate::wavelet::WaveletNoise;

impl WaveletNoise {
    /// Seed unless [`WaveletNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// A plane (2) unless [`WaveletNoiseBuilder::dimensions`] is given.
    pub const DEFAULT_DIMENSIONS: u32 = 2;
    /// Tile side of a 2D noise, samples: 128² values, so repetition is rare at the default
    /// cell (a 2048-pixel period).
    pub const DEFAULT_TILE_SIZE_2D: u32 = 128;
    /// Tile side of a 3D noise, samples: 32³ values.
    pub const DEFAULT_TILE_SIZE_3D: u32 = 32;
    /// Pixels per tile sample of the first band.
    pub const DEFAULT_CELL_SIZE: f32 = 16.0;
    /// One band of weight 1.
    pub const DEFAULT_BANDS: [f32; 1] = [1.0];
    /// Standard deviation of the sum.
    pub const DEFAULT_AMPLITUDE: f32 = DEFAULT_STD_DEV;
    /// The constant added.
    pub const DEFAULT_MEAN: f32 = DEFAULT_MEAN;

    /// The default tile side for `dimensions`: [`Self::DEFAULT_TILE_SIZE_3D`] for 3, else
    /// [`Self::DEFAULT_TILE_SIZE_2D`].
    #[must_use]
    pub fn default_tile_size(dimensions: u32) -> u32 {
        if dimensions == 3 {
            Self::DEFAULT_TILE_SIZE_3D
        } else {
            Self::DEFAULT_TILE_SIZE_2D
        }
    }

    /// A wavelet noise with every field at its default; set what differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::WaveletNoise;
    ///
    /// let noise = WaveletNoise::builder().dimensions(3).bands(vec![1.0, 0.5]).build()?;
    /// assert_eq!(noise.tile_size, WaveletNoise::DEFAULT_TILE_SIZE_3D);
    /// assert_eq!(noise.bands().len(), 2);
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> WaveletNoiseBuilder {
        WaveletNoiseBuilder {
            seed: Self::DEFAULT_SEED,
            dimensions: Self::DEFAULT_DIMENSIONS,
            tile_size: None,
            cell_size: Self::DEFAULT_CELL_SIZE,
            bands: Self::DEFAULT_BANDS.to_vec(),
            amplitude: Self::DEFAULT_AMPLITUDE,
            mean: Self::DEFAULT_MEAN,
        }
    }
}

/// Builds a [`WaveletNoise`]; start from [`WaveletNoise::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct WaveletNoiseBuilder {
    seed: u32,
    dimensions: u32,
    tile_size: Option<u32>,
    cell_size: f32,
    bands: Vec<f32>,
    amplitude: f32,
    mean: f32,
}

impl WaveletNoiseBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// 2 (a plane) or 3 (a volume, rendered on a plane `z`).
    pub fn dimensions(mut self, dimensions: u32) -> Self {
        self.dimensions = dimensions;
        self
    }

    /// Side of the periodic tile, samples: even, 16 to 256 in 2D, 16 to 64 in 3D (default:
    /// [`WaveletNoise::default_tile_size`] of the dimensions).
    pub fn tile_size(mut self, tile_size: u32) -> Self {
        self.tile_size = Some(tile_size);
        self
    }

    /// Pixels per tile sample of the first (coarsest) band, at least 1.
    pub fn cell_size(mut self, cell_size: f32) -> Self {
        self.cell_size = cell_size;
        self
    }

    /// Weight of each band, 1 to 16 of them; band `b` has `2^b` times the first one's
    /// frequency.
    pub fn bands(mut self, bands: Vec<f32>) -> Self {
        self.bands = bands;
        self
    }

    /// The standard deviation of the sum (the bands are normalised by `√Σw²`).
    pub fn amplitude(mut self, amplitude: f32) -> Self {
        self.amplitude = amplitude;
        self
    }

    /// The constant added.
    pub fn mean(mut self, mean: f32) -> Self {
        self.mean = mean;
        self
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first field outside its
    /// range (`wavelet.tile_size`, `wavelet.bands`, …).
    pub fn build(self) -> Result<WaveletNoise, ModelError> {
        let noise = WaveletNoise {
            seed: self.seed,
            dimensions: self.dimensions,
            tile_size: self
                .tile_size
                .unwrap_or_else(|| WaveletNoise::default_tile_size(self.dimensions)),
            cell_size: self.cell_size,
            bands: self.bands,
            amplitude: self.amplitude,
            mean: self.mean,
        };
        noise.validate()?;
        Ok(noise)
    }
}

impl From<WaveletNoise> for Model {
    fn from(noise: WaveletNoise) -> Self {
        Self::Wavelet(noise)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn defaults_are_the_documented_constants() {
        let noise = WaveletNoise::builder().build().expect("defaults are valid");
        let expected = WaveletNoise {
            seed: 0,
            dimensions: 2,
            tile_size: 128,
            cell_size: 16.0,
            bands: vec![1.0],
            amplitude: 0.15,
            mean: 0.5,
        };
        assert_eq!(noise, expected);
        let volume = WaveletNoise::builder().dimensions(3).build();
        assert_eq!(volume.expect("valid").tile_size, 32);
        let given = WaveletNoise::builder().dimensions(3).tile_size(16).build();
        assert_eq!(given.expect("valid").tile_size, 16);
    }

    pub fn invalid_settings_name_the_field() {
        let out_of_range = [
            (
                WaveletNoise::builder().tile_size(17).build(),
                "wavelet.tile_size",
            ),
            // A 2D tile side is too large for a volume.
            (
                WaveletNoise::builder().tile_size(128).dimensions(3).build(),
                "wavelet.tile_size",
            ),
            (
                WaveletNoise::builder().cell_size(0.5).build(),
                "wavelet.cell_size",
            ),
            (
                WaveletNoise::builder().bands(vec![0.0, 0.0]).build(),
                "wavelet.bands",
            ),
            (
                WaveletNoise::builder().mean(f32::NAN).build(),
                "wavelet.mean",
            ),
        ];
        for (result, field) in out_of_range {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
        match WaveletNoise::builder().bands(Vec::new()).build() {
            Err(ModelError::Length { field, len, .. }) => {
                assert_eq!((field.as_str(), len), ("wavelet.bands", 0));
            }
            other => panic!("{other:?}"),
        }
    }
}
