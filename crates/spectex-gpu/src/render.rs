//! The render loop of [`GpuEvaluator`](crate::GpuEvaluator): a window cut into tiles, each
//! dispatched into one slot of a [`Ring`] of device buffers made once per evaluator, packed to
//! its [`OutputFormat`] on the device, and copied either back to the host (mapped while the next
//! tile computes, then written straight into the caller's slice) or into a caller's
//! `wgpu::Buffer` with no read-back at all. Error scopes are pushed once per render; timestamp
//! queries (where the device has them) time every dispatch, so a render reports its kernel-only
//! time beside its end-to-end time ([`RenderStats`]).

use std::cell::Cell;
use std::collections::{BTreeMap, VecDeque};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Instant;

use crate::cache::CachedPipeline;
use crate::kernel::{GpuKernel, PreparedTile};
use crate::layout::wgsl_struct;
use crate::pipeline::{
    DEVICE_WAIT_NANOS, ErrorScopes, Gpu, Mapping, TIMESTAMP_PAIR_BYTES, compute_pipeline,
    encode_pass, flat_grid, leading,
};
use crate::{GpuError, GpuWindow, wgsl_source};

/// Tiles in flight: tile k + 1 (and k + 2) compute while tile k is mapped and copied out.
pub(crate) const RING_SLOTS: usize = 3;

/// Workgroup size of `output.wgsl`'s packing entry points.
const PACK_WORKGROUP: u32 = 64;

/// How a render's values reach the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum OutputFormat {
    /// `f32`, the evaluator's own values (4 bytes each).
    #[default]
    F32,
    /// IEEE binary16 (2 bytes each), round to nearest; magnitudes past 65504 clamped to it.
    F16,
    /// 8-bit unorm (1 byte each), the CPU's PNG quantisation `round(clamp(v, 0, 1) · 255)`
    /// with halves up, exactly (the device computes the level in integers, as exact as the
    /// CPU's f64): the bytes of the `f32` render quantised by the CPU.
    Unorm8,
    /// 16-bit unorm (2 bytes each), `round(clamp(v, 0, 1) · 65535)`, exactly as [`Self::Unorm8`].
    Unorm16,
}

impl OutputFormat {
    /// Bytes of one value in this format.
    #[must_use]
    pub fn bytes_per_value(self) -> usize {
        match self {
            Self::F32 => 4,
            Self::F16 | Self::Unorm16 => 2,
            Self::Unorm8 => 1,
        }
    }

    /// The packing entry point of `output.wgsl`, `None` for `f32` (no packing).
    fn entry_point(self) -> Option<&'static str> {
        match self {
            Self::F32 => None,
            Self::F16 => Some("pack_f16"),
            Self::Unorm8 => Some("pack_unorm8"),
            Self::Unorm16 => Some("pack_unorm16"),
        }
    }
}

/// What a render cost, end to end and on the device.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct RenderStats {
    /// Wall-clock seconds of the render call: tables, dispatches, waits and copies.
    pub seconds: f64,
    /// Seconds the device spent in the render's dispatches (model kernels, the passes of a
    /// composite kind, packing), from timestamp queries; `None` where the device has none,
    /// and for a render into a device buffer or texture, which does not wait for the device.
    pub kernel_seconds: Option<f64>,
    /// Tiles dispatched.
    pub tiles: usize,
    /// Bytes copied from the device to the host (0 for a render into a device buffer or
    /// texture).
    pub bytes_read_back: u64,
    /// Values the output format clamped, counted on the device, for a packed render read back
    /// to the host ([`OutputFormat::Unorm8`] and [`OutputFormat::Unorm16`]: outside `[0, 1]`
    /// or NaN, as the CPU's PNG writer counts them; [`OutputFormat::F16`]: magnitudes past
    /// 65504 or NaN); `None` for `f32` and for renders that stay on the device.
    pub clipped: Option<u64>,
    /// Seconds the host spent preparing the tiles (uniforms and tables, a phasor's drawn cells,
    /// the operands' host parts of a chain, or a composite kind's whole host composition),
    /// summed over the worker threads that do it beside the dispatches, less their waits for
    /// the device (a composition's operands read back, a warp's displacement range): what the
    /// host's part of the render costs.
    pub host_seconds: f64,
}

impl RenderStats {
    /// Millions of pixels per second of `pixels` end to end.
    #[must_use]
    pub fn mpix_per_second(&self, pixels: usize) -> f64 {
        pixels as f64 / self.seconds.max(f64::MIN_POSITIVE) / 1e6
    }

    /// Millions of pixels per second of `pixels` on the device alone, where timed.
    #[must_use]
    pub fn kernel_mpix_per_second(&self, pixels: usize) -> Option<f64> {
        self.kernel_seconds
            .map(|s| pixels as f64 / s.max(f64::MIN_POSITIVE) / 1e6)
    }
}

wgsl_struct! {
    /// `PackParams` of `output.wgsl` (binding 0).
    pub(crate) struct PackParams {
        count: u32,
        words_per_row: u32,
        _pad0: u32,
        _pad1: u32,
    }
}

