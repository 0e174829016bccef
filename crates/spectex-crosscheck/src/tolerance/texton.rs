//! Texton placement / spot noise: its tolerance and regularity.
//!
//! Both evaluators split positions by the same f64 expression (the host computes the GPU's
//! tables), draw the same textons from bit-identical integers and evaluate the same f32
//! expressions in the same order (`spectex_model::texton`), so they differ only where the GPU
//! rounds differently: a contracted `a·b + c`, WGSL's `/` and `sqrt` (2.5 ulp instead of
//! correctly rounded), and the cosine/sine polynomials under contraction.

use spectex_model::NEG_LN_20;
use spectex_model::texton::{Combine, MAX_TEXTONS_PER_CELL, Placement, Spot, TextonNoise};

use super::{
    COS_ABS_ERROR, CheckKind, EXP_REL_ERROR, F32_UNIT_ROUNDOFF, MEAN_FRACTION, Regularity,
    SUMMATION_ROUNDINGS, Tolerance, impulse_count,
};

/// Roundings of a texton's normalised coordinate `q = (c·d_x + s·d_y)/(a·s)` beyond the cosine's:
/// `d = t·C` (1), two products and a sum (3, any of which a contraction may skip), `a·s` (1),
/// the quotient (2.5 ulp in WGSL, 0.5 on the CPU) and the product by it (1): 9 on either side,
/// 18 between them, relative to `|q| ≤ √2` over the textons that matter (`ρ² < 1` on a side).
const Q_ROUNDINGS: f64 = 18.0;
/// Roundings of WGSL's `sqrt` against the CPU's correctly rounded one (2.5 ulp and 0.5 ulp),
/// and of `1 − ρ²` under it, relative to values ≤ 1.
const SQRT_ROUNDINGS: f64 = 4.0;
/// Roundings of the bilinear sample (the texel coordinate's 3 operations, the two lerps of a row
/// and the lerp between them: 9 products and sums, either side), relative to the largest
/// texel.
const BILINEAR_ROUNDINGS: f64 = 18.0;

/// What one texton's term can differ by, and by how much it can jump where a rounding moves it
/// across the edge of its support (`ρ² = 1`), for a weight of magnitude 1.
struct Term {
    smooth: f64,
    jump: f64,
}

/// The error of `ρ² = q_u² + q_v²` between the two sides, for the textons inside the support on
/// either side: `|δq| ≤ 2·COS_ABS_ERROR·√2·aspect + Q_ROUNDINGS·u` per coordinate (the rotation's
/// cosine and sine errors times `|d|/(min(a, b)·s) ≤ aspect = max(a, b)/min(a, b)`), and
/// `|δρ²| ≤ 2·√2·(|δq_u| + |δq_v|)` plus the sum's own rounding.
fn rho2_error(m: &TextonNoise) -> (f64, f64) {
    let (a, b) = (f64::from(m.radii[0]), f64::from(m.radii[1]));
    let aspect = a.max(b) / a.min(b);
    let dq =
        2.0 * COS_ABS_ERROR * std::f64::consts::SQRT_2 * aspect + Q_ROUNDINGS * F32_UNIT_ROUNDOFF;
    let dr2 = 2.0 * std::f64::consts::SQRT_2 * 2.0 * dq + 2.0 * F32_UNIT_ROUNDOFF;
    (dq, dr2)
}

