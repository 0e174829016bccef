//! [`GpuEvaluator`]: a model prepared on the device once (its kind's [`GpuKernel`]), and tiled
//! rendering of any window through the render ring (`render.rs`): into a host slice in any
//! [`OutputFormat`], or into a caller's device buffer with no read-back.

use std::sync::Mutex;

use spectex_model::{Model, Period};

use crate::kernel::{GpuKernel, GpuKind, PreparedTile};
use crate::pipeline::Gpu;
use crate::render::{self, OutputFormat, Packers, RenderStats, Ring, Sink, Tile};
use crate::{GpuContext, GpuError, GpuWindow};

/// Default largest tile, as pixels per side of a square: tiles hold at most
/// `DEFAULT_MAX_TILE²` pixels, a dispatch short enough for desktop watchdogs (about 0.1 s on a
/// discrete GPU at J = 50) and a 16 MiB output buffer. Tiles are as wide as the window where
/// that fits ([`DEFAULT_MAX_TILE_WIDTH`]), so each one is a contiguous band of the output.
pub const DEFAULT_MAX_TILE: usize = 2048;

/// Default largest tile width, in pixels: windows up to this wide render in full-width bands.
pub const DEFAULT_MAX_TILE_WIDTH: usize = 16_384;

/// A model prepared on the device: validated, packed into storage buffers, with its pipeline.
/// Rendering can then fail only on a bad window or a device problem.
#[derive(Debug)]
pub struct GpuEvaluator {
    adapter_info: wgpu::AdapterInfo,
    kernel: Box<dyn GpuKernel>,
    /// A cap on the tile's sides set by [`set_max_tile`](Self::set_max_tile), else the default
    /// band policy.
    max_tile: Option<[usize; 2]>,
    gpu: Gpu,
    packers: Packers,
    /// The render ring, made on the first render and kept while large enough.
    ring: Mutex<Option<Ring>>,
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
            max_tile: None,
            gpu: Gpu::new(context),
            packers: Packers::default(),
            ring: Mutex::new(None),
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

    /// Caps the tile size (pixels per side) used by the renders: smaller tiles bound the
    /// device memory and the length of one dispatch. The device's limits cap it further.
    /// Values are the same for any tile size (tests force several tiles this way).
    pub fn set_max_tile(&mut self, width: usize, height: usize) {
        self.max_tile = Some([width.max(1), height.max(1)]);
    }

    /// The tile size the renders use for `window`: full-width bands of at most
    /// [`DEFAULT_MAX_TILE`]² pixels (fewer for a kind whose host part grows with the tile), or
    /// the cap of [`set_max_tile`](Self::set_max_tile)), then
    /// the device's storage-binding and buffer-size limits (output and per-axis tables) and
    /// its dispatch limit.
    ///
    /// # Errors
    /// [`GpuError::LimitsExceeded`] if not even a one-pixel-wide tile fits.
    pub fn tile_size(&self, window: &GpuWindow) -> Result<[usize; 2], GpuError> {
        let cap = self.max_tile.unwrap_or_else(|| {
            let pixels = self
                .kernel
                .tile_pixels()
                .unwrap_or(DEFAULT_MAX_TILE * DEFAULT_MAX_TILE);
            let width = window.width.clamp(1, DEFAULT_MAX_TILE_WIDTH);
            [width, (pixels / width).max(1)]
        });
        self.kernel.tile_size(window, cap)
    }

    /// Renders `window` row-major (`width × height × output_channels` values, channels
    /// interleaved per pixel as on the CPU), tile by tile; the size is bounded only by host
    /// memory. Tiling does not change any value.
    ///
    /// # Errors
    /// [`GpuError::Window`] for a window out of range; [`GpuError::Validation`],
    /// [`GpuError::DeviceLost`] for device problems.
    pub fn render(&self, window: &GpuWindow) -> Result<Vec<f32>, GpuError> {
        let mut out = vec![0.0f32; self.values(window)?];
        self.render_into(window, &mut out)?;
        Ok(out)
    }

    /// As [`render`](Self::render), into `out` (exactly `width × height × output_channels`
    /// values): each tile is written straight from the mapped device memory while the next
    /// computes.
    ///
    /// # Errors
    /// As [`render`](Self::render), and [`GpuError::Output`] for a slice of another length.
    pub fn render_into(
        &self,
        window: &GpuWindow,
        out: &mut [f32],
    ) -> Result<RenderStats, GpuError> {
        self.render_bytes_into(window, OutputFormat::F32, bytemuck::cast_slice_mut(out))
    }