/// The packing pipelines of `output.wgsl` (built on first use, once per device through the
/// context's cache) and the store pipelines of the texture formats.
#[derive(Debug, Default)]
pub(crate) struct Packers(Mutex<Vec<((&'static str, &'static str), CachedPipeline)>>);

impl Packers {
    /// The pipeline of `key`, from this evaluator's list or the context's cache.
    fn get(
        &self,
        gpu: &Gpu,
        key: (&'static str, &'static str),
        source: impl FnOnce() -> Option<String>,
    ) -> Result<CachedPipeline, GpuError> {
        let mut list = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some((_, hit)) = list.iter().find(|(k, _)| *k == key) {
            return Ok(hit.clone());
        }
        let built = compute_pipeline(gpu, (key.0, key.1, Vec::new()), 1, source)?;
        list.push((key, built.clone()));
        Ok(built)
    }

    /// Whether the packing pipeline of `format` is built (`f32` has none).
    #[cfg(feature = "unit-tests")]
    pub(crate) fn holds(&self, format: OutputFormat) -> bool {
        let list = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        format
            .entry_point()
            .is_some_and(|entry| list.iter().any(|(k, _)| *k == ("output", entry)))
    }

    /// The packing pipeline of `format`, `None` for `f32`.
    pub(crate) fn pack(
        &self,
        gpu: &Gpu,
        format: OutputFormat,
    ) -> Result<Option<CachedPipeline>, GpuError> {
        format
            .entry_point()
            .map(|entry| self.get(gpu, ("output", entry), || wgsl_source("output")))
            .transpose()
    }

    /// The store pipeline of a storage texture format of [`TEXTURE_FORMATS`].
    pub(crate) fn store(&self, gpu: &Gpu, name: &'static str) -> Result<CachedPipeline, GpuError> {
        self.get(gpu, (name, "store_main"), || Some(store_wgsl(name)))
    }
}

/// Bytes of a tile's count of clamped values (one `u32`).
const CLIPPED_BYTES: u64 = 4;

/// One slot of the ring: a tile's values, its packed words, and the host-visible copy.
#[derive(Debug)]
struct Slot {
    /// `f32` values of a tile (the model kernel's output binding, or the upload of a composite
    /// kind's host values).
    values: wgpu::Buffer,
    /// The tile packed by `output.wgsl` (half the values' size, enough for every packing).
    packed: wgpu::Buffer,
    /// The packing's count of clamped values in the tile (`output.wgsl`'s `clipped`).
    clipped: wgpu::Buffer,
    /// What comes back to the host: a tile's bytes, then a timestamp pair and the count of
    /// clamped values, where recorded.
    readback: wgpu::Buffer,
    /// Where the slot's timestamp pair is resolved.
    stamps: Option<wgpu::Buffer>,
}

/// The device buffers of a render, made once per evaluator and kept for the next render while
/// large enough. A ring of [`RING_SLOTS`] slots of `capacity` values each.
#[derive(Debug)]
pub(crate) struct Ring {
    /// Values (`f32`) one slot holds.
    capacity: u64,
    slots: Vec<Slot>,
    /// Two timestamps per slot, where the device has them.
    queries: Option<wgpu::QuerySet>,
}

impl Ring {
    /// A ring whose slots hold `capacity` values each.
    pub(crate) fn new(gpu: &Gpu, capacity: u64) -> Self {
        use wgpu::BufferUsages as U;
        let bytes = 4 * capacity.max(1);
        let slots = (0..RING_SLOTS)
            .map(|_| Slot {
                values: gpu.empty(
                    "spectex tile values",
                    bytes,
                    U::STORAGE | U::COPY_SRC | U::COPY_DST,
                ),
                packed: gpu.empty(
                    "spectex tile packed",
                    bytes.div_ceil(2).next_multiple_of(4),
                    U::STORAGE | U::COPY_SRC,
                ),
                clipped: gpu.empty(
                    "spectex tile clipped",
                    CLIPPED_BYTES,
                    U::STORAGE | U::COPY_SRC | U::COPY_DST,
                ),
                readback: gpu.empty(
                    "spectex tile readback",
                    bytes + TIMESTAMP_PAIR_BYTES + CLIPPED_BYTES,
                    U::MAP_READ | U::COPY_DST,
                ),
                stamps: gpu.timestamps.then(|| {
                    gpu.empty(
                        "spectex tile timestamps",
                        TIMESTAMP_PAIR_BYTES,
                        U::QUERY_RESOLVE | U::COPY_SRC,
                    )
                }),
            })
            .collect();
        Self {
            capacity,
            slots,
            queries: gpu.query_set(RING_SLOTS as u32),
        }
    }

    /// Values one slot holds.
    pub(crate) fn capacity(&self) -> u64 {
        self.capacity
    }
}

/// What takes a tile's bytes on the host: the tile's column and row in the window, the tile,
/// and its bytes (row-major over the tile).
pub(crate) type HostWrite<'a> = dyn FnMut([usize; 2], &GpuWindow, &[u8]) + 'a;

/// Bytes a thread copies at a time in [`copy_tile`]; a tile of at most this many bytes is
/// copied on the calling thread, where waking the pool would cost more than the copy.
const COPY_CHUNK: usize = 256 << 10;

