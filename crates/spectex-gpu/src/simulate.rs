//! Whole-grid simulations on the GPU ([`GpuSimulator`]): Gray–Scott and the cellular automata
//! of `spectex_model::simulation`, one compute dispatch per step over ping-pong storage
//! buffers (`shaders/simulate.wgsl`), from the same initial state as the CPU stepper
//! (`SimulationSpec::initial_state`, computed on the host). The automata give the CPU's cells
//! exactly; Gray–Scott evaluates the CPU's f32 expression in its order (a driver may fuse
//! `a·b + c`, so values agree within rounding, not bit for bit). Swift–Hohenberg, whose step
//! is spectral, has no GPU stepper: [`GpuSimulator::new`] refuses it with
//! [`GpuError::Unsupported`].

use wgpu::util::DeviceExt;

use spectex_model::simulation::{
    InitialState, Neighbourhood, Simulation, SimulationSpec, cell_grey,
};

use crate::GpuError;
use crate::cache::LostFlag;
use crate::context::GpuContext;
use crate::layout::wgsl_struct;
use crate::pipeline::ErrorScopes;

wgsl_struct! {
    /// `SimParams` of `simulate.wgsl`.
    pub(crate) struct SimParams {
        width: u32,
        height: u32,
        /// Life: birth | survive << 16; elementary: the rule; cyclic: states.
        rule: u32,
        /// Cyclic: threshold | moore << 8; elementary: the first drawn generation.
        extra: u32,
        feed: f32,
        kill: f32,
        du: f32,
        dv: f32,
        dt: f32,
        _pad0: u32,
        _pad1: u32,
        _pad2: u32,
    }
}

/// Steps between two submissions (and progress reports).
const STEPS_PER_SUBMIT: u64 = 64;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    GrayScott,
    Life,
    Cyclic,
    Elementary,
}

