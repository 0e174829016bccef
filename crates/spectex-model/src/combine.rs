//! Combination (survey Dong et al. 2020, §4.1–4.2): a model computed pointwise from other
//! models — sums, products, minima and maxima, a mix by a third model, thresholds, the
//! survey's folds (§4.1.1), histogram matching to an exemplar (§4.1.2) and colour ramps.
//! Operands are any models, combinations included (field paths `combine.operands[1].…`).
//!
//! # Definition
//!
//! Every operand is evaluated at the pixel's position; [`CombineOp::apply`] then computes the
//! value per channel in f32, the one expression every evaluator uses (the GPU evaluator
//! renders the operands on the device per tile and applies it on the host, as a warp applies
//! its displacement):
//! - `add`, `multiply`, `min`, `max` of 2 to 8 operands with the same channels, left to right;
//! - `mix` of `(a, b, t)`: `a + (b − a)·t`, `t` grey;
//! - `smoothstep` with edges `(e₀, e₁)`: `s = clamp((v − e₀)/(e₁ − e₀), 0, 1)`, `s·s·(3 − 2s)`;
//!   equal edges threshold (`v ≥ e₀` gives 1, else 0);
//! - `abs_fold` (§4.1.1): `v ← v − offset`, then `folds` times `v ← |v − step|` (the survey's
//!   `A = abs(A − fold_A)` with `offset` its minimum and `step` its `max/(n + 1)`);
//! - `sin_fold`: `sin(2π·gain·v)` ([`crate::math::sin_turns`]);
//! - `histogram` (§4.1.2): the monotone table `T` over `domain`, linear between its `N` knots
//!   `x_k = d₀ + (d₁ − d₀)·k/(N − 1)`, clamped at the ends; [`histogram_table`] fits it;
//! - `ramp`: a grey operand to RGB, linear between stops sorted by position, clamped.

use serde::{Deserialize, Serialize};

use crate::Model;
use crate::error::{ModelError, check_len, check_level, check_range};
use crate::math::sin_turns;

pub(crate) mod builder;
pub use builder::CombineBuilder;

/// Most operands of one combination.
pub const MAX_OPERANDS: usize = 8;
/// Most combinations nested inside one model (itself included).
pub const MAX_COMBINE_DEPTH: usize = 8;
/// Most knots of a histogram table.
pub const MAX_TABLE_KNOTS: usize = 4096;
/// Most ramp stops.
pub const MAX_STOPS: usize = 64;
/// Most folds.
pub const MAX_FOLDS: u32 = 32;
/// Largest `|gain|` of a sine fold.
pub const MAX_GAIN: f32 = 1.0e4;

/// A colour ramp's stop.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RampStop {
    /// The grey value at which the colour is reached.
    pub at: f32,
    /// RGB.
    pub colour: [f32; 3],
}

/// The pointwise operation (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum CombineOp {
    /// Sum of the operands.
    Add,
    /// Product of the operands.
    Multiply,
    /// Smallest operand.
    Min,
    /// Largest operand.
    Max,
    /// `a + (b − a)·t` of three operands `(a, b, t)`.
    Mix,
    /// Hermite step between two edges (a threshold when they are equal).
    Smoothstep {
        /// `(e₀, e₁)`, `e₀ ≤ e₁`.
        edges: [f32; 2],
    },
    /// The survey's fold: `v − offset`, then `folds` times `|v − step|`.
    AbsFold {
        /// Subtracted first (the operand's minimum).
        offset: f32,
        /// Subtracted before each absolute value.
        step: f32,
        /// `0..=32`.
        folds: u32,
    },
    /// `sin(2π·gain·v)`.
    SinFold {
        /// Cycles per unit of the operand, `|gain| ≤ 10⁴`.
        gain: f32,
    },
    /// A monotone lookup table (histogram matching).
    Histogram {
        /// `(d₀, d₁)`, `d₀ < d₁`: the operand values of the first and last knots.
        domain: [f32; 2],
        /// `2..=4096` values at evenly spaced knots.
        table: Vec<f32>,
    },
    /// A grey operand to RGB.
    Ramp {
        /// `1..=64` stops in increasing `at`.
        stops: Vec<RampStop>,
    },
}

