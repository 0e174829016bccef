//! Which evaluator renders (`--device cpu|gpu|auto`) and the render on it: the CPU reference
//! or the GPU, timed from the render itself.

use anyhow::{Result, anyhow};
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;

pub use crate::args::Device;
use crate::io;
use crate::progress::progress_bar;

/// Where and how fast a window was rendered.
pub(crate) struct Rendered {
    /// "CPU" or "GPU <adapter>".
    pub device: String,
    /// Seconds of evaluation: device start-up and shader compilation are not evaluation, nor
    /// is storing the values as the output's samples (clamping, quantising, first touch of
    /// their memory) on the CPU (see [`render`]).
    pub seconds: f64,
    /// Seconds the GPU spent in the render's dispatches (timestamp queries), where measured.
    pub kernel_seconds: Option<f64>,
    /// Values a PNG output clamped ([`io::Band::store`]).
    pub clipped: usize,
}

impl Rendered {
    /// The speed the command reports: `N Mpix/s`, and on a GPU with timestamps also the
    /// kernel-only figure, `N Mpix/s end to end, M Mpix/s in the kernels`.
    pub(crate) fn speed(&self, pixels: usize) -> String {
        let mpix = |seconds: f64| pixels as f64 / seconds.max(1e-9) / 1e6;
        match self.kernel_seconds {
            None => format!("{:.2} Mpix/s", mpix(self.seconds)),
            Some(kernel) => format!(
                "{:.2} Mpix/s end to end, {:.2} Mpix/s in the kernels",
                mpix(self.seconds),
                mpix(kernel)
            ),
        }
    }
}

/// Rows the CPU evaluates (and stores) at a time: the evaluator's own band (`spectex_cpu`'s
/// `BAND_ROWS`), whose rows share their lattice rows.
const BAND_ROWS: usize = 16;

