//! What the criterion benches share: the size of a case's window.
//!
//! `cargo bench` runs a bench binary with `--bench`; `cargo test --bench NAME` (CI's test step)
//! runs it without, and criterion then runs every case once, untimed, as a test. That pass only
//! has to show that each case runs, so a window shrinks to [`TEST_SIDE`]: a 2048² render of a
//! reference library compiled unoptimised (the test profile's dependencies) took most of a
//! minute there, for nothing measured.

/// The side of a bench window when the bench runs once as a test.
pub const TEST_SIDE: usize = 64;

/// Whether this process is a bench binary that `cargo bench` started (`--bench` among its
/// arguments), not a test pass of it.
#[must_use]
pub fn benchmarking() -> bool {
    std::env::args().any(|arg| arg == "--bench")
}

/// `side` when benchmarking, else at most [`TEST_SIDE`].
#[must_use]
pub fn side(side: usize) -> usize {
    if benchmarking() {
        side
    } else {
        side.min(TEST_SIDE)
    }
}
