//! [`GpuEvaluator`]: a model packed into storage buffers once, a compute pipeline, and tiled
//! rendering of any window with read-back.

use std::sync::mpsc;

use spectex_model::{Model, Warp};

use crate::classic::{CLASSIC_AXIS_BYTES, ClassicPack};
use crate::context::LostFlag;
use crate::pack::{
    self, GABOR_AXIS_BYTES, GaborPack, LRP_AXIS_BYTES, LrpPack, WAVELET_AXIS_BYTES, WaveletPack,
};
use crate::phasor::{IMPULSE_BYTES, PhasorPack};
use crate::texture::{PLACEMENT_AXIS_BYTES, TexturePack};
use crate::{GpuContext, GpuError, GpuWindow, wgsl_source};

/// Side of the compute workgroups of every model shader (`@workgroup_size(8, 8, 1)`).
const WORKGROUP_SIDE: usize = 8;
/// Default largest tile, in pixels per side: a dispatch short enough for desktop watchdogs
/// (about 0.1 s on a discrete GPU at J = 50) and a 16 MiB output buffer.
pub const DEFAULT_MAX_TILE: usize = 2048;

/// A model prepared on the device: validated, packed into storage buffers, with its pipeline.
/// Rendering can then fail only on a bad window or a device problem.
#[derive(Debug)]
pub struct GpuEvaluator {
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter_info: wgpu::AdapterInfo,
    limits: wgpu::Limits,
    lost: LostFlag,
    /// The model shader's pipeline and its group-0 layout; `None` for a warp, which only
    /// drives its sub-evaluators.
    pipeline: Option<(wgpu::ComputePipeline, wgpu::BindGroupLayout)>,
    /// Group 1 of every model shader: the displacement convention of `common.wgsl`.
    warp_layout: wgpu::BindGroupLayout,
    model: Packed,
    max_tile: [usize; 2],
}

/// The model-specific part.
#[derive(Debug)]
enum Packed {
    Lrp {
        pack: LrpPack,
        strata: wgpu::Buffer,
        frequencies: wgpu::Buffer,
        tables: wgpu::Buffer,
    },
    Gabor {
        pack: GaborPack,
    },
    Phasor {
        pack: Box<PhasorPack>,
        profile_data: wgpu::Buffer,
    },
    Texture {
        pack: Box<TexturePack>,
        structures: wgpu::Buffer,
        blocks: wgpu::Buffer,
        cosines: wgpu::Buffer,
    },
    Classic {
        pack: ClassicPack,
        octaves: wgpu::Buffer,
    },
    /// Domain warping: x and y rendered for the tile, then the base with their displacement.
    Warp {
        model: Warp,
        /// The whole model, for [`spectex_model::warp::check_window`].
        whole: Box<Model>,
        base: Box<GpuEvaluator>,
        x: Box<GpuEvaluator>,
        y: Box<GpuEvaluator>,
    },
    Wavelet {
        pack: Box<WaveletPack>,
        tile: wgpu::Buffer,
        bands: wgpu::Buffer,
    },
}

/// The model kind's name as the JSON spells it (`Lrp`, `Texture`, …), for messages.
fn kind_name(model: &Model) -> String {
    format!("{model:?}")
        .chars()
        .take_while(|c| c.is_alphanumeric())
        .collect()
}

/// Storage buffers larger than this are refused up front with [`GpuError::LimitsExceeded`].
fn binding_limit(limits: &wgpu::Limits) -> u64 {
    limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
}

impl GpuEvaluator {
    /// Validates `model`, packs it into storage buffers and builds its compute pipeline.
    ///
    /// # Errors
    /// [`GpuError::Model`] for an invalid model, [`GpuError::LimitsExceeded`] when its tables
    /// do not fit one storage buffer, [`GpuError::Unsupported`] for a model kind without a
    /// shader, [`GpuError::Validation`] if the device rejects the shader or the buffers.
    pub fn new(context: &GpuContext, model: &Model) -> Result<Self, GpuError> {
        Self::new_at_z(context, model, 0.0)
    }

