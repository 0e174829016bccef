//! Tiling and blending (Heitz & Neyret 2018; `spectex_model::tiling`): both evaluators draw the
//! same vertices in integers, locate the same rhombus and triangle (every operation before the
//! taps is exact or rounds once on both sides: `½·x` is exact, so a contracted product-add
//! rounds as the two operations do) and read the same texels; they differ only by the
//! roundings a compiler may fuse or a device may widen in the taps, the blend, the look-up and
//! the colour basis, which this module bounds.

use spectex_model::TilingTexture;
use spectex_model::tiling::{Blend, LUT_ENTRIES, LUT_RANGE, TilingTables};

use super::{COS_ABS_ERROR, CheckKind, F32_UNIT_ROUNDOFF, Regularity, Tolerance};

/// Roundings of a bilinear tap that may differ: three lerps `a + f·(b − a)`, each a product and
/// a sum the GPU may contract (one rounding more or less), of values bounded by the largest
/// texel: 3, rounded up to 4 for the subtraction inside each lerp.
const TAP_ROUNDINGS: f64 = 4.0;

/// Roundings of the variance-preserving blend `G = (w₀g₀ + w₁g₁ + w₂g₂)/√Σw²` that may differ, in
/// units of `|G| ≤ √3·max|g|`: the weighted sum's 2 contractible product-adds (2), `Σw²` (2,
/// relative to a value ≥ ⅓ that the square root halves), WGSL's `sqrt` (3 ulps, inherited from
/// `inverseSqrt`) and division (2.5 ulps) against the CPU's one rounding each: 10, rounded up
/// to 12.
const BLEND_ROUNDINGS: f64 = 12.0;

/// Roundings of the table index `x = (clamp(G) + R)·scale` (a sum and a product, `x ≤ 1023`)
/// that may differ: 2, each at most half an ulp of 1024.
const INDEX_ROUNDINGS: f64 = 2.0;

/// Roundings of a value read from a table, `lut[i] + f·(lut[i+1] − lut[i])`: 2 (a contractible
/// product-add and the difference).
const LOOKUP_ROUNDINGS: f64 = 2.0;

/// The largest magnitude of the Gaussianised exemplar's values.
fn gaussian_max(m: &TilingTexture) -> f64 {
    m.gaussian
        .iter()
        .map(|g| f64::from(g.abs()))
        .fold(0.0, f64::max)
}

/// The tables' largest step between neighbouring entries and largest magnitude, over every
/// level and channel.
fn lut_bounds(tables: &TilingTables) -> (f64, f64) {
    let mut step = 0.0f64;
    let mut magnitude = 0.0f64;
    for lut in tables.luts.chunks_exact(LUT_ENTRIES) {
        for pair in lut.windows(2) {
            step = step.max(f64::from((pair[1] - pair[0]).abs()));
        }
        for v in lut {
            magnitude = magnitude.max(f64::from(v.abs()));
        }
    }
    (step, magnitude)
}

/// Per output component `i`, the bound on `|cpu − gpu|`:
/// - a tap differs by `e_tap = TAP_ROUNDINGS·u·max|g|` (`u` = [`F32_UNIT_ROUNDOFF`]), and with
///   the hex option's rotation its position by `δ = 2·reach·(COS_ABS_ERROR + 2u)` texels (two
///   cosines and a contractible product-add per axis), moving a bilinear tap by at most the
///   largest texel difference `2·max|g|` per texel on each axis: `e_tap += 4·max|g|·δ`;
/// - the blended value: the variance blend's `G` by `e_G = √3·(BLEND_ROUNDINGS·u·max|g| +
///   e_tap)` (the taps' weights sum to 1 and `1/√Σw² ≤ √3`); the hex blend reads each tap
///   itself, `e_G = e_tap`;
/// - the table: the index moves by `e_G·scale + INDEX_ROUNDINGS·u·1024` entries, the value by
///   that times the largest step between entries, plus [`LOOKUP_ROUNDINGS`] of the largest
///   entry `L`: `e_t`; the hex blend's weighted mean of three such values adds 3 contractible
///   product-adds and WGSL's 2.5-ulp division (6 roundings of `L`);
/// - the output `mean_i + Σ_c B_ic·t_c`: `Σ_c |B_ic|·e_t` plus 2 roundings per term of the
///   magnitude `M_i = |mean_i| + Σ_c |B_ic|·L`, and a minified window's level mix `v₀ + m·(v₁ −
///   v₀)` two more of `M_i` (the bound holds for every level: the tables' bounds span them all).
#[must_use]
pub fn tiling(m: &TilingTexture) -> Vec<Tolerance> {
    let u = F32_UNIT_ROUNDOFF;
    let tables = m.tables();
    let g_max = gaussian_max(m);
    let (step, l_max) = lut_bounds(&tables);
    let reach = m.lattice(None).map_or(0.0, |l| l.reach());
    let mut e_tap = TAP_ROUNDINGS * u * g_max;
    let (e_g, extra) = match m.blend {
        Blend::Variance => (3f64.sqrt() * (BLEND_ROUNDINGS * u * g_max + e_tap), 0.0),
        Blend::Hex { rotation, .. } => {
            if rotation > 0.0 {
                let delta = 2.0 * reach * (COS_ABS_ERROR + 2.0 * u);
                e_tap += 4.0 * g_max * delta;
            }
            (e_tap, 6.0 * u * l_max)
        }
    };
    let scale = (LUT_ENTRIES - 1) as f64 / (2.0 * f64::from(LUT_RANGE));
    let e_t = step * (e_g * scale + INDEX_ROUNDINGS * u * LUT_ENTRIES as f64)
        + LOOKUP_ROUNDINGS * u * l_max
        + extra;
    let nc = m.channels as usize;
    (0..nc)
        .map(|i| {
            let row = &m.basis[i * nc..(i + 1) * nc];
            let b: f64 = row.iter().map(|v| f64::from(v.abs())).sum();
            let magnitude = f64::from(m.mean[i].abs()) + b * l_max;
            let roundings = 2.0 * (nc as f64 + 1.0) + 2.0;
            Tolerance::from_max(b * e_t + roundings * u * magnitude)
        })
        .collect()
}

