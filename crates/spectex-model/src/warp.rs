//! Domain warping (distortion): one model evaluated at positions displaced by two others — the
//! survey's filtering family (Dong et al. 2020, "warping" filters of texture editors such as
//! NeoTextureEdit), as Quilez writes it, `f(p + s·(g(p), h(p)))`.
//!
//! # Definition
//!
//! For a position `p` in pixels, `warp(p) = base(p + d(p))` with the displacement
//! `d(p) = (D(x(p)), D(y(p)))`, `D(v) = clamp(strength·v, −MAX_WARP, MAX_WARP)` computed in f32
//! ([`Warp::displacement`]; NaN gives 0). `x` and `y` are one-value models (typically zero-mean
//! fBm or LRP noise) evaluated at `p`; `base` is any model — a colour texture, a 3D model on its
//! plane `z` (the same `z` for all three), or another warp.
//!
//! # Positions (DESIGN invariant 2)
//!
//! The displaced position is the window's f64 position plus the f32 displacement, summed in f64,
//! so a warp at `(10⁷, 10⁷)` is as precise as one at the origin. `|strength·v|` is not known a
//! priori for every model, hence the clamp: a displacement never exceeds [`MAX_WARP`] pixels per
//! axis, and a model nesting `n` warps along its base chain reaches at most
//! [`reach`]` ≤ n·MAX_WARP` pixels beyond the window. Evaluators therefore accept a window for a
//! warp only within `MAX_POSITION − reach` ([`check_window`]), so every displaced position stays
//! in the range where lattice cells are `i32`.

use serde::{Deserialize, Serialize};

use crate::Model;
use crate::error::{ModelError, check_range};
use crate::grid::{MAX_POSITION, Window, WindowError};

pub(crate) mod builder;
pub use builder::WarpBuilder;

/// Largest displacement along one axis, pixels (`2¹⁶`, exact in f32): displacements are clamped
/// to `±MAX_WARP` on every evaluator.
pub const MAX_WARP: f32 = 65_536.0;
/// Largest `|strength|`, pixels per unit of the displacement models.
pub const MAX_STRENGTH: f32 = 65_536.0;
/// Most warps nested inside one model (in any of `base`, `x`, `y`).
pub const MAX_WARP_DEPTH: usize = 8;

/// `base(p + strength·(x(p), y(p)))`, displacements clamped to `±MAX_WARP` pixels (module doc).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Warp {
    /// The model evaluated at the displaced positions.
    pub base: Box<Model>,
    /// The displacement along x (one value per pixel), before `strength`.
    pub x: Box<Model>,
    /// The displacement along y (one value per pixel), before `strength`.
    pub y: Box<Model>,
    /// Pixels of displacement per unit of `x` and `y`, in `[−65536, 65536]`.
    pub strength: f32,
}

impl Warp {
    /// `D(v) = clamp(strength·v, −MAX_WARP, MAX_WARP)` in f32, 0 for NaN: the one expression
    /// every evaluator uses.
    #[inline]
    #[must_use]
    pub fn displacement(&self, v: f32) -> f32 {
        let d = self.strength * v;
        if d.is_nan() {
            0.0
        } else {
            d.clamp(-MAX_WARP, MAX_WARP)
        }
    }

    /// Checks `strength`, the nesting depth, that `x` and `y` give one value per pixel, and
    /// every sub-model; field paths start with `warp.` (`warp.x.classic.cell_size`).
    ///
    /// # Errors
    /// The first invalid field.
    pub fn validate(&self) -> Result<(), ModelError> {
        let depth = self.depth();
        if depth > MAX_WARP_DEPTH {
            return Err(ModelError::OutOfRange {
                field: "warp".into(),
                value: depth as f64,
                range: "at most 8 nested warps",
            });
        }
        check_range(
            || "warp.strength".into(),
            f64::from(self.strength),
            -f64::from(MAX_STRENGTH),
            f64::from(MAX_STRENGTH),
            "[-65536, 65536] pixels",
        )?;
        for (name, model) in [("base", &self.base), ("x", &self.x), ("y", &self.y)] {
            model.validate().map_err(|e| prefixed(e, name))?;
        }
        for (name, model) in [("x", &self.x), ("y", &self.y)] {
            let channels = model.output_channels();
            if channels != 1 {
                return Err(ModelError::Length {
                    field: format!("warp.{name} (values per pixel)"),
                    len: channels,
                    range: "exactly 1 (a grey model)",
                });
            }
        }
        Ok(())
    }