/// A combination of models (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Combine {
    /// What is computed.
    pub op: CombineOp,
    /// The models it reads, in the operation's order.
    pub operands: Vec<Model>,
}

impl CombineOp {
    /// Operands the operation takes: `(fewest, most)`.
    #[must_use]
    pub fn arity(&self) -> (usize, usize) {
        match self {
            Self::Add | Self::Multiply | Self::Min | Self::Max => (2, MAX_OPERANDS),
            Self::Mix => (3, 3),
            _ => (1, 1),
        }
    }

    /// The value of one channel `c` from the operands' values at a pixel (`values[k]` the
    /// channels of operand `k`), and for a ramp all three channels from the grey operand.
    #[inline]
    #[must_use]
    pub fn apply(&self, values: &[&[f32]], c: usize) -> f32 {
        match self {
            Self::Add => values[1..].iter().fold(values[0][c], |acc, v| acc + v[c]),
            Self::Multiply => values[1..].iter().fold(values[0][c], |acc, v| acc * v[c]),
            Self::Min => values[1..]
                .iter()
                .fold(values[0][c], |acc, v| acc.min(v[c])),
            Self::Max => values[1..]
                .iter()
                .fold(values[0][c], |acc, v| acc.max(v[c])),
            Self::Mix => {
                let (a, b, t) = (values[0][c], values[1][c], values[2][0]);
                a + (b - a) * t
            }
            Self::Smoothstep { edges } => smoothstep(*edges, values[0][c]),
            Self::AbsFold {
                offset,
                step,
                folds,
            } => {
                let mut v = values[0][c] - offset;
                for _ in 0..*folds {
                    v = (v - step).abs();
                }
                v
            }
            Self::SinFold { gain } => sin_turns(gain * values[0][c]),
            Self::Histogram { domain, table } => lookup(*domain, table, values[0][c]),
            Self::Ramp { stops } => ramp(stops, values[0][0], c),
        }
    }
}

/// `s·s·(3 − 2s)` of `s = clamp((v − e₀)/(e₁ − e₀), 0, 1)`; a threshold for equal edges.
#[inline]
#[must_use]
pub fn smoothstep(edges: [f32; 2], v: f32) -> f32 {
    if edges[0] >= edges[1] {
        return if v >= edges[0] { 1.0 } else { 0.0 };
    }
    let s = ((v - edges[0]) / (edges[1] - edges[0])).clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// The table over `domain` at `v`, linear between knots, clamped (NaN gives the first entry).
#[inline]
#[must_use]
pub fn lookup(domain: [f32; 2], table: &[f32], v: f32) -> f32 {
    let last = (table.len() - 1) as f32;
    let x = ((v - domain[0]) / (domain[1] - domain[0]) * last).clamp(0.0, last);
    let x = if x.is_nan() { 0.0 } else { x };
    let k = (x.floor() as usize).min(table.len() - 2);
    let f = x - k as f32;
    table[k] + (table[k + 1] - table[k]) * f
}

/// Channel `c` of the ramp at `v`: linear between the stops around it, clamped at the ends.
#[inline]
#[must_use]
pub fn ramp(stops: &[RampStop], v: f32, c: usize) -> f32 {
    let first = &stops[0];
    if v.is_nan() || v <= first.at {
        return first.colour[c];
    }
    for pair in stops.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if v < b.at {
            let f = (v - a.at) / (b.at - a.at);
            return a.colour[c] + (b.colour[c] - a.colour[c]) * f;
        }
    }
    stops[stops.len() - 1].colour[c]
}

