//! `spectex.fit`, `spectex.rpn` and `spectex.analyze`: the library calls the `spectex fit`,
//! `rpn` and `analyze` commands make, on an exemplar array or file, with the GIL released.

use ndarray::{Array2, Array3, ArrayView3, Axis};
use numpy::{PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spectex_model::tiling::Blend;
use spectex_model::{Fit, Model};
use spectex_sampling::tiling::TilingOptions;
use spectex_sampling::{FitMethod, FitOptions, TextureOptions};
use spectex_spectrum::{
    Fft2, NoiseKind, Rpn, RpnOptions, centered, log_magnitude_spectrum, periodic_smooth,
    radial_profile, validate_image, variance_spectrum, welch_psd,
};

use crate::errors::{guard, value_error};
use crate::image_in::exemplar;
use crate::model::PyModel;

/// Tiling and blending by example (Heitz & Neyret 2018, with Deliot & Heitz's PCA channels and
/// prefiltered tables): the exemplar's tiles on a triangle lattice, blended so that its
/// histogram is kept. The same model as ``spectex fit --method tiling``.
///
/// ``image``: an array of shape (H, W) or (H, W, 3) (sides 8 to 4096) or a path; ``tile``: the
/// triangles' side in pixels (default a sixth of the smaller side; at most half of it);
/// ``blend``: ``"variance"`` (histogram-preserving) or ``"hex"`` (Mikkelsen's hex-tiling, with
/// ``sharpness`` γ from 1 to 32 and ``rotation`` up to 0.5 turns); ``seed``.
///
/// Example::
///
///     >>> import numpy as np, spectex
///     >>> model = spectex.fit_tiling(np.random.default_rng(0).random((64, 64, 3)), tile=8)
///     >>> model.kind, model.render(32, 32).shape
///     ('tiling', (32, 32, 3))
#[pyfunction]
#[pyo3(signature = (image, tile = None, blend = "variance", sharpness = 7, rotation = 0.0, seed = 0))]
pub(crate) fn fit_tiling(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    tile: Option<f32>,
    blend: &str,
    sharpness: i64,
    rotation: f32,
    seed: i64,
) -> PyResult<PyModel> {
    let seed = u32::try_from(seed).map_err(|_| {
        value_error(format!(
            "seed = {seed} is outside its valid range 0 to 2^32 - 1"
        ))
    })?;
    let blend = match blend {
        "variance" => Blend::Variance,
        "hex" => Blend::Hex {
            sharpness: u32::try_from(sharpness).map_err(|_| {
                value_error(format!(
                    "sharpness = {sharpness} is outside its valid range 1 to 32"
                ))
            })?,
            rotation,
        },
        other => {
            return Err(value_error(format!(
                "blend = '{other}' is not a blend; valid: 'variance', 'hex'"
            )));
        }
    };
    let options = TilingOptions { tile, blend, seed };
    let exemplar = exemplar("image", image)?;
    let view = exemplar.view()?;
    let model = py.detach(|| {
        guard(|| {
            spectex_sampling::tiling::fit_tiling(view, &options)
                .map(Model::Tiling)
                .map_err(value_error)
        })
    })?;
    Ok(PyModel {
        model,
        period: None,
        fit: None,
    })
}

/// Fits a model to an exemplar (Gilet et al. 2014): Local Random-Phase noise for a grey
/// exemplar, a texture model for a colour one or with ``structure``, ``turbulence`` or
/// ``random_placement`` (§5). The same model as ``spectex fit`` on the same image.
///
/// ``image``: an array of shape (H, W) or (H, W, 3) — uint8, uint16 or float (values in
/// [0, 1] for floats) — or a path to a PNG or JPEG file. ``budget``: cosines per lattice point
/// J (1 to 1024); ``strata``: number of strata L (1 to 64, at most J; default 4);
/// ``structure``: share r of the energy whose phases are kept (0 to 1); ``turbulence``: σ in
/// pixels (0 to 1e4); ``random_placement``: shift half-period blocks at random; ``seed``;
/// ``method``: ``"spectrum"`` (match the exemplar's spectrum) or ``"paper"`` (§4.3 as printed).
///
/// Example::
///
///     >>> import numpy as np, spectex
///     >>> rng = np.random.default_rng(0)
///     >>> exemplar = rng.random((64, 64))
///     >>> model = spectex.fit(exemplar, budget=16, strata=2)
///     >>> model.kind
///     'lrp'
///     >>> model.render(128, 128, offset=(1e6, 1e6)).shape
///     (128, 128)
#[pyfunction]
#[pyo3(signature = (image, budget = 50, strata = None, structure = 0.0, turbulence = None, random_placement = false, seed = 0, method = "spectrum"))]
#[allow(
    clippy::too_many_arguments,
    reason = "the Python signature's keyword arguments"
)]
pub(crate) fn fit(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    budget: i64,
    strata: Option<i64>,
    structure: f64,
    turbulence: Option<f64>,
    random_placement: bool,
    seed: i64,
    method: &str,
) -> PyResult<PyModel> {
    let whole = |name: &str, v: i64, range: &str| {
        u32::try_from(v)
            .map_err(|_| value_error(format!("{name} = {v} is outside its valid range {range}")))
    };
    let method = FitMethod::from_name(method).map_err(value_error)?;
    let defaults = FitOptions::default();
    let options = TextureOptions {
        fit: FitOptions {
            budget: whole("budget", budget, "1..=1024 cosines")?,
            strata: match strata {
                Some(s) => whole("strata", s, "1..=64")?,
                None => defaults.strata,
            },
            seed: whole("seed", seed, "0 to 2^32 - 1")?,
            method,
            ..defaults
        },
        structure,
        turbulence: turbulence.unwrap_or(0.0),
        random_placement,
        ..TextureOptions::default()
    };
    // Options first: a bad budget is reported before the image is read.
    options.validate().map_err(value_error)?;
    let wants_texture =
        options.structure > 0.0 || options.turbulence > 0.0 || options.random_placement;
    let exemplar = exemplar("image", image)?;
    let view = exemplar.view()?;
    let model = py.detach(|| {
        guard(|| {
            if view.dim().0 == 1 && !wants_texture {
                let grey = view.index_axis(Axis(0), 0);
                spectex_sampling::fit_image(grey, &options.fit)
                    .map(Model::from)
                    .map_err(value_error)
            } else {
                spectex_sampling::fit_texture(view, &options)
                    .map(|(m, _)| Model::Texture(m))
                    .map_err(value_error)
            }
        })
    })?;
    Ok(PyModel {
        model,
        period: None,
        fit: Some(match method {
            FitMethod::Spectrum => Fit::Spectrum,
            FitMethod::Paper => Fit::Paper,
        }),
    })
}