/// One texton's term per unit weight, by spot:
/// - ellipsoid `√(1 − ρ²)`: ½-Hölder, `|√x − √y| ≤ √|x − y|`, so `√δρ²` (which also bounds a
///   texton entering or leaving: its value there is at most `√δρ²`), plus the square root's
///   roundings;
/// - Gaussian `exp(−ln 20·ρ²)`: slope `ln 20` in `ρ²` and [`EXP_REL_ERROR`] on either side; a
///   texton crossing `ρ² = 1` jumps by its truncation, 5% of its peak;
/// - image: the bilinear sample's slope `step·max(W, H)/2` per unit of `q` (`step` the largest
///   difference between neighbouring texels) times `|δq|`, its roundings; crossing the edge
///   jumps by the largest texel.
fn term(m: &TextonNoise) -> Term {
    let (dq, dr2) = rho2_error(m);
    let u = F32_UNIT_ROUNDOFF;
    match &m.spot {
        Spot::Ellipsoid => Term {
            smooth: dr2.sqrt() + SQRT_ROUNDINGS * u,
            jump: 0.0,
        },
        Spot::Gaussian => Term {
            smooth: f64::from(-NEG_LN_20) * dr2 + 2.0 * EXP_REL_ERROR,
            jump: 0.05,
        },
        Spot::Image { .. } => {
            let shape = shape(&m.spot);
            Term {
                smooth: shape.step * shape.side * dq + BILINEAR_ROUNDINGS * u * shape.peak,
                jump: shape.peak,
            }
        }
    }
}

/// What the tolerances need of a spot's shape: its largest `|g|`, and for an image the largest
/// step between neighbouring texels and its longer side (the bilinear sample's slope is
/// `step·side/2` per unit of `q`).
struct Shape {
    peak: f64,
    step: f64,
    side: f64,
}

fn shape(spot: &Spot) -> Shape {
    let Spot::Image {
        width,
        height,
        values,
    } = spot
    else {
        // √(1 − ρ²) and exp(−ln 20·ρ²) peak at 1 and have no texels.
        return Shape {
            peak: 1.0,
            step: 0.0,
            side: 0.0,
        };
    };
    let (w, h) = (*width as usize, *height as usize);
    let texel = |x: usize, y: usize| f64::from(values[y * w + x]);
    let mut step = 0.0f64;
    for y in 0..h {
        for x in 0..w {
            if x + 1 < w {
                step = step.max((texel(x + 1, y) - texel(x, y)).abs());
            }
            if y + 1 < h {
                step = step.max((texel(x, y + 1) - texel(x, y)).abs());
            }
        }
    }
    Shape {
        peak: values
            .iter()
            .fold(0.0f64, |a, &v| a.max(f64::from(v).abs())),
        step,
        side: (*width).max(*height) as f64,
    }
}

/// How many textons' errors add up at a pixel: every one visited under the addition rule, one
/// under the maximum rule (a maximum is 1-Lipschitz in each argument).
fn combined_terms(m: &TextonNoise) -> f64 {
    match m.combine {
        Combine::Sum => texton_count(m),
        Combine::Max => 1.0,
    }
}

/// A pixel's bound on the textons it visits: `(2·reach + 1)²` cells of one texton (grid), or of
/// a Poisson count of mean `density` (bounded as Gabor's impulses are, and never beyond the
/// cap of 16 per cell).
fn texton_count(m: &TextonNoise) -> f64 {
    let side = f64::from(2 * m.reach() + 1);
    let cells = side * side;
    match m.placement {
        Placement::Grid { .. } => cells,
        Placement::Poisson { density } => {
            impulse_count(cells, f64::from(density)).min(cells * f64::from(MAX_TEXTONS_PER_CELL))
        }
    }
}

/// The largest weight magnitude.
fn weight(m: &TextonNoise) -> f64 {
    f64::from(m.intensity[0].abs().max(m.intensity[1].abs()))
}

