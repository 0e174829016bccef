//! Windows rendered into the bytes `spectex render` writes: PNG tiles and views (the same
//! samples, encoded by the same encoder), OpenEXR, streamed PNG downloads of large sizes, and
//! the display of a power spectrum.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, SyncSender};

use anyhow::{Result, anyhow};
use image::{DynamicImage, ImageBuffer};
use ndarray::Array2;
use spectex_cpu::{Evaluator, Window};

use crate::io::{self, BitDepth, Format, Samples};

/// Largest side of a displayed spectrum.
pub(crate) const MAX_SPECTRUM: usize = 1024;

/// What tiles are: 8-bit PNGs, as `spectex render -o out.png` writes.
pub(crate) const TILE_FORMAT: Format = Format::Png(BitDepth::Eight);

/// Rows evaluated at a time: the evaluator's band (as `device::render`).
const BAND_ROWS: usize = 16;

/// What renders a model's windows: its CPU evaluator, and the GPU's when the view asked for it.
pub(crate) struct Renderer {
    /// The CPU evaluator (also the validation of the model, plane and period).
    pub cpu: Evaluator,
    /// The GPU evaluator, one render at a time.
    pub gpu: Option<std::sync::Mutex<spectex_gpu::GpuEvaluator>>,
}

impl Renderer {
    /// Values per pixel.
    pub(crate) fn channels(&self) -> usize {
        self.cpu.output_channels()
    }

    /// The f32 values of `window` (`channels()` per pixel, row-major), on the GPU when there
    /// is one, else the CPU (in parallel bands).
    fn values_into(&self, window: &Window, first_row: usize, out: &mut [f32]) -> Result<()> {
        if let Some(gpu) = &self.gpu {
            let rows = out.len() / (window.width * self.channels()).max(1);
            let band = window.tile(0, first_row, window.width, rows);
            let gpu = gpu
                .lock()
                .map_err(|_| anyhow!("internal: a GPU render panicked"))?;
            gpu.render_into(&band, out)
                .map_err(|e| anyhow!("{e}; start the view with --device cpu"))?;
            return Ok(());
        }
        self.cpu.eval_rows(window, first_row, out);
        Ok(())
    }

    /// `window` as the samples of `format` (PNG levels or EXR values), as `spectex render` stores
    /// them.
    pub(crate) fn samples(&self, window: &Window, format: Format) -> Result<Samples> {
        self.samples_unless(window, format, &|| false)?
            .ok_or_else(|| anyhow!("internal: a render stopped unasked"))
    }

