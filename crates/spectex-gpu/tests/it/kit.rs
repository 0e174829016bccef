//! The test kit (`spectex-testkit`, without its CPU parts) on the GPU evaluator: generated
//! models of every kind through validation, the packer and a render (never a panic, a hang, an
//! untyped error or a non-finite value), and the invariance harness — tiles, far offset,
//! reseeding — over every `testdata/models/*.json`, one line per model; and the kit's models at
//! each limit, rendered near, far and minified. Skips loudly without an adapter unless
//! `SPECTEX_REQUIRE_GPU=1`.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stdout,
    reason = "the campaign summary and per-model lines are the tests' report"
)]

use crate::common;

use std::sync::Arc;
use std::time::Instant;

use spectex_gpu::{GpuContext, GpuError, GpuEvaluator, GpuWindow};
use spectex_model::{MAX_POSITION, Model};
use spectex_testkit::cases::{ModelCase, describe, model_cases};
use spectex_testkit::fuzz::{Observation, Settings, Target, run};
use spectex_testkit::invariance::{Backend, Plan, Prepared, check, testdata_cases};
use spectex_testkit::limits::limit_cases;

/// Cases CI runs (each builds a pipeline on lavapipe: about 20 ms).
const CI_CASES: u32 = 120;

/// The GPU evaluator as the harness's [`Backend`]: renders through [`GpuEvaluator::render`].
struct GpuBackend(Arc<GpuContext>);

struct GpuPrepared(GpuEvaluator);

impl Prepared for GpuPrepared {
    fn channels(&self) -> usize {
        self.0.output_channels()
    }

    fn render(&self, window: &GpuWindow) -> Result<Vec<f32>, String> {
        self.0.render(window).map_err(|e| e.to_string())
    }
}

impl Backend for GpuBackend {
    fn name(&self) -> String {
        format!("gpu {}", self.0.adapter_name())
    }

    fn prepare(&self, model: &Model, z: f64) -> Result<Box<dyn Prepared>, String> {
        GpuEvaluator::new_at_z(&self.0, model, z)
            .map(|e| Box::new(GpuPrepared(e)) as Box<dyn Prepared>)
            .map_err(|e| e.to_string())
    }
}

/// Validation, the packer and a render of one case: what validation accepts is packed (or
/// refused as unsupported or past a device limit, typed), a valid window renders finite values
/// and an invalid one is a typed window error.
fn gpu_target(context: Arc<GpuContext>) -> Target<ModelCase> {
    Arc::new(move |case: &ModelCase| {
        let kind = case.model.kind();
        let mut seen = Observation {
            kind: Some(kind),
            ..Observation::default()
        };
        if case.model.validate().is_err() {
            return match GpuEvaluator::new_at_z(&context, &case.model, case.z) {
                Err(GpuError::Model(_)) => Ok(seen),
                Err(e) => Err(format!("an invalid model gave another error: {e}")),
                Ok(_) => Err("the GPU evaluator accepted an invalid model".into()),
            };
        }
        seen.accepted = true;
        let plane_valid = case.z.is_finite() && case.z.abs() <= MAX_POSITION;
        let started = Instant::now();
        let evaluator = match GpuEvaluator::new_at_z(&context, &case.model, case.z) {
            Ok(e) if plane_valid => e,
            Ok(_) => return Err(format!("accepted z = {}", case.z)),
            Err(GpuError::Window { parameter: "z", .. }) if !plane_valid => return Ok(seen),
            // Typed refusals of valid models: a feature the GPU path lacks, or tables past
            // what one buffer holds.
            Err(GpuError::Unsupported { .. } | GpuError::LimitsExceeded { .. }) => {
                return Ok(seen);
            }
            Err(e) => return Err(format!("a valid model could not be prepared: {e}")),
        };
        seen.build_seconds = started.elapsed().as_secs_f64();
        let window_valid = case.window.validate().is_ok()
            && spectex_model::warp::check_window(&case.model, &case.window).is_ok();
        let started = Instant::now();
        match (evaluator.render(&case.window), window_valid) {
            (Ok(values), true) => {
                let pixels = case.window.width * case.window.height;
                if values.len() != pixels * evaluator.output_channels() {
                    return Err(format!("{} values for {pixels} pixels", values.len()));
                }
                if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                    return Err(format!("value {i} is {}", values[i]));
                }
                seen.pixels = pixels;
                seen.render_seconds = started.elapsed().as_secs_f64();
                Ok(seen)
            }
            // Device limits may refuse what the CPU renders (a per-tile table past a buffer).
            (Err(GpuError::LimitsExceeded { .. }), true) => Ok(seen),
            (Err(e), true) => Err(format!("a valid window was refused: {e}")),
            (Ok(_), false) => Err("an invalid window was rendered".into()),
            (Err(GpuError::Window { .. }), false) => Ok(seen),
            (Err(e), false) => Err(format!("an invalid window gave another error: {e}")),
        }
    })
}

