//! The wgpu side every shader kind shares: [`Shaded`] builds a kind's compute pipeline (once per
//! device, through the context's pipeline cache) with the layout derived from its WGSL
//! (`layout: None`, then `get_bind_group_layout`, as wgpu's examples do: the shader is the one
//! place the layout is written), uploads its tables and records the dispatch of a tile into an
//! output buffer it is given (the render ring of `render.rs`), or renders a tile with read-back
//! for the kinds that compose tiles on the host; [`Gpu`] holds the device handles, and
//! [`ErrorScopes`] turns wgpu's validation and out-of-memory errors into [`GpuError`]s.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, mpsc};

use crate::cache::{CachedPipeline, LostFlag, PipelineCache, PipelineKey};
use crate::kernel::{
    DisplacementRange, DisplacementRead, GpuKernel, PreparedTile, ShaderKernel, Table,
    TileDisplacement, TileTables, split_timer,
};
use crate::layout::wgsl_struct;
use crate::{GpuContext, GpuError, GpuWindow, wgsl_source};

/// Side of the compute workgroups of every model shader (`@workgroup_size(8, 8, 1)`).
pub(crate) const WORKGROUP_SIDE: usize = 8;

/// Bytes of one timestamp pair (start and end of a pass), as resolved by the device.
pub(crate) const TIMESTAMP_PAIR_BYTES: u64 = 2 * wgpu::QUERY_SIZE as u64;

wgsl_struct! {
    /// `WarpParams` of `common.wgsl` (bind group 1, binding 0): whether this dispatch is
    /// displaced.
    pub(crate) struct WarpParams {
        enabled: u32,
        // Padding to a whole 16-byte uniform row, as the WGSL struct has it.
        _pad0: u32,
        _pad1: u32,
        _pad2: u32,
    }
}

/// The largest storage buffer one binding of a device with `limits` may hold: tables beyond it
/// are refused up front with [`GpuError::LimitsExceeded`].
pub(crate) fn binding_limit(limits: &wgpu::Limits) -> u64 {
    limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
}

/// The device handles a kernel keeps: it may outlive the [`GpuContext`] it was built from.
#[derive(Debug, Clone)]
pub(crate) struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub limits: wgpu::Limits,
    pub lost: LostFlag,
    /// Whether the device takes timestamp queries.
    pub timestamps: bool,
    /// The context's count of timestamped nanoseconds.
    clock: Arc<AtomicU64>,
    /// The context's pipelines.
    pipelines: Arc<PipelineCache>,
}

impl Gpu {
    pub(crate) fn new(context: &GpuContext) -> Self {
        let device = context.device().clone();
        Self {
            limits: device.limits(),
            queue: context.queue().clone(),
            timestamps: context.has_timestamps(),
            device,
            lost: context.lost_flag(),
            clock: context.kernel_clock(),
            pipelines: context.pipeline_cache(),
        }
    }

    /// The largest storage buffer one binding may hold ([`binding_limit`]).
    pub(crate) fn binding_limit(&self) -> u64 {
        binding_limit(&self.limits)
    }

    /// A buffer of `usage` holding `bytes`.
    pub(crate) fn buffer(
        &self,
        label: &str,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage,
            })
    }

    /// An uninitialised buffer of `size` bytes and `usage` (wgpu zeroes it before first use).
    pub(crate) fn empty(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    }

    /// A read-only buffer holding `table`, bound as the shader declares it: storage, or
    /// uniform ([`Table::uniform`]).
    fn table_buffer(&self, table: &Table) -> wgpu::Buffer {
        use wgpu::BufferUsages as U;
        self.buffer(table.label, &table.bytes, U::STORAGE | U::UNIFORM)
    }

    /// A query set of `pairs` timestamp pairs, where the device has timestamps.
    pub(crate) fn query_set(&self, pairs: u32) -> Option<wgpu::QuerySet> {
        self.timestamps.then(|| {
            self.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("spectex timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * pairs,
            })
        })
    }

    /// The context's count of timestamped nanoseconds so far.
    pub(crate) fn clock_nanos(&self) -> u64 {
        self.clock.load(Ordering::Relaxed)
    }

    /// Adds the dispatch time of resolved timestamp pairs (`bytes`: start, end, start, end …
    /// as `u64` ticks) to the context's clock, and returns it in nanoseconds. A pair whose end
    /// precedes its start (a device that reset its counter) counts nothing.
    pub(crate) fn clock_pairs(&self, bytes: &[u8]) -> u64 {
        let period = f64::from(self.queue.get_timestamp_period());
        let nanos: f64 = bytes
            .chunks_exact(TIMESTAMP_PAIR_BYTES as usize)
            .map(|pair| {
                let start = u64::from_le_bytes(pair[..8].try_into().unwrap_or_default());
                let end = u64::from_le_bytes(pair[8..].try_into().unwrap_or_default());
                end.saturating_sub(start) as f64 * period
            })
            .sum();
        let nanos = nanos.round() as u64;
        self.clock.fetch_add(nanos, Ordering::Relaxed);
        nanos
    }
}

