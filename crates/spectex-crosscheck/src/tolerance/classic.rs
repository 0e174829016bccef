//! The classic noises (`spectex_model::classic`: gradient, value, simplex and Worley bases,
//! fractal sums): their tolerance, regularity and the plane a 3D one is checked on.

use spectex_model::classic::{
    Basis, ClassicNoise, FractalKind, KENSLER2_SCALE, KENSLER3_SCALE, Metric, SIMPLEX2_R2,
    SIMPLEX2_SCALE, SIMPLEX3_R2, SIMPLEX3_SCALE, WORLEY_MAX_RING,
};

use super::{CheckKind, F32_UNIT_ROUNDOFF, Regularity, SUMMATION_ROUNDINGS, Tolerance};

/// The plane `z` (pixels) on which a 3D classic noise is checked: off the lattice planes of
/// every octave of the shipped cases (cells of 32, 24, 16 and 8 pixels, halved per octave),
/// where a zero `z` fraction would leave the `z` interpolation untested.
pub const CHECK_PLANE_Z: f64 = 37.3;

/// identical `t`: a compiler may contract `t·6 − 15` (skipping a rounding of `|6t| ≤ 6`) and
/// `(·)·t + 10` (skipping one of a product `≤ 15`); the difference then passes through products
/// by `t ≤ 1` and `t³ ≤ 1`, which round alike on both sides up to a unit roundoff of the result
/// (≤ 1): `(6 + 15 + 1)·2⁻²⁴`, rounded up to `24·2⁻²⁴`.
pub const FADE_ABS_ERROR: f64 = 24.0 * F32_UNIT_ROUNDOFF;

/// Error of a simplex corner offset (cell units, per coordinate) between the two sides. The CPU
/// rounds the f64 offset to f32 once (`1·2⁻²⁴` of a value below 1). The GPU builds the skewed
/// fraction from 2 (2D) or 3 (3D) per-axis f32 fractions, each rounded from f64 (`≤ 2⁻²⁴`), summed
/// (≤ 2 roundings of values below 3: `6·2⁻²⁴`), so the fraction is within `9·2⁻²⁴`; the offset
/// `x₀ = f_x − (Σf)·G` adds `3·9·2⁻²⁴·G ≤ 5·2⁻²⁴` (G ≤ 0.22) and 3 roundings of values ≤ 3;
/// each corner's `(x₀ − i₁) + G` rounds twice more on each side (values ≤ 1.5: `6·2⁻²⁴`). In all
/// `≤ 1 + 9 + 5 + 9 + 6 = 30` unit roundoffs, rounded up to 32.
pub const SIMPLEX_OFFSET_ERROR: f64 = 32.0 * F32_UNIT_ROUNDOFF;

/// Rounding difference of one simplex corner term `max(0, r² − |δ|²)⁴ (g·δ)` from identical
/// `δ`: contracting the squared norm skips up to 2 roundings of values ≤ 1 and the subtraction
/// rounds a value ≤ 0.6 (`Δt ≤ 3·2⁻²⁴`), amplified by `d(t⁴)/dt = 4t³ ≤ 0.87` and `|g·δ| ≤ √2·0.78`
/// (`≤ 4·2⁻²⁴`), plus the final products' roundings of a value ≤ 0.2: `5·2⁻²⁴`.
pub const SIMPLEX_TERM_ERROR: f64 = 5.0 * F32_UNIT_ROUNDOFF;

/// Rounding difference of one Kensler corner term `w(r²)·(g·δ)` from identical `δ` (the host
/// hands the GPU the CPU's f32 offsets, and `δ = u − d` is one IEEE operation on both sides):
/// `r² = (δx² + δy²) + δz²` may be contracted (2 skipped roundings of squares `< 4`) and its
/// two sums then round differing values (`< 4`): `Δr² ≤ 16·2⁻²⁴`; `t = 1 − r²/4` (the
/// quarter is exact) `Δt ≤ 4 + 1` units; `fade` amplifies by `fade' ≤ 30/16` and adds
/// [`FADE_ABS_ERROR`]: `Δw ≤ (9.4 + 24)·2⁻²⁴ ≤ 34·2⁻²⁴`. `g·δ` is `(a·δ)·c` with `a ∈ {0, ±1}`
/// (exact products: contraction changes nothing), so it is identical; `|g·δ| ≤ r < 2` where
/// `w > 0`, and the product rounds a value `< 2` on each side: `2·34 + 2·2 = 72` units.
pub const KENSLER_TERM_ERROR: f64 = 72.0 * F32_UNIT_ROUNDOFF;

