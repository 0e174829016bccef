//! Every model of `testdata/models` on the GPU and on the CPU (all threads) in one run: the GPU
//! kernel-only (timestamp queries, where the adapter has them) and end to end (tables, dispatches,
//! read-back into the caller's slice), the CPU end to end; then the LRP paper's Table 1 texture
//! frame (128², the synthetic grey and colour textures) on the GPU, in milliseconds; the models'
//! rows end with `bench-lrp-j50`, the GPU bench's LRP model (J = 50, 4 strata). Prints one
//! tab-separated line per figure for `cargo xtask bench gpu`, which writes the Markdown table
//! and the chart:
//!
//! `model, name, evaluations/px, GPU kernel Mpix/s (or -), GPU end-to-end Mpix/s, CPU Mpix/s,
//! tiles, bytes read back per pixel, GPU end-to-end Mpix/s as 8-bit unorm, host ms per tile`
//! (the unorm figure: the levels of a PNG packed on the device, a quarter of the bytes read
//! back; the host figure: the tiles' preparation on the worker threads, `RenderStats::host_seconds`)
//! and `frame, name, side, GPU kernel ms (or -), GPU end-to-end ms`, fields separated by tabs.
//!
//! `cargo bench -p spectex-crosscheck --bench models -- --bench [--size N] [--repeat R]
//! [--only SUBSTRING] [--models DIR]`: N² windows (default 256), the best of R timed GPU renders
//! after one warm-up (default 3; the CPU's best of at most 2), the models of DIR (default the
//! repository's `testdata/models`). On lavapipe set `WGPU_ADAPTER_NAME=llvmpipe` and keep N small. Run without
//! `--bench` (as `cargo test --all-targets` does) it only checks that it starts.

#![allow(clippy::print_stdout, reason = "the lines are the bench's report")]
#![allow(clippy::print_stderr, reason = "progress and skips go to stderr")]

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use spectex_cpu::{Evaluator, Window};
use spectex_gpu::{GpuContext, GpuEvaluator};
use spectex_model::Model;

struct Options {
    size: usize,
    repeat: usize,
    only: Option<String>,
    models: PathBuf,
}

fn options() -> Result<Option<Options>> {
    let mut args = std::env::args().skip(1);
    let mut options = Options {
        size: 256,
        repeat: 3,
        only: None,
        models: Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models"),
    };
    let mut measuring = false;
    while let Some(arg) = args.next() {
        let mut value = |name: &str| args.next().with_context(|| format!("{name} needs a value"));
        match arg.as_str() {
            "--bench" => measuring = true,
            "--size" => options.size = value("--size")?.parse().context("--size: a pixel count")?,
            "--repeat" => {
                options.repeat = value("--repeat")?.parse().context("--repeat: a count")?;
            }
            "--only" => options.only = Some(value("--only")?),
            "--models" => options.models = PathBuf::from(value("--models")?),
            _ => {}
        }
    }
    if !(1..=16_384).contains(&options.size) || options.repeat == 0 {
        bail!("--size must be 1..=16384 and --repeat at least 1");
    }
    Ok(measuring.then_some(options))
}

fn main() -> Result<()> {
    let Some(options) = options()? else {
        println!("models bench: run with --bench to measure");
        return Ok(());
    };
    let context = GpuContext::new().context("the models bench compares the GPU with the CPU")?;
    let timestamps = if context.has_timestamps() {
        "kernel-only by timestamp queries"
    } else {
        "no timestamp queries: end to end only"
    };
    println!(
        "adapter\t{}\t{timestamps}\t{} CPU threads",
        context.adapter_name(),
        rayon_threads()
    );
    let dir = &options.models;
    let mut names: Vec<String> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".json"))
        .filter(|n| options.only.as_ref().is_none_or(|o| n.contains(o.as_str())))
        .collect();
    names.sort();
    let side = options.size;
    let mut models = Vec::with_capacity(names.len() + 1);
    for name in &names {
        let text = std::fs::read_to_string(dir.join(name))?;
        let model = spectex_model::from_json(&text).with_context(|| name.clone())?;
        models.push((name.trim_end_matches(".json").to_owned(), model));
    }
    // The GPU bench's LRP model (J = 50 over 4 strata), whose kernel-only and end-to-end
    // figures the LRP target names.
    if options
        .only
        .as_ref()
        .is_none_or(|o| BENCH_LRP.contains(o.as_str()))
    {
        let model = Model::Lrp(spectex_model::fixtures::lrp_four_strata(50));
        models.push((BENCH_LRP.to_owned(), model));
    }
    for (stem, model) in &models {
        match measure(&context, model, side, options.repeat) {
            Ok(m) => println!(
                "model\t{stem}\t{:.1}\t{}\t{:.2}\t{:.2}\t{}\t{:.2}\t{:.2}\t{:.3}",
                m.evaluations,
                m.kernel
                    .map_or_else(|| "-".to_owned(), |k| format!("{k:.2}")),
                m.gpu,
                m.cpu,
                m.tiles,
                m.bytes_per_pixel,
                m.unorm8,
                m.host_ms_per_tile
            ),
            Err(e) => eprintln!("{stem}: skipped: {e:#}"),
        }
    }
    for name in ["texture-synthetic-grey", "texture-synthetic-colour"] {
        if options
            .only
            .as_ref()
            .is_some_and(|o| !name.contains(o.as_str()))
        {
            continue;
        }
        let text = std::fs::read_to_string(dir.join(format!("{name}.json")))?;
        let model = spectex_model::from_json(&text)?;
        let (kernel, end_to_end) = frame_ms(&context, &model, 128, options.repeat.max(5))?;
        println!(
            "frame\t{name}\t128\t{}\t{end_to_end:.3}",
            kernel.map_or_else(|| "-".to_owned(), |k| format!("{k:.3}"))
        );
    }
    Ok(())
}