/// Copies a tile's rows, `line` bytes each and packed in `bytes`, into `rows` (the window's
/// rows the tile covers, `row` bytes each) from byte `at` of each row.
///
/// Large tiles are copied on every core (rayon's pool), while the device computes the next
/// tile. A render into fresh memory (the CLI's output image, a new numpy array) is the first
/// write to every page of it, and on a virtual machine a page fault costs about 2 µs: one
/// thread copied 64 MiB into fresh memory in 41–47 ms here, 1.5 GB/s, against 9 ms into
/// memory already touched, so the copy, not the device, bounded a fast kernel's render.
pub(crate) fn copy_tile(rows: &mut [u8], row: usize, at: usize, line: usize, bytes: &[u8]) {
    use rayon::prelude::{
        IndexedParallelIterator, ParallelIterator, ParallelSlice, ParallelSliceMut,
    };
    if line == row {
        let rows = &mut rows[..bytes.len()];
        if bytes.len() <= COPY_CHUNK {
            rows.copy_from_slice(bytes);
        } else {
            rows.par_chunks_mut(COPY_CHUNK)
                .zip(bytes.par_chunks(COPY_CHUNK))
                .for_each(|(to, from)| to.copy_from_slice(from));
        }
    } else if bytes.len() <= COPY_CHUNK {
        for (to, from) in rows.chunks_exact_mut(row).zip(bytes.chunks_exact(line)) {
            to[at..at + line].copy_from_slice(from);
        }
    } else {
        rows.par_chunks_exact_mut(row)
            .zip(bytes.par_chunks_exact(line))
            .with_min_len((COPY_CHUNK / line).max(1))
            .for_each(|(to, from)| to[at..at + line].copy_from_slice(from));
    }
}

/// Where a render's bytes go.
pub(crate) enum Sink<'a> {
    /// The host, tile by tile.
    Host(&'a mut HostWrite<'a>),
    /// A caller's device buffer, row-major over the window from byte `offset`.
    Device {
        buffer: &'a wgpu::Buffer,
        offset: u64,
    },
    /// A caller's storage texture (its first mip level), pixel (x, y) of the window at texel
    /// (x, y), written by `pipeline` (`store_wgsl` of the texture's format).
    Texture {
        view: wgpu::TextureView,
        pipeline: CachedPipeline,
    },
}

impl Sink<'_> {
    /// Whether the render's tiles come back to the host, so that it waits for the device (and
    /// can read its timestamps); one that stays on the device returns once submitted.
    fn reads_back(&self) -> bool {
        matches!(self, Self::Host(_))
    }
}

/// The storage texture formats [`GpuEvaluator::render_to_texture`] writes: grey values go to
/// every colour channel, colour to R, G, B; alpha is 1.
///
/// [`GpuEvaluator::render_to_texture`]: crate::GpuEvaluator::render_to_texture
pub const TEXTURE_FORMATS: &[wgpu::TextureFormat] = &[
    wgpu::TextureFormat::R32Float,
    wgpu::TextureFormat::Rgba32Float,
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
];

/// The WGSL name and pipeline key of a storage format in [`TEXTURE_FORMATS`].
pub(crate) fn texture_format_name(format: wgpu::TextureFormat) -> Option<&'static str> {
    match format {
        wgpu::TextureFormat::R32Float => Some("r32float"),
        wgpu::TextureFormat::Rgba32Float => Some("rgba32float"),
        wgpu::TextureFormat::Rgba16Float => Some("rgba16float"),
        wgpu::TextureFormat::Rgba8Unorm => Some("rgba8unorm"),
        _ => None,
    }
}

/// The store shader for a storage texture of WGSL format `format`: a tile's values to texels.
pub(crate) fn store_wgsl(format: &str) -> String {
    format!(
        "// A tile's f32 values (1 or 3 per pixel) stored into a caller's {format} texture.
struct StoreParams {{
    origin_x: u32,
    origin_y: u32,
    width: u32,
    height: u32,
    channels: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}}

@group(0) @binding(0) var<uniform> store: StoreParams;
@group(0) @binding(1) var<storage, read> values: array<f32>;
@group(0) @binding(2) var target_texture: texture_storage_2d<{format}, write>;

@compute @workgroup_size(8, 8, 1)
fn store_main(@builtin(global_invocation_id) gid: vec3<u32>) {{
    if (gid.x >= store.width || gid.y >= store.height) {{
        return;
    }}
    let i = (gid.y * store.width + gid.x) * store.channels;
    var texel = vec4<f32>(values[i], values[i], values[i], 1.0);
    if (store.channels == 3u) {{
        texel = vec4<f32>(values[i], values[i + 1u], values[i + 2u], 1.0);
    }}
    textureStore(target_texture, vec2<u32>(store.origin_x + gid.x, store.origin_y + gid.y), texel);
}}
"
    )
}

wgsl_struct! {
    /// `StoreParams` of the store shader (binding 0).
    pub(crate) struct StoreParams {
        origin_x: u32,
        origin_y: u32,
        width: u32,
        height: u32,
        channels: u32,
        _pad0: u32,
        _pad1: u32,
        _pad2: u32,
    }
}

/// One tile of a window: its column and row in the window, and its own window.
pub(crate) struct Tile {
    pub at: [usize; 2],
    pub window: GpuWindow,
}

