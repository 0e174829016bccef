//! Combinations: their tolerance and regularity composed from their operands'.
//!
//! Both evaluators apply the same f32 operation (`spectex_model::combine::CombineOp::apply`,
//! or its exact WGSL twin on the GPU) to operand values that differ by at most the operands' bounds, so
//! `|f̃(a) − f̃(a')| ≤ L·|a − a'| + 2ε`, with `L` the operation's Lipschitz constant over the
//! operands' range and `ε` its own f32 evaluation error (counted once per side). Operand
//! magnitudes come from their [`Regularity`]; an operation that needs one and an operand
//! without it (or without a bound) gives no tolerance.
//!
//! Where that composition has no bound — an operand judged by its own criterion, such as the
//! phase-based outputs of phasor noise in the phasor paper's crossed waves, or a threshold —
//! the combination is judged by composing verdicts instead ([`CheckKind::own_verdict`]): its
//! [`companions`](CheckKind::companions) are its operands (each followed by its own
//! companions), every operand must pass its own kind's criterion, and on each evaluator the
//! combination's value must be `CombineOp::apply` of that evaluator's operand values, bit for
//! bit (both evaluators compose exactly so: the CPU per row, the GPU in a pass of its own in
//! integer IEEE arithmetic, `exact.wgsl`, or on the host for a displaced combination). An operand
//! judged by the generic criterion is held to its max and mean bounds there (its spectral
//! bound needs the window's shape, which a verdict does not see; the operand's own
//! cross-check keeps it).

use spectex_model::Model;
use spectex_model::combine::{Combine, CombineOp, RampStop};

use super::{COS_ABS_ERROR, CheckKind, F32_UNIT_ROUNDOFF, Regularity, Tolerance, check_kind};

const U: f64 = F32_UNIT_ROUNDOFF;

/// What the composition needs of an operand: its bound on `|cpu − gpu|`, its largest `|v|`,
/// and how fast it changes (slope per pixel and jumps).
#[derive(Debug, Clone, Copy)]
struct Operand {
    tol: f64,
    mag: Option<f64>,
    slope: Option<f64>,
    jump: Option<f64>,
    cell: f64,
}

fn operand(m: &Model) -> Option<Operand> {
    operand_with(m, check_kind(m).value_bound()?)
}

/// An operand with `tol` standing for its bound: the scale of [`super::tolerance`] for an
/// operand judged by its own criterion, in the figure a composed verdict's report shows.
fn operand_with(m: &Model, tol: f64) -> Option<Operand> {
    let k = check_kind(m);
    let r = k.regularity();
    Some(Operand {
        tol,
        mag: r.map(|r| r.magnitude),
        slope: r.map(|r| r.slope),
        jump: r.map(|r| r.jump),
        cell: r.map_or(f64::INFINITY, |r| r.cell),
    })
}

/// The largest slope `|Δy/Δx|` of a piecewise-linear curve through `points`, and its largest
/// `|y|`.
fn piecewise(points: &[(f64, f64)]) -> (f64, f64) {
    let slope = points
        .windows(2)
        .map(|w| ((w[1].1 - w[0].1) / (w[1].0 - w[0].0)).abs())
        .fold(0.0, f64::max);
    let peak = points.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    (slope, peak)
}

fn histogram_points(domain: [f32; 2], table: &[f32]) -> Vec<(f64, f64)> {
    let n = (table.len() - 1) as f64;
    let (d0, d1) = (f64::from(domain[0]), f64::from(domain[1]));
    table
        .iter()
        .enumerate()
        .map(|(k, &v)| (d0 + (d1 - d0) * k as f64 / n, f64::from(v)))
        .collect()
}

fn ramp_points(stops: &[RampStop], c: usize) -> Vec<(f64, f64)> {
    stops
        .iter()
        .map(|s| (f64::from(s.at), f64::from(s.colour[c])))
        .collect()
}