/// The tolerance: per texton `W·(smooth + jump)` with `W` the largest weight, summed over the
/// textons a pixel visits for the addition rule, or taken once for the maximum rule (a maximum
/// is 1-Lipschitz in each argument), plus the summation's roundings of the summed magnitude.
///
/// The mean bound counts the jumps only on their share of the pixels: a texton can cross its
/// edge only where `|ρ² − 1| ≤ δρ²`, an annulus of area `π·a·b·s²·δρ²` (the ellipse's area is
/// linear in `ρ²`), against the `C²` pixels of a cell per texton.
#[must_use]
pub fn texton(m: &TextonNoise) -> Tolerance {
    let t = term(m);
    let w = weight(m);
    let n = texton_count(m);
    let terms = combined_terms(m);
    let magnitude = n * w * shape(&m.spot).peak + f64::from(m.mean).abs();
    let rounding = SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * magnitude;
    let smooth = terms * w * t.smooth + rounding;
    let (_, dr2) = rho2_error(m);
    let (a, b) = (f64::from(m.radii[0]), f64::from(m.radii[1]));
    let s = f64::from(m.scale[0].max(m.scale[1]));
    let cell = f64::from(m.cell_size);
    let edge_share = (std::f64::consts::PI * a * b * s * s * dr2 / (cell * cell)).min(1.0);
    Tolerance {
        max_abs: smooth + terms * w * t.jump,
        mean_abs: MEAN_FRACTION * smooth + n * w * t.jump * edge_share,
    }
}

impl CheckKind for TextonNoise {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![texton(self)])
    }

    /// The Gaussian and image spots are Lipschitz inside their support (slopes `2·ln 20/r` per
    /// unit `ρ` and `step·max(W, H)/(2r)`, with `r = min(a, b)·min s`) and jump at its edge; the
    /// ellipsoid's slope is unbounded at its edge (`√(1 − ρ²)`), so no regularity is derived
    /// for it and a warp over it is not cross-checked.
    fn regularity(&self) -> Option<Regularity> {
        let w = weight(self);
        let r = f64::from(self.radii[0].min(self.radii[1]) * self.scale[0].min(self.scale[1]));
        let shape = shape(&self.spot);
        let (slope, jump) = match &self.spot {
            Spot::Ellipsoid => return None,
            Spot::Gaussian => (2.0 * f64::from(-NEG_LN_20) / r, 0.05),
            Spot::Image { .. } => (shape.step * shape.side / (2.0 * r), shape.peak),
        };
        let terms = combined_terms(self);
        Some(Regularity {
            slope: terms * w * slope,
            jump: terms * w * jump,
            magnitude: texton_count(self) * w * shape.peak + f64::from(self.mean).abs(),
            cell: f64::from(self.cell_size),
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn the_sum_bound_grows_with_the_textons_and_the_maximum_does_not() {
        let sparse = TextonNoise::default();
        let dense = TextonNoise {
            placement: Placement::Poisson { density: 6.0 },
            ..TextonNoise::default()
        };
        assert!(texton(&dense).max_abs > texton(&sparse).max_abs);
        let max = |m: TextonNoise| TextonNoise {
            combine: Combine::Max,
            ..m
        };
        // The default texton reaches 14·1.25 = 17.5 px < C = 32 px: 3×3 cells. Sparse: 9
        // textons; dense: a Poisson count of mean 9·6 = 54 bounded by 54 + 6√54 + 6 (under the
        // cap 9·16). Weights reach 1 (the default range [0.5, 1]).
        let extra = (54.0 + 6.0 * 54.0f64.sqrt() + 6.0) - 9.0;
        let (a, b) = (texton(&max(sparse)).max_abs, texton(&max(dense)).max_abs);
        // Only the summation term, which counts the textons' magnitude, differs.
        let summation = SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * extra;
        assert!((b - a - summation).abs() < 1e-12, "{a} vs {b}");
    }

    pub fn the_ellipsoid_bound_is_the_square_root_of_the_rho2_error() {
        let m = TextonNoise {
            intensity: [1.0, 1.0],
            placement: Placement::Grid { jitter: 0.0 },
            combine: Combine::Max,
            mean: 0.0,
            ..TextonNoise::default()
        };
        let (_, dr2) = rho2_error(&m);
        let t = texton(&m);
        assert!(t.max_abs >= dr2.sqrt());
        // Well below 1% of the unit height for the default aspect (2): the bound is usable.
        assert!(t.max_abs < 0.01, "{}", t.max_abs);
    }
}
