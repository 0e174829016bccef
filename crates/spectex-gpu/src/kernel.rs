//! What a model kind provides on the device: [`GpuKind`] builds a kind's [`GpuKernel`] once per
//! model; a kind with a shader of its own implements [`ShaderKernel`] (its WGSL, its uniform and
//! tables per tile, its sizes for tiling) and [`Shaded`](crate::pipeline::Shaded) turns that into
//! a kernel, while a kind that only combines others (a warp) implements [`GpuKernel`] directly.
//!
//! Each kind implements these in its own module; [`GpuEvaluator::new_at_z`] is the one dispatch
//! over kinds, through `spectex_model::for_each_kind!`.
//!
//! [`GpuEvaluator::new_at_z`]: crate::GpuEvaluator::new_at_z

use std::fmt;

use spectex_model::{ModelKind, Period};

use crate::pipeline::{OwnPass, OwnPassLayout};
use crate::{GpuContext, GpuError, GpuWindow};

/// The largest tile, from `[width, height]` halved (rounding up) on both sides together, whose
/// box of host-drawn cells fits half a buffer of `limit` bytes: `cells(width, height)` cells of
/// `per_cell` bytes each. A 1×1 tile is returned when nothing larger fits (the caller's table
/// check then refuses a cell box past the limit, typed).
pub(crate) fn halve_tile_to_fit(
    [mut width, mut height]: [usize; 2],
    per_cell: f64,
    limit: u64,
    cells: impl Fn(usize, usize) -> f64,
) -> [usize; 2] {
    while (width > 1 || height > 1) && cells(width, height) * per_cell > limit as f64 / 2.0 {
        width = width.div_ceil(2);
        height = height.div_ceil(2);
    }
    [width, height]
}

/// The device layer of one model kind: a kind writes its kernel construction once,
/// [`kernel_with_period`](Self::kernel_with_period), and the evaluator reaches it through the
/// provided [`gpu_kernel`](Self::gpu_kernel) and [`gpu_kernel_periodic`](Self::gpu_kernel_periodic).
pub(crate) trait GpuKind: ModelKind {
    /// The kind's compute shader in `shaders/` (composed and validated with the others, see
    /// [`crate::SHADERS`]), or `None` for a kind whose kernel runs other kernels (warp,
    /// combine).
    const SHADER: Option<crate::shaders::ShaderFile>;

    /// The kernel of a **validated** model on the plane `z` (ignored by 2D models): its tables
    /// packed and uploaded, its pipeline built; made exactly periodic with `period` when given,
    /// a period the model accepts ([`ModelKind::check_period`], checked by the caller): tile
    /// positions reduced modulo the period on the host (`spectex_model::period::reduce`, per
    /// axis) and cells hashed modulo it in the shader, as on the CPU.
    ///
    /// # Errors
    /// [`GpuError::LimitsExceeded`] when a table does not fit one storage buffer,
    /// [`GpuError::Unsupported`] for a feature of the kind the device path lacks (a period
    /// included, for a kind without a periodic form), [`GpuError::Validation`] if the device
    /// rejects the shader or the buffers.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError>;

    /// The kernel of a **validated** model on the plane `z`, not periodic.
    ///
    /// # Errors
    /// As [`kernel_with_period`](Self::kernel_with_period).
    fn gpu_kernel(&self, context: &GpuContext, z: f64) -> Result<Box<dyn GpuKernel>, GpuError> {
        self.kernel_with_period(context, z, None)
    }

    /// The kernel of a **validated** model made exactly periodic with `period`, once the model
    /// layer accepts the period ([`ModelKind::check_period`]; kinds without a periodic form
    /// refuse every period there).
    ///
    /// # Errors
    /// [`GpuError::Model`] for a period the model refuses, else as
    /// [`kernel_with_period`](Self::kernel_with_period).
    fn gpu_kernel_periodic(
        &self,
        context: &GpuContext,
        z: f64,
        period: Period,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        self.check_period(period)?;
        self.kernel_with_period(context, z, Some(period))
    }
}

