//! What a [`GpuContext`](crate::GpuContext) owns for every evaluator on its device: the compute
//! pipelines built so far ([`PipelineCache`]) and the flag wgpu's device-lost callback writes
//! ([`LostFlag`]). A ground-floor module: it depends on nothing else in the crate, so the
//! context (which owns these) and the pipeline code (which reads them) both build on it.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Why the device was lost, written by wgpu's device-lost callback.
pub(crate) type LostFlag = Arc<Mutex<Option<String>>>;

/// A compute pipeline and the bind group layouts derived from its shader (`layout: None`), in
/// group order.
#[derive(Debug, Clone)]
pub(crate) struct CachedPipeline {
    pub pipeline: wgpu::ComputePipeline,
    pub layouts: Vec<wgpu::BindGroupLayout>,
}

/// A pipeline's identity: shader, entry point and the values of its pipeline-overridable
/// constants (`override` declarations: a kind's shape, which the driver folds).
pub(crate) type PipelineKey = (&'static str, &'static str, Vec<(&'static str, u32)>);

/// The compute pipelines a context has built, by [`PipelineKey`]. A shader's source is fixed by
/// its name, so every evaluator of a kind and shape on the device shares one pipeline: building
/// a pipeline compiles the shader (on lavapipe, LLVM: 0.1 s to seconds per shader), where a
/// model's own data lives in its uniform and tables.
#[derive(Debug, Default)]
pub(crate) struct PipelineCache(Mutex<HashMap<PipelineKey, CachedPipeline>>);

impl PipelineCache {
    /// The cached pipeline of `key`, or the one `build` makes (then cached). A poisoned lock (a
    /// panic while another thread held it) only loses the cache: the pipeline is built again.
    pub(crate) fn get_or_build<E>(
        &self,
        key: PipelineKey,
        build: impl FnOnce() -> Result<CachedPipeline, E>,
    ) -> Result<CachedPipeline, E> {
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