/// The first `bytes` bytes of `buffer` as a binding: a tile's values in a ring slot sized for
/// the largest tile.
pub(crate) fn leading(buffer: &wgpu::Buffer, bytes: u64) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer,
        offset: 0,
        size: wgpu::BufferSize::new(bytes),
    })
}

/// The compute pipeline of `(shader, entry, constants)` on the device (`constants`: values of
/// the shader's pipeline-overridable constants), from the context's cache or built from
/// `source` (then cached), with the layouts of its first `groups` bind groups.
///
/// # Errors
/// [`GpuError::Validation`] if the device rejects the shader.
pub(crate) fn compute_pipeline(
    gpu: &Gpu,
    key: PipelineKey,
    groups: u32,
    source: impl FnOnce() -> Option<String>,
) -> Result<CachedPipeline, GpuError> {
    let (shader, entry, constants) = key.clone();
    gpu.pipelines.get_or_build(key, || {
        let source = source().ok_or_else(|| {
            GpuError::Validation(format!("shader {shader} missing from the registry"))
        })?;
        build_pipeline(gpu, shader, source, (entry, &constants), groups)
    })
}

/// The compute pipeline of `entry` in the WGSL `source` (labelled `label`), its
/// pipeline-overridable constants set to `constants`, with the layouts of its first `groups`
/// bind groups, built now and not cached (a shader written for one model: a combination's).
///
/// # Errors
/// [`GpuError::Validation`] if the device rejects the shader.
pub(crate) fn build_pipeline(
    gpu: &Gpu,
    label: &str,
    source: String,
    (entry, constants): (&str, &[(&'static str, u32)]),
    groups: u32,
) -> Result<CachedPipeline, GpuError> {
    let constants: Vec<(&str, f64)> = constants
        .iter()
        .map(|&(name, value)| (name, f64::from(value)))
        .collect();
    let device = &gpu.device;
    let scope = ErrorScopes::push(device);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    // The layout is the shader's own. A derived layout leaves out bindings the entry point
    // does not use; the shader test `model_shaders_use_every_binding_in_the_host_order`
    // keeps every declared binding used, so the host may bind them all.
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: &constants,
            ..Default::default()
        },
        cache: None,
    });
    let layouts = (0..groups)
        .map(|g| pipeline.get_bind_group_layout(g))
        .collect();
    scope.pop()?;
    Ok(CachedPipeline { pipeline, layouts })
}

/// `count` invocations in workgroups of `workgroup` laid out on a 2D grid (one dimension of a
/// dispatch is limited): the invocations per grid row, which the shader multiplies its row by,
/// and the grid.
pub(crate) fn flat_grid(gpu: &Gpu, count: u32, workgroup: u32) -> (u32, [u32; 2]) {
    let groups = count.div_ceil(workgroup).max(1);
    let across = groups.min(gpu.limits.max_compute_workgroups_per_dimension.max(1));
    (across * workgroup, [across, groups.div_ceil(across)])
}

