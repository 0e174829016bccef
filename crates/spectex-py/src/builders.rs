//! The builders' native side: each builder's default model (from [`crate::defaults`]), from
//! which `spectex/noise.py` generates the Python functions and their signatures; LRP noise of
//! a spectral target (`spectex.noise.ring`, …: the target's defaults and the fit); and the
//! models made of other models (`spectex.warp`, `spectex.combine`).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use spectex_model::combine::CombineOp;
use spectex_model::{Combine, Model, SpectralTarget, Warp};
use spectex_sampling::LrpFromTarget;

use crate::defaults::{
    BASES, BUILDERS, TARGETS, default_model as default_of, default_target, target_parameters,
};
use crate::errors::{guard, type_error, value_error};
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

/// `[(name, description)]` of the spectral targets an LRP noise is fitted to.
#[pyfunction]
pub(crate) fn target_names() -> Vec<(&'static str, &'static str)> {
    TARGETS.to_vec()
}

/// The defaults of target builder `name`: a dict of `variant` (the `SpectralTarget` variant's
/// name in a model file), `target` (its parameters in the order they are defined, an absent
/// optional one, the fractal's `spread`, as `None`) and `options` (`budget`, `strata`, `seed`,
/// `std_dev`, `mean`: `LrpFromTarget`'s defaults for that target; a fractal has its own budget
/// and strata). Numbers are the shortest decimals of the f32 values (0.1, not the f64
/// expansion 0.10000000149011612), which read back as the same f32.
#[pyfunction]
pub(crate) fn target_default<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
    let target = default_target(name).ok_or_else(|| {
        value_error(format!(
            "no spectral target {name:?}; targets: {}",
            TARGETS.iter().map(|t| t.0).collect::<Vec<_>>().join(", ")
        ))
    })?;
    let options = LrpFromTarget::new(target.clone()).options();
    let (variant, parameters) = target_parameters(&target);
    let fields = PyDict::new(py);
    for (field, value) in parameters {
        fields.set_item(field, value.map(shortest))?;
    }
    let fit = PyDict::new(py);
    fit.set_item("budget", options.budget)?;
    fit.set_item("strata", options.strata)?;
    fit.set_item("seed", LrpFromTarget::DEFAULT_SEED)?;
    fit.set_item("std_dev", shortest(LrpFromTarget::DEFAULT_STD_DEV))?;
    fit.set_item("mean", shortest(LrpFromTarget::DEFAULT_MEAN))?;
    let defaults = PyDict::new(py);
    defaults.set_item("variant", variant)?;
    defaults.set_item("target", fields)?;
    defaults.set_item("options", fit)?;
    Ok(defaults)
}

/// `v` as the f64 of its shortest decimal (what `to_json` writes for it), not its expansion.
fn shortest(v: f32) -> f64 {
    v.to_string().parse().unwrap_or(f64::NAN)
}

/// LRP noise fitted to the spectral target `target_json` (a `SpectralTarget` as JSON, such as
/// `{"ring": {"radius": 0.0625, "width": 0.005}}`) by `spectex_sampling::LrpFromTarget`, the
/// options not given at its defaults; the GIL is released while it fits.
#[pyfunction]
#[pyo3(signature = (target_json, budget = None, strata = None, seed = None, std_dev = None, mean = None))]
pub(crate) fn lrp_from_target(
    py: Python<'_>,
    target_json: &str,
    budget: Option<i64>,
    strata: Option<i64>,
    seed: Option<i64>,
    std_dev: Option<f32>,
    mean: Option<f32>,
) -> PyResult<PyModel> {
    let whole = |name: &str, v: i64, range: &str| {
        u32::try_from(v)
            .map_err(|_| value_error(format!("{name} = {v} is outside its valid range {range}")))
    };
    let target: SpectralTarget = serde_json::from_str(target_json)
        .map_err(|e| value_error(format!("spectral target {target_json}: {e}")))?;
    let mut builder = LrpFromTarget::new(target);
    if let Some(b) = budget {
        builder = builder.budget(whole("budget", b, "1..=1024 cosines")?);
    }
    if let Some(s) = strata {
        builder = builder.strata(whole("strata", s, "1..=64")?);
    }
    if let Some(s) = seed {
        builder = builder.seed(whole("seed", s, "0 to 2^32 - 1")?);
    }
    if let Some(s) = std_dev {
        builder = builder.std_dev(s);
    }
    if let Some(m) = mean {
        builder = builder.mean(m);
    }
    let noise = py.detach(|| guard(|| builder.build().map_err(value_error)))?;
    Ok(PyModel::plain(noise.into()))
}
