//! The render ring: output formats packed on the device against the `f32` render quantised on
//! the host by the CPU's formulas, tiles and ring reuse that change no bit, renders into a
//! caller's device buffer (a caller's own device included), timestamps, and the typed errors of
//! a caller's output that does not fit.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::Path;

use crate::common;

use spectex_gpu::{GpuContext, GpuError, GpuEvaluator, GpuWindow, OutputFormat, wgpu};
use spectex_model::Model;

/// A testdata model by file name.
fn model(name: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/models")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    spectex_model::from_json(&text).unwrap()
}

/// The CPU's unorm quantisation of an `f32` value (`spectex-cli`'s PNG writer): in f64.
fn quantise(v: f32, levels: f64) -> f64 {
    (f64::from(v).clamp(0.0, 1.0) * levels).round()
}

/// An IEEE binary16 value as f64 (normal, subnormal, zero; no infinities or NaN expected).
fn f16_value(bits: u16) -> f64 {
    let sign = if bits >> 15 == 1 { -1.0 } else { 1.0 };
    let exponent = i32::from((bits >> 10) & 0x1f);
    let fraction = f64::from(bits & 0x3ff);
    match exponent {
        0 => sign * fraction * 2f64.powi(-24),
        e => sign * (1.0 + fraction / 1024.0) * 2f64.powi(e - 15),
    }
}

/// Every output format of grey and colour models, in tiles narrower than the window and ragged
/// at its edges (so packed words straddle tile rows), against the `f32` render quantised here.
#[test]
fn packed_formats_are_the_f32_render_quantised() {
    let Some(context) = common::gpu_or_skip("packed_formats") else {
        return;
    };
    for (name, window) in [
        (
            "classic-perlin-fbm.json",
            GpuWindow::new(37, 23).at([1.0e7 + 0.25, -3.0e6], 1.0),
        ),
        (
            "combine-bark.json",
            GpuWindow::new(19, 11).at([5.0, 7.0], 1.0),
        ),
    ] {
        let mut gpu = GpuEvaluator::new(&context, &model(name)).unwrap();
        gpu.set_max_tile(13, 7);
        let mut values = vec![0.0; window.width * window.height * gpu.output_channels()];
        let f32_stats = gpu.render_into(&window, &mut values).unwrap();
        assert_eq!(f32_stats.clipped, None, "{name}: f32 clamps nothing");
        let mut unorm8 = vec![0; values.len()];
        let stats8 = gpu
            .render_bytes_into(&window, OutputFormat::Unorm8, &mut unorm8)
            .unwrap();
        // Summed over tiles: the CPU's count of what a PNG clamps.
        let outside = values.iter().filter(|v| !(0.0..=1.0).contains(*v)).count();
        assert_eq!(stats8.clipped, Some(outside as u64), "{name}");
        let unorm16 = gpu.render_bytes(&window, OutputFormat::Unorm16).unwrap();
        let half = gpu.render_bytes(&window, OutputFormat::F16).unwrap();
        assert_eq!(unorm8.len(), values.len(), "{name}");
        assert_eq!(unorm16.len(), 2 * values.len(), "{name}");
        assert_eq!(half.len(), 2 * values.len(), "{name}");
        for (i, &v) in values.iter().enumerate() {
            let level8 = f64::from(unorm8[i]);
            assert_eq!(level8, quantise(v, 255.0), "{name} unorm8 [{i}] {v}");
            let level16 = f64::from(u16::from_le_bytes([unorm16[2 * i], unorm16[2 * i + 1]]));
            assert_eq!(level16, quantise(v, 65535.0), "{name} unorm16 [{i}] {v}");
            // Round to nearest keeps half an ulp of binary16: 2⁻¹¹ relative for normals,
            // 2⁻²⁵ absolute below them.
            let h = f16_value(u16::from_le_bytes([half[2 * i], half[2 * i + 1]]));
            let bound = (f64::from(v).abs() * 2f64.powi(-11)).max(2f64.powi(-25));
            assert!(
                (h - f64::from(v)).abs() <= bound,
                "{name} f16 [{i}] {v} -> {h}"
            );
        }
        let spread = values
            .iter()
            .fold([f32::MAX, f32::MIN], |[lo, hi], &v| [lo.min(v), hi.max(v)]);
        assert!(
            spread[1] - spread[0] > 0.05,
            "{name}: a flat render proves little ({spread:?})"
        );
    }
}

