//! The builder of [`Combine`], with the `spectex noise combine` defaults:
//! `Combine::builder().op(CombineOp::Max).operand(a).operand(b).build()?`.

use crate::Model;
use crate::combine::{Combine, CombineOp, RampStop};
use crate::error::ModelError;

/// An 8-bit sRGB byte as the `[0, 1]` value a ramp stop holds (`b/255`, as `spectex noise
/// combine ramp --stops` reads `RRGGBB`).
const fn byte(b: u8) -> f32 {
    b as f32 / 255.0
}

impl Combine {
    /// The operation unless [`CombineBuilder::op`] is given: the sum.
    pub const DEFAULT_OP: CombineOp = CombineOp::Add;
    /// `(e₀, e₁)` of a smoothstep: a soft threshold around ½, the middle of a default
    /// operand's `[0, 1]`.
    pub const DEFAULT_EDGES: [f32; 2] = [0.45, 0.55];
    /// Folds of the survey's fold: three.
    pub const DEFAULT_FOLDS: u32 = 3;
    /// Cycles per unit of the operand of a sine fold: two bands across `[0, 1]`.
    pub const DEFAULT_SIN_GAIN: f32 = 2.0;
    /// A bark ramp: dark brown `#2b1a0e` at 0.2, brown `#6b4226` at 0.5, tan `#c8a27a` at 0.8.
    pub const DEFAULT_RAMP_STOPS: [RampStop; 3] = [
        RampStop {
            at: 0.2,
            colour: [byte(0x2b), byte(0x1a), byte(0x0e)],
        },
        RampStop {
            at: 0.5,
            colour: [byte(0x6b), byte(0x42), byte(0x26)],
        },
        RampStop {
            at: 0.8,
            colour: [byte(0xc8), byte(0xa2), byte(0x7a)],
        },
    ];

    /// A combination of no operands with [`Self::DEFAULT_OP`]; set the operation and add the
    /// operands, then `build()`.
    ///
    /// ```
    /// use spectex_model::{ClassicNoise, Combine, VoronoiNoise};
    /// use spectex_model::combine::CombineOp;
    ///
    /// let c = Combine::builder()
    ///     .op(CombineOp::Smoothstep { edges: Combine::DEFAULT_EDGES })
    ///     .operand(ClassicNoise::fbm().build()?)
    ///     .build()?;
    /// assert_eq!(c.operands.len(), 1);
    /// // The sum takes at least two operands.
    /// let one = Combine::builder().operand(VoronoiNoise::builder().build()?).build();
    /// assert!(one.unwrap_err().to_string().contains("combine.operands"));
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> CombineBuilder {
        CombineBuilder {
            model: Self {
                op: Self::DEFAULT_OP,
                operands: Vec::new(),
            },
        }
    }
}

/// Builds a [`Combine`]; start from [`Combine::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct CombineBuilder {
    model: Combine,
}

impl CombineBuilder {
    /// The operation, with its parameters (smoothstep edges `e₀ ≤ e₁`, `0..=32` folds, a gain
    /// of at most 10⁴, 1 to 64 ramp stops in increasing `at`, …).
    pub fn op(mut self, op: CombineOp) -> Self {
        self.model.op = op;
        self
    }

    /// Appends an operand (any kind; at most 8 nested combinations).
    pub fn operand(mut self, operand: impl Into<Model>) -> Self {
        self.model.operands.push(operand.into());
        self
    }

    /// The operands, in the operation's order: as many as it takes (1, 3 for mix, or 2 to 8).
    pub fn operands(mut self, operands: Vec<Model>) -> Self {
        self.model.operands = operands;
        self
    }

    /// The validated combination.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first invalid field
    /// (`combine.operands`, `combine.op.smoothstep.edges[1]`, an operand's own field under
    /// `combine.operands[k]`, …).
    pub fn build(self) -> Result<Combine, ModelError> {
        self.model.validate()?;
        Ok(self.model)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::{ClassicNoise, VoronoiNoise};

    fn grey() -> Model {
        ClassicNoise::fbm().build().expect("valid").into()
    }

    pub fn defaults_are_the_documented_constants() {
        let b = Combine::builder();
        let sum = b.clone().operand(grey()).operand(grey()).build();
        assert_eq!(sum.expect("valid").op, CombineOp::Add);
        let folds = Combine::DEFAULT_FOLDS;
        let fold = CombineOp::AbsFold {
            offset: 0.0,
            step: 0.25,
            folds,
        };
        let fold = b.clone().op(fold).operand(grey()).build().expect("valid");
        assert!(matches!(fold.op, CombineOp::AbsFold { folds: 3, .. }));
        let ramp = CombineOp::Ramp {
            stops: Combine::DEFAULT_RAMP_STOPS.to_vec(),
        };
        let ramp = b.op(ramp).operand(grey()).build().expect("valid");
        let CombineOp::Ramp { stops } = ramp.op else {
            panic!("a ramp");
        };
        // #6b4226: 0x6b = 107.
        assert_eq!((stops[1].at, stops[1].colour[0]), (0.5, 107.0 / 255.0));
        assert_eq!(Combine::DEFAULT_EDGES, [0.45, 0.55]);
        assert_eq!(Combine::DEFAULT_SIN_GAIN, 2.0);
    }

    pub fn invalid_settings_name_the_field() {
        let b = || Combine::builder().operand(grey());
        let length = b().build();
        match length {
            Err(ModelError::Length { field, .. }) => assert_eq!(field, "combine.operands"),
            other => panic!("{other:?}"),
        }
        let cases = [
            (
                b().op(CombineOp::Smoothstep { edges: [0.6, 0.4] }).build(),
                "combine.op.smoothstep.edges[1]",
            ),
            (
                b().op(CombineOp::SinFold { gain: 2e4 }).build(),
                "combine.op.sin_fold.gain",
            ),
            (
                b().op(CombineOp::AbsFold {
                    offset: 0.0,
                    step: 0.1,
                    folds: 33,
                })
                .build(),
                "combine.op.abs_fold.folds",
            ),
            (
                Combine::builder()
                    .operand(grey())
                    .operand(VoronoiNoise {
                        jitter: 2.0,
                        ..VoronoiNoise::default()
                    })
                    .build(),
                "combine.operands[1].voronoi.jitter",
            ),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert!(f.contains(field), "{f}"),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