/// A model prepared on the device, rendering one tile at a time.
pub(crate) trait GpuKernel: fmt::Debug + Send + Sync {
    /// Values per pixel in the output, interleaved: 1, or 3 for colour.
    fn output_channels(&self) -> usize;

    /// The largest tile (pixels per side) for `window`, at most `cap`, whose buffers and
    /// dispatch fit the device's limits.
    ///
    /// # Errors
    /// [`GpuError::LimitsExceeded`] if not even a one-pixel tile fits.
    fn tile_size(&self, window: &GpuWindow, cap: [usize; 2]) -> Result<[usize; 2], GpuError>;

    /// Checks what [`GpuWindow::validate`] cannot know: a kind whose positions reach beyond the
    /// window (a warp) checks that they stay in range.
    ///
    /// # Errors
    /// [`GpuError::Window`] naming the parameter.
    fn check_window(&self, window: &GpuWindow) -> Result<(), GpuError> {
        let _ = window;
        Ok(())
    }

    /// The values of `tile` (which fits [`tile_size`](Self::tile_size)), row-major, channels
    /// interleaved, at positions displaced by `displacement` (pixels, `(dx, dy)` per pixel
    /// interleaved, row-major over the tile) when given: `common.wgsl`'s convention.
    ///
    /// # Errors
    /// [`GpuError::Validation`], [`GpuError::DeviceLost`], or [`GpuError::LimitsExceeded`] for
    /// a per-tile table (a warped tile can reach far more cells than its own box).
    fn render_tile(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError>;

    /// The host's part of `tile`'s undisplaced render, which a render prepares on worker
    /// threads ahead of the dispatches: a shader kind's uniform and tables, or (the default)
    /// a composite kind's values, rendered through [`render_tile`](Self::render_tile) (its
    /// operands' dispatches and its host arithmetic), which the render uploads.
    ///
    /// # Errors
    /// As [`render_tile`](Self::render_tile).
    fn prepare_tile(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
        self.render_tile(tile, None).map(PreparedTile::Values)
    }

    /// Records the undisplaced dispatch of `tile`, whose host part `tables`
    /// [`prepare_tile`](Self::prepare_tile) made, into `encoder`, writing its values (`f32`,
    /// row-major, channels interleaved) from the start of `output`, with `timer` writing the
    /// pass's timestamps. Only called with tables `prepare_tile` returned.
    ///
    /// # Errors
    /// [`GpuError::Validation`] for a kernel without a dispatch of its own.
    fn encode_tile(
        &self,
        tile: &GpuWindow,
        tables: TileTables,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let _ = (tile, tables, encoder, output, timer);
        Err(GpuError::Validation(
            "a composite kernel has no dispatch of its own to record".to_owned(),
        ))
    }

    /// Pixels per tile a render aims at, where the kind wants smaller tiles than the default:
    /// a kind whose host part grows with the tile (a phasor's drawn kernels) gets more tiles,
    /// prepared in parallel.
    fn tile_pixels(&self) -> Option<usize> {
        None
    }

    /// Records a composite kind's tile whose host part is a [`PreparedTile::Chain`]: its
    /// operands' dispatches, its composition, and its base's dispatch, writing the values from
    /// the start of `output`, with `timer` spanning them.
    ///
    /// # Errors
    /// [`GpuError::Validation`] for a kernel that prepares no chain.
    fn encode_chain(
        &self,
        tile: &GpuWindow,
        operands: Vec<PreparedTile>,
        base: Option<TileTables>,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let _ = (tile, operands, base, encoder, output, timer);
        Err(GpuError::Validation(
            "a kernel without a chain of its own was given one to record".to_owned(),
        ))
    }

    /// What the kernel's host part reads of a displacement, so whether a warp over it may keep
    /// the displacement on the device ([`encode_device_displaced`](Self::encode_device_displaced)):
    /// not at all, its range only (a phasor's cell box, a Voronoi search), or every pixel's
    /// (a composite kind, a phasor's varying fields): then the host composes.
    fn displacement_read(&self) -> DisplacementRead {
        DisplacementRead::Pixels
    }

    /// The host part of `tile` for [`encode_device_displaced`](Self::encode_device_displaced),
    /// given the displacement's `range` (read back from the device) where the kernel reads it.
    ///
    /// # Errors
    /// As [`render_tile`](Self::render_tile); [`GpuError::Validation`] where
    /// [`displacement_read`](Self::displacement_read) is [`DisplacementRead::Pixels`], or is
    /// [`DisplacementRead::Range`] and `range` is `None`.
    fn prepare_device_displaced(
        &self,
        tile: &GpuWindow,
        range: Option<DisplacementRange>,
    ) -> Result<TileTables, GpuError> {
        let _ = (tile, range);
        Err(GpuError::Validation(
            "this kernel is not displaced on the device".to_owned(),
        ))
    }

    /// Records `tile`'s dispatch displaced by `displacement` (`(dx, dy)` per pixel, `f32`, on
    /// the device), with `tables` from [`prepare_device_displaced`](Self::prepare_device_displaced).
    ///
    /// # Errors
    /// As [`prepare_device_displaced`](Self::prepare_device_displaced).
    fn encode_device_displaced(
        &self,
        tile: &GpuWindow,
        tables: TileTables,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        displacement: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let _ = (tile, tables, encoder, output, displacement, timer);
        Err(GpuError::Validation(
            "this kernel is not displaced on the device".to_owned(),
        ))
    }
}

/// `timer` split in two: one that writes only its start (for the first of several passes) and
/// one that writes only its end (for the last); a half with nothing to write is `None` (a
/// timer split already, handed to a pass that splits it again).
pub(crate) fn split_timer(
    timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
) -> (
    Option<wgpu::ComputePassTimestampWrites<'_>>,
    Option<wgpu::ComputePassTimestampWrites<'_>>,
) {
    let Some(t) = timer else {
        return (None, None);
    };
    let start = t
        .beginning_of_pass_write_index
        .map(|index| wgpu::ComputePassTimestampWrites {
            query_set: t.query_set,
            beginning_of_pass_write_index: Some(index),
            end_of_pass_write_index: None,
        });
    let end = t
        .end_of_pass_write_index
        .map(|index| wgpu::ComputePassTimestampWrites {
            query_set: t.query_set,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: Some(index),
        });
    (start, end)
}

/// A kind rendered by a compute shader of its own: everything kind-specific about it, and
/// nothing about wgpu (pipelines, bind groups, dispatch and read-back are
/// [`Shaded`](crate::pipeline::Shaded)'s).
///
/// Bind group 0 of its shader is, in binding order: the uniform (binding 0), the tables packed
/// once (handed to `Shaded::boxed` in that order), the per-tile tables of
/// [`tile_tables`](Self::tile_tables) in order, and last the `f32` output. Bind group 1 is the
/// displacement of `common.wgsl`. The layouts come from the shader itself.
pub(crate) trait ShaderKernel: fmt::Debug + Send + Sync + 'static {
    /// The shader's name in the registry (`shaders/<SHADER>.wgsl`).
    const SHADER: &'static str;
    /// Its compute entry point.
    const ENTRY_POINT: &'static str;
    /// What [`tile_tables`](Self::tile_tables) reads of a displacement: nothing (the shader
    /// moves each pixel; a texture's passes read the device's displacement too), its range (a
    /// phasor's cell box, a Voronoi search: a warp then keeps the displacement on the device
    /// and reads back 16 bytes), or every pixel's (a phasor's varying fields: displaced from
    /// the host only).
    fn displacement_read(&self) -> DisplacementRead {
        DisplacementRead::Nothing
    }

