//! The WGSL export inside someone else's shader: for every model of `testdata/models/` whose
//! kind `spectex_gpu::export` covers, a wgpu **render** pipeline (a full-screen triangle and a
//! fragment shader that includes the exported module and calls `spectex_sample` or
//! `spectex_sample_cell` at its pixel's position) draws into an `Rgba32Float` texture on the
//! adapter (lavapipe under `cargo xtask verify`), and the image is compared with the CPU
//! evaluator's render of the same window: at the origin, at a fractional offset with scale
//! 0.75, and at `(10⁷, 10⁷)` with scale 1.5 through the `(cell, offset)` entry.
//!
//! Tolerance, per model: the CPU–GPU bound of spectex-crosscheck (`tolerance(model)`, derived
//! per kind: the fragment stage runs the same f32 WGSL functions as the compute evaluator, and
//! uses no derivative, so the same contraction and rounding bounds hold), plus what the export
//! adds — its lattice positions come from `export/split.wgsl` instead of the host's f64, off by
//! at most `POSITION_ROUNDINGS` roundings of a number below `2·cell + 2` pixels per axis — times
//! the kind's Lipschitz bound (`regularity(model).slope`, per pixel), plus its `jump` for kinds
//! whose kernels are truncated (a kernel edge within that distance may flip). The test
//! positions are dyadic, so the fragment shader forms them exactly.
//!
//! Skips with a printed reason when no GPU adapter exists, unless `SPECTEX_REQUIRE_GPU=1`.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stdout,
    reason = "the per-model lines are the test's report"
)]

use std::path::PathBuf;

use spectex_crosscheck::tolerance::{F32_UNIT_ROUNDOFF, regularity, tolerance};
use spectex_gpu::export::{ExportOptions, wgsl_module};
use spectex_gpu::{GpuContext, GpuError, wgpu};
use spectex_model::{Model, Window};

/// Roundings that separate the export's lattice offsets from the host's: up to 32 table
/// remainders of half an f32 ulp each where a lattice side is not an f32 (Gabor's radius), the
/// carries, the offsets' sums and Gabor's scaling to cell units (8): 40 unit roundoffs.
const POSITION_ROUNDINGS: f64 = 40.0;

/// Image size: small, lavapipe is slow (FACTS.md).
const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// Kinds the exporter does not cover yet (as in spectex-gpu's export test).
const NOT_EXPORTED: &[&str] = &["phasor", "texture", "classic", "warp", "wavelet", "texton"];

/// One window: how the fragment shader reaches it, and the CPU window.
struct Case {
    name: &'static str,
    /// WGSL expression of the sample at `ij` (the pixel index as `vec2<f32>`).
    call: &'static str,
    window: Window,
}

fn cases() -> Vec<Case> {
    let size = (WIDTH as usize, HEIGHT as usize);
    vec![
        Case {
            name: "origin",
            call: "spectex_sample(ij)",
            window: Window::new(size.0, size.1),
        },
        Case {
            name: "offset, scale 0.75",
            call: "spectex_sample(vec2<f32>(-37.25f, 81.5f) + ij * 0.75f)",
            window: Window::new(size.0, size.1).at([-37.25, 81.5], 0.75),
        },
        Case {
            name: "(1e7, 1e7), scale 1.5",
            call: "spectex_sample_cell(vec2<i32>(10000000i, 10000000i), vec2<f32>(0.25f, 0.5f) + ij * 1.5f)",
            window: Window::new(size.0, size.1).at([10_000_000.25, 10_000_000.5], 1.5),
        },
    ]
}

fn model_files() -> Vec<PathBuf> {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models"
    ));
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

fn gpu_or_skip() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(c) => Some(c),
        Err(e) if std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1") => {
            panic!("SPECTEX_REQUIRE_GPU=1 but no GPU: {e}")
        }
        Err(e) => {
            println!("SKIPPED export render test: {e}");
            None
        }
    }
}

/// The shader the test compiles: the exported module, a full-screen triangle and a fragment
/// shader writing the sample at its pixel.
fn shader(module: &str, call: &str, channels: usize) -> String {
    let store = if channels == 3 {
        "vec4<f32>(v, 1.0f)"
    } else {
        "vec4<f32>(v, 0.0f, 0.0f, 1.0f)"
    };
    format!(
        "{module}
// ---- the test's own shader ----
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {{
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0f - 1.0f;
    return vec4<f32>(xy, 0.0f, 1.0f);
}}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {{
    let ij = frag.xy - vec2<f32>(0.5f);
    let v = {call};
    return {store};
}}
"
    )
}

