//! Grey-level defaults shared by the builders of every kind: a model built with its defaults is
//! centred on [`DEFAULT_MEAN`] with standard deviation [`DEFAULT_STD_DEV`], so it renders into
//! `[0, 1]` (an 8-bit PNG) with almost nothing clipped, as the `spectex` command's do.

/// The constant a builder adds by default: the middle of `[0, 1]`.
pub const DEFAULT_MEAN: f32 = 0.5;

/// The standard deviation a builder gives a noise by default (where the kind's parameters set
/// it: LRP from a spectral target, Gabor and wavelet noise): `0.5 ± 0.15` puts 99.9% of a
/// Gaussian's values (±3.3σ) inside `[0, 1]`.
pub const DEFAULT_STD_DEV: f32 = 0.15;

/// The seed a builder uses unless told otherwise.
pub const DEFAULT_SEED: u32 = 0;

/// A constant and a factor: a model writes `mean + amplitude·v` for its raw value `v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Levels {
    /// The constant added.
    pub mean: f32,
    /// The factor.
    pub amplitude: f32,
}
