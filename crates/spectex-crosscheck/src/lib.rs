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
