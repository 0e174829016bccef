//! Which evaluator renders (`--device cpu|gpu|auto`) and the render on it: the CPU reference
//! or the GPU, timed from the render itself.

use anyhow::{Result, anyhow};
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;

use crate::render::progress_bar;

/// Which evaluator renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    /// spectex-cpu: same bytes for any thread count.
    Cpu,
    /// spectex-gpu: within the cross-checked tolerances of the CPU.
    Gpu,
    /// The GPU when an adapter exists, else the CPU.
    Auto,
}

/// A window's values and where and how fast they were computed.
pub(crate) struct Rendered {
    /// The values, interleaved per pixel (`Evaluator::output_channels` of them), row-major.
    pub pixels: Vec<f32>,
    /// "CPU" or "GPU <adapter>".
    pub device: String,
    /// Seconds of evaluation: device start-up and shader compilation are not evaluation.
    pub seconds: f64,
    /// Seconds the GPU spent in the render's dispatches (timestamp queries), where measured.
    pub kernel_seconds: Option<f64>,
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

/// Renders `window` of `model` on the plane `z` on the device `device` asks for; `cpu` is the
/// CPU evaluator of the same model, already built (it has validated the model and the plane).
pub(crate) fn render(
    model: &Model,
    z: f64,
    window: &Window,
    device: Device,
    cpu: &Evaluator,
    period: Option<spectex_model::Period>,
) -> Result<Rendered> {
    match gpu_for(device)? {
        Some(context) => {
            let gpu = match period {
                None => spectex_gpu::GpuEvaluator::new_at_z(&context, model, z),
                Some(p) => spectex_gpu::GpuEvaluator::periodic_at_z(&context, model, z, p),
            }
            .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            let start = std::time::Instant::now();
            let mut pixels = vec![0.0f32; window.width * window.height * gpu.output_channels()];
            let stats = gpu
                .render_into(window, &mut pixels)
                .map_err(|e| anyhow!("{e}; try --device cpu"))?;
            Ok(Rendered {
                pixels,
                device: format!("GPU {}", context.adapter_name()),
                seconds: start.elapsed().as_secs_f64(),
                kernel_seconds: stats.kernel_seconds,
            })
        }
        None => {
            let start = std::time::Instant::now();
            let mut pixels = vec![0.0f32; window.width * window.height * cpu.output_channels()];
            let bar = progress_bar(window.height as u64, "rendering");
            cpu.render_into(window, &mut pixels, &|_| bar.inc(1))
                .map_err(|e| anyhow!("{e}"))?;
            bar.finish_and_clear();
            Ok(Rendered {
                pixels,
                device: "CPU".to_owned(),
                seconds: start.elapsed().as_secs_f64(),
                kernel_seconds: None,
            })
        }
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
