//! Fits models to an example image and renders them larger than the example: an LRP noise of
//! its grey levels (Gilet et al. 2014, §4: the power spectrum, random phases) and a colour
//! texture by example (§5: the phases of its strongest frequencies kept, turbulence, random
//! placement).
//!
//! ```sh
//! cargo run --example 02_fit_and_render -- [OUT_DIR] [EXAMPLE.png]
//! ```
//!
//! `EXAMPLE.png` defaults to `crates/spectex-cli/default_exemplar.png`, the 256×256 colour exemplar
//! spectex made itself.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use ndarray::{Array2, Array3};
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_sampling::{FitOptions, TextureOptions, fit_image, fit_texture};

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out_dir = args.next().map_or_else(std::env::temp_dir, PathBuf::from);
    let example = args.next().map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("default_exemplar.png"),
        PathBuf::from,
    );
    let rgb = image::open(&example)
        .with_context(|| format!("cannot read {}", example.display()))?
        .to_rgb32f();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    std::fs::create_dir_all(&out_dir)?;

    // LRP noise by example: fitted to the Rec. 709 luminance, 16 cosines per lattice point in
    // 4 strata. The model is small (a few kB of frequencies) and renders at any size.
    let grey = Array2::from_shape_fn((h, w), |(y, x)| {
        let p = rgb.get_pixel(x as u32, y as u32);
        f64::from(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])
    });
    let options = FitOptions {
        budget: 16,
        strata: 4,
        seed: 1,
        ..FitOptions::default()
    };
    let noise = fit_image(grey.view(), &options)?;
    let json = out_dir.join("02_noise.json");
    std::fs::write(&json, spectex_model::to_json(&noise.clone().into())?)?;
    render(&noise.into(), 3 * w / 2, h, &out_dir.join("02_noise.png"))?;
    println!("wrote {} (the fitted model)", json.display());

    // Texture by example, from the top-left 64×64 pixels: colour channels decorrelated by
    // PCA, the phases of the frequencies holding 20% of the energy kept (the structure),
    // distorted by 2-pixel turbulence, blocks placed at random to hide the period.
    let side = w.min(h).min(64);
    let colour = Array3::from_shape_fn((3, side, side), |(c, y, x)| {
        f64::from(rgb.get_pixel(x as u32, y as u32)[c])
    });
    let texture_options = TextureOptions {
        fit: options,
        structure: 0.2,
        turbulence: 2.0,
        random_placement: true,
        ..TextureOptions::default()
    };
    let (texture, report) = fit_texture(colour.view(), &texture_options)?;
    println!(
        "texture: period {} px, {} blocks per side, structure {} cosines per block",
        report.period, report.channels[0].blocks, report.channels[0].structure_cosines
    );
    render(
        &texture.into(),
        2 * side,
        2 * side,
        &out_dir.join("02_texture.png"),
    )
}

/// Renders `width × height` pixels of `model` at the origin on the CPU and writes an 8-bit PNG
/// (grey or RGB as the model gives), clamping to [0, 1].
fn render(model: &Model, width: usize, height: usize, path: &Path) -> Result<()> {
    let evaluator = Evaluator::new(model)?;
    let values = evaluator.render(&Window::new(width, height))?;
    let bytes: Vec<u8> = values
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    let colour = if evaluator.output_channels() == 3 {
        image::ColorType::Rgb8
    } else {
        image::ColorType::L8
    };
    image::save_buffer(path, &bytes, width as u32, height as u32, colour)?;
    println!(
        "wrote {} ({width}×{height}, {})",
        path.display(),
        model.kind()
    );
    Ok(())
}
