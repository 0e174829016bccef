//! Renders the same model windows through `spectex-cpu` and `spectex-gpu` and compares them:
//! max / mean absolute error, the 99.9th percentile of the error and the relative distance
//! between their Welch spectra (from `spectex-spectrum`), each against a tolerance derived from
//! the model ([`tolerance`]), writing actual and difference images and a report on failure.
//! A kind whose outputs those measures cannot judge (phasor noise: phases wrap, profiles jump)
//! brings its own criterion.
//!
//! The two evaluators are independent implementations of one contract (invariant 1 of `docs/ARCHITECTURE.md`):
//! their integer draws are bit-identical, so every difference is float rounding, bounded by
//! the constants of [`tolerance`].
//!
//! Each model kind is judged through its [`CheckKind`] (its tolerance per output component, its
//! regularity under a warp, the plane it is checked on, its own criterion if it has one),
//! implemented in the kind's own module of [`tolerance`]; [`tolerance::check_kind`] is the one
//! dispatch over kinds. A new kind adds its file there and one `pub mod` line in
//! `tolerance/mod.rs`, and the compiler points at that dispatch until it does.
//!
//! The modules form a DAG; each uses only those listed before it:
//! `error` ([`CrosscheckError`]) and [`tolerance`] (bounds and criteria, no rendering; its
//! kind modules use only its shared items and, for composite kinds, other kinds' modules) ←
//! `compare` (measuring two renders, verdicts) ← `report` (failure images and reports) ←
//! `check` ([`check_model`]: renders, judges by the kind's criterion, reports); `simulation`
//! (whole-grid simulations, [`simulation::check_simulation`]) uses only `error`.
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

mod check;
mod compare;
mod error;
mod report;
pub mod simulation;
pub mod tolerance;

pub use check::{check_model, check_model_at_z, check_model_with_period};
pub use compare::{
    CaseWindow, Comparison, EXPECTED_FAILURES, Outcome, Verdict, compare, expected_failure, judge,
    judge_by_reasons, standard_windows,
};
pub use error::CrosscheckError;
pub use report::{REPORT_DIR, write_failure_report, write_failure_report_in};
pub use tolerance::{CheckKind, Tolerance};

/// The unit tests' bodies, one module per source module (`pub mod tests` behind this feature),
/// run by `tests/it/unit.rs`: a unit-test harness would compile the crate a second time.
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod unit_tests {
    pub use crate::compare::tests as compare;
    pub use crate::report::tests as report;
    pub use crate::tolerance::classic::tests as tolerance_classic;
    pub use crate::tolerance::combine::tests as tolerance_combine;
    pub use crate::tolerance::gabor::tests as tolerance_gabor;
    pub use crate::tolerance::islamic::tests as tolerance_islamic;
    pub use crate::tolerance::lrp::tests as tolerance_lrp;
    pub use crate::tolerance::phasor::tests as tolerance_phasor;
    pub use crate::tolerance::subdivision::tests as tolerance_subdivision;
    pub use crate::tolerance::tests as tolerance;
    pub use crate::tolerance::texton::tests as tolerance_texton;
    pub use crate::tolerance::texture::tests as tolerance_texture;
    pub use crate::tolerance::voronoi::tests as tolerance_voronoi;
    pub use crate::tolerance::warp::tests as tolerance_warp;
    pub use crate::tolerance::wavelet::tests as tolerance_wavelet;
}
