//! Renders a noise on the GPU (wgpu compute) and compares it with the CPU reference. Without
//! a GPU adapter it says why and exits successfully; lavapipe (`apt-get install
//! mesa-vulkan-drivers`) is a software Vulkan adapter that works everywhere, and
//! `WGPU_ADAPTER_NAME=llvmpipe` selects it.
//!
//! ```sh
//! cargo run --example 04_render_on_gpu -- [OUT_DIR]
//! ```

use std::path::{Path, PathBuf};

use anyhow::Result;
use spectex_cpu::Evaluator;
use spectex_gpu::{GpuContext, GpuEvaluator, GpuWindow};
use spectex_model::{ClassicNoise, Model};

fn main() -> Result<()> {
    let out_dir = std::env::args()
        .nth(1)
        .map_or_else(std::env::temp_dir, PathBuf::from);

    let context = match GpuContext::new() {
        Ok(context) => context,
        Err(e) => {
            println!("no GPU to render on ({e}); nothing written");
            return Ok(());
        }
    };
    let model: Model = ClassicNoise::fbm().octaves(5).seed(11).build()?.into();
    let gpu = GpuEvaluator::new(&context, &model)?;
    // Any window, anywhere: the host splits positions into cells and offsets in f64.
    let window = GpuWindow::new(256, 256).at([5.0e6, 5.0e6], 0.5);
    let values = gpu.render(&window)?;

    // The CPU reference of the same window: the two agree within the cross-checked
    // tolerances (bit for bit for most classic noises on lavapipe).
    let reference = Evaluator::new(&model)?.render(&window)?;
    let largest_difference = values
        .iter()
        .zip(&reference)
        .map(|(g, c)| (g - c).abs())
        .fold(0.0f32, f32::max);

    std::fs::create_dir_all(&out_dir)?;
    let out = out_dir.join("04_gpu.png");
    save_grey_png(&out, &window, &values)?;
    println!(
        "wrote {} (256×256 on {}; largest difference from the CPU {largest_difference:e})",
        out.display(),
        gpu.adapter_name()
    );
    Ok(())
}

/// Writes one grey value per pixel as an 8-bit PNG, clamping to [0, 1].
fn save_grey_png(path: &Path, window: &GpuWindow, values: &[f32]) -> Result<()> {
    let bytes: Vec<u8> = values
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    let (w, h) = (window.width as u32, window.height as u32);
    image::save_buffer(path, &bytes, w, h, image::ColorType::L8)?;
    Ok(())
}
