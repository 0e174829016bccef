//! The view of an image: the exemplar, its fit (as `spectex fit` makes it, with J, the
//! structure share r, turbulence and random placement as the page's controls) and the spectra
//! shown beside the synthesis.

use anyhow::{Context, Result, anyhow};
use image::{DynamicImage, ImageBuffer};
use ndarray::{Array3, Axis};
use serde_json::{Value, json};
use spectex_model::Model;
use spectex_sampling::{FitOptions, TextureOptions};

use super::query::HttpError;
use crate::io;

/// An example image and what the page shows of it.
pub(crate) struct Exemplar {
    /// The pixels, `(channel, row, column)` in `[0, 1]`.
    pub pixels: Array3<f64>,
    /// Its name, for the page.
    pub name: String,
    /// The image as an 8-bit PNG.
    pub png: Vec<u8>,
    /// Its log-magnitude spectrum as a PNG.
    pub spectrum: Vec<u8>,
}

impl Exemplar {
    /// The exemplar of `pixels`.
    pub(crate) fn new(pixels: Array3<f64>, name: String) -> Result<Self> {
        let (c, h, w) = pixels.dim();
        let levels: Vec<u8> = (0..h)
            .flat_map(|y| (0..w).flat_map(move |x| (0..c).map(move |ch| (ch, y, x))))
            .map(|(ch, y, x)| io::level8(pixels[[ch, y, x]] as f32))
            .collect();
        let (w32, h32) = (w as u32, h as u32);
        let img = if c == 1 {
            DynamicImage::ImageLuma8(ImageBuffer::from_raw(w32, h32, levels).context("grey")?)
        } else {
            DynamicImage::ImageRgb8(ImageBuffer::from_raw(w32, h32, levels).context("RGB")?)
        };
        let mut png = Vec::new();
        img.write_with_encoder(image::codecs::png::PngEncoder::new(&mut png))?;
        let spectrum = super::tiles::spectrum_png(&pixels)?;
        Ok(Self {
            pixels,
            name,
            png,
            spectrum,
        })
    }

    /// The exemplar's size `(width, height)`.
    pub(crate) fn size(&self) -> (usize, usize) {
        let (_, h, w) = self.pixels.dim();
        (w, h)
    }
}

/// The fit's controls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FitParams {
    /// Cosines per lattice point, J.
    pub budget: u32,
    /// Share of the energy whose phases are kept, r.
    pub structure: f64,
    /// Turbulence σ, pixels.
    pub turbulence: f64,
    /// Random placement of half-period blocks.
    pub random_placement: bool,
    /// Seed of the fit.
    pub seed: u32,
}

impl Default for FitParams {
    fn default() -> Self {
        Self {
            budget: 50,
            structure: 0.0,
            turbulence: 0.0,
            random_placement: false,
            seed: 0,
        }
    }
}

impl FitParams {
    /// The options `spectex fit` would use.
    fn options(&self) -> TextureOptions {
        TextureOptions {
            fit: FitOptions {
                budget: self.budget,
                seed: self.seed,
                ..FitOptions::default()
            },
            structure: self.structure,
            turbulence: self.turbulence,
            random_placement: self.random_placement,
            ..TextureOptions::default()
        }
    }

    /// The parameters of a request body `{"budget", "structure", "turbulence",
    /// "random_placement", "seed"}` (absent ones keep `self`'s), checked as `spectex fit`
    /// checks its flags.
    pub(crate) fn updated(&self, body: &Value) -> Result<Self, HttpError> {
        let obj = body
            .as_object()
            .ok_or_else(|| HttpError::bad("the body must be a JSON object"))?;
        let mut p = *self;
        for (key, v) in obj {
            let number = || {
                v.as_f64()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| HttpError::bad(format!("{key} = {v} is not a finite number")))
            };
            let whole = |max: f64| -> Result<u32, HttpError> {
                let x = number()?;
                if x.fract() != 0.0 || !(0.0..=max).contains(&x) {
                    return Err(HttpError::bad(format!(
                        "{key} = {x} is outside its valid range [0, {max}] (whole numbers)"
                    )));
                }
                Ok(x as u32)
            };
            match key.as_str() {
                "budget" => p.budget = whole(f64::from(u32::MAX))?,
                "seed" => p.seed = whole(f64::from(u32::MAX))?,
                "structure" => p.structure = number()?,
                "turbulence" => p.turbulence = number()?,
                "random_placement" => {
                    p.random_placement = v.as_bool().ok_or_else(|| {
                        HttpError::bad(format!("random_placement = {v} is not true or false"))
                    })?;
                }
                other => {
                    return Err(HttpError::bad(format!(
                        "unknown fit parameter '{}'; give budget, structure, turbulence, \
                         random_placement or seed",
                        other.escape_default()
                    )));
                }
            }
        }
        p.options()
            .validate()
            .map_err(|e| HttpError::bad(format!("{e}")))?;
        Ok(p)
    }

    /// The parameters as the page shows them.
    pub(crate) fn to_json(self) -> Value {
        json!({
            "budget": self.budget,
            "structure": self.structure,
            "turbulence": self.turbulence,
            "random_placement": self.random_placement,
            "seed": self.seed,
        })
    }
}

/// Fits `exemplar` as `spectex fit` does with these parameters: an LRP noise for a grey image
/// without structure, turbulence or placement, else a texture model.
pub(crate) fn fit(exemplar: &Exemplar, params: &FitParams) -> Result<Model> {
    let options = params.options();
    options.validate().map_err(|e| anyhow!("{e}"))?;
    let texture = params.structure > 0.0 || params.turbulence > 0.0 || params.random_placement;
    if exemplar.pixels.dim().0 == 1 && !texture {
        let grey = exemplar.pixels.index_axis(Axis(0), 0);
        let model = spectex_sampling::fit_image(grey, &options.fit)
            .with_context(|| format!("cannot fit {}", exemplar.name))?;
        return Ok(model.into());
    }
    let (model, _) = spectex_sampling::fit_texture(exemplar.pixels.view(), &options)
        .with_context(|| format!("cannot fit {}", exemplar.name))?;
    Ok(model.into())
}
