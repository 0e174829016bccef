//! The error type of spectex-sampling: every variant names the parameter, the value and what is
//! accepted.

use spectex_model::ModelError;
use spectex_spectrum::SpectrumError;

/// Why a model could not be fitted. Each message reads as a sentence naming the parameter, the
/// value given and the valid range.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SamplingError {
    /// A scalar option or argument is NaN, infinite or outside its range.
    #[error("{parameter} = {value} is outside its valid range {range}")]
    OutOfRange {
        /// Which option or argument (`budget`, `strata`, `coverage`, `variance`, `grid`, …).
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range, in words.
        range: &'static str,
    },
    /// More strata were asked for than there are cosines to give them (`J_S ≥ 1` for each).
    #[error(
        "strata = {strata} exceeds budget = {budget}; every stratum needs at least one cosine, \
         so strata must be in 1..=budget"
    )]
    StrataExceedBudget {
        /// `L` given.
        strata: u32,
        /// `J` given.
        budget: u32,
    },
    /// A power spectrum is not square, or its side is outside the accepted range.
    #[error(
        "{parameter} is {height}×{width}; it must be square with a side in {min_side}..={max_side}"
    )]
    Shape {
        /// Which input.
        parameter: &'static str,
        /// Rows given.
        height: usize,
        /// Columns given.
        width: usize,
        /// Smallest side accepted.
        min_side: usize,
        /// Largest side accepted.
        max_side: usize,
    },
    /// A value of a power spectrum or an image is NaN or infinite.
    #[error(
        "{parameter} has a non-finite value ({value}) at row {row}, column {column}; every value \
         must be finite"
    )]
    NonFinite {
        /// Which input.
        parameter: &'static str,
        /// The offending value.
        value: f64,
        /// Row index.
        row: usize,
        /// Column index.
        column: usize,
    },
    /// A power spectrum has a negative value.
    #[error(
        "{parameter} has a negative value ({value}) at row {row}, column {column}; a power \
         spectrum must be ≥ 0 everywhere"
    )]
    Negative {
        /// Which input.
        parameter: &'static str,
        /// The offending value.
        value: f64,
        /// Row index.
        row: usize,
        /// Column index.
        column: usize,
    },
    /// A power spectrum has no energy outside the zero frequency: there is nothing to fit.
    #[error(
        "{parameter} has no energy outside the zero frequency; it must have a positive value at \
         some non-zero frequency (a constant image or an empty target cannot be fitted)"
    )]
    NoEnergy {
        /// Which input.
        parameter: &'static str,
    },
    /// The spectral target failed its own validation.
    #[error("invalid spectral target: {0}")]
    Target(#[source] ModelError),
    /// The fitted model is outside the ranges a model file accepts (for instance an amplitude
    /// above 1e9, from a spectrum of enormous energy).
    #[error("the fitted model is out of range: {0}; rescale the input")]
    Model(#[source] ModelError),
    /// A fit method name that is not one of `spectrum`, `paper`.
    #[error(
        "fit method `{name}` is unknown; valid: spectrum (the default), paper (Gilet et al. 2014 as printed)"
    )]
    UnknownFitMethod {
        /// The name given.
        name: String,
    },
    /// The power spectrum of an image could not be computed.
    #[error(transparent)]
    Spectrum(#[from] SpectrumError),
}