    /// As [`new`](Self::new), for the plane `z` (pixels) of a 3D model; 2D models ignore it.
    ///
    /// # Errors
    /// As [`new`](Self::new), and [`GpuError::Window`] for a `z` that is not finite or beyond
    /// [`MAX_POSITION`](crate::MAX_POSITION).
    pub fn new_at_z(context: &GpuContext, model: &Model, z: f64) -> Result<Self, GpuError> {
        model.validate()?;
        if !(z.is_finite() && z.abs() <= crate::MAX_POSITION) {
            return Err(GpuError::Window {
                parameter: "z",
                value: z,
                range: "finite, |z| ≤ 2³⁰ pixels",
            });
        }
        Self::build(context, model, z)
    }

    /// Builds a validated model. Every model shader takes the displacement of `common.wgsl`
    /// (bind group 1), so any model can be a warp's base, x or y.
    fn build(context: &GpuContext, model: &Model, z: f64) -> Result<Self, GpuError> {
        let device = context.device().clone();
        let limits = device.limits();
        let warp_layout = warp_group_layout(&device);
        if let Model::Warp(w) = model {
            let base = Self::build(context, &w.base, z)?;
            let x = Self::build(context, &w.x, z)?;
            let y = Self::build(context, &w.y, z)?;
            return Ok(Self {
                device,
                queue: context.queue().clone(),
                adapter_info: context.adapter_info(),
                limits,
                lost: context.lost_flag(),
                pipeline: None,
                warp_layout,
                model: Packed::Warp {
                    model: w.clone(),
                    whole: Box::new(model.clone()),
                    base: Box::new(base),
                    x: Box::new(x),
                    y: Box::new(y),
                },
                max_tile: [DEFAULT_MAX_TILE, DEFAULT_MAX_TILE],
            });
        }
        let scope = ErrorScopes::push(&device);
        let (shader, entry, model) = match model {
            Model::Lrp(m) => {
                let pack = pack::pack_lrp(m);
                let limit = binding_limit(&limits);
                let needed = 4 * pack.frequencies.len() as u64;
                if needed > limit {
                    return Err(GpuError::LimitsExceeded {
                        what: "frequency tables (bytes in one storage buffer)",
                        value: needed,
                        limit,
                    });
                }
                let strata = storage_buffer(&device, "lrp strata", &pack.strata);
                let frequencies = storage_buffer(&device, "lrp frequencies", &pack.frequencies);
                let tables = storage_buffer(&device, "lrp tables", &pack.tables);
                (
                    "lrp",
                    "lrp_main",
                    Packed::Lrp {
                        pack,
                        strata,
                        frequencies,
                        tables,
                    },
                )
            }
            Model::Gabor(m) => (
                "gabor",
                "gabor_main",
                Packed::Gabor {
                    pack: pack::pack_gabor(m),
                },
            ),
            Model::Phasor(m) => {
                let pack = crate::phasor::pack_phasor(m, z)?;
                let profile_data = storage_buffer(&device, "phasor profile", &pack.profile_data);
                (
                    "phasor",
                    "phasor_main",
                    Packed::Phasor {
                        pack: Box::new(pack),
                        profile_data,
                    },
                )
            }
            Model::Texture(m) => {
                let pack = crate::texture::pack_texture(context, m, binding_limit(&limits))?;
                let structures = storage_buffer(&device, "texture structures", &pack.structures);
                let blocks = storage_buffer(&device, "texture blocks", &pack.blocks);
                let cosines = storage_buffer(&device, "texture cosines", &pack.cosines);
                (
                    "texture",
                    "texture_main",
                    Packed::Texture {
                        pack: Box::new(pack),
                        structures,
                        blocks,
                        cosines,
                    },
                )
            }
            Model::Classic(m) => {
                let pack = ClassicPack::new(m, z);
                let octaves = storage_buffer(&device, "classic octaves", &pack.octaves);
                ("classic", "classic_main", Packed::Classic { pack, octaves })
            }
            Model::Wavelet(m) => {
                let pack = pack::pack_wavelet(m, z);
                let tile = storage_buffer(&device, "wavelet tile", &pack.tile);
                let bands = storage_buffer(&device, "wavelet bands", &pack.band_words);
                (
                    "wavelet",
                    "wavelet_main",
                    Packed::Wavelet {
                        pack: Box::new(pack),
                        tile,
                        bands,
                    },
                )
            }
            #[allow(unreachable_patterns)] // reason: `Model` is non_exhaustive for other crates
            other => {
                return Err(GpuError::Unsupported {
                    kind: kind_name(other),
                });
            }
        };
        let source = wgsl_source(shader).ok_or_else(|| {
            GpuError::Validation(format!("shader {shader} missing from the registry"))
        })?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(shader),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let layout = bind_group_layout(&device, &model);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(shader),
            bind_group_layouts: &[Some(&layout), Some(&warp_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(shader),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        scope.pop()?;
        Ok(Self {
            device,
            queue: context.queue().clone(),
            adapter_info: context.adapter_info(),
            limits,
            lost: context.lost_flag(),
            pipeline: Some((pipeline, layout)),
            warp_layout,
            model,
            max_tile: [DEFAULT_MAX_TILE, DEFAULT_MAX_TILE],
        })
    }

    /// Values per pixel in [`render`](Self::render)'s output: 3 for a colour texture (RGB,
    /// interleaved), 1 for every other model.
    #[must_use]
    pub fn output_channels(&self) -> usize {
        match &self.model {
            Packed::Texture { pack, .. } => pack.channels(),
            Packed::Warp { base, .. } => base.output_channels(),
            _ => 1,
        }
    }

    /// The name of the adapter this evaluator runs on.
    #[must_use]
    pub fn adapter_name(&self) -> &str {
        &self.adapter_info.name
    }

    /// Everything wgpu knows about the adapter.
    #[must_use]
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.adapter_info
    }

    /// Caps the tile size (pixels per side) used by [`render`](Self::render): smaller tiles
    /// bound the device memory and the length of one dispatch. The device's limits cap it
    /// further. Values are the same for any tile size (tests force several tiles this way).
    pub fn set_max_tile(&mut self, width: usize, height: usize) {
        self.max_tile = [width.max(1), height.max(1)];
    }

    /// The tile size `render` would use for `window`: the requested cap, then the device's
    /// storage-binding and buffer-size limits (output and per-axis tables) and its dispatch limit.
    ///
    /// # Errors
    /// [`GpuError::LimitsExceeded`] if not even a one-pixel-wide tile fits.
    pub fn tile_size(&self, window: &GpuWindow) -> Result<[usize; 2], GpuError> {
        let limit = binding_limit(&self.limits);
        if let Packed::Warp { base, x, y, .. } = &self.model {
            // Every sub-evaluator renders the same tile.
            let mut size = [
                window.width.min(self.max_tile[0]),
                window.height.min(self.max_tile[1]),
            ];
            for e in [base, x, y] {
                let [w, h] = e.tile_size(window)?;
                size = [size[0].min(w), size[1].min(h)];
            }
            return Ok(size);
        }
        let axis_bytes = match &self.model {
            Packed::Lrp { pack, .. } => LRP_AXIS_BYTES * pack.deltas.len() as u64,
            Packed::Gabor { .. } | Packed::Phasor { .. } | Packed::Warp { .. } => GABOR_AXIS_BYTES,
            Packed::Texture { .. } => PLACEMENT_AXIS_BYTES,
            Packed::Classic { pack, .. } => CLASSIC_AXIS_BYTES * pack.octave_count() as u64,
            Packed::Wavelet { pack, .. } => WAVELET_AXIS_BYTES * pack.bands.len() as u64,
        };
        // Output or a warp's displacement (2 values), plus a phasor profile's per-pixel
        // parameters (3 values); a texture's largest per-pixel buffer holds its strata and the
        // two displacements.
        let pixel_bytes = match &self.model {
            Packed::Phasor { .. } => 16,
            Packed::Texture { pack, .. } => 4 * (pack.channels() as u64 + 2),
            _ => 8,
        };
        let by_axis = (limit / axis_bytes) as usize;
        let by_dispatch =
            self.limits.max_compute_workgroups_per_dimension as usize * WORKGROUP_SIDE;
        let width = window
            .width
            .min(self.max_tile[0])
            .min(by_axis)
            .min(by_dispatch);
        let by_output = (limit / pixel_bytes) as usize / width.max(1);
        let mut height = window
            .height
            .min(self.max_tile[1])
            .min(by_axis)
            .min(by_dispatch)
            .min(by_output);
        let mut width = width;
        if let Packed::Phasor { pack, .. } = &self.model {
            // The tile's box of kernel cells must fit one buffer, with room for a Poisson
            // count well above its mean (1.5λ + 4 impulses per cell).
            let per_cell = (1.5 * pack.lambda + 4.0) * IMPULSE_BYTES as f64;
            while width > 1 || height > 1 {
                if pack.box_cells(width, height, window.scale) * per_cell <= limit as f64 / 2.0 {
                    break;
                }
                width = width.div_ceil(2);
                height = height.div_ceil(2);
            }
        }
        if let Packed::Texture { pack, .. } = &self.model {
            // Each LRP pass renders the same tile in one dispatch: it must fit them all.
            for e in pack.evaluators() {
                let [w, h] = e.tile_size(window)?;
                width = width.min(w);
                height = height.min(h);
            }
        }
        if width == 0 || height == 0 {
            return Err(GpuError::LimitsExceeded {
                what: "bytes of one tile row of the output and axis tables",
                value: axis_bytes.max(4),
                limit,
            });
        }
        Ok([width, height])
    }

    /// Renders `window` row-major (`width × height × output_channels` values, channels
    /// interleaved per pixel as on the CPU), tile by tile, reading each tile back; the size is
    /// bounded only by host memory. Tiling does not change any value.
    ///
    /// # Errors
    /// [`GpuError::Window`] for a window out of range; [`GpuError::Validation`],
    /// [`GpuError::DeviceLost`] for device problems.
    pub fn render(&self, window: &GpuWindow) -> Result<Vec<f32>, GpuError> {
        window.validate()?;
        if let Packed::Warp { whole, .. } = &self.model {
            spectex_model::warp::check_window(whole, window)?;
        }
        let [tile_width, tile_height] = self.tile_size(window)?;
        let channels = self.output_channels();
        let mut out = vec![0.0f32; window.width * window.height * channels];
        for ty in (0..window.height).step_by(tile_height) {
            for tx in (0..window.width).step_by(tile_width) {
                let tile = window.tile(
                    tx,
                    ty,
                    tile_width.min(window.width - tx),
                    tile_height.min(window.height - ty),
                );
                let values = self.render_tile(&tile)?;
                for (row, line) in values.chunks_exact(tile.width * channels).enumerate() {
                    let start = ((ty + row) * window.width + tx) * channels;
                    out[start..start + line.len()].copy_from_slice(line);
                }
            }
        }
        Ok(out)
    }

    /// One dispatch over a window that fits the device's limits (for a texture, after the LRP
    /// dispatches of its strata and turbulence).
    pub(crate) fn render_tile(&self, tile: &GpuWindow) -> Result<Vec<f32>, GpuError> {
        self.render_tile_displaced(tile, None)
    }

    /// [`render_tile`](Self::render_tile) at positions displaced by `displacement` (pixels,
    /// `(dx, dy)` per pixel interleaved, row-major over the tile), bound as group 1 of the model
    /// shader (`common.wgsl`). A warp renders its x and y at the (displaced) positions, adds
    /// their clamped displacement in f32, and renders its base displaced by the sum.
    pub(crate) fn render_tile_displaced(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError> {
        let device = &self.device;
        if let Packed::Warp {
            model, base, x, y, ..
        } = &self.model
        {
            let vx = x.render_tile_displaced(tile, displacement)?;
            let vy = y.render_tile_displaced(tile, displacement)?;
            let mut total = Vec::with_capacity(2 * vx.len());
            for (k, (a, b)) in vx.iter().zip(&vy).enumerate() {
                let d = [model.displacement(*a), model.displacement(*b)];
                match displacement {
                    Some(outer) => total.extend([outer[2 * k] + d[0], outer[2 * k + 1] + d[1]]),
                    None => total.extend(d),
                }
            }
            return base.render_tile_displaced(tile, Some(&total));
        }
        let Some((pipeline, layout)) = &self.pipeline else {
            return Err(GpuError::Validation(
                "internal: a model shader without its pipeline".to_owned(),
            ));
        };
        // A texture's LRP passes run first, each in its own error scope.
        let texture_tile = match &self.model {
            Packed::Texture { pack, .. } => Some(pack.tile(tile, displacement)?),
            _ => None,
        };
        let scope = ErrorScopes::push(device);
        let (width, height) = (tile.width, tile.height);
        let output_bytes = 4 * (width * height * self.output_channels()) as u64;
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("spectex output"),
            size: output_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("spectex readback"),
            size: output_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut extra: Vec<wgpu::Buffer> = Vec::new();
        let (uniform, columns, rows) = match &self.model {
            Packed::Lrp { pack, .. } => {
                let params = [
                    width as u32,
                    height as u32,
                    pack.deltas.len() as u32,
                    pack.seed,
                    pack.mean.to_bits(),
                    0,
                    0,
                    0,
                ];
                (
                    params.to_vec(),
                    pack::lrp_axis(&pack.deltas, width, pack::columns(tile)),
                    pack::lrp_axis(&pack.deltas, height, pack::rows(tile)),
                )
            }
            Packed::Gabor { pack } => {
                let mut params = pack.params;
                params[0] = width as u32;
                params[1] = height as u32;
                (
                    params.to_vec(),
                    pack::gabor_axis(pack.radius, width, pack::columns(tile)),
                    pack::gabor_axis(pack.radius, height, pack::rows(tile)),
                )
            }
            Packed::Phasor { pack, .. } => {
                let t = pack.tile(tile, binding_limit(&self.limits), displacement)?;
                extra.push(storage_buffer(device, "phasor cells", &t.cells));
                extra.push(storage_buffer(device, "phasor impulses", &t.impulses));
                extra.push(storage_buffer(
                    device,
                    "phasor pixel params",
                    &t.pixel_params,
                ));
                (t.params, t.columns, t.rows)
            }
            Packed::Texture { .. } => {
                let t = texture_tile.ok_or_else(|| {
                    GpuError::Validation("texture tile tables missing".to_owned())
                })?;
                extra.push(storage_buffer(device, "texture values", &t.values));
                (t.params, t.columns, t.rows)
            }
            Packed::Classic { pack, .. } => {
                let mut params = pack.params;
                params[0] = width as u32;
                params[1] = height as u32;
                (
                    params.to_vec(),
                    pack.axis(width, pack::columns(tile)),
                    pack.axis(height, pack::rows(tile)),
                )
            }
            Packed::Warp { .. } => {
                return Err(GpuError::Validation(
                    "internal: a warp has no shader of its own".to_owned(),
                ));
            }
            Packed::Wavelet { pack, .. } => {
                let params = [
                    width as u32,
                    height as u32,
                    pack.bands.len() as u32,
                    pack.n,
                    pack.dimensions,
                    pack.mean.to_bits(),
                    0,
                    0,
                ];
                (
                    params.to_vec(),
                    pack::wavelet_axis(pack, 0, width, pack::columns(tile)),
                    pack::wavelet_axis(pack, 1, height, pack::rows(tile)),
                )
            }
        };
        let uniform = init_buffer(device, "params", &uniform, wgpu::BufferUsages::UNIFORM);
        let columns = storage_buffer(device, "columns", &columns);
        let rows = storage_buffer(device, "rows", &rows);
        let mut buffers: Vec<&wgpu::Buffer> = vec![&uniform];
        if let Packed::Lrp {
            strata,
            frequencies,
            tables,
            ..
        } = &self.model
        {
            buffers.extend([strata, frequencies, tables]);
        }
        if let Packed::Phasor { profile_data, .. } = &self.model {
            buffers.push(profile_data);
        }
        if let Packed::Texture {
            structures,
            blocks,
            cosines,
            ..
        } = &self.model
        {
            buffers.extend([structures, blocks, cosines]);
        }
        if let Packed::Classic { octaves, .. } = &self.model {
            buffers.push(octaves);
        }
        if let Packed::Wavelet { tile, bands, .. } = &self.model {
            buffers.extend([tile, bands]);
        }
        buffers.extend(extra.iter());
        buffers.extend([&columns, &rows, &output]);
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("spectex tile"),
            layout,
            entries: &entries,
        });
        let warp_uniform = init_buffer(
            device,
            "warp params",
            &[u32::from(displacement.is_some()), 0, 0, 0],
            wgpu::BufferUsages::UNIFORM,
        );
        let warp_words: Vec<u32> =
            displacement.map_or_else(|| vec![0, 0], |d| d.iter().map(|v| v.to_bits()).collect());
        let warp_buffer = storage_buffer(device, "warp displacement", &warp_words);
        let warp_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("spectex warp"),
            layout: &self.warp_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: warp_uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: warp_buffer.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("spectex tile"),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("spectex tile"),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_bind_group(1, &warp_group, &[]);
            pass.dispatch_workgroups(
                width.div_ceil(WORKGROUP_SIDE) as u32,
                height.div_ceil(WORKGROUP_SIDE) as u32,
                1,
            );
        }
        encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, output_bytes);
        self.queue.submit([encoder.finish()]);
        scope.pop()?;
        let bytes = read_buffer(device, &readback, &self.lost)?;
        Ok(bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }
}

