//! `spectex.Model`: a validated model (with the period and fit its file records), its files and
//! JSON, and its renders and samples as numpy arrays.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyArray3, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyType;
use spectex_cpu::{Evaluator, Filter, Window};
use spectex_model::{Fit, Model, Period};

use crate::errors::{type_error, value_error};
use crate::render::{render_window, sample_points};

/// A procedural texture model (any kind: ``lrp``, ``classic``, ``voronoi``, …), validated.
///
/// Build one with a builder (``spectex.noise.perlin()``, ``spectex.phasor()``, …), by fitting
/// an exemplar (``spectex.fit``) or from a model file (``Model.load``). Models are immutable:
/// ``reseeded`` and ``periodic`` return new ones.
///
/// Example::
///
///     >>> import spectex
///     >>> m = spectex.noise.perlin(cell_size=16.0, seed=3)
///     >>> m.kind, m.channels
///     ('classic', 1)
///     >>> m.render(64, 32).shape
///     (32, 64)
#[pyclass(name = "Model", module = "spectex", frozen)]
#[derive(Clone)]
pub struct PyModel {
    pub(crate) model: Model,
    pub(crate) period: Option<Period>,
    pub(crate) fit: Option<Fit>,
}

impl PyModel {
    /// A model without period or fit.
    pub(crate) fn plain(model: Model) -> Self {
        Self {
            model,
            period: None,
            fit: None,
        }
    }

    fn evaluator(&self, z: f64) -> PyResult<Evaluator> {
        Evaluator::with_period(&self.model, z, self.period).map_err(value_error)
    }
}

/// A side of a render, checked before it is a `usize` (a negative side is a `ValueError`
/// naming it, not an overflow).
fn side(name: &str, value: i64) -> PyResult<usize> {
    usize::try_from(value)
        .ok()
        .filter(|&v| v > 0)
        .ok_or_else(|| {
            value_error(format!(
                "{name} = {value} is outside its valid range 1 to 65536 pixels"
            ))
        })
}

#[pymethods]
impl PyModel {
    /// Reads a model file (JSON written by ``Model.save``, ``spectex fit`` or
    /// ``spectex noise … --model``), with the period it records.
    ///
    /// Example::
    ///
    ///     >>> import os, tempfile
    ///     >>> path = os.path.join(tempfile.mkdtemp(), "ring.json")
    ///     >>> spectex.noise.gabor().save(path)
    ///     >>> spectex.Model.load(path).kind
    ///     'gabor'
    #[classmethod]
    fn load(_cls: &Bound<'_, PyType>, path: PathBuf) -> PyResult<Self> {
        let text = std::fs::read_to_string(&path).map_err(|e| {
            pyo3::exceptions::PyOSError::new_err(format!(
                "cannot open model '{}': {e}",
                path.display()
            ))
        })?;
        Self::parse(&text).map_err(|e| value_error(format!("model '{}': {e}", path.display())))
    }

    /// A model from the text of a model file (``to_json``'s output).
    ///
    /// Example::
    ///
    ///     >>> m = spectex.noise.voronoi()
    ///     >>> spectex.Model.from_json(m.to_json()) == m
    ///     True
    #[classmethod]
    fn from_json(_cls: &Bound<'_, PyType>, text: &str) -> PyResult<Self> {
        Self::parse(text)
    }

    /// Writes the model file (pretty JSON with ``schema_version``) to ``path``, which must end
    /// in ``.json``.
    ///
    /// Example::
    ///
    ///     >>> import os, tempfile
    ///     >>> path = os.path.join(tempfile.mkdtemp(), "perlin.json")
    ///     >>> m = spectex.noise.perlin(seed=4)
    ///     >>> m.save(path)
    ///     >>> spectex.Model.load(path) == m
    ///     True
    fn save(&self, path: PathBuf) -> PyResult<()> {
        if path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
            != Some("json")
        {
            return Err(value_error(format!(
                "model file '{}' must end in .json",
                path.display()
            )));
        }
        let text = self.to_json()?;
        std::fs::write(&path, text).map_err(|e| {
            pyo3::exceptions::PyOSError::new_err(format!("cannot write '{}': {e}", path.display()))
        })
    }

    /// The model file's text (pretty JSON with ``schema_version``, the fit and the period).
    ///
    /// Example::
    ///
    ///     >>> '"voronoi"' in spectex.noise.voronoi().to_json()
    ///     True
    fn to_json(&self) -> PyResult<String> {
        spectex_model::to_json_file(&self.model, self.fit, self.period).map_err(value_error)
    }