    /// Values per pixel in the output, interleaved.
    fn output_channels(&self) -> usize {
        1
    }

    /// The shader's pipeline-overridable constants (`common.wgsl`'s "Shapes"): the uniform's
    /// fields that fix a model's shape (a classic noise's basis, a phasor's output).
    const SHAPE: &'static [&'static str] = &[];

    /// This model's values of [`SHAPE`](Self::SHAPE), in its order: the driver folds them, so
    /// it compiles only the branches the model takes. One pipeline per shape, shared.
    fn shape(&self) -> Vec<u32> {
        Vec::new()
    }

    /// [`SHAPE`](Self::SHAPE) with this model's values: the pipeline's constants.
    fn constants(&self) -> Vec<(&'static str, u32)> {
        Self::SHAPE.iter().copied().zip(self.shape()).collect()
    }

    /// Bytes of the per-column (and per-row) tables for one tile column (row): what bounds a
    /// tile's side through the storage-binding limit.
    fn axis_bytes(&self) -> u64;

    /// Bytes per pixel of the tile's largest per-pixel buffer: the output or the displacement
    /// (two `f32`) unless the kind uploads more per pixel.
    fn pixel_bytes(&self) -> u64 {
        8
    }

    /// Pixels per tile for a render ([`GpuKernel::tile_pixels`]): `Some` for a kind whose host
    /// part grows with the tile.
    fn tile_pixels(&self) -> Option<usize> {
        None
    }

    /// Shrinks a tile that fits the generic limits for what the kind adds (a phasor's box of
    /// kernel cells, a texture's LRP passes); `limit` bounds one storage buffer.
    ///
    /// # Errors
    /// As [`GpuKernel::tile_size`].
    fn fit_tile(
        &self,
        window: &GpuWindow,
        size: [usize; 2],
        limit: u64,
    ) -> Result<[usize; 2], GpuError> {
        let _ = (window, limit);
        Ok(size)
    }

    /// The uniform and the per-tile tables of `tile` (displaced by `displacement`, which a kind
    /// drawing cells on the host must cover; a kind is given no more than its
    /// [`displacement_read`](Self::displacement_read)); `limit` bounds one storage buffer.
    ///
    /// # Errors
    /// [`GpuError::LimitsExceeded`] for a table over `limit`; a kind running passes of its own
    /// first (a texture's strata) passes their errors on.
    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        limit: u64,
    ) -> Result<TileTables, GpuError>;

    /// Records the dispatches of other kernels that fill the tile's table left to the device
    /// ([`Table::filled_on_device`]) before the kind's own: `passes`, the host parts
    /// [`tile_tables`](Self::tile_tables) prepared for them, write into `target`, displaced by
    /// `displacement` where given (the device's displacement of the kind's own dispatch, a
    /// warp's); `bound` holds the buffers of the kind's own bindings from 1 on (its resident
    /// tables, then the tile's, `target` among them), for passes that read them too; `timer`
    /// writes the first pass's start. Called for every tile whose tables leave one to the
    /// device.
    ///
    /// By default the kind's [`own_pass`](Self::own_pass) ([`OwnPass::record`]).
    ///
    /// # Errors
    /// [`GpuError::Validation`] for a kind without passes of its own, and as
    /// [`OwnPass::record`].
    fn encode_passes(
        &self,
        tile: &GpuWindow,
        passes: Vec<PreparedTile>,
        encoder: &mut wgpu::CommandEncoder,
        buffers: (&wgpu::Buffer, &[&wgpu::Buffer], Option<&wgpu::Buffer>),
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let _ = tile;
        let Some((own, layout)) = self.own_pass() else {
            return Err(GpuError::Validation(
                "a kernel without passes of its own was given passes to record".to_owned(),
            ));
        };
        own.record(layout, (&passes, encoder), buffers, timer)
    }

    /// The kind's own pass (`lrp_draw`, `gabor_draw`, `texton_draw`, `phasor_bin`), where it
    /// was built: the pipeline and how it binds and dispatches. `None` by default.
    fn own_pass(&self) -> Option<(&OwnPass, &'static OwnPassLayout)> {
        None
    }
}

