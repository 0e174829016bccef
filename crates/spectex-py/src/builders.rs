//! The builders' native side: each builder's default model (from [`crate::defaults`]), from
//! which `spectex/noise.py` generates the Python functions and their signatures, and the
//! models made of other models (`spectex.warp`, `spectex.combine`).

use pyo3::prelude::*;
use spectex_model::combine::CombineOp;
use spectex_model::{Combine, Model, Warp};

use crate::defaults::{BASES, BUILDERS, default_model as default_of};
use crate::errors::{type_error, value_error};
use crate::model::PyModel;

/// `[(name, description)]` of every builder, and the bases a fractal sum takes.
#[pyfunction]
pub(crate) fn builder_names() -> (Vec<(&'static str, &'static str)>, Vec<&'static str>) {
    (BUILDERS.to_vec(), BASES.to_vec())
}

/// The model file text of builder `name`'s default model (`variant`: see
/// [`crate::defaults::default_model`]).
#[pyfunction]
#[pyo3(signature = (name, variant = None))]
pub(crate) fn default_model(name: &str, variant: Option<&str>) -> PyResult<String> {
    let model = default_of(name, variant)
        .ok_or_else(|| {
            value_error(format!(
                "no builder {name:?}{}; builders: {}; bases: {}",
                variant.map(|v| format!(" with {v:?}")).unwrap_or_default(),
                BUILDERS.iter().map(|b| b.0).collect::<Vec<_>>().join(", "),
                BASES.join(", ")
            ))
        })?
        .map_err(value_error)?;
    spectex_model::to_json(&model).map_err(value_error)
}

/// `spectex.warp`: `base` evaluated at `p + strength·(x(p), y(p))` for the models `by` (x) and
/// `by_y` (y; `by` reseeded by one unless given), through `spectex_model::Warp`'s builder
/// (its defaults: the built-in fBms, strength, seed).
#[pyfunction]
#[pyo3(signature = (base = None, by = None, by_y = None, strength = None, seed = None))]
pub(crate) fn warp(
    base: Option<PyRef<'_, PyModel>>,
    by: Option<PyRef<'_, PyModel>>,
    by_y: Option<PyRef<'_, PyModel>>,
    strength: Option<f32>,
    seed: Option<i64>,
) -> PyResult<PyModel> {
    let mut builder = Warp::builder();
    if let Some(m) = base {
        builder = builder.base(m.model.clone());
    }
    if let Some(m) = by {
        builder = builder.by(m.model.clone());
    }
    if let Some(m) = by_y {
        builder = builder.by_y(m.model.clone());
    }
    if let Some(s) = strength {
        builder = builder.strength(s);
    }
    if let Some(s) = seed {
        let s = u32::try_from(s).map_err(|_| {
            value_error(format!(
                "warp.seed = {s} is outside its valid range 0 to 2^32 - 1"
            ))
        })?;
        builder = builder.seed(s);
    }
    let warp = builder.build().map_err(value_error)?;
    Ok(PyModel::plain(warp.into()))
}

/// `spectex.combine`: the operation `op_json` (a `CombineOp` as JSON: `"add"` or
/// `{"smoothstep": {"edges": [0.4, 0.6]}}`) of `operands`, validated.
#[pyfunction]
pub(crate) fn combine(op_json: &str, operands: Vec<PyRef<'_, PyModel>>) -> PyResult<PyModel> {
    let op: CombineOp = serde_json::from_str(op_json)
        .map_err(|e| value_error(format!("combine op {op_json}: {e}")))?;
    if operands.is_empty() {
        return Err(type_error("combine needs at least one model"));
    }
    let combine = Combine {
        op,
        operands: operands.iter().map(|m| m.model.clone()).collect(),
    };
    let model = Model::from(combine);
    model.validate().map_err(value_error)?;
    Ok(PyModel::plain(model))
}
