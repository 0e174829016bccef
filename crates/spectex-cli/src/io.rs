//! Image files in and out: decoding PNG/JPEG into `(channel, row, column)` arrays of `f64` in
//! `[0, 1]`, and writing PNG (8/16-bit) or OpenEXR (32-bit float) through a temporary file that
//! is renamed into place, so no half-written output is ever left behind; and the grey levels
//! (Rec. 709 luminance) of a loaded image.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use image::{DynamicImage, ImageBuffer, ImageReader, Limits, Luma, Rgb};
use ndarray::{Array2, Array3};

/// Largest input side accepted by the decoder (also the synthesis limit).
pub const MAX_INPUT_SIDE: u32 = 16_384;

/// A decoded image and what the file held.
#[derive(Debug)]
pub struct Loaded {
    /// Colour channels only (alpha dropped), `(channel, row, column)`, values in `[0, 1]`.
    pub pixels: Array3<f64>,
    /// The file had an alpha channel, which was dropped.
    pub dropped_alpha: bool,
}

/// Decodes an image from memory (the built-in exemplar) or a file's bytes.
pub fn decode(bytes: &[u8], what: &str) -> Result<Loaded> {
    let mut reader = ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .with_context(|| format!("cannot read {what}"))?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_INPUT_SIDE);
    limits.max_image_height = Some(MAX_INPUT_SIDE);
    limits.max_alloc = Some(4 << 30);
    reader.limits(limits);
    if reader.format().is_none() {
        bail!(
            "{what} is not a PNG or JPEG image (unrecognised content); give a PNG \
             (8/16-bit grey, grey+alpha, RGB or RGBA) or a JPEG"
        );
    }
    let img = reader.decode().map_err(|e| {
        anyhow!(
            "cannot decode {what}: {e}; the file may be truncated or corrupt (PNG and JPEG are \
             read, up to {MAX_INPUT_SIDE} pixels per side)"
        )
    })?;
    Ok(to_array(&img))
}

/// Reads and decodes an image file.
pub fn load(path: &Path) -> Result<Loaded> {
    let bytes = std::fs::read(path).map_err(|e| {
        anyhow!(
            "cannot open input '{}': {e}; check the path",
            path.display()
        )
    })?;
    decode(&bytes, &format!("input '{}'", path.display()))
}

/// Rec. 709 luminance of a colour image, or the single channel of a grey one
/// ([`spectex_spectrum::luminance`]).
pub fn luminance(img: &Array3<f64>) -> Array2<f64> {
    spectex_spectrum::luminance(img.view())
}

/// The image as grey levels for a command that reads grey (a height map, a control image):
/// its [`luminance`], with a note when `name` is in colour.
pub fn grey(img: &Array3<f64>, name: &str) -> Array2<f64> {
    if img.dim().0 != 1 {
        eprintln!("note: {name} is in colour; its Rec. 709 luminance is used");
    }
    luminance(img)
}

fn to_array(img: &DynamicImage) -> Loaded {
    let (w, h) = (img.width() as usize, img.height() as usize);
    let color = img.color();
    let dropped_alpha = color.has_alpha();
    if color.has_color() {
        let rgb = img.to_rgb32f();
        let raw = rgb.as_raw();
        Loaded {
            pixels: Array3::from_shape_fn((3, h, w), |(c, y, x)| {
                f64::from(raw[(y * w + x) * 3 + c])
            }),
            dropped_alpha,
        }
    } else {
        let grey = img.to_luma32f();
        let raw = grey.as_raw();
        Loaded {
            pixels: Array3::from_shape_fn((1, h, w), |(_, y, x)| f64::from(raw[y * w + x])),
            dropped_alpha,
        }
    }
}

/// Bit depth of a PNG output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BitDepth {
    /// 8 bits per channel.
    #[value(name = "8")]
    Eight,
    /// 16 bits per channel.
    #[value(name = "16")]
    Sixteen,
}

impl BitDepth {
    /// The bit depth of a PNG output unless `--bit-depth` is given: 8 bits, what every viewer
    /// reads.
    pub const DEFAULT: Self = Self::Eight;
}

/// The output format, chosen by the file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// PNG, values clamped to `[0, 1]` and quantised.
    Png(BitDepth),
    /// OpenEXR, 32-bit float, values kept as they are.
    Exr,
}