/// The pipeline of another entry point of a kind's shader, run before the kind's own dispatch
/// ([`OwnPass::record`]: `lrp_draw`, `gabor_draw`, `texton_draw`, `phasor_bin`). It binds the
/// evaluator's own buffers (`encode_passes`' `bound`).
#[derive(Debug)]
pub(crate) struct OwnPass {
    pub(crate) gpu: Gpu,
    pub(crate) pipeline: CachedPipeline,
}

impl OwnPass {
    /// `entry` of shader `shader`, from the context's cache.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the device rejects the shader.
    pub(crate) fn new(
        context: &GpuContext,
        shader: &'static str,
        entry: &'static str,
    ) -> Result<Arc<Self>, GpuError> {
        let gpu = Gpu::new(context);
        let pipeline =
            compute_pipeline(&gpu, (shader, entry, Vec::new()), 1, || wgsl_source(shader))?;
        Ok(Arc::new(Self { gpu, pipeline }))
    }
}

/// The most bytes a tile's table written by a kind's own pass may take (draws, masks): above
/// it the pixels do the work themselves. The tables are sized for the worst cell (a Poisson
/// count at its cap, about 10× its mean), so a model with hundreds of impulses a cell would
/// otherwise ask for gigabytes a tile wherever the binding limit allows it.
pub(crate) const MAX_PASS_TABLE_BYTES: u64 = 256 << 20;

/// The box of cells a kind's own pass draws once for a tile (`gabor_draw`, `texton_draw`): the
/// cells within `reach` of the tile's pixels' cells, row-major, `cell_bytes` of records each.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DrawBox {
    /// First column and row.
    pub(crate) i0: i32,
    pub(crate) j0: i32,
    /// Columns and rows.
    pub(crate) cols: u32,
    pub(crate) rows: u32,
    /// The pass's invocations per row of its dispatch grid (one invocation a cell).
    pub(crate) stride: u32,
    /// The table's size.
    pub(crate) bytes: u64,
}

impl OwnPass {
    /// The box of cells a tile's pass draws, from the range of its pixels' cells (`range`,
    /// `CellAxes::cell_range`) widened by `reach`: `None` where the tile has no valid pixel
    /// or the table would exceed `limit` or [`MAX_PASS_TABLE_BYTES`] (the pixels then draw
    /// for themselves).
    pub(crate) fn draw_box(
        &self,
        range: [Option<(i32, i32)>; 2],
        (reach, cell_bytes): (u32, u64),
        (workgroup, limit): (u32, u64),
    ) -> Option<DrawBox> {
        let [Some((i_lo, i_hi)), Some((j_lo, j_hi))] = range else {
            return None;
        };
        let span = |lo: i32, hi: i32| u64::from(hi.abs_diff(lo)) + 1 + 2 * u64::from(reach);
        let (cols, rows) = (span(i_lo, i_hi), span(j_lo, j_hi));
        let bytes = cols * rows * cell_bytes;
        let cells = u32::try_from(cols * rows).ok()?;
        if bytes > limit.min(MAX_PASS_TABLE_BYTES) {
            return None;
        }
        Some(DrawBox {
            i0: i_lo.wrapping_sub_unsigned(reach),
            j0: j_lo.wrapping_sub_unsigned(reach),
            cols: cols as u32,
            rows: rows as u32,
            stride: flat_grid(&self.gpu, cells, workgroup).0,
            bytes,
        })
    }

