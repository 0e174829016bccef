//! The WGSL export inside someone else's shader: for every model of `testdata/models/` (every
//! kind exports; `REFUSED` lists the models with a feature the exporter refuses), a wgpu
//! **render** pipeline (a full-screen triangle
//! and a fragment shader that includes the exported module and calls `spectex_sample` or
//! `spectex_sample_cell` at its pixel's position; models over `MAX_TABLE_BYTES` with their
//! tables' storage buffer bound) draws into an `Rgba32Float` texture on the
//! adapter (lavapipe under `cargo xtask verify`), and the image is compared with the CPU
//! evaluator's render of the same window: at the origin, at a fractional offset with scale
//! 0.75, and at `(10⁷, 10⁷)` with scale 1.5 through the `(cell, offset)` entry (point samples:
//! the CPU window is unfiltered, `render --no-filter`, as the export does not filter).
//!
//! Tolerance, per model: the CPU–GPU bound of spectex-crosscheck (`tolerance(model)`, derived
//! per kind: the fragment stage runs the same f32 WGSL functions as the compute evaluator, and
//! uses no derivative, so the same contraction and rounding bounds hold), plus what the export
//! adds — its lattice positions come from `export/split.wgsl` instead of the host's f64, off by
//! at most `POSITION_ROUNDINGS` roundings of a number below `2·cell + 2` pixels per axis — times
//! the kind's Lipschitz bound (`regularity(model).slope`, per pixel), plus its `jump` for kinds
//! whose kernels are truncated (a kernel edge within that distance may flip). The cell is the
//! largest lattice the export locates on (a warp's x and y have their own). A texture's
//! inputs are LRP models and its placement lattice a power of two: the texture tolerance
//! (spectex-crosscheck's, which bounds the LRP strata and turbulence as computed on the GPU)
//! covers them the same way. A warp's export adds the displacement's fraction to the offset
//! (one rounding of a number below 2, far below the compute path's relocation that the warp
//! tolerance bounds) and moves whole pixels exactly. The test positions are dyadic, so the
//! fragment shader forms them exactly. A matrix transformation takes its pixel cell from the
//! integer part exactly: its bound is spectex-crosscheck's alone. A combination's bound is
//! spectex-crosscheck's (composed from its operands') with the position term of its largest
//! operand lattice. Where spectex-crosscheck judges a kind by its own criterion over
//! companion renders, so does this test, every companion exported too: a phasor model by
//! phasor's pixel criterion with its complex-sum bound `E` grown by what the export's offsets
//! and in-shader directions add (`phasor_export_bound`), on the pixels no kernel edge can
//! cross (`phasor_edge_mask`); a Voronoi cell ID by equality wherever the two nearest seeds
//! cannot swap (`check_voronoi_discrete`). Phasor kernels and Voronoi sites are drawn in the
//! shader from the same integer hashes as on the host, so they are the same kernels. A phasor
//! model whose fields vary (or steered by an image's gradient or the coherent direction
//! process) has them evaluated in f32 in the shader: `fields` (an f64 reference of its
//! kernel process) grows `E` per pixel by what each impulse's field errors add and leaves out,
//! counting them, the pixels where a thinning comparison or a direction is within the f32
//! evaluation's error of its discontinuity. A combination with no pointwise bound (crossed
//! waves) is judged by spectex-crosscheck's composed verdict (`composed_verdict`): each
//! operand exported, rendered and judged as above, and the combination's render equal to
//! `CombineOp::apply` of its operands' renders on each side (`check_combination`).
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

mod fields;

use std::path::{Path, PathBuf};

use spectex_crosscheck::tolerance::combine::composed_verdict;
use spectex_crosscheck::tolerance::phasor::{complex_bound, judge_with_pixel_bounds};
use spectex_crosscheck::tolerance::{
    COS_ABS_ERROR, F32_UNIT_ROUNDOFF, check_kind, regularity, tolerance,
};
use spectex_gpu::export::{ExportOptions, TableStorage, export};
use spectex_gpu::{GpuContext, GpuError, wgpu};
use spectex_model::phasor_kernels::{Impulse, PhasorKernels};
use spectex_model::{
    Field, Filter, Model, PhasorNoise, PhasorOrientation, PhasorOutput, Profile, Window,
};

use crate::common::gpu_or_skip;

/// Roundings that separate the export's lattice offsets from the host's: up to 32 table
/// remainders of half an f32 ulp each where a lattice side is not an f32 (Gabor's radius), the
/// carries, the offsets' sums and Gabor's scaling to cell units (8): 40 unit roundoffs.
const POSITION_ROUNDINGS: f64 = 40.0;

/// Image size: small, lavapipe is slow.
const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// Models the exporter refuses (as in spectex-gpu's export test), each for one feature it
/// cannot export exactly (`spectex_gpu::export`'s module doc says why), with a word of the
/// error's feature.
const REFUSED: &[(&str, &str)] = &[
    ("combine-cracks", "Lloyd"),
    ("voronoi-border-lloyd", "Lloyd"),
    ("voronoi-palette-lloyd", "Lloyd"),
];

