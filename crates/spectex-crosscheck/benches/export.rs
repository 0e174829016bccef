//! The cost of an exported module (`spectex export --wgsl`) per evaluation, in calibration
//! cosines: every exportable model of `testdata/models/` is wrapped in a compute shader that
//! evaluates `spectex_sample_cell` once per pixel of a W×H grid and writes one f32 per pixel,
//! and timed beside calibration shaders of the same harness in the same run: one that only
//! writes an f32 per pixel, one that sums 450 polynomial cosines per pixel (their arguments
//! depend on the pixel, so nothing folds), and one that sums 450 draws of the randomness
//! contract (its cost per draw, in cosines, is printed: the floor under kinds whose
//! evaluations draw). Per model:
//!
//! `cal-cos/eval = (ms − ms_empty) / evaluations / ((ms_cal − ms_empty) / 450)`,
//!
//! the model's time per evaluation in units of one polynomial cosine, `ms_cal` timed again just
//! before each model (its own column): on lavapipe the same calibration ran at 2.4 ms in one
//! run and 4.5 ms in another, so a ratio to the run's first calibration drifted by as much.
//! A last row,
//! `bench-lrp-j50`, times the GPU bench's LRP model (J = 50, 4 strata) and says its time as a
//! multiple of the calibration's. Evaluations per pixel
//! are the project's own count, `spectex_cpu::Evaluator::cost_per_pixel` (cosines for LRP,
//! kernels for Gabor and phasor, octaves for classic noise — times the cells searched for
//! Worley —, lattice or tile evaluations for the other kinds): the reason this bench lives
//! here and not in spectex-gpu, which never links the CPU evaluator. Times are the fastest of
//! the repetitions, from GPU timestamp queries where the adapter has
//! `wgpu::Features::TIMESTAMP_QUERY`, else the wall time of submit + wait (both printed).
//!
//! Run: `WGPU_ADAPTER_NAME=llvmpipe cargo bench -p spectex-crosscheck --bench export` (the
//! table is printed and written to `target/bench/export.md`). Environment:
//! - `SPECTEX_BENCH_SIZE=WxH`: the grid (default 128x128 on a CPU adapter such as lavapipe,
//!   1920x1080 otherwise; e.g. 3840x2160 on a real GPU);
//! - `SPECTEX_BENCH_CELL=x,y`: the integer position of the grid's first pixel (default
//!   `1000,2000`; `10000000,10000000` times the far-from-origin case the exports keep precise);
//! - `SPECTEX_BENCH_REPS=n`: repetitions per shader (default 9);
//! - `SPECTEX_BENCH_MODELS=a,b`: only the models whose name contains one of these;
//! - `SPECTEX_BENCH_MODELS_DIR=<folder>`: the models' folder (default the repository's
//!   `testdata/models`; the GPU report's script sets it, as it runs away from the checkout);
//! - `SPECTEX_BENCH_TABLES=buffer`: every model's tables in the storage buffer (`spectex export
//!   --tables`), not only those over `MAX_TABLE_BYTES`;
//! - `SPECTEX_BENCH_ALL=1`: also the models lavapipe compiles for minutes (left out on CPU
//!   adapters otherwise, as in the export render test);
//! - `SPECTEX_BENCH_FILE=<a .wgsl file>`: time this module (e.g. an export edited by hand)
//!   instead of exporting, with the evaluations (and, for a model over `MAX_TABLE_BYTES`, the
//!   storage buffer) of the testdata model of the same name (the file name up to its first dot);
//! - `SPECTEX_BENCH_DUMP=<folder>`: write each timed module there, named after its model (to
//!   read or edit and time again with `SPECTEX_BENCH_FILE`);
//! - `SPECTEX_BENCH_RENDER=1`: time every shader (calibrations included) as a full-screen
//!   fragment shader writing an `R32Float` target instead (what a game pays). One stage per
//!   run: timing both from one module in one run gave lavapipe's compute passes timestamps
//!   of ~0 ms.
//!
//! Skips with a message when no adapter exists. Run without `--bench` (as `cargo test
//! --bench '*'` in `cargo xtask ci` does) it only checks that it starts.

