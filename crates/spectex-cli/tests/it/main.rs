//! Integration tests of the `spectex` command (run end to end) and the fidelity measurements
//! on renders of models the CLI builds.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod bad_inputs;
mod classic_fidelity;
mod cli;
mod common;
mod docs;
mod export;
mod fidelity;
mod fidelity_dirt;
mod fuzz_images;
mod phasor_fidelity;
mod signal;
mod simulate;
mod stream;
mod texture;
mod unit;
mod view;
mod warp_reseed;
mod wavelet;