/// Kensler noise's bounds in `d` dimensions: corners in the stencil `K` (16, 64), the output
/// scale, `|basis| ≤ N = scale·K·2` (each term `|w·(g·δ)| ≤ r < 2`), the sum's error
/// `scale·K·(KENSLER_TERM_ERROR + 2·2⁻²⁴·(N/scale + 2))` (the terms' differences, then each of
/// the `K` additions rounding a partial sum `≤ N/scale` on each side, a contracted product
/// `< 2` included) and the per-axis slope `scale·K·4.75`: `∂ₓ[w(r)(g·δ)] = w'(r)(δx/r)(g·δ) +
/// w·g_x` with `|w'| = |fade'(t)|·r/2 ≤ 1.875`, `|g·δ| ≤ r`, `|δx| ≤ r` and `|g_x| ≤ 1`:
/// `1.875·2 + 1`.
fn kensler_bounds(three_d: bool) -> (f64, f64, f64) {
    let (k, scale) = if three_d {
        (64.0, f64::from(KENSLER3_SCALE))
    } else {
        (16.0, f64::from(KENSLER2_SCALE))
    };
    let n = scale * k * 2.0;
    let e = scale * k * (KENSLER_TERM_ERROR + 2.0 * F32_UNIT_ROUNDOFF * (k * 2.0 + 2.0));
    (n, e, scale * k * 4.75)
}

/// Relative error of WGSL's `sqrt` (the spec inherits it from `1/inverseSqrt`: 2 + 2.5 ulps,
/// one ulp being at most `2·2⁻²⁴` relative) plus the CPU's correctly rounded one: `10 + 1` unit
/// roundoffs, and 1 more for a contracted `dx² + dy² (+ dz²)` (2 skipped roundings relative to
/// the squared distance, halved by the square root): 12.
pub const WORLEY_SQRT_ROUNDINGS: f64 = 12.0;

/// The largest Worley distance kept, cell units (`WORLEY_MAX_RING + 1`).
const WORLEY_CAP: f64 = (WORLEY_MAX_RING + 1) as f64;

/// `max |basis|` and `L`, a bound on the norm of its gradient (per cell unit), of simplex noise
/// in `d` dimensions: `d + 1` kernels `(r² − s)⁴ (g·δ)`, `s = |δ|²`, `|g| ≤ √2` (Perlin's
/// cube-edge gradients), times the output scale. `(r² − s)⁴√s` peaks at `s = r²/9`; the
/// kernel's gradient norm is at most `√2 (r² − s)³ (r² + 7s)`, which peaks at `s = r²/14`.
fn simplex_bounds(three_d: bool) -> (f64, f64) {
    let (r2, scale, corners) = if three_d {
        (f64::from(SIMPLEX3_R2), f64::from(SIMPLEX3_SCALE), 4.0)
    } else {
        (f64::from(SIMPLEX2_R2), f64::from(SIMPLEX2_SCALE), 3.0)
    };
    let s = r2 / 9.0;
    let value = (r2 - s).powi(4) * s.sqrt();
    let s = r2 / 14.0;
    let slope = (r2 - s).powi(3) * (r2 + 7.0 * s);
    let k = scale * corners * std::f64::consts::SQRT_2;
    (k * value, k * slope)
}