#![allow(
    clippy::print_stdout,
    clippy::print_stderr,
    reason = "the table is the bench's output"
)]
#![allow(missing_docs, reason = "a bench binary")]

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use spectex_gpu::export::{ExportOptions, MAX_TABLE_BYTES, TableStorage, export};
use spectex_gpu::{GpuError, wgpu};
use spectex_model::Model;

/// Models whose exported module lavapipe compiles for tens of seconds to minutes (the export
/// render test's `SLOW_ON_LAVAPIPE`): left out on CPU adapters unless `SPECTEX_BENCH_ALL=1`.
const SLOW_ON_CPU_ADAPTERS: &[&str] = &[
    "classic-simplex-3d",
    "combine-bark",
    "combine-mix-product",
    "lrp-fractal-anisotropic",
    "texture-fitted-colour",
    "texture-synthetic-colour",
    "warp-classic-fbm",
    "warp-texture-colour",
    "warp-wavelet-by-fbm",
    // 16 KiB of planes as `var<private>` constants: 6.4 minutes of LLVM (bound, with
    // SPECTEX_BENCH_ALL=1 SPECTEX_BENCH_TABLES=buffer, it compiles in a second).
    "wavelet-3d-multiband",
    // LRP J = 50 over 4 strata: lavapipe's LLVM spends minutes in `buildCoroutineFrame`
    // since the lattice splits are written out in closed form.
    "bench-lrp-j50",
];

/// The row of the GPU bench's LRP model (J = 50, 4 strata; not a testdata file).
const BENCH_LRP: &str = "bench-lrp-j50";

/// Cosines per pixel of the calibration shader.
const CAL_COSINES: u32 = 450;

/// The harness's bind group 0: its parameters and output. An exported module's storage
/// buffer (models over `MAX_TABLE_BYTES`) is group 1, binding 0.
const HARNESS: &str = "
// ---- bench harness ----
struct BenchParams {
    width: u32,
    height: u32,
    cell: vec2<i32>,
    offset: vec2<f32>,
}
@group(0) @binding(0) var<uniform> bench: BenchParams;
@group(0) @binding(1) var<storage, read_write> bench_out: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn bench_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= bench.width || id.y >= bench.height) {
        return;
    }
    let cell = bench.cell + vec2<i32>(id.xy);
    bench_out[id.y * bench.width + id.x] = bench_value(cell, bench.offset);
}

@vertex
fn bench_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0f - 1.0f;
    return vec4<f32>(xy, 0.0f, 1.0f);
}

@fragment
fn bench_fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let cell = bench.cell + vec2<i32>(frag.xy);
    return vec4<f32>(bench_value(cell, bench.offset), 0.0f, 0.0f, 1.0f);
}
";

/// The empty calibration: one f32 from the position, written.
const EMPTY: &str = "
fn bench_value(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    return f32(cell.x & 1023) * 0.001f + f32(cell.y & 1023) * 0.002f + offset.x;
}
";

/// The cosine calibration: 450 polynomial cosines (the argument reduced to a half turn, an
/// even degree-10 polynomial of cos 2πt) of arguments depending on the pixel.
const CALIBRATION: &str = "
fn bench_pcos(turns: f32) -> f32 {
    let t = turns - round(turns);
    let u = t * t;
    return 1.0f + u * (-19.739208f + u * (64.939394f + u * (-85.456817f + u * (60.244639f
        + u * -26.426257f))));
}

fn bench_value(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let x = f32(cell.x & 1023) + offset.x;
    let y = f32(cell.y & 1023) + offset.y;
    var acc = 0.0f;
    for (var i = 0u; i < 450u; i++) {
        let k = f32(i);
        acc += bench_pcos(k * 0.618034f + x * (0.00137f + k * 1e-6f) + y * 0.00091f);
    }
    return acc;
}
";

/// The draw calibration: 450 draws of the randomness contract (`prng_next_f32` of
/// `common.wgsl`, composed before it: an LCG step, the RXS-M-XS permutation and a 24-bit
/// float), summed. Every kind draws its impulses, phases and table indexes with them and the
/// CPU's bytes fix how many an evaluation takes, so a draw's cost in calibration cosines
/// bounds what an evaluation can cost from below (LRP: a cosine and two draws; Gabor: three
/// draws, an exponential and a cosine; a phasor impulse: four draws, an exponential, a cosine
/// and a sine).
const DRAWS: &str = "
fn bench_value(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    var prng = Prng((bitcast<u32>(cell.x) * 73856093u) ^ bitcast<u32>(cell.y));
    var acc = offset.x;
    for (var i = 0u; i < 450u; i++) {
        acc += prng_next_f32(&prng);
    }
    return acc;
}
";

