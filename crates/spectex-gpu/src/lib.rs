//! The GPU evaluator: wgpu compute pipelines over the same models as `spectex-cpu`, built from
//! the WGSL in `shaders/`, packing a model into storage buffers once and rendering any window.
//!
//! Depends on `spectex-model` only, never on `spectex-cpu`: the two evaluators are independent
//! implementations of one contract, which is what makes cross-checking them meaningful.
//! Nothing is implemented here yet: the GPU evaluator issue fills it.
