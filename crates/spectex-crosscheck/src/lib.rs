//! Renders the same model windows through `spectex-cpu` and `spectex-gpu` and compares them:
//! max / mean absolute error, the 99.9th percentile of the error and the relative distance
//! between their Welch spectra (from `spectex-spectrum`), each against a tolerance derived from
//! the model ([`tolerance`]), writing actual and difference images and a report on failure.
//!
//! The two evaluators are independent implementations of one contract (DESIGN invariant 1):
//! their integer draws are bit-identical, so every difference is float rounding, bounded by
//! the constants of [`tolerance`].
//!
//! ```no_run
//! use spectex_crosscheck::{check_model, standard_windows};
//! use spectex_gpu::GpuContext;
//!
//! let context = GpuContext::new()?;
//! let text = std::fs::read_to_string("testdata/models/gabor-isotropic.json")?;
//! let model = spectex_model::from_json(&text)?;
//! for (window, outcome) in check_model(&context, "gabor-isotropic", &model, &standard_windows())? {
//!     println!("{window}: {}", outcome.summary());
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod compare;
pub mod phasor;
mod report;
pub mod tolerance;

pub use compare::{
    CaseWindow, Comparison, EXPECTED_FAILURES, Outcome, Verdict, check_model, check_model_at_z,
    compare, expected_failure, judge, standard_windows,
};
pub use report::{REPORT_DIR, write_failure_report, write_failure_report_in};
pub use tolerance::Tolerance;

/// Why a cross-check could not run (a failed comparison is an [`Outcome`], not an error).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CrosscheckError {
    /// The CPU evaluator refused the model or window.
    #[error("CPU evaluator: {0}")]
    Cpu(#[from] spectex_cpu::CpuError),
    /// The GPU evaluator refused the model or window, or the device failed.
    #[error("GPU evaluator: {0}")]
    Gpu(#[from] spectex_gpu::GpuError),
    /// The model has no derivable tolerance (a kind this version of the crate does not know).
    #[error("no cross-check tolerance is defined for this kind of model; add one in tolerance.rs")]
    Unsupported,
    /// The evaluators disagree on the values per pixel, or the tolerance does not match them.
    #[error(
        "values per pixel differ: CPU {cpu}, GPU {gpu}, tolerances {tolerances}; both evaluators \
         must interleave the same components"
    )]
    Channels {
        /// The CPU evaluator's `output_channels`.
        cpu: usize,
        /// The GPU evaluator's `output_channels`.
        gpu: usize,
        /// Tolerances derived for the model.
        tolerances: usize,
    },
    /// Writing a failure report failed.
    #[error("writing the report {path}: {source}")]
    Report {
        /// The file.
        path: String,
        /// The I/O or encoding error.
        source: std::io::Error,
    },
}
