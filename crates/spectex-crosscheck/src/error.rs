//! [`CrosscheckError`]: why a cross-check could not run.

/// Why a cross-check could not run (a failed comparison is an [`Outcome`](crate::Outcome), not an error).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CrosscheckError {
    /// The CPU evaluator refused the model or window.
    #[error("CPU evaluator: {0}")]
    Cpu(#[from] spectex_cpu::CpuError),
    /// The GPU evaluator refused the model or window, or the device failed.
    #[error("GPU evaluator: {0}")]
    Gpu(#[from] spectex_gpu::GpuError),
    /// No tolerance is derived for the model: a warp whose base, x or y has no
    /// [`Regularity`](crate::tolerance::Regularity) (phasor noise's phase-based outputs).
    #[error(
        "no cross-check tolerance is derived for this {kind} model: a warp needs its base, x and \
         y to have a bounded slope, which phasor noise's phase and profiled outputs do not"
    )]
    Unsupported {
        /// The model's kind ([`spectex_model::Model::kind`]).
        kind: &'static str,
    },
    /// A simulation could not run on the CPU (a parameter out of range).
    #[error(transparent)]
    Simulation(#[from] spectex_simulate::SimulateError),
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