    /// Records this pass for a tile (`ShaderKernel::encode_passes`), laid out by `layout`: the
    /// uniform of the one pass its tile prepared, the kind's buffers `bound` at
    /// `layout.bindings` (binding b is `bound[b − 1]`) and `target` at `layout.target`. Only
    /// an undisplaced tile prepares one: a displaced tile's pixels leave the cells a pass would
    /// have worked for, so they do that work themselves.
    ///
    /// # Errors
    /// [`GpuError::Validation`] naming the pass unless `passes` is one prepared pass and the
    /// tile is undisplaced, or for a binding `bound` lacks.
    pub(crate) fn record(
        &self,
        layout: &OwnPassLayout,
        (passes, encoder): (&[PreparedTile], &mut wgpu::CommandEncoder),
        (target, bound, displacement): (&wgpu::Buffer, &[&wgpu::Buffer], Option<&wgpu::Buffer>),
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let label = layout.label;
        let ([PreparedTile::Tables(pass)], None) = (passes, displacement) else {
            return Err(GpuError::Validation(format!(
                "{label}: needs the one pass its tile prepared and an undisplaced tile"
            )));
        };
        let gpu = &self.gpu;
        let uniform = gpu.buffer(label, &pass.uniform, wgpu::BufferUsages::UNIFORM);
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: uniform.as_entire_binding(),
        }];
        for &binding in layout.bindings {
            let buffer = bound.get(binding as usize - 1).ok_or_else(|| {
                GpuError::Validation(format!("{label}: no buffer bound at {binding}"))
            })?;
            entries.push(wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            });
        }
        entries.push(wgpu::BindGroupEntry {
            binding: layout.target,
            resource: target.as_entire_binding(),
        });
        let group_layout = self.pipeline.layouts.first().ok_or_else(|| {
            GpuError::Validation(format!("{label}: its pipeline has no bind group"))
        })?;
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: group_layout,
            entries: &entries,
        });
        let count = (layout.invocations)(&pass.uniform);
        let (_, grid) = flat_grid(gpu, count, layout.workgroup);
        let mut compute = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: timer,
        });
        compute.set_pipeline(&self.pipeline.pipeline);
        compute.set_bind_group(0, &group, &[]);
        compute.dispatch_workgroups(grid[0], grid[1], 1);
        Ok(())
    }
}

/// How a kind's own pass binds and dispatches ([`OwnPass::record`]).
#[derive(Debug)]
pub(crate) struct OwnPassLayout {
    /// The pass's label (buffers, bind group, errors).
    pub(crate) label: &'static str,
    /// The kind's bindings the pass reads, besides its uniform at 0.
    pub(crate) bindings: &'static [u32],
    /// The binding its table takes: the output's.
    pub(crate) target: u32,
    /// Its `@workgroup_size` (a flat grid).
    pub(crate) workgroup: u32,
    /// Its invocations, from its uniform's bytes.
    pub(crate) invocations: fn(&[u8]) -> u32,
}

/// The own-pass tests' check: `with` (a kernel with its pass) prepares that one pass for
/// `tile`, and renders it with the bits of `without` (the same kernel without the pass), both
/// over the resident `tables`.
#[cfg(feature = "unit-tests")]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub(crate) fn assert_own_pass_keeps_bits<K: ShaderKernel>(
    context: &GpuContext,
    (with, without): (K, K),
    tables: &[Table],
    tile: &GpuWindow,
) {
    let prepared = with
        .tile_tables(tile, TileDisplacement::None, u64::MAX)
        .unwrap();
    assert_eq!(prepared.passes.len(), 1, "{tile:?} prepares its pass");
    let bits = |k: K| -> Vec<u32> {
        let values = Shaded::boxed(context, k, tables)
            .unwrap()
            .render_tile(tile, None)
            .unwrap();
        values.into_iter().map(f32::to_bits).collect()
    };
    assert_eq!(bits(with), bits(without), "{tile:?}");
}

/// Records one dispatch of `pipeline` (one bind group) over `groups` workgroups: `params` as
/// the uniform at binding 0, then `bindings` at 1, 2, …, with `timer` writing its timestamps.
///
/// # Errors
/// [`GpuError::Validation`] for a pipeline without a bind group.
pub(crate) fn encode_pass<P: bytemuck::Pod>(
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    (label, pipeline): (&str, &CachedPipeline),
    params: &P,
    bindings: Vec<wgpu::BindingResource<'_>>,
    groups: [u32; 2],
    timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
) -> Result<(), GpuError> {
    let layout = pipeline
        .layouts
        .first()
        .ok_or_else(|| GpuError::Validation(format!("{label}: its pipeline has no bind group")))?;
    let uniform = gpu.buffer(
        label,
        bytemuck::bytes_of(params),
        wgpu::BufferUsages::UNIFORM,
    );
    let entries: Vec<wgpu::BindGroupEntry<'_>> = std::iter::once(uniform.as_entire_binding())
        .chain(bindings)
        .enumerate()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource,
        })
        .collect();
    let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    });
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: timer,
    });
    pass.set_pipeline(&pipeline.pipeline);
    pass.set_bind_group(0, &group, &[]);
    pass.dispatch_workgroups(groups[0], groups[1], 1);
    Ok(())
}

