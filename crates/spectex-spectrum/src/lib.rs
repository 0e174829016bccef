//! Spectral analysis for spectex, on `ndarray` with `rustfft`.
//!
//! - [`Fft2`]: 2D FFTs whose plans and buffers are cached and reused.
//! - [`periodic_smooth`]: Moisan's periodic + smooth decomposition.
//! - [`welch_psd`], [`log_magnitude_spectrum`], [`radial_profile`], [`variance_spectrum`]:
//!   power-spectrum estimates with documented conventions (see the [`welch`] module).
//! - [`metrics`]: the spectral shape distance, moments and log–log slopes the fidelity tests
//!   and the reproduction report share.
//! - [`Rpn`]: Random Phase Noise and ADSN, at the sample's size or any larger one (spot
//!   extension), after Galerne, Gousseau & Morel (IPOL).
//!
//! Images are `ndarray` arrays of `f64`: one channel is an `Array2` indexed `[row, column]`, a
//! multi-channel image an `Array3` indexed `[channel, row, column]`.
//!
//! ```
//! use ndarray::Array3;
//! use spectex_spectrum::{Rpn, RpnOptions, NoiseKind};
//!
//! // A small grey "sample": stripes plus a ramp.
//! let sample = Array3::from_shape_fn((1, 64, 64), |(_, y, x)| ((x / 3) % 2) as f64 + 0.01 * y as f64);
//! let mut rpn = Rpn::new();
//! let texture = rpn
//!     .synthesize(sample.view(), &RpnOptions { size: Some((256, 128)), seed: 42, kind: NoiseKind::RandomPhase, ..Default::default() })
//!     .unwrap();
//! assert_eq!(texture.dim(), (1, 128, 256));
//! ```

mod error;
pub mod fft;
pub mod metrics;
pub mod periodic;
pub mod relief;
pub mod rpn;
pub mod welch;

pub use error::SpectrumError;
pub use fft::{Fft2, FftFloat, centered, signed_frequency};
pub use metrics::{
    excess_kurtosis, fraction_above_gaussian_quantile, gradient_magnitudes, log_log_fit, luminance,
    mean_variance, normalised_smoothed, ring_power_peak, shape_distance, standard_normal_cdf,
    standard_normal_quantile, variance_low_fraction, wasserstein1,
};
pub use periodic::{PeriodicSmooth, interior_laplacian, periodic_laplacian, periodic_smooth};
pub use rpn::{
    NoiseKind, Rpn, RpnOptions, extended_spot, random_phase_field, rpn, transition, validate_image,
};
pub use welch::{
    RadialBin, log_magnitude_spectrum, radial_profile, variance_spectrum, welch_block_size,
    welch_psd, welch_psd_with_block,
};
