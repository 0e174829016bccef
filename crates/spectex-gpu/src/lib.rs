//! The GPU evaluator: wgpu compute pipelines over the same models as `spectex-cpu`, built from
//! the WGSL in `shaders/`, packing a model into storage buffers once and rendering any window in
//! tiles that respect the device's limits.
//!
//! Depends on `spectex-model` only, never on `spectex-cpu`: the two evaluators are independent
//! implementations of one contract, which is what makes cross-checking them meaningful.
//!
//! * Randomness: `shaders/common.wgsl` is the WGSL twin of `spectex_model::random`; every integer
//!   draw (hash, PRNG stream, frequency index, Poisson count) is bit-identical to the CPU's.
//! * Floats: the same f32 formulas as the CPU (cosine in turns, Kaiser–Bessel window,
//!   exponential), but a GPU compiler may fuse `a·b + c`; values agree within tolerances, not
//!   necessarily bit for bit.
//! * Positions (DESIGN invariant 2): the host does the f64 part per tile column and row (lattice
//!   cell and f32 offsets to the nearby lattice points, see `shaders/lrp.wgsl`), so a window at
//!   `(10⁷, 10⁷)` is as precise as one at the origin.
//! * Tiles (invariant 3): every value depends only on its own pixel's position, so any tiling
//!   gives the same bits.
//! * Textures by example (`Model::Texture`): each channel's random-phase strata and each
//!   turbulence stratum run through the LRP shader, the host sums `|n_S|` and scales the
//!   displacement in the CPU's f32 order, and `shaders/texture.wgsl` adds the placement, the
//!   block structure and the colour basis; [`GpuEvaluator::output_channels`] values (1 or 3) per
//!   pixel, interleaved as on the CPU.
//! * Classic noises (`Model::Classic`: gradient, simplex, value, Worley, fBm / turbulence /
//!   ridged, 2D or a plane `z` of 3D): `shaders/classic.wgsl`, per pixel, with per-column,
//!   per-row and per-octave cells and offsets from the host (for simplex, the per-axis parts of
//!   the skewed coordinates as integer + f32 fraction).
//! * Kinds: each model kind is one module implementing the crate's `GpuKind` trait (its kernel:
//!   a shader kind's WGSL name, tables packed once, uniform and tables per tile, bytes per tile
//!   column and pixel for tiling; a warp drives three sub-evaluators instead), and
//!   [`GpuEvaluator::new_at_z`] is the one dispatch over kinds. Pipeline layouts are derived
//!   from the shaders (`layout: None`), and every record the device reads is a `#[repr(C)]`
//!   `bytemuck::Pod` struct whose field offsets a test holds against naga's layout of its WGSL
//!   twin. A new kind adds its module `<kind>.rs` (declared by
//!   `for_each_kind!(mod)`: its `GpuKind`, whose `SHADER` is the compute part of its
//!   `shaders/<kind>.wgsl`, collected into [`SHADERS`], and its `ExportKind`, whose `GLUE` is
//!   the rest of that file).
//!
//! Adapter choice: `WGPU_ADAPTER_NAME` (a substring of the adapter's name, e.g. `llvmpipe`), else
//! wgpu's high-performance default. Without a GPU, lavapipe (`apt-get install mesa-vulkan-drivers
//! libvulkan1`) is a software Vulkan adapter.
//!
//! ```
//! use spectex_gpu::{GpuContext, GpuEvaluator, GpuWindow};
//! use spectex_model::{LrpNoise, Model, Stratum};
//!
//! let context = match GpuContext::new() {
//!     Ok(context) => context,
//!     Err(e) => {
//!         eprintln!("skipping the example: {e}");
//!         return Ok(());
//!     }
//! };
//! let model = Model::Lrp(LrpNoise {
//!     seed: 1,
//!     mean: 0.5,
//!     strata: vec![Stratum {
//!         window_width: 16.0,
//!         amplitude: 0.1,
//!         sub_strata: vec![vec![[0.1, 0.0], [0.0, 0.1]]; 4],
//!     }],
//! });
//! let gpu = GpuEvaluator::new(&context, &model)?;
//! let window = GpuWindow::new(32, 16).at([1.0e7, 1.0e7], 0.5);
//! let pixels = gpu.render(&window)?;
//! assert_eq!(pixels.len(), 32 * 16);
//! // Tiles are invisible: a tile of the window has exactly the same values.
//! let tile = gpu.render(&window.tile(8, 4, 8, 8))?;
//! assert_eq!(tile[0].to_bits(), pixels[4 * 32 + 8].to_bits());
//! println!("rendered on {}", gpu.adapter_name());
//! # Ok::<(), spectex_gpu::GpuError>(())
//! ```

// Infrastructure: the device, the public evaluator, the kernel traits, the shared pipeline
// code, the records' layout check and the shader registry.
mod axis;
mod cache;
mod context;
mod error;
mod evaluator;
pub mod export;
mod kernel;
mod layout;
mod pipeline;
mod render;
pub mod shaders;
pub mod simulate;

// One module per kind (`<kind>.rs`: its records, packing, `GpuKind` and `ExportKind`),
// declared from the one list of kinds.
spectex_model::for_each_kind!(mod);

pub use context::{ADAPTER_NAME_ENV, GpuContext};
pub use error::{GpuError, LAVAPIPE_HINT};
pub use evaluator::{DEFAULT_MAX_TILE, DEFAULT_MAX_TILE_WIDTH, GpuEvaluator};
pub use render::{OutputFormat, RenderStats, TEXTURE_FORMATS};
pub use shaders::{SHADERS, wgsl_source};
/// The window type is `spectex-model`'s, shared with the CPU evaluator (so both map pixels to
/// positions by one expression); `GpuWindow` is its name here.
pub use spectex_model::{
    Filter, MAX_POSITION, MAX_WINDOW_PIXELS, MAX_WINDOW_SIDE, Window as GpuWindow,
};
/// The wgpu version this crate is built on, for callers using [`GpuContext::device`].
pub use wgpu;

/// The unit tests' bodies, one module per source module (`pub mod tests` behind this feature),
/// run by `tests/it/unit.rs`: a unit-test harness would compile the crate a second time.
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod unit_tests {
    pub use crate::axis::tests as axis;
    pub use crate::classic::tests as classic;
    pub use crate::combine::tests as combine;
    pub use crate::evaluator::tests as evaluator;
    pub use crate::export::emitter::tests as export_emitter;
    pub use crate::export::wgsl_text::tests as export_wgsl_text;
    pub use crate::gabor::tests as gabor;
    pub use crate::islamic::tests as islamic;
    pub use crate::lrp::tests as lrp;
    pub use crate::matrix::tests as matrix;
    pub use crate::phasor::tests as phasor;
    pub use crate::pipeline::tests as pipeline;
    pub use crate::render::tests as render;
    pub use crate::shaders::tests as shaders;
    pub use crate::simulate::tests as simulate;
    pub use crate::subdivision::tests as subdivision;
    pub use crate::texton::tests as texton;
    pub use crate::texture::tests as texture;
    pub use crate::tiling::tests as tiling;
    pub use crate::voronoi::tests as voronoi;
    pub use crate::warp::tests as warp;
    pub use crate::wavelet::tests as wavelet;

    /// A WGSL source parsed and validated as wgpu has naga do it, or a panic with naga's
    /// annotated excerpt (for the integration tests of the shaders and the exports).
    pub use crate::layout::check::validated_module;
}
