//! The WGSL twin of the randomness contract against `spectex_model::random`, on the device: the
//! integer functions must match bit for bit; the float functions of `common.wgsl` are compared
//! with f64 (within the tolerances below) and with a host transcription of the CPU's f32 code
//! (reporting how many values are bit-identical — WGSL cannot forbid fused multiply-adds).
//!
//! Run with `--nocapture` to see the measured errors and bit-identity counts.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::{cpu_cos_turns, cpu_exp_poly, cpu_fract_turns, cpu_kaiser_bessel_r2};

use spectex_gpu::{GpuContext, wgpu, wgsl_source};
use spectex_model::random::{
    Prng, cell_hash, cell_hash_in_row, hash, layer_key, lcg_step, permute, row_key, unit_f32,
};

/// Runs entry point `entry` of `probe.wgsl` with `input` bound at `bindings.0` and an output of
/// `output_words` words at `bindings.1`; one invocation per element of `input` (of `stride`
/// words each).
fn run_probe(
    context: &GpuContext,
    entry: &str,
    bindings: (u32, u32),
    input: &[u32],
    stride: usize,
    output_words: usize,
) -> Vec<u32> {
    use wgpu::util::DeviceExt;
    let device = context.device();
    let source = wgsl_source("probe").unwrap();
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("probe"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    let bytes: Vec<u8> = input.iter().flat_map(|w| w.to_le_bytes()).collect();
    let input_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("probe input"),
        contents: &bytes,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = 4 * output_words as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe output"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("probe"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: bindings.0,
                resource: input_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: bindings.1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        let invocations = input.len() / stride;
        pass.dispatch_workgroups(invocations.div_ceil(64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, size);
    context.queue().submit([encoder.finish()]);
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.unwrap());
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let words = slice
        .get_mapped_range()
        .unwrap()
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    readback.unmap();
    words
}

/// Records `(a, b, c, d)`: edge values, then a stream of the contract's own PRNG (with small
/// layers, as models use them, and some arbitrary ones).
fn integer_inputs() -> Vec<[u32; 4]> {
    let edges = [0u32, 1, 2, 0x7fff_ffff, 0x8000_0000, u32::MAX, u32::MAX - 1];
    let mut records = Vec::new();
    for &a in &edges {
        for &b in &edges {
            records.push([a, b, a ^ b, b.wrapping_sub(a)]);
        }
    }
    let mut prng = Prng::new(0x5eed);
    for i in 0..8192u32 {
        let (a, b) = (prng.next_u32(), prng.next_u32());
        let layer = if i % 2 == 0 { i % 64 } else { prng.next_u32() };
        records.push([a, b, layer, prng.next_u32()]);
    }
    records
}

/// What `probe_integers` must write for one record: spectex_model::random on the host.
fn expected_integers([a, b, c, d]: [u32; 4]) -> [u32; 16] {
    let cell = cell_hash(a as i32, b as i32, c, d);
    let mut prng = Prng::new(cell);
    let mut out = [
        hash(a),
        permute(a),
        lcg_step(a),
        layer_key(c, d),
        row_key(b as i32, a),
        cell_hash_in_row(a as i32, b),
        cell,
        0,
        0,
        0,
        0,
        0,
        0,
        0,
        0,
        unit_f32(a).to_bits(),
    ];
    for slot in &mut out[7..11] {
        *slot = prng.next_u32();
    }
    for slot in &mut out[11..15] {
        *slot = prng.next_f32().to_bits();
    }
    out
}

const INTEGER_NAMES: [&str; 16] = [
    "hash(a)",
    "permute(a)",
    "lcg_step(a)",
    "layer_key(c, d)",
    "row_key(b, a)",
    "cell_hash_in_row(a, b)",
    "cell_hash(a, b, c, d)",
    "prng.next_u32 #0",
    "prng.next_u32 #1",
    "prng.next_u32 #2",
    "prng.next_u32 #3",
    "prng.next_f32 #0",
    "prng.next_f32 #1",
    "prng.next_f32 #2",
    "prng.next_f32 #3",
    "unit_f32(a)",
];

#[test]
fn integer_contract_is_bit_identical_on_the_device() {
    let Some(context) = common::gpu_or_skip("integer_contract_is_bit_identical_on_the_device")
    else {
        return;
    };
    let records = integer_inputs();
    let flat: Vec<u32> = records.iter().flatten().copied().collect();
    let got = run_probe(
        &context,
        "probe_integers",
        (0, 1),
        &flat,
        4,
        16 * records.len(),
    );
    for (i, &record) in records.iter().enumerate() {
        let want = expected_integers(record);
        for (k, (&g, &w)) in got[16 * i..16 * i + 16].iter().zip(&want).enumerate() {
            assert_eq!(
                g,
                w,
                "record #{i} {record:08x?}: {} is {g:#010x} on {}, {w:#010x} on the host",
                INTEGER_NAMES[k],
                context.adapter_name()
            );
        }
    }
    eprintln!(
        "integer contract: {} records × 16 values bit-identical on {}",
        records.len(),
        context.adapter_name()
    );
}

/// Tolerance of the device's `cos_turns` against `cos(2π·fract)` in f64. The CPU's polynomial is
/// within 2e-7 (truncation 7e-9 plus f32 rounding of seven Horner steps, each ≤ 2⁻²⁴ relative of
/// a value ≤ 1 in magnitude); a fused multiply-add changes one rounding per step by at most one
/// ulp of the step's value (≤ 2⁻²³ ≈ 1.2e-7 for the last steps, whose values are ≤ 1), so
/// 2e-7 + 7·1.2e-7 ≈ 1e-6 covers any mix of fused and unfused steps.
const COS_TOLERANCE: f64 = 1e-6;
/// Tolerance of the device's Kaiser–Bessel window against the f64 definition: the CPU's 2e-6,
/// plus WGSL's `sqrt`, which Vulkan lets be a few ulp off (relative 2⁻²¹ for 4 ulp, at a window
/// value ≤ 1), plus fused Horner steps as above: 2e-6 + 5e-7 + 1e-6.
const WINDOW_TOLERANCE: f64 = 3.5e-6;
/// Relative tolerance of the device's `exp_poly` against f64 `exp` of the same f32 input: the
/// CPU's 1e-6 (measured 2.5e-7), plus one ulp per fused Horner step (7 × 2⁻²³ relative).
const EXP_TOLERANCE: f64 = 2e-6;

#[test]
#[allow(clippy::float_cmp, reason = "exactness is what is tested")]
fn float_functions_are_within_tolerance_on_the_device() {
    let Some(context) = common::gpu_or_skip("float_functions_are_within_tolerance_on_the_device")
    else {
        return;
    };
    // Turns over several periods densely, large angles up to 2²², window arguments r² ∈ [0, 3],
    // exponents over the Gabor range [−3.1, 0] and [−80, 80].
    let mut inputs: Vec<f32> = Vec::new();
    inputs.extend((-200_000..=200_000).map(|i| i as f32 * 1.37e-5 + (i % 7) as f32 * 100.0));
    inputs.extend((0..20_000).map(|i| (i as f32 * 211.37) % 4_194_000.0 - 2_097_000.0));
    inputs.extend((0..=30_000).map(|i| i as f32 * 1e-4));
    inputs.extend((0..=31_000).map(|i| -(i as f32) * 1e-4));
    inputs.extend((-8000..=8000).map(|i| i as f32 * 0.01));
    let words: Vec<u32> = inputs.iter().map(|v| v.to_bits()).collect();
    let got: Vec<f32> = run_probe(
        &context,
        "probe_floats",
        (2, 3),
        &words,
        1,
        6 * inputs.len(),
    )
    .into_iter()
    .map(f32::from_bits)
    .collect();

    let name = context.adapter_name();
    let (mut cos_err, mut window_err, mut exp_err) = (0.0f64, 0.0f64, 0.0f64);
    let (mut cos_same, mut window_same, mut exp_same, mut magic_same) = (0, 0, 0, 0);
    let (mut window_n, mut exp_n) = (0, 0);
    for (i, &t) in inputs.iter().enumerate() {
        let g = &got[6 * i..6 * i + 6];
        // fract_turns and round are exact: equal to the CPU's magic-number form (bit for bit,
        // except that −0 gives +0 here and −0 on the CPU; the cosine takes |r| anyway).
        let fract = cpu_fract_turns(t);
        assert_eq!(
            g[0], fract,
            "fract_turns({t}) = {} on {name}, {fract} on the host",
            g[0]
        );
        assert_eq!(g[5], t.round_ties_even(), "round({t}) on {name}");
        magic_same += usize::from(g[1] == fract);

        let want = (std::f64::consts::TAU * f64::from(fract)).cos();
        let err = (f64::from(g[2]) - want).abs();
        assert!(
            err <= COS_TOLERANCE,
            "cos_turns({t}) = {} on {name}, cos = {want}: error {err:e}",
            g[2]
        );
        cos_err = cos_err.max(err);
        cos_same += usize::from(g[2].to_bits() == cpu_cos_turns(t).to_bits());

        if (0.0..=3.0).contains(&t) {
            let want = spectex_model::window::kaiser_bessel(f64::from(t).sqrt());
            let err = (f64::from(g[3]) - want).abs();
            assert!(
                err <= WINDOW_TOLERANCE,
                "kaiser_bessel_r2({t}) = {} on {name}, {want} in f64: error {err:e}",
                g[3]
            );
            if t >= 2.25 {
                assert_eq!(g[3], 0.0, "window beyond the support at r² = {t}");
            }
            window_err = window_err.max(err);
            window_same += usize::from(g[3].to_bits() == cpu_kaiser_bessel_r2(t).to_bits());
            window_n += 1;
        }
        if (-80.0..=80.0).contains(&t) {
            let want = f64::from(t).exp();
            let err = ((f64::from(g[4]) - want) / want).abs();
            assert!(
                err <= EXP_TOLERANCE,
                "exp_poly({t}) = {} on {name}, {want} in f64: relative error {err:e}",
                g[4]
            );
            exp_err = exp_err.max(err);
            exp_same += usize::from(g[4].to_bits() == cpu_exp_poly(t).to_bits());
            exp_n += 1;
        }
    }
    let n = inputs.len();
    eprintln!("float functions on {name} ({n} inputs):");
    eprintln!("  fract_turns (round): equal to the CPU's for all inputs");
    eprintln!(
        "  fract_turns (magic-number form): {magic_same}/{n} equal to the CPU's{}",
        if magic_same == n {
            " (this compiler keeps the rounding trick)"
        } else {
            " (this compiler folds the trick away)"
        }
    );
    eprintln!(
        "  cos_turns: max error {cos_err:.3e} (tolerance {COS_TOLERANCE:e}), {cos_same}/{n} bit-identical to the CPU"
    );
    eprintln!(
        "  kaiser_bessel_r2: max error {window_err:.3e} (tolerance {WINDOW_TOLERANCE:e}), {window_same}/{window_n} bit-identical"
    );
    eprintln!(
        "  exp_poly: max relative error {exp_err:.3e} (tolerance {EXP_TOLERANCE:e}), {exp_same}/{exp_n} bit-identical"
    );
}