/// Models whose exported module lavapipe compiles for 20–200 s each (LLVM inlines every nested
/// model and LRP part into the fragment shader), measured on the 2-core CI machine's kind: the
/// render test leaves them out unless `SPECTEX_EXPORT_ALL=1` (`cargo xtask export-check`), so
/// that CI stays in its time budget. Each kind keeps a model in the CI run
/// (`texture-synthetic-grey`, `warp-lrp-by-gabor`, `combine-crossed-waves`; `combine-bark`, a
/// ramp of a fold of a warp, compiled in 84 s). `classic-simplex-3d` compiled in 48 s of the
/// test's 185 (the other seven classic models in 30 s together); its kernel is the compute
/// shader's, cross-checked in every CI run, and the export's glue is the other classic models'.
/// So do `combine-mix-product` (22 s: a combination's glue is also crossed waves', whose
/// operands and sum CI renders) and `lrp-fractal-anisotropic` (16 s; CI renders three other
/// LRP models through the same glue).
const SLOW_ON_LAVAPIPE: &[&str] = &[
    "classic-simplex-3d",
    "combine-bark",
    "combine-mix-product",
    "lrp-fractal-anisotropic",
    "texture-fitted-colour",
    "texture-synthetic-colour",
    "warp-classic-fbm",
    "warp-texture-colour",
    "warp-wavelet-by-fbm",
];

/// Where the test binds the storage buffer of models whose tables exceed `MAX_TABLE_BYTES`
/// (not the CLI's defaults: any group and binding work).
const TABLES_GROUP: u32 = 0;
const TABLES_BINDING: u32 = 7;

/// One window: its top-left position as the fragment shader receives it (integer part and
/// f32 fraction), its scale, and the CPU window.
struct Case {
    name: &'static str,
    cell: [i32; 2],
    offset: [f32; 2],
    scale: f32,
    window: Window,
}

fn cases() -> Vec<Case> {
    let size = (WIDTH as usize, HEIGHT as usize);
    vec![
        Case {
            name: "origin",
            cell: [0, 0],
            offset: [0.0, 0.0],
            scale: 1.0,
            window: Window::new(size.0, size.1),
        },
        Case {
            name: "offset, scale 0.75",
            cell: [0, 0],
            offset: [-37.25, 81.5],
            scale: 0.75,
            window: Window::new(size.0, size.1).at([-37.25, 81.5], 0.75),
        },
        Case {
            name: "(1e7, 1e7), scale 1.5",
            cell: [10_000_000, 10_000_000],
            offset: [0.25, 0.5],
            scale: 1.5,
            // A minified window: the export point-samples, as `render --no-filter` does.
            window: Window::new(size.0, size.1)
                .at([10_000_000.25, 10_000_000.5], 1.5)
                .filtered(Filter::Off),
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

/// The shader the test compiles: the exported module, a full-screen triangle and a fragment
/// shader writing, in row band `k` (`HEIGHT` rows each), case `k`'s sample at its pixel:
/// through `spectex_sample(p)` for cases at cell (0, 0), else through
/// `spectex_sample_cell(cell, offset + ij·scale)`. One pipeline per model, with two call sites
/// only: lavapipe inlines every call and compiles a module with large constant tables slowly.
fn shader(module: &str, cases: &[Case], channels: usize) -> String {
    let (ty, store) = if channels == 3 {
        ("vec3<f32>", "vec4<f32>(v, 1.0f)")
    } else {
        ("f32", "vec4<f32>(v, 0.0f, 0.0f, 1.0f)")
    };
    let branches = cases
        .iter()
        .enumerate()
        .map(|(k, c)| {
            format!(
                "if (band == {k}u) {{\n        cell = vec2<i32>({}i, {}i);\n        \
                 offset = vec2<f32>({:?}f, {:?}f);\n        scale = {:?}f;\n    }}",
                c.cell[0], c.cell[1], c.offset[0], c.offset[1], c.scale
            )
        })
        .collect::<Vec<_>>()
        .join(" else ");
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
    let pixel = frag.xy - vec2<f32>(0.5f);
    let band = u32(pixel.y) / {HEIGHT}u;
    let ij = vec2<f32>(pixel.x, pixel.y - f32(band * {HEIGHT}u));
    var cell = vec2<i32>(0i);
    var offset = vec2<f32>(0.0f);
    var scale = 1.0f;
    {branches}
    var v: {ty};
    if (all(cell == vec2<i32>(0i))) {{
        v = spectex_sample(offset + ij * scale);
    }} else {{
        v = spectex_sample_cell(cell, offset + ij * scale);
    }}
    return {store};
}}
"
    )
}