/// A tile submitted and not yet copied out.
struct Pending {
    tile: usize,
    slot: usize,
    submission: wgpu::SubmissionIndex,
    mapping: Option<Mapping>,
    /// Bytes of the tile's values in the output format.
    bytes: usize,
    /// Where the timestamp pair sits in the readback, when the dispatch was timed here.
    stamps_at: Option<usize>,
    /// Where the count of clamped values sits in the readback, when counted.
    clipped_at: Option<usize>,
}

/// What [`record_all`] gathered from the tiles it read back.
#[derive(Debug, Default, Clone, Copy)]
struct ReadBack {
    bytes: u64,
    /// Clamped values, where the tiles' packing counted them.
    clipped: Option<u64>,
    /// Seconds of tile preparation on the workers.
    host_seconds: f64,
}

impl ReadBack {
    fn add(&mut self, tile: Self) {
        self.bytes += tile.bytes;
        if let Some(n) = tile.clipped {
            *self.clipped.get_or_insert(0) += n;
        }
    }
}

/// Renders `tiles` of `window` through `kernel` into `sink`, in `format`, on `ring`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn run(
    gpu: &Gpu,
    kernel: &dyn GpuKernel,
    packers: &Packers,
    ring: &Ring,
    window: &GpuWindow,
    tiles: &[Tile],
    format: OutputFormat,
    mut sink: Sink<'_>,
) -> Result<RenderStats, GpuError> {
    let start = Instant::now();
    let clock = gpu.clock_nanos();
    let timed = gpu.timestamps && sink.reads_back();
    let scope = ErrorScopes::push(&gpu.device);
    let result = run_scoped(gpu, kernel, packers, ring, window, tiles, format, &mut sink);
    // A failed submission shows as a failed map: the scope then says what failed.
    let popped = scope.pop();
    let read_back = match (result, popped) {
        (_, Err(scoped)) => return Err(scoped),
        (Err(e), Ok(())) => return Err(e),
        (Ok(read_back), Ok(())) => read_back,
    };
    Ok(RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        kernel_seconds: timed.then(|| gpu.clock_nanos().saturating_sub(clock) as f64 * 1e-9),
        tiles: tiles.len(),
        bytes_read_back: read_back.bytes,
        clipped: read_back.clipped,
        host_seconds: read_back.host_seconds,
    })
}

/// Tiles' host parts ([`GpuKernel::prepare_tile`]) made on worker threads ahead of the
/// dispatches, at most `lookahead` tiles ahead of the one being recorded, and taken in order.
struct Prepared<'a> {
    kernel: &'a dyn GpuKernel,
    tiles: &'a [Tile],
    lookahead: usize,
    next: AtomicUsize,
    state: Mutex<PreparedState>,
    changed: Condvar,
    /// Nanoseconds the workers spent in `prepare_tile`.
    host_nanos: AtomicU64,
}

#[derive(Default)]
struct PreparedState {
    ready: BTreeMap<usize, Result<PreparedTile, GpuError>>,
    /// Tiles taken by the recording thread.
    taken: usize,
    stop: bool,
}

impl Prepared<'_> {
    fn lock(&self) -> MutexGuard<'_, PreparedState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// A worker: prepares the next tile nobody has taken, while within the lookahead.
    fn work(&self) {
        loop {
            let k = self.next.fetch_add(1, Ordering::Relaxed);
            if k >= self.tiles.len() {
                return;
            }
            let mut state = self.lock();
            while !state.stop && k >= state.taken + self.lookahead {
                state = self
                    .changed
                    .wait(state)
                    .unwrap_or_else(PoisonError::into_inner);
            }
            if state.stop {
                return;
            }
            drop(state);
            // A panic in a worker would leave the recording thread waiting for this tile: it
            // becomes the tile's error instead.
            let started = Instant::now();
            let waited_before = DEVICE_WAIT_NANOS.with(Cell::get);
            let tables = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                self.kernel.prepare_tile(&self.tiles[k].window)
            }))
            .unwrap_or_else(|_| {
                Err(GpuError::Validation(format!(
                    "preparing tile {k} on a worker thread panicked"
                )))
            });
            // The host's work: the time spent waiting for the device (a warp's range, a tile
            // the host composes) is the device's.
            let waited = DEVICE_WAIT_NANOS
                .with(Cell::get)
                .saturating_sub(waited_before);
            let nanos = u64::try_from(started.elapsed().as_nanos()).unwrap_or(u64::MAX);
            self.host_nanos
                .fetch_add(nanos.saturating_sub(waited), Ordering::Relaxed);
            self.lock().ready.insert(k, tables);
            self.changed.notify_all();
        }
    }

    /// Tile `k`'s host part, once a worker made it (tiles are taken in order).
    fn take(&self, k: usize) -> Result<PreparedTile, GpuError> {
        let mut state = self.lock();
        loop {
            if let Some(tables) = state.ready.remove(&k) {
                state.taken = k + 1;
                self.changed.notify_all();
                return tables;
            }
            state = self
                .changed
                .wait(state)
                .unwrap_or_else(PoisonError::into_inner);
        }
    }

    fn stop(&self) {
        self.lock().stop = true;
        self.changed.notify_all();
    }
}

