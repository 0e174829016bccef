//! Integration tests of spectex-crosscheck: the cross-check suite over `testdata/models/` and
//! the generators of its texture fixtures.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod common;
mod export;
mod islamic;
mod models;
mod phasor_fields;
mod simulations;
mod subdivision;
mod texture_fixtures;
mod unit;
