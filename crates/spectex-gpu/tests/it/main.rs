//! Integration tests of the wgpu evaluator: shaders, the shared contract and every model kind.
//! Without an adapter they skip with a printed reason, unless `SPECTEX_REQUIRE_GPU=1`.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod api;
mod classic;
mod common;
mod contract;
mod export;
mod gabor;
mod kit;
mod lrp;
mod matrix;
mod periodic;
mod phasor;
mod render;
mod shaders;
mod subdivision;
mod texture;
mod unit;
mod warp;
mod wavelet;