    /// `window` in `format`, row-major, channels interleaved (`f32` and `f16` values and unorm
    /// levels as little-endian bytes): a render for an 8-bit PNG reads back a quarter of the
    /// bytes of an `f32` one.
    ///
    /// # Errors
    /// As [`render`](Self::render).
    pub fn render_bytes(
        &self,
        window: &GpuWindow,
        format: OutputFormat,
    ) -> Result<Vec<u8>, GpuError> {
        let mut out = vec![0u8; self.values(window)? * format.bytes_per_value()];
        self.render_bytes_into(window, format, &mut out)?;
        Ok(out)
    }

    /// As [`render_bytes`](Self::render_bytes), into `out` (exactly the window's bytes).
    ///
    /// # Errors
    /// As [`render`](Self::render), and [`GpuError::Output`] for a slice of another length.
    pub fn render_bytes_into(
        &self,
        window: &GpuWindow,
        format: OutputFormat,
        out: &mut [u8],
    ) -> Result<RenderStats, GpuError> {
        let expected = self.values(window)? * format.bytes_per_value();
        if out.len() != expected {
            return Err(GpuError::Output {
                what: "bytes of the output slice",
                value: out.len() as u64,
                expected: format!("{expected} (width × height × channels × bytes per value)"),
            });
        }
        let pixel = self.output_channels() * format.bytes_per_value();
        let row = window.width * pixel;
        let mut write = |[tx, ty]: [usize; 2], tile: &GpuWindow, bytes: &[u8]| {
            let rows = &mut out[ty * row..(ty + tile.height) * row];
            render::copy_tile(rows, row, tx * pixel, tile.width * pixel, bytes);
        };
        self.render_with(window, format, Sink::Host(&mut write))
    }

