//! Exemplar images from Python: a numpy array of shape `(H, W)` or `(H, W, 3)` (uint8, uint16,
//! float32 or float64) or a path to a PNG or JPEG file, as the `(channel, row, column)` f64
//! arrays the libraries take, with the values the `spectex` command reads from a file.
//!
//! Integer arrays go through the `image` crate's own conversion (the one a decoded PNG takes),
//! so an array and the PNG file holding it give the same values bit for bit; float64 arrays are
//! viewed, not copied.

use std::path::PathBuf;

use image::{DynamicImage, ImageBuffer, ImageReader, Limits, Luma, Rgb};
use ndarray::{Array3, ArrayView3, Axis};
use numpy::{PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::{type_error, value_error};

/// Largest side the decoder accepts (the `spectex` command's limit).
const MAX_INPUT_SIDE: u32 = 16_384;

/// An exemplar: owned when converted, borrowed from numpy when it was float64 already.
pub(crate) enum Exemplar<'py> {
    /// Converted (integers, float32, a decoded file): `(channel, row, column)`.
    Owned(Array3<f64>),
    /// A C-contiguous float64 numpy array of shape `(H, W)` or `(H, W, 3)`.
    Borrowed(PyReadonlyArrayDyn<'py, f64>),
}

impl Exemplar<'_> {
    /// The image as `(channel, row, column)` (a strided view of a borrowed `(H, W, C)` array).
    pub(crate) fn view(&self) -> PyResult<ArrayView3<'_, f64>> {
        match self {
            Self::Owned(a) => Ok(a.view()),
            Self::Borrowed(a) => {
                let v = a.as_array();
                let v = if v.ndim() == 2 {
                    v.insert_axis(Axis(2))
                } else {
                    v
                };
                v.into_dimensionality::<ndarray::Ix3>()
                    .map(|v| v.permuted_axes([2, 0, 1]))
                    .map_err(value_error)
            }
        }
    }
}

/// Reads `image` (`name` in messages): an array or a path.
pub(crate) fn exemplar<'py>(name: &str, image: &Bound<'py, PyAny>) -> PyResult<Exemplar<'py>> {
    if let Ok(path) = image.extract::<PathBuf>() {
        return load(&path).map(Exemplar::Owned);
    }
    let array = image.cast::<PyUntypedArray>().map_err(|_| {
        type_error(format!(
            "{name} must be a numpy array of shape (H, W) or (H, W, 3) or a path to a PNG/JPEG \
             file, not {}",
            image
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    let shape = array.shape().to_vec();
    let channels = match shape.len() {
        2 => 1,
        3 if shape[2] == 3 => 3,
        3 if shape[2] == 4 => {
            return Err(value_error(format!(
                "{name} has 4 channels (shape {shape:?}); give grey (H, W) or RGB (H, W, 3): \
                 drop the alpha channel with {name}[..., :3]"
            )));
        }
        3 => {
            return Err(value_error(format!(
                "{name} has shape {shape:?}; a colour image must be (H, W, 3)"
            )));
        }
        n => {
            return Err(value_error(format!(
                "{name} has {n} dimensions (shape {shape:?}); it must be (H, W) or (H, W, 3)"
            )));
        }
    };
    let (h, w) = (shape[0], shape[1]);
    if h < 2 || w < 2 || h > MAX_INPUT_SIDE as usize || w > MAX_INPUT_SIDE as usize {
        return Err(value_error(format!(
            "{name} is {w}×{h} pixels; each side must be 2 to {MAX_INPUT_SIDE}"
        )));
    }
    if !array.is_c_contiguous() {
        return Err(value_error(format!(
            "{name} is not C-contiguous (a slice or a transpose); pass \
             numpy.ascontiguousarray({name})"
        )));
    }
    let dtype = array.dtype().to_string();
    let owned = match dtype.as_str() {
        "float64" => {
            let a = image.extract::<PyReadonlyArrayDyn<'py, f64>>()?;
            check_finite(name, a.as_slice()?)?;
            return Ok(Exemplar::Borrowed(a));
        }
        "float32" => {
            let a = image.extract::<PyReadonlyArrayDyn<'py, f32>>()?;
            let values = a.as_slice()?;
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(non_finite(name, i, f64::from(values[i])));
            }
            interleaved(h, w, channels, values.iter().map(|&v| f64::from(v)))
        }
        "uint8" => {
            let a = image.extract::<PyReadonlyArrayDyn<'py, u8>>()?;
            let raw = a.as_slice()?.to_vec();
            let img = match channels {
                1 => ImageBuffer::<Luma<u8>, _>::from_raw(w as u32, h as u32, raw)
                    .map(DynamicImage::ImageLuma8),
                _ => ImageBuffer::<Rgb<u8>, _>::from_raw(w as u32, h as u32, raw)
                    .map(DynamicImage::ImageRgb8),
            };
            decoded(img)?
        }
        "uint16" => {
            let a = image.extract::<PyReadonlyArrayDyn<'py, u16>>()?;
            let raw = a.as_slice()?.to_vec();
            let img = match channels {
                1 => ImageBuffer::<Luma<u16>, _>::from_raw(w as u32, h as u32, raw)
                    .map(DynamicImage::ImageLuma16),
                _ => ImageBuffer::<Rgb<u16>, _>::from_raw(w as u32, h as u32, raw)
                    .map(DynamicImage::ImageRgb16),
            };
            decoded(img)?
        }
        other => {
            return Err(type_error(format!(
                "{name} has dtype {other}; give uint8, uint16 (levels over 255 or 65535), \
                 float32 or float64"
            )));
        }
    };
    Ok(Exemplar::Owned(owned))
}

/// The error for a value that is NaN or infinite at flat index `i`.
fn non_finite(name: &str, i: usize, value: f64) -> PyErr {
    value_error(format!(
        "{name} holds {value} at flat index {i}; every value must be finite"
    ))
}

fn check_finite(name: &str, values: &[f64]) -> PyResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(non_finite(name, i, values[i])),
        None => Ok(()),
    }
}

