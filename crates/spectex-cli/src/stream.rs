//! Renders that never hold the whole image: band by band into a tiled OpenEXR or a PNG
//! written row band by row band (`--stream`, automatic above [`STREAM_THRESHOLD_PIXELS`]), and
//! one tile of a `--tiles C×R` grid for batch clusters, its place in the EXR's data window.

use std::io::{BufWriter, Seek, Write};
use std::sync::mpsc;

use anyhow::{Context, Result, anyhow, bail};
use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::math::{RoundingMode, Vec2};
use exr::meta::attribute::{
    AttributeValue, ChannelDescription, IntegerBounds, LevelMode, LineOrder, SampleType, Text,
    TileDescription,
};
use exr::meta::header::Header;
use exr::meta::{BlockDescription, Headers};
use rayon::prelude::*;
use spectex_cpu::{Evaluator, Window};
use spectex_model::{Model, Period};

use crate::args::{RenderArgs, StreamArgs};
use crate::device;
use crate::io::{self, BitDepth, EXR_TILE, Format, WriteReport};

/// Renders with more pixels than this (4096 × 4096) stream without `--stream`.
pub const STREAM_THRESHOLD_PIXELS: usize = 4096 * 4096;

/// Compression of a streamed OpenEXR: none. The whole-image writer's RLE saved 0.04% of a
/// 32768² f32 Perlin render's 4.3 GB (noise has few runs) and doubled the user CPU time.
pub const EXR_COMPRESSION: exr::compression::Compression =
    exr::compression::Compression::Uncompressed;

/// Pixels a band holds at least (whole rows of EXR tiles): 16 evaluator bands of 16 rows at
/// 32768 columns, so that a thread stalled at a band's end costs little; 32 MB of f32.
pub const BAND_PIXELS: usize = 1 << 23;

/// Where a batch engine puts the index of the task that runs: a Slurm job array, then a
/// Kubernetes Indexed Job.
pub const TILE_INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// The EXR attribute naming the render a file belongs to (model and window), which `spectex
/// assemble` requires to be the same in every tile.
pub const RENDER_ATTRIBUTE: &str = "spectexRender";

/// The EXR attribute naming a tile's place in its grid: `K of CxR`.
pub const TILE_ATTRIBUTE: &str = "spectexTile";

/// The rectangle of the image a streamed render writes, in the image's pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// Size of the whole image.
    pub image: (usize, usize),
    /// Left column.
    pub x: usize,
    /// Top row.
    pub y: usize,
    /// Width.
    pub width: usize,
    /// Height.
    pub height: usize,
    /// For a tile of a grid: its index and the grid (columns, rows).
    pub tile: Option<(usize, (usize, usize))>,
}

/// Tile `index` (row-major from the top-left) of a `grid` = (columns, rows) grid over an
/// `image` = (width, height): tiles of `⌈W/C⌉ × ⌈H/R⌉`, the last column and row cut to the
/// image.
///
/// # Errors
/// A grid with no tiles, one whose last column or row would be empty, or an index out of range.
pub fn tile_region(image: (usize, usize), grid: (usize, usize), index: usize) -> Result<Region> {
    let ((w, h), (c, r)) = (image, grid);
    if c == 0 || r == 0 {
        bail!("--tiles {c}x{r} has no tiles; give at least 1 column and 1 row, e.g. --tiles 4x4");
    }
    let (tw, th) = (w.div_ceil(c), h.div_ceil(r));
    if (c - 1) * tw >= w {
        bail!(
            "--tiles {c}x{r}: with tiles ceil({w}/{c}) = {tw} pixels wide the last column of the \
             {w}-pixel-wide image is empty; give fewer columns (at most {w}, e.g. a divisor of {w})"
        );
    }
    if (r - 1) * th >= h {
        bail!(
            "--tiles {c}x{r}: with tiles ceil({h}/{r}) = {th} pixels high the last row of the \
             {h}-pixel-high image is empty; give fewer rows (at most {h}, e.g. a divisor of {h})"
        );
    }
    if index >= c * r {
        bail!(
            "tile index {index} is out of range: a {c}x{r} grid has tiles 0 to {}",
            c * r - 1
        );
    }
    let (x, y) = ((index % c) * tw, (index / c) * th);
    Ok(Region {
        image,
        x,
        y,
        width: tw.min(w - x),
        height: th.min(h - y),
        tile: Some((index, grid)),
    })
}

