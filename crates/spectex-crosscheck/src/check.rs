//! The cross-check of one model: renders each window on both evaluators and judges it by the
//! criterion of the model's kind ([`CheckKind`]), writing a failure report for every window
//! that does not pass.

use spectex_cpu::{Evaluator, Window};
use spectex_gpu::{GpuContext, GpuEvaluator};
use spectex_model::{Model, Period};

use crate::compare::{
    CaseWindow, Outcome, Verdict, compare, expected_failure, judge, judge_by_reasons, plane,
};
use crate::error::CrosscheckError;
use crate::report::write_failure_report;
use crate::tolerance::{CheckKind, check_kind};

/// Renders `model` on both evaluators for each window, on the plane its kind is checked on
/// ([`CheckKind::check_plane`]), and judges the differences: see [`check_model_at_z`].
///
/// # Errors
/// As [`check_model_at_z`].
pub fn check_model(
    context: &GpuContext,
    case: &str,
    model: &Model,
    windows: &[CaseWindow],
) -> Result<Vec<(CaseWindow, Outcome)>, CrosscheckError> {
    check_model_at_z(
        context,
        case,
        model,
        windows,
        check_kind(model).check_plane(),
    )
}

/// Renders `model` (and its kind's [`CheckKind::companions`]) on both evaluators for each
/// window, on the plane `z` (pixels; 2D models ignore it), and judges the differences by its
/// kind's criterion: its [`CheckKind::own_verdict`] where it has one, else each output
/// component's errors against its tolerance ([`CheckKind::tolerances`]). One outcome per window
/// and component, in that order (a colour texture has three); a failure report
/// ([`write_failure_report`]) for every one that does not pass.
///
/// # Errors
/// An evaluator refusing the model or a window, a device failure, a model without a derived
/// tolerance, or a report that could not be written.
pub fn check_model_at_z(
    context: &GpuContext,
    case: &str,
    model: &Model,
    windows: &[CaseWindow],
    z: f64,
) -> Result<Vec<(CaseWindow, Outcome)>, CrosscheckError> {
    check_model_with_period(context, case, model, windows, z, None)
}

/// [`check_model_at_z`] of `model` made exactly periodic with `period` when given
/// (`spectex_cpu::Evaluator::periodic` against `spectex_gpu::GpuEvaluator::periodic_at_z`),
/// judged by the kind's own tolerances: a periodic model evaluates the plain one's formulas at
/// positions reduced modulo the period, so the same derivations hold.
///
/// # Errors
/// As [`check_model_at_z`], or a period the model or the device path refuses.
pub fn check_model_with_period(
    context: &GpuContext,
    case: &str,
    model: &Model,
    windows: &[CaseWindow],
    z: f64,
    period: Option<Period>,
) -> Result<Vec<(CaseWindow, Outcome)>, CrosscheckError> {
    let kind: &dyn CheckKind = check_kind(model);
    let tolerances = kind
        .tolerances()
        .ok_or(CrosscheckError::Unsupported { kind: model.kind() })?;
    let cpu = Evaluator::with_period(model, z, period)?;
    let gpu = match period {
        None => GpuEvaluator::new_at_z(context, model, z)?,
        Some(p) => GpuEvaluator::periodic_at_z(context, model, z, p)?,
    };
    let channels = cpu.output_channels();
    if gpu.output_channels() != channels || tolerances.len() != channels {
        return Err(CrosscheckError::Channels {
            cpu: channels,
            gpu: gpu.output_channels(),
            tolerances: tolerances.len(),
        });
    }
    let mut pairs = vec![(cpu, gpu)];
    // Companions with the model's period: a combination's verdict composes its operands'
    // renders, which must be the ones it evaluated.
    for companion in kind.companions() {
        pairs.push((
            Evaluator::with_period(&companion, z, period)?,
            match period {
                None => GpuEvaluator::new_at_z(context, &companion, z)?,
                Some(p) => GpuEvaluator::periodic_at_z(context, &companion, z, p)?,
            },
        ));
    }
    let adapter = context.adapter_name();
    let expected = expected_failure(case, &adapter);
    let mut outcomes = Vec::new();
    for &w in windows {
        // One window type for both evaluators (spectex_model::Window).
        let window = Window::new(w.width, w.height).at(w.offset, w.scale);
        let mut renders = Vec::with_capacity(pairs.len());
        for (cpu, gpu) in &pairs {
            renders.push((cpu.render(&window)?, gpu.render(&window)?));
        }
        let own_verdict = kind.own_verdict(&renders, window.footprint());
        let (a, b) = &renders[0];
        for (c, &tolerance) in tolerances.iter().enumerate() {
            let (comparison, name) = if channels == 1 {
                (
                    compare(w.width, w.height, a.clone(), b.clone()),
                    case.to_owned(),
                )
            } else {
                let mut comparison = compare(
                    w.width,
                    w.height,
                    plane(a, channels, c),
                    plane(b, channels, c),
                );
                comparison.channel = Some(c);
                (comparison, format!("{case}-c{c}"))
            };
            let outcome = match &own_verdict {
                Some(why) => judge_by_reasons(comparison, tolerance, why.clone(), expected),
                None => judge(comparison, tolerance, expected),
            };
            if !matches!(outcome.verdict, Verdict::Pass) {
                write_failure_report(&format!("{name}-{}", w.name), &adapter, &w, &outcome)?;
            }
            outcomes.push((w, outcome));
        }
    }
    Ok(outcomes)
}
