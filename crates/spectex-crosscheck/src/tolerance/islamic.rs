//! Islamic star patterns: their tolerances.
//!
//! Both evaluators read the same f32 segment table and the same per-column and per-row lattice
//! fractions (split in f64 by `spectex_model::islamic::LatticeMap` on the host), and run the
//! same f32 loop (`spectex_model::islamic::IslamicGeometry::nearest`) and output formula. A
//! pixel's lattice fractions `s`, `t` are therefore equal on both sides (one addition, a floor
//! and a subtraction: nothing to contract); they may differ afterwards only where the GPU
//! contracts `a·b + c` into an FMA and in WGSL's `sqrt` (2.5 ulp instead of correctly
//! rounded). Below, `u = 2⁻²⁴`, lengths are in cell units unless said otherwise, `|q| ≤ 2`
//! (`q = s·e₁ + t·e₂`, `|e₁| = |e₂| = 1`), segment endpoints are below
//! [`MAX_COORDINATE`] = 4 so `|q − a| ≤ 6` and `|d| ≤ 8`.

use std::f64::consts::SQRT_2;

use spectex_model::islamic::{IslamicOutput, IslamicPattern, MAX_COORDINATE};

use super::{CheckKind, F32_UNIT_ROUNDOFF, Regularity, Tolerance};

/// Largest `|q − a|`, cell units: `|q| ≤ 2` and `|a| ≤ √2·MAX_COORDINATE` would give more;
/// the component bound `2 + MAX_COORDINATE` per axis is what each rounding sees.
const P_MAX: f64 = 2.0 + MAX_COORDINATE;

/// One side's error of the distance to the nearest segment, in units of `u·` cell units, from
/// the exact distance at its `(s, t)`:
/// - `q`: two roundings of components `≤ 2` (contracted or not): `4√2 ≈ 6`;
/// - `p = q − a`: one rounding of components `≤ P_MAX = 6`: `6√2 ≈ 9`;
/// - the projection `h`: four roundings of `p·d` (`≤ |p||d|`) and its product with `ι =
///   1/|d|²`; along the segment `|d|·δh ≤ 4·|p| ≤ 24`;
/// - `e = p − d·h`: two roundings of components `≤ P_MAX + 8` (their sum): `2·14·√2 ≈ 40`;
/// - `e·e` and `√`: `(3/2 + 2.5)·D ≤ 4` for `D ≤ 1` (every point is within a circumradius,
///   below 1, of a motif line).
///
/// Sum `≈ 82` per side.
const DISTANCE_ROUNDINGS: f64 =
    4.0 * SQRT_2 + P_MAX * SQRT_2 + 4.0 * P_MAX + 2.0 * (P_MAX + 8.0) * SQRT_2 + 4.0;

/// How far from a line one side's crossing parity may be wrong, in units of `u·` cell units:
/// a side's parity is that of a point within its `q` rounding (6) of its `q`, unless the sign
/// of a cross product `d_x·p_y − d_y·p_x` rounds wrong: three roundings of products
/// `≤ |d|·|p|`, which divided by `|d|` are a distance `≤ 3·P_MAX = 18` from the line, plus
/// `p`'s own rounding (9). Sum `≈ 33` per side.
const FLIP_ROUNDINGS: f64 = 4.0 * SQRT_2 + 3.0 * P_MAX + P_MAX * SQRT_2;

/// `|δD|` between the two sides, cell units: each side's error.
fn distance_error() -> f64 {
    2.0 * DISTANCE_ROUNDINGS * F32_UNIT_ROUNDOFF
}

/// `|δσ|` of the signed distance, cell units: where the parities agree, `|δD|`; where they
/// differ the pixel is within `2·FLIP_ROUNDINGS·u` of a line (either side's error), so
/// `|σ_cpu − σ_gpu| ≤ D_cpu + D_gpu ≤ 2·(2·FLIP_ROUNDINGS·u) + |δD|`.
fn signed_error() -> f64 {
    4.0 * FLIP_ROUNDINGS * F32_UNIT_ROUNDOFF + distance_error()
}

/// The output formulas round the same inputs the same way on both sides; a different `D`
/// changes their roundings: `hi − lo` and its product, three roundings of values at most
/// `w/2 + 1` (the band, `ι_f ≤ 1`), or `½ − σ·ι_f` (the filled region, values ≤ 1 once
/// clamped): at most `3u·(w + 2)` in `[0, 1]` units.
fn formula_error(m: &IslamicPattern) -> f64 {
    3.0 * F32_UNIT_ROUNDOFF * (f64::from(m.line_width) + 2.0)
}

impl CheckKind for IslamicPattern {
    /// In pixels (`× C`, plus the product's rounding): the signed distance by
    /// [`signed_error`]; the band, a function of `D` with slope at most `ι_f ≤ 1` per pixel
    /// (footprints are at least 1 pixel), by `|δD|·C`; the filled region, of `σ` with the
    /// same slope, by `|δσ|·C`; both plus [`formula_error`].
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        let c = f64::from(self.cell_size);
        let bound = match self.output {
            IslamicOutput::Distance => signed_error() * c + 2.0 * F32_UNIT_ROUNDOFF * c,
            IslamicOutput::Band => distance_error() * c + formula_error(self),
            IslamicOutput::Filled => signed_error() * c + formula_error(self),
        };
        Some(vec![Tolerance::from_max(bound)])
    }

    /// The signed distance is 1-Lipschitz per pixel (a distance to a set, its sign changing
    /// only where it is 0) and below `C` (every point lies within a tile's circumradius,
    /// at most `√½` period, of a motif line); the band and the filled region have slope
    /// `ι_f ≤ 1` per pixel and lie in `[0, 1]`. None jumps.
    fn regularity(&self) -> Option<Regularity> {
        let cell = f64::from(self.cell_size);
        let magnitude = match self.output {
            IslamicOutput::Distance => cell,
            IslamicOutput::Band | IslamicOutput::Filled => 1.0,
        };
        Some(Regularity {
            slope: 1.0,
            jump: 0.0,
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

    pub fn bounds_are_far_below_a_pixel() {
        // A few hundred unit roundoffs of a cell: at the largest cell (4096 px) still below
        // 0.1 px, and at the default cell a thousandth of a pixel.
        let m = IslamicPattern {
            output: IslamicOutput::Distance,
            ..IslamicPattern::default()
        };
        let t = m
            .tolerances()
            .and_then(|t| t.first().copied())
            .map(|t| t.max_abs);
        assert!(t.is_some_and(|t| t > 0.0 && t < 2e-3), "{t:?}");
        assert!(signed_error() * 4096.0 < 0.1);
    }
}