/// Pixels per tile of a kind whose host part grows with the tile (a phasor's drawn kernels,
/// a composition done on the host): quarter-megapixel tiles, so a render prepares many of them
/// in parallel ([`GpuKernel::tile_pixels`]).
pub(crate) const HOST_TILE_PIXELS: usize = 1 << 18;

/// Pixels per tile of a kind that holds several planes a pixel on the device while a tile is in
/// flight (a chain's operands, a texture's passes): megapixel tiles.
pub(crate) const CHAIN_TILE_PIXELS: usize = 1 << 20;

/// [`GpuKernel::tile_pixels`] of a composite kind: [`CHAIN_TILE_PIXELS`] where the device
/// composes its tiles in one submission, [`HOST_TILE_PIXELS`] where the host does.
pub(crate) fn composite_tile_pixels(on_device: bool) -> Option<usize> {
    Some(if on_device {
        CHAIN_TILE_PIXELS
    } else {
        HOST_TILE_PIXELS
    })
}

/// What a kernel's host part reads of a displacement of its positions
/// ([`GpuKernel::displacement_read`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum DisplacementRead {
    /// Nothing: the shader moves each pixel by its displacement.
    Nothing,
    /// Its range: the cells the displaced pixels reach.
    Range,
    /// Every pixel's.
    Pixels,
}

