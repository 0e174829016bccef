//! The CPU side of the kit: the fuzz targets that run inputs through `spectex_model::from_json`
//! and `spectex_cpu::Evaluator`, the cost bound per kind that makes "bounded time per pixel"
//! checkable, and the CPU [`Backend`](crate::invariance::Backend) of the invariance harness.

use std::sync::{Arc, LazyLock};
use std::time::Instant;

use spectex_cpu::{CpuError, Evaluator};
use spectex_model::{MAX_POSITION, Model, ModelKind, Window};

use crate::cases::{ModelCase, check_file_round_trip};
use crate::fuzz::{Observation, Target};
use crate::invariance::{Backend, Prepared};

/// The largest [`Evaluator::cost_per_pixel`] a valid model of a kind can have, derived from the
/// limits `spectex-model` validates (each kind's `MAX_COST` comment gives the derivation). The
/// units are the kind's own (cosines, kernels, lattice or tile evaluations), each a bounded
/// amount of work, so a valid model renders in bounded time per pixel. Every kind implements it
/// in its module of [`crate::models`] (collected through `spectex_model::for_each_kind!`, so a
/// kind without one does not compile).
pub trait CostBound: ModelKind {
    /// The bound.
    const MAX_COST: f64;
}

/// Every kind's [`CostBound`], by name, in the order of `Model`'s variants.
pub static COST_BOUNDS: LazyLock<Vec<(&'static str, f64)>> = LazyLock::new(|| {
    let mut bounds = Vec::new();
    spectex_model::for_each_kind!(types: K => {
        bounds.push((<K as ModelKind>::NAME, <K as CostBound>::MAX_COST));
    });
    bounds
});

/// The cost bound of `kind` ([`COST_BOUNDS`]); `None` for a kind missing from the table.
#[must_use]
pub fn cost_bound(kind: &str) -> Option<f64> {
    COST_BOUNDS
        .iter()
        .find(|(name, _)| *name == kind)
        .map(|(_, bound)| *bound)
}

/// Seconds a render call may take whatever its size: starting rayon's pool, allocating, and a
/// loaded 2-core machine's scheduling.
pub const CALL_ALLOWANCE_SECONDS: f64 = 1.0;
/// Seconds per pixel not counted by the cost (locating the pixel, a warp's one-pixel window per
/// base evaluation, wavelet noise's row tables).
pub const PIXEL_ALLOWANCE_SECONDS: f64 = 2e-3;
/// Seconds per unit of cost: measured units take 1 to 20 ns (a cosine ≈ 1 ns vectorised, a
/// Worley cell with its points ≈ 20 ns), so this is 50 to 1000 times generous. The limit is a
/// runaway detector — work out of proportion to the model — not a speed test.
pub const SECONDS_PER_COST_UNIT: f64 = 1e-6;

/// The longest a render of `pixels` pixels of cost `cost_per_pixel` may take.
#[must_use]
pub fn time_limit(pixels: usize, cost_per_pixel: f64) -> f64 {
    CALL_ALLOWANCE_SECONDS
        + pixels as f64 * (PIXEL_ALLOWANCE_SECONDS + cost_per_pixel * SECONDS_PER_COST_UNIT)
}