/// More tiles than ring slots, a second render on the kept ring, a larger window that grows
/// it, a ring reserved ahead for a larger window, and the default full-width bands: the same
/// bits everywhere, composite kinds and tiles prepared on worker threads included.
#[test]
fn tiles_and_ring_reuse_change_no_bit() {
    let Some(context) = common::gpu_or_skip("tiles_and_ring_reuse") else {
        return;
    };
    for name in [
        "lrp-ring.json",
        "warp-classic-fbm.json",
        "combine-bark.json",
    ] {
        let window = GpuWindow::new(40, 30).at([2.0e6, 1.0e6 + 0.5], 1.0);
        let whole = GpuEvaluator::new(&context, &model(name)).unwrap();
        let reference = whole.render(&window).unwrap();
        let mut tiled = GpuEvaluator::new(&context, &model(name)).unwrap();
        tiled.set_max_tile(9, 8);
        let small = tiled.render(&window.tile(3, 2, 20, 10)).unwrap();
        for pass in 0..2 {
            let values = tiled.render(&window).unwrap();
            assert_eq!(
                common::first_bit_difference(&values, &reference),
                None,
                "{name}, pass {pass}"
            );
        }
        let reserved = GpuEvaluator::new(&context, &model(name)).unwrap();
        reserved
            .reserve(&GpuWindow::new(300, 200), OutputFormat::F16)
            .unwrap();
        let values = reserved.render(&window).unwrap();
        assert_eq!(
            common::first_bit_difference(&values, &reference),
            None,
            "{name}, reserved"
        );
        let c = whole.output_channels();
        let part: Vec<f32> = (0..10)
            .flat_map(|y| reference[((2 + y) * 40 + 3) * c..((2 + y) * 40 + 23) * c].to_vec())
            .collect();
        assert_eq!(common::first_bit_difference(&small, &part), None, "{name}");
    }
}

/// A render into a device buffer of the caller's own device (a context made from it), read
/// back here, equals the host render; nothing comes back to spectex, so it does not wait for
/// the device.
#[test]
fn render_to_a_callers_buffer_on_a_callers_device() {
    let Some(own) = common::gpu_or_skip("render_to_buffer") else {
        return;
    };
    let context = GpuContext::from_device(own.device().clone(), own.queue().clone());
    let m = model("gabor-anisotropic.json");
    let mut gpu = GpuEvaluator::new(&context, &m).unwrap();
    let window = GpuWindow::new(24, 20).at([-7.5e6, 3.0], 0.75);
    let reference = gpu.render(&window).unwrap();
    let device = context.device();
    let offset = 256u64;
    for (max_tile, format) in [
        (None, OutputFormat::F32),
        (Some([8, 8]), OutputFormat::F32),
        (None, OutputFormat::Unorm8),
    ] {
        if let Some([w, h]) = max_tile {
            gpu.set_max_tile(w, h);
        }
        let bytes = (reference.len() * format.bytes_per_value()) as u64;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("caller's buffer"),
            size: offset + bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let stats = gpu
            .render_to_buffer(&window, format, &buffer, offset)
            .unwrap();
        // Nothing read back, not even timestamps: the call did not wait for the device.
        assert_eq!(
            (stats.bytes_read_back, stats.kernel_seconds),
            (0, None),
            "{stats:?}"
        );
        let back = read(device, context.queue(), &buffer)[offset as usize..].to_vec();
        let host = gpu.render_bytes(&window, format).unwrap();
        assert_eq!(back, host, "{max_tile:?} {format:?}");
    }
}