    /// The kind: ``"lrp"``, ``"classic"``, ``"voronoi"``, … (the model file's tag).
    #[getter]
    fn kind(&self) -> &'static str {
        self.model.kind()
    }

    /// Values per pixel: 3 for a colour texture, else 1.
    #[getter]
    fn channels(&self) -> usize {
        self.model.output_channels()
    }

    /// ``(width, height)`` of the period the model is evaluated with, or ``None``.
    #[getter]
    fn period(&self) -> Option<(u32, u32)> {
        self.period.map(|p| {
            let [w, h] = p.to_array();
            (w, h)
        })
    }

    /// The same model with every seed (nested models' too) advanced by ``delta``: an
    /// independent copy of the same noise.
    ///
    /// Example::
    ///
    ///     >>> m = spectex.noise.perlin()
    ///     >>> bool((m.reseeded(1).render(8, 8) != m.render(8, 8)).any())
    ///     True
    fn reseeded(&self, delta: i64) -> PyResult<Self> {
        let delta = u32::try_from(delta).map_err(|_| {
            value_error(format!(
                "delta = {delta} is outside its valid range 0 to 2^32 - 1"
            ))
        })?;
        Ok(Self {
            model: self.model.reseeded(delta),
            ..self.clone()
        })
    }

    /// The model made exactly periodic with period ``width × height`` model pixels (seamless
    /// tiles: a ``2w × 2h`` render is the ``w × h`` one repeated 2 × 2, bit for bit).
    ///
    /// Example::
    ///
    ///     >>> t = spectex.noise.perlin(cell_size=16.0).periodic(64, 64)
    ///     >>> a = t.render(128, 128)
    ///     >>> bool((a[:64, :64] == a[64:, 64:]).all())
    ///     True
    fn periodic(&self, width: i64, height: i64) -> PyResult<Self> {
        let w = u32::try_from(width).map_err(|_| {
            value_error(format!("period.width = {width} is outside its valid range"))
        })?;
        let h = u32::try_from(height).map_err(|_| {
            value_error(format!(
                "period.height = {height} is outside its valid range"
            ))
        })?;
        let period = Period::new(w, h).map_err(value_error)?;
        self.model.check_period(period).map_err(value_error)?;
        Ok(Self {
            period: Some(period),
            ..self.clone()
        })
    }

    /// Renders a ``width × height`` window on the CPU (bit for bit the Rust evaluator's
    /// values; the GIL is released, Ctrl-C stops it within one band of rows) or the GPU.
    ///
    /// ``offset`` is the top-left pixel's position in model pixels (anywhere up to ±2³⁰),
    /// ``scale`` the model pixels per output pixel (0 < scale ≤ 1e6), ``z`` the plane of a 3D
    /// model; ``filter=False`` point-samples a minified render instead of fading out what its
    /// pixels cannot resolve. Returns a float32 array of shape ``(height, width)``, or
    /// ``(height, width, 3)`` for a colour model.
    ///
    /// Example::
    ///
    ///     >>> m = spectex.noise.perlin()
    ///     >>> far = m.render(64, 64, offset=(1e7, 1e7), scale=4.0)
    ///     >>> far.dtype, far.shape
    ///     (dtype('float32'), (64, 64))
    #[pyo3(signature = (width, height, offset = (0.0, 0.0), scale = 1.0, z = 0.0, filter = true, device = "cpu"))]
    #[allow(
        clippy::too_many_arguments,
        reason = "the Python signature's keyword arguments"
    )]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: i64,
        height: i64,
        offset: (f64, f64),
        scale: f64,
        z: f64,
        filter: bool,
        device: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (w, h) = (side("width", width)?, side("height", height)?);
        let window = Window::new(w, h)
            .at([offset.0, offset.1], scale)
            .filtered(if filter { Filter::Pixel } else { Filter::Off });
        window.validate().map_err(value_error)?;
        let pixels = match device {
            "cpu" => {
                let eval = self.evaluator(z)?;
                render_window(py, &eval, &window)?
            }
            "gpu" => self.render_gpu(py, &window, z)?,
            other => {
                return Err(value_error(format!(
                    "device = {other:?} is not one of \"cpu\", \"gpu\""
                )));
            }
        };
        shaped(py, pixels, &[h, w], self.model.output_channels())
    }

    /// Evaluates the model at arbitrary positions: ``points`` is a C-contiguous float array
    /// of shape ``(N, 2)`` (x, y in model pixels) or ``(N, 3)`` (x, y, z for 3D models; 2D
    /// models ignore z). Returns float32 values of shape ``(N,)``, or ``(N, 3)`` in colour:
    /// the same bits as a render whose pixel lies at each point.
    ///
    /// Example::
    ///
    ///     >>> import numpy as np
    ///     >>> m = spectex.noise.perlin()
    ///     >>> v = m.sample(np.array([[3.0, 5.0], [10.0, 2.0]]))
    ///     >>> bool(v[0] == m.render(1, 1, offset=(3.0, 5.0))[0, 0])
    ///     True
    fn sample<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let points = points_array(points)?;
        let view = points.as_array();
        let (n, dims) = (view.shape()[0], view.shape()[1]);
        let channels = self.model.output_channels();
        let slice = points
            .as_slice()
            .map_err(|_| value_error("points must be C-contiguous"))?;
        if let Some(i) = slice.iter().position(|v| !v.is_finite()) {
            return Err(value_error(format!(
                "points[{}, {}] = {} is outside its valid range (finite, |v| ≤ 2^30)",
                i / dims,
                i % dims,
                slice[i]
            )));
        }
        let xy: Vec<[f64; 2]> = slice.chunks_exact(dims).map(|p| [p[0], p[1]]).collect();
        let values = if dims == 2 {
            sample_points(py, &self.evaluator(0.0)?, &xy)?
        } else {
            // Points grouped by their plane: one evaluator per distinct z.
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&a, &b| slice[a * 3 + 2].total_cmp(&slice[b * 3 + 2]));
            let mut values = vec![0.0f32; n * channels];
            let mut start = 0;
            while start < n {
                let z = slice[order[start] * 3 + 2];
                let end = start
                    + order[start..]
                        .iter()
                        .take_while(|&&i| slice[i * 3 + 2].to_bits() == z.to_bits())
                        .count();
                let group: Vec<[f64; 2]> = order[start..end].iter().map(|&i| xy[i]).collect();
                let got = sample_points(py, &self.evaluator(z)?, &group)?;
                for (k, &i) in order[start..end].iter().enumerate() {
                    values[i * channels..(i + 1) * channels]
                        .copy_from_slice(&got[k * channels..(k + 1) * channels]);
                }
                start = end;
            }
            values
        };
        if channels == 1 {
            Ok(PyArray1::from_vec(py, values).into_any())
        } else {
            let array =
                ndarray::Array2::from_shape_vec((n, channels), values).map_err(value_error)?;
            Ok(PyArray2::from_owned_array(py, array).into_any())
        }
    }

    /// The model as one WGSL module for a fragment shader (``fn spectex_sample(p: vec2<f32>)``),
    /// self-contained, its tables as constants; ``z`` is the plane of a 3D model. Needs the
    /// ``gpu`` build feature, on by default (``spectex.GPU`` says whether this build has it).
    ///
    /// Example::
    ///
    ///     >>> m = spectex.noise.perlin()
    ///     >>> "fn spectex_sample" in m.export_wgsl() if spectex.GPU else True
    ///     True
    #[pyo3(signature = (z = 0.0))]
    fn export_wgsl(&self, z: f64) -> PyResult<String> {
        self.export(z)
    }

    fn __repr__(&self) -> String {
        let period = self
            .period
            .map(|p| format!(", period={p}"))
            .unwrap_or_default();
        let fit = self
            .fit
            .map(|f| format!(", fit={:?}", format!("{f:?}").to_lowercase()))
            .unwrap_or_default();
        format!(
            "spectex.Model(kind={:?}, channels={}{period}{fit})",
            self.model.kind(),
            self.model.output_channels()
        )
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyModel>()
            .map(|o| {
                let o = o.get();
                o.model == self.model && o.period == self.period
            })
            .unwrap_or(false)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (String,))> {
        let from_json = slf.get_type().getattr("from_json")?;
        Ok((from_json, (slf.get().to_json()?,)))
    }
}

