//! spectex for Python (`import spectex`): the native module `spectex._spectex`, a thin layer
//! of pyo3 over the library crates — numpy arrays in, numpy arrays out.
//!
//! Nothing here computes a texture: models are `spectex-model`'s, renders `spectex-cpu`'s
//! (`spectex-gpu`'s with the `gpu` feature), fits `spectex-sampling`'s, analyses
//! `spectex-spectrum`'s and simulations `spectex-simulate`'s. This crate converts arrays,
//! releases the GIL around the work, turns every error into a `ValueError` or `TypeError`
//! carrying the library's message, and catches panics so that none reaches the interpreter.
//! The Python package around it (`python/spectex/`) adds the builders' signatures, the type
//! stubs and the docstrings' examples.

// pyo3's `#[pymodule]`, `#[pyclass]` and `#[pymethods]` expand to the `unsafe` FFI glue that
// registers functions with the interpreter; this crate writes no `unsafe` of its own.
#![allow(
    unsafe_code,
    reason = "pyo3's macros expand to unsafe FFI registration code"
)]

mod builders;
mod defaults;
mod errors;
mod image_in;
mod model;
mod render;
mod simulate;
mod spectra;

use pyo3::prelude::*;

/// The native module: `spectex/__init__.py` re-exports it with the pure-Python parts.
#[pymodule]
fn _spectex(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<model::PyModel>()?;
    m.add_function(wrap_pyfunction!(spectra::fit, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::fit_tiling, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::rpn, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(builders::default_model, m)?)?;
    m.add_function(wrap_pyfunction!(builders::builder_names, m)?)?;
    m.add_function(wrap_pyfunction!(builders::combine, m)?)?;
    m.add_function(wrap_pyfunction!(builders::warp, m)?)?;
    m.add_function(wrap_pyfunction!(builders::target_names, m)?)?;
    m.add_function(wrap_pyfunction!(builders::target_default, m)?)?;
    m.add_function(wrap_pyfunction!(builders::lrp_from_target, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulation_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(render::bench_rust_render, m)?)?;
    m.add("GPU", cfg!(feature = "gpu"))?;
    m.add("KIND_NAMES", spectex_model::KIND_NAMES.to_vec())?;
    Ok(())
}
