//! Loads a model file, renders a window of it on the CPU and writes a PNG: what a game or a
//! tool needs to use a model fitted by `spectex fit` (or written by any `--model` flag).
//!
//! ```sh
//! cargo run --example 01_evaluate_model_file -- [OUT_DIR] [MODEL.json]
//! ```
//!
//! `OUT_DIR` defaults to the system's temporary directory, `MODEL.json` to
//! `testdata/models/lrp-gravel.json` (an LRP noise fitted to a photograph of gravel).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use spectex_cpu::{Evaluator, Window};

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out_dir = args.next().map_or_else(std::env::temp_dir, PathBuf::from);
    let model_path = args.next().map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models/lrp-gravel.json"),
        PathBuf::from,
    );

    // Read and validate the model, build its evaluator, render a window.
    let text = std::fs::read_to_string(&model_path)
        .with_context(|| format!("cannot read {}", model_path.display()))?;
    let model = spectex_model::from_json(&text)?;
    let evaluator = Evaluator::new(&model)?;
    // 256 × 256 pixels far from the origin: positions are continuous and the noise infinite,
    // so this window is as precise as one at (0, 0).
    let window = Window::new(256, 256).at([1.0e7, -2.5e6], 1.0);
    let values = evaluator.render(&window)?;

    std::fs::create_dir_all(&out_dir)?;
    let out = out_dir.join("01_model.png");
    save_png(&out, &window, evaluator.output_channels(), &values)?;
    println!(
        "wrote {} ({} model, {}×{} at (1e7, -2.5e6))",
        out.display(),
        model.kind(),
        window.width,
        window.height
    );
    Ok(())
}

/// Writes `values` (1 grey or 3 RGB values per pixel, row-major, as the evaluators return
/// them) as an 8-bit PNG, clamping to [0, 1].
fn save_png(path: &Path, window: &Window, channels: usize, values: &[f32]) -> Result<()> {
    let bytes: Vec<u8> = values
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    let (w, h) = (window.width as u32, window.height as u32);
    let colour = if channels == 3 {
        image::ColorType::Rgb8
    } else {
        image::ColorType::L8
    };
    image::save_buffer(path, &bytes, w, h, colour)?;
    Ok(())
}