impl PyModel {
    fn parse(text: &str) -> PyResult<Self> {
        let contents = spectex_model::from_json_file(text).map_err(value_error)?;
        Ok(Self {
            model: contents.model,
            period: contents.period,
            fit: contents.fit,
        })
    }

    #[cfg(feature = "gpu")]
    fn render_gpu(&self, py: Python<'_>, window: &Window, z: f64) -> PyResult<Vec<f32>> {
        use spectex_gpu::{GpuError, GpuEvaluator};
        let (model, period) = (&self.model, self.period);
        py.detach(|| {
            crate::errors::guard(|| {
                let context = shared_gpu_context()?;
                let gpu = match period {
                    None => GpuEvaluator::new_at_z(&context, model, z),
                    Some(p) => GpuEvaluator::periodic_at_z(&context, model, z, p),
                }
                .map_err(value_error)?;
                gpu.render(window).map_err(|e| {
                    if matches!(e, GpuError::DeviceLost(_)) {
                        forget_gpu_context();
                    }
                    value_error(e)
                })
            })
        })
    }

    #[cfg(not(feature = "gpu"))]
    fn render_gpu(&self, _py: Python<'_>, _window: &Window, _z: f64) -> PyResult<Vec<f32>> {
        Err(pyo3::exceptions::PyRuntimeError::new_err(
            "device=\"gpu\" needs spectex built with its gpu feature (on by default; this build \
             was made with --no-default-features): pip install ./crates/spectex-py",
        ))
    }