    /// Warps nested in this one, itself included.
    #[must_use]
    pub fn depth(&self) -> usize {
        1 + [&self.base, &self.x, &self.y]
            .iter()
            .map(|m| depth(m))
            .max()
            .unwrap_or(0)
    }
}

/// Puts `warp.{name}.` in front of the field path of a validation error.
fn prefixed(e: ModelError, name: &str) -> ModelError {
    match e {
        ModelError::OutOfRange {
            field,
            value,
            range,
        } => ModelError::OutOfRange {
            field: format!("warp.{name}.{field}"),
            value,
            range,
        },
        ModelError::Length { field, len, range } => ModelError::Length {
            field: format!("warp.{name}.{field}"),
            len,
            range,
        },
        other => other,
    }
}

/// Warps nested in `model` (0 for a model that is not a warp; a combination's deepest operand's).
#[must_use]
pub fn depth(model: &Model) -> usize {
    match model {
        Model::Warp(w) => w.depth(),
        Model::Combine(c) => c.operands.iter().map(depth).max().unwrap_or(0),
        _ => 0,
    }
}

/// How far beyond a window's positions `model` may be evaluated, pixels: `MAX_WARP` per warp
/// along the chain of bases (x and y are evaluated at the warp's own positions).
#[must_use]
pub fn reach(model: &Model) -> f64 {
    match model {
        Model::Warp(w) => (f64::from(MAX_WARP) + reach(&w.base))
            .max(reach(&w.x))
            .max(reach(&w.y)),
        Model::Combine(c) => c.operands.iter().map(reach).fold(0.0, f64::max),
        _ => 0.0,
    }
}

/// Checks that every position `model` evaluates for `window` — the window's, displaced by up to
/// [`reach`] — lies within `±MAX_POSITION` (nothing to check for a model without warps).
///
/// # Errors
/// A [`WindowError`] on `window position` naming the narrower range.
pub fn check_window(model: &Model, window: &Window) -> Result<(), WindowError> {
    let reach = reach(model);
    if reach == 0.0 || window.width == 0 || window.height == 0 {
        return Ok(());
    }
    let corners = [
        window.x(0),
        window.x(window.width - 1),
        window.y(0),
        window.y(window.height - 1),
    ];
    match corners.iter().find(|v| v.abs() > MAX_POSITION - reach) {
        Some(&value) => Err(WindowError {
            parameter: "window position",
            value,
            range: "[-(2^30 - 65536·n), 2^30 - 65536·n] model pixels for a model with n nested warps",
        }),
        None => Ok(()),
    }
}

impl crate::ModelKind for Warp {
    const PERIODIC: bool = true;

    const NAME: &'static str = "warp";