/// The tile index: `--tile-index`, else the first of [`TILE_INDEX_VARIABLES`] that is set
/// (`lookup` reads the environment).
///
/// # Errors
/// Neither given, or a variable that is not a whole number.
pub fn tile_index(given: Option<usize>, lookup: impl Fn(&str) -> Option<String>) -> Result<usize> {
    if let Some(k) = given {
        return Ok(k);
    }
    for name in TILE_INDEX_VARIABLES {
        if let Some(value) = lookup(name) {
            return value.trim().parse().map_err(|_| {
                anyhow!("{name} = '{value}' is not a tile index; it must be a whole number from 0")
            });
        }
    }
    bail!(
        "--tiles needs the tile to render: give --tile-index K, or run it as a Slurm array task \
         (SLURM_ARRAY_TASK_ID) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX)"
    )
}

/// The region to stream for these flags, or `None` for an ordinary whole render.
///
/// # Errors
/// Bad `--tiles`/`--tile-index`, or `--tiles` with an output that is not OpenEXR.
pub fn plan(args: &StreamArgs, image: (usize, usize), format: Format) -> Result<Option<Region>> {
    if let Some(grid) = args.tiles {
        if format != Format::Exr {
            bail!(
                "--tiles writes each tile as an OpenEXR that records its place: give -o a .exr \
                 name (spectex assemble joins them into one .exr)"
            );
        }
        let index = tile_index(args.tile_index, |name| std::env::var(name).ok())?;
        return tile_region(image, grid, index).map(Some);
    }
    let whole = Region {
        image,
        x: 0,
        y: 0,
        width: image.0,
        height: image.1,
        tile: None,
    };
    Ok((args.stream || image.0.saturating_mul(image.1) > STREAM_THRESHOLD_PIXELS).then_some(whole))
}

/// Rows per band for a region `width` pixels wide: whole rows of EXR tiles, about
/// [`BAND_PIXELS`] pixels.
pub fn band_rows(width: usize) -> usize {
    (BAND_PIXELS / width.max(1)).div_ceil(EXR_TILE).max(1) * EXR_TILE
}

/// A band of rows of a region, one plane of `rows × width` values per channel of the file
/// (in the order the file lists them).
pub(crate) struct Band {
    /// First row, relative to the region.
    pub y: usize,
    /// Rows.
    pub rows: usize,
    /// One plane per channel.
    pub planes: Vec<Vec<f32>>,
}

/// A band's values interleaved per pixel (`channels` of them) as planes in `order`.
fn deinterleave(values: Vec<f32>, channels: usize, order: &[usize]) -> Vec<Vec<f32>> {
    if channels == 1 {
        return vec![values];
    }
    order
        .iter()
        .map(|&c| values.iter().skip(c).step_by(channels).copied().collect())
        .collect()
}

/// What identifies the render a tile belongs to: the model and the window, but not the tile.
fn render_identity(model: &Model, window: &Window, z: f64) -> String {
    // FNV-1a over the model file's text: equal models, equal text.
    let text = spectex_model::to_json(model).unwrap_or_default();
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    format!(
        "model fnv1a64 {hash:016x}, {}x{} at offset ({}, {}), scale {}, z {z}, filter {:?}",
        window.width,
        window.height,
        window.offset[0],
        window.offset[1],
        window.scale,
        window.filter
    )
}