/// For a one-operand operation `f` of an operand of magnitude `mag`: its Lipschitz constant,
/// its own evaluation error and its output magnitude, for channel `c`; `None` for a threshold
/// (discontinuous).
fn unary(op: &CombineOp, mag: Option<f64>, c: usize) -> Option<(f64, f64, f64)> {
    match op {
        CombineOp::Smoothstep { edges } => {
            let (e0, e1) = (f64::from(edges[0]), f64::from(edges[1]));
            if e1 <= e0 {
                return None;
            }
            // s = (v − e₀)/(e₁ − e₀): 2 roundings relative to (|v| + |e₀|)/(e₁ − e₀), then
            // s·s·(3 − 2s) (slope ≤ 1.5, 4 roundings of values ≤ 3).
            let x = (mag? + e0.abs()) / (e1 - e0);
            Some((1.5 / (e1 - e0), 1.5 * 2.0 * U * x + 12.0 * U, 1.0))
        }
        CombineOp::AbsFold {
            offset,
            step,
            folds,
        } => {
            let m = mag? + f64::from(*offset).abs() + f64::from(*folds) * f64::from(*step).abs();
            Some((1.0, (f64::from(*folds) + 1.0) * U * m, m))
        }
        CombineOp::SinFold { gain } => {
            let g = f64::from(*gain).abs();
            Some((
                std::f64::consts::TAU * g,
                std::f64::consts::TAU * U * g * mag? + COS_ABS_ERROR,
                1.0,
            ))
        }
        CombineOp::Histogram { domain, table } => {
            let (slope, peak) = piecewise(&histogram_points(*domain, table));
            // The knot coordinate x = (v − d₀)/(d₁ − d₀)·(N − 1): 3 roundings relative to its
            // largest value; the lerp's 3 roundings of values ≤ the peak.
            let span = f64::from(domain[1]) - f64::from(domain[0]);
            let n = (table.len() - 1) as f64;
            let x = (mag? + f64::from(domain[0]).abs()) / span * n;
            Some((slope, slope * span / n * 3.0 * U * x + 3.0 * U * peak, peak))
        }
        CombineOp::Ramp { stops } => {
            let points = ramp_points(stops, c);
            let (slope, peak) = piecewise(&points);
            // f = (v − at_a)/(at_b − at_a): 3 roundings relative to (|v| + |at_a|)/gap, times
            // the segment's step slope·gap: 3u·(|v| + |at|)·slope; the lerp's 3 roundings.
            let far = mag? + points.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
            Some((slope, 3.0 * U * far * slope + 3.0 * U * peak, peak))
        }
        _ => None,
    }
}

/// `(tolerance, magnitude)` of channel `c`.
fn compose(m: &Combine, c: usize) -> Option<(f64, Option<f64>)> {
    let ops: Vec<Operand> = m.operands.iter().map(operand).collect::<Option<_>>()?;
    compose_ops(m, &ops, c)
}

/// The per-channel bounds of the composition, or `None` where it has none and the combination
/// is judged by composing its operands' verdicts.
fn composed(m: &Combine) -> Option<Vec<Tolerance>> {
    (0..spectex_model::ModelKind::output_channels(m))
        .map(|c| compose(m, c).map(|(t, _)| Tolerance::from_max(t)))
        .collect()
}

/// The scale a composed verdict reports: the composition with each operand's reported
/// tolerance ([`super::tolerance`]) in place of a bound; where an operand has no magnitude
/// either, the sum of the operands' scales (infinite where one has none).
fn reported(m: &Combine) -> Vec<Tolerance> {
    let scales: Vec<f64> = m
        .operands
        .iter()
        .map(|o| super::tolerance(o).map_or(f64::INFINITY, |t| t.max_abs))
        .collect();
    let ops: Option<Vec<Operand>> = m
        .operands
        .iter()
        .zip(&scales)
        .map(|(o, &s)| operand_with(o, s))
        .collect();
    (0..spectex_model::ModelKind::output_channels(m))
        .map(|c| {
            let t = ops
                .as_deref()
                .and_then(|ops| compose_ops(m, ops, c))
                .map_or_else(|| scales.iter().sum(), |(t, _)| t);
            Tolerance::from_max(t)
        })
        .collect()
}