/// A [`ShaderKernel`] on the device: its pipeline (layouts derived from the shader), its tables
/// packed once, the bind group of an undisplaced dispatch made once, and the dispatch of a
/// tile. The [`GpuKernel`] of every kind with a shader.
#[derive(Debug)]
pub(crate) struct Shaded<K> {
    gpu: Gpu,
    pipeline: wgpu::ComputePipeline,
    /// Group 0 of the shader: uniform, tables, output.
    model_layout: wgpu::BindGroupLayout,
    /// Group 1: the displacement of `common.wgsl`.
    warp_layout: wgpu::BindGroupLayout,
    /// Group 1 of an undisplaced dispatch (every tile of a direct render).
    still: wgpu::BindGroup,
    /// The tables packed once, bound after the uniform.
    resident: Vec<wgpu::Buffer>,
    /// One timestamp pair for [`render_tile`](GpuKernel::render_tile)'s dispatches.
    queries: Option<wgpu::QuerySet>,
    kind: K,
}

impl<K: ShaderKernel> Shaded<K> {
    /// Uploads `resident` (the kind's tables packed once, in binding order after the uniform)
    /// and takes the kind's pipeline from the context's cache, building it the first time.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the device rejects the shader or a buffer.
    pub(crate) fn boxed(
        context: &GpuContext,
        kind: K,
        resident: &[Table],
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let gpu = Gpu::new(context);
        let CachedPipeline { pipeline, layouts } = compute_pipeline(
            &gpu,
            (K::SHADER, K::ENTRY_POINT, kind.constants()),
            2,
            || wgsl_source(K::SHADER),
        )?;
        let [model_layout, warp_layout]: [wgpu::BindGroupLayout; 2] =
            layouts.try_into().map_err(|_| {
                GpuError::Validation(format!("shader {} lacks bind group 1", K::SHADER))
            })?;
        let scope = ErrorScopes::push(&gpu.device);
        let resident = resident.iter().map(|t| gpu.table_buffer(t)).collect();
        let still = warp_group(&gpu, &warp_layout, Displacement::None);
        let queries = gpu.query_set(1);
        scope.pop()?;
        Ok(Box::new(Self {
            pipeline,
            model_layout,
            warp_layout,
            still,
            resident,
            queries,
            kind,
            gpu,
        }))
    }

    /// Records the dispatch of `tile` (displaced by `displacement` when given, with the
    /// kind's `tables` for it) writing the first `tile`-many values of `output`, with `timer`
    /// writing its timestamps; first the kind's passes that fill a table on the device (then
    /// timed from the first pass's start to the dispatch's end).
    fn record(
        &self,
        tile: &GpuWindow,
        TileTables {
            uniform,
            tables,
            passes,
        }: TileTables,
        displacement: Displacement<'_>,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let gpu = &self.gpu;
        let (width, height) = (tile.width, tile.height);
        let output_bytes = 4 * (width * height * self.kind.output_channels()) as u64;
        let uniform = gpu.buffer("params", &uniform, wgpu::BufferUsages::UNIFORM);
        let per_tile: Vec<wgpu::Buffer> = tables
            .iter()
            .map(|t| match t.on_device {
                Some(size) => gpu.empty(
                    t.label,
                    size,
                    wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                ),
                None => gpu.table_buffer(t),
            })
            .collect();
        let mut timer = timer;
        let target = tables
            .iter()
            .zip(&per_tile)
            .find_map(|(t, b)| t.on_device.map(|_| b));
        if !passes.is_empty() && target.is_none() {
            return Err(GpuError::Validation(format!(
                "{}: passes without a table for them to fill",
                K::SHADER
            )));
        }
        if let Some(target) = target {
            // With passes, the timer starts at the first one and ends with the dispatch.
            let (start, end) = if passes.is_empty() {
                (None, timer)
            } else {
                split_timer(timer)
            };
            let on_device = match displacement {
                Displacement::Device(buffer) => Some(buffer),
                Displacement::None | Displacement::Host(_) => None,
            };
            let bound: Vec<&wgpu::Buffer> = self.resident.iter().chain(&per_tile).collect();
            self.kind
                .encode_passes(tile, passes, encoder, (target, &bound, on_device), start)?;
            timer = end;
        }
        let mut entries: Vec<wgpu::BindGroupEntry<'_>> = std::iter::once(&uniform)
            .chain(&self.resident)
            .chain(&per_tile)
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: entries.len() as u32,
            resource: leading(output, output_bytes),
        });
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("spectex tile"),
            layout: &self.model_layout,
            entries: &entries,
        });
        let displaced = match displacement {
            Displacement::None => None,
            d => Some(warp_group(gpu, &self.warp_layout, d)),
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("spectex tile"),
            timestamp_writes: timer,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.set_bind_group(1, displaced.as_ref().unwrap_or(&self.still), &[]);
        pass.dispatch_workgroups(
            width.div_ceil(WORKGROUP_SIDE) as u32,
            height.div_ceil(WORKGROUP_SIDE) as u32,
            1,
        );
        Ok(())
    }
}