/// Renders `region` of `window` band by band and writes it to `args.output` in `format`,
/// through a temporary file renamed into place once complete.
pub(crate) fn render(
    model: &Model,
    period: Option<Period>,
    args: &RenderArgs,
    window: &Window,
    format: Format,
    region: &Region,
) -> Result<()> {
    // The whole window is checked through its first and last row and first column (its
    // corners, sides and scale) without the in-memory limit on its pixel count.
    for edge in [
        window.tile(0, 0, window.width, 1),
        window.tile(0, window.height.saturating_sub(1), window.width, 1),
        window.tile(0, 0, 1, window.height),
    ] {
        edge.validate()
            .map_err(|e| anyhow!("{e}; check --size, --offset and --scale"))?;
    }
    // A periodic stream is the periodic model's render, as in memory (`render_to_file_with_period`).
    let eval = match period {
        None => Evaluator::new_at_z(model, args.z).map_err(|e| anyhow!("{e}; check --z"))?,
        Some(p) => Evaluator::periodic_at_z(model, args.z, p)
            .map_err(|e| anyhow!("--periodic: {e}; check --periodic and --z"))?,
    };
    let gpu = match device::gpu_for(args.device)? {
        Some(context) => Some((
            match period {
                None => spectex_gpu::GpuEvaluator::new_at_z(&context, model, args.z),
                Some(p) => spectex_gpu::GpuEvaluator::periodic_at_z(&context, model, args.z, p),
            }
            .map_err(|e| anyhow!("{e}; try --device cpu"))?,
            context.adapter_name(),
        )),
        None => None,
    };
    let device_name = gpu
        .as_ref()
        .map_or_else(|| "CPU".to_owned(), |(_, name)| format!("GPU {name}"));
    let channels = eval.output_channels();
    let render_band = |band: &Window, out: &mut Vec<f32>| -> Result<()> {
        match &gpu {
            Some((gpu, _)) => {
                // Every band reuses the evaluator's render ring.
                out.resize(band.width * band.height * channels, 0.0);
                gpu.render_into(band, out)
                    .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            }
            None => {
                out.resize(band.width * band.height * channels, 0.0);
                eval.render_into(band, out, &|_| {})
                    .map_err(|e| anyhow!("{e}"))?;
            }
        }
        Ok(())
    };

    crate::interrupt::watch();
    let tmp = io::temporary_beside(&args.output)?;
    let start = std::time::Instant::now();
    let rows = args
        .stream
        .band_rows
        .unwrap_or_else(|| band_rows(region.width));
    let bar = crate::progress::progress_bar(region.height as u64, "rendering");
    let order: Vec<usize> = if channels == 1 {
        vec![0]
    } else {
        vec![2, 1, 0]
    };
    keep_freed_memory();
    let (send, receive) = mpsc::sync_channel::<Band>(1);
    let (give_back, take_back) = mpsc::channel::<Vec<f32>>();
    let report = std::thread::scope(|scope| -> Result<WriteReport> {
        let file = tmp.as_file();
        let path = &args.output;
        let identity = render_identity(model, window, args.z);
        let writer = scope.spawn(move || -> Result<WriteReport> {
            let mut out = BufWriter::with_capacity(1 << 20, file);
            let next_band = || receive.recv().ok();
            let recycle = |band: Band| {
                if let Some(plane) = band.planes.into_iter().next() {
                    let _ = give_back.send(plane);
                }
            };
            let report = match format {
                Format::Exr => {
                    let header = exr_header(region, channels, &identity);
                    write_tiled_exr(&mut out, header, next_band, recycle)
                        .with_context(|| format!("cannot write '{}'", path.display()))?;
                    WriteReport::default()
                }
                Format::Png(depth) => {
                    write_png_rows(&mut out, region, channels, depth, next_band, recycle)
                        .with_context(|| format!("cannot write '{}'", path.display()))?
                }
            };
            out.flush()
                .with_context(|| format!("cannot write '{}'", path.display()))?;
            Ok(report)
        });
        let mut rendered = Ok(());
        let mut y = 0;
        while y < region.height {
            if let Err(stop) = crate::interrupt::check() {
                rendered = Err(stop.into());
                break;
            }
            let n = rows.min(region.height - y);
            let mut values = take_back.try_recv().unwrap_or_default();
            let band = window.tile(region.x, region.y + y, region.width, n);
            if let Err(e) = render_band(&band, &mut values) {
                rendered = Err(e);
                break;
            }
            let planes = if format == Format::Exr {
                deinterleave(values, channels, &order)
            } else {
                vec![values]
            };
            if send.send(Band { y, rows: n, planes }).is_err() {
                break; // the writer failed: its error is the one to report
            }
            bar.inc(n as u64);
            y += n;
        }
        drop(send);
        let written = writer
            .join()
            .map_err(|_| anyhow!("internal: the writing thread panicked"))?;
        rendered?;
        written
    })?;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    io::finish(tmp, &args.output)?;
    let pixels = region.width * region.height;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        let what = match region.tile {
            Some((k, (c, r))) => format!(
                "tile {k} of {c}x{r}: {}×{} at ({}, {}) of {}×{}",
                region.width, region.height, region.x, region.y, region.image.0, region.image.1
            ),
            None => format!("{}×{}", region.width, region.height),
        };
        println!(
            "wrote {} ({what}, streamed in bands of {} rows on the {device_name}, {:.1} \
             evaluations per pixel, {:.2} Mpix/s rendered and written)",
            args.output.display(),
            rows.min(region.height),
            eval.cost_per_pixel(),
            pixels as f64 / seconds.max(1e-9) / 1e6
        );
    }
    crate::progress::note_clipping(report);
    Ok(())
}