/// Histogram matching (§4.1.2): the table of `knots` values mapping an operand whose values
/// are `samples` (a rendered window) to the exemplar's distribution `exemplar`: over the
/// samples' range, knot `x_k` maps to the exemplar's quantile at the samples' CDF `F(x_k)`
/// (the fraction of samples `≤ x_k`, nearest rank). Monotone by construction. Returns the
/// domain and the table, or `None` for empty or constant samples or an empty exemplar.
#[must_use]
pub fn histogram_table(
    samples: &[f32],
    exemplar: &[f32],
    knots: usize,
) -> Option<([f32; 2], Vec<f32>)> {
    let mut s: Vec<f32> = samples.iter().copied().filter(|v| v.is_finite()).collect();
    let mut e: Vec<f32> = exemplar.iter().copied().filter(|v| v.is_finite()).collect();
    if s.is_empty() || e.is_empty() || knots < 2 {
        return None;
    }
    s.sort_by(f32::total_cmp);
    e.sort_by(f32::total_cmp);
    let (lo, hi) = (s[0], s[s.len() - 1]);
    if lo >= hi {
        return None;
    }
    let table = (0..knots)
        .map(|k| {
            let x = f64::from(lo) + (f64::from(hi) - f64::from(lo)) * k as f64 / (knots - 1) as f64;
            let below = s.partition_point(|&v| f64::from(v) <= x);
            let cdf = below as f64 / s.len() as f64;
            let rank = ((cdf * e.len() as f64).ceil() as usize).clamp(1, e.len());
            e[rank - 1]
        })
        .collect();
    Some(([lo, hi], table))
}

/// Combinations nested in `model`, itself included (0 for another kind; warps are looked
/// through).
#[must_use]
pub fn depth(model: &Model) -> usize {
    match model {
        Model::Combine(c) => 1 + c.operands.iter().map(depth).max().unwrap_or(0),
        Model::Warp(w) => [&w.base, &w.x, &w.y]
            .iter()
            .map(|m| depth(m))
            .max()
            .unwrap_or(0),
        _ => 0,
    }
}

/// Puts `combine.operands[k].` in front of the field path of a validation error.
fn prefixed(e: ModelError, k: usize) -> ModelError {
    match e {
        ModelError::OutOfRange {
            field,
            value,
            range,
        } => ModelError::OutOfRange {
            field: format!("combine.operands[{k}].{field}"),
            value,
            range,
        },
        ModelError::Length { field, len, range } => ModelError::Length {
            field: format!("combine.operands[{k}].{field}"),
            len,
            range,
        },
        other => other,
    }
}

