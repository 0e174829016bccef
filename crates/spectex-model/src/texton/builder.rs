//! The builder of [`TextonNoise`], with the `spectex noise texton` defaults:
//! `TextonNoise::builder().spot(Spot::Gaussian).poisson(2.0).build()?`.

use crate::defaults::DEFAULT_SEED;
use crate::error::ModelError;
use crate::texton::{Combine, Placement, Spot, TextonNoise};

impl TextonNoise {
    /// Seed unless [`TextonNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// `C`, the cell side, pixels: one texton per 32 px cell.
    pub const DEFAULT_CELL_SIZE: f32 = 32.0;
    /// Grid jitter, cells: the survey's random grid (a texton anywhere in its cell).
    pub const DEFAULT_JITTER: f32 = 1.0;
    /// The ellipsoid of the survey's Eq. (6).
    pub const DEFAULT_SPOT: Spot = Spot::Ellipsoid;
    /// `(a, b)`, the semi-axes, pixels: elongated 2:1, and within one cell at the largest
    /// default scale (14·1.25 = 17.5 < 32), so a pixel visits 3 × 3 cells.
    pub const DEFAULT_RADII: [f32; 2] = [14.0, 7.0];
    /// Rotation range, turns: every direction.
    pub const DEFAULT_ROTATION: [f32; 2] = [0.0, 1.0];
    /// Scale range: ±25% around the radii.
    pub const DEFAULT_SCALE: [f32; 2] = [0.75, 1.25];
    /// Weight range: heights from half to full.
    pub const DEFAULT_INTENSITY: [f32; 2] = [0.5, 1.0];
    /// The addition rule.
    pub const DEFAULT_COMBINE: Combine = Combine::Sum;
    /// The constant added: none (textons add up from a canvas of 0).
    pub const DEFAULT_MEAN: f32 = 0.0;

    /// A texton noise with every field at its default ([`Self::default`]); set what differs,
    /// then `build()`.
    ///
    /// ```
    /// use spectex_model::TextonNoise;
    /// use spectex_model::texton::{Placement, Spot};
    ///
    /// let t = TextonNoise::builder().spot(Spot::Gaussian).poisson(2.0).build()?;
    /// assert_eq!(t.placement, Placement::Poisson { density: 2.0 });
    /// // Radii 14 px × scale 1.25 stay within one cell of 32 px: 3 × 3 cells of 2 textons.
    /// assert!((t.textons_per_pixel() - 18.0).abs() < 1e-12);
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> TextonNoiseBuilder {
        TextonNoiseBuilder {
            model: Self::default(),
        }
    }
}

impl Default for TextonNoise {
    /// Every field at its `DEFAULT_` constant: randomly rotated ellipsoids of semi-axes 14 × 7
    /// px on a fully jittered 32 px grid, scales 0.75–1.25, weights 0.5–1, added. Valid as it
    /// is.
    fn default() -> Self {
        Self {
            seed: Self::DEFAULT_SEED,
            cell_size: Self::DEFAULT_CELL_SIZE,
            placement: Placement::Grid {
                jitter: Self::DEFAULT_JITTER,
            },
            spot: Self::DEFAULT_SPOT,
            radii: Self::DEFAULT_RADII,
            rotation: Self::DEFAULT_ROTATION,
            scale: Self::DEFAULT_SCALE,
            intensity: Self::DEFAULT_INTENSITY,
            combine: Self::DEFAULT_COMBINE,
            mean: Self::DEFAULT_MEAN,
        }
    }
}

/// Builds a [`TextonNoise`]; start from [`TextonNoise::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct TextonNoiseBuilder {
    model: TextonNoise,
}

impl TextonNoiseBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.model.seed = seed;
        self
    }

    /// `C`, the cell side, `[1, 4096]` pixels.
    pub fn cell_size(mut self, cell_size: f32) -> Self {
        self.model.cell_size = cell_size;
        self
    }

    /// One texton per cell, moved by up to `jitter`, `[0, 1]` cells (0: a regular grid).
    pub fn jitter(mut self, jitter: f32) -> Self {
        self.model.placement = Placement::Grid { jitter };
        self
    }

    /// A Poisson number of textons per cell of this mean, `(0, 8]`, instead of a grid.
    pub fn poisson(mut self, density: f32) -> Self {
        self.model.placement = Placement::Poisson { density };
        self
    }

    /// Where textons go (a grid or Poisson points).
    pub fn placement(mut self, placement: Placement) -> Self {
        self.model.placement = placement;
        self
    }

    /// What is placed: an ellipsoid, a Gaussian spot or a grey image (at most 1024 per side,
    /// finite values).
    pub fn spot(mut self, spot: Spot) -> Self {
        self.model.spot = spot;
        self
    }

    /// `(a, b)`, the semi-axes before scaling, `[0.001, 65536]` pixels each, with
    /// `max(radii)·max(scale) ≤ 3·cell_size`.
    pub fn radii(mut self, radii: [f32; 2]) -> Self {
        self.model.radii = radii;
        self
    }

    /// Range of the rotation, turns, each in `[-1e4, 1e4]`.
    pub fn rotation(mut self, rotation: [f32; 2]) -> Self {
        self.model.rotation = rotation;
        self
    }

    /// Range of the scale, each in `[0.001, 16]`.
    pub fn scale(mut self, scale: [f32; 2]) -> Self {
        self.model.scale = scale;
        self
    }

    /// Range of the weight (height), each finite, `|w| ≤ 1e9`.
    pub fn intensity(mut self, intensity: [f32; 2]) -> Self {
        self.model.intensity = intensity;
        self
    }

    /// The addition or maximum rule.
    pub fn combine(mut self, combine: Combine) -> Self {
        self.model.combine = combine;
        self
    }

    /// The constant added, finite, `|mean| ≤ 1e9`.
    pub fn mean(mut self, mean: f32) -> Self {
        self.model.mean = mean;
        self
    }

    /// The validated noise.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first field outside its
    /// range (`texton.cell_size`, `texton.radii`, …).
    pub fn build(self) -> Result<TextonNoise, ModelError> {
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
        let t = TextonNoise::builder().build().expect("defaults are valid");
        let expected = TextonNoise {
            seed: 0,
            cell_size: 32.0,
            placement: Placement::Grid { jitter: 1.0 },
            spot: Spot::Ellipsoid,
            radii: [14.0, 7.0],
            rotation: [0.0, 1.0],
            scale: [0.75, 1.25],
            intensity: [0.5, 1.0],
            combine: Combine::Sum,
            mean: 0.0,
        };
        assert_eq!(t, expected);
    }

    pub fn invalid_settings_name_the_field() {
        let b = TextonNoise::builder;
        let cases = [
            (b().cell_size(0.5).build(), "texton.cell_size"),
            (b().jitter(1.5).build(), "texton.placement.grid.jitter"),
            (b().poisson(0.0).build(), "texton.placement.poisson.density"),
            (b().radii([200.0, 7.0]).build(), "texton.radii"),
            (b().rotation([0.0, 2e4]).build(), "texton.rotation[1]"),
            (b().scale([0.0, 1.0]).build(), "texton.scale[0]"),
            (
                b().intensity([f32::NAN, 1.0]).build(),
                "texton.intensity[0]",
            ),
            (b().mean(f32::INFINITY).build(), "texton.mean"),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