/// Tells glibc's allocator to keep freed memory for reuse instead of returning it to the kernel.
///
/// Each band allocates and frees its tiles' chunks (64 MB for a band of 8 Mpix: the exr crate
/// takes each chunk by value), and by default glibc trims the freed top of each thread's heap
/// at once, so the next band faults the same pages in again, zeroed by the kernel: a 32768²
/// stream spent 8.3 s of system time against 4.6 s with trimming held off (`/usr/bin/time`,
/// `spectex noise perlin --size 32768x32768 -o OUT.exr`), 20% of its CPU time. What is kept
/// is memory the bands already used, so memory stays bounded by the band size (peak RSS 172
/// against 154 MB in that run). Elsewhere (other C libraries) this does nothing.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        #[allow(unsafe_code)]
        // SAFETY: `mallopt` only sets an allocator parameter; it is called before the band
        // threads start, and glibc serialises it with allocation anyway.
        let _ = unsafe { libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30) };
    }
}

/// The header of a tiled OpenEXR holding `region` of its image: the image as display window,
/// the region as data window, f32 `Y` (grey) or `R`, `G`, `B`, uncompressed 64×64 tiles in
/// increasing line order, and the render's identity (and tile) as attributes.
fn exr_header(region: &Region, channels: usize, identity: &str) -> Header {
    let names: &[&str] = if channels == 1 {
        &["Y"]
    } else {
        &["B", "G", "R"]
    };
    let list = names
        .iter()
        .map(|n| ChannelDescription::new(*n, SampleType::F32, false))
        .collect::<Vec<_>>();
    let mut header = Header::new(
        Text::from("spectex"),
        (region.width, region.height),
        list.into(),
    )
    .with_encoding(
        EXR_COMPRESSION,
        BlockDescription::Tiles(TileDescription {
            tile_size: Vec2(EXR_TILE, EXR_TILE),
            level_mode: LevelMode::Singular,
            rounding_mode: RoundingMode::Down,
        }),
        LineOrder::Increasing,
    )
    .with_display_window(IntegerBounds::new(
        Vec2(0, 0),
        Vec2(region.image.0, region.image.1),
    ))
    .with_position(Vec2(region.x as i32, region.y as i32));
    header.own_attributes.layer_name = None;
    header.own_attributes.software_name = Some(Text::from("spectex"));
    let other = &mut header.own_attributes.other;
    other.insert(
        Text::from(RENDER_ATTRIBUTE),
        AttributeValue::Text(Text::from(identity)),
    );
    if let Some((k, (c, r))) = region.tile {
        other.insert(
            Text::from(TILE_ATTRIBUTE),
            AttributeValue::Text(Text::from(format!("{k} of {c}x{r}").as_str())),
        );
    }
    header
}