/// The row of the GPU bench's LRP model (not a testdata file).
const BENCH_LRP: &str = "bench-lrp-j50";

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

struct Measured {
    evaluations: f64,
    kernel: Option<f64>,
    gpu: f64,
    cpu: f64,
    tiles: usize,
    bytes_per_pixel: f64,
    /// GPU end to end as 8-bit unorm.
    unorm8: f64,
    /// Host preparation per tile, ms (summed over the workers).
    host_ms_per_tile: f64,
}

/// Mpix/s of one model: the best of `repeat` renders after a warm-up, on each evaluator.
fn measure(context: &GpuContext, model: &Model, side: usize, repeat: usize) -> Result<Measured> {
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let cpu = Evaluator::new(model)?;
    let gpu = GpuEvaluator::new(context, model)?;
    let pixels = side * side;
    let mut out = vec![0.0f32; pixels * gpu.output_channels()];
    let mut best: Option<spectex_gpu::RenderStats> = None;
    for i in 0..=repeat {
        let stats = gpu.render_into(&window, &mut out)?;
        if i > 0 && best.is_none_or(|b| stats.seconds < b.seconds) {
            best = Some(stats);
        }
    }
    let best = best.context("no timed render")?;
    let mut levels = vec![0u8; out.len()];
    let mut unorm8 = f64::INFINITY;
    for _ in 0..repeat.max(1) {
        let format = spectex_gpu::OutputFormat::Unorm8;
        let stats = gpu.render_bytes_into(&window, format, &mut levels)?;
        unorm8 = unorm8.min(stats.seconds);
    }
    let mut cpu_out = vec![0.0f32; pixels * cpu.output_channels()];
    let mut cpu_best = f64::INFINITY;
    for _ in 0..repeat.min(2) {
        let start = Instant::now();
        cpu.render_into(&window, &mut cpu_out, &|_| {})?;
        cpu_best = cpu_best.min(start.elapsed().as_secs_f64());
    }
    Ok(Measured {
        evaluations: cpu.cost_per_pixel(),
        kernel: best.kernel_mpix_per_second(pixels),
        gpu: best.mpix_per_second(pixels),
        cpu: pixels as f64 / cpu_best / 1e6,
        tiles: best.tiles,
        bytes_per_pixel: best.bytes_read_back as f64 / pixels as f64,
        unorm8: pixels as f64 / unorm8 / 1e6,
        host_ms_per_tile: best.host_seconds * 1e3 / best.tiles.max(1) as f64,
    })
}

/// Milliseconds of a `side`² frame on the GPU, kernel-only and end to end, best of `repeat`.
fn frame_ms(
    context: &GpuContext,
    model: &Model,
    side: usize,
    repeat: usize,
) -> Result<(Option<f64>, f64)> {
    let gpu = GpuEvaluator::new(context, model)?;
    let window = Window::new(side, side);
    let mut out = vec![0.0f32; side * side * gpu.output_channels()];
    gpu.render_into(&window, &mut out)?;
    let mut kernel = f64::INFINITY;
    let mut end_to_end = f64::INFINITY;
    for _ in 0..repeat {
        let stats = gpu.render_into(&window, &mut out)?;
        end_to_end = end_to_end.min(stats.seconds * 1e3);
        if let Some(k) = stats.kernel_seconds {
            kernel = kernel.min(k * 1e3);
        }
    }
    Ok((kernel.is_finite().then_some(kernel), end_to_end))
}