/// Where a dispatch's displacement (pixels, `(dx, dy)` per pixel, row-major over the tile) is.
#[derive(Clone, Copy)]
pub(crate) enum Displacement<'a> {
    /// Not displaced.
    None,
    /// On the host, uploaded with the dispatch.
    Host(&'a [f32]),
    /// On the device, written by earlier passes of the same submission.
    Device(&'a wgpu::Buffer),
}

/// Bind group 1 of a dispatch: displaced by `displacement` or not, where the displacement is
/// one unused (0, 0) (a binding holds at least one element).
fn warp_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    displacement: Displacement<'_>,
) -> wgpu::BindGroup {
    let params = WarpParams {
        enabled: u32::from(!matches!(displacement, Displacement::None)),
        ..bytemuck::Zeroable::zeroed()
    };
    let uniform = gpu.buffer(
        "warp params",
        bytemuck::bytes_of(&params),
        wgpu::BufferUsages::UNIFORM,
    );
    let uploaded;
    let values = match displacement {
        Displacement::Device(buffer) => buffer,
        Displacement::Host(d) => {
            uploaded = gpu.table_buffer(&Table::new("warp displacement", d));
            &uploaded
        }
        Displacement::None => {
            uploaded = gpu.table_buffer(&Table::new("warp displacement", &[0.0f32, 0.0]));
            &uploaded
        }
    };
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("spectex warp"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: values.as_entire_binding(),
            },
        ],
    })
}

impl<K: ShaderKernel> GpuKernel for Shaded<K> {
    fn output_channels(&self) -> usize {
        self.kind.output_channels()
    }

    /// The cap, then the storage-binding and buffer-size limits (output and per-axis tables),
    /// the dispatch limit, and what the kind adds ([`ShaderKernel::fit_tile`]).
    fn tile_size(&self, window: &GpuWindow, cap: [usize; 2]) -> Result<[usize; 2], GpuError> {
        let limit = self.gpu.binding_limit();
        let axis_bytes = self.kind.axis_bytes();
        let by_axis = (limit / axis_bytes) as usize;
        let by_dispatch =
            self.gpu.limits.max_compute_workgroups_per_dimension as usize * WORKGROUP_SIDE;
        let width = window.width.min(cap[0]).min(by_axis).min(by_dispatch);
        let by_output = (limit / self.kind.pixel_bytes()) as usize / width.max(1);
        let height = window
            .height
            .min(cap[1])
            .min(by_axis)
            .min(by_dispatch)
            .min(by_output);
        let [width, height] = self.kind.fit_tile(window, [width, height], limit)?;
        if width == 0 || height == 0 {
            return Err(GpuError::LimitsExceeded {
                what: "bytes of one tile row of the output and axis tables",
                value: axis_bytes.max(4),
                limit,
            });
        }
        Ok([width, height])
    }

    fn prepare_tile(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
        self.kind
            .tile_tables(tile, TileDisplacement::None, self.gpu.binding_limit())
            .map(PreparedTile::Tables)
    }

