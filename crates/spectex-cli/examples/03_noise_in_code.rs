//! Builds noises in code with the model builders (every default a documented constant, every
//! value checked by `build()`), renders them on the CPU and writes PNGs and the model files.
//!
//! ```sh
//! cargo run --example 03_noise_in_code -- [OUT_DIR]
//! ```

use std::path::{Path, PathBuf};

use anyhow::Result;
use spectex_cpu::{Evaluator, Window};
use spectex_model::classic::{Metric, Worley};
use spectex_model::{ClassicNoise, Model, SpectralTarget, Warp, WaveletNoise};
use spectex_sampling::LrpFromTarget;

fn main() -> Result<()> {
    let out_dir = std::env::args()
        .nth(1)
        .map_or_else(std::env::temp_dir, PathBuf::from);
    std::fs::create_dir_all(&out_dir)?;

    // Six octaves of Perlin noise, mapped into [0, 1] (ClassicNoise::default_levels).
    let fbm = ClassicNoise::fbm().octaves(6).seed(3).build()?;
    // Cell borders: Worley's F₂ − F₁ under the Manhattan distance.
    let cells = ClassicNoise::worley()
        .worley(Worley {
            metric: Metric::Manhattan,
            coefficients: [-1.0, 1.0, 0.0, 0.0],
            ..Worley::default()
        })
        .cell_size(24.0)
        .build()?;
    // Isotropic noise of one scale: LRP noise whose power lies on a ring of 1/16 cycle per
    // pixel (Gilet et al. 2014, Fig. 10), fitted once from the spectrum.
    let ring = LrpFromTarget::new(SpectralTarget::Ring {
        radius: 0.0625,
        width: 0.005,
    })
    .budget(6)
    .build()?;
    // Wavelet noise in three octave bands, warped by a zero-mean fBm: marble-like veins.
    let marble = Warp::of(
        WaveletNoise::builder()
            .bands(vec![1.0, 0.5, 0.25])
            .cell_size(32.0)
            .build()?,
    )
    .strength(24.0)
    .build()?;

    let noises: [(&str, Model); 4] = [
        ("fbm", fbm.into()),
        ("cells", cells.into()),
        ("ring", ring.into()),
        ("marble", marble.into()),
    ];
    let window = Window::new(192, 192);
    for (name, model) in noises {
        let values = Evaluator::new(&model)?.render(&window)?;
        let png = out_dir.join(format!("03_{name}.png"));
        save_grey_png(&png, &window, &values)?;
        // The same model as a file, for `spectex render` or 01_evaluate_model_file.
        let json = out_dir.join(format!("03_{name}.json"));
        std::fs::write(&json, spectex_model::to_json(&model)?)?;
        println!(
            "wrote {} and {} ({})",
            png.display(),
            json.display(),
            model.kind()
        );
    }
    Ok(())
}

/// Writes one grey value per pixel as an 8-bit PNG, clamping to [0, 1].
fn save_grey_png(path: &Path, window: &Window, values: &[f32]) -> Result<()> {
    let bytes: Vec<u8> = values
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    let (w, h) = (window.width as u32, window.height as u32);
    image::save_buffer(path, &bytes, w, h, image::ColorType::L8)?;
    Ok(())
}