/// Why one operand's renders (its own, then its companions') fail its kind's criterion.
fn operand_reasons(
    index: usize,
    model: &Model,
    renders: &[(Vec<f32>, Vec<f32>)],
    footprint: Option<f64>,
) -> Vec<String> {
    let kind = check_kind(model);
    let why = kind.own_verdict(renders, footprint).unwrap_or_else(|| {
        let Some(tolerances) = kind.tolerances() else {
            return vec!["no derived tolerance".to_owned()];
        };
        let (cpu, gpu) = &renders[0];
        let channels = tolerances.len();
        let mut why = Vec::new();
        for (c, t) in tolerances.iter().enumerate() {
            let errors: Vec<f64> = cpu
                .iter()
                .zip(gpu)
                .skip(c)
                .step_by(channels)
                .map(|(a, b)| (f64::from(*a) - f64::from(*b)).abs())
                .collect();
            let max = errors.iter().copied().fold(0.0, f64::max);
            let mean = errors.iter().sum::<f64>() / errors.len().max(1) as f64;
            if errors.iter().any(|e| e.is_nan()) || max > t.max_abs {
                why.push(format!("channel {c}: max {max:.3e} > {:.3e}", t.max_abs));
            }
            if mean > t.mean_abs {
                why.push(format!("channel {c}: mean {mean:.3e} > {:.3e}", t.mean_abs));
            }
        }
        why
    });
    why.into_iter()
        .map(|w| format!("operand {index} ({}): {w}", model.kind()))
        .collect()
}

/// The pixels where `out` (one evaluator's render of the combination) is not `op` applied to
/// that evaluator's operand renders `operands`, bit for bit: at most a few are named.
fn composition_reasons(m: &Combine, side: &str, out: &[f32], operands: &[&[f32]]) -> Vec<String> {
    let channels = spectex_model::ModelKind::output_channels(m);
    let widths: Vec<usize> = m.operands.iter().map(Model::output_channels).collect();
    let mut pixel: Vec<&[f32]> = Vec::with_capacity(operands.len());
    let (mut wrong, mut first) = (0usize, None);
    for (p, o) in out.chunks_exact(channels).enumerate() {
        pixel.clear();
        pixel.extend(
            operands
                .iter()
                .zip(&widths)
                .map(|(v, &w)| &v[p * w..p * w + w]),
        );
        for (c, &v) in o.iter().enumerate() {
            let want = m.op.apply(&pixel, c);
            if v.to_bits() != want.to_bits() && !(v.is_nan() && want.is_nan()) {
                wrong += 1;
                first.get_or_insert((p, c, v, want));
            }
        }
    }
    first
        .map(|(p, c, v, want)| {
            format!(
                "{side}: {wrong} value(s) are not the operation of the operands, first pixel {p} \
                 channel {c}: {v:e} against {want:e}"
            )
        })
        .into_iter()
        .collect()
}

/// A judge of one operand for [`composed_verdict`]: its index, its model and its renders
/// (its own, then its companions', each `(cpu, gpu)`) to the reasons it fails.
pub type OperandJudge<'a> = dyn FnMut(usize, &Model, &[(Vec<f32>, Vec<f32>)]) -> Vec<String> + 'a;

/// The composed verdict of a combination (module docs) with each operand judged by `judge`
/// (its index, its model, and its renders: its own, then its companions'; it returns the
/// reasons that operand fails, prefixed with its index and kind by `judge` itself): every
/// operand passes its judge, and on each side the combination's value is `CombineOp::apply`
/// of that side's operand values, bit for bit. `renders` as
/// [`own_verdict`](CheckKind::own_verdict)'s: the combination's, then per operand its own
/// and its companions' ([`CheckKind::companions`] of the combination). Evaluators that add
/// their own, derived error to an operand's (the WGSL export's position rounding) judge the
/// operands with their own bounds through this; `own_verdict` judges them by their kind's
/// criterion.
pub fn composed_verdict(
    m: &Combine,
    renders: &[(Vec<f32>, Vec<f32>)],
    judge: &mut OperandJudge<'_>,
) -> Vec<String> {
    let mut why = Vec::new();
    let (mut cpu, mut gpu) = (Vec::new(), Vec::new());
    let mut at = 1;
    for (i, o) in m.operands.iter().enumerate() {
        let n = 1 + check_kind(o).companions().len();
        let Some(own) = renders.get(at..at + n) else {
            why.push(format!("operand {i}: its renders are missing"));
            return why;
        };
        why.extend(judge(i, o, own));
        cpu.push(own[0].0.as_slice());
        gpu.push(own[0].1.as_slice());
        at += n;
    }
    let Some(whole) = renders.first() else {
        why.push("the combination's render is missing".to_owned());
        return why;
    };
    why.extend(composition_reasons(m, "cpu", &whole.0, &cpu));
    why.extend(composition_reasons(m, "gpu", &whole.1, &gpu));
    why
}