    /// A warp `base(p + d(p))` is periodic when its base and both displacements are.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        self.base.check_period(period)?;
        self.x.check_period(period)?;
        self.y.check_period(period)
    }

    fn validate(&self) -> Result<(), ModelError> {
        Warp::validate(self)
    }

    fn output_channels(&self) -> usize {
        self.base.output_channels()
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        self.base.visit_seeds(visit);
        self.x.visit_seeds(visit);
        self.y.visit_seeds(visit);
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::fixtures::constant;

    fn warp(base: Model) -> Warp {
        Warp {
            base: Box::new(base),
            x: Box::new(constant(1.0)),
            y: Box::new(constant(-1.0)),
            strength: 4.0,
        }
    }

    pub fn displacement_is_clamped_and_nan_free() {
        let w = warp(constant(0.0));
        assert_eq!(w.displacement(0.25), 1.0);
        assert_eq!(w.displacement(1e9), MAX_WARP);
        assert_eq!(w.displacement(-1e9), -MAX_WARP);
        assert_eq!(w.displacement(f32::NAN), 0.0);
        assert_eq!(w.displacement(f32::INFINITY), MAX_WARP);
    }

    pub fn validation_names_the_nested_field() {
        let mut bad_x = warp(constant(0.0));
        if let Model::Classic(c) = bad_x.x.as_mut() {
            c.cell_size = 0.0;
        }
        let mut inner = warp(constant(0.0));
        inner.strength = f32::NAN;
        let cases = [
            (bad_x, "warp.x.classic.cell_size"),
            (warp(Model::Warp(inner)), "warp.base.warp.strength"),
        ];
        for (w, field) in cases {
            match Model::Warp(w).validate() {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
        assert!(Model::Warp(warp(constant(0.5))).validate().is_ok());
    }

    pub fn depth_is_limited() {
        let mut m = constant(0.0);
        for _ in 0..MAX_WARP_DEPTH {
            m = Model::Warp(warp(m));
        }
        assert!(m.validate().is_ok());
        assert_eq!(reach(&m), f64::from(MAX_WARP) * MAX_WARP_DEPTH as f64);
        let deeper = Model::Warp(warp(m));
        match deeper.validate() {
            Err(ModelError::OutOfRange { field, value, .. }) => {
                assert_eq!((field.as_str(), value), ("warp", 9.0));
            }
            other => panic!("{other:?}"),
        }
    }

    pub fn x_and_y_must_be_grey() {
        use crate::{ColourBasis, TextureChannel, TextureModel};
        let channel = TextureChannel {
            seed: 1,
            mean: 0.5,
            strata: vec![],
            structure: None,
        };
        let colour = Model::Texture(TextureModel {
            seed: 0,
            period: 16,
            channels: vec![channel; 3],
            colour: Some(ColourBasis {
                mean: [0.5; 3],
                basis: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            }),
            turbulence: None,
            random_placement: false,
        });
        assert!(colour.validate().is_ok(), "{:?}", colour.validate());
        let mut w = warp(constant(0.0));
        w.y = Box::new(colour.clone());
        match Model::Warp(w).validate() {
            Err(ModelError::Length { field, len, .. }) => {
                assert_eq!((field.as_str(), len), ("warp.y (values per pixel)", 3));
            }
            other => panic!("{other:?}"),
        }
        // A colour base is fine.
        assert!(Model::Warp(warp(colour)).validate().is_ok());
    }

    pub fn windows_keep_displaced_positions_in_range() {
        let m = Model::Warp(warp(constant(0.0)));
        let near = MAX_POSITION - f64::from(MAX_WARP);
        assert!(check_window(&m, &Window::new(2, 2).at([near - 1.0, 0.0], 1.0)).is_ok());
        let e = check_window(&m, &Window::new(2, 2).at([near, 0.0], 1.0)).unwrap_err();
        assert_eq!(e.parameter, "window position");
        // Models without warps are not restricted further.
        assert!(check_window(&constant(0.0), &Window::new(2, 2).at([2e9, 0.0], 1.0)).is_ok());
    }

    pub fn json_round_trip_and_unknown_fields() {
        let m = Model::Warp(warp(constant(0.5)));
        let text = crate::to_json(&m).unwrap();
        assert!(text.contains("\"warp\""));
        assert_eq!(crate::from_json(&text).unwrap(), m);
        let bad = text.replace("\"strength\"", "\"strenght\"");
        assert!(matches!(crate::from_json(&bad), Err(ModelError::Json(_))));
    }
}
