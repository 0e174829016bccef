//! The wgpu side every shader kind shares: [`Shaded`] builds a kind's compute pipeline (once per
//! device: [`PipelineCache`]) with the layout derived from its WGSL (`layout: None`, then
//! `get_bind_group_layout`, as wgpu's examples do: the shader is the one place the layout is
//! written), uploads its tables, dispatches a tile and reads it back; [`Gpu`] holds the device
//! handles, and [`ErrorScopes`] turns wgpu's validation and out-of-memory errors into
//! [`GpuError`]s.

use std::collections::HashMap;
use std::sync::{Mutex, mpsc};

use crate::context::LostFlag;
use crate::kernel::{GpuKernel, ShaderKernel, Table, TileTables};
use crate::layout::wgsl_struct;
use crate::{GpuContext, GpuError, GpuWindow, wgsl_source};

/// Side of the compute workgroups of every model shader (`@workgroup_size(8, 8, 1)`).
pub(crate) const WORKGROUP_SIDE: usize = 8;

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
    lost: LostFlag,
}

impl Gpu {
    pub(crate) fn new(context: &GpuContext) -> Self {
        let device = context.device().clone();
        Self {
            limits: device.limits(),
            queue: context.queue().clone(),
            device,
            lost: context.lost_flag(),
        }
    }

    /// The largest storage buffer one binding may hold ([`binding_limit`]).
    pub(crate) fn binding_limit(&self) -> u64 {
        binding_limit(&self.limits)
    }

    /// A buffer of `usage` holding `bytes`.
    fn buffer(&self, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage,
            })
    }

    /// A read-only storage buffer holding `table`.
    fn storage(&self, table: &Table) -> wgpu::Buffer {
        self.buffer(table.label, &table.bytes, wgpu::BufferUsages::STORAGE)
    }
}

/// A compute pipeline and the two bind group layouts derived from its shader.
#[derive(Debug, Clone)]
struct CachedPipeline {
    pipeline: wgpu::ComputePipeline,
    model_layout: wgpu::BindGroupLayout,
    warp_layout: wgpu::BindGroupLayout,
}

/// The compute pipelines a [`GpuContext`] has built, by `(shader, entry point)`. A kind's shader
/// source is fixed by its name ([`wgsl_source`]), so every evaluator of that kind on the device
/// shares one pipeline: building a pipeline compiles the shader (on lavapipe, LLVM: 0.1 s to
/// seconds per shader), where a model's own data lives in its uniform and tables.
#[derive(Debug, Default)]
pub(crate) struct PipelineCache(Mutex<HashMap<(&'static str, &'static str), CachedPipeline>>);

impl PipelineCache {
    /// The cached pipeline of `(shader, entry)`, or the one `build` makes (then cached). A
    /// poisoned lock (a panic while another thread held it) only loses the cache: the pipeline
    /// is built again.
    fn get_or_build(
        &self,
        key: (&'static str, &'static str),
        build: impl FnOnce() -> Result<CachedPipeline, GpuError>,
    ) -> Result<CachedPipeline, GpuError> {
        if let Some(hit) = self.0.lock().ok().and_then(|m| m.get(&key).cloned()) {
            return Ok(hit);
        }
        let built = build()?;
        if let Ok(mut map) = self.0.lock() {
            map.insert(key, built.clone());
        }
        Ok(built)
    }
}

/// A [`ShaderKernel`] on the device: its pipeline (layouts derived from the shader), its tables
/// packed once, and the dispatch of a tile. The [`GpuKernel`] of every kind with a shader.
#[derive(Debug)]
pub(crate) struct Shaded<K> {
    gpu: Gpu,
    pipeline: wgpu::ComputePipeline,
    /// Group 0 of the shader: uniform, tables, output.
    model_layout: wgpu::BindGroupLayout,
    /// Group 1: the displacement of `common.wgsl`.
    warp_layout: wgpu::BindGroupLayout,
    /// The tables packed once, bound after the uniform.
    resident: Vec<wgpu::Buffer>,
    kind: K,
}