/// The classic noises (`spectex_model::classic`): both sides evaluate the same f32 formulas from
/// bit-identical hashes and feature points. Per octave, a bound `e` on the difference of the
/// basis and a bound `N` on `|basis|`:
/// - **gradient / value** (`d` = 2 or 3 lerp levels): the host hands the GPU the CPU's own f32
///   offsets, and a corner value is one addition of them (or an exact lattice value), so corners
///   agree bit for bit. A level `a + s(b − a)` adds `|b − a|·`[`FADE_ABS_ERROR`] and 2 roundings
///   of values ≤ `|b − a|` (a contracted product) and ≤ `N` (the sum): with `|b − a| ≤ 2N`,
///   `e = d·(2N·FADE + 4N·2⁻²⁴)`; `N = 2` for gradients (`|g·δ| ≤ |δ_u| + |δ_v| ≤ 2`), 1 for values.
/// - **simplex**: the GPU forms the offsets from per-axis skew parts, so they differ by
///   [`SIMPLEX_OFFSET_ERROR`] per coordinate, worth `L·√d·SIMPLEX_OFFSET_ERROR` with `L` the
///   noise's Lipschitz bound (`simplex_bounds`), plus `(d + 1)` corners'
///   [`SIMPLEX_TERM_ERROR`] and the 3 sums, times the output scale. A near-tie in the choice of
///   the skewed cell or of the simplex in it can make the two sides use different simplices: in
///   2D, `r² = ½` equals the squared distance from a corner to the opposite edge, so each
///   kernel vanishes there and the noise is continuous; in 3D, Gustavson's `r² = 0.6` exceeds the
///   squared corner-to-face distance ½, so the noise jumps by up to `scale·(0.6 − ½)⁴·|g·δ|`,
///   `|g·δ| ≤ √2·√½ = 1`, for the corner that leaves and the one that enters: `2·32·10⁻⁴`.
///   Such ties are not rare on a pixel grid: where `x − y` is a multiple of the cell side,
///   `x₀ = y₀` exactly, and the two sides' roundings break the tie differently (measured on
///   lavapipe: `1.04·10⁻³` at amplitude ½ in `testdata/models/classic-simplex-3d.json`).
/// - **Kensler**: the corners' offsets are the CPU's, so each term differs only by its
///   roundings ([`KENSLER_TERM_ERROR`], `kensler_bounds`); the 16 (64) terms are summed in
///   the same order on both sides.
/// - **Worley**: offsets and feature points are bit-identical; Manhattan and Chebyshev distances
///   are sums, `abs` and `max` only, so they agree exactly; a Euclidean distance differs by
///   [`WORLEY_SQRT_ROUNDINGS`] relative. `F_n`, the `n`-th smallest distance, is 1-Lipschitz in
///   the largest change of any one distance, so a near-tie between candidates may swap which
///   point is nearest but moves `F_n` no more than the distances move; so does a search that
///   stops one ring earlier or later on a near-tie with the ring's gap (the points beyond lie at
///   least the gap away). Distances are at most `7` cells, so
///   `e = Σ|C_k|·7·(WORLEY_SQRT_ROUNDINGS + 4)·2⁻²⁴` (4: the contracted, rounded sum of
///   `C_k F_k`), `N = 7·Σ|C_k|`.
///
/// The fractal sum: fBm and turbulence add `gain^o·e_o` (`|·|` is 1-Lipschitz). Ridged:
/// `s_o = (offset − |n_o|)²·clamp(w·s_{o−1}, 0, 1)` with `|offset − |n|| ≤ A = max(offset,
/// N − offset)`, so `e'_o = 2A·e_o + A²·w·e'_{o−1}`, and the sum adds `gain^o·e'_o`. Then
/// `|amplitude|` times the sum, plus [`SUMMATION_ROUNDINGS`] of the magnitudes
/// `|mean| + |amplitude|·Σ gain^o·N_o` (the accumulation, a contracted `w·n + acc`, the last
/// `mean + amplitude·acc`).
#[must_use]
pub fn classic(m: &ClassicNoise) -> Tolerance {
    let u = F32_UNIT_ROUNDOFF;
    let three_d = m.dimensions == 3;
    let d = f64::from(m.dimensions);
    let (e, n) = match &m.basis {
        Basis::Gradient | Basis::Value => {
            let n = if m.basis == Basis::Gradient { 2.0 } else { 1.0 };
            (d * (2.0 * n * FADE_ABS_ERROR + 4.0 * n * u), n)
        }
        Basis::Simplex => {
            let (n, lipschitz) = simplex_bounds(three_d);
            let (scale, corners) = if three_d {
                (f64::from(SIMPLEX3_SCALE), 4.0)
            } else {
                (f64::from(SIMPLEX2_SCALE), 3.0)
            };
            let seam = if three_d {
                2.0 * scale * (f64::from(SIMPLEX3_R2) - 0.5).powi(4)
            } else {
                0.0
            };
            let e = lipschitz * d.sqrt() * SIMPLEX_OFFSET_ERROR
                + scale * (corners * SIMPLEX_TERM_ERROR + 3.0 * u * n / scale)
                + seam;
            (e, n)
        }
        Basis::Kensler => {
            let (n, e, _) = kensler_bounds(three_d);
            (e, n)
        }
        Basis::Worley(w) => {
            let c: f64 = w.coefficients.iter().map(|c| f64::from(*c).abs()).sum();
            let per_distance = if w.metric == Metric::Euclidean {
                WORLEY_SQRT_ROUNDINGS
            } else {
                0.0
            };
            (c * WORLEY_CAP * (per_distance + 4.0) * u, c * WORLEY_CAP)
        }
    };
    let (sum, magnitude) = octave_sum(m, n, |_| e);
    let amplitude = f64::from(m.amplitude).abs();
    Tolerance::from_max(
        amplitude * sum
            + SUMMATION_ROUNDINGS * u * (f64::from(m.mean).abs() + amplitude * magnitude),
    )
}