/// Renders `source`'s full-screen triangle into an `Rgba32Float` target and reads back the
/// first `channels` components of every pixel, row-major from the top.
fn render(
    context: &GpuContext,
    source: &str,
    channels: usize,
    bands: u32,
    tables: &[u8],
) -> Result<Vec<f32>, String> {
    let rows = HEIGHT * bands;
    let device = context.device();
    let queue = context.queue();
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
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
            height: rows,
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
        size: u64::from(row_bytes * rows),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    // The exported tables, uploaded as they are (little-endian words, as the device reads them
    // on every adapter wgpu supports).
    let bind_group = (!tables.is_empty()).then(|| {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("export tables"),
            size: tables.len() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&buffer, 0, tables);
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("export tables"),
            layout: &pipeline.get_bind_group_layout(TABLES_GROUP),
            entries: &[wgpu::BindGroupEntry {
                binding: TABLES_BINDING,
                resource: buffer.as_entire_binding(),
            }],
        })
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
        if let Some(group) = &bind_group {
            pass.set_bind_group(TABLES_GROUP, group, &[]);
        }
        pass.draw(0..3, 0..1);
    }
    encoder.copy_texture_to_buffer(
        target.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row_bytes),
                rows_per_image: Some(rows),
            },
        },
        wgpu::Extent3d {
            width: WIDTH,
            height: rows,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    if let Some(e) = pollster::block_on(scope.pop()) {
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

/// The largest lattice side a model's export locates positions on: its regularity's grid, or
/// for a warp the largest of its base's, x's and y's (each is located by the split).
fn largest_cell(case: &str, model: &Model) -> f64 {
    if let Model::Warp(w) = model {
        return largest_cell(case, &w.base)
            .max(largest_cell(case, &w.x))
            .max(largest_cell(case, &w.y));
    }
    if let Model::Combine(c) = model {
        return c
            .operands
            .iter()
            .map(|m| largest_cell(case, m))
            .fold(0.0, f64::max);
    }
    regularity(model)
        .unwrap_or_else(|| panic!("{case}: no regularity"))
        .cell
}

/// `(max, mean)` bounds on `|cpu − export|` for a texton model with ellipsoid spots, which
/// has no Lipschitz bound: `g(ρ) = √(1 − ρ²)` moves by at most `√(2·Δρ)` when `ρ` moves by `Δρ`
/// (`|√a − √b| ≤ √|a − b|` and `|ρ₁² − ρ₂²| ≤ 2Δρ`), `Δρ = δ/r` for the position error `δ`
/// and the smallest texton radius `r = min(a, b)·min(s)` pixels; each texton that reaches a
/// pixel adds that times its largest `|w|`: at most one per cell (grid) or 16 (Poisson) over
/// the `(2·reach + 1)²` cells, one for the maximum rule (the maximum of values each moved by
/// `ε` moves by `ε`). The mean takes the same bound: few pixels sit near an edge, but no
/// sharper share is derived here.
fn ellipsoid_tolerance(texton: &spectex_model::TextonNoise, base: (f64, f64)) -> (f64, f64) {
    use spectex_model::texton::{Combine, MAX_TEXTONS_PER_CELL, Placement};
    let delta = std::f64::consts::SQRT_2
        * POSITION_ROUNDINGS
        * F32_UNIT_ROUNDOFF
        * (2.0 * f64::from(texton.cell_size) + 2.0);
    let r = f64::from(texton.radii[0].min(texton.radii[1]) * texton.scale[0].min(texton.scale[1]));
    let w = f64::from(texton.intensity[0].abs().max(texton.intensity[1].abs()));
    let per_cell = match texton.placement {
        Placement::Grid { .. } => 1.0,
        Placement::Poisson { .. } => f64::from(MAX_TEXTONS_PER_CELL),
    };
    let cells = f64::from(2 * texton.reach() + 1).powi(2);
    let terms = match texton.combine {
        Combine::Sum => per_cell * cells,
        Combine::Max => 1.0,
    };
    let moved = terms * w * (2.0 * delta / r).sqrt();
    (base.0 + moved, base.1 + moved)
}

/// `(max, mean)` bounds on `|cpu − export|` for `model` (see the module doc).
fn export_tolerance(case: &str, model: &Model) -> (f64, f64) {
    let base = tolerance(model).unwrap_or_else(|| panic!("{case}: no tolerance"));
    if let Model::Texton(t) = model
        && matches!(t.spot, spectex_model::texton::Spot::Ellipsoid)
    {
        return ellipsoid_tolerance(t, (base.max_abs, base.mean_abs));
    }
    if let Model::Matrix(_) = model {
        // No position term: the export's pixel cell is the floor of its integer part plus an
        // exactly formed (dyadic) offset, the CPU's ⌊x⌋ of the same x, and the texel is read
        // by the same integer map.
        return (base.max_abs, base.mean_abs);
    }
    let reg = regularity(model).unwrap_or_else(|| panic!("{case}: no regularity"));
    let position = POSITION_ROUNDINGS * F32_UNIT_ROUNDOFF * (2.0 * largest_cell(case, model) + 2.0);
    let moved = reg.slope * position * std::f64::consts::SQRT_2;
    (
        base.max_abs + moved + reg.jump.max(0.0),
        base.mean_abs + moved,
    )
}

/// Position error of the export's offsets in kernel cells, for a phasor model of cell side
/// `r` (pixels) rendered at positions up to `far` pixels from the origin: the export's
/// `POSITION_ROUNDINGS` roundings of a number below `2r + 2` pixels, the CPU's own rounding of
/// its offset (below 1: half an ulp, `u`) and its f64 division `x/r` (`2⁻⁵²·(far/r + 1)`).
fn phasor_delta(r: f64, far: f64) -> f64 {
    POSITION_ROUNDINGS * F32_UNIT_ROUNDOFF * (2.0 * r + 2.0) / r
        + F32_UNIT_ROUNDOFF
        + 2f64.powi(-52) * (far / r + 1.0)
}

/// Per axis, how far either evaluator's `d = (u − s) − o` (cell units, below 2 in magnitude)
/// lies from the exact one: `delta` of the offset and three roundings of numbers below 2
/// (`2u` each).
fn phasor_axis_error(delta: f64) -> f64 {
    delta + 6.0 * F32_UNIT_ROUNDOFF
}

/// The complex-sum bound `E` of a phasor model's export: spectex-crosscheck's
/// [`complex_bound`] (the same f32 sum in the fragment shader as in the compute shader) plus,
/// per impulse term of the `n + 6√n + 6` a pixel sums (`n` = cells × λ), what the export
/// changes — its offsets `d` move by at most `|Δd| = √dims·phasor_axis_error(δ)` cell units,
/// which moves `g = exp(−ln 20·|d|²)` by at most `√(2 ln 20)·e^{−½}·|Δd|` (the Gaussian's
/// steepest slope) and the phase `t = f·d + ψ` by `|f|·|Δd|` turns (`|f| = F·r`); an isotropic
/// model's directions are computed in the shader, each component of `f` within
/// `F·r·(COS_ABS_ERROR + 4u)` on either side, which moves `t` by `√dims` of it twice over
/// (`|d| < 1` inside the support). A term changes by `|Δg| + 2π|Δt|` in re and in im.
/// Impulses whose support edge lies within reach of the position error are not bounded here
/// (the term jumps by the truncation): [`phasor_edge_mask`] leaves their pixels out.
fn phasor_export_bound(m: &PhasorNoise, far: f64) -> f64 {
    let three_d = m.dimensions == 3;
    let (dims, cells) = if three_d { (3.0, 27.0) } else { (2.0, 9.0) };
    let r = m.kernel_radius();
    let n = cells * m.impulses_per_cell();
    let count = n + 6.0 * n.sqrt() + 6.0;
    let fr = m.frequency.range().1.clamp(0.0, 0.5) * r;
    let dd = f64::sqrt(dims) * phasor_axis_error(phasor_delta(r, far));
    let g_slope = (2.0 * 20f64.ln()).sqrt() * (-0.5f64).exp();
    let direction = match m.orientation {
        PhasorOrientation::Isotropic => {
            2.0 * f64::sqrt(dims) * fr * (COS_ABS_ERROR + 4.0 * F32_UNIT_ROUNDOFF)
        }
        _ => 0.0,
    };
    let dt = fr * dd + direction;
    complex_bound(m) + count * (g_slope * dd + std::f64::consts::TAU * dt)
}

/// Pixels of `window` (row-major) that an impulse's support edge may cross between the CPU and
/// the export: some impulse of the 3×3 (3×3×3) cells around the pixel (drawn by
/// `spectex_model::phasor_kernels`, as both evaluators draw them) has its exact `sharp·|d|²`
/// (f64, a slow reference) within `η` of 1, where `η` bounds how far either evaluator's f32
/// `sharp·|d|²` lies from it: `2·√dims·1.1·e + dims·e² + 4u` for the per-axis error `e`
/// ([`phasor_axis_error`]; `|d_a| ≤ 1.1` near the edge, and the sum of three squares rounds
/// within `3u` of a number below 1.1, with `sharp` = 1 for the exported constant bandwidth).
/// Such an impulse is in one sum and not the other: the pixel is not judged.
fn phasor_edge_mask(m: &PhasorNoise, window: &Window, delta: f64) -> Vec<bool> {
    let kernels = PhasorKernels::new(m);
    let side = kernels.side();
    let three_d = kernels.three_d();
    let dims = if three_d { 3.0 } else { 2.0 };
    let e = phasor_axis_error(delta);
    let eta = 2.0 * f64::sqrt(dims) * 1.1 * e + dims * e * e + 4.0 * F32_UNIT_ROUNDOFF;
    let mut drawn: std::collections::HashMap<[i32; 3], Vec<Impulse>> =
        std::collections::HashMap::new();
    let layers: &[i32] = if three_d { &[-1, 0, 1] } else { &[0] };
    let mut mask = Vec::with_capacity(window.width * window.height);
    for j in 0..window.height {
        for i in 0..window.width {
            let (px, py) = (window.x(i) / side, window.y(j) / side);
            let (cx, cy) = (px.floor(), py.floor());
            let (ux, uy) = (px - cx, py - cy);
            let mut edge = false;
            for &sz in layers {
                for sy in -1..=1 {
                    for sx in -1..=1 {
                        let c = [cx as i32 + sx, cy as i32 + sy, sz];
                        let imps = drawn.entry(c).or_insert_with(|| {
                            let mut v = Vec::new();
                            kernels.draw_cell(c, &mut v);
                            v
                        });
                        for imp in imps.iter() {
                            let d = [
                                ux - f64::from(sx) - f64::from(imp.o[0]),
                                uy - f64::from(sy) - f64::from(imp.o[1]),
                                -f64::from(sz) - f64::from(imp.o[2]),
                            ];
                            let d2 =
                                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * f64::from(imp.sharp);
                            edge |= (d2 - 1.0).abs() <= eta;
                        }
                    }
                }
            }
            mask.push(edge);
        }
    }
    mask
}

/// The export's renders of every case for each of `variants` (one pipeline each, tables in
/// a storage buffer where a model exceeds `MAX_TABLE_BYTES`): per variant, the cases' values
/// one after the other.
fn export_renders(context: &GpuContext, case: &str, variants: &[Model]) -> Vec<Vec<f32>> {
    let cases = cases();
    variants
        .iter()
        .map(|variant| {
            let exported = export(variant, &ExportOptions::default())
                .unwrap_or_else(|e| panic!("{case}: {e}"));
            let channels = variant.output_channels();
            render(
                context,
                &shader(&exported.wgsl, &cases, channels),
                channels,
                cases.len() as u32,
                &exported.tables,
            )
            .unwrap_or_else(|e| panic!("{case}: {e}"))
        })
        .collect()
}

/// `(cpu, export)` of each of `variants` for case `k` (`c`), from [`export_renders`]' output.
fn case_renders(
    variants: &[Model],
    exported: &[Vec<f32>],
    k: usize,
    c: &Case,
) -> Vec<(Vec<f32>, Vec<f32>)> {
    variants
        .iter()
        .zip(exported)
        .map(|(variant, got)| {
            let want = spectex_cpu::Evaluator::new(variant)
                .unwrap()
                .render(&c.window)
                .unwrap();
            let n = want.len();
            (want, got[k * n..(k + 1) * n].to_vec())
        })
        .collect()
}

/// A phasor model's renders of one window (`(cpu, export)` of the model, then of its Gabor,
/// intensity and phase companions) judged by phasor's own criterion (`judge_with_bound`,
/// spectex-crosscheck's pixel criterion) with [`phasor_export_bound`] for `E`, on the pixels
/// [`phasor_edge_mask`] keeps. Returns the reasons it fails and a line saying the largest
/// Gabor companion error against `E` and the pixels left out.
fn judge_phasor(
    m: &PhasorNoise,
    window: &Window,
    renders: &[(Vec<f32>, Vec<f32>)],
) -> (Vec<String>, String) {
    let far = 2.0e7;
    let e = phasor_export_bound(m, far);
    let delta = phasor_delta(m.kernel_radius(), far);
    let varying = m.dimensions == 2 && has_varying_fields(m);
    let bounds = if varying {
        let dims = 2.0;
        let axis = phasor_axis_error(delta);
        let eta = 2.0 * f64::sqrt(dims) * 1.1 * axis + dims * axis * axis + 4.0 * F32_UNIT_ROUNDOFF;
        let dx = fields::position_error(m.kernel_radius(), POSITION_ROUNDINGS, far);
        fields::field_bounds(m, window, dx, eta)
    } else {
        let edge = phasor_edge_mask(m, window, delta);
        let n = edge.len();
        fields::FieldBounds {
            edge,
            ambiguous: vec![false; n],
            extra: vec![0.0; n],
            slack: vec![0.0; n],
            duties: Vec::new(),
        }
    };
    let left = |k: usize| bounds.edge[k] || bounds.ambiguous[k];
    let per_case = bounds.edge.len();
    let keep = |v: &[f32]| -> Vec<f32> {
        v.iter()
            .enumerate()
            .filter(|(k, _)| !left(*k))
            .map(|(_, x)| *x)
            .collect()
    };
    let kept: Vec<(Vec<f32>, Vec<f32>)> = renders
        .iter()
        .map(|(want, got)| (keep(want), keep(got)))
        .collect();
    let es: Vec<f64> = (0..per_case)
        .filter(|k| !left(*k))
        .map(|k| e + bounds.extra[k])
        .collect();
    let slack: Vec<f64> = (0..per_case)
        .filter(|k| !left(*k))
        .map(|k| bounds.slack[k])
        .collect();
    let gabor = &kept[1];
    let (worst, ratio) = gabor
        .0
        .iter()
        .zip(&gabor.1)
        .zip(&es)
        .map(|((a, b), e)| {
            let d = (f64::from(*a) - f64::from(*b)).abs();
            (d, d / e)
        })
        .fold((0.0f64, 0.0f64), |(w, r), (d, q)| (w.max(d), r.max(q)));
    let edges = bounds.edge.iter().filter(|e| **e).count();
    let ambiguous = bounds.ambiguous.iter().filter(|e| **e).count();
    let largest = es.iter().copied().fold(0.0, f64::max);
    let line = format!(
        "Gabor companion max {worst:.3e} (E {e:.3e}, per pixel up to {largest:.3e}; largest \
         error/bound {ratio:.3}); {edges} of {per_case} pixels next to a kernel edge and \
         {ambiguous} ambiguous (a thinning or direction the f32 fields may decide otherwise) \
         left out"
    );
    let duties: Vec<Vec<(f64, f64)>> = if bounds.duties.is_empty() {
        Vec::new()
    } else {
        (0..per_case)
            .filter(|k| !left(*k))
            .map(|k| bounds.duties[k].clone())
            .collect()
    };
    (
        judge_with_pixel_bounds(m, &es, &slack, &duties, &kept, None),
        line,
    )
}

/// Whether a phasor model has a field that varies or a direction computed from the plane
/// (gradient, coherent): the export evaluates those in f32 ([`fields`]).
fn has_varying_fields(m: &PhasorNoise) -> bool {
    use spectex_model::Profile;
    let varies = |f: &Field| {
        let (lo, hi) = f.range();
        lo != hi
    };
    let duty = |p: &Profile| matches!(p, Profile::Square { duty } if varies(duty));
    varies(&m.bandwidth)
        || varies(&m.frequency)
        || match &m.orientation {
            PhasorOrientation::Aligned { angle } => varies(angle),
            PhasorOrientation::Gradient { .. } | PhasorOrientation::Coherent { .. } => true,
            _ => false,
        }
        || match &m.profile {
            Profile::Blend { a, b, weight } => varies(weight) || duty(a) || duty(b),
            other => duty(other),
        }
}

/// A standalone phasor model through the export, judged by [`judge_phasor`] over its and its
/// companions' exported renders. Returns the failures.
fn check_phasor(context: &GpuContext, case: &str, model: &Model, m: &PhasorNoise) -> Vec<String> {
    let mut variants = vec![model.clone()];
    variants.extend(check_kind(model).companions());
    let exported = export_renders(context, case, &variants);
    let mut failures = Vec::new();
    for (k, c) in cases().iter().enumerate() {
        let renders = case_renders(&variants, &exported, k, c);
        let (why, line) = judge_phasor(m, &c.window, &renders);
        println!("export: {case} {}: {line}", c.name);
        if !why.is_empty() {
            failures.push(format!("{case} {}: {}", c.name, why.join(", ")));
        }
    }
    failures
}

/// A combination with no pointwise bound (crossed phasor waves) through the export, judged
/// as spectex-crosscheck judges it on the compute path, by the composed verdict
/// (`tolerance::combine::composed_verdict`): the combination and every operand (each with its
/// companions) exported and rendered on their own, each operand judged as this test judges a
/// model of its kind ([`judge_phasor`] for a phasor, else `|cpu − export|` within
/// [`export_tolerance`]), and on each side the combination equal, bit for bit, to
/// `CombineOp::apply` of that side's operand renders. That relation is exact for the export
/// too: `combine_sample_cell` evaluates each operand's exported function (the same WGSL
/// function the operand's own module exports, at the same position) and applies
/// `CombineOp::apply`'s operations in its order, each an f32 operation WGSL rounds correctly
/// (`+`, `*`, `min`, `max`); a fused or reordered glue would show here as a mismatch.
fn check_combination(
    context: &GpuContext,
    case: &str,
    model: &Model,
    m: &spectex_model::Combine,
) -> Vec<String> {
    let mut variants = vec![model.clone()];
    variants.extend(check_kind(model).companions());
    let exported = export_renders(context, case, &variants);
    let mut failures = Vec::new();
    for (k, c) in cases().iter().enumerate() {
        let renders = case_renders(&variants, &exported, k, c);
        let mut judge = |i: usize, o: &Model, own: &[(Vec<f32>, Vec<f32>)]| -> Vec<String> {
            let why = if let Model::Phasor(p) = o {
                let (why, line) = judge_phasor(p, &c.window, own);
                println!("export: {case} {} operand {i}: {line}", c.name);
                why
            } else {
                let (max_allowed, mean_allowed) = export_tolerance(case, o);
                let errors: Vec<f64> = own[0]
                    .0
                    .iter()
                    .zip(&own[0].1)
                    .map(|(a, b)| (f64::from(*a) - f64::from(*b)).abs())
                    .collect();
                let worst = errors.iter().copied().fold(0.0, f64::max);
                let mean = errors.iter().sum::<f64>() / errors.len().max(1) as f64;
                println!(
                    "export: {case} {} operand {i}: max {worst:.3e} (allowed \
                     {max_allowed:.3e}), mean {mean:.3e} (allowed {mean_allowed:.3e})",
                    c.name
                );
                if errors.iter().any(|e| e.is_nan()) || worst > max_allowed || mean > mean_allowed {
                    vec![format!("max {worst:.3e}, mean {mean:.3e}")]
                } else {
                    Vec::new()
                }
            };
            why.into_iter()
                .map(|w| format!("operand {i} ({}): {w}", o.kind()))
                .collect()
        };
        let why = composed_verdict(m, &renders, &mut judge);
        println!(
            "export: {case} {}: composed verdict over {} exported modules: {}",
            c.name,
            variants.len(),
            if why.is_empty() { "passes" } else { "fails" }
        );
        if !why.is_empty() {
            failures.push(format!("{case} {}: {}", c.name, why.join(", ")));
        }
    }
    failures
}

/// A Voronoi model's discontinuous output (the cell ID, a palette colour) through the export,
/// judged as spectex-crosscheck judges it (`CheckKind::own_verdict` of the Voronoi kind):
/// every pixel equal on both sides unless the CPU's `F2 − F1` (the companion model, exported
/// and rendered too) is within the margin where the two nearest seeds may swap —
/// spectex-crosscheck's `FLIP_MARGIN` plus what the export adds: a swap needs
/// `F2 − F1 ≤ 2·(|δd_q| + |δd_n|)` more, for the seeds' vectors `d = s − f` moved by the
/// export's pixel offset `f` (`POSITION_ROUNDINGS` roundings of a number below `2C + 2`
/// pixels per axis, `/C` in cell units) and its site offsets (drawn in the shader:
/// `½ + jitter·(u − ½)` may be contracted into one fused operation, one ulp of a number
/// below 1, `u`), `√2` of that per vector. Returns the failures.
fn check_voronoi_discrete(
    context: &GpuContext,
    case: &str,
    model: &Model,
    m: &spectex_model::voronoi::VoronoiNoise,
) -> Vec<String> {
    use spectex_crosscheck::tolerance::voronoi::FLIP_MARGIN;
    let cases = cases();
    let c = f64::from(m.cell_size);
    let per_axis = POSITION_ROUNDINGS * F32_UNIT_ROUNDOFF * (2.0 * c + 2.0) / c + F32_UNIT_ROUNDOFF;
    let margin = FLIP_MARGIN + 2.0 * 2.0 * std::f64::consts::SQRT_2 * per_axis;
    let channels = m.output.channels();
    let companion = check_kind(model).companions().remove(0);
    let mut renders = Vec::new();
    for (variant, width) in [(model, channels), (&companion, 1)] {
        let module = export(variant, &ExportOptions::default())
            .unwrap_or_else(|e| panic!("{case}: {e}"))
            .wgsl;
        renders.push(
            render(
                context,
                &shader(&module, &cases, width),
                width,
                cases.len() as u32,
                &[],
            )
            .unwrap_or_else(|e| panic!("{case}: {e}")),
        );
    }
    let mut failures = Vec::new();
    for (k, c) in cases.iter().enumerate() {
        let want = spectex_cpu::Evaluator::new(model)
            .unwrap()
            .render(&c.window)
            .unwrap();
        let gaps = spectex_cpu::Evaluator::new(&companion)
            .unwrap()
            .render(&c.window)
            .unwrap();
        let pixels = gaps.len();
        let got = &renders[0][k * pixels * channels..(k + 1) * pixels * channels];
        let (mut differ, mut bad) = (0, 0);
        for ((a, b), gap) in want
            .chunks_exact(channels)
            .zip(got.chunks_exact(channels))
            .zip(&gaps)
        {
            if a != b {
                differ += 1;
                if f64::from(*gap) > margin {
                    bad += 1;
                }
            }
        }
        println!(
            "export: {case} {}: {differ} of {pixels} pixels differ, {bad} where F2 − F1 > \
             {margin:.2e}",
            c.name
        );
        if bad > 0 {
            failures.push(format!(
                "{case} {}: {bad} pixels differ where the nearest seed is unambiguous",
                c.name
            ));
        }
    }
    failures
}

/// The frame `cargo xtask bevy-check` rendered through examples/bevy-material (its
/// `BEVY_MODEL` and `BEVY_WINDOW`), named by `SPECTEX_BEVY_FRAME`: RGB f32 per pixel from an
/// `Rgba16Float` target, compared with the CPU render within [`export_tolerance`] plus the
/// target's rounding to f16 (half an ulp: `|v|·2⁻¹¹` for normal values, `2⁻²⁵` below 2⁻¹⁴).
/// Without the variable (every run but `bevy-check`'s) there is no frame and it says so.
#[test]
fn bevy_frame_matches_the_cpu() {
    let Some(path) = std::env::var_os("SPECTEX_BEVY_FRAME") else {
        println!("SKIPPED: SPECTEX_BEVY_FRAME is not set (cargo xtask bevy-check sets it)");
        return;
    };
    let (width, height, offset, scale) = (128usize, 96usize, [-37.25, 81.5], 0.75);
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models/lrp-ring.json"
    );
    let model: Model = spectex_model::from_json(&std::fs::read_to_string(file).unwrap()).unwrap();
    let want = spectex_cpu::Evaluator::new(&model)
        .unwrap()
        .render(&Window::new(width, height).at(offset, scale))
        .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let got: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(got.len(), 3 * width * height, "frame size");
    let (max_allowed, mean_allowed) = export_tolerance("lrp-ring", &model);
    let (mut worst, mut excess, mut sum) = (0.0f64, f64::NEG_INFINITY, 0.0);
    for (k, &w) in want.iter().enumerate() {
        let w = f64::from(w);
        let half_ulp = (w.abs() * 2f64.powi(-11)).max(2f64.powi(-25));
        for c in 0..3 {
            let e = (w - f64::from(got[3 * k + c])).abs();
            worst = worst.max(e);
            sum += e;
            excess = excess.max(e - (max_allowed + half_ulp));
        }
    }
    let mean = sum / (3 * width * height) as f64;
    let peak = want.iter().fold(0.0f64, |m, v| m.max(f64::from(*v).abs()));
    println!(
        "bevy-check: lrp-ring {width}x{height} at {offset:?} scale {scale}: max |cpu − bevy| \
         {worst:.3e} (allowed {max_allowed:.3e} + f16 half-ulp ≤ {:.3e}), mean {mean:.3e}",
        peak * 2f64.powi(-11)
    );
    assert!(excess <= 0.0, "a pixel exceeds its bound by {excess:.3e}");
    assert!(
        mean <= mean_allowed + peak * 2f64.powi(-11),
        "mean {mean:.3e} over {mean_allowed:.3e} + f16 rounding"
    );
}

/// A gradient orientation steered by images of 1, 2 and 3 samples along an axis (the export's
/// per-sample central differences wrap, `sample_differences` in spectex-gpu, where a sample's
/// neighbours are itself or each other), small enough that the windows cover many repeats on
/// both sides of the origin: judged as every phasor model is, against the CPU's f64 gradient.
#[test]
fn exported_gradient_orientation_wraps_small_steering_images() {
    let Some(context) = gpu_or_skip("export of gradient orientations") else {
        return;
    };
    let mut failures = Vec::new();
    for (width, height) in [(1, 3), (2, 3), (4, 1), (3, 2)] {
        let grey: Vec<f32> = (0..width * height)
            .map(|k| [0.1, 0.9, 0.35, 0.6, 0.0, 1.0][k % 6])
            .collect();
        let m = PhasorNoise {
            seed: 11,
            dimensions: 2,
            bandwidth: Field::constant(0.03),
            frequency: Field::constant(0.06),
            orientation: PhasorOrientation::Gradient {
                image: Field::Image {
                    width,
                    height,
                    grey,
                    pixel_size: 5.0,
                    min: 0.0,
                    max: 1.0,
                },
                offset: 0.7,
            },
            impulses_per_kernel: 12.0,
            profile: Profile::Sine,
            output: PhasorOutput::Profiled,
            mean: 0.5,
            amplitude: 0.5,
        };
        let case = format!("gradient {width}x{height}");
        failures.extend(check_phasor(&context, &case, &Model::Phasor(m.clone()), &m));
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// What [`check_file`] did with one model file.
enum Outcome {
    /// Not rendered: not selected by `SPECTEX_EXPORT_ONLY`, or slow and not `SPECTEX_EXPORT_ALL`.
    Skipped,
    /// The exporter refused it for a feature `REFUSED` names.
    Refused,
    /// Rendered and judged: the failures (none when it passed).
    Rendered(Vec<String>),
}

#[test]
fn exported_modules_render_the_cpu_values_in_a_fragment_shader() {
    let Some(context) = gpu_or_skip("export render test") else {
        return;
    };
    let all = std::env::var("SPECTEX_EXPORT_ALL").is_ok_and(|v| v == "1");
    // `SPECTEX_EXPORT_ONLY=a,b`: only the models whose names start with `a` or `b` (a
    // developer's shortcut; the counts are then not checked).
    let only: Option<Vec<String>> = std::env::var("SPECTEX_EXPORT_ONLY")
        .ok()
        .map(|v| v.split(',').map(str::to_owned).collect());
    // Two workers take the models in turn: lavapipe compiles a pipeline on the thread that
    // creates it, one core per compile, and the compiles are most of this test's time. (Error
    // scopes are per thread in wgpu, so each worker's `render` sees its own errors.)
    let files = model_files();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let outcomes = std::sync::Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get().min(2));
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                while let Some(file) =
                    files.get(next.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
                {
                    let outcome = check_file(&context, file, all, only.as_deref());
                    outcomes.lock().unwrap().push(outcome);
                }
            });
        }
    });
    let (mut failures, mut rendered, mut refused) = (Vec::new(), 0, 0);
    for outcome in outcomes.into_inner().unwrap() {
        match outcome {
            Outcome::Skipped => {}
            Outcome::Refused => refused += 1,
            Outcome::Rendered(f) => {
                rendered += 1;
                failures.extend(f);
            }
        }
    }
    failures.sort();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    if only.is_some() {
        println!("SPECTEX_EXPORT_ONLY is set: {rendered} models rendered, counts not checked");
        return;
    }
    assert_eq!(refused, REFUSED.len(), "refused models");
    let expected = if all { 42 } else { 42 - SLOW_ON_LAVAPIPE.len() };
    assert!(
        rendered >= expected,
        "only {rendered} models rendered through the export, {expected} expected (LRP 4, \
         Gabor 2, classic 8, texton 3, wavelet 2, phasor 5, matrix 2, Islamic 3, Voronoi 2, \
         combinations 3 (crossed waves among them), warp-lrp-by-gabor, warp-phasor-by-lrp, and with SPECTEX_EXPORT_ALL=1 \
         textures 3 and warps 4; else one of each)"
    );
}