/// `(channel, row, column)` from values interleaved `(row, column, channel)`.
fn interleaved(h: usize, w: usize, c: usize, values: impl Iterator<Item = f64>) -> Array3<f64> {
    let hwc: Vec<f64> = values.collect();
    Array3::from_shape_fn((c, h, w), |(k, y, x)| hwc[(y * w + x) * c + k])
}

fn decoded(img: Option<DynamicImage>) -> PyResult<Array3<f64>> {
    img.map(|img| to_array(&img))
        .ok_or_else(|| value_error("internal: the array's size does not match its shape"))
}

/// Reads and decodes an image file as the `spectex` command does (PNG or JPEG, alpha dropped).
fn load(path: &std::path::Path) -> PyResult<Array3<f64>> {
    let bytes = std::fs::read(path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!(
            "cannot open input '{}': {e}; check the path",
            path.display()
        ))
    })?;
    let what = format!("input '{}'", path.display());
    let mut reader = ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| value_error(format!("cannot read {what}: {e}")))?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_INPUT_SIDE);
    limits.max_image_height = Some(MAX_INPUT_SIDE);
    limits.max_alloc = Some(4 << 30);
    reader.limits(limits);
    if reader.format().is_none() {
        return Err(value_error(format!(
            "{what} is not a PNG or JPEG image (unrecognised content)"
        )));
    }
    let img = reader.decode().map_err(|e| {
        value_error(format!(
            "cannot decode {what}: {e}; the file may be truncated or corrupt (PNG and JPEG are \
             read, up to {MAX_INPUT_SIDE} pixels per side)"
        ))
    })?;
    Ok(to_array(&img))
}

/// A decoded image as `(channel, row, column)` in `[0, 1]`: RGB when it has colour, else grey
/// (alpha dropped), through the `image` crate's conversions (as `spectex_cli::io` reads files).
fn to_array(img: &DynamicImage) -> Array3<f64> {
    let (w, h) = (img.width() as usize, img.height() as usize);
    if img.color().has_color() {
        let rgb = img.to_rgb32f();
        let raw = rgb.as_raw();
        Array3::from_shape_fn((3, h, w), |(c, y, x)| f64::from(raw[(y * w + x) * 3 + c]))
    } else {
        let grey = img.to_luma32f();
        let raw = grey.as_raw();
        Array3::from_shape_fn((1, h, w), |(_, y, x)| f64::from(raw[y * w + x]))
    }
}