/// Random Phase Noise (Galerne, Gousseau & Morel 2011): a texture with the exemplar's mean
/// and the modulus of its periodic component's spectrum, all channels sharing one random
/// phase; ``size=(width, height)`` at least the exemplar's uses the spot extension; ``adsn``
/// convolves with Gaussian white noise instead. Returns float64 of shape (H, W) or (H, W, 3).
///
/// Example::
///
///     >>> import numpy as np, spectex
///     >>> exemplar = np.random.default_rng(1).random((32, 32, 3))
///     >>> spectex.rpn(exemplar, size=(64, 48), seed=2).shape
///     (48, 64, 3)
#[pyfunction]
#[pyo3(signature = (image, size = None, seed = 0, adsn = false))]
pub(crate) fn rpn<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    size: Option<(i64, i64)>,
    seed: i64,
    adsn: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let size = size
        .map(|(w, h)| {
            let side = |name: &str, v: i64| {
                usize::try_from(v).ok().filter(|&v| v > 0).ok_or_else(|| {
                    value_error(format!(
                        "size {name} = {v} is outside its valid range (at least the image's)"
                    ))
                })
            };
            Ok::<_, PyErr>((side("width", w)?, side("height", h)?))
        })
        .transpose()?;
    let options = RpnOptions {
        size,
        seed: u32::try_from(seed).map_err(|_| {
            value_error(format!(
                "seed = {seed} is outside its valid range 0 to 2^32 - 1"
            ))
        })?,
        kind: if adsn {
            NoiseKind::Adsn
        } else {
            NoiseKind::RandomPhase
        },
        ..RpnOptions::default()
    };
    let exemplar = exemplar("image", image)?;
    let view = exemplar.view()?;
    let out = py.detach(|| guard(|| Rpn::new().synthesize(view, &options).map_err(value_error)))?;
    channels_last(py, out)
}

