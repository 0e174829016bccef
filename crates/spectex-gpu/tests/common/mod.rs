//! Helpers shared by the GPU tests: one place that decides whether a test without an adapter
//! skips (loudly) or fails (`SPECTEX_REQUIRE_GPU=1`), and bit-comparison messages.

#![allow(dead_code, reason = "each test binary uses a different subset")]

use spectex_gpu::GpuContext;

/// Environment variable that turns a missing adapter from a skip into a failure.
pub const REQUIRE_GPU_ENV: &str = "SPECTEX_REQUIRE_GPU";

/// A device for `test`, or `None` (after printing why) when there is no adapter and
/// `SPECTEX_REQUIRE_GPU` is not `1`.
///
/// # Panics
/// When no adapter exists and `SPECTEX_REQUIRE_GPU=1`; the message lists the adapters found.
pub fn gpu_or_skip(test: &str) -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(context) => {
            eprintln!("{test}: running on {}", context.adapter_name());
            Some(context)
        }
        Err(e) if std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| v == "1") => {
            panic!("{test}: {REQUIRE_GPU_ENV}=1 but no GPU: {e}")
        }
        Err(e) => {
            eprintln!("SKIPPED {test}: {e}");
            None
        }
    }
}

/// Index of the first pair of values whose bits differ.
pub fn first_bit_difference(a: &[f32], b: &[f32]) -> Option<usize> {
    assert_eq!(a.len(), b.len(), "lengths differ");
    a.iter()
        .zip(b)
        .position(|(x, y)| x.to_bits() != y.to_bits())
}

// The CPU's f32 functions (defined once in spectex-model, which this crate may depend on): used to
// count how many device values are bit-identical to what the CPU computes.
#[allow(unused_imports, reason = "each test binary uses a different subset")]
pub use spectex_model::math::{
    ATAN_TURNS, COS_TURNS, KB_POLY, atan2_turns as cpu_atan2_turns, cos_turns as cpu_cos_turns,
    exp_poly as cpu_exp_poly, fract_turns as cpu_fract_turns,
    kaiser_bessel_r2 as cpu_kaiser_bessel_r2,
};