/// [`run`] inside its error scope: what was read back. The tiles' host parts are prepared on
/// up to one worker thread per core (less one for this thread), so a kind whose tables cost
/// the host (a phasor's drawn kernels, a texture's passes) keeps the device busy, and a
/// composite kind's tiles (a warp's, a combination's) render side by side. A single tile has
/// nothing to overlap with and is prepared on this thread: starting a thread for it took about
/// 0.1 ms, a third of a small render (16², lavapipe).
#[allow(clippy::too_many_arguments)]
fn run_scoped(
    gpu: &Gpu,
    kernel: &dyn GpuKernel,
    packers: &Packers,
    ring: &Ring,
    window: &GpuWindow,
    tiles: &[Tile],
    format: OutputFormat,
    sink: &mut Sink<'_>,
) -> Result<ReadBack, GpuError> {
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let workers = cores.saturating_sub(1).clamp(1, 16).min(tiles.len());
    let prepared = Prepared {
        kernel,
        tiles,
        lookahead: workers + RING_SLOTS,
        next: AtomicUsize::new(0),
        state: Mutex::new(PreparedState::default()),
        changed: Condvar::new(),
        host_nanos: AtomicU64::new(0),
    };
    std::thread::scope(|scope| {
        if tiles.len() == 1 {
            prepared.work();
        } else {
            for _ in 0..workers {
                scope.spawn(|| prepared.work());
            }
        }
        let result = record_all(
            gpu, kernel, packers, ring, window, tiles, format, sink, &prepared,
        );
        prepared.stop();
        result.map(|read_back| ReadBack {
            host_seconds: prepared.host_nanos.load(Ordering::Relaxed) as f64 * 1e-9,
            ..read_back
        })
    })
}

/// Records, submits and drains every tile in order, its host part from `prepared`.
#[allow(clippy::too_many_arguments)]
fn record_all(
    gpu: &Gpu,
    kernel: &dyn GpuKernel,
    packers: &Packers,
    ring: &Ring,
    window: &GpuWindow,
    tiles: &[Tile],
    format: OutputFormat,
    sink: &mut Sink<'_>,
    prepared: &Prepared<'_>,
) -> Result<ReadBack, GpuError> {
    let channels = kernel.output_channels();
    let per_value = format.bytes_per_value();
    let pack = packers.pack(gpu, format)?;
    let reads_back = sink.reads_back();
    let mut pending: VecDeque<Pending> = VecDeque::with_capacity(RING_SLOTS);
    let mut read_back = ReadBack::default();
    for (k, tile) in tiles.iter().enumerate() {
        let tables = prepared.take(k)?;
        if pending.len() == RING_SLOTS
            && let Some(done) = pending.pop_front()
        {
            read_back.add(finish(gpu, ring, tiles, done, sink)?);
        }
        let slot_index = k % RING_SLOTS;
        let slot = &ring.slots[slot_index];
        let values = tile.window.width * tile.window.height * channels;
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("spectex render"),
            });
        let pair = 2 * slot_index as u32;
        let direct = !matches!(tables, PreparedTile::Values(_) | PreparedTile::OnDevice(_));
        let timer = ring.queries.as_ref().filter(|_| reads_back).map(|set| {
            wgpu::ComputePassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: Some(pair),
                end_of_pass_write_index: Some(pair + 1),
            }
        });
        let output = &slot.values;
        encode_prepared(
            gpu,
            kernel,
            &tile.window,
            tables,
            &mut encoder,
            output,
            timer,
        )?;
        let bytes = values * per_value;
        let source = match &pack {
            None => &slot.values,
            Some(pipeline) => {
                encoder.clear_buffer(&slot.clipped, 0, None);
                encode_pack(gpu, &mut encoder, pipeline, slot, values as u32)?;
                &slot.packed
            }
        };
        let copied = (bytes as u64).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let mut stamps_at = None;
        match sink {
            Sink::Host(_) => {
                encoder.copy_buffer_to_buffer(source, 0, &slot.readback, 0, copied);
            }
            Sink::Device { buffer, offset } => {
                copy_to_device(
                    &mut encoder,
                    source,
                    buffer,
                    *offset,
                    window,
                    tile,
                    channels,
                    per_value,
                )?;
            }
            Sink::Texture { view, pipeline } => {
                encode_store(gpu, &mut encoder, pipeline, view, slot, tile, channels)?;
            }
        }
        if reads_back
            && direct
            && let (Some(set), Some(stamps)) = (&ring.queries, &slot.stamps)
        {
            encoder.resolve_query_set(set, pair..pair + 2, stamps, 0);
            encoder.copy_buffer_to_buffer(stamps, 0, &slot.readback, copied, TIMESTAMP_PAIR_BYTES);
            stamps_at = Some(copied as usize);
        }
        // A packed tile read back to the host brings its count of clamped values along.
        let mut clipped_at = None;
        if pack.is_some() && reads_back {
            let at = copied + TIMESTAMP_PAIR_BYTES;
            encoder.copy_buffer_to_buffer(&slot.clipped, 0, &slot.readback, at, CLIPPED_BYTES);
            clipped_at = Some(at as usize);
        }
        let submission = gpu.queue.submit([encoder.finish()]);
        let mapping = reads_back.then(|| Mapping::ask(&slot.readback));
        pending.push_back(Pending {
            tile: k,
            slot: slot_index,
            submission,
            mapping,
            bytes,
            stamps_at,
            clipped_at,
        });
    }
    while let Some(done) = pending.pop_front() {
        read_back.add(finish(gpu, ring, tiles, done, sink)?);
    }
    Ok(read_back)
}