/// The range of a tile's displacements (pixels): `dx` in `[x[0], x[1]]`, `dy` in
/// `[y[0], y[1]]`, the exact extremes of the device's `f32` values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DisplacementRange {
    pub x: [f32; 2],
    pub y: [f32; 2],
}

/// What a tile's host part is told of a displacement of its positions (a warp's base).
#[derive(Debug, Clone, Copy)]
pub(crate) enum TileDisplacement<'a> {
    /// Not displaced.
    None,
    /// Each pixel's `(dx, dy)` (pixels, interleaved, row-major over the tile).
    Pixels(&'a [f32]),
    /// Only their range: the displacement itself stays on the device.
    Within(DisplacementRange),
    /// Displaced on the device by a displacement the kind does not read
    /// ([`DisplacementRead::Nothing`]): its shader moves each pixel (and a pass of its own
    /// would draw cells the pixels leave).
    OnDevice,
}

impl<'a> TileDisplacement<'a> {
    /// Whether the positions are displaced at all.
    pub(crate) fn is_some(&self) -> bool {
        !matches!(self, Self::None)
    }

    /// Each pixel's displacement, where the host has it.
    pub(crate) fn pixels(&self) -> Option<&'a [f32]> {
        match *self {
            Self::Pixels(d) => Some(d),
            _ => None,
        }
    }
}

/// What [`GpuKernel::prepare_tile`] makes of a tile on the host.
#[derive(Debug)]
pub(crate) enum PreparedTile {
    /// A shader kind's uniform and tables, for [`GpuKernel::encode_tile`].
    Tables(TileTables),
    /// A composite kind's values (`f32`, row-major, channels interleaved).
    Values(Vec<f32>),
    /// Values a worker's submission left on the device (`f32`, row-major, channels
    /// interleaved): a warp's displacement, whose range the worker read back.
    OnDevice(wgpu::Buffer),
    /// A composite kind's operands' host parts and its base's tables, recorded with its
    /// composition on the device ([`GpuKernel::encode_chain`]): a warp's x and y (or its
    /// displacement already on the device), and its base.
    Chain {
        operands: Vec<PreparedTile>,
        base: Option<TileTables>,
    },
}

/// One storage table as the device receives it.
#[derive(Debug, Clone)]
pub(crate) struct Table {
    /// A debugging label for the buffer.
    pub label: &'static str,
    /// Its bytes: at least one record, since a binding may not be smaller than one element of
    /// the array the shader declares (the layout derived from the shader says so).
    pub bytes: Vec<u8>,
    /// The size of a table the tile's passes write on the device ([`TileTables::passes`]),
    /// uploaded from nowhere: `bytes` is then empty.
    pub on_device: Option<u64>,
}