/// Validation and out-of-memory error scopes around a group of device calls.
/// (Fields drop in order, so an early return pops the inner scope first.)
struct ErrorScopes {
    validation: wgpu::ErrorScopeGuard,
    out_of_memory: wgpu::ErrorScopeGuard,
}

impl ErrorScopes {
    fn push(device: &wgpu::Device) -> Self {
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        Self {
            out_of_memory,
            validation,
        }
    }

    /// Pops both scopes (innermost first) and turns a captured error into [`GpuError`].
    fn pop(self) -> Result<(), GpuError> {
        let validation = pollster::block_on(self.validation.pop());
        let out_of_memory = pollster::block_on(self.out_of_memory.pop());
        match validation.or(out_of_memory) {
            None => Ok(()),
            Some(e) => Err(GpuError::Validation(e.to_string())),
        }
    }
}

/// Maps `buffer`, waits for the device, and copies its bytes out.
fn read_buffer(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    lost: &LostFlag,
) -> Result<Vec<u8>, GpuError> {
    let slice = buffer.slice(..);
    let (sender, receiver) = mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // The receiver waits below; a send error only means it is gone already.
        let _ = sender.send(result);
    });
    let polled = device.poll(wgpu::PollType::wait_indefinitely());
    let lost_reason = lost.lock().ok().and_then(|g| g.clone());
    if let Some(reason) = lost_reason {
        return Err(GpuError::DeviceLost(reason));
    }
    polled.map_err(|e| GpuError::DeviceLost(format!("waiting for the device: {e}")))?;
    match receiver.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(GpuError::DeviceLost(format!("mapping the output: {e}"))),
        Err(_) => {
            return Err(GpuError::DeviceLost(
                "the output was never mapped".to_owned(),
            ));
        }
    }
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::DeviceLost(format!("reading the output: {e}")))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// A read-only storage buffer holding `words`.
fn storage_buffer(device: &wgpu::Device, label: &str, words: &[u32]) -> wgpu::Buffer {
    init_buffer(device, label, words, wgpu::BufferUsages::STORAGE)
}