/// Exports, renders and judges one model file (the test's module docs), printing its lines.
fn check_file(context: &GpuContext, file: &Path, all: bool, only: Option<&[String]>) -> Outcome {
    let case = file.file_stem().unwrap().to_string_lossy().into_owned();
    if only.is_some_and(|o| !o.iter().any(|p| case.starts_with(p.as_str()))) {
        return Outcome::Skipped;
    }
    if !all && SLOW_ON_LAVAPIPE.contains(&case.as_str()) {
        println!("export: {case}: left out (SPECTEX_EXPORT_ALL=1 renders it)");
        return Outcome::Skipped;
    }
    let model: Model = spectex_model::from_json(&std::fs::read_to_string(file).unwrap())
        .unwrap_or_else(|e| panic!("{case}: {e}"));
    // A tiling texture's texels and tables are a storage buffer's for any real exemplar (and
    // as constants, initialised per invocation, take lavapipe minutes a frame). A 3D wavelet's
    // planes too: as 16 KiB of `var<private>` constants, lavapipe's LLVM compiled
    // wavelet-3d-multiband's module for 6.4 minutes (bound, in a second); the constants path
    // is the other models' and naga validates this one (spectex-gpu's export test).
    let bound = matches!(model, Model::Tiling(_))
        || matches!(&model, Model::Wavelet(w) if w.dimensions == 3);
    let first = if bound {
        let buffer = ExportOptions {
            tables: TableStorage::Buffer {
                group: TABLES_GROUP,
                binding: TABLES_BINDING,
            },
            ..ExportOptions::default()
        };
        export(&model, &buffer)
    } else {
        export(&model, &ExportOptions::default())
    };
    let exported = match first {
        Err(GpuError::Unsupported { feature, .. })
            if REFUSED
                .iter()
                .any(|(m, word)| *m == case && feature.contains(word)) =>
        {
            println!("export: {case}: refused ({feature})");
            return Outcome::Refused;
        }
        // Models over MAX_TABLE_BYTES (spectex-gpu's export test lists them): their tables
        // in a storage buffer.
        Err(GpuError::LimitsExceeded { .. }) => {
            let options = ExportOptions {
                tables: TableStorage::Buffer {
                    group: TABLES_GROUP,
                    binding: TABLES_BINDING,
                },
                ..ExportOptions::default()
            };
            export(&model, &options).unwrap_or_else(|e| panic!("{case}: {e}"))
        }
        other => other.unwrap_or_else(|e| panic!("{case}: {e}")),
    };
    if let Model::Voronoi(m) = &model
        && regularity(&model).is_none()
    {
        return Outcome::Rendered(check_voronoi_discrete(context, &case, &model, m));
    }
    if let Model::Phasor(m) = &model {
        let started = std::time::Instant::now();
        let failures = check_phasor(context, &case, &model, m);
        println!(
            "export: {case}: 4 modules (the model and its companions) compiled and \
             rendered in {:.1} s",
            started.elapsed().as_secs_f64()
        );
        return Outcome::Rendered(failures);
    }
    // A combination over operands judged by their own criteria (crossed phasor waves) has
    // no pointwise bound: judged by composing its operands' verdicts, as its compute
    // cross-check is.
    if let Model::Combine(m) = &model
        && check_kind(&model).value_bound().is_none()
    {
        let started = std::time::Instant::now();
        let failures = check_combination(context, &case, &model, m);
        println!(
            "export: {case}: the combination and its operands' modules compiled and \
             rendered in {:.1} s",
            started.elapsed().as_secs_f64()
        );
        return Outcome::Rendered(failures);
    }
    let module = exported.wgsl;
    let channels = model.output_channels();
    let started = std::time::Instant::now();
    let cpu = spectex_cpu::Evaluator::new(&model).unwrap();
    let (max_allowed, mean_allowed) = export_tolerance(&case, &model);
    let cases = cases();
    let pixels = render(
        context,
        &shader(&module, &cases, channels),
        channels,
        cases.len() as u32,
        &exported.tables,
    )
    .unwrap_or_else(|e| panic!("{case}: {e}"));
    let per_case = pixels.len() / cases.len();
    let mut failures = Vec::new();
    for (c, got) in cases.iter().zip(pixels.chunks_exact(per_case)) {
        let want = cpu.render(&c.window).unwrap();
        assert_eq!(got.len(), want.len());
        let errors: Vec<f64> = want
            .iter()
            .zip(got)
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
    println!(
        "export: {case}: {} bytes of WGSL, {} bytes of buffer, compiled and rendered in {:.1} s",
        module.len(),
        exported.tables.len(),
        started.elapsed().as_secs_f64()
    );
    Outcome::Rendered(failures)
}
