//! The error type of spectex-spectrum: every variant names the parameter and its valid range.

/// Why a spectral analysis or a synthesis could not run. Each message reads as a sentence
/// naming the parameter, the value given and what is accepted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpectrumError {
    /// An image or an output size is smaller than the operation needs.
    #[error("{parameter} is {width}×{height} pixels; it must be at least {min_width}×{min_height}")]
    TooSmall {
        /// Which input or option.
        parameter: &'static str,
        /// Width given.
        width: usize,
        /// Height given.
        height: usize,
        /// Smallest width accepted.
        min_width: usize,
        /// Smallest height accepted.
        min_height: usize,
    },
    /// An image or an output size is larger than the documented limits.
    #[error(
        "{parameter} is {width}×{height} pixels; the limit is {max_side} pixels per side and \
         {max_pixels} pixels in all"
    )]
    TooLarge {
        /// Which input or option.
        parameter: &'static str,
        /// Width given.
        width: usize,
        /// Height given.
        height: usize,
        /// Largest side accepted.
        max_side: usize,
        /// Largest pixel count accepted.
        max_pixels: usize,
    },
    /// A value of an image is NaN or infinite.
    #[error(
        "{parameter} has a non-finite value ({value}) at channel {channel}, row {row}, column \
         {column}; every value must be finite"
    )]
    NonFinite {
        /// Which input.
        parameter: &'static str,
        /// The offending value.
        value: f64,
        /// Channel index.
        channel: usize,
        /// Row index.
        row: usize,
        /// Column index.
        column: usize,
    },
    /// A scalar option is outside its valid range.
    #[error("{parameter} = {value} is outside its valid range {range}")]
    OutOfRange {
        /// Which option.
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range, written as an interval.
        range: &'static str,
    },
    /// An image has a number of channels the operation does not handle.
    #[error("{parameter} has {channels} channels; between 1 and {max} are accepted")]
    Channels {
        /// Which input.
        parameter: &'static str,
        /// Channels given.
        channels: usize,
        /// Largest channel count accepted.
        max: usize,
    },
}