impl Format {
    /// The format for `path`'s extension (`.png` or `.exr`, any case).
    pub fn for_path(path: &Path, depth: BitDepth) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Format::Png(depth)),
            Some("exr") => Ok(Format::Exr),
            Some(other) => bail!(
                "output '{}' has the extension '.{other}'; use .png (8 or 16 bit) or .exr (32-bit float)",
                path.display()
            ),
            None => bail!(
                "output '{}' has no extension; end it with .png (8 or 16 bit) or .exr (32-bit float)",
                path.display()
            ),
        }
    }
}

/// Checks, before any work, that `path` can be written: a known extension and an existing,
/// writable parent directory.
pub fn check_output(path: &Path, depth: BitDepth) -> Result<Format> {
    let format = Format::for_path(path, depth)?;
    let dir = parent_dir(path);
    let meta = std::fs::metadata(&dir).map_err(|e| {
        anyhow!(
            "cannot write '{}': its directory '{}' is not accessible ({e}); create it first",
            path.display(),
            dir.display()
        )
    })?;
    if !meta.is_dir() {
        bail!(
            "cannot write '{}': '{}' is not a directory",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!(
            "cannot write '{}': it is a directory; give a file name",
            path.display()
        );
    }
    // Prove the directory is writable now rather than after minutes of work.
    tempfile::NamedTempFile::new_in(&dir).map_err(|e| {
        anyhow!(
            "cannot write into '{}': {e}; choose a writable location",
            dir.display()
        )
    })?;
    Ok(format)
}

pub(crate) fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Statistics of a write, for notes to the user.
#[derive(Debug, Default, Clone, Copy)]
pub struct WriteReport {
    /// Values outside `[0, 1]` clamped by a PNG output.
    pub clipped: usize,
    /// Total values written.
    pub total: usize,
}

/// A hidden temporary file (`.spectex-XXXX.tmp`) in the directory of `path`, where its output
/// is written before [`finish`] renames it into place (removed if dropped unfinished).
///
/// # Errors
/// The directory is not writable.
pub(crate) fn temporary_beside(path: &Path) -> Result<tempfile::NamedTempFile> {
    let dir = parent_dir(path);
    tempfile::Builder::new()
        .prefix(".spectex-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(|e| {
            anyhow!(
                "cannot write into '{}': {e}; choose a writable location",
                dir.display()
            )
        })
}

/// Writes `pixels` (`(channel, row, column)`, 1 or 3 channels) to `path` atomically: the data
/// go to a temporary file in the same directory, which is renamed over `path` only once
/// complete. A failure at any point leaves no file behind.
pub fn save(path: &Path, pixels: &Array3<f64>, format: Format) -> Result<WriteReport> {
    let (channels, h, w) = pixels.dim();
    if channels != 1 && channels != 3 {
        bail!("internal: cannot write an image of {channels} channels");
    }
    let tmp = temporary_beside(path)?;
    let mut report = WriteReport {
        clipped: 0,
        total: pixels.len(),
    };
    {
        let mut out = BufWriter::new(tmp.as_file());
        match format {
            Format::Png(depth) => {
                report.clipped = pixels.iter().filter(|v| !(0.0..=1.0).contains(*v)).count();
                let img = to_dynamic(pixels, depth);
                img.write_with_encoder(image::codecs::png::PngEncoder::new(&mut out))
                    .with_context(|| format!("cannot encode '{}'", path.display()))?;
            }
            Format::Exr => {
                // Interleaved f32 values, then the one EXR writer (grey as one Y channel).
                let mut values = Vec::with_capacity(h * w * channels);
                for y in 0..h {
                    for x in 0..w {
                        for c in 0..channels {
                            values.push(pixels[[c, y, x]] as f32);
                        }
                    }
                }
                write_exr(&mut out, &values, w, h, channels)
                    .with_context(|| format!("cannot encode '{}'", path.display()))?;
            }
        }
        out.flush()
            .with_context(|| format!("cannot write '{}'", path.display()))?;
    }
    finish(tmp, path)?;
    Ok(report)
}

/// A rendered image in the samples its file stores: 8- or 16-bit PNG levels (clamped to
/// `[0, 1]` and quantised by [`quantise`]) or the f32 values of an OpenEXR, interleaved per
/// pixel, row-major. Filled band by band as a render goes ([`Samples::fill`]), so a render
/// never holds its f32 values and its file's samples at once (but for an OpenEXR, whose samples
/// are the values).
#[derive(Debug)]
pub(crate) struct Samples {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Values per pixel: 1 (grey) or 3 (RGB).
    pub channels: usize,
    /// The samples.
    pub data: SampleData,
}

