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

// ---------------------------------------------------------------------------------------------
// Host transcription of the CPU's f32 functions (crates/spectex-cpu/src/math.rs; this crate may not
// depend on spectex-cpu): plain `*` and `+`, never fused on the host, in the CPU's order. Used to
// count how many device values are bit-identical to what the CPU computes.

/// `spectex_cpu::math::COS_TURNS`.
pub const COS_TURNS: [f32; 5] = [1.0, -19.739_182, 64.935_22, -85.254_01, 56.340_71];

/// `spectex_cpu::math::fract_turns`.
pub fn cpu_fract_turns(t: f32) -> f32 {
    const MAGIC: f32 = 12_582_912.0;
    t - ((t + MAGIC) - MAGIC)
}

/// `spectex_cpu::math::cos_turns`.
pub fn cpu_cos_turns(t: f32) -> f32 {
    let a = cpu_fract_turns(t).abs();
    let far = a > 0.25;
    let b = if far { 0.5 - a } else { a };
    let x = b * b;
    let mut p = COS_TURNS[4];
    for k in (0..4).rev() {
        p = p * x + COS_TURNS[k];
    }
    if far { -p } else { p }
}

/// `spectex_cpu::math::KB_POLY`.
pub const KB_POLY: [f32; 8] = [
    0.017_600_192,
    0.098_341_09,
    0.212_476_86,
    0.290_033_43,
    0.155_061_08,
    0.205_698_98,
    -0.027_654_441,
    0.048_442_75,
];

/// `spectex_cpu::math::kaiser_bessel_r2`.
pub fn cpu_kaiser_bessel_r2(r2: f32) -> f32 {
    let inside = 1.0 - r2 * (1.0 / 2.25);
    let u = inside.max(0.0);
    let mut p = KB_POLY[7];
    for m in (0..7).rev() {
        p = p * u + KB_POLY[m];
    }
    let w = u * u.sqrt() * p;
    if inside > 0.0 { w } else { 0.0 }
}

/// `spectex_cpu::math::exp_poly`.
pub fn cpu_exp_poly(z: f32) -> f32 {
    const MAGIC: f32 = 12_582_912.0;
    let taylor = [
        1.0f32,
        1.0,
        0.5,
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 120.0,
        1.0 / 720.0,
        1.0 / 5040.0,
    ];
    let z = z.clamp(-87.0, 88.0);
    let shifted = z * std::f32::consts::LOG2_E + MAGIC;
    let n = shifted - MAGIC;
    let n_int = shifted.to_bits().wrapping_sub(MAGIC.to_bits()) as i32;
    let f = (z - n * 0.693_145_75) - n * 1.428_606_8e-6;
    let mut p = taylor[7];
    for k in (0..7).rev() {
        p = p * f + taylor[k];
    }
    p * f32::from_bits(((n_int + 127) as u32) << 23)
}