    fn encode_tile(
        &self,
        tile: &GpuWindow,
        tables: TileTables,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        self.record(tile, tables, Displacement::None, encoder, output, timer)
    }

    fn displacement_read(&self) -> DisplacementRead {
        self.kind.displacement_read()
    }

    fn prepare_device_displaced(
        &self,
        tile: &GpuWindow,
        range: Option<DisplacementRange>,
    ) -> Result<TileTables, GpuError> {
        let displacement = match (self.kind.displacement_read(), range) {
            (DisplacementRead::Nothing, _) => TileDisplacement::OnDevice,
            (DisplacementRead::Range, Some(range)) => TileDisplacement::Within(range),
            (read, _) => {
                return Err(GpuError::Validation(format!(
                    "{}: its tables read the displacement ({read:?}), which stays on the \
                     device without its range",
                    K::SHADER
                )));
            }
        };
        self.kind
            .tile_tables(tile, displacement, self.gpu.binding_limit())
    }

    fn encode_device_displaced(
        &self,
        tile: &GpuWindow,
        tables: TileTables,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let displaced = Displacement::Device(displacement);
        self.record(tile, tables, displaced, encoder, output, timer)
    }

    fn tile_pixels(&self) -> Option<usize> {
        self.kind.tile_pixels()
    }

