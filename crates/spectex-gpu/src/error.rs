//! The error type of spectex-gpu: finding a device, validating inputs, and running on it.

use spectex_model::ModelError;

/// How to get a software Vulkan adapter on Debian or Ubuntu, quoted in [`GpuError::NoAdapter`].
pub const LAVAPIPE_HINT: &str = "for a software Vulkan adapter install lavapipe \
    (`apt-get install mesa-vulkan-drivers libvulkan1`) and select it with \
    WGPU_ADAPTER_NAME=llvmpipe";

/// Why the GPU evaluator could not start or could not render.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    /// No usable adapter, or none whose name contains `WGPU_ADAPTER_NAME`.
    #[error(
        "no GPU adapter{}; adapters found: {}; {LAVAPIPE_HINT}",
        wanted.as_ref().map(|w| format!(" whose name contains {w:?} (WGPU_ADAPTER_NAME)")).unwrap_or_default(),
        if found.is_empty() { "none".to_owned() } else { found.join(", ") }
    )]
    NoAdapter {
        /// Every adapter wgpu enumerated (name, backend, device type).
        found: Vec<String>,
        /// The substring asked for through `WGPU_ADAPTER_NAME`, if any.
        wanted: Option<String>,
    },
    /// The adapter refused to create a device.
    #[error("the GPU adapter refused to create a device: {0}")]
    RequestDevice(#[from] wgpu::RequestDeviceError),
    /// The device was lost (driver reset, out of memory, destroyed) or stopped answering.
    #[error("the GPU device was lost: {0}")]
    DeviceLost(String),
    /// An input needs more than the device allows in one buffer or dispatch.
    #[error("{what} = {value} exceeds the device limit {limit}")]
    LimitsExceeded {
        /// What was measured, with its unit.
        what: &'static str,
        /// The size needed.
        value: u64,
        /// The device's limit.
        limit: u64,
    },
    /// A caller's output (a slice, a device buffer) does not fit the render.
    #[error("output {what} = {value}: expected {expected}")]
    Output {
        /// What was measured, with its unit.
        what: &'static str,
        /// The value found.
        value: u64,
        /// What the render needs.
        expected: String,
    },
    /// A caller's texture of a format the renders do not write.
    #[error("target texture format {found}: expected one of {expected}")]
    TextureFormat {
        /// The texture's format.
        found: String,
        /// The formats a render writes.
        expected: String,
    },
    /// wgpu reported a validation or out-of-memory error (caught by an error scope).
    #[error("GPU validation error: {0}")]
    Validation(String),
    /// The model failed validation.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The model uses a feature of its kind that the GPU evaluator does not evaluate.
    #[error("the GPU evaluator does not support {feature} in {kind} models")]
    Unsupported {
        /// The model kind ([`Model::kind`](spectex_model::Model::kind)).
        kind: &'static str,
        /// What it lacks, e.g. `profiles with nested blends`.
        feature: String,
    },
    /// A window parameter is out of range.
    #[error("window {parameter} = {value} is outside its valid range {range}")]
    Window {
        /// Which parameter.
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
}

impl From<spectex_model::WindowError> for GpuError {
    fn from(e: spectex_model::WindowError) -> Self {
        Self::Window {
            parameter: e.parameter,
            value: e.value,
            range: e.range,
        }
    }
}
