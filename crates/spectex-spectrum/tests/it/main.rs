//! Integration tests of Random Phase Noise and the spectral analyses behind it.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod rpn_properties;
mod unit;