/// The samples of a [`Samples`], as the format stores them.
#[derive(Debug)]
pub(crate) enum SampleData {
    /// 8-bit PNG levels.
    U8(Vec<u8>),
    /// 16-bit PNG levels.
    U16(Vec<u16>),
    /// OpenEXR values.
    F32(Vec<f32>),
}

impl Samples {
    /// Zeroed samples of a `width × height` image of `channels` values per pixel in `format`.
    ///
    /// # Errors
    /// A channel count other than 1 or 3.
    pub(crate) fn new(
        format: Format,
        width: usize,
        height: usize,
        channels: usize,
    ) -> Result<Self> {
        if channels != 1 && channels != 3 {
            bail!("internal: cannot write an image of {channels} channels");
        }
        let n = width * height * channels;
        let data = match format {
            Format::Png(BitDepth::Eight) => SampleData::U8(vec![0; n]),
            Format::Png(BitDepth::Sixteen) => SampleData::U16(vec![0; n]),
            Format::Exr => SampleData::F32(vec![0.0; n]),
        };
        Ok(Self {
            width,
            height,
            channels,
            data,
        })
    }

    /// Values per row.
    pub(crate) fn row_len(&self) -> usize {
        self.width * self.channels
    }

    /// Calls `band(first_row, samples)` for each band of `rows` whole rows (the last one
    /// shorter), in parallel, and sums what the calls return.
    pub(crate) fn fill<R: Send + std::iter::Sum>(
        &mut self,
        rows: usize,
        band: impl Fn(usize, Band<'_>) -> R + Sync + Send,
    ) -> R {
        use rayon::prelude::*;
        let chunk = (self.row_len() * rows).max(1);
        match &mut self.data {
            SampleData::U8(v) => v
                .par_chunks_mut(chunk)
                .enumerate()
                .map(|(i, s)| band(i * rows, Band::U8(s)))
                .sum(),
            SampleData::U16(v) => v
                .par_chunks_mut(chunk)
                .enumerate()
                .map(|(i, s)| band(i * rows, Band::U16(s)))
                .sum(),
            SampleData::F32(v) => v
                .par_chunks_mut(chunk)
                .enumerate()
                .map(|(i, s)| band(i * rows, Band::F32(s)))
                .sum(),
        }
    }
}

/// The samples of one band of rows of a [`Samples`].
#[derive(Debug)]
pub(crate) enum Band<'a> {
    /// 8-bit PNG levels.
    U8(&'a mut [u8]),
    /// 16-bit PNG levels.
    U16(&'a mut [u16]),
    /// OpenEXR values.
    F32(&'a mut [f32]),
}

impl Band<'_> {
    /// Samples in the band.
    pub(crate) fn len(&self) -> usize {
        match self {
            Band::U8(s) => s.len(),
            Band::U16(s) => s.len(),
            Band::F32(s) => s.len(),
        }
    }

    /// Stores `values` (as many as the band has samples) as the format does: the values
    /// themselves for an OpenEXR, clamped to `[0, 1]` and quantised ([`quantise`], the same
    /// levels as [`save`] of the values as f64) for a PNG. Returns how many values a PNG
    /// clamped (outside `[0, 1]`, or NaN).
    pub(crate) fn store(self, values: &[f32]) -> usize {
        let mut clipped = 0;
        match self {
            Band::U8(s) => {
                for (s, &v) in s.iter_mut().zip(values) {
                    clipped += usize::from(!(0.0..=1.0).contains(&v));
                    *s = level8(v);
                }
            }
            Band::U16(s) => {
                for (s, &v) in s.iter_mut().zip(values) {
                    clipped += usize::from(!(0.0..=1.0).contains(&v));
                    *s = level16(v);
                }
            }
            Band::F32(s) => s.copy_from_slice(values),
        }
        clipped
    }
}

/// The 8-bit PNG level of `v`: `quantise(f64::from(v), 255.0) as u8`, without the call to
/// `round` (none of x86-64's baseline instructions rounds half away from zero; the call took
/// as long as the evaluation of 2048² Perlin noise). `v · 255` is exact in f64 (a 24-bit
/// significand times an 8-bit one) and not negative, so adding ½ is exact wherever the sum
/// reaches 1 (below, both levels are 0), and truncating the sum (`as`) rounds half up, as
/// `round` does for values ≥ 0; NaN gives 0 both ways.
#[doc(hidden)]
#[inline]
#[must_use]
pub fn level8(v: f32) -> u8 {
    (f64::from(v).clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// The 16-bit PNG level of `v`: `quantise(f64::from(v), 65535.0) as u16`, exactly as
/// [`level8`] (`v · 65535` has at most 40 significant bits).
#[doc(hidden)]
#[inline]
#[must_use]
pub fn level16(v: f32) -> u16 {
    (f64::from(v).clamp(0.0, 1.0) * 65535.0 + 0.5) as u16
}

/// Writes `samples` to `path` atomically as [`save`] does, in `format` (the one they were made
/// for); `clipped` is what [`Band::store`] counted. The same bytes as [`save`] of the values.
pub(crate) fn save_samples(
    path: &Path,
    samples: Samples,
    format: Format,
    clipped: usize,
) -> Result<WriteReport> {
    let Samples {
        width: w,
        height: h,
        channels,
        data,
    } = samples;
    let tmp = temporary_beside(path)?;
    let report = WriteReport {
        clipped,
        total: w * h * channels,
    };
    {
        let mut out = BufWriter::new(tmp.as_file());
        encode_samples(
            &mut out,
            Samples {
                width: w,
                height: h,
                channels,
                data,
            },
            format,
        )
        .with_context(|| format!("cannot encode '{}'", path.display()))?;
        out.flush()
            .with_context(|| format!("cannot write '{}'", path.display()))?;
    }
    finish(tmp, path)?;
    Ok(report)
}

/// Encodes `samples` into `out` as the file `format` names: an 8- or 16-bit PNG (grey or RGB) of
/// their levels, or the OpenEXR of their values ([`write_exr`]). The one encoder of rendered
/// samples: files ([`save_samples`]) and `spectex view`'s tiles.
///
/// # Errors
/// Samples of the wrong length or made for another format, or the encoder's error.
pub(crate) fn encode_samples<W: Write + std::io::Seek>(
    out: W,
    samples: Samples,
    format: Format,
) -> Result<()> {
    let Samples {
        width: w,
        height: h,
        channels,
        data,
    } = samples;
    let (w32, h32) = (w as u32, h as u32);
    let wrong = || anyhow!("internal: {w}×{h}×{channels} samples of the wrong length");
    let img = match (data, channels) {
        (SampleData::U8(v), 1) => {
            DynamicImage::ImageLuma8(ImageBuffer::from_raw(w32, h32, v).ok_or_else(wrong)?)
        }
        (SampleData::U8(v), _) => {
            DynamicImage::ImageRgb8(ImageBuffer::from_raw(w32, h32, v).ok_or_else(wrong)?)
        }
        (SampleData::U16(v), 1) => {
            DynamicImage::ImageLuma16(ImageBuffer::from_raw(w32, h32, v).ok_or_else(wrong)?)
        }
        (SampleData::U16(v), _) => {
            DynamicImage::ImageRgb16(ImageBuffer::from_raw(w32, h32, v).ok_or_else(wrong)?)
        }
        (SampleData::F32(v), _) => {
            if v.len() != w * h * channels {
                return Err(wrong());
            }
            return write_exr(out, &v, w, h, channels);
        }
    };
    if !matches!(format, Format::Png(_)) {
        bail!("internal: PNG samples for a {format:?} output");
    }
    img.write_with_encoder(image::codecs::png::PngEncoder::new(out))?;
    Ok(())
}

/// Writes `values` (`channels` = 1 or 3 per pixel, row-major) as a 32-bit float OpenEXR: one
/// `Y` channel for a grey image, `R`, `G`, `B` for a colour one, as the streamed and tiled
/// writers (`stream.rs`) do, so that a command writes the same channels whatever its size.
/// `exr`'s default encoding, which `image`'s `OpenExrEncoder` also uses.
pub(crate) fn write_exr<W: Write + std::io::Seek>(
    out: W,
    values: &[f32],
    width: usize,
    height: usize,
    channels: usize,
) -> Result<()> {
    use exr::prelude::{Image, SpecificChannels, Vec2, WritableImage};
    let index = |pixel: Vec2<usize>| pixel.flat_index_for_size(Vec2(width, height)) * channels;
    if channels == 1 {
        Image::from_channels(
            (width, height),
            SpecificChannels::build()
                .with_channel("Y")
                .with_pixel_fn(|pixel: Vec2<usize>| (values[index(pixel)],)),
        )
        .write()
        .to_buffered(out)
    } else {
        Image::from_channels(
            (width, height),
            SpecificChannels::rgb(|pixel: Vec2<usize>| {
                let i = index(pixel);
                (values[i], values[i + 1], values[i + 2])
            }),
        )
        .write()
        .to_buffered(out)
    }
    .map_err(|e| anyhow!("{e}"))
}

/// Writes a text file atomically (temporary file in the same directory, then rename).
pub fn write_text_atomically(path: &Path, text: &str) -> Result<()> {
    write_bytes_atomically(path, text.as_bytes())
}

/// Writes a binary file atomically (temporary file in the same directory, then rename).
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut tmp = temporary_beside(path)?;
    tmp.write_all(bytes)
        .with_context(|| format!("cannot write '{}'", path.display()))?;
    finish(tmp, path)
}

/// Gives a finished temporary file ordinary permissions, flushes it to disk and renames it over
/// `path` (atomic on one file system).
pub fn finish(tmp: tempfile::NamedTempFile, path: &Path) -> Result<()> {
    // Temporary files are created private (0600); a finished output is an ordinary file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644))
            .with_context(|| format!("cannot write '{}'", path.display()))?;
    }
    tmp.as_file()
        .sync_all()
        .with_context(|| format!("cannot write '{}'", path.display()))?;
    // A signal that came while the file was written: it is dropped (removed), not published.
    crate::interrupt::check()?;
    tmp.persist(path).map_err(|e| {
        anyhow!(
            "cannot move the finished file to '{}': {}",
            path.display(),
            e.error
        )
    })?;
    Ok(())
}

/// `v` clamped to `[0, 1]`, times `max`, rounded half away from zero: a PNG level.
#[doc(hidden)]
#[must_use]
pub fn quantise(v: f64, max: f64) -> f64 {
    (v.clamp(0.0, 1.0) * max).round()
}

fn to_dynamic(pixels: &Array3<f64>, depth: BitDepth) -> DynamicImage {
    let (channels, h, w) = pixels.dim();
    let (w32, h32) = (w as u32, h as u32);
    let px = |c: usize, x: u32, y: u32| pixels[[c, y as usize, x as usize]];
    match (channels, depth) {
        (1, BitDepth::Eight) => DynamicImage::ImageLuma8(ImageBuffer::from_fn(w32, h32, |x, y| {
            Luma([quantise(px(0, x, y), 255.0) as u8])
        })),
        (1, BitDepth::Sixteen) => {
            DynamicImage::ImageLuma16(ImageBuffer::from_fn(w32, h32, |x, y| {
                Luma([quantise(px(0, x, y), 65535.0) as u16])
            }))
        }
        (_, BitDepth::Eight) => DynamicImage::ImageRgb8(ImageBuffer::from_fn(w32, h32, |x, y| {
            Rgb([0, 1, 2].map(|c| quantise(px(c, x, y), 255.0) as u8))
        })),
        (_, BitDepth::Sixteen) => {
            DynamicImage::ImageRgb16(ImageBuffer::from_fn(w32, h32, |x, y| {
                Rgb([0, 1, 2].map(|c| quantise(px(c, x, y), 65535.0) as u16))
            }))
        }
    }
}

/// Side of the square tiles of a streamed OpenEXR: OpenEXR's customary 64, as the whole-image
/// writer (`image`) uses.
pub const EXR_TILE: usize = 64;

/// The sample named on the command line, or the built-in exemplar.
pub(crate) fn load_input(input: Option<&Path>) -> Result<(Loaded, String)> {
    let loaded = load_input_as_is(input)?;
    if loaded.0.dropped_alpha {
        eprintln!("note: the alpha channel of {} is ignored", loaded.1);
    }
    Ok(loaded)
}

/// [`load_input`] without its note on a dropped alpha channel: for a caller that refuses one.
pub(crate) fn load_input_as_is(input: Option<&Path>) -> Result<(Loaded, String)> {
    let loaded = match input {
        Some(p) => (load(p)?, format!("'{}'", p.display())),
        None => (
            decode(
                crate::exemplar::DEFAULT_EXEMPLAR_PNG,
                crate::exemplar::DEFAULT_EXEMPLAR_NAME,
            )?,
            crate::exemplar::DEFAULT_EXEMPLAR_NAME.to_string(),
        ),
    };
    Ok(loaded)
}