impl Table {
    /// The records `records`, or one zeroed record where there are none (the shader reads no
    /// further than the counts it is given, so the filler is never read).
    pub(crate) fn new<T: bytemuck::Pod>(label: &'static str, records: &[T]) -> Self {
        let bytes = if records.is_empty() {
            bytemuck::bytes_of(&T::zeroed()).to_vec()
        } else {
            bytemuck::cast_slice(records).to_vec()
        };
        Self {
            label,
            bytes,
            on_device: None,
        }
    }

    /// The records `records` for a shader's `var<uniform>` array of `capacity` records (a
    /// table every invocation reads at the same index, which a GPU serves from its constant
    /// cache and lavapipe without a gather), zero-padded to that size, as a uniform binding
    /// must be at least the array it declares.
    ///
    /// # Errors
    /// [`GpuError::LimitsExceeded`] naming `what` for more than `capacity` records.
    pub(crate) fn uniform<T: bytemuck::Pod>(
        label: &'static str,
        what: &'static str,
        records: &[T],
        capacity: usize,
    ) -> Result<Self, GpuError> {
        if records.len() > capacity {
            return Err(GpuError::LimitsExceeded {
                what,
                value: records.len() as u64,
                limit: capacity as u64,
            });
        }
        let mut bytes: Vec<u8> = bytemuck::cast_slice(records).to_vec();
        bytes.resize(capacity * size_of::<T>(), 0);
        Ok(Self {
            label,
            bytes,
            on_device: None,
        })
    }

    /// A table of `size` bytes that the tile's passes fill on the device, where the host
    /// uploads nothing ([`ShaderKernel::encode_passes`]).
    pub(crate) fn filled_on_device(label: &'static str, size: u64) -> Self {
        Self {
            label,
            bytes: Vec::new(),
            on_device: Some(size.max(4)),
        }
    }

    /// The table a kind's own pass fills (`size` bytes, [`filled_on_device`](Self::filled_on_device)),
    /// or, for a tile without the pass (`None`), 16 zero bytes that the shader does not read
    /// (one record of any array its tables declare).
    pub(crate) fn left_to_pass(label: &'static str, size: Option<u64>) -> Self {
        match size {
            Some(size) => Self::filled_on_device(label, size),
            None => Self {
                label,
                bytes: vec![0; 16],
                on_device: None,
            },
        }
    }
}

/// What a [`ShaderKernel`] uploads for one tile.
#[derive(Debug)]
pub(crate) struct TileTables {
    /// The uniform of binding 0 (the shader's params struct) as bytes.
    pub uniform: Vec<u8>,
    /// The per-tile storage tables, in binding order (the columns and rows last).
    pub tables: Vec<Table>,
    /// Host parts of other kernels' dispatches that fill the table left to the device, in
    /// the order [`ShaderKernel::encode_passes`] records them (a texture's LRP strata).
    pub passes: Vec<PreparedTile>,
}

impl TileTables {
    /// A uniform record and the tile's tables.
    pub(crate) fn new<U: bytemuck::Pod>(uniform: &U, tables: Vec<Table>) -> Self {
        Self {
            uniform: bytemuck::bytes_of(uniform).to_vec(),
            tables,
            passes: Vec::new(),
        }
    }

    /// These tables with the kind's own pass to record first, with `uniform` as its uniform
    /// (the pass fills the table [`Table::left_to_pass`] left to it); unchanged for `None`.
    pub(crate) fn with_pass<U: bytemuck::Pod>(mut self, uniform: Option<&U>) -> Self {
        if let Some(uniform) = uniform {
            self.passes
                .push(PreparedTile::Tables(Self::new(uniform, Vec::new())));
        }
        self
    }
}