/// Writes a single-layer tiled OpenEXR with `header` to `out`, pulling its bands of rows in
/// order from `next_band` (each a whole number of tile rows, but the last) and handing each
/// back to `recycle` once written. Tiles are compressed in parallel, written in order.
///
/// # Errors
/// An I/O or encoding error, or bands that stop before the image is complete.
pub(crate) fn write_tiled_exr<W: Write + Seek>(
    out: W,
    header: Header,
    mut next_band: impl FnMut() -> Option<Band>,
    mut recycle: impl FnMut(Band),
) -> Result<()> {
    let width = header.layer_size.0;
    let headers = Headers::from_vec(vec![header]);
    exr::block::write(out, headers, true, |meta, chunks| {
        let headers = &meta.headers;
        let mut blocks = exr::block::enumerate_ordered_header_block_indices(headers).peekable();
        while let Some(band) = next_band() {
            let end = band.y + band.rows;
            let mut these: Vec<(usize, BlockIndex)> = Vec::new();
            while let Some((i, b)) = blocks.next_if(|(_, b)| b.pixel_position.1 < end) {
                these.push((i, b));
            }
            let compressed: Vec<exr::error::Result<(usize, exr::block::chunk::Chunk)>> = these
                .par_iter()
                .map(|&(i, index)| {
                    let Vec2(bx, by) = index.pixel_position;
                    let Vec2(bw, bh) = index.pixel_size;
                    let mut data = Vec::with_capacity(bw * bh * band.planes.len() * 4);
                    for row in by - band.y..by - band.y + bh {
                        for plane in &band.planes {
                            let start = row * width + bx;
                            for v in &plane[start..start + bw] {
                                data.extend_from_slice(&v.to_ne_bytes());
                            }
                        }
                    }
                    UncompressedBlock { index, data }
                        .compress_to_chunk(headers)
                        .map(|chunk| (i, chunk))
                })
                .collect();
            for result in compressed {
                let (i, chunk) = result?;
                chunks.write_chunk(i, chunk)?;
            }
            recycle(band);
        }
        if blocks.peek().is_some() {
            return Err(exr::error::Error::Io(std::io::Error::other(
                "the image stopped before its last row",
            )));
        }
        Ok(())
    })
    .map_err(|e| anyhow!("{e}"))
}

/// Writes a PNG of `region`'s size to `out` band by band (values interleaved per pixel in
/// the bands' one plane), clamped to `[0, 1]` and quantised exactly as a whole-image PNG.
fn write_png_rows<W: Write>(
    out: W,
    region: &Region,
    channels: usize,
    depth: BitDepth,
    mut next_band: impl FnMut() -> Option<Band>,
    mut recycle: impl FnMut(Band),
) -> Result<WriteReport> {
    let mut encoder = png::Encoder::new(out, region.width as u32, region.height as u32);
    encoder.set_color(if channels == 1 {
        png::ColorType::Grayscale
    } else {
        png::ColorType::Rgb
    });
    encoder.set_depth(match depth {
        BitDepth::Eight => png::BitDepth::Eight,
        BitDepth::Sixteen => png::BitDepth::Sixteen,
    });
    // What `image`'s PNG encoder uses by default, so whole and streamed files compress alike.
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::Filter::Adaptive);
    let mut writer = encoder.write_header()?;
    let mut stream = writer.stream_writer_with_size(1 << 20)?;
    let mut report = WriteReport::default();
    let mut bytes = Vec::new();
    let mut rows = 0;
    while let Some(band) = next_band() {
        bytes.clear();
        for plane in &band.planes {
            for &v in plane {
                report.clipped += usize::from(!(0.0..=1.0).contains(&v));
                report.total += 1;
                match depth {
                    BitDepth::Eight => bytes.push(io::level8(v)),
                    BitDepth::Sixteen => bytes.extend_from_slice(&io::level16(v).to_be_bytes()),
                }
            }
        }
        stream.write_all(&bytes)?;
        rows += band.rows;
        recycle(band);
    }
    if rows != region.height {
        bail!("the image stopped at row {rows} of {}", region.height);
    }
    stream.finish()?;
    writer.finish()?;
    Ok(report)
}
