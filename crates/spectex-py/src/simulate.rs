//! `spectex.simulate`: the whole-grid simulations of `spectex-simulate` (Gray–Scott,
//! Swift–Hohenberg, Life-like, elementary and cyclic automata) run with the GIL released,
//! Ctrl-C checked between chunks of steps, the final state as a numpy array.

use numpy::PyArray2;
use pyo3::prelude::*;
use spectex_model::simulation::{
    Cyclic, Elementary, GrayScott, GrayScottPreset, LifeLike, Simulation, SimulationSpec,
    SwiftHohenberg, spec_from_json, spec_to_json,
};
use spectex_simulate::Simulator;

use crate::errors::{guard, value_error};

/// Side of the default grid (the `spectex simulate` command's 256 × 256).
const DEFAULT_SIDE: u32 = 256;

/// Steps run between two looks for Ctrl-C.
const STEPS_PER_CHECK: u64 = 64;

/// The spec file text of simulation `name` (`gray_scott`, `swift_hohenberg`, `life`,
/// `elementary`, `cyclic`) at its defaults: the model crate's presets and `DEFAULT_STEPS`,
/// `preset` naming a Gray–Scott preset (`mazes` unless given, as `spectex simulate`).
#[pyfunction]
#[pyo3(signature = (name, preset = None))]
pub(crate) fn simulation_defaults(name: &str, preset: Option<&str>) -> PyResult<String> {
    let (steps, simulation) = match name {
        "gray_scott" => {
            let preset = preset.unwrap_or("mazes");
            let p = GrayScottPreset::ALL
                .iter()
                .find(|(n, _)| *n == preset)
                .map(|(_, p)| *p)
                .ok_or_else(|| {
                    value_error(format!(
                        "preset = {preset:?} is not one of {}",
                        GrayScottPreset::ALL.map(|(n, _)| n).join(", ")
                    ))
                })?;
            let mut gs = GrayScott::preset(p);
            // `spectex simulate`'s density of patches: one per 32² pixels, at least one.
            gs.patches = (DEFAULT_SIDE * DEFAULT_SIDE / 1024).max(1);
            (GrayScott::DEFAULT_STEPS, Simulation::GrayScott(gs))
        }
        "swift_hohenberg" => (
            SwiftHohenberg::DEFAULT_STEPS,
            Simulation::SwiftHohenberg(SwiftHohenberg::STRIPES),
        ),
        "life" => (
            LifeLike::DEFAULT_STEPS,
            Simulation::Life(LifeLike::conway()),
        ),
        "elementary" => (0, Simulation::Elementary(Elementary::RULE_30)),
        "cyclic" => (Cyclic::DEFAULT_STEPS, Simulation::Cyclic(Cyclic::SPIRALS)),
        other => {
            return Err(value_error(format!(
                "no simulation {other:?}; simulations: gray_scott, swift_hohenberg, life, \
                 elementary, cyclic"
            )));
        }
    };
    let spec = SimulationSpec::new(
        DEFAULT_SIDE,
        DEFAULT_SIDE,
        steps,
        spectex_model::DEFAULT_SEED,
        simulation,
    );
    spec_to_json(&spec).map_err(value_error)
}

/// Runs the simulation of the spec file text `spec_json` and returns its grey image,
/// float32 of shape `(height, width)` (Gray–Scott: u; automata: the states' grey levels).
#[pyfunction]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    spec_json: &str,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let spec = spec_from_json(spec_json).map_err(value_error)?;
    let mut sim = Simulator::new(&spec).map_err(value_error)?;
    let total = Simulator::total_steps(&spec);
    let mut done = 0;
    while done < total {
        let chunk = STEPS_PER_CHECK.min(total - done);
        py.detach(|| {
            guard(|| {
                sim.run(chunk, &mut |_| {});
                Ok(())
            })
        })?;
        done += chunk;
        py.check_signals()?;
    }
    let grey = sim.grey();
    let array = ndarray::Array2::from_shape_vec((spec.height as usize, spec.width as usize), grey)
        .map_err(value_error)?;
    Ok(PyArray2::from_owned_array(py, array))
}