/// Records the dispatches of `tile`, whose host part is `prepared`, through `kernel` into
/// `encoder`, its values written from the start of `output`; values made on the host (a
/// composite kind's, its operands' passes run and timed on a worker) or left on the device by
/// a worker are copied there. `timer` writes the dispatches' timestamps.
///
/// # Errors
/// What the kernel's `encode_tile` or `encode_chain` returns.
pub(crate) fn encode_prepared(
    gpu: &Gpu,
    kernel: &dyn GpuKernel,
    tile: &GpuWindow,
    prepared: PreparedTile,
    encoder: &mut wgpu::CommandEncoder,
    output: &wgpu::Buffer,
    timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
) -> Result<(), GpuError> {
    match prepared {
        PreparedTile::Tables(tables) => kernel.encode_tile(tile, tables, encoder, output, timer),
        PreparedTile::Chain { operands, base } => {
            kernel.encode_chain(tile, operands, base, encoder, output, timer)
        }
        PreparedTile::OnDevice(values) => {
            encoder.copy_buffer_to_buffer(&values, 0, output, 0, values.size());
            Ok(())
        }
        PreparedTile::Values(values) => {
            let bytes: &[u8] = bytemuck::cast_slice(&values);
            let upload = gpu.buffer("spectex values", bytes, wgpu::BufferUsages::COPY_SRC);
            encoder.copy_buffer_to_buffer(&upload, 0, output, 0, bytes.len() as u64);
            Ok(())
        }
    }
}

/// Waits for a pending tile, hands its bytes to a host sink, clocks its timestamps and reads
/// its count of clamped values; what was read back.
fn finish(
    gpu: &Gpu,
    ring: &Ring,
    tiles: &[Tile],
    done: Pending,
    sink: &mut Sink<'_>,
) -> Result<ReadBack, GpuError> {
    let Some(mapping) = done.mapping else {
        return Ok(ReadBack::default());
    };
    let readback = &ring.slots[done.slot].readback;
    mapping.wait(&gpu.device, &gpu.lost, Some(done.submission))?;
    let mut read = ReadBack::default();
    {
        let view = readback
            .slice(..)
            .get_mapped_range()
            .map_err(|e| GpuError::DeviceLost(format!("reading the output: {e}")))?;
        if let Sink::Host(write) = sink {
            let tile = &tiles[done.tile];
            write(tile.at, &tile.window, &view[..done.bytes]);
            read.bytes += done.bytes as u64;
        }
        if let Some(at) = done.stamps_at {
            gpu.clock_pairs(&view[at..at + TIMESTAMP_PAIR_BYTES as usize]);
            read.bytes += TIMESTAMP_PAIR_BYTES;
        }
        if let Some(at) = done.clipped_at {
            let count: [u8; 4] = view[at..at + 4].try_into().unwrap_or_default();
            read.clipped = Some(u64::from(u32::from_le_bytes(count)));
            read.bytes += CLIPPED_BYTES;
        }
    }
    readback.unmap();
    Ok(read)
}

/// Records the packing of a slot's first `count` values into its packed buffer.
fn encode_pack(
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &CachedPipeline,
    slot: &Slot,
    count: u32,
) -> Result<(), GpuError> {
    // Every packing puts at most 4 and at least 2 values in a word; the pipeline's entry point
    // knows which, so size the grid for the larger count of words (extra invocations return).
    let (words_per_row, grid) = flat_grid(gpu, count.div_ceil(2), PACK_WORKGROUP);
    let params = PackParams {
        count,
        words_per_row,
        ..bytemuck::Zeroable::zeroed()
    };
    let target = slot.packed.as_entire_binding();
    let tile = (u64::from(count), target, grid);
    let counter = Some(&slot.clipped);
    encode_output_pass(
        gpu,
        encoder,
        "spectex pack",
        pipeline,
        &params,
        slot,
        tile,
        counter,
    )
}

/// Records the store of a slot's tile values into a caller's storage texture.
fn encode_store(
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &CachedPipeline,
    view: &wgpu::TextureView,
    slot: &Slot,
    tile: &Tile,
    channels: usize,
) -> Result<(), GpuError> {
    let (width, height) = (tile.window.width as u32, tile.window.height as u32);
    let params = StoreParams {
        origin_x: tile.at[0] as u32,
        origin_y: tile.at[1] as u32,
        width,
        height,
        channels: channels as u32,
        ..bytemuck::Zeroable::zeroed()
    };
    let values = u64::from(width) * u64::from(height) * channels as u64;
    let target = wgpu::BindingResource::TextureView(view);
    let tile = (values, target, [width.div_ceil(8), height.div_ceil(8)]);
    encode_output_pass(
        gpu,
        encoder,
        "spectex store",
        pipeline,
        &params,
        slot,
        tile,
        None,
    )
}