impl<K: ShaderKernel> Shaded<K> {
    /// Uploads `resident` (the kind's tables packed once, in binding order after the uniform)
    /// and takes the kind's pipeline from the context's [`PipelineCache`], building it the
    /// first time.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the device rejects the shader or a buffer.
    pub(crate) fn boxed(
        context: &GpuContext,
        kind: K,
        resident: &[Table],
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let gpu = Gpu::new(context);
        let device = &gpu.device;
        let cached = context
            .pipeline_cache()
            .get_or_build((K::SHADER, K::ENTRY_POINT), || {
                let source = wgsl_source(K::SHADER).ok_or_else(|| {
                    GpuError::Validation(format!("shader {} missing from the registry", K::SHADER))
                })?;
                let scope = ErrorScopes::push(device);
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(K::SHADER),
                    source: wgpu::ShaderSource::Wgsl(source.into()),
                });
                // The layout is the shader's own. A derived layout leaves out bindings the entry
                // point does not use; the shader test `every_binding_is_used_by_its_entry_point`
                // keeps every declared binding used, so the host may bind them all.
                let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(K::SHADER),
                    layout: None,
                    module: &module,
                    entry_point: Some(K::ENTRY_POINT),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    cache: None,
                });
                let model_layout = pipeline.get_bind_group_layout(0);
                let warp_layout = pipeline.get_bind_group_layout(1);
                scope.pop()?;
                Ok(CachedPipeline {
                    pipeline,
                    model_layout,
                    warp_layout,
                })
            })?;
        let CachedPipeline {
            pipeline,
            model_layout,
            warp_layout,
        } = cached;
        let scope = ErrorScopes::push(device);
        let resident = resident.iter().map(|t| gpu.storage(t)).collect();
        scope.pop()?;
        Ok(Box::new(Self {
            pipeline,
            model_layout,
            warp_layout,
            resident,
            kind,
            gpu,
        }))
    }
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

    fn render_tile(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError> {
        // Built first: a texture runs its LRP passes here, each in its own error scope.
        let TileTables { uniform, tables } =
            self.kind
                .tile_tables(tile, displacement, self.gpu.binding_limit())?;
        let gpu = &self.gpu;
        let device = &gpu.device;
        let scope = ErrorScopes::push(device);
        let (width, height) = (tile.width, tile.height);
        let output_bytes = 4 * (width * height * self.kind.output_channels()) as u64;
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
        let uniform = gpu.buffer("params", &uniform, wgpu::BufferUsages::UNIFORM);
        let per_tile: Vec<wgpu::Buffer> = tables.iter().map(|t| gpu.storage(t)).collect();
        let buffers = std::iter::once(&uniform)
            .chain(&self.resident)
            .chain(&per_tile)
            .chain([&output]);
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("spectex tile"),
            layout: &self.model_layout,
            entries: &entries,
        });
        let warp_params = WarpParams {
            enabled: u32::from(displacement.is_some()),
            ..bytemuck::Zeroable::zeroed()
        };
        let warp_uniform = gpu.buffer(
            "warp params",
            bytemuck::bytes_of(&warp_params),
            wgpu::BufferUsages::UNIFORM,
        );
        // Disabled, the displacement is one unused (0, 0): a binding holds at least one element.
        let warp_buffer = gpu.storage(&Table::new(
            "warp displacement",
            displacement.map_or(&[0.0f32, 0.0][..], |d| d),
        ));
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
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_bind_group(1, &warp_group, &[]);
            pass.dispatch_workgroups(
                width.div_ceil(WORKGROUP_SIDE) as u32,
                height.div_ceil(WORKGROUP_SIDE) as u32,
                1,
            );
        }
        encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, output_bytes);
        gpu.queue.submit([encoder.finish()]);
        scope.pop()?;
        let bytes = read_buffer(device, &readback, &gpu.lost)?;
        Ok(bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }
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

/// Maps `buffer`, waits for the device, and copies its bytes out.
pub(crate) fn read_buffer(
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

#[cfg(test)]
mod tests {
    use crate::layout::check::assert_matches_wgsl;

    #[test]
    fn warp_params_match_the_wgsl() {
        // common.wgsl is prepended to every model shader; any of them holds the struct.
        assert_matches_wgsl::<super::WarpParams>("lrp", "WarpParams");
    }
}
