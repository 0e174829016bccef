//! Combinations: their tolerance and regularity composed from their operands'.
//!
//! Both evaluators apply the same f32 operation (`spectex_model::combine::CombineOp::apply`,
//! on the host for the GPU) to operand values that differ by at most the operands' bounds, so
//! `|f̃(a) − f̃(a')| ≤ L·|a − a'| + 2ε`, with `L` the operation's Lipschitz constant over the
//! operands' range and `ε` its own f32 evaluation error (counted once per side). Operand
//! magnitudes come from their [`Regularity`]; an operation that needs one and an operand
//! without it (or without a bound) gives no tolerance.

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
    let k = check_kind(m);
    let tol = k.value_bound()?;
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
    /// Per output channel, the composed bound (module docs).
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        let channels = spectex_model::ModelKind::output_channels(self);
        (0..channels)
            .map(|c| compose(self, c).map(|(t, _)| Tolerance::from_max(t)))
            .collect()
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

#[cfg(test)]
mod tests {
    use super::*;
    use spectex_model::voronoi::{VoronoiNoise, VoronoiOutput};

    fn f1() -> Model {
        Model::Voronoi(VoronoiNoise {
            output: VoronoiOutput::F1,
            ..VoronoiNoise::default()
        })
    }

    #[test]
    fn a_sum_adds_its_operands_bounds_and_a_maximum_takes_the_largest() {
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

    #[test]
    fn a_threshold_has_no_bound_and_a_smoothstep_scales_by_its_slope() {
        let step = |edges| Combine {
            op: CombineOp::Smoothstep { edges },
            operands: vec![f1()],
        };
        assert!(step([0.5, 0.5]).tolerances().is_none());
        let one = check_kind(&f1()).value_bound().expect("bound");
        let t = step([0.0, 0.5]).tolerances().expect("bound")[0].max_abs;
        // Slope 1.5/0.5 = 3.
        assert!(t >= 3.0 * one && t < 3.0 * one + 1e-5, "{t} vs {one}");
    }
}