/// How far the value can move with the position. The value is continuous (a vertex enters or
/// leaves a pixel's triangle with weight 0, and every table is continuous), so there is no jump;
/// its slope per pixel, with `D` the largest difference between neighbouring texels of any
/// level and channel (a bilinear tap moves by at most `√2·D` per pixel: one texel per pixel,
/// rotations keep lengths), `|∇wᵢ| ≤ 1/a` for the triangles' smallest altitude `a` and
/// `T = scale·step` the tables' largest slope per unit of `g`:
/// - variance blend: `G = S/N` with `S = Σwᵢgᵢ`, `N = √Σwᵢ² ≥ 1/√3`: `|∇S| ≤ √2·D +
///   3·max|g|/a`, `|∇N| ≤ √3/a`, `|S| ≤ max|g|`, so `|∇G| ≤ √3·|∇S| + 3√3·max|g|/a`, and the
///   channel moves by `T·|∇G|`;
/// - hex blend: `t = Σ p̂ᵢ·LUT(gᵢ)` with `p̂ᵢ = wᵢᵞ/Σwⱼᵞ`: `|∇LUT(gᵢ)| ≤ T·√2·D`, and
///   `|∇p̂ᵢ| = γ·p̂ᵢ·|∇wᵢ/wᵢ − Σⱼ p̂ⱼ∇wⱼ/wⱼ| ≤ 2γ·3ᵞ/a` (`p̂ᵢ/wᵢ ≤ 1/Σwⱼᵞ ≤ 3ᵞ`), times the
///   spread `2L` of the table values, for each of the 3 weights;
/// - the output sums the channels with `Σ_c |B_ic|`; the grid is the pixel grid (positions are
///   split there, the lattice in integers).
#[must_use]
pub fn regularity(m: &TilingTexture) -> Regularity {
    let tables = m.tables();
    let nc = m.channels as usize;
    let mut d = 0.0f64;
    for lv in &tables.levels {
        let (w, h) = (lv.width as usize, lv.height as usize);
        let at = |x: usize, y: usize| tables.texels[lv.offset as usize + y * w + x];
        for y in 0..h {
            for x in 0..w {
                for (dx, dy) in [(1, 0), (0, 1)] {
                    if x + dx < w && y + dy < h {
                        let (a, b) = (at(x, y), at(x + dx, y + dy));
                        for c in 0..nc {
                            d = d.max(f64::from((a[c] - b[c]).abs()));
                        }
                    }
                }
            }
        }
    }
    let g_max = gaussian_max(m);
    let (step, l_max) = lut_bounds(&tables);
    let scale = (LUT_ENTRIES - 1) as f64 / (2.0 * f64::from(LUT_RANGE));
    let slope_t = scale * step;
    let lattice = m.lattice(None);
    // The smallest altitude: the row spacing, or for a stretched lattice the side times the
    // sine of the smallest angle, at least row·side/longest edge.
    let altitude = lattice.map_or(1.0, |l| l.row * l.side / l.reach());
    let s2 = std::f64::consts::SQRT_2;
    let s3 = 3f64.sqrt();
    let channel = match m.blend {
        Blend::Variance => {
            let grad_s = s2 * d + 3.0 * g_max / altitude;
            slope_t * (s3 * grad_s + 3.0 * s3 * g_max / altitude)
        }
        Blend::Hex { sharpness, .. } => {
            let gamma = f64::from(sharpness);
            slope_t * s2 * d + 3.0 * 2.0 * gamma * 3f64.powf(gamma) / altitude * 2.0 * l_max
        }
    };
    let (mut slope, mut magnitude) = (0.0f64, 0.0f64);
    for i in 0..nc {
        let b: f64 = m.basis[i * nc..(i + 1) * nc]
            .iter()
            .map(|v| f64::from(v.abs()))
            .sum();
        slope = slope.max(b * channel);
        magnitude = magnitude.max(f64::from(m.mean[i].abs()) + b * l_max);
    }
    // The grid positions are located on: the pixel grid (the lattice is split in integers).
    Regularity {
        slope,
        jump: 0.0,
        magnitude,
        cell: 1.0,
    }
}

impl CheckKind for TilingTexture {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(tiling(self))
    }

    fn regularity(&self) -> Option<Regularity> {
        Some(regularity(self))
    }
}