/// A per-octave bound `t_o` (an error, a slope or a jump of the basis, `|basis| ≤ n`) carried
/// through the fractal sum: `Σ gain^o·t_o` for fBm and turbulence (`|·|` is 1-Lipschitz);
/// for ridged, `s_o = (offset − |n_o|)²·clamp(w·s_{o−1}, 0, 1)` with `|offset − |n|| ≤ A =
/// max(offset, n − offset)` gives `t'_o = 2A·t_o + A²·w·t'_{o−1}` and `Σ gain^o·t'_o`. Also
/// returns the bound on `Σ gain^o·|term|` (`n`, or `A²` for ridged).
fn octave_sum(m: &ClassicNoise, n: f64, term: impl Fn(u32) -> f64) -> (f64, f64) {
    let (mut sum, mut magnitude, mut previous) = (0.0, 0.0, 0.0);
    for o in 0..m.octaves() {
        let weight = f64::from(m.octave_weight(o)).abs();
        let t = term(o);
        match m.fractal.as_ref().map(|f| f.kind) {
            Some(FractalKind::Ridged {
                offset,
                weight_gain,
            }) => {
                let offset = f64::from(offset);
                let a = offset.max(n - offset);
                let mut carried = 2.0 * a * t;
                if o > 0 {
                    carried += a * a * f64::from(weight_gain) * previous;
                }
                previous = carried;
                sum += weight * carried;
                magnitude += weight * a * a;
            }
            _ => {
                sum += weight * t;
                magnitude += weight * n;
            }
        }
    }
    (sum, magnitude)
}

/// The classic noises, per octave in cell units (the basis `N` and its gradient norm `L`):
/// - **value**: `∂n/∂x` is a lerp of `fade'(t)·(b − a)` with `fade' ≤ 30/16` and
///   `|b − a| ≤ 2`: 3.75 per axis, `N = 1`;
/// - **gradient**: corner values `g·δ` with `|g·δ| ≤ 2` and `|∂(g·δ)/∂x| = |g_x| ≤ 1`:
///   `1.875·4 + 1 = 8.5` per axis, `N = 2`;
/// - **Kensler**: `kensler_bounds` (`scale·K·4.75` per axis, `N = scale·K·2`);
/// - **simplex**: [`simplex_bounds`]; 3D noise also jumps at simplex faces by
///   `2·scale·(0.6 − ½)⁴` (see [`classic`]);
/// - **Worley**: a distance is 1-Lipschitz in the Euclidean and Chebyshev metrics and
///   `√d`-Lipschitz in the Manhattan one, and so is `F_n` (an order statistic) and its cap:
///   `Σ|C_k|` times that, `N = 7·Σ|C_k|`.
///
/// A per-axis bound becomes a gradient norm by `√d`. Octave `o` divides by its cell side
/// `c_o` pixels; fBm and turbulence add `gain^o` times it (`|·|` is 1-Lipschitz); ridged
/// follows `s_o = (offset − |n_o|)²·clamp(w·s_{o−1}, 0, 1)`: `s'_o ≤ 2A·n'_o + A²·w·s'_{o−1}`,
/// jumps alike. Times `|amplitude|`; `cell` is the first octave's side.
fn classic_regularity(m: &ClassicNoise) -> Regularity {
    let d = f64::from(m.dimensions);
    let three_d = m.dimensions == 3;
    let (lipschitz, n, jump) = match &m.basis {
        Basis::Value => (3.75 * d.sqrt(), 1.0, 0.0),
        Basis::Gradient => (8.5 * d.sqrt(), 2.0, 0.0),
        Basis::Simplex => {
            let (n, l) = simplex_bounds(three_d);
            let seam = if three_d {
                2.0 * f64::from(SIMPLEX3_SCALE) * (f64::from(SIMPLEX3_R2) - 0.5).powi(4)
            } else {
                0.0
            };
            (l, n, seam)
        }
        Basis::Kensler => {
            let (n, _, slope) = kensler_bounds(three_d);
            (slope * d.sqrt(), n, 0.0)
        }
        Basis::Worley(w) => {
            let c: f64 = w.coefficients.iter().map(|c| f64::from(*c).abs()).sum();
            let metric = if w.metric == Metric::Manhattan {
                d.sqrt()
            } else {
                1.0
            };
            (c * metric, c * WORLEY_CAP, 0.0)
        }
    };
    let (slope, magnitude) = octave_sum(m, n, |o| lipschitz / m.octave_cell(o));
    let (jumps, _) = octave_sum(m, n, |_| jump);
    let amplitude = f64::from(m.amplitude).abs();
    Regularity {
        slope: amplitude * slope,
        jump: amplitude * jumps,
        magnitude: f64::from(m.mean).abs() + amplitude * magnitude,
        cell: m.octave_cell(0),
    }
}

