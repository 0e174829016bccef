//! Turns a target power spectrum into a procedural model: Local Random-Phase noise by example
//! (Gilet, Sauvage, Vanhoey, Dischler & Ghazanfarpour 2014, §4), and Gabor noise by example
//! (Galerne et al. 2012, [`gabor_fit`]).
//!
//! A power spectrum — measured from an image ([`fit_image`]), given as an array ([`fit_psd`]) or
//! a formula ([`fit_target`]) — becomes an [`LrpNoise`](spectex_model::LrpNoise) in these
//! steps, each a public function tested against a direct computation:
//!
//! 1. [`stratify::equal_energy_strata`] (§4.2): `L` strata of equal energy and homogeneous power.
//! 2. [`stratify::distribute_budget`] and [`stratify::window_width`] (§4.3): `J_S = J/L` cosines
//!    and the window width `Δ_S = T·√J_S/√(2|S|)` of each stratum.
//! 3. [`shrink::shrink_unit`] (§4.3): the radius `δ₀` holding 75% of a window's spectral energy,
//!    from the Hankel transform of the Kaiser–Bessel window; a stratum is shrunk by `δ₀/Δ_S`.
//! 4. [`erosion::erode`] (§4.3): morphological erosion on the periodic grid that never sweeps a
//!    stratum out.
//! 5. [`kmeans::sub_strata`] (§4.3): k-means with random seeding of the shrunk stratum's half
//!    plane into `J_S` sub-strata, whose frequencies become the model's tables.
//! 6. [`amplitude::amplitude`] (Eq. 3): `A_S` so that the noise's variance is the spectrum's.
//!
//! [`stratify()`] returns every intermediate result (the paper's Fig. 4) for reports and figures.
//! Conventions: a power spectrum is `T × T`, uncentred (zero frequency at `[0, 0]`, index
//! `[k, l]` ↔ `(f_y, f_x)` in signed cycles per pixel) and normalised so that `Σ P/T²` is the
//! variance, as [`spectex_spectrum::welch_psd`] returns it. Fitting is deterministic: the same
//! inputs give the same model for any thread count; its random choices (k-means seeding) come
//! from the randomness contract on layer [`kmeans::KMEANS_LAYER`].
//!
//! ```
//! use ndarray::Array2;
//! use spectex_sampling::{FitOptions, fit_image};
//!
//! // A small synthetic exemplar: two oriented waves and a ramp-free texture.
//! let image = Array2::from_shape_fn((64, 64), |(y, x)| {
//!     let (x, y) = (x as f64, y as f64);
//!     0.5 + 0.2 * (0.9 * x + 0.3 * y).sin() + 0.1 * (0.2 * x - 0.7 * y).cos()
//! });
//! let options = FitOptions { budget: 16, strata: 4, seed: 7, ..FitOptions::default() };
//! let model = fit_image(image.view(), &options).unwrap();
//! assert_eq!(model.budget(), 16); // Σ_S J_S = J
//! assert!((model.mean - 0.5).abs() < 0.01);
//! for stratum in &model.strata {
//!     assert!(stratum.sub_strata.iter().all(|table| !table.is_empty()));
//! }
//! // Same inputs, same model.
//! assert_eq!(model, fit_image(image.view(), &options).unwrap());
//! ```

pub mod amplitude;
pub mod erosion;
mod error;
mod fit;
mod from_target;
pub mod gabor_fit;
pub mod grid;
pub mod kmeans;
pub mod shrink;
pub mod spectrum_fit;
pub mod stratify;
pub mod texture;
pub mod tiling;

/// The unit tests' bodies, one module per source module (`pub mod tests` behind this feature),
/// run by `tests/it/unit.rs`: a unit-test harness would compile the crate a second time.
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod unit_tests {
    pub use crate::amplitude::tests as amplitude;
    pub use crate::erosion::tests as erosion;
    pub use crate::fit::tests as fit;
    pub use crate::from_target::tests as from_target;
    pub use crate::gabor_fit::tests as gabor_fit;
    pub use crate::grid::tests as grid;
    pub use crate::kmeans::tests as kmeans;
    pub use crate::shrink::tests as shrink;
    pub use crate::spectrum_fit::tests as spectrum_fit;
    pub use crate::stratify::tests as stratify;
    pub use crate::texture::tests as texture;
    pub use crate::tiling::tests as tiling;
}

pub use error::SamplingError;
pub use fit::{
    DEFAULT_TARGET_GRID, FitMethod, FitOptions, MAX_IMAGE_SIDE, MAX_TARGET_GRID, MIN_TARGET_GRID,
    Stratification, StratumPlan, exemplar_psd, exemplar_target, fit_image, fit_psd, fit_target,
    stratify,
};
pub use from_target::LrpFromTarget;
pub use gabor_fit::{GaborFit, GaborFitOptions, fit_gabor, fit_gabor_psd};
pub use stratify::Partition;
pub use texture::{TextureOptions, TextureReport, false_colour_fraction, fit_texture};