#[test]
fn fuzz_generated_models_on_the_gpu() {
    let Some(context) = common::gpu_or_skip("fuzz_generated_models_on_the_gpu") else {
        return;
    };
    let report = run(
        "models-gpu",
        &Settings::from_env(CI_CASES),
        &model_cases(),
        describe,
        &gpu_target(Arc::new(context)),
    );
    println!("{}", report.summary());
    assert!(report.findings.is_empty(), "{}", report.summary());
}

#[test]
fn every_testdata_model_passes_the_invariance_checks_on_the_gpu() {
    let Some(context) = common::gpu_or_skip("invariance on the GPU") else {
        return;
    };
    let backend = GpuBackend(Arc::new(context));
    let plan = Plan::light();
    let mut failed = Vec::new();
    for case in testdata_cases() {
        let report = check(&case, &backend, &plan);
        println!("{}", report.line());
        if !report.passed() {
            failed.push(report.line());
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// Every valid limit case of the kit packs (or is refused as unsupported or past a device
/// limit, typed) and renders finite values at a pixel, a far patch and a minified row whose
/// pixels lie 10⁶ pixels apart (a host table spanning the row's extent would not fit).
#[test]
fn models_at_each_limit_render_on_the_gpu() {
    let Some(context) = common::gpu_or_skip("limits on the GPU") else {
        return;
    };
    // Not the full warp tree at the depth limit (6561 leaves): the GPU builds one evaluator,
    // with its pipeline and buffers, per nested model — more than 3 GB and minutes on lavapipe
    // (bounded by the depth limit, but past a test's budget; reported to the GPU layer).
    let cases = limit_cases()
        .into_iter()
        .filter(|c| c.valid && !c.name.starts_with("warp: a full tree"));
    for case in cases {
        let started = Instant::now();
        let evaluator = match GpuEvaluator::new_at_z(&context, &case.model, 37.3) {
            Ok(e) => e,
            Err(e @ (GpuError::Unsupported { .. } | GpuError::LimitsExceeded { .. })) => {
                println!("limits on the gpu: {:<50} refused: {e}", case.name);
                continue;
            }
            Err(e) => panic!("{}: {e}", case.name),
        };
        for window in [
            GpuWindow::new(1, 1),
            GpuWindow::new(2, 2).at([-1.0e7 + 0.5, 1.0e7 - 0.25], 0.37),
            GpuWindow::new(8, 2).at([-4.0e6, 3.0e6], 1e6),
        ] {
            match evaluator.render(&window) {
                Ok(values) => assert!(
                    values.iter().all(|v| v.is_finite()),
                    "{} in {window:?}: {values:?}",
                    case.name
                ),
                Err(e @ GpuError::LimitsExceeded { .. }) => {
                    println!(
                        "limits on the gpu: {:<50} {window:?} refused: {e}",
                        case.name
                    );
                }
                Err(e) => panic!("{} in {window:?}: {e}", case.name),
            }
        }
        println!(
            "limits on the gpu: {:<50} build + 21 pixels in {:.3} s",
            case.name,
            started.elapsed().as_secs_f64()
        );
    }
}
