//! Finding an adapter and opening a device: [`GpuContext`].

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::GpuError;
use crate::cache::{LostFlag, PipelineCache};

/// Environment variable naming the adapter to use: the first adapter whose name contains it
/// (ignoring case) is chosen, e.g. `WGPU_ADAPTER_NAME=llvmpipe` for lavapipe.
pub const ADAPTER_NAME_ENV: &str = "WGPU_ADAPTER_NAME";

/// A wgpu device and queue: spectex's own on the chosen adapter ([`new`](Self::new)), or a
/// caller's ([`from_device`](Self::from_device)), so a wgpu or Bevy renderer renders spectex
/// into its own buffers and textures. Cheap to share by reference; evaluators keep their own
/// handles to the device, so the context may be dropped after building them.
#[derive(Debug)]
pub struct GpuContext {
    info: wgpu::AdapterInfo,
    device: wgpu::Device,
    queue: wgpu::Queue,
    lost: LostFlag,
    /// The compute pipelines built on this device, by shader and entry point.
    pipelines: Arc<PipelineCache>,
    /// Nanoseconds of every timestamped dispatch on this device so far ([`kernel_nanos`]).
    ///
    /// [`kernel_nanos`]: Self::kernel_nanos
    kernel_ns: Arc<AtomicU64>,
}

impl GpuContext {
    /// Opens a device on the adapter named by `WGPU_ADAPTER_NAME` when that is set (the first
    /// whose name contains it), else on wgpu's default high-performance adapter. The device gets
    /// the adapter's own limits, so large buffers and dispatches are allowed where the hardware
    /// allows them. Backends can be restricted with wgpu's `WGPU_BACKEND`.
    ///
    /// # Errors
    /// [`GpuError::NoAdapter`] listing the adapters found (and how to install lavapipe), or
    /// [`GpuError::RequestDevice`].
    pub fn new() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let found: Vec<String> = adapters.iter().map(describe).collect();
        let wanted = std::env::var(ADAPTER_NAME_ENV)
            .ok()
            .filter(|w| !w.trim().is_empty());
        let adapter = match &wanted {
            Some(w) => {
                let w = w.to_lowercase();
                adapters
                    .into_iter()
                    .find(|a| a.get_info().name.to_lowercase().contains(&w))
            }
            None => pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            }))
            .ok(),
        };
        let Some(adapter) = adapter else {
            return Err(GpuError::NoAdapter { found, wanted });
        };
        // Timestamp queries where the adapter has them: kernel-only time beside end-to-end.
        let required_features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
        let (device, queue) =
            pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
                label: Some("spectex-gpu"),
                required_features,
                required_limits: adapter.limits(),
                memory_hints: wgpu::MemoryHints::Performance,
                ..Default::default()
            }))?;
        let lost: LostFlag = Arc::new(Mutex::new(None));
        let flag = Arc::clone(&lost);
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut slot) = flag.lock() {
                *slot = Some(format!("{reason:?}: {message}"));
            }
        });
        Ok(Self {
            info: adapter.get_info(),
            device,
            queue,
            lost,
            pipelines: Arc::default(),
            kernel_ns: Arc::default(),
        })
    }

    /// A context on a caller's device and queue (a wgpu or Bevy renderer's own), so evaluators
    /// render into the caller's buffers and textures with no read-back
    /// ([`GpuEvaluator::render_to_buffer`](crate::GpuEvaluator::render_to_buffer)). The
    /// caller's device-lost callback is left as it is: a lost device then shows as a failed
    /// wait ([`GpuError::DeviceLost`]). Kernel timing needs the device to have been created
    /// with [`wgpu::Features::TIMESTAMP_QUERY`]; without it renders report end-to-end time only.
    #[must_use]
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue) -> Self {
        Self {
            info: device.adapter_info(),
            device,
            queue,
            lost: Arc::new(Mutex::new(None)),
            pipelines: Arc::default(),
            kernel_ns: Arc::default(),
        }
    }

    /// Whether the device was lost (its device-lost callback ran): nothing renders on it any
    /// more, and a long-lived caller opens a new context. Always `false` for a caller's device
    /// ([`from_device`](Self::from_device)), whose callback is the caller's.
    #[must_use]
    pub fn is_lost(&self) -> bool {
        self.lost.lock().map_or(true, |reason| reason.is_some())
    }

    /// The adapter's name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    #[must_use]
    pub fn adapter_name(&self) -> String {
        self.info.name.clone()
    }

    /// Everything wgpu knows about the adapter (name, vendor, device type, driver, backend).
    #[must_use]
    pub fn adapter_info(&self) -> wgpu::AdapterInfo {
        self.info.clone()
    }

    /// Whether dispatches on this device are timed by timestamp queries (the device has
    /// [`wgpu::Features::TIMESTAMP_QUERY`]).
    #[must_use]
    pub fn has_timestamps(&self) -> bool {
        self.device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Nanoseconds the device spent in spectex's timestamped dispatches on this context so far
    /// (every evaluator and every pass of a composite kind), or `None` without timestamp
    /// queries. The difference across a render is its kernel-only time when no other render
    /// runs on the context meanwhile.
    #[must_use]
    pub fn kernel_nanos(&self) -> Option<u64> {
        self.has_timestamps()
            .then(|| self.kernel_ns.load(Ordering::Relaxed))
    }

    /// The device's limits (the adapter's, as requested).
    #[must_use]
    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// The wgpu device, for callers that run their own pipelines next to spectex's.
    #[must_use]
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The wgpu queue of [`device`](Self::device).
    #[must_use]
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    pub(crate) fn lost_flag(&self) -> LostFlag {
        Arc::clone(&self.lost)
    }

    pub(crate) fn pipeline_cache(&self) -> Arc<PipelineCache> {
        Arc::clone(&self.pipelines)
    }

    pub(crate) fn kernel_clock(&self) -> Arc<AtomicU64> {
        Arc::clone(&self.kernel_ns)
    }
}

/// `name (backend, device type)` of an adapter, for error messages and reports.
fn describe(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
}
