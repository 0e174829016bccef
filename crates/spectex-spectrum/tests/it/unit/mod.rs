//! The crate's unit tests, through its public modules: here rather than in a unit-test harness
//! of the library, which would compile the whole library a second time (at the test profile's
//! opt-level 2). A module per source module.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

mod fft;
mod metrics;
mod periodic;
mod relief;
mod rpn;
mod welch;