/// Copies `buffer` out through a staging buffer.
fn read(device: &wgpu::Device, queue: &wgpu::Queue, buffer: &wgpu::Buffer) -> Vec<u8> {
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("staging"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    queue.submit([encoder.finish()]);
    staging
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.unwrap());
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let bytes = staging.slice(..).get_mapped_range().unwrap().to_vec();
    staging.unmap();
    bytes
}

/// A caller's output that does not fit is a typed error naming what is wrong, before any
/// device work; the evaluator renders normally afterwards.
#[test]
fn outputs_that_do_not_fit_are_typed_errors() {
    let Some(context) = common::gpu_or_skip("outputs_that_do_not_fit") else {
        return;
    };
    let gpu = GpuEvaluator::new(&context, &model("lrp-ring.json")).unwrap();
    let window = GpuWindow::new(8, 6);
    let mut short = vec![0.0f32; 47];
    match gpu.render_into(&window, &mut short) {
        Err(GpuError::Output { what, value, .. }) => {
            assert_eq!((what, value), ("bytes of the output slice", 188));
        }
        other => panic!("expected an output error, got {other:?}"),
    }
    let buffer = |size, usage| {
        context.device().create_buffer(&wgpu::BufferDescriptor {
            label: Some("target"),
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let copy = wgpu::BufferUsages::COPY_DST;
    for (target, offset, needle) in [
        (buffer(192, wgpu::BufferUsages::STORAGE), 0, "usage bits"),
        (buffer(192, copy), 2, "byte offset"),
        (buffer(188, copy), 4, "bytes of the target buffer"),
    ] {
        match gpu.render_to_buffer(&window, OutputFormat::F32, &target, offset) {
            Err(e @ GpuError::Output { .. }) => assert!(e.to_string().contains(needle), "{e}"),
            other => panic!("{needle}: expected an output error, got {other:?}"),
        }
    }
    assert_eq!(gpu.render(&window).unwrap().len(), 48);
}

/// Where the device has timestamp queries, a render's kernel time is positive and within its
/// end-to-end time (the device cannot compute longer than the call waits for it); the host's
/// preparation of the tiles is timed too, within the end-to-end time times the workers.
#[test]
fn timestamps_time_the_kernels_within_the_render() {
    let Some(context) = common::gpu_or_skip("timestamps") else {
        return;
    };
    let mut gpu = GpuEvaluator::new(&context, &model("lrp-gravel.json")).unwrap();
    gpu.set_max_tile(16, 16);
    let window = GpuWindow::new(48, 40);
    let mut out = vec![0.0f32; 48 * 40];
    let stats = gpu.render_into(&window, &mut out).unwrap();
    assert_eq!(stats.tiles, 9);
    let workers = std::thread::available_parallelism().map_or(1, usize::from) as f64;
    assert!(
        stats.host_seconds > 0.0 && stats.host_seconds <= stats.seconds * workers,
        "{stats:?}"
    );
    assert_eq!(
        stats.bytes_read_back,
        4 * 48 * 40 + if context.has_timestamps() { 9 * 16 } else { 0 }
    );
    match stats.kernel_seconds {
        Some(kernel) => {
            assert!(context.has_timestamps());
            assert!(kernel > 0.0 && kernel <= stats.seconds, "{stats:?}");
        }
        None => {
            assert!(!context.has_timestamps());
            eprintln!(
                "timestamps: {} has no timestamp queries",
                context.adapter_name()
            );
        }
    }
}

/// A render into a caller's storage texture, read back here, holds the host render: `f32`
/// texels bit for bit, `rgba8unorm` within one level of the CPU's quantisation; colour in R, G,
/// B, alpha 1; a texture of another format, without storage usage or too small is refused.
#[test]
fn render_to_a_callers_storage_texture() {
    let Some(context) = common::gpu_or_skip("render_to_texture") else {
        return;
    };
    let device = context.device();
    let texture = |format, width, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("caller's texture"),
            size: wgpu::Extent3d {
                width,
                height: 20,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC;
    let window = GpuWindow::new(24, 20).at([3.0e6, -1.0], 1.0);
    for (name, format, texel_bytes) in [
        ("lrp-ring.json", wgpu::TextureFormat::R32Float, 4),
        ("combine-bark.json", wgpu::TextureFormat::Rgba32Float, 16),
        ("lrp-ring.json", wgpu::TextureFormat::Rgba8Unorm, 4),
    ] {
        let mut gpu = GpuEvaluator::new(&context, &model(name)).unwrap();
        gpu.set_max_tile(16, 8);
        let values = gpu.render(&window).unwrap();
        let c = gpu.output_channels();
        // 64 texels a row: a whole number of 256-byte rows for every format here.
        let target = texture(format, 64, usage);
        let stats = gpu.render_to_texture(&window, &target).unwrap();
        assert_eq!(
            (stats.bytes_read_back, stats.kernel_seconds),
            (0, None),
            "{stats:?}"
        );
        let bytes = read_texture(device, context.queue(), &target, 64 * texel_bytes);
        for y in 0..20 {
            for x in 0..24 {
                let texel = &bytes[(y * 64 + x) * texel_bytes..][..texel_bytes];
                let v = &values[(y * 24 + x) * c..][..c];
                match format {
                    wgpu::TextureFormat::R32Float => {
                        assert_eq!(texel, v[0].to_le_bytes(), "{name} ({x}, {y})");
                    }
                    wgpu::TextureFormat::Rgba32Float => {
                        let rgba: Vec<f32> = bytemuck::pod_collect_to_vec(texel);
                        assert_eq!(&rgba[..3], v, "{name} ({x}, {y})");
                        assert_eq!(rgba[3], 1.0);
                    }
                    _ => {
                        for channel in 0..3 {
                            let level = f64::from(texel[channel]);
                            let want = quantise(v[0], 255.0);
                            assert!(
                                (level - want).abs() <= 1.0,
                                "{name} ({x}, {y}) {level} {want}"
                            );
                        }
                        assert_eq!(texel[3], 255);
                    }
                }
            }
        }
    }
    let gpu = GpuEvaluator::new(&context, &model("lrp-ring.json")).unwrap();
    match gpu.render_to_texture(
        &window,
        &texture(
            wgpu::TextureFormat::Rgba8UnormSrgb,
            64,
            wgpu::TextureUsages::COPY_SRC,
        ),
    ) {
        Err(e @ GpuError::TextureFormat { .. }) => {
            assert!(e.to_string().contains("Rgba8UnormSrgb"), "{e}")
        }
        other => panic!("expected a format error, got {other:?}"),
    }
    for (target, needle) in [
        (
            texture(
                wgpu::TextureFormat::R32Float,
                64,
                wgpu::TextureUsages::COPY_SRC,
            ),
            "usage bits",
        ),
        (
            texture(wgpu::TextureFormat::R32Float, 16, usage),
            "texels along a side",
        ),
    ] {
        match gpu.render_to_texture(&window, &target) {
            Err(e @ GpuError::Output { .. }) => assert!(e.to_string().contains(needle), "{e}"),
            other => panic!("{needle}: expected an output error, got {other:?}"),
        }
    }
}

/// The texels of `texture` (rows of `row` bytes, a multiple of 256).
fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    row: usize,
) -> Vec<u8> {
    let size = texture.size();
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("staging"),
        size: (row * size.height as usize) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row as u32),
                rows_per_image: Some(size.height),
            },
        },
        size,
    );
    queue.submit([encoder.finish()]);
    staging
        .slice(..)
        .map_async(wgpu::MapMode::Read, |r| r.unwrap());
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let bytes = staging.slice(..).get_mapped_range().unwrap().to_vec();
    staging.unmap();
    bytes
}
