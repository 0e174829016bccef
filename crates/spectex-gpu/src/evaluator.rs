//! [`GpuEvaluator`]: a model prepared on the device once (its kind's [`GpuKernel`]), and tiled
//! rendering of any window with read-back.

use spectex_model::{Model, Period};

use crate::kernel::{GpuKernel, GpuKind};
use crate::{GpuContext, GpuError, GpuWindow};

/// Default largest tile, in pixels per side: a dispatch short enough for desktop watchdogs
/// (about 0.1 s on a discrete GPU at J = 50) and a 16 MiB output buffer.
pub const DEFAULT_MAX_TILE: usize = 2048;

/// A model prepared on the device: validated, packed into storage buffers, with its pipeline.
/// Rendering can then fail only on a bad window or a device problem.
#[derive(Debug)]
pub struct GpuEvaluator {
    adapter_info: wgpu::AdapterInfo,
    kernel: Box<dyn GpuKernel>,
    max_tile: [usize; 2],
}

impl GpuEvaluator {
    /// Validates `model`, packs it into storage buffers and builds its compute pipeline.
    ///
    /// # Errors
    /// [`GpuError::Model`] for an invalid model, [`GpuError::LimitsExceeded`] when its tables
    /// do not fit one storage buffer, [`GpuError::Unsupported`] for a feature of a kind the
    /// device path lacks, [`GpuError::Validation`] if the device rejects the shader or the
    /// buffers.
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
        Self::prepared(context, model, z)
    }

    /// As [`new_at_z`](Self::new_at_z), for `model` made exactly periodic with `period`
    /// (`spectex_model::period`; the CPU's `Evaluator::periodic`): positions reduced modulo the
    /// period on the host, cells hashed modulo it on the device. Every kind with a periodic form
    /// (`spectex_model::PERIODIC_KINDS`) has a periodic device path.
    ///
    /// # Errors
    /// As [`new_at_z`](Self::new_at_z); [`GpuError::Model`] for a period the model cannot take,
    /// [`GpuError::Unsupported`] for a kind whose device path has no periodic form.
    pub fn periodic_at_z(
        context: &GpuContext,
        model: &Model,
        z: f64,
        period: Period,
    ) -> Result<Self, GpuError> {
        model.validate()?;
        model.check_period(period)?;
        if !(z.is_finite() && z.abs() <= crate::MAX_POSITION) {
            return Err(GpuError::Window {
                parameter: "z",
                value: z,
                range: "finite, |z| ≤ 2³⁰ pixels",
            });
        }
        Self::prepared_with_period(context, model, z, Some(period))
    }

    /// The evaluator of a validated model and plane.
    pub(crate) fn prepared(context: &GpuContext, model: &Model, z: f64) -> Result<Self, GpuError> {
        Self::prepared_with_period(context, model, z, None)
    }

    /// The evaluator of a validated model and plane, periodic with `period` when given (a
    /// period the model accepts): the one dispatch over model kinds in this crate (every kind
    /// implements [`GpuKind`] in its own module). A warp builds its base, x and y through here
    /// too, a combination its operands, a texture its LRP passes.
    pub(crate) fn prepared_with_period(
        context: &GpuContext,
        model: &Model,
        z: f64,
        period: Option<Period>,
    ) -> Result<Self, GpuError> {
        let kernel = match period {
            None => {
                spectex_model::for_each_kind!(model, m: K => <K as GpuKind>::gpu_kernel(m, context, z)?)
            }
            Some(p) => {
                spectex_model::for_each_kind!(model, m: K => <K as GpuKind>::gpu_kernel_periodic(m, context, z, p)?)
            }
        };
        Ok(Self {
            adapter_info: context.adapter_info(),
            kernel,
            max_tile: [DEFAULT_MAX_TILE, DEFAULT_MAX_TILE],
        })
    }

    /// Values per pixel in [`render`](Self::render)'s output: 3 for a colour texture (RGB,
    /// interleaved), 1 for every other model.
    #[must_use]
    pub fn output_channels(&self) -> usize {
        self.kernel.output_channels()
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
        self.kernel.tile_size(window, self.max_tile)
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
        self.kernel.check_window(window)?;
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
                let values = self.render_tile_displaced(&tile, None)?;
                for (row, line) in values.chunks_exact(tile.width * channels).enumerate() {
                    let start = ((ty + row) * window.width + tx) * channels;
                    out[start..start + line.len()].copy_from_slice(line);
                }
            }
        }
        Ok(out)
    }

    /// One tile (which fits [`tile_size`](Self::tile_size)) at positions displaced by
    /// `displacement` (pixels, `(dx, dy)` per pixel interleaved, row-major over the tile) when
    /// given: what a warp asks of its base, x and y, and a texture of its LRP passes.
    pub(crate) fn render_tile_displaced(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError> {
        self.kernel.render_tile(tile, displacement)
    }
}