    /// [`samples`](Self::samples), or `None` once `stop()` says the render is no longer wanted
    /// (asked before each band, so a stale tile costs at most the bands already started).
    pub(crate) fn samples_unless(
        &self,
        window: &Window,
        format: Format,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<Samples>> {
        self.cpu.check_window(window).map_err(|e| anyhow!("{e}"))?;
        let mut samples = Samples::new(format, window.width, window.height, self.channels())?;
        if let Some(gpu) = &self.gpu {
            if stop() {
                return Ok(None);
            }
            let gpu = gpu
                .lock()
                .map_err(|_| anyhow!("internal: a GPU render panicked"))?;
            crate::device::gpu_samples(&gpu, window, &mut samples)
                .map_err(|e| anyhow!("{e}; start the view with --device cpu"))?;
            return Ok(Some(samples));
        }
        let stopped = AtomicBool::new(false);
        samples.fill(BAND_ROWS, |first, band| {
            if stopped.load(Ordering::Relaxed) || stop() {
                stopped.store(true, Ordering::Relaxed);
                return 0;
            }
            let mut values = vec![0.0f32; band.len()];
            self.cpu.eval_rows(window, first, &mut values);
            band.store(&values)
        });
        Ok((!stopped.into_inner()).then_some(samples))
    }

    /// `window` as the PNG (8 bits per channel) `spectex render -o out.png` writes of it.
    pub(crate) fn png(&self, window: &Window) -> Result<Vec<u8>> {
        encode(self.samples(window, TILE_FORMAT)?, TILE_FORMAT)
    }

    /// `window` as the OpenEXR (32-bit float RGB) `spectex render -o out.exr` writes of it.
    pub(crate) fn exr(&self, window: &Window) -> Result<Vec<u8>> {
        encode(self.samples(window, Format::Exr)?, Format::Exr)
    }

    /// `window` as an 8-bit PNG written band by band into `out` (memory: one band), for large
    /// downloads. Stops at the first failed write (the browser went away).
    pub(crate) fn stream_png(&self, window: &Window, out: impl Write + 'static) -> Result<()> {
        self.cpu.check_window(window).map_err(|e| anyhow!("{e}"))?;
        let channels = self.channels();
        let mut encoder = png::Encoder::new(out, window.width as u32, window.height as u32);
        encoder.set_color(if channels == 1 {
            png::ColorType::Grayscale
        } else {
            png::ColorType::Rgb
        });
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?.into_stream_writer()?;
        let row_len = window.width * channels;
        let mut values = vec![0.0f32; row_len * BAND_ROWS];
        let mut levels = vec![0u8; row_len * BAND_ROWS];
        let mut first = 0;
        while first < window.height {
            let rows = BAND_ROWS.min(window.height - first);
            let n = rows * row_len;
            self.values_into(window, first, &mut values[..n])?;
            for (l, &v) in levels[..n].iter_mut().zip(&values[..n]) {
                *l = io::level8(v);
            }
            writer.write_all(&levels[..n])?;
            first += rows;
        }
        writer.finish()?;
        Ok(())
    }
}

/// The file bytes of `samples` in `format`, by the encoder `spectex render` writes files with.
pub(crate) fn encode(samples: Samples, format: Format) -> Result<Vec<u8>> {
    let mut out = std::io::Cursor::new(Vec::new());
    io::encode_samples(&mut out, samples, format)?;
    Ok(out.into_inner())
}

/// A grey image of values in `[0, 1]` as an 8-bit PNG.
pub(crate) fn grey_png(values: &Array2<f64>) -> Result<Vec<u8>> {
    let (h, w) = values.dim();
    let levels: Vec<u8> = values.iter().map(|&v| io::level8(v as f32)).collect();
    let img = DynamicImage::ImageLuma8(
        ImageBuffer::from_raw(w as u32, h as u32, levels)
            .ok_or_else(|| anyhow!("internal: spectrum of the wrong length"))?,
    );
    let mut out = Vec::new();
    img.write_with_encoder(image::codecs::png::PngEncoder::new(&mut out))?;
    Ok(out)
}

/// The centred log-magnitude spectrum of the luminance of `pixels` (`(channel, row, column)`),
/// scaled to `[0, 1]` for display, as an 8-bit PNG (`spectex analyze`'s `log_spectrum.png`).
pub(crate) fn spectrum_png(pixels: &ndarray::Array3<f64>) -> Result<Vec<u8>> {
    // At most 1024 × 1024 (the top-left corner of a larger image): the display's resolution,
    // and a bound on the FFT's memory.
    let (_, h, w) = pixels.dim();
    let crop = pixels.slice(ndarray::s![
        ..,
        ..h.min(MAX_SPECTRUM),
        ..w.min(MAX_SPECTRUM)
    ]);
    let luma = io::luminance(&crop.to_owned());
    let mut fft = spectex_spectrum::Fft2::new();
    let periodic = spectex_spectrum::periodic_smooth(luma.view(), &mut fft).periodic;
    let log = spectex_spectrum::log_magnitude_spectrum(periodic.view(), &mut fft);
    let (lo, hi) = log
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let span = if hi > lo { hi - lo } else { 1.0 };
    grey_png(&log.mapv(|v| (v - lo) / span))
}

/// A [`Write`] whose bytes go, in chunks, to a [`ChannelReader`] on another thread: a streamed
/// response body. A write fails once the reader is gone (the response was dropped).
pub(crate) struct ChannelWriter {
    /// Where full chunks go.
    sender: SyncSender<Vec<u8>>,
    /// The chunk being filled.
    chunk: Vec<u8>,
}

/// Bytes per chunk of a streamed body.
const CHUNK: usize = 1 << 16;

impl Write for ChannelWriter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.chunk.extend_from_slice(buf);
        if self.chunk.len() >= CHUNK {
            self.flush()?;
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if self.chunk.is_empty() {
            return Ok(());
        }
        let chunk = std::mem::take(&mut self.chunk);
        self.sender
            .send(chunk)
            .map_err(|_| std::io::Error::new(std::io::ErrorKind::BrokenPipe, "the browser left"))
    }
}

impl Drop for ChannelWriter {
    fn drop(&mut self) {
        // The last, partial chunk (a reader already gone is no error here).
        let _ = self.flush();
    }
}

/// The reading end of a [`ChannelWriter`]: ends when the writer is dropped.
pub(crate) struct ChannelReader {
    /// Chunks from the writer.
    receiver: Receiver<Vec<u8>>,
    /// The chunk being read, and how far.
    chunk: Vec<u8>,
    /// Bytes of `chunk` already read.
    at: usize,
}

impl std::io::Read for ChannelReader {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        while self.at >= self.chunk.len() {
            match self.receiver.recv() {
                Ok(chunk) => {
                    self.chunk = chunk;
                    self.at = 0;
                }
                Err(_) => return Ok(0),
            }
        }
        let n = buf.len().min(self.chunk.len() - self.at);
        buf[..n].copy_from_slice(&self.chunk[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// A writer and reader joined by a channel of at most two chunks in flight.
pub(crate) fn channel() -> (ChannelWriter, ChannelReader) {
    let (sender, receiver) = std::sync::mpsc::sync_channel(2);
    (
        ChannelWriter {
            sender,
            chunk: Vec::with_capacity(CHUNK),
        },
        ChannelReader {
            receiver,
            chunk: Vec::new(),
            at: 0,
        },
    )
}
