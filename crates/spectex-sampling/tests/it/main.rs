//! Integration tests of fitting on an exemplar.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod fit_gravel;
mod unit;
