//! Periods: a model made exactly periodic (`--periodic WxH`), so that its renders tile seamlessly.
//!
//! A [`Period`] `(W, H)` in model pixels makes a pointwise model a function with
//! `f(x + W, y) = f(x, y + H) = f(x, y)` in two steps, both needed:
//!
//! 1. **A periodic function.** Each kind hashes its lattice or impulse cells modulo the number of
//!    cells in one period ([`wrap`]), so the cells one period apart draw the same randomness and
//!    the field is continuous across the seam (a kind whose cells cannot fit a period whole says
//!    what it needs in [`ModelError::Period`]).
//! 2. **Exact evaluation.** An evaluator first reduces each position modulo the period in f64
//!    ([`reduce`]), before the usual `(cell, offset)` split, so positions one period apart are
//!    evaluated at the same bits: a `2W × 2H` render equals its four `W × H` quarters bit for bit,
//!    at any offset, and a window at `10⁷·W` is as precise as one at the origin.
//!
//! [`reduce`] is exact: for a finite `x` and an integer period `p < 2³¹`, `x mod p` is the
//! f64 remainder (`%`, exact by IEEE 754), plus `p` when negative. That last sum is exact too
//! unless `x` is a negative number so close to 0 that `x + p` rounds to `p`, which is then
//! reported as 0 — the same value `x + p` itself reduces to, so positions one period apart still
//! agree.

use crate::error::ModelError;

/// Largest period side, in model pixels (2²⁴: cell counts and positions stay exact in f32 and f64).
pub const MAX_PERIOD: u32 = 1 << 24;

/// The period of a periodic model, in model pixels along x and y (3D models: periodic in x and
/// y on every `z` plane).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Period {
    /// Period along x (`W`).
    pub width: u32,
    /// Period along y (`H`).
    pub height: u32,
}

impl Period {
    /// A `width × height` period.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming `period.width` or `period.height` outside
    /// `1..=`[`MAX_PERIOD`].
    pub fn new(width: u32, height: u32) -> Result<Self, ModelError> {
        for (field, v) in [("period.width", width), ("period.height", height)] {
            if v == 0 || v > MAX_PERIOD {
                return Err(ModelError::OutOfRange {
                    field: field.into(),
                    value: f64::from(v),
                    range: "1 to 16777216 model pixels",
                });
            }
        }
        Ok(Self { width, height })
    }

    /// The period along each axis, in model pixels.
    #[must_use]
    pub fn sides(&self) -> [f64; 2] {
        [f64::from(self.width), f64::from(self.height)]
    }

    /// `p` reduced into `[0, W) × [0, H)`, exactly ([`reduce`] per axis).
    #[must_use]
    pub fn reduce(&self, p: [f64; 2]) -> [f64; 2] {
        let [w, h] = self.sides();
        [reduce(p[0], w), reduce(p[1], h)]
    }

    /// Cells of side `side` (model pixels) in one period along each axis when a kind fits its
    /// lattice to the period: the nearest whole number, at least 1 ([`cells_in`]).
    #[must_use]
    pub fn cells(&self, side: f64) -> [i64; 2] {
        let [w, h] = self.sides();
        [cells_in(w, side), cells_in(h, side)]
    }

    /// A lattice of nominal side `side` fitted to the period (the LRP's `Δ_S` "adjusted to
    /// divide it"): `cells_in(W, side)` columns of side `W / columns` and `cells_in(H, side)` rows
    /// of side `H / rows`, computed in f64. The sides are within half a cell of `side` over the
    /// period, so the spectrum barely moves; lattice point `n` of a row sits at `n·(W/n_x)`,
    /// within rounding of `W` itself, and draws the randomness of point 0 ([`wrap`]).
    #[must_use]
    pub fn fit_lattice(&self, side: f64) -> FittedLattice {
        let cells = self.cells(side);
        let [w, h] = self.sides();
        FittedLattice {
            cells,
            side: [w / cells[0] as f64, h / cells[1] as f64],
        }
    }

    /// The largest side dividing both `W` and `H`: the largest square cell that tiles the period.
    #[must_use]
    pub fn common_side(&self) -> u32 {
        let (mut a, mut b) = (self.width, self.height);
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    }