impl Combine {
    /// Checks the nesting, the operand count and channels, the operation's parameters and
    /// every operand; field paths start with `combine.`.
    ///
    /// # Errors
    /// The first invalid field.
    pub fn validate(&self) -> Result<(), ModelError> {
        let depth = 1 + self.operands.iter().map(depth).max().unwrap_or(0);
        if depth > MAX_COMBINE_DEPTH {
            return Err(ModelError::OutOfRange {
                field: "combine".into(),
                value: depth as f64,
                range: "at most 8 nested combinations",
            });
        }
        let (lo, hi) = self.op.arity();
        check_len(
            || "combine.operands".into(),
            self.operands.len(),
            lo,
            hi,
            match (lo, hi) {
                (1, 1) => "exactly 1 operand for this operation",
                (3, 3) => "exactly 3 operands (a, b, t) for mix",
                _ => "2 to 8 operands",
            },
        )?;
        for (k, m) in self.operands.iter().enumerate() {
            m.validate().map_err(|e| prefixed(e, k))?;
        }
        let channels: Vec<usize> = self.operands.iter().map(Model::output_channels).collect();
        let must_be = |k: usize, want: usize, range: &'static str| {
            if channels[k] == want {
                Ok(())
            } else {
                Err(ModelError::Length {
                    field: format!("combine.operands[{k}] (values per pixel)"),
                    len: channels[k],
                    range,
                })
            }
        };
        match &self.op {
            CombineOp::Add | CombineOp::Multiply | CombineOp::Min | CombineOp::Max => {
                for k in 1..channels.len() {
                    must_be(k, channels[0], "the values per pixel of operands[0]")?;
                }
            }
            CombineOp::Mix => {
                must_be(1, channels[0], "the values per pixel of operands[0]")?;
                must_be(2, 1, "exactly 1 (a grey t)")?;
            }
            CombineOp::Smoothstep { edges } => {
                for (k, &e) in edges.iter().enumerate() {
                    check_level(|| format!("combine.op.smoothstep.edges[{k}]"), e)?;
                }
                if edges[0] > edges[1] {
                    return Err(ModelError::OutOfRange {
                        field: "combine.op.smoothstep.edges[1]".into(),
                        value: f64::from(edges[1]),
                        range: "at least edges[0]",
                    });
                }
            }
            CombineOp::AbsFold {
                offset,
                step,
                folds,
            } => {
                check_level(|| "combine.op.abs_fold.offset".into(), *offset)?;
                check_level(|| "combine.op.abs_fold.step".into(), *step)?;
                check_range(
                    || "combine.op.abs_fold.folds".into(),
                    f64::from(*folds),
                    0.0,
                    f64::from(MAX_FOLDS),
                    "[0, 32]",
                )?;
            }
            CombineOp::SinFold { gain } => check_range(
                || "combine.op.sin_fold.gain".into(),
                f64::from(*gain),
                -f64::from(MAX_GAIN),
                f64::from(MAX_GAIN),
                "[-1e4, 1e4] cycles per unit",
            )?,
            CombineOp::Histogram { domain, table } => {
                for (k, &d) in domain.iter().enumerate() {
                    check_level(|| format!("combine.op.histogram.domain[{k}]"), d)?;
                }
                if domain[0] >= domain[1] {
                    return Err(ModelError::OutOfRange {
                        field: "combine.op.histogram.domain[1]".into(),
                        value: f64::from(domain[1]),
                        range: "above domain[0]",
                    });
                }
                check_len(
                    || "combine.op.histogram.table".into(),
                    table.len(),
                    2,
                    MAX_TABLE_KNOTS,
                    "2 to 4096 knots",
                )?;
                for (k, &v) in table.iter().enumerate() {
                    check_level(|| format!("combine.op.histogram.table[{k}]"), v)?;
                }
            }
            CombineOp::Ramp { stops } => {
                must_be(0, 1, "exactly 1 (a grey operand)")?;
                check_len(
                    || "combine.op.ramp.stops".into(),
                    stops.len(),
                    1,
                    MAX_STOPS,
                    "1 to 64 stops",
                )?;
                for (k, s) in stops.iter().enumerate() {
                    check_level(|| format!("combine.op.ramp.stops[{k}].at"), s.at)?;
                    for (n, &v) in s.colour.iter().enumerate() {
                        check_level(|| format!("combine.op.ramp.stops[{k}].colour[{n}]"), v)?;
                    }
                    if k > 0 && s.at <= stops[k - 1].at {
                        return Err(ModelError::OutOfRange {
                            field: format!("combine.op.ramp.stops[{k}].at"),
                            value: f64::from(s.at),
                            range: "above the previous stop's",
                        });
                    }
                }
            }
        }
        Ok(())
    }
}

impl From<Combine> for Model {
    fn from(model: Combine) -> Self {
        Self::Combine(model)
    }
}

impl crate::ModelKind for Combine {
    const PERIODIC: bool = true;

    const NAME: &'static str = "combine";