/// A simulation being stepped on a GPU.
#[derive(Debug)]
pub struct GpuSimulator {
    device: wgpu::Device,
    queue: wgpu::Queue,
    lost: LostFlag,
    spec: SimulationSpec,
    kind: Kind,
    pipeline: wgpu::ComputePipeline,
    tick: Option<wgpu::ComputePipeline>,
    /// Bind groups reading buffer set 0 (writing 1), and reading 1 (writing 0).
    bind_groups: [wgpu::BindGroup; 2],
    /// Per buffer set, the buffers holding the state (u, v or cells).
    state: [Vec<wgpu::Buffer>; 2],
    /// Elementary: the image of drawn generations.
    image: Option<wgpu::Buffer>,
    steps_done: u64,
    adapter: String,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl GpuSimulator {
    /// Uploads the initial state of `spec` and builds its pipeline.
    ///
    /// # Errors
    /// [`GpuError::Model`] naming a parameter out of range, [`GpuError::Unsupported`] for
    /// Swift–Hohenberg, [`GpuError::LimitsExceeded`] for a grid larger than a storage binding,
    /// [`GpuError::Validation`] if the device refuses a call.
    pub fn new(context: &GpuContext, spec: &SimulationSpec) -> Result<Self, GpuError> {
        spec.validate()?;
        let device = context.device().clone();
        let (w, h) = (spec.width, spec.height);
        let (kind, params) = match &spec.simulation {
            Simulation::GrayScott(p) => (
                Kind::GrayScott,
                SimParams {
                    feed: p.feed,
                    kill: p.kill,
                    du: p.du,
                    dv: p.dv,
                    dt: p.dt,
                    ..params(w, h, 0, 0)
                },
            ),
            Simulation::Life(p) => {
                let (birth, survive) = p.masks()?;
                (
                    Kind::Life,
                    params(w, h, u32::from(birth) | (u32::from(survive) << 16), 0),
                )
            }
            Simulation::Cyclic(p) => {
                let moore = u32::from(p.neighbourhood == Neighbourhood::Moore);
                (
                    Kind::Cyclic,
                    params(w, h, p.states, p.threshold | (moore << 8)),
                )
            }
            Simulation::Elementary(p) => (Kind::Elementary, params(w, h, p.rule, spec.steps)),
            Simulation::SwiftHohenberg(_) => {
                return Err(GpuError::Unsupported {
                    kind: "swift-hohenberg",
                    feature: "the semi-implicit spectral (FFT) step; run it on the CPU".to_owned(),
                });
            }
        };
        let bytes = spec.cells() as u64 * 4;
        let limit = context.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            return Err(GpuError::LimitsExceeded {
                what: "simulation grid (bytes per field)",
                value: bytes,
                limit,
            });
        }
        let scopes = ErrorScopes::push(&device);
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let buffer = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("simulate params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let (state, image, generation): ([Vec<wgpu::Buffer>; 2], _, _) = match spec.initial_state()
        {
            InitialState::Fields { u, v } => {
                let set = || {
                    vec![
                        buffer("u", bytemuck::cast_slice(&u)),
                        buffer("v", bytemuck::cast_slice(&v)),
                    ]
                };
                ([set(), set()], None, None)
            }
            InitialState::Cells(cells) => {
                let set = || vec![buffer("cells", bytemuck::cast_slice(&cells))];
                if kind == Kind::Elementary {
                    let mut img = vec![0u32; spec.cells()];
                    if spec.steps == 0 {
                        img[..cells.len()].copy_from_slice(&cells);
                    }
                    let image = buffer("elementary image", bytemuck::cast_slice(&img));
                    let generation = buffer("generation", bytemuck::bytes_of(&0u32));
                    ([set(), set()], Some(image), Some(generation))
                } else {
                    ([set(), set()], None, None)
                }
            }
            InitialState::Field(_) => {
                return Err(GpuError::Unsupported {
                    kind: "swift-hohenberg",
                    feature: "the semi-implicit spectral (FFT) step; run it on the CPU".to_owned(),
                });
            }
        };
        let mut entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }];
        match kind {
            Kind::GrayScott => entries.extend([
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, false),
                storage_entry(4, false),
            ]),
            Kind::Life | Kind::Cyclic => {
                entries.extend([storage_entry(5, true), storage_entry(6, false)]);
            }
            Kind::Elementary => entries.extend([
                storage_entry(5, true),
                storage_entry(6, false),
                storage_entry(7, false),
                storage_entry(8, false),
            ]),
        }
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("simulate"),
            entries: &entries,
        });
        let source = crate::wgsl_source("simulate").unwrap_or_default();
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("simulate.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("simulate"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let make = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        let pipeline = make(match kind {
            Kind::GrayScott => "gray_scott_step",
            Kind::Life => "life_step",
            Kind::Cyclic => "cyclic_step",
            Kind::Elementary => "elementary_step",
        });
        let tick = (kind == Kind::Elementary).then(|| make("elementary_tick"));
        let bind = |from: usize| {
            let to = 1 - from;
            let mut entries = vec![wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }];
            let n = state[from].len() as u32;
            let first = if kind == Kind::GrayScott { 1 } else { 5 };
            for (k, b) in state[from].iter().enumerate() {
                entries.push(wgpu::BindGroupEntry {
                    binding: first + k as u32,
                    resource: b.as_entire_binding(),
                });
            }
            for (k, b) in state[to].iter().enumerate() {
                entries.push(wgpu::BindGroupEntry {
                    binding: first + n + k as u32,
                    resource: b.as_entire_binding(),
                });
            }
            if let (Some(image), Some(generation)) = (&image, &generation) {
                entries.push(wgpu::BindGroupEntry {
                    binding: 7,
                    resource: image.as_entire_binding(),
                });
                entries.push(wgpu::BindGroupEntry {
                    binding: 8,
                    resource: generation.as_entire_binding(),
                });
            }
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("simulate"),
                layout: &layout,
                entries: &entries,
            })
        };
        let bind_groups = [bind(0), bind(1)];
        scopes.pop()?;
        Ok(GpuSimulator {
            queue: context.queue().clone(),
            lost: context.lost_flag(),
            device,
            spec: spec.clone(),
            kind,
            pipeline,
            tick,
            bind_groups,
            state,
            image,
            steps_done: 0,
            adapter: context.adapter_name(),
        })
    }

    /// The adapter's name.
    #[must_use]
    pub fn adapter_name(&self) -> &str {
        &self.adapter
    }

    /// Steps run so far.
    #[must_use]
    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }

    /// Advances `steps` steps, submitting them in batches and calling `on_steps` with the
    /// number of steps done after each batch (waiting for the device there).
    ///
    /// # Errors
    /// [`GpuError::Validation`] or [`GpuError::DeviceLost`].
    pub fn run(&mut self, steps: u64, on_steps: &mut dyn FnMut(u64)) -> Result<(), GpuError> {
        let (w, h) = (self.spec.width, self.spec.height);
        let groups = match self.kind {
            Kind::Elementary => (w.div_ceil(64), 1),
            _ => (w.div_ceil(16), h.div_ceil(16)),
        };
        let mut done = 0;
        while done < steps {
            let batch = (steps - done).min(STEPS_PER_SUBMIT);
            let scopes = ErrorScopes::push(&self.device);
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("simulate"),
                });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("simulate"),
                    timestamp_writes: None,
                });
                for _ in 0..batch {
                    let from = (self.steps_done % 2) as usize;
                    pass.set_pipeline(&self.pipeline);
                    pass.set_bind_group(0, &self.bind_groups[from], &[]);
                    pass.dispatch_workgroups(groups.0, groups.1, 1);
                    if let Some(tick) = &self.tick {
                        pass.set_pipeline(tick);
                        pass.dispatch_workgroups(1, 1, 1);
                    }
                    self.steps_done += 1;
                }
            }
            self.queue.submit([encoder.finish()]);
            self.wait()?;
            scopes.pop()?;
            done += batch;
            on_steps(done);
        }
        Ok(())
    }

    fn wait(&self) -> Result<(), GpuError> {
        let polled = self.device.poll(wgpu::PollType::wait_indefinitely());
        if let Some(reason) = self.lost.lock().ok().and_then(|g| g.clone()) {
            return Err(GpuError::DeviceLost(reason));
        }
        polled
            .map(|_| ())
            .map_err(|e| GpuError::DeviceLost(format!("waiting for the device: {e}")))
    }

    fn read(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let size = buffer.size();
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("simulate readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("simulate readback"),
            });
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        crate::pipeline::read_buffer(&self.device, &staging, &self.lost, None)
    }

    /// The current buffer set (the one the last step wrote).
    fn current(&self) -> &[wgpu::Buffer] {
        &self.state[(self.steps_done % 2) as usize]
    }

    /// The raw fields (Gray–Scott: `u` then `v`), or `None` for a cellular automaton.
    ///
    /// # Errors
    /// [`GpuError::DeviceLost`] if the read-back fails.
    pub fn fields(&self) -> Result<Option<Vec<Vec<f32>>>, GpuError> {
        if self.kind != Kind::GrayScott {
            return Ok(None);
        }
        self.current()
            .iter()
            .map(|b| Ok(bytemuck::pod_collect_to_vec(&self.read(b)?)))
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// The cell states (elementary: the image of drawn generations), or `None` for Gray–Scott.
    ///
    /// # Errors
    /// [`GpuError::DeviceLost`] if the read-back fails.
    pub fn cells(&self) -> Result<Option<Vec<u32>>, GpuError> {
        let buffer = match (self.kind, &self.image) {
            (Kind::GrayScott, _) => return Ok(None),
            (Kind::Elementary, Some(image)) => image,
            _ => &self.current()[0],
        };
        Ok(Some(bytemuck::pod_collect_to_vec(&self.read(buffer)?)))
    }

    /// The image shown for the current state, as `spectex_simulate::Simulator::grey`.
    ///
    /// # Errors
    /// [`GpuError::DeviceLost`] if the read-back fails.
    pub fn grey(&self) -> Result<Vec<f32>, GpuError> {
        if let Some(fields) = self.fields()? {
            return Ok(fields.into_iter().next().unwrap_or_default());
        }
        let cells = self.cells()?.unwrap_or_default();
        Ok(cells
            .iter()
            .map(|&c| cell_grey(&self.spec.simulation, c))
            .collect())
    }
}

fn params(width: u32, height: u32, rule: u32, extra: u32) -> SimParams {
    SimParams {
        width,
        height,
        rule,
        extra,
        feed: 0.0,
        kill: 0.0,
        du: 0.0,
        dv: 0.0,
        dt: 0.0,
        _pad0: 0,
        _pad1: 0,
        _pad2: 0,
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use crate::layout::check::assert_matches_wgsl;

    pub fn sim_params_match_the_wgsl() {
        assert_matches_wgsl::<super::SimParams>("simulate", "SimParams");
    }
}