/// A buffer of `usage` initialised with `words` (at least one word, as bindings must not be
/// empty).
fn init_buffer(
    device: &wgpu::Device,
    label: &str,
    words: &[u32],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    let mut bytes = pack::bytes(words);
    if bytes.is_empty() {
        bytes.resize(4, 0);
    }
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &bytes,
        usage,
    })
}

/// Group 1 of every model shader (`common.wgsl`): the warp uniform and the per-pixel
/// displacement.
fn warp_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("spectex warp"),
        entries: &[
            buffer_entry(0, wgpu::BufferBindingType::Uniform),
            buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: true }),
        ],
    })
}

/// A compute-stage buffer binding of a bind group layout.
fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The bind group layout of a model's shader: binding 0 the uniform parameters, then read-only
/// storage buffers, and last the output.
fn bind_group_layout(device: &wgpu::Device, model: &Packed) -> wgpu::BindGroupLayout {
    let read_only = match model {
        Packed::Lrp { .. } => 5,
        Packed::Gabor { .. } => 2,
        Packed::Classic { .. } => 3,
        Packed::Wavelet { .. } => 4,
        Packed::Phasor { .. } | Packed::Texture { .. } => 6,
        Packed::Warp { .. } => 0,
    };
    let mut entries = vec![buffer_entry(0, wgpu::BufferBindingType::Uniform)];
    for binding in 1..=read_only {
        entries.push(buffer_entry(
            binding,
            wgpu::BufferBindingType::Storage { read_only: true },
        ));
    }
    entries.push(buffer_entry(
        read_only + 1,
        wgpu::BufferBindingType::Storage { read_only: false },
    ));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("spectex model"),
        entries: &entries,
    })
}