thread_local! {
    /// A render thread's values of one band, kept from band to band: its pages stay in the
    /// cache, where a whole image of f32 values took a page fault every 1024 values (as long as
    /// the evaluation itself on one thread, 2048² Perlin noise).
    static BAND_VALUES: std::cell::RefCell<Vec<f32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Renders `window` of `model` on the plane `z` on the device `device` asks for into `out`
/// (the output's samples, of `cpu.output_channels()` values per pixel); `cpu` is the CPU
/// evaluator of the same model, already built (it has validated the model and the plane).
///
/// The CPU evaluates band by band into a buffer of its thread's, which each band's samples are
/// then stored from, and reports the evaluation's share of the wall time: the time the render
/// took, scaled by the evaluation's share of the render threads' time (on one thread, the time
/// spent in the evaluator), as the classic bench times the evaluator alone.
pub(crate) fn render(
    model: &Model,
    z: f64,
    window: &Window,
    device: Device,
    cpu: &Evaluator,
    period: Option<spectex_model::Period>,
    out: &mut io::Samples,
) -> Result<Rendered> {
    match gpu_for(device)? {
        Some(context) => {
            let gpu = match period {
                None => spectex_gpu::GpuEvaluator::new_at_z(&context, model, z),
                Some(p) => spectex_gpu::GpuEvaluator::periodic_at_z(&context, model, z, p),
            }
            .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            let samples = out.row_len() * window.height;
            let values = window.width * window.height * gpu.output_channels();
            if values != samples {
                return Err(anyhow!(
                    "internal: the GPU renders {values} values for {samples} samples"
                ));
            }
            // Set-up, not evaluation: the device's buffers for the tiles, the pipeline that
            // packs a PNG's levels, and rayon's pool, which copies the read-back tiles into
            // `out`.
            gpu.reserve(window, sample_format(out))
                .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            let _ = rayon::current_num_threads();
            crate::interrupt::watch();
            let start = std::time::Instant::now();
            let stats =
                gpu_samples(&gpu, window, out).map_err(|e| anyhow!("{e}; try --device cpu"))?;
            let seconds = start.elapsed().as_secs_f64();
            crate::interrupt::check()?;
            Ok(Rendered {
                device: format!("GPU {}", context.adapter_name()),
                seconds,
                kernel_seconds: stats.kernel_seconds,
                clipped: stats.clipped.map_or(0, |n| n as usize),
            })
        }
        None => {
            cpu.check_window(window).map_err(|e| anyhow!("{e}"))?;
            // Start the thread pool first: its start-up is not evaluation.
            let _ = rayon::current_num_threads();
            let row_len = out.row_len();
            let bar = progress_bar(window.height as u64, "rendering");
            crate::interrupt::watch();
            let start = std::time::Instant::now();
            let bands: Bands = out.fill(BAND_ROWS, |first, band| {
                // After a signal the remaining bands are skipped: the render stops at the
                // bands in flight.
                if crate::interrupt::requested().is_some() {
                    return Bands::default();
                }
                BAND_VALUES.with(|values| {
                    let mut values = values.borrow_mut();
                    values.resize(band.len(), 0.0);
                    let evaluating = std::time::Instant::now();
                    cpu.eval_rows(window, first, &mut values);
                    let evaluated = evaluating.elapsed();
                    let clipped = band.store(&values);
                    bar.inc((values.len() / row_len.max(1)) as u64);
                    Bands {
                        clipped,
                        evaluating: evaluated,
                        all: evaluating.elapsed(),
                    }
                })
            });
            let wall = start.elapsed().as_secs_f64();
            bar.finish_and_clear();
            crate::interrupt::check()?;
            Ok(Rendered {
                device: "CPU".to_owned(),
                seconds: wall * bands.evaluation_share(),
                kernel_seconds: None,
                clipped: bands.clipped,
            })
        }
    }
}

/// Renders `window` on `gpu` straight into `out`, the output's samples: a PNG's levels packed
/// on the device (the CPU's quantisation, exactly, with its count of clamped values) and read
/// back at 1 or 2 bytes a value, an OpenEXR's f32 values. `out` holds the window's samples.
pub(crate) fn gpu_samples(
    gpu: &spectex_gpu::GpuEvaluator,
    window: &Window,
    out: &mut io::Samples,
) -> Result<spectex_gpu::RenderStats, spectex_gpu::GpuError> {
    use io::SampleData;
    let format = sample_format(out);
    let bytes: &mut [u8] = match &mut out.data {
        SampleData::U8(v) => v,
        SampleData::U16(v) => bytemuck::cast_slice_mut(v),
        SampleData::F32(v) => bytemuck::cast_slice_mut(v),
    };
    let stats = gpu.render_bytes_into(window, format, bytes)?;
    if let SampleData::U16(v) = &mut out.data {
        // The device's levels are little-endian (a no-op on little-endian hosts).
        v.iter_mut().for_each(|level| *level = u16::from_le(*level));
    }
    Ok(stats)
}

/// The GPU's output format for `out`'s samples: a PNG's 8- or 16-bit levels, an OpenEXR's f32.
fn sample_format(out: &io::Samples) -> spectex_gpu::OutputFormat {
    use spectex_gpu::OutputFormat;
    match &out.data {
        io::SampleData::U8(_) => OutputFormat::Unorm8,
        io::SampleData::U16(_) => OutputFormat::Unorm16,
        io::SampleData::F32(_) => OutputFormat::F32,
    }
}

/// What bands of a CPU render report, summed over bands.
#[derive(Debug, Default, Clone, Copy)]
struct Bands {
    /// Values a PNG clamped.
    clipped: usize,
    /// Time spent evaluating.
    evaluating: std::time::Duration,
    /// Time spent evaluating and storing the samples.
    all: std::time::Duration,
}

impl Bands {
    /// The evaluation's share of the bands' time (1 when there was none).
    fn evaluation_share(self) -> f64 {
        let all = self.all.as_secs_f64();
        if all > 0.0 {
            self.evaluating.as_secs_f64() / all
        } else {
            1.0
        }
    }
}

impl std::iter::Sum for Bands {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::default(), |a, b| Self {
            clipped: a.clipped + b.clipped,
            evaluating: a.evaluating + b.evaluating,
            all: a.all + b.all,
        })
    }
}

/// The GPU to render on, or `None` for the CPU, as `--device` asks.
pub(crate) fn gpu_for(device: Device) -> Result<Option<spectex_gpu::GpuContext>> {
    match device {
        Device::Cpu => Ok(None),
        Device::Gpu => spectex_gpu::GpuContext::new()
            .map(Some)
            .map_err(|e| anyhow!("--device gpu: {e}; or use --device cpu")),
        Device::Auto => match spectex_gpu::GpuContext::new() {
            Ok(context) => Ok(Some(context)),
            Err(e) => {
                eprintln!("note: --device auto: no GPU ({e}); rendering on the CPU");
                Ok(None)
            }
        },
    }
}