    #[cfg(feature = "gpu")]
    fn export(&self, z: f64) -> PyResult<String> {
        use spectex_gpu::export::{ExportOptions, TableStorage, export};
        export(
            &self.model,
            &ExportOptions {
                z,
                tables: TableStorage::Constants,
            },
        )
        .map(|e| e.wgsl)
        .map_err(value_error)
    }

    #[cfg(not(feature = "gpu"))]
    fn export(&self, _z: f64) -> PyResult<String> {
        Err(pyo3::exceptions::PyRuntimeError::new_err(
            "export_wgsl needs spectex built with its gpu feature (the WGSL exporter is part of \
             spectex-gpu; on by default, this build was made with --no-default-features): \
             pip install ./crates/spectex-py",
        ))
    }
}

/// `pixels` (row-major, `channels` interleaved) as a numpy array of shape `dims` (+ channels
/// when more than one), without copying: the array owns the vector.
pub(crate) fn shaped<'py>(
    py: Python<'py>,
    pixels: Vec<f32>,
    dims: &[usize; 2],
    channels: usize,
) -> PyResult<Bound<'py, PyAny>> {
    if channels == 1 {
        let array =
            ndarray::Array2::from_shape_vec((dims[0], dims[1]), pixels).map_err(value_error)?;
        Ok(PyArray2::from_owned_array(py, array).into_any())
    } else {
        let array = ndarray::Array3::from_shape_vec((dims[0], dims[1], channels), pixels)
            .map_err(value_error)?;
        Ok(PyArray3::from_owned_array(py, array).into_any())
    }
}

/// `points` as a C-contiguous float64 array of shape `(N, 2)` or `(N, 3)`.
fn points_array<'py>(points: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    let array = points
        .cast::<numpy::PyUntypedArray>()
        .map_err(|_| type_error("points must be a numpy array of shape (N, 2) or (N, 3)"))?;
    let shape = array.shape().to_vec();
    if shape.len() != 2 || !(shape[1] == 2 || shape[1] == 3) {
        return Err(value_error(format!(
            "points has shape {shape:?}; it must be (N, 2) or (N, 3)"
        )));
    }
    if !array.is_c_contiguous() {
        return Err(value_error(
            "points is not C-contiguous; pass numpy.ascontiguousarray(points)",
        ));
    }
    let typed = points
        .extract::<PyReadonlyArrayDyn<'py, f64>>()
        .map_err(|_| {
            type_error(format!(
                "points has dtype {}; it must be float64 (points.astype(numpy.float64))",
                array.dtype()
            ))
        })?;
    Ok(typed)
}

/// The GPU context every `device="gpu"` render shares, opened by the first one. Each render
/// opened its own before: a device, and the kind's pipelines compiled anew (the context keeps
/// them), about 140 ms of a 256² Perlin render's 150 ms on lavapipe, on every call.
#[cfg(feature = "gpu")]
static GPU_CONTEXT: std::sync::Mutex<Option<std::sync::Arc<spectex_gpu::GpuContext>>> =
    std::sync::Mutex::new(None);

/// The shared context ([`GPU_CONTEXT`]), opened where there is none or its device was lost.
#[cfg(feature = "gpu")]
fn shared_gpu_context() -> PyResult<std::sync::Arc<spectex_gpu::GpuContext>> {
    let mut slot = GPU_CONTEXT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(context) = slot.as_ref().filter(|c| !c.is_lost()) {
        return Ok(std::sync::Arc::clone(context));
    }
    let context =
        std::sync::Arc::new(spectex_gpu::GpuContext::new().map_err(|e| {
            pyo3::exceptions::PyRuntimeError::new_err(format!("device=\"gpu\": {e}"))
        })?);
    *slot = Some(std::sync::Arc::clone(&context));
    Ok(context)
}

/// Drops the shared context (after its device was lost), so the next render opens another.
#[cfg(feature = "gpu")]
fn forget_gpu_context() {
    *GPU_CONTEXT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner) = None;
}