/// The device, and whether it writes timestamps.
struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    name: String,
    cpu: bool,
    timestamps: bool,
}

impl Gpu {
    fn new() -> Result<Self, String> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let wanted = std::env::var("WGPU_ADAPTER_NAME")
            .ok()
            .filter(|w| !w.trim().is_empty())
            .map(|w| w.to_lowercase());
        let adapter = match &wanted {
            Some(w) => adapters
                .into_iter()
                .find(|a| a.get_info().name.to_lowercase().contains(w)),
            None => pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            }))
            .ok(),
        }
        .ok_or_else(|| format!("no adapter (WGPU_ADAPTER_NAME={wanted:?})"))?;
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("export bench"),
            required_features: if timestamps {
                wgpu::Features::TIMESTAMP_QUERY
            } else {
                wgpu::Features::empty()
            },
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| e.to_string())?;
        Ok(Self {
            device,
            queue,
            name: info.name,
            cpu: info.device_type == wgpu::DeviceType::Cpu,
            timestamps,
        })
    }
}

/// The grid and the position.
#[derive(Clone, Copy)]
struct Setup {
    width: u32,
    height: u32,
    cell: [i32; 2],
    reps: usize,
    render: bool,
}

/// The fastest of one shader's repetitions (ms): wall time of submit + wait, and the GPU's
/// timestamps where it writes them.
#[derive(Clone, Copy)]
struct Timing {
    wall: f64,
    gpu: Option<f64>,
}

impl Timing {
    /// The time the figures use: the GPU's where there is one.
    fn ms(self) -> f64 {
        self.gpu.unwrap_or(self.wall)
    }
}

/// The fastest repetition: on a machine shared with other work (lavapipe runs on the CPU
/// cores) interference only ever adds time, so the minimum is the steadiest figure.
fn fastest(v: Vec<f64>) -> f64 {
    v.into_iter().fold(f64::INFINITY, f64::min)
}