/// The spectral analyses ``spectex analyze`` writes, as arrays: ``periodic`` and ``smooth``
/// (Moisan's periodic + smooth decomposition, per channel), ``log_spectrum`` and
/// ``log_spectrum_periodic`` (centred ln(1 + |DFT|) of the Rec. 709 luminance, before and
/// after removing the smooth component), ``welch_psd`` and ``variance_spectrum`` (centred, on
/// the Welch blocks' grid),
/// and ``radial_profile``: a dict of ``radius`` (cycles per pixel), ``count`` and ``power``
/// (Welch power of the luminance per ring) and ``power_channels`` (one column per channel).
///
/// Example::
///
///     >>> import numpy as np, spectex
///     >>> a = spectex.analyze(np.random.default_rng(0).random((32, 32)))
///     >>> sorted(a)[:3], a["log_spectrum"].shape
///     (['log_spectrum', 'log_spectrum_periodic', 'periodic'], (32, 32))
#[pyfunction]
pub(crate) fn analyze<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let exemplar = exemplar("image", image)?;
    let view = exemplar.view()?;
    let analysis = py.detach(|| guard(|| analyses(view)))?;
    let dict = PyDict::new(py);
    dict.set_item("periodic", channels_last(py, analysis.periodic)?)?;
    dict.set_item("smooth", channels_last(py, analysis.smooth)?)?;
    for (name, a) in [
        ("log_spectrum", analysis.log_spectrum),
        ("log_spectrum_periodic", analysis.log_spectrum_periodic),
        ("welch_psd", analysis.welch_psd),
        ("variance_spectrum", analysis.variance_spectrum),
    ] {
        dict.set_item(name, PyArray2::from_owned_array(py, a))?;
    }
    let radial = PyDict::new(py);
    radial.set_item("radius", PyArray1::from_vec(py, analysis.radius))?;
    radial.set_item("count", PyArray1::from_vec(py, analysis.count))?;
    radial.set_item("power", PyArray1::from_vec(py, analysis.power))?;
    radial.set_item(
        "power_channels",
        PyArray2::from_owned_array(py, analysis.power_channels),
    )?;
    dict.set_item("radial_profile", radial)?;
    Ok(dict)
}

/// What [`analyze`] returns, computed without the GIL.
struct Analysis {
    periodic: Array3<f64>,
    smooth: Array3<f64>,
    log_spectrum: Array2<f64>,
    log_spectrum_periodic: Array2<f64>,
    welch_psd: Array2<f64>,
    variance_spectrum: Array2<f64>,
    radius: Vec<f64>,
    count: Vec<u64>,
    power: Vec<f64>,
    power_channels: Array2<f64>,
}

/// The analyses of `spectex analyze` (`spectex-cli`'s `analyze.rs`), the same library calls.
fn analyses(img: ArrayView3<'_, f64>) -> PyResult<Analysis> {
    validate_image("image", img).map_err(value_error)?;
    let (channels, h, w) = img.dim();
    spectex_spectrum::welch_block_size(h, w).map_err(value_error)?;
    let mut fft = Fft2::new();
    let mut periodic = Array3::zeros(img.dim());
    let mut smooth = Array3::zeros(img.dim());
    for c in 0..channels {
        let d = periodic_smooth(img.index_axis(Axis(0), c), &mut fft);
        periodic.index_axis_mut(Axis(0), c).assign(&d.periodic);
        smooth.index_axis_mut(Axis(0), c).assign(&d.smooth);
    }
    let luma = spectex_spectrum::luminance(img);
    let luma_p = spectex_spectrum::luminance(periodic.view());
    let psd = welch_psd(luma.view(), &mut fft).map_err(value_error)?;
    let var = variance_spectrum(luma.view(), &mut fft).map_err(value_error)?;
    let log_spectrum = log_magnitude_spectrum(luma.view(), &mut fft);
    let log_spectrum_periodic = log_magnitude_spectrum(luma_p.view(), &mut fft);
    let rings = radial_profile(psd.view());
    let mut power_channels = Array2::zeros((rings.len(), channels));
    for c in 0..channels {
        let p = welch_psd(img.index_axis(Axis(0), c), &mut fft).map_err(value_error)?;
        for (i, bin) in radial_profile(p.view())
            .iter()
            .enumerate()
            .take(rings.len())
        {
            power_channels[[i, c]] = bin.power;
        }
    }
    Ok(Analysis {
        periodic,
        smooth,
        log_spectrum,
        log_spectrum_periodic,
        welch_psd: centered(psd.view()),
        variance_spectrum: centered(var.view()),
        radius: rings.iter().map(|b| b.radius).collect(),
        count: rings.iter().map(|b| b.count as u64).collect(),
        power: rings.iter().map(|b| b.power).collect(),
        power_channels,
    })
}

/// A `(channel, row, column)` array as numpy `(H, W)` for one channel or `(H, W, C)`, without
/// copying (a strided view of the array numpy now owns).
fn channels_last<'py>(py: Python<'py>, a: Array3<f64>) -> PyResult<Bound<'py, PyAny>> {
    if a.dim().0 == 1 {
        let grey = a.index_axis_move(Axis(0), 0);
        Ok(PyArray2::from_owned_array(py, grey).into_any())
    } else {
        Ok(PyArray3::from_owned_array(py, a.permuted_axes([1, 2, 0])).into_any())
    }
}
