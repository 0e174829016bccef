//! Helpers shared by the GPU tests: one place that decides whether a test without an adapter
//! skips (loudly) or fails (`SPECTEX_REQUIRE_GPU=1`), and bit-comparison messages.

use spectex_gpu::GpuContext;
use spectex_model::LrpNoise;
use spectex_model::random::{Prng, cell_hash};

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
pub use spectex_model::math::{
    ATAN_TURNS, COS_TURNS, KB_POLY, cos_turns as cpu_cos_turns, exp_poly as cpu_exp_poly,
    fract_turns as cpu_fract_turns, kaiser_bessel_r2 as cpu_kaiser_bessel_r2,
};

/// The CPU's f32 evaluation of one LRP pixel (crates/spectex-cpu/src/lrp.rs), transcribed: same
/// offsets, same order of every operation. Lattice points outside the support add `+0` there and
/// are skipped here.
pub fn lrp_f32(m: &LrpNoise, x: f64, y: f64) -> f32 {
    let mut out = 0.0f32;
    for (s, st) in m.strata.iter().enumerate() {
        let delta = f64::from(st.window_width);
        let inv_delta2 = (1.0 / (delta * delta)) as f32;
        let (cx, cy) = ((x / delta).floor() as i64, (y / delta).floor() as i64);
        let mut acc_out = 0.0f32;
        for ly in cy - 2..=cy + 2 {
            let dy = (y - ly as f64 * delta) as f32;
            let dy2 = dy * dy;
            if dy2 * inv_delta2 >= 2.25 {
                continue;
            }
            for lx in cx - 2..=cx + 2 {
                let dx = (x - lx as f64 * delta) as f32;
                let r2 = (dx * dx + dy2) * inv_delta2;
                if r2 >= 2.25 {
                    continue;
                }
                let w = cpu_kaiser_bessel_r2(r2);
                let mut prng = Prng::new(cell_hash(lx as i32, ly as i32, s as u32, m.seed));
                let mut acc = 0.0f32;
                for table in &st.sub_strata {
                    let f = table[(prng.next_u32() % table.len() as u32) as usize];
                    let phase = prng.next_f32();
                    let c = f[1] * dy + phase;
                    acc += cpu_cos_turns(f[0] * dx + c);
                }
                acc_out += w * acc;
            }
        }
        out += st.amplitude * acc_out;
    }
    out + m.mean
}