/// Renders `source`'s full-screen triangle into an `Rgba32Float` target and reads back the
/// first `channels` components of every pixel, row-major from the top.
fn render(context: &GpuContext, source: &str, channels: usize) -> Result<Vec<f32>, String> {
    let device = context.device();
    let queue = context.queue();
    device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("export test"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let format = wgpu::TextureFormat::Rgba32Float;
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("export test"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    });
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("export target"),
        size: wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let row_bytes = WIDTH * 16;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("export readback"),
        size: u64::from(row_bytes * HEIGHT),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let view = target.create_view(&wgpu::TextureViewDescriptor::default());
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("export test"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.draw(0..3, 0..1);
    }
    encoder.copy_texture_to_buffer(
        target.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row_bytes),
                rows_per_image: Some(HEIGHT),
            },
        },
        wgpu::Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    if let Some(e) = pollster::block_on(device.pop_error_scope()) {
        return Err(e.to_string());
    }
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    let data = slice.get_mapped_range().map_err(|e| e.to_string())?;
    let texels: &[f32] = bytemuck::cast_slice(&data);
    Ok(texels
        .chunks_exact(4)
        .flat_map(|t| t[..channels].to_vec())
        .collect())
}

#[test]
fn exported_modules_render_the_cpu_values_in_a_fragment_shader() {
    let Some(context) = gpu_or_skip() else {
        return;
    };
    let mut failures = Vec::new();
    let mut rendered = 0;
    for file in model_files() {
        let case = file.file_stem().unwrap().to_string_lossy().into_owned();
        let model: Model = spectex_model::from_json(&std::fs::read_to_string(&file).unwrap())
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        let module = match wgsl_module(&model, &ExportOptions::default()) {
            Err(GpuError::Unsupported { .. }) if NOT_EXPORTED.contains(&model.kind()) => continue,
            other => other.unwrap_or_else(|e| panic!("{case}: {e}")),
        };
        let channels = model.output_channels();
        let cpu = spectex_cpu::Evaluator::new(&model).unwrap();
        let base = tolerance(&model).unwrap_or_else(|| panic!("{case}: no tolerance"));
        let reg = regularity(&model).unwrap_or_else(|| panic!("{case}: no regularity"));
        let position = POSITION_ROUNDINGS * F32_UNIT_ROUNDOFF * (2.0 * reg.cell + 2.0);
        let moved = reg.slope * position * std::f64::consts::SQRT_2;
        let max_allowed = base.max_abs + moved + if reg.jump > 0.0 { reg.jump } else { 0.0 };
        let mean_allowed = base.mean_abs + moved;
        for c in cases() {
            let want = cpu.render(&c.window).unwrap();
            let got = render(&context, &shader(&module, c.call, channels), channels)
                .unwrap_or_else(|e| panic!("{case} {}: {e}", c.name));
            assert_eq!(got.len(), want.len());
            let errors: Vec<f64> = want
                .iter()
                .zip(&got)
                .map(|(a, b)| (f64::from(*a) - f64::from(*b)).abs())
                .collect();
            let (worst, at) = errors.iter().enumerate().fold((0.0, 0), |(m, i), (k, &e)| {
                if e > m || e.is_nan() { (e, k) } else { (m, i) }
            });
            let mean = errors.iter().sum::<f64>() / errors.len() as f64;
            println!(
                "export: {case} {}: max {worst:.3e} (allowed {max_allowed:.3e}), mean {mean:.3e} \
                 (allowed {mean_allowed:.3e})",
                c.name
            );
            if !(worst <= max_allowed && mean <= mean_allowed) {
                failures.push(format!(
                    "{case} {}: max {worst:.3e} at value {at} (cpu {}, export {}) vs {max_allowed:.3e}, \
                     mean {mean:.3e} vs {mean_allowed:.3e}",
                    c.name, want[at], got[at]
                ));
            }
        }
        rendered += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        rendered >= 6,
        "only {rendered} models rendered through the export"
    );
}