/// Records one dispatch of an output pass (a packing of `output.wgsl` or a texture store):
/// `params` at binding 0, the slot's first `values` values at binding 1, `target` at binding 2,
/// over `groups` workgroups; `tile` is `(values, target, groups)`; a packing's count of clamped
/// values, `counter`, at binding 3.
#[allow(clippy::too_many_arguments)]
fn encode_output_pass<P: bytemuck::Pod>(
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    label: &'static str,
    pipeline: &CachedPipeline,
    params: &P,
    slot: &Slot,
    (values, target, groups): (u64, wgpu::BindingResource<'_>, [u32; 2]),
    counter: Option<&wgpu::Buffer>,
) -> Result<(), GpuError> {
    let mut bindings = vec![leading(&slot.values, 4 * values.max(1)), target];
    bindings.extend(counter.map(wgpu::Buffer::as_entire_binding));
    encode_pass(
        gpu,
        encoder,
        (label, pipeline),
        params,
        bindings,
        groups,
        None,
    )
}

/// Records the copy of a tile's bytes from `source` into a caller's `buffer`, row-major over
/// the window from byte `offset`: one copy for a tile as wide as the window, one per row
/// otherwise. Device copies move whole 4-byte words, which the caller's layout must allow.
#[allow(clippy::too_many_arguments)]
fn copy_to_device(
    encoder: &mut wgpu::CommandEncoder,
    source: &wgpu::Buffer,
    buffer: &wgpu::Buffer,
    offset: u64,
    window: &GpuWindow,
    tile: &Tile,
    channels: usize,
    per_value: usize,
) -> Result<(), GpuError> {
    let pixel = (channels * per_value) as u64;
    let window_row = window.width as u64 * pixel;
    let tile_row = tile.window.width as u64 * pixel;
    let at = offset + (tile.at[1] as u64 * window_row) + tile.at[0] as u64 * pixel;
    let align = wgpu::COPY_BUFFER_ALIGNMENT;
    if tile.window.width == window.width {
        let bytes = tile_row * tile.window.height as u64;
        let size = bytes.next_multiple_of(align);
        check_aligned(at, "byte offset of a tile in the buffer")?;
        encoder.copy_buffer_to_buffer(source, 0, buffer, at, size);
        return Ok(());
    }
    check_aligned(window_row, "bytes of one window row")?;
    check_aligned(at, "byte offset of a tile in the buffer")?;
    check_aligned(tile_row, "bytes of one tile row")?;
    for row in 0..tile.window.height as u64 {
        encoder.copy_buffer_to_buffer(
            source,
            row * tile_row,
            buffer,
            at + row * window_row,
            tile_row,
        );
    }
    Ok(())
}

/// A device copy's offset or size must be a whole number of 4-byte words.
fn check_aligned(value: u64, what: &'static str) -> Result<(), GpuError> {
    if value.is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT) {
        Ok(())
    } else {
        Err(GpuError::Output {
            what,
            value,
            expected: format!(
                "a multiple of {} (device copies move 4-byte words): render a width whose rows \
                 are whole words, or use OutputFormat::F32",
                wgpu::COPY_BUFFER_ALIGNMENT
            ),
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use crate::layout::check::{assert_matches_wgsl, assert_source_matches_wgsl};

    pub fn pack_params_match_the_wgsl() {
        assert_matches_wgsl::<super::PackParams>("output", "PackParams");
    }

    /// `copy_tile` puts byte `c` of a tile's row `r` at byte `at + c` of the window's row `r`
    /// and touches nothing else, on the calling thread (small tiles) and on the pool (large
    /// ones, full-width and narrower than the window), as a byte-by-byte loop does.
    pub fn copied_tiles_land_where_their_rows_say() {
        let chunk = super::COPY_CHUNK;
        // (window row bytes, the tile's first byte in a row, tile row bytes, rows)
        let cases = [
            (96, 0, 96, 5),
            (96, 20, 36, 5),
            (4096, 0, 4096, 3 * chunk / 4096 + 7),
            (4100, 1000, 1212, 2 * chunk / 1212 + 3),
            (1 << 20, 12, 1 << 19, 3),
        ];
        for (row, at, line, height) in cases {
            let tile: Vec<u8> = (0..line * height).map(|i| (i % 251) as u8).collect();
            let mut expected = vec![0xA5u8; row * height];
            for r in 0..height {
                for c in 0..line {
                    expected[r * row + at + c] = tile[r * line + c];
                }
            }
            let mut rows = vec![0xA5u8; row * height];
            super::copy_tile(&mut rows, row, at, line, &tile);
            assert!(
                rows == expected,
                "a tile of {height} rows of {line} bytes at byte {at} of rows of {row} bytes"
            );
        }
    }

    /// The CPU's PNG level of `v` for `bits` 8 or 16: `round(clamp(v, 0, 1) · L)` in f64,
    /// where `v · L` is exact, halves up (`spectex-cli`'s `level8`, `level16`).
    fn cpu_level(v: f32, bits: u32) -> u32 {
        let levels = f64::from((1u32 << bits) - 1);
        (f64::from(v).clamp(0.0, 1.0) * levels + 0.5).floor() as u32
    }

    /// Values at and around every half level of 8 and 16 bits (the f32 neighbours where f32
    /// arithmetic rounds `v · L` across the half), the ends, NaN, infinities, negatives,
    /// subnormals and binary16's largest value: what `pack` makes of `values` in `format`,
    /// and the count of values it clamped.
    fn pack_on_device(
        gpu: &super::Gpu,
        values: &[f32],
        format: super::OutputFormat,
    ) -> (Vec<u8>, Option<u64>) {
        let packers = super::Packers::default();
        let pipeline = packers.pack(gpu, format).unwrap().unwrap();
        let ring = super::Ring::new(gpu, values.len() as u64);
        let slot = &ring.slots[0];
        gpu.queue
            .write_buffer(&slot.values, 0, bytemuck::cast_slice(values));
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encoder.clear_buffer(&slot.clipped, 0, None);
        super::encode_pack(gpu, &mut encoder, &pipeline, slot, values.len() as u32).unwrap();
        let bytes = values.len() * format.bytes_per_value();
        let copied = (bytes as u64).next_multiple_of(4);
        encoder.copy_buffer_to_buffer(&slot.packed, 0, &slot.readback, 0, copied);
        encoder.copy_buffer_to_buffer(&slot.clipped, 0, &slot.readback, copied, 4);
        gpu.queue.submit([encoder.finish()]);
        let all =
            crate::pipeline::read_buffer(&gpu.device, &slot.readback, &gpu.lost, None).unwrap();
        let at = copied as usize;
        let count = u32::from_le_bytes(all[at..at + 4].try_into().unwrap());
        (all[..bytes].to_vec(), Some(u64::from(count)))
    }

    /// Every unorm level the device packs is the CPU's level of the same f32 value, exactly,
    /// at and next to every half level (where a rounding of `v · L` in f32 lands a level
    /// apart), and the device counts the values the CPU counts as clipped; binary16 counts
    /// what it clamps. Skips with a message without a GPU (fails when `SPECTEX_REQUIRE_GPU=1`).
    pub fn packing_is_the_cpus_quantisation_and_counts_what_it_clamps() {
        let Some(context) = crate::layout::check::context_or_skip(
            "packing_is_the_cpus_quantisation_and_counts_what_it_clamps",
        ) else {
            return;
        };
        let gpu = super::Gpu::new(&context);
        let specials = [
            0.0,
            -0.0,
            1.0,
            f32::NAN,
            -1.0,
            2.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-40,
            1.0 - f32::EPSILON / 2.0,
            65504.0,
            65505.0,
            -70000.0,
        ];
        for (format, bits) in [
            (super::OutputFormat::Unorm8, 8u32),
            (super::OutputFormat::Unorm16, 16),
        ] {
            let levels = (1u32 << bits) - 1;
            let mut values: Vec<f32> = specials.to_vec();
            for k in 0..levels {
                let half = ((f64::from(k) + 0.5) / f64::from(levels)) as f32;
                let (mut up, mut down) = (half, half);
                values.push(half);
                for _ in 0..3 {
                    up = f32::from_bits(up.to_bits() + 1);
                    down = f32::from_bits(down.to_bits() - 1);
                    values.extend([up, down]);
                }
            }
            // The smallest levels: every 97th f32 from 2^(−bits−3) to 2^(−bits+3).
            let (lo, hi) = (
                (2f32).powi(-(bits as i32) - 3).to_bits(),
                (2f32).powi(-(bits as i32) + 3).to_bits(),
            );
            values.extend((lo..hi).step_by(97).map(f32::from_bits));
            let (bytes, clipped) = pack_on_device(&gpu, &values, format);
            let mut naive_misses = 0;
            for (i, &v) in values.iter().enumerate() {
                let level = if bits == 8 {
                    u32::from(bytes[i])
                } else {
                    u32::from(u16::from_le_bytes([bytes[2 * i], bytes[2 * i + 1]]))
                };
                assert_eq!(level, cpu_level(v, bits), "{format:?} of {v:e}");
                let naive = (v.clamp(0.0, 1.0) * levels as f32 + 0.5).floor();
                naive_misses += usize::from(naive != cpu_level(v, bits) as f32);
            }
            // The values do sit where f32 rounding fails: the test can tell.
            assert!(
                naive_misses > 0,
                "{format:?}: no value next to a half level"
            );
            let outside = values.iter().filter(|v| !(0.0..=1.0).contains(*v)).count();
            assert_eq!(clipped, Some(outside as u64), "{format:?}");
        }
        let (_, clipped) = pack_on_device(&gpu, &specials, super::OutputFormat::F16);
        let past = specials
            .iter()
            .filter(|v| v.is_nan() || v.abs() > 65504.0)
            .count();
        assert_eq!(clipped, Some(past as u64), "f16");
    }

    /// The store shader of every texture format parses and validates, and its uniform has the
    /// layout of the Rust record.
    pub fn store_shaders_validate_with_the_record_layout() {
        for &format in super::TEXTURE_FORMATS {
            let name = super::texture_format_name(format).unwrap_or("?");
            let source = super::store_wgsl(name);
            assert_source_matches_wgsl::<super::StoreParams>(name, &source, "StoreParams");
        }
    }
}