/// `(tolerance, magnitude)` of channel `c` over the operands `ops`.
fn compose_ops(m: &Combine, ops: &[Operand], c: usize) -> Option<(f64, Option<f64>)> {
    let ops = ops.to_vec();
    let sum_mag = || ops.iter().map(|o| o.mag).sum::<Option<f64>>();
    match &m.op {
        CombineOp::Add => {
            let mag = sum_mag();
            let n = ops.len() as f64;
            let rounding = 2.0 * (n - 1.0) * U * mag?;
            Some((ops.iter().map(|o| o.tol).sum::<f64>() + rounding, mag))
        }
        CombineOp::Multiply => {
            let (mut tol, mut mag) = (ops[0].tol, ops[0].mag?);
            for o in &ops[1..] {
                tol = mag * o.tol + (o.mag? + o.tol) * tol;
                mag *= o.mag?;
            }
            let n = ops.len() as f64;
            Some((tol + 2.0 * (n - 1.0) * U * mag, Some(mag)))
        }
        CombineOp::Min | CombineOp::Max => Some((
            ops.iter().map(|o| o.tol).fold(0.0, f64::max),
            ops.iter()
                .map(|o| o.mag)
                .try_fold(0.0, |a, m| m.map(|m| f64::max(a, m))),
        )),
        CombineOp::Mix => {
            let (a, b, t) = (ops[0], ops[1], ops[2]);
            let big_t = t.mag? + t.tol;
            let mag = a.mag? + (a.mag? + b.mag?) * t.mag?;
            let tol = a.tol * (1.0 + big_t) + b.tol * big_t + (a.mag? + b.mag?) * t.tol;
            Some((tol + 2.0 * 3.0 * U * mag, Some(mag)))
        }
        op => {
            let (l, eps, mag) = unary(op, ops[0].mag, c)?;
            Some((l * ops[0].tol + 2.0 * eps, Some(mag)))
        }
    }
}