    /// Parses `WxH` (or `W` alone for a square period), as the command line writes it.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] for a side out of range, or text that is not two positive
    /// integers (named `period`).
    pub fn parse(text: &str) -> Result<Self, ModelError> {
        let bad = || ModelError::OutOfRange {
            field: format!("period \"{text}\""),
            value: f64::NAN,
            range: "WxH with W, H whole numbers of model pixels in 1 to 16777216",
        };
        let (w, h) = match text.split_once(['x', 'X']) {
            Some((w, h)) => (w, h),
            None => (text, text),
        };
        let w: u32 = w.trim().parse().map_err(|_| bad())?;
        let h: u32 = h.trim().parse().map_err(|_| bad())?;
        Self::new(w, h)
    }

    /// The period as JSON stores it, `[W, H]`.
    #[must_use]
    pub fn to_array(&self) -> [u32; 2] {
        [self.width, self.height]
    }
}

impl std::fmt::Display for Period {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// A lattice fitted to a period ([`Period::fit_lattice`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FittedLattice {
    /// Cells per period along x and y.
    pub cells: [i64; 2],
    /// Side of a cell along x and y, in model pixels.
    pub side: [f64; 2],
}

/// `x mod period` in `[0, period)`, exactly (see the module doc); `period` a positive integer.
#[inline]
#[must_use]
pub fn reduce(x: f64, period: f64) -> f64 {
    let r = x % period;
    if r < 0.0 {
        let s = r + period;
        if s < period { s } else { 0.0 }
    } else {
        // `+ 0.0` turns a remainder of −0 (from x = −0 or a negative multiple) into +0.
        r + 0.0
    }
}

/// Lattice cell `cell` wrapped into `0..cells`: the cell whose randomness it draws in a periodic
/// model with `cells` cells per period.
#[inline]
#[must_use]
pub fn wrap(cell: i64, cells: i64) -> i64 {
    cell.rem_euclid(cells)
}

/// Cells of side `side` fitted to a period of `period` pixels: `round(period / side)`, at least 1.
/// A kind that fits its lattice to the period uses cells of side `period / cells_in(…)`.
#[must_use]
pub fn cells_in(period: f64, side: f64) -> i64 {
    ((period / side).round() as i64).max(1)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn reduce_is_exact_and_one_period_apart_agrees() {
        // Exact: every value below is representable and so is its remainder.
        assert_eq!(reduce(0.0, 256.0), 0.0);
        assert_eq!(reduce(-0.0, 256.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(reduce(256.0, 256.0), 0.0);
        assert_eq!(reduce(-0.25, 256.0), 255.75);
        assert_eq!(reduce(1.0e7 * 256.0 + 3.5, 256.0), 3.5);
        assert_eq!(reduce(-1.0e7 * 256.0 - 3.5, 256.0), 252.5);
        // A fraction with all 52 bits set survives the reduction of a far position exactly.
        let f = 0.1f64;
        assert_eq!(reduce(f + 512.0, 256.0), (f + 512.0) - 512.0);
        // A negative position too close to 0 for x + p: reported as 0, as x + p is.
        let tiny = -1e-300;
        assert_eq!(reduce(tiny, 256.0), 0.0);
        assert_eq!(reduce(tiny + 256.0, 256.0), 0.0);
        // Every integer position one period apart reduces to the same bits, both signs.
        for x in -1000i32..1000 {
            let x = f64::from(x) * 0.75;
            let (a, b) = (reduce(x, 96.0), reduce(x + 96.0, 96.0));
            assert_eq!(a.to_bits(), b.to_bits(), "x = {x}");
            assert!((0.0..96.0).contains(&a), "x = {x}: {a}");
        }
    }

    pub fn wrap_and_cells() {
        assert_eq!(wrap(-1, 7), 6);
        assert_eq!(wrap(7, 7), 0);
        assert_eq!(wrap(13, 7), 6);
        assert_eq!(cells_in(256.0, 37.3), 7);
        assert_eq!(cells_in(256.0, 1000.0), 1);
        assert_eq!(Period::new(96, 64).unwrap().cells(32.0), [3, 2]);
        assert_eq!(Period::new(96, 64).unwrap().common_side(), 32);
        assert_eq!(Period::new(7, 5).unwrap().common_side(), 1);
    }

    pub fn parse_and_range() {
        assert_eq!(
            Period::parse("256x128").unwrap(),
            Period::new(256, 128).unwrap()
        );
        assert_eq!(Period::parse("64").unwrap(), Period::new(64, 64).unwrap());
        for bad in ["0x4", "4x", "ax4", "-3x4", "4x16777217", ""] {
            let err = Period::parse(bad).unwrap_err().to_string();
            assert!(err.contains("period"), "{bad}: {err}");
        }
        assert_eq!(Period::new(3, 5).unwrap().to_string(), "3x5");
    }
}