/// Compiles `body` (defining `bench_value`) with the harness and times it: as a compute
/// dispatch, or as a full-screen draw when `setup.render`.
fn time_shader(gpu: &Gpu, setup: Setup, body: &str, tables: &[u8]) -> Result<Timing, String> {
    let device = &gpu.device;
    let source = format!("{body}\n{HARNESS}");
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("export bench"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let compute = (!setup.render).then(|| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("export bench"),
            layout: None,
            module: &module,
            entry_point: Some("bench_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        })
    });
    let render = setup.render.then(|| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("export bench"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("bench_vs"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("bench_fs"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: wgpu::TextureFormat::R32Float,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(e.to_string());
    }

    let pixels = u64::from(setup.width) * u64::from(setup.height);
    let mut params = Vec::with_capacity(24);
    for w in [setup.width, setup.height] {
        params.extend_from_slice(&w.to_le_bytes());
    }
    for c in setup.cell {
        params.extend_from_slice(&c.to_le_bytes());
    }
    for o in [0.25f32, 0.5] {
        params.extend_from_slice(&o.to_le_bytes());
    }
    let uniform = buffer(gpu, &params, wgpu::BufferUsages::UNIFORM);
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("export bench out"),
        size: 4 * pixels,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let table_buffer =
        (!tables.is_empty()).then(|| buffer(gpu, tables, wgpu::BufferUsages::STORAGE));
    let groups = |layout: &dyn Fn(u32) -> wgpu::BindGroupLayout, with_out: bool| {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: uniform.as_entire_binding(),
        }];
        if with_out {
            entries.push(wgpu::BindGroupEntry {
                binding: 1,
                resource: out.as_entire_binding(),
            });
        }
        let g0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout(0),
            entries: &entries,
        });
        let g1 = table_buffer.as_ref().map(|b| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &layout(1),
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: b.as_entire_binding(),
                }],
            })
        });
        (g0, g1)
    };

    let queries = gpu.timestamps.then(|| {
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: None,
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: 16,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        (set, resolve, read)
    });

    // One pass of `record` per repetition (the first a warm-up, not counted).
    let run = |record: &dyn Fn(&mut wgpu::CommandEncoder, Option<&wgpu::QuerySet>)| -> Timing {
        let (mut walls, mut gpus) = (Vec::new(), Vec::new());
        for rep in 0..=setup.reps {
            let mut encoder = device.create_command_encoder(&Default::default());
            record(&mut encoder, queries.as_ref().map(|q| &q.0));
            if let Some((set, resolve, read)) = &queries {
                encoder.resolve_query_set(set, 0..2, resolve, 0);
                encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
            }
            let start = Instant::now();
            gpu.queue.submit([encoder.finish()]);
            let _ = device.poll(wgpu::PollType::wait_indefinitely());
            let wall = start.elapsed().as_secs_f64() * 1e3;
            if let Some((_, _, read)) = &queries {
                let slice = read.slice(..);
                slice.map_async(wgpu::MapMode::Read, |_| {});
                let _ = device.poll(wgpu::PollType::wait_indefinitely());
                if let Ok(view) = slice.get_mapped_range() {
                    let t: Vec<u64> = view
                        .chunks_exact(8)
                        .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                        .collect();
                    let ns = t[1].saturating_sub(t[0]) as f64
                        * f64::from(gpu.queue.get_timestamp_period());
                    if rep > 0 {
                        gpus.push(ns * 1e-6);
                    }
                }
                read.unmap();
            }
            if rep > 0 {
                walls.push(wall);
            }
        }
        Timing {
            wall: fastest(walls),
            gpu: (!gpus.is_empty() && gpus.iter().any(|&t| t > 0.0)).then(|| fastest(gpus)),
        }
    };

    if let Some(compute) = compute {
        let (g0, g1) = groups(&|i| compute.get_bind_group_layout(i), true);
        return Ok(run(&|encoder, set| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: None,
                timestamp_writes: set.map(|query_set| wgpu::ComputePassTimestampWrites {
                    query_set,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                }),
            });
            pass.set_pipeline(&compute);
            pass.set_bind_group(0, &g0, &[]);
            if let Some(g) = &g1 {
                pass.set_bind_group(1, g, &[]);
            }
            pass.dispatch_workgroups(setup.width.div_ceil(8), setup.height.div_ceil(8), 1);
        }));
    }

    let Some(pipeline) = render else {
        return Err("no pipeline".into());
    };
    {
        let target = device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: setup.width,
                height: setup.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let view = target.create_view(&wgpu::TextureViewDescriptor::default());
        let (g0, g1) = groups(&|i| pipeline.get_bind_group_layout(i), false);
        Ok(run(&|encoder, set| {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
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
                timestamp_writes: set.map(|query_set| wgpu::RenderPassTimestampWrites {
                    query_set,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                }),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &g0, &[]);
            if let Some(g) = &g1 {
                pass.set_bind_group(1, g, &[]);
            }
            pass.draw(0..3, 0..1);
        }))
    }
}

fn buffer(gpu: &Gpu, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    let b = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: bytes.len().next_multiple_of(16) as u64,
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue.write_buffer(&b, 0, bytes);
    b
}

/// A model's exported module, with its storage buffer's bytes: its tables as constants, in
/// the storage buffer where they exceed `MAX_TABLE_BYTES` or `SPECTEX_BENCH_TABLES=buffer`.
fn model_module(model: &Model) -> Result<(String, Vec<u8>), GpuError> {
    let constants = ExportOptions::default();
    let in_buffer = ExportOptions {
        tables: TableStorage::Buffer {
            group: 1,
            binding: 0,
        },
        ..constants
    };
    let exported = if std::env::var("SPECTEX_BENCH_TABLES").is_ok_and(|v| v == "buffer") {
        export(model, &in_buffer)?
    } else {
        match export(model, &constants) {
            Err(GpuError::LimitsExceeded { limit, .. }) if limit == MAX_TABLE_BYTES => {
                export(model, &in_buffer)?
            }
            other => other?,
        }
    };
    Ok((exported.wgsl, exported.tables))
}