    /// Renders `window` in `format` into a caller's device `buffer` from byte `offset`,
    /// row-major, with nothing read back: a wgpu or Bevy renderer on the same device
    /// ([`GpuContext::from_device`]) fills its own storage buffer, then copies it into a
    /// texture or reads it in its shaders. The buffer needs [`wgpu::BufferUsages::COPY_DST`];
    /// the copies move 4-byte words, so `offset` and, for tiles narrower than the window, each
    /// row's bytes must be whole words, and the buffer must hold the window's bytes rounded up
    /// to a whole word. The work is submitted to the device's queue when this returns, and
    /// the call does not wait for the device: a renderer's frame goes on recording while it
    /// computes, and its own submissions after this one see the values. So the stats have no
    /// kernel time (a render into host memory has, where the device has timestamps).
    ///
    /// # Errors
    /// [`GpuError::Output`] for a buffer too small, without `COPY_DST`, or misaligned;
    /// [`GpuError::Validation`] for a buffer of another device; otherwise as
    /// [`render`](Self::render).
    pub fn render_to_buffer(
        &self,
        window: &GpuWindow,
        format: OutputFormat,
        buffer: &wgpu::Buffer,
        offset: u64,
    ) -> Result<RenderStats, GpuError> {
        let bytes = (self.values(window)? * format.bytes_per_value()) as u64;
        if !buffer.usage().contains(wgpu::BufferUsages::COPY_DST) {
            return Err(GpuError::Output {
                what: "usage bits of the target buffer",
                value: u64::from(buffer.usage().bits()),
                expected: "a buffer created with wgpu::BufferUsages::COPY_DST".to_owned(),
            });
        }
        if !offset.is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT) {
            return Err(GpuError::Output {
                what: "byte offset into the target buffer",
                value: offset,
                expected: "a multiple of 4".to_owned(),
            });
        }
        let needed = offset + bytes.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        if buffer.size() < needed {
            return Err(GpuError::Output {
                what: "bytes of the target buffer",
                value: buffer.size(),
                expected: format!(
                    "at least {needed} (offset {offset} + the window's {bytes} bytes, rounded up \
                     to a whole word)"
                ),
            });
        }
        self.render_with(window, format, Sink::Device { buffer, offset })
    }

    /// Renders `window` into a caller's storage `texture` (its first mip level and layer),
    /// pixel (x, y) at texel (x, y), with nothing read back: grey values in every colour
    /// channel, colour in R, G, B, alpha 1. The texture is one of [`TEXTURE_FORMATS`], has
    /// [`wgpu::TextureUsages::STORAGE_BINDING`] and is at least as large as the window. As
    /// [`render_to_buffer`](Self::render_to_buffer), the call returns once the work is
    /// submitted, without waiting for the device.
    ///
    /// # Errors
    /// [`GpuError::TextureFormat`] for another format, [`GpuError::Output`] for a missing usage
    /// or a texture too small;
    /// otherwise as [`render`](Self::render).
    ///
    /// [`TEXTURE_FORMATS`]: crate::TEXTURE_FORMATS
    pub fn render_to_texture(
        &self,
        window: &GpuWindow,
        texture: &wgpu::Texture,
    ) -> Result<RenderStats, GpuError> {
        self.values(window)?;
        let Some(name) = render::texture_format_name(texture.format()) else {
            return Err(GpuError::TextureFormat {
                found: format!("{:?}", texture.format()),
                expected: format!("{:?}", render::TEXTURE_FORMATS),
            });
        };
        if !texture
            .usage()
            .contains(wgpu::TextureUsages::STORAGE_BINDING)
            || texture.dimension() != wgpu::TextureDimension::D2
        {
            return Err(GpuError::Output {
                what: "usage bits of the target texture",
                value: u64::from(texture.usage().bits()),
                expected: "a 2D texture created with wgpu::TextureUsages::STORAGE_BINDING"
                    .to_owned(),
            });
        }
        let size = texture.size();
        for (side, window_side) in [(size.width, window.width), (size.height, window.height)] {
            if (side as usize) < window_side {
                return Err(GpuError::Output {
                    what: "texels along a side of the target texture",
                    value: u64::from(side),
                    expected: format!("at least the window's {window_side}"),
                });
            }
        }
        let pipeline = self.packers.store(&self.gpu, name)?;
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("spectex target"),
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_mip_level: 0,
            mip_level_count: Some(1),
            base_array_layer: 0,
            array_layer_count: Some(1),
            ..Default::default()
        });
        self.render_with(window, OutputFormat::F32, Sink::Texture { view, pipeline })
    }

    /// Values of a render of `window`, after checking the window.
    fn values(&self, window: &GpuWindow) -> Result<usize, GpuError> {
        window.validate()?;
        self.kernel.check_window(window)?;
        Ok(window.width * window.height * self.output_channels())
    }

    /// The tiles of `window` (checked by [`values`](Self::values) first), through the ring,
    /// into `sink`.
    fn render_with(
        &self,
        window: &GpuWindow,
        format: OutputFormat,
        sink: Sink<'_>,
    ) -> Result<RenderStats, GpuError> {
        let [tile_width, tile_height] = self.tile_size(window)?;
        let mut tiles = Vec::new();
        for ty in (0..window.height).step_by(tile_height) {
            for tx in (0..window.width).step_by(tile_width) {
                tiles.push(Tile {
                    at: [tx, ty],
                    window: window.tile(
                        tx,
                        ty,
                        tile_width.min(window.width - tx),
                        tile_height.min(window.height - ty),
                    ),
                });
            }
        }
        let capacity = (tile_width * tile_height * self.output_channels()) as u64;
        let mut guard = self.lock_ring();
        let ring = ring_of(&self.gpu, &mut guard, capacity);
        let result = render::run(
            &self.gpu,
            self.kernel.as_ref(),
            &self.packers,
            ring,
            window,
            &tiles,
            format,
            sink,
        );
        if result.is_err() {
            // A failed render may leave a slot mapped or its map pending: start afresh.
            *guard = None;
        }
        result
    }

    /// Makes ahead of a render what a render of `window` in `format` needs on the device and
    /// makes itself where missing: the ring of buffers for its tiles and the pipeline that
    /// packs `format`. A caller timing a single render (as `spectex render` does) calls this
    /// first, so that the time is the render's and not the allocation of its device and
    /// host-visible memory or the compilation of a shader. Renders of windows whose tiles are
    /// no larger reuse both.
    ///
    /// # Errors
    /// As [`render`](Self::render).
    pub fn reserve(&self, window: &GpuWindow, format: OutputFormat) -> Result<(), GpuError> {
        self.values(window)?;
        let [tile_width, tile_height] = self.tile_size(window)?;
        self.packers.pack(&self.gpu, format)?;
        let capacity = (tile_width * tile_height * self.output_channels()) as u64;
        ring_of(&self.gpu, &mut self.lock_ring(), capacity);
        Ok(())
    }

    /// The render ring's lock; a poisoned lock (a panic during another render) only loses the
    /// ring.
    fn lock_ring(&self) -> std::sync::MutexGuard<'_, Option<Ring>> {
        self.ring.lock().unwrap_or_else(|poisoned| {
            let mut guard = poisoned.into_inner();
            *guard = None;
            guard
        })
    }

    /// The host's part of `tile`'s undisplaced render, for [`encode_pass`](Self::encode_pass)
    /// into another kernel's dispatches (a texture's LRP strata).
    pub(crate) fn prepare_pass(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
        self.kernel.prepare_tile(tile)
    }

    /// Records `tile`'s dispatch, whose host part `prepared` is, into `encoder`, writing its
    /// values from the start of `output` (a composite kind's values are copied there); `timer`
    /// writes the dispatch's timestamps.
    pub(crate) fn encode_pass(
        &self,
        tile: &GpuWindow,
        prepared: PreparedTile,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let kernel = self.kernel.as_ref();
        render::encode_prepared(&self.gpu, kernel, tile, prepared, encoder, output, timer)
    }

    /// What this model's host part reads of a displacement: whether, and how, it can be
    /// displaced by a displacement that stays on the device.
    pub(crate) fn displacement_read(&self) -> crate::kernel::DisplacementRead {
        self.kernel.displacement_read()
    }

    /// The host part of `tile`'s dispatch displaced on the device, by a displacement within
    /// `range` where the model reads its range.
    pub(crate) fn prepare_device_displaced(
        &self,
        tile: &GpuWindow,
        range: Option<crate::kernel::DisplacementRange>,
    ) -> Result<crate::kernel::TileTables, GpuError> {
        self.kernel.prepare_device_displaced(tile, range)
    }

    /// Records `tile`'s dispatch displaced by `displacement`, a device buffer of `(dx, dy)`
    /// per pixel that earlier passes of the same submission write.
    pub(crate) fn encode_device_displaced(
        &self,
        tile: &GpuWindow,
        tables: crate::kernel::TileTables,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        self.kernel
            .encode_device_displaced(tile, tables, encoder, output, displacement, timer)
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

/// The ring in `slot`, made anew where there is none or it holds fewer than `capacity` values
/// a slot.
fn ring_of<'a>(gpu: &Gpu, slot: &'a mut Option<Ring>, capacity: u64) -> &'a Ring {
    if slot.as_ref().is_some_and(|ring| ring.capacity() < capacity) {
        *slot = None;
    }
    slot.get_or_insert_with(|| Ring::new(gpu, capacity))
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// `reserve` makes the ring a render of its window needs (slots of one whole tile's
    /// values, from `tile_size`) and the packing pipeline of its format, before any render;
    /// the render then keeps both, and a larger window's reserve grows the ring.
    pub fn reserve_makes_what_the_render_uses() {
        use crate::layout::check::context_or_skip;
        let Some(context) = context_or_skip("reserve_makes_what_the_render_uses") else {
            return;
        };
        let model = Model::Gabor(spectex_model::fixtures::gabor_isotropic());
        let mut gpu = GpuEvaluator::new(&context, &model).unwrap();
        gpu.set_max_tile(64, 48);
        let capacity = |gpu: &GpuEvaluator| gpu.lock_ring().as_ref().map(Ring::capacity);
        let needs = |gpu: &GpuEvaluator, window: &GpuWindow| {
            let [w, h] = gpu.tile_size(window).unwrap();
            Some((w * h * gpu.output_channels()) as u64)
        };
        let window = GpuWindow::new(100, 30);
        assert_eq!(capacity(&gpu), None);
        assert!(!gpu.packers.holds(OutputFormat::Unorm8));
        gpu.reserve(&window, OutputFormat::Unorm8).unwrap();
        assert_eq!(capacity(&gpu), needs(&gpu, &window));
        assert!(gpu.packers.holds(OutputFormat::Unorm8));
        gpu.render_bytes(&window, OutputFormat::Unorm8).unwrap();
        assert_eq!(capacity(&gpu), needs(&gpu, &window));
        let larger = GpuWindow::new(300, 200);
        gpu.reserve(&larger, OutputFormat::F32).unwrap();
        assert_eq!(capacity(&gpu), needs(&gpu, &larger));
        assert!(needs(&gpu, &larger) > needs(&gpu, &window));
    }
}