/// Builds `model`'s evaluator on the plane `z` and renders `window`, checking what must hold:
/// the evaluator accepts every model validation accepts (and refuses a bad `z` with a typed
/// error), its cost per pixel is within [`COST_BOUNDS`], a window is refused exactly when it is
/// invalid (a typed error), a render has one finite value per pixel and channel, and takes no
/// longer than [`time_limit`].
///
/// # Errors
/// The property that does not hold.
pub fn evaluate(model: &Model, window: &Window, z: f64) -> Result<Observation, String> {
    let kind = model.kind();
    let mut seen = Observation {
        kind: Some(kind),
        accepted: true,
        ..Observation::default()
    };
    let plane_valid = z.is_finite() && z.abs() <= MAX_POSITION;
    let started = Instant::now();
    let evaluator = match (Evaluator::new_at_z(model, z), plane_valid) {
        (Ok(e), true) => e,
        (Err(CpuError::Window { parameter: "z", .. }), false) => return Ok(seen),
        (Ok(_), false) => return Err(format!("Evaluator::new_at_z accepted z = {z}")),
        (Err(e), _) => {
            return Err(format!(
                "Evaluator::new_at_z refused a model that validation accepts (z = {z}): {e}"
            ));
        }
    };
    seen.build_seconds = started.elapsed().as_secs_f64();
    let cost = evaluator.cost_per_pixel();
    seen.cost_per_pixel = cost;
    let bound = cost_bound(kind).ok_or_else(|| format!("no cost bound for kind {kind}"))?;
    if !(cost.is_finite() && cost >= 0.0 && cost <= bound) {
        return Err(format!(
            "cost per pixel {cost} is outside [0, {bound:e}], the bound derived for {kind}"
        ));
    }
    if evaluator.output_channels() != model.output_channels() {
        return Err(format!(
            "the evaluator gives {} values per pixel, the model says {}",
            evaluator.output_channels(),
            model.output_channels()
        ));
    }
    let window_valid =
        window.validate().is_ok() && spectex_model::warp::check_window(model, window).is_ok();
    let started = Instant::now();
    let rendered = evaluator.render(window);
    let seconds = started.elapsed().as_secs_f64();
    match (rendered, window_valid) {
        (Ok(values), true) => {
            let pixels = window.width * window.height;
            let expected = pixels * evaluator.output_channels();
            if values.len() != expected {
                return Err(format!("{} values for {expected}", values.len()));
            }
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!("value {i} of the render is {}", values[i]));
            }
            let limit = time_limit(pixels, cost);
            if seconds > limit {
                return Err(format!(
                    "{pixels} pixels of cost {cost:.0} took {seconds:.2} s (limit {limit:.2} s)"
                ));
            }
            seen.pixels = pixels;
            seen.render_seconds = seconds;
            Ok(seen)
        }
        (Err(e), true) => Err(format!("render refused a valid window: {e}")),
        (Ok(_), false) => Err("render accepted an invalid window".into()),
        (Err(CpuError::Window { .. }), false) => Ok(seen),
        (Err(e), false) => Err(format!(
            "an invalid window gave an error that does not name a window parameter: {e}"
        )),
    }
}

/// The fuzz target for [`ModelCase`]s: validation and the file round trip
/// ([`check_file_round_trip`]), then, for valid models, [`evaluate`].
#[must_use]
pub fn model_target() -> Target<ModelCase> {
    Arc::new(|case: &ModelCase| {
        check_file_round_trip(&case.model)?;
        if case.model.validate().is_err() {
            return Ok(Observation {
                kind: Some(case.model.kind()),
                ..Observation::default()
            });
        }
        evaluate(&case.model, &case.window, case.z)
    })
}

/// Windows every accepted model text is rendered in: a few pixels near the origin and far away
/// at a fractional scale.
fn text_windows() -> [Window; 2] {
    [
        Window::new(4, 3).at([-3.5, 2.25], 1.0),
        Window::new(3, 2).at([1.0e7 + 0.5, -1.0e7], 0.37),
    ]
}

/// The fuzz target for model file texts: `from_json`; when it accepts, the model written back
/// by `to_json` reads back identically, and renders in [`text_windows`] on the plane
/// `z = 37.3` ([`evaluate`]).
#[must_use]
pub fn text_target() -> Target<String> {
    Arc::new(|text: &String| {
        let Ok(model) = spectex_model::from_json(text) else {
            return Ok(Observation::default());
        };
        check_file_round_trip(&model)?;
        let mut seen = Observation::default();
        for window in text_windows() {
            let o = evaluate(&model, &window, 37.3)?;
            seen.kind = o.kind;
            seen.accepted = true;
            seen.pixels += o.pixels;
            seen.render_seconds += o.render_seconds;
            seen.build_seconds = seen.build_seconds.max(o.build_seconds);
            seen.cost_per_pixel = o.cost_per_pixel;
        }
        Ok(seen)
    })
}

/// The CPU evaluator as a [`Backend`] of the invariance harness: renders through
/// [`Evaluator::render`], and on a rayon pool of a given size for the thread check.
#[derive(Debug, Clone, Copy, Default)]
pub struct CpuBackend;

struct CpuPrepared(Evaluator);

impl Prepared for CpuPrepared {
    fn channels(&self) -> usize {
        self.0.output_channels()
    }

    fn render(&self, window: &Window) -> Result<Vec<f32>, String> {
        self.0.render(window).map_err(|e| e.to_string())
    }

    fn render_on_threads(
        &self,
        window: &Window,
        threads: usize,
    ) -> Option<Result<Vec<f32>, String>> {
        let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool,
            Err(e) => return Some(Err(format!("no pool of {threads} threads: {e}"))),
        };
        Some(pool.install(|| self.render(window)))
    }
}

impl Backend for CpuBackend {
    fn name(&self) -> String {
        "cpu".into()
    }

    fn prepare(&self, model: &Model, z: f64) -> Result<Box<dyn Prepared>, String> {
        Evaluator::new_at_z(model, z)
            .map(|e| Box::new(CpuPrepared(e)) as Box<dyn Prepared>)
            .map_err(|e| e.to_string())
    }
}
