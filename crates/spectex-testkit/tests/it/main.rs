//! The kit's own tests, one binary: the short fixed-seed fuzz campaigns on the CPU (generated
//! models, mutated model files, limits), the invariance harness over every testdata model, and
//! proofs that each check can fail.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stdout,
    reason = "campaign summaries and per-model lines are the tests' report"
)]

mod fuzz_files;
mod fuzz_models;
mod invariance;
mod kinds;
mod limits;
mod runner;