    /// One dispatch read back at once (the passes of a texture, the operands of a warp or a
    /// combination), timed into the context's clock where the device has timestamps.
    fn render_tile(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError> {
        let gpu = &self.gpu;
        let values = tile.width * tile.height * self.kind.output_channels();
        let output_bytes = 4 * values as u64;
        let output = gpu.empty(
            "spectex output",
            output_bytes,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        // Built first: a texture runs its LRP passes here, each in its own error scope.
        let seen = displacement.map_or(TileDisplacement::None, TileDisplacement::Pixels);
        let tables = self.kind.tile_tables(tile, seen, gpu.binding_limit())?;
        let displaced = displacement.map_or(Displacement::None, Displacement::Host);
        let bytes = submit_and_read(
            gpu,
            self.queries.as_ref(),
            (&output, output_bytes),
            |encoder, timer| self.record(tile, tables, displaced, encoder, &output, timer),
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}

thread_local! {
    /// Nanoseconds this thread has waited in [`submit_and_read`] for the device: what a
    /// render's workers subtract from their tiles' preparation time (`render.rs`), so that it
    /// counts the host's work.
    pub(crate) static DEVICE_WAIT_NANOS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Records passes with `record` (given a timer of one pair of `queries`, where the device has
/// timestamps) in a submission of their own, and reads back the first `bytes` bytes of
/// `source` once it is done, its time added to the context's clock: a dispatch whose values
/// the host needs now (a tile the host composes, a warp's displacement range).
///
/// # Errors
/// What `record` returns; [`GpuError::DeviceLost`] where the device is lost or the map fails.
pub(crate) fn submit_and_read(
    gpu: &Gpu,
    queries: Option<&wgpu::QuerySet>,
    (source, bytes): (&wgpu::Buffer, u64),
    record: impl FnOnce(
        &mut wgpu::CommandEncoder,
        Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError>,
) -> Result<Vec<u8>, GpuError> {
    use wgpu::BufferUsages as U;
    let stamps = if queries.is_some() {
        TIMESTAMP_PAIR_BYTES
    } else {
        0
    };
    let readback = gpu.empty(
        "spectex readback",
        bytes + stamps,
        U::MAP_READ | U::COPY_DST,
    );
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("spectex read back"),
        });
    let timer = queries.map(|set| wgpu::ComputePassTimestampWrites {
        query_set: set,
        beginning_of_pass_write_index: Some(0),
        end_of_pass_write_index: Some(1),
    });
    record(&mut encoder, timer)?;
    encoder.copy_buffer_to_buffer(source, 0, &readback, 0, bytes);
    if let Some(set) = queries {
        let resolved = gpu.empty(
            "spectex timestamps",
            TIMESTAMP_PAIR_BYTES,
            U::QUERY_RESOLVE | U::COPY_SRC,
        );
        encoder.resolve_query_set(set, 0..2, &resolved, 0);
        encoder.copy_buffer_to_buffer(&resolved, 0, &readback, bytes, TIMESTAMP_PAIR_BYTES);
    }
    let index = gpu.queue.submit([encoder.finish()]);
    let waiting = std::time::Instant::now();
    let read = read_buffer(&gpu.device, &readback, &gpu.lost, Some(index));
    let waited = u64::try_from(waiting.elapsed().as_nanos()).unwrap_or(u64::MAX);
    DEVICE_WAIT_NANOS.with(|w| w.set(w.get().saturating_add(waited)));
    let mut read = read?;
    gpu.clock_pairs(&read[bytes as usize..]);
    read.truncate(bytes as usize);
    Ok(read)
}

/// Validation and out-of-memory error scopes around a group of device calls.
/// (Fields drop in order, so an early return pops the inner scope first.)
pub(crate) struct ErrorScopes {
    validation: wgpu::ErrorScopeGuard,
    out_of_memory: wgpu::ErrorScopeGuard,
}

impl ErrorScopes {
    pub(crate) fn push(device: &wgpu::Device) -> Self {
        let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
        Self {
            out_of_memory,
            validation,
        }
    }

    /// Pops both scopes (innermost first) and turns a captured error into [`GpuError`].
    pub(crate) fn pop(self) -> Result<(), GpuError> {
        let validation = pollster::block_on(self.validation.pop());
        let out_of_memory = pollster::block_on(self.out_of_memory.pop());
        match validation.or(out_of_memory) {
            None => Ok(()),
            Some(e) => Err(GpuError::Validation(e.to_string())),
        }
    }
}

/// A map of a whole buffer for reading, asked for and not yet waited on ([`Mapping::wait`]).
pub(crate) struct Mapping {
    receiver: mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
}

impl Mapping {
    /// Asks for `buffer` to be mapped for reading once the device is done with it.
    pub(crate) fn ask(buffer: &wgpu::Buffer) -> Self {
        let (sender, receiver) = mpsc::channel();
        buffer
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |result| {
                // The receiver waits in `wait`; a send error only means it is gone already.
                let _ = sender.send(result);
            });
        Self { receiver }
    }

    /// Waits for the device to finish `submission` (the latest one when `None`) and for the
    /// map; the buffer may then be read through `get_mapped_range` and must be unmapped.
    pub(crate) fn wait(
        self,
        device: &wgpu::Device,
        lost: &LostFlag,
        submission: Option<wgpu::SubmissionIndex>,
    ) -> Result<(), GpuError> {
        let polled = device.poll(wgpu::PollType::Wait {
            submission_index: submission,
            timeout: None,
        });
        let lost_reason = lost.lock().ok().and_then(|g| g.clone());
        if let Some(reason) = lost_reason {
            return Err(GpuError::DeviceLost(reason));
        }
        polled.map_err(|e| GpuError::DeviceLost(format!("waiting for the device: {e}")))?;
        match self.receiver.recv() {
            Ok(Ok(())) => Ok(()),
            Ok(Err(e)) => Err(GpuError::DeviceLost(format!("mapping the output: {e}"))),
            Err(_) => Err(GpuError::DeviceLost(
                "the output was never mapped".to_owned(),
            )),
        }
    }
}

/// Maps `buffer` once `submission` (the latest when `None`) is done, and copies its bytes out.
pub(crate) fn read_buffer(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    lost: &LostFlag,
    submission: Option<wgpu::SubmissionIndex>,
) -> Result<Vec<u8>, GpuError> {
    Mapping::ask(buffer).wait(device, lost, submission)?;
    let bytes = buffer
        .slice(..)
        .get_mapped_range()
        .map_err(|e| GpuError::DeviceLost(format!("reading the output: {e}")))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use crate::layout::check::assert_matches_wgsl;

    pub fn warp_params_match_the_wgsl() {
        // common.wgsl is prepended to every model shader; any of them holds the struct.
        assert_matches_wgsl::<super::WarpParams>("lrp", "WarpParams");
    }
}