impl CheckKind for ClassicNoise {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![classic(self)])
    }

    fn regularity(&self) -> Option<Regularity> {
        Some(classic_regularity(self))
    }

    fn check_plane(&self) -> f64 {
        if self.dimensions == 3 {
            CHECK_PLANE_Z
        } else {
            0.0
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::tolerance::tests::check_slope_on_fine_render;
    use crate::tolerance::tolerance;
    use spectex_model::Model;

    /// The slope bounds of the classic noises hold on fine CPU renders: along rows and columns
    /// sampled every 1/16 pixel, no step changes the value by more than `slope·step + jump`, and
    /// the bound is within a factor 12 of the steepest step seen (so it is not vacuous).
    pub fn classic_slope_bounds_hold_on_fine_renders() {
        let model = |basis: Basis, dimensions: u32, fractal: Option<FractalKind>| ClassicNoise {
            seed: 5,
            dimensions,
            cell_size: 8.0,
            basis,
            fractal: fractal.map(|kind| spectex_model::classic::Fractal {
                kind,
                octaves: 3,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude: 0.7,
            mean: 0.1,
        };
        let worley = |metric| {
            Basis::Worley(spectex_model::classic::Worley {
                metric,
                coefficients: [-1.0, 1.0, 0.0, 0.0],
                points: spectex_model::classic::FeaturePoints::Fixed(2),
            })
        };
        let ridged = FractalKind::Ridged {
            offset: 1.0,
            weight_gain: 2.0,
        };
        for (name, m) in [
            ("value", model(Basis::Value, 2, None)),
            ("gradient", model(Basis::Gradient, 2, None)),
            ("gradient 3d", model(Basis::Gradient, 3, None)),
            ("simplex", model(Basis::Simplex, 2, None)),
            (
                "worley manhattan",
                model(worley(Metric::Manhattan), 2, None),
            ),
            (
                "worley euclidean",
                model(worley(Metric::Euclidean), 2, None),
            ),
            ("fbm", model(Basis::Gradient, 2, Some(FractalKind::Fbm))),
            ("ridged", model(Basis::Value, 2, Some(ridged))),
        ] {
            let m = Model::Classic(m);
            check_slope_on_fine_render(name, &m, 12.0);
        }
    }

    fn classic_model(basis: Basis, dimensions: u32) -> ClassicNoise {
        ClassicNoise {
            seed: 0,
            dimensions,
            cell_size: 32.0,
            basis,
            fractal: None,
            amplitude: 1.0,
            mean: 0.0,
        }
    }

    /// A 3D classic noise is checked on a plane off the lattice planes of every octave of the
    /// shipped 3D cases (a zero `z` fraction would leave the `z` interpolation untested); a 2D
    /// one on `z = 0`, which it ignores.
    pub fn a_3d_noise_is_checked_off_its_lattice_planes() {
        for case in ["classic-simplex-3d", "classic-worley-3d-turbulence"] {
            let path = format!(
                "{}/../../testdata/models/{case}.json",
                env!("CARGO_MANIFEST_DIR")
            );
            let file: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
            let m: ClassicNoise = serde_json::from_value(file["model"]["classic"].clone()).unwrap();
            assert_eq!(m.dimensions, 3, "{case}");
            let z = m.check_plane();
            for o in 0..m.octaves() {
                let cell = m.octave_cell(o);
                let t = (z / cell).fract();
                assert!(
                    t > 0.01 && t < 0.99,
                    "{case}: z = {z} is at {t} of octave {o}'s cell {cell}"
                );
            }
        }
        assert_eq!(classic_model(Basis::Value, 2).check_plane(), 0.0);
    }

    /// The simplex bounds against a dense scan of one kernel's value and radial slope.
    pub fn simplex_bounds_cover_a_scan_of_the_kernel() {
        for (three_d, r2, scale, corners) in [(false, 0.5, 70.0, 3.0), (true, 0.6, 32.0, 4.0)] {
            let (n, l) = simplex_bounds(three_d);
            let (mut vmax, mut smax) = (0.0f64, 0.0f64);
            for k in 0..=100_000 {
                let r = f64::from(k) / 100_000.0 * f64::sqrt(r2);
                let t = r2 - r * r;
                // |g·δ| ≤ √2 r along g; the radial derivative of t⁴·√2·r.
                vmax = vmax.max(t.powi(4) * std::f64::consts::SQRT_2 * r);
                let slope = std::f64::consts::SQRT_2 * (t.powi(4) - 8.0 * r * r * t.powi(3)).abs();
                smax = smax.max(slope);
            }
            assert!(
                (n - scale * corners * vmax).abs() < 1e-6 * n,
                "{n} vs {vmax}"
            );
            assert!(l >= scale * corners * smax * (1.0 - 1e-9), "{l} vs {smax}");
        }
        // 2D simplex noise is known to reach about ±1 with these constants: the bound is above.
        assert!(simplex_bounds(false).0 > 1.0);
    }

    /// Bounds scale with the amplitude, grow with octaves, the 3D simplex seam dominates its
    /// bound, and Manhattan Worley is tighter than Euclidean.
    pub fn classic_bounds_follow_their_derivation() {
        use spectex_model::classic::{FeaturePoints, Fractal, Worley};
        let g = classic(&classic_model(Basis::Gradient, 2)).max_abs;
        let mut louder = classic_model(Basis::Gradient, 2);
        louder.amplitude = 2.0;
        assert!((classic(&louder).max_abs / g - 2.0).abs() < 1e-12);
        assert!(g > 0.0 && g < 1e-4, "{g}");
        let mut fbm = classic_model(Basis::Gradient, 2);
        fbm.fractal = Some(Fractal {
            kind: FractalKind::Fbm,
            octaves: 4,
            lacunarity: 2.0,
            gain: 0.5,
        });
        let f = classic(&fbm).max_abs;
        assert!(f > g && f < 2.0 * g, "{f} vs {g}");
        let s3 = classic(&classic_model(Basis::Simplex, 3)).max_abs;
        assert!(s3 > 6.4e-3 && s3 < 7e-3, "{s3}");
        let worley = |metric| {
            classic(&classic_model(
                Basis::Worley(Worley {
                    metric,
                    coefficients: [-1.0, 1.0, 0.0, 0.0],
                    points: FeaturePoints::Fixed(1),
                }),
                2,
            ))
            .max_abs
        };
        assert!(worley(Metric::Manhattan) < worley(Metric::Euclidean));
        let mut ridged = classic_model(Basis::Value, 2);
        ridged.fractal = Some(Fractal {
            kind: FractalKind::Ridged {
                offset: 1.0,
                weight_gain: 2.0,
            },
            octaves: 3,
            lacunarity: 2.0,
            gain: 0.5,
        });
        // e'_0 = 2e, e'_1 = 2e + 2e'_0 = 6e, e'_2 = 2e + 2e'_1 = 14e: Σ gain^o e'_o = 2e + 3e + 3.5e.
        let e = 2.0 * (2.0 * FADE_ABS_ERROR + 4.0 * F32_UNIT_ROUNDOFF);
        let sums = SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * (1.0 + 0.5 + 0.25);
        assert!((classic(&ridged).max_abs - (8.5 * e + sums)).abs() < 1e-15);
        assert_eq!(
            tolerance(&Model::Classic(classic_model(Basis::Value, 3))),
            Some(classic(&classic_model(Basis::Value, 3)))
        );
    }
}