    /// A period every operand accepts: the operation applies pixel by pixel, so the
    /// combination of periodic operands is periodic (as a warp of periodic models is).
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        self.operands
            .iter()
            .try_for_each(|m| m.check_period(period))
    }

    fn validate(&self) -> Result<(), ModelError> {
        Combine::validate(self)
    }

    /// 3 for a ramp; otherwise the first operand's.
    fn output_channels(&self) -> usize {
        match self.op {
            CombineOp::Ramp { .. } => 3,
            _ => self.operands.first().map_or(1, Model::output_channels),
        }
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        for m in &mut self.operands {
            m.visit_seeds(visit);
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::fixtures::constant;

    pub fn operations_follow_their_definitions() {
        let (a, b, t) = ([0.25f32], [1.0f32], [0.5f32]);
        let v: [&[f32]; 3] = [&a, &b, &t];
        assert_eq!(CombineOp::Add.apply(&v[..2], 0), 1.25);
        assert_eq!(CombineOp::Multiply.apply(&v[..2], 0), 0.25);
        assert_eq!(CombineOp::Min.apply(&v[..2], 0), 0.25);
        assert_eq!(CombineOp::Max.apply(&v[..2], 0), 1.0);
        assert_eq!(CombineOp::Mix.apply(&v, 0), 0.625);
        // Hermite: ½ at the middle, 0 and 1 beyond the edges; equal edges threshold.
        assert_eq!(smoothstep([0.0, 1.0], 0.5), 0.5);
        assert_eq!(smoothstep([0.0, 1.0], -3.0), 0.0);
        assert_eq!(smoothstep([0.0, 1.0], 3.0), 1.0);
        assert_eq!(smoothstep([0.5, 0.5], 0.5), 1.0);
        assert_eq!(smoothstep([0.5, 0.5], 0.49), 0.0);
        // The survey's fold of 0.9 with min 0, max 1, two folds: step 1/3;
        // |0.9 − ⅓| = 0.5667, |0.5667 − ⅓| = 0.2333.
        let fold = CombineOp::AbsFold {
            offset: 0.0,
            step: 1.0 / 3.0,
            folds: 2,
        };
        assert!((fold.apply(&[&[0.9]], 0) - 0.233_333).abs() < 1e-6);
        // A quarter cycle of the sine fold.
        assert!((CombineOp::SinFold { gain: 0.25 }.apply(&[&[1.0]], 0) - 1.0).abs() < 1e-6);
    }

    pub fn lookup_and_ramp_interpolate_and_clamp() {
        let table = [0.0, 10.0, 40.0];
        assert_eq!(lookup([0.0, 2.0], &table, 0.5), 5.0);
        assert_eq!(lookup([0.0, 2.0], &table, 1.5), 25.0);
        assert_eq!(lookup([0.0, 2.0], &table, 9.0), 40.0);
        assert_eq!(lookup([0.0, 2.0], &table, -9.0), 0.0);
        let stops = [
            RampStop {
                at: 0.0,
                colour: [0.0, 1.0, 0.0],
            },
            RampStop {
                at: 2.0,
                colour: [1.0, 0.0, 0.5],
            },
        ];
        assert_eq!(ramp(&stops, 1.0, 0), 0.5);
        assert_eq!(ramp(&stops, 1.0, 1), 0.5);
        assert_eq!(ramp(&stops, -1.0, 2), 0.0);
        assert_eq!(ramp(&stops, 7.0, 2), 0.5);
    }

    pub fn histogram_matching_maps_quantiles() {
        // Samples uniform on [0, 1); exemplar uniform on [10, 20): the matched table is
        // 10 + 10·x up to the quantisation of 1000 ranks.
        let samples: Vec<f32> = (0..1000).map(|k| k as f32 / 1000.0).collect();
        let exemplar: Vec<f32> = (0..1000).map(|k| 10.0 + k as f32 / 100.0).collect();
        let (domain, table) = histogram_table(&samples, &exemplar, 11).expect("table");
        assert_eq!(domain, [0.0, 0.999]);
        for (k, &v) in table.iter().enumerate() {
            let want = 10.0 + 10.0 * (k as f32 * 0.0999);
            assert!((v - want).abs() < 0.03, "knot {k}: {v} vs {want}");
        }
        assert!(table.windows(2).all(|w| w[0] <= w[1]), "monotone");
    }

    pub fn validation_names_nested_fields() {
        let mut bad = constant(0.0);
        if let Model::Classic(c) = &mut bad {
            c.cell_size = 0.0;
        }
        let cases = [
            (
                Combine {
                    op: CombineOp::Add,
                    operands: vec![constant(0.0), bad],
                },
                "combine.operands[1].classic.cell_size",
            ),
            (
                Combine {
                    op: CombineOp::Mix,
                    operands: vec![constant(0.0), constant(1.0)],
                },
                "combine.operands",
            ),
            (
                Combine {
                    op: CombineOp::Smoothstep { edges: [1.0, 0.0] },
                    operands: vec![constant(0.0)],
                },
                "combine.op.smoothstep.edges[1]",
            ),
        ];
        for (c, field) in cases {
            let err = Model::Combine(c).validate().expect_err(field);
            assert!(err.to_string().starts_with(field), "{field}: {err}");
        }
        let ok = Combine {
            op: CombineOp::Add,
            operands: vec![constant(0.0), constant(1.0)],
        };
        Model::Combine(ok).validate().expect("valid");
    }
}