impl CheckKind for Combine {
    /// Per output channel, the composed bound (module docs); where there is none, the scale a
    /// composed verdict reports.
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(composed(self).unwrap_or_else(|| reported(self)))
    }

    /// A bound only where the composition has one: a warp over a combination judged by its
    /// operands' verdicts has none.
    fn value_bound(&self) -> Option<f64> {
        composed(self)?
            .iter()
            .map(|t| t.max_abs)
            .max_by(f64::total_cmp)
    }

    /// None where the composition bounds the combination; else each operand followed by its
    /// own companions, for [`own_verdict`](CheckKind::own_verdict).
    fn companions(&self) -> Vec<Model> {
        if composed(self).is_some() {
            return Vec::new();
        }
        self.operands
            .iter()
            .flat_map(|o| std::iter::once(o.clone()).chain(check_kind(o).companions()))
            .collect()
    }

    /// The composed verdict (module docs), where the composition has no bound.
    fn own_verdict(
        &self,
        renders: &[(Vec<f32>, Vec<f32>)],
        footprint: Option<f64>,
    ) -> Option<Vec<String>> {
        if composed(self).is_some() {
            return None;
        }
        Some(composed_verdict(self, renders, &mut |i, o, own| {
            operand_reasons(i, o, own, footprint)
        }))
    }

    /// The chain rule on the operands' regularities: a sum's slopes and jumps add, a product's
    /// are weighted by the other factor's magnitude, a minimum's or maximum's are the largest,
    /// a one-operand operation's are its Lipschitz constant times its operand's.
    fn regularity(&self) -> Option<Regularity> {
        let ops: Vec<Operand> = self.operands.iter().map(operand).collect::<Option<_>>()?;
        let cell = ops.iter().map(|o| o.cell).fold(f64::INFINITY, f64::min);
        let channels = spectex_model::ModelKind::output_channels(self);
        let (slope, jump, magnitude) = match &self.op {
            CombineOp::Add => (
                ops.iter().map(|o| o.slope).sum::<Option<f64>>()?,
                ops.iter().map(|o| o.jump).sum::<Option<f64>>()?,
                ops.iter().map(|o| o.mag).sum::<Option<f64>>()?,
            ),
            CombineOp::Min | CombineOp::Max => (
                ops.iter()
                    .map(|o| o.slope)
                    .try_fold(0.0, |a, s| s.map(|s| f64::max(a, s)))?,
                ops.iter()
                    .map(|o| o.jump)
                    .try_fold(0.0, |a, s| s.map(|s| f64::max(a, s)))?,
                ops.iter()
                    .map(|o| o.mag)
                    .try_fold(0.0, |a, s| s.map(|s| f64::max(a, s)))?,
            ),
            CombineOp::Multiply => {
                let (mut s, mut j, mut m) = (ops[0].slope?, ops[0].jump?, ops[0].mag?);
                for o in &ops[1..] {
                    s = m * o.slope? + o.mag? * s;
                    j = m * o.jump? + o.mag? * j + j * o.jump?;
                    m *= o.mag?;
                }
                (s, j, m)
            }
            CombineOp::Mix => {
                let (a, b, t) = (ops[0], ops[1], ops[2]);
                let (ma, mb, mt) = (a.mag?, b.mag?, t.mag?);
                (
                    a.slope? * (1.0 + mt) + b.slope? * mt + (ma + mb) * t.slope?,
                    a.jump? * (1.0 + mt) + b.jump? * mt + (ma + mb + a.jump? + b.jump?) * t.jump?,
                    ma + (ma + mb) * mt,
                )
            }
            op => {
                let o = ops[0];
                let (mut l, mut mag) = (0.0f64, 0.0f64);
                for c in 0..channels {
                    let (lc, _, mc) = unary(op, o.mag, c)?;
                    l = l.max(lc);
                    mag = mag.max(mc);
                }
                (l * o.slope?, l * o.jump?, mag)
            }
        };
        Some(Regularity {
            slope,
            jump,
            magnitude,
            cell,
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::voronoi::{VoronoiNoise, VoronoiOutput};

    fn f1() -> Model {
        Model::Voronoi(VoronoiNoise {
            output: VoronoiOutput::F1,
            ..VoronoiNoise::default()
        })
    }

    pub fn a_sum_adds_its_operands_bounds_and_a_maximum_takes_the_largest() {
        let one = check_kind(&f1()).value_bound().expect("F1 has a bound");
        let add = Combine {
            op: CombineOp::Add,
            operands: vec![f1(), f1()],
        };
        let max = Combine {
            op: CombineOp::Max,
            ..add.clone()
        };
        let t_add = add.tolerances().expect("bound")[0].max_abs;
        let t_max = max.tolerances().expect("bound")[0].max_abs;
        // Two operands: 2·tol plus one rounding of the sum of magnitudes (2√2) on each side.
        let rounding = 2.0 * U * 2.0 * std::f64::consts::SQRT_2;
        assert!((t_add - (2.0 * one + rounding)).abs() < 1e-15, "{t_add}");
        assert_eq!(t_max, one);
    }

    fn wave(angle: f32) -> Model {
        use spectex_model::{Field, PhasorNoise, PhasorOrientation, PhasorOutput, Profile};
        Model::Phasor(PhasorNoise {
            seed: 1,
            dimensions: 2,
            bandwidth: Field::constant(0.02),
            frequency: Field::constant(0.07),
            orientation: PhasorOrientation::Aligned {
                angle: Field::constant(angle),
            },
            impulses_per_kernel: 16.0,
            profile: Profile::Sine,
            output: PhasorOutput::Profiled,
            mean: 0.25,
            amplitude: 0.25,
        })
    }

    /// One pixel of crossed waves: the sum's (cpu, gpu), then per wave its profiled value,
    /// Gabor, intensity and phase, each (cpu, gpu).
    fn crossed_pixel(sum: [f32; 2], waves: [[[f32; 2]; 4]; 2]) -> Vec<(Vec<f32>, Vec<f32>)> {
        std::iter::once(sum)
            .chain(waves.into_iter().flatten())
            .map(|p| (vec![p[0]], vec![p[1]]))
            .collect()
    }

    pub fn crossed_waves_are_judged_by_their_operands_verdicts_and_the_operation() {
        let crossed = Combine {
            op: CombineOp::Add,
            operands: vec![wave(0.4), wave(1.97)],
        };
        // Phasor's profiled output has no value bound: the composition has none either.
        assert!(composed(&crossed).is_none());
        assert!(crossed.value_bound().is_none());
        // Each wave brings its Gabor, intensity and phase companions.
        let companions = crossed.companions();
        assert_eq!(companions.len(), 8);
        assert_eq!(companions[0], crossed.operands[0]);
        assert_eq!(companions[4], crossed.operands[1]);
        // A pixel where both evaluators agree on every render, the sum being the f32 sum.
        let (a, b) = (0.375f32, 0.125f32);
        let good = [[a, a], [0.5, 0.5], [1.0, 1.0], [0.125, 0.125]];
        let other = [[b, b], [-0.5, -0.5], [1.0, 1.0], [0.875, 0.875]];
        let ok = crossed_pixel([a + b, a + b], [good, other]);
        assert_eq!(crossed.own_verdict(&ok, None), Some(vec![]));
        // The GPU's sum one ulp away from the sum of its operands.
        let off = f32::from_bits((a + b).to_bits() + 1);
        let why = crossed
            .own_verdict(&crossed_pixel([a + b, off], [good, other]), None)
            .expect("a composed verdict");
        assert_eq!(why.len(), 1, "{why:?}");
        assert!(why[0].starts_with("gpu: 1 value"), "{why:?}");
        // The second wave's phase a tenth of a turn off where its intensity determines it.
        let bent = [[b, b], [-0.5, -0.5], [1.0, 1.0], [0.875, 0.975]];
        let why = crossed
            .own_verdict(&crossed_pixel([a + b, a + b], [good, bent]), None)
            .expect("a composed verdict");
        assert!(
            why.iter().any(|w| w.starts_with("operand 1 (phasor)")),
            "{why:?}"
        );
    }

    pub fn a_bounded_combination_keeps_the_generic_criterion() {
        let add = Combine {
            op: CombineOp::Add,
            operands: vec![f1(), f1()],
        };
        assert!(add.companions().is_empty());
        assert_eq!(add.own_verdict(&[(vec![0.0], vec![1.0])], None), None);
        // A threshold over a bounded operand is judged by the composed verdict.
        let step = Combine {
            op: CombineOp::Smoothstep { edges: [0.5, 0.5] },
            operands: vec![f1()],
        };
        assert_eq!(step.companions(), vec![f1()]);
        let ok = [(vec![1.0], vec![1.0]), (vec![0.75], vec![0.75])];
        assert_eq!(step.own_verdict(&ok, None), Some(vec![]));
    }

    pub fn a_threshold_has_no_bound_and_a_smoothstep_scales_by_its_slope() {
        let step = |edges| Combine {
            op: CombineOp::Smoothstep { edges },
            operands: vec![f1()],
        };
        assert!(composed(&step([0.5, 0.5])).is_none());
        let one = check_kind(&f1()).value_bound().expect("bound");
        let t = step([0.0, 0.5]).tolerances().expect("bound")[0].max_abs;
        // Slope 1.5/0.5 = 3.
        assert!(t >= 3.0 * one && t < 3.0 * one + 1e-5, "{t} vs {one}");
    }
}
