//! The builder of [`Warp`], with the `spectex noise warp` defaults: any model displaced by
//! built-in zero-mean Perlin fBms, `Warp::of(base).strength(24.0).build()?`.

use crate::Model;
use crate::classic::ClassicNoise;
use crate::defaults::DEFAULT_SEED;
use crate::error::ModelError;
use crate::warp::Warp;

impl Warp {
    /// Pixels of displacement per unit of the displacement models.
    pub const DEFAULT_STRENGTH: f32 = 16.0;
    /// Seed of the built-in displacement along x (y uses every seed of x plus one).
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// Cell side of the built-in fBms (displacement and base), pixels.
    pub const DEFAULT_FBM_CELL_SIZE: f32 = 64.0;
    /// Octaves of the built-in fBms: 64 → 4-pixel cells.
    pub const DEFAULT_FBM_OCTAVES: u32 = 5;
    /// The built-in base's seed is the displacement's plus this, so the base does not
    /// correlate with its own displacement.
    pub const DEFAULT_BASE_SEED_OFFSET: u32 = 1_000;

    /// A warp of the built-in base, a Perlin fBm in `[0, 1]` ([`Self::DEFAULT_FBM_CELL_SIZE`],
    /// [`Self::DEFAULT_FBM_OCTAVES`]); give another with [`WarpBuilder::base`] or start from
    /// [`Warp::of`].
    pub fn builder() -> WarpBuilder {
        WarpBuilder {
            base: None,
            x: None,
            y: None,
            strength: Self::DEFAULT_STRENGTH,
            seed: Self::DEFAULT_SEED,
        }
    }

    /// A warp of `base` (any model: a texture, a 3D model on its plane `z`, another warp).
    ///
    /// ```
    /// use spectex_model::{ClassicNoise, Model, Warp, WaveletNoise};
    ///
    /// let marble = Warp::of(WaveletNoise::builder().build()?)
    ///     .by(ClassicNoise::fbm().mean(0.0).amplitude(1.0).build()?)
    ///     .strength(24.0)
    ///     .build()?;
    /// // y is displaced by x's model with every seed plus one.
    /// assert_eq!(*marble.y, marble.x.reseeded(1));
    /// let model = Model::from(marble);
    /// assert_eq!(model.kind(), "warp");
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn of(base: impl Into<Model>) -> WarpBuilder {
        Self::builder().base(base)
    }
}

/// `mean + amplitude·fBm`: the built-in Perlin fBm of [`Warp::DEFAULT_FBM_OCTAVES`] octaves on
/// [`Warp::DEFAULT_FBM_CELL_SIZE`]-pixel cells.
fn fbm(seed: u32, mean: f32, amplitude: f32) -> Result<Model, ModelError> {
    let noise = ClassicNoise::fbm()
        .cell_size(Warp::DEFAULT_FBM_CELL_SIZE)
        .octaves(Warp::DEFAULT_FBM_OCTAVES)
        .seed(seed)
        .mean(mean)
        .amplitude(amplitude)
        .build()?;
    Ok(noise.into())
}

/// Builds a [`Warp`]; start from [`Warp::of`] or [`Warp::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct WarpBuilder {
    base: Option<Model>,
    x: Option<Model>,
    y: Option<Model>,
    strength: f32,
    seed: u32,
}

impl WarpBuilder {
    /// The model evaluated at the displaced positions (default: the built-in fBm in `[0, 1]`,
    /// seed [`Warp::DEFAULT_BASE_SEED_OFFSET`] past [`Self::seed`]).
    pub fn base(mut self, base: impl Into<Model>) -> Self {
        self.base = Some(base.into());
        self
    }

    /// The displacement along x, before the strength: one value per pixel, ideally of mean 0
    /// (default: the built-in zero-mean fBm of amplitude 1 with [`Self::seed`]).
    pub fn by(mut self, x: impl Into<Model>) -> Self {
        self.x = Some(x.into());
        self
    }

    /// The displacement along y (default: x's model with every seed in it plus one,
    /// [`Model::reseeded`]).
    pub fn by_y(mut self, y: impl Into<Model>) -> Self {
        self.y = Some(y.into());
        self
    }

    /// Pixels of displacement per unit of the displacement models, `[−65536, 65536]`.
    pub fn strength(mut self, strength: f32) -> Self {
        self.strength = strength;
        self
    }

    /// The seed of the built-in displacement (and, plus
    /// [`Warp::DEFAULT_BASE_SEED_OFFSET`], of the built-in base).
    pub fn seed(mut self, seed: u32) -> Self {
        self.seed = seed;
        self
    }

    /// The validated warp.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first invalid field
    /// (`warp.strength`, `warp.x (values per pixel)` for a colour displacement, a nested
    /// model's `warp.base.classic.cell_size`, …).
    pub fn build(self) -> Result<Warp, ModelError> {
        let base = match self.base {
            Some(base) => base,
            None => fbm(
                self.seed.wrapping_add(Warp::DEFAULT_BASE_SEED_OFFSET),
                0.5,
                0.5,
            )?,
        };
        let x = match self.x {
            Some(x) => x,
            None => fbm(self.seed, 0.0, 1.0)?,
        };
        let y = match self.y {
            Some(y) => y,
            None => x.reseeded(1),
        };
        let warp = Warp {
            base: Box::new(base),
            x: Box::new(x),
            y: Box::new(y),
            strength: self.strength,
        };
        warp.validate()?;
        Ok(warp)
    }
}

impl From<Warp> for Model {
    fn from(warp: Warp) -> Self {
        Self::Warp(warp)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::classic::{Basis, Fractal, FractalKind};
    use crate::fixtures::constant;

    fn perlin_fbm(seed: u32, mean: f32, amplitude: f32) -> Model {
        Model::Classic(ClassicNoise {
            seed,
            dimensions: 2,
            cell_size: 64.0,
            basis: Basis::Gradient,
            fractal: Some(Fractal {
                kind: FractalKind::Fbm,
                octaves: 5,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude,
            mean,
        })
    }

    pub fn defaults_are_the_documented_constants() {
        let warp = Warp::builder().seed(7).build().expect("defaults are valid");
        assert_eq!(*warp.base, perlin_fbm(1_007, 0.5, 0.5));
        assert_eq!(*warp.x, perlin_fbm(7, 0.0, 1.0));
        assert_eq!(*warp.y, perlin_fbm(8, 0.0, 1.0));
        assert_eq!(warp.strength, 16.0);
        let plain = Warp::builder().build().expect("defaults are valid");
        assert_eq!(*plain.x, perlin_fbm(0, 0.0, 1.0));
    }

    pub fn given_models_are_kept() {
        let warp = Warp::of(constant(0.25))
            .by(constant(1.0))
            .by_y(constant(-1.0))
            .strength(-3.0)
            .build()
            .expect("valid");
        assert_eq!(
            (*warp.base, *warp.x, *warp.y, warp.strength),
            (constant(0.25), constant(1.0), constant(-1.0), -3.0)
        );
    }

    pub fn invalid_settings_name_the_field() {
        match Warp::builder().strength(f32::NAN).build() {
            Err(ModelError::OutOfRange { field, .. }) => assert_eq!(field, "warp.strength"),
            other => panic!("{other:?}"),
        }
        let mut bad = ClassicNoise::perlin().build().expect("valid");
        bad.cell_size = 0.0;
        match Warp::of(bad).build() {
            Err(ModelError::OutOfRange { field, .. }) => {
                assert_eq!(field, "warp.base.classic.cell_size");
            }
            other => panic!("{other:?}"),
        }
    }
}
