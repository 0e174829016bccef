//! Integration tests of the CPU evaluator, one module per model kind.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod classic;
mod fast_paths;
mod filter;
mod gabor;
mod kensler;
mod lrp;
mod matrix;
mod periodic;
mod phasor;
mod subdivision;
mod unit;
mod warp;
mod wavelet;