/// An exported module with the `bench_value` the harness calls.
fn bench_body(wgsl: &str) -> String {
    let value =
        if wgsl.contains("fn spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32") {
            "v"
        } else {
            "v.x + v.y + v.z"
        };
    format!(
        "{wgsl}\nfn bench_value(cell: vec2<i32>, offset: vec2<f32>) -> f32 {{\n    \
         let v = spectex_sample_cell(cell, offset);\n    return {value};\n}}\n"
    )
}

fn env_pair<T: std::str::FromStr>(name: &str, sep: char) -> Option<(T, T)> {
    let v = std::env::var(name).ok()?;
    let (a, b) = v.split_once(sep)?;
    Some((a.trim().parse().ok()?, b.trim().parse().ok()?))
}

/// `(ms − empty) / evaluations / ((cal − empty) / 450)`.
fn cosines(ms: f64, evaluations: f64, empty: f64, cal: f64) -> f64 {
    (ms - empty) / evaluations / ((cal - empty) / f64::from(CAL_COSINES))
}

fn main() {
    // `cargo bench` passes `--bench`; the test run of CI does not, and a full table on lavapipe
    // takes minutes.
    if !std::env::args().any(|a| a == "--bench") {
        println!("export bench: run with --bench (cargo bench) to measure");
        return;
    }
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            eprintln!("skipping the export bench: {e}");
            return;
        }
    };
    let (width, height) = env_pair("SPECTEX_BENCH_SIZE", 'x').unwrap_or(if gpu.cpu {
        (128, 128)
    } else {
        (1920, 1080)
    });
    let (cx, cy) = env_pair("SPECTEX_BENCH_CELL", ',').unwrap_or((1000, 2000));
    let setup = Setup {
        width,
        height,
        cell: [cx, cy],
        reps: std::env::var("SPECTEX_BENCH_REPS")
            .ok()
            .and_then(|r| r.parse().ok())
            .unwrap_or(9)
            .max(1),
        render: std::env::var("SPECTEX_BENCH_RENDER").is_ok_and(|v| v == "1"),
    };
    let filter: Vec<String> = std::env::var("SPECTEX_BENCH_MODELS")
        .map(|v| v.split(',').map(str::to_owned).collect())
        .unwrap_or_default();
    let all = std::env::var("SPECTEX_BENCH_ALL").is_ok_and(|v| v == "1");

    let calibrate = |body: &str, what: &str| {
        time_shader(&gpu, setup, body, &[])
            .unwrap_or_else(|e| panic!("the {what} calibration shader failed: {e}"))
    };
    let empty = calibrate(EMPTY, "empty");
    let cal = calibrate(CALIBRATION, "cosine");
    let common = spectex_gpu::shaders::wgsl_source("common").unwrap_or_default();
    let draws = calibrate(&format!("{common}\n{DRAWS}"), "draw");
    let stage = if setup.render { "fragment" } else { "compute" };
    let timing = |t: Timing| match t.gpu {
        Some(g) => format!("{g:.3} (wall {:.3})", t.wall),
        None => format!("wall {:.3}", t.wall),
    };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "Export cost per evaluation on {} ({width}×{height}, first pixel at cell ({cx}, {cy}), \
         fastest of {} repetitions; ms from {}).\n\n\
         Calibration, {stage}: empty {}, 450 polynomial cosines {} ms; 450 draws of the \
         randomness contract {} ms: one draw costs {:.2} calibration cosines.",
        gpu.name,
        setup.reps,
        if gpu.timestamps {
            "GPU timestamps"
        } else {
            "wall time of submit + wait"
        },
        timing(empty),
        timing(cal),
        timing(draws),
        cosines(draws.ms(), f64::from(CAL_COSINES), empty.ms(), cal.ms()),
    );
    let _ = writeln!(
        md,
        "\n| model | evaluations/px | {stage} ms | calibration ms | cal-cos/eval |\n\
         |---|---:|---:|---:|---:|"
    );
    print!("{md}");

    // The models' folder: `SPECTEX_BENCH_MODELS_DIR` where the bench runs away from its
    // checkout (the GPU report's machine), else the repository's `testdata/models`.
    let dir = std::env::var_os("SPECTEX_BENCH_MODELS_DIR").map_or_else(
        || {
            PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../testdata/models"
            ))
        },
        PathBuf::from,
    );
    let file_override = std::env::var_os("SPECTEX_BENCH_FILE").map(PathBuf::from);
    let mut files: Vec<PathBuf> = match &file_override {
        Some(path) => {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let model = name.split('.').next().unwrap_or_default();
            vec![dir.join(format!("{model}.json"))]
        }
        None => std::fs::read_dir(&dir)
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default(),
    };
    files.retain(|p| p.extension().is_some_and(|e| e == "json"));
    files.sort();
    let mut cases: Vec<(String, Option<PathBuf>)> = files
        .into_iter()
        .map(|file| {
            let case = file
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            (case, Some(file))
        })
        .collect();
    if file_override.is_none() {
        // The GPU bench's model (`spectex-gpu`'s `gpu` bench, the CPU's `eval` bench): LRP
        // with J = 50 cosines over 4 strata, whose export the issue times against the
        // calibration.
        cases.push((BENCH_LRP.to_owned(), None));
    }
    let mut bench_lrp_ms = None;
    for (case, file) in cases {
        if !filter.is_empty() && !filter.iter().any(|f| case.contains(f.as_str())) {
            continue;
        }
        if gpu.cpu
            && !all
            && file_override.is_none()
            && SLOW_ON_CPU_ADAPTERS.contains(&case.as_str())
        {
            continue;
        }
        let model = match &file {
            Some(file) => std::fs::read_to_string(file)
                .map_err(|e| e.to_string())
                .and_then(|t| spectex_model::from_json(&t).map_err(|e| e.to_string())),
            None => Ok(Model::Lrp(spectex_model::fixtures::lrp_four_strata(50))),
        };
        let Ok(model) = model else {
            eprintln!("{case}: unreadable");
            continue;
        };
        let exported = match &file_override {
            // The model's own tables: a module edited by hand reads the same storage buffer.
            Some(path) => std::fs::read_to_string(path)
                .map_err(|e| GpuError::Validation(format!("{}: {e}", path.display())))
                .and_then(|wgsl| Ok((wgsl, model_module(&model)?.1))),
            None => model_module(&model),
        };
        if let (Some(dir), Ok((wgsl, _))) = (std::env::var_os("SPECTEX_BENCH_DUMP"), &exported) {
            let path = PathBuf::from(dir).join(format!("{case}.wgsl"));
            if let Err(e) = std::fs::write(&path, wgsl) {
                eprintln!("could not write {}: {e}", path.display());
            }
        }
        let (body, tables) = match exported.map(|(wgsl, tables)| (bench_body(&wgsl), tables)) {
            Ok(b) => b,
            // Features the exporter refuses (Lloyd relaxation): not exportable, not timed.
            Err(e) => {
                eprintln!("{case}: not exported ({e})");
                continue;
            }
        };
        let evaluations = spectex_cpu::Evaluator::new(&model)
            .map(|e| e.cost_per_pixel())
            .unwrap_or(f64::NAN);
        // The calibration again, just before the model (module doc).
        let cal_now = calibrate(CALIBRATION, "cosine");
        let row = match time_shader(&gpu, setup, &body, &tables) {
            Ok(t) => {
                if case == BENCH_LRP {
                    bench_lrp_ms = Some((t.ms(), cal_now.ms()));
                }
                format!(
                    "| {case} | {evaluations:.1} | {:.3} | {:.3} | {:.2} |",
                    t.ms(),
                    cal_now.ms(),
                    cosines(t.ms(), evaluations, empty.ms(), cal_now.ms())
                )
            }
            Err(e) => format!(
                "| {case} | {evaluations:.1} | failed: {} | {:.3} | |",
                e.lines().next().unwrap_or(""),
                cal_now.ms()
            ),
        };
        println!("{row}");
        md.push_str(&row);
        md.push('\n');
    }
    if let Some((ms, cal_ms)) = bench_lrp_ms {
        let line = format!(
            "\n{BENCH_LRP} (LRP J = 50, 4 strata): {ms:.3} ms, {:.2}× the 450-cosine calibration \
             ({cal_ms:.3} ms, timed just before it)",
            ms / cal_ms
        );
        println!("{line}");
        md.push_str(&line);
        md.push('\n');
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(
            || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../target")),
            PathBuf::from,
        )
        .join("bench");
    let path = target.join("export.md");
    match std::fs::create_dir_all(&target).and_then(|()| std::fs::write(&path, &md)) {
        Ok(()) => println!("\nwritten to {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
}
