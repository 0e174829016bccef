//! The classic pointwise noises of the survey (Dong et al. 2020, §2.5 and §3.2): lattice
//! gradient noise (Perlin 2002), simplex noise (Perlin 2001, as written by Gustavson 2005),
//! value noise, Worley cellular noise (Worley 1996) and their fractal sums (fBm, turbulence,
//! Musgrave's ridged multifractal), in 2D or 3D.
//!
//! # Definitions
//!
//! A position `x` in pixels is divided by the octave's cell side `c_o = cell_size / λ^o`
//! (f64, exact division), split into its integer cell and an f32 offset in `[0, 1)` (the
//! split is exact in f64, rounded to f32 once), so a render at `(10⁷, 10⁷)` is as precise as
//! one at the origin (DESIGN invariant 2).
//!
//! - **Gradient** (Perlin, "Improving Noise", SIGGRAPH 2002): `n = lerp` over the cell's
//!   corners of `g_c · (x − c)` with weights `fade(t) = t³(t(6t − 15) + 10)`; the gradient of a
//!   corner is Perlin's 12 cube-edge directions padded to 16 ([`gradient_dot`]), chosen by the
//!   top four bits of the corner's [`cell_hash`](crate::random::cell_hash) instead of Perlin's
//!   permutation table. In 2D the same set is used with `z = 0`. `n = 0` at every lattice point.
//! - **Simplex** (Perlin 2001; Gustavson, "Simplex noise demystified", 2005): skew by
//!   `F = (√(d+1) − 1)/d`, unskew by `G = (1 − 1/√(d+1))/d`; each of the `d + 1` simplex corners
//!   adds `max(0, r² − |δ|²)⁴ · (g_c · δ)` with `r² = ½` (2D) or `0.6` (3D), times 70 (2D) or
//!   32 (3D), with the same gradient set.
//! - **Kensler** (Kensler, Knoll & Shirley, "Better Gradient Noise", UUSCI-2008-001; survey
//!   §3.2.3): gradient noise with the report's two planar changes, the xor hash and the
//!   extended, radially symmetric reconstruction kernel. Corner `c` adds
//!   `w(|x − c|) · (g_c · (x − c))` with `w(r) = fade(1 − r²/4)` for `r < 2` and 0 beyond
//!   ([`kensler_weight`], [`KENSLER_RADIUS2`]): a 4×4 (4×4×4) stencil instead of Perlin's 2×2
//!   (2×2×2) tensor-product lerp, so the spectrum is isotropic (for gradients whose second
//!   moment `E[g gᵀ] = I/d`). Hash: Perlin's nested `P[P[P[i] + j] + k]` becomes a xor of
//!   independent per-axis tables, `H = P_x[i] ⊕ P_y[j] ⊕ P_z[k]` (report §2), with each table
//!   an entry of the randomness contract, `P_a[n] = cell_hash(n, a, o, seed)`, instead of a
//!   256-entry permutation (so the noise does not repeat every 256 cells), and the gradient
//!   table `G[H]` the hash `hash(H)` ([`kensler_dot`]): 8 unit directions at multiples of 45°
//!   in 2D, Perlin's 12 cube-edge directions normalised in 3D. Output `KENSLER{2,3}_SCALE ·
//!   Σ`, standard deviation ¼. The report's third change (the stencil projected onto a surface
//!   normal, for 2D slices of 3D noise) is not implemented: a 3D model is rendered on a plane
//!   `z` with the full 3D stencil. Departure: the report's text was not at hand (only its
//!   abstract and figure captions, and the survey's summary); the kernel's form and radius
//!   here are our reading of "extended reconstruction kernel", stated so it can be checked.
//! - **Value**: lattice values `2·unit_f32(h) − 1 ∈ [−1, 1)` interpolated with the same fade.
//! - **Worley** (Worley 1996; survey §2.5): feature points per cell (a fixed count, or a Poisson
//!   count), `F_n` the distance from `x` to its `n`-th nearest point in cell units under the
//!   chosen metric, and the value `C₁F₁ + C₂F₂ + C₃F₃ + C₄F₄`. Points are searched ring by
//!   ring until `F_n` (the largest `n` with `C_n ≠ 0`) is at most the distance to the unsearched
//!   cells, up to [`WORLEY_MAX_RING`] rings; distances are capped at `WORLEY_MAX_RING + 1` cells.
//! - **Fractal** (survey §3.1.4 and §3.2.1): octave `o` evaluates the basis on cells of side
//!   `c_o` with its own random layer `o` and weight `gain^o`: fBm `Σ gain^o n_o`, turbulence
//!   `Σ gain^o |n_o|`, ridged (Musgrave, "Texturing and Modeling", ch. 16) `Σ gain^o s_o` with
//!   `s_0 = (offset − |n_0|)²`, `s_o = (offset − |n_o|)² · clamp(weight_gain·s_{o−1}, 0, 1)`.
//!
//! The value is `mean + amplitude · (fractal sum, or the basis alone)`.
//!
//! # Randomness contract (layers = octaves)
//!
//! 2D corner `(i, j)` of octave `o` hashes to `cell_hash(i, j, o, seed)`; 3D corner `(i, j, k)`
//! to `cell_hash(i, j, o, cell_hash(k, 0, o, seed))` (as phasor noise does). Gradient and
//! simplex take the gradient index `h >> 28`, value noise `unit_f32(h)`. Kensler
//! noise xors per-axis entries `cell_hash(n, a, o, seed)` (axis `a` = 0, 1, 2) and takes its
//! gradient from `hash` of the xor ([`kensler_dot`]). A Worley cell seeds
//! `Prng::new(h)` and draws, in order: for a Poisson count one uniform `u`, the count being the
//! number of `k ∈ 0..WORLEY_MAX_POINTS` with `u ≥ P(N ≤ k)` (the CDF rounded to f32); then per
//! point its offsets `x`, `y` (and `z`) with `next_f32`.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_level, check_range};

pub(crate) mod builder;
pub use builder::{ClassicNoiseBuilder, FractalNoiseBuilder};

/// Most octaves of a fractal sum.
pub const MAX_OCTAVES: u32 = 16;
/// Most feature points in one Worley cell (fixed counts and the Poisson count's cap).
pub const WORLEY_MAX_POINTS: u32 = 16;
/// Rings of cells searched around a point's cell at most, for Worley `F_n`.
pub const WORLEY_MAX_RING: i32 = 6;
/// Squared support radius of Kensler noise's kernel, cell units: `w(r) = 0` for `r² ≥ 4`.
pub const KENSLER_RADIUS2: f32 = 4.0;
/// Output scale of 2D Kensler noise: `¼/σ`, `σ² = ½∫ w(|δ|)²|δ|² dδ = 2.230395` the variance
/// of the unscaled sum (closed form of a sum of independent corners with `E[g gᵀ] = I/2`, the
/// integral in f64 by the midpoint rule).
pub const KENSLER2_SCALE: f32 = 0.167_397_57;
/// Output scale of 3D Kensler noise: `¼/σ`, `σ² = ⅓∫ w(|δ|)²|δ|² dδ = 3.334172` (averaged over
/// the plane's `z`).
pub const KENSLER3_SCALE: f32 = 0.136_913_4;

/// Smallest cell side of the finest octave, in pixels: cells stay `i32` over the whole
/// position range (`|x| ≤ 2³⁰`), skewed simplex coordinates included (`1.74·2³⁰ < 2³¹`).
pub const MIN_CELL_SIZE: f64 = 1.0;

/// `(√3 − 1)/2`, the 2D simplex skew factor.
pub const SIMPLEX_F2: f64 = 0.366_025_403_784_438_6;
/// `(3 − √3)/6`, the 2D simplex unskew factor.
pub const SIMPLEX_G2: f64 = 0.211_324_865_405_187_13;
/// `1/3`, the 3D simplex skew factor.
pub const SIMPLEX_F3: f64 = 1.0 / 3.0;
/// `1/6`, the 3D simplex unskew factor.
pub const SIMPLEX_G3: f64 = 1.0 / 6.0;
/// Squared kernel radius and output scale of 2D simplex noise (Gustavson 2005).
pub const SIMPLEX2_R2: f32 = 0.5;
/// Output scale of 2D simplex noise.
pub const SIMPLEX2_SCALE: f32 = 70.0;
/// Squared kernel radius of 3D simplex noise (Perlin 2001, Gustavson 2005).
pub const SIMPLEX3_R2: f32 = 0.6;
/// Output scale of 3D simplex noise.
pub const SIMPLEX3_SCALE: f32 = 32.0;

/// A classic pointwise noise: a basis function, optionally summed over octaves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClassicNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// 2 (a plane) or 3 (a volume, rendered on a plane `z`).
    pub dimensions: u32,
    /// Side of a lattice cell of the first octave, pixels.
    pub cell_size: f32,
    /// The basis function.
    pub basis: Basis,
    /// A fractal sum of the basis over octaves; the basis alone if absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fractal: Option<Fractal>,
    /// Factor applied to the (fractal) value.
    pub amplitude: f32,
    /// Constant added after the factor.
    pub mean: f32,
}

/// The basis function of a [`ClassicNoise`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Basis {
    /// Improved Perlin gradient noise (2002).
    Gradient,
    /// Simplex noise.
    Simplex,
    /// Value noise.
    Value,
    /// Kensler, Knoll & Shirley's better gradient noise (2008): xor hash, radial kernel.
    Kensler,
    /// Worley cellular noise.
    Worley(Worley),
}

/// Worley cellular noise: `C₁F₁ + C₂F₂ + C₃F₃ + C₄F₄` (survey §2.5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Worley {
    /// The distance.
    pub metric: Metric,
    /// `[C₁, C₂, C₃, C₄]`; `[1, 0, 0, 0]` is `F₁`, `[-1, 1, 0, 0]` is `F₂ − F₁`.
    pub coefficients: [f32; 4],
    /// How many feature points a cell holds.
    pub points: FeaturePoints,
}

/// The distance of Worley noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    /// `√(Σ δᵢ²)`.
    Euclidean,
    /// `Σ |δᵢ|`.
    Manhattan,
    /// `max |δᵢ|`.
    Chebyshev,
}

/// Feature points per Worley cell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum FeaturePoints {
    /// Exactly this many points in every cell (1 is the jittered grid of most libraries).
    Fixed(u32),
    /// A Poisson count of this mean (Worley 1996), capped at [`WORLEY_MAX_POINTS`].
    Poisson(f32),
}

/// A fractal sum over octaves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fractal {
    /// How octaves are combined.
    pub kind: FractalKind,
    /// Number of octaves.
    pub octaves: u32,
    /// Frequency ratio `λ` between octaves.
    pub lacunarity: f32,
    /// Amplitude ratio between octaves (`λ^{−H}` in Musgrave's notation).
    pub gain: f32,
}

/// How the octaves of a [`Fractal`] are combined.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum FractalKind {
    /// Fractional Brownian motion: `Σ gain^o n_o`.
    Fbm,
    /// Turbulence: `Σ gain^o |n_o|`.
    Turbulence,
    /// Musgrave's ridged multifractal.
    Ridged {
        /// Musgrave's `offset` (1 in his examples).
        offset: f32,
        /// Musgrave's `gain`, which weights each octave by the previous signal (2 in his
        /// examples).
        weight_gain: f32,
    },
}

impl FeaturePoints {
    /// The Poisson CDF `P(N ≤ k)` for `k < WORLEY_MAX_POINTS`, rounded to f32 (f64 sums); for a
    /// fixed count, `None`.
    #[must_use]
    pub fn poisson_cdf(&self) -> Option<[f32; WORLEY_MAX_POINTS as usize]> {
        let Self::Poisson(mean) = *self else {
            return None;
        };
        Some(crate::random::poisson_cdf(f64::from(mean)))
    }

    /// The most points a cell can hold.
    #[must_use]
    pub fn max_count(&self) -> u32 {
        match *self {
            Self::Fixed(n) => n,
            Self::Poisson(_) => WORLEY_MAX_POINTS,
        }
    }
}

impl Worley {
    /// The largest `n` with `C_n ≠ 0` (at least 1): how many nearest distances are needed.
    #[must_use]
    pub fn needed(&self) -> usize {
        self.coefficients
            .iter()
            .rposition(|&c| c != 0.0)
            .map_or(1, |i| i + 1)
    }
}

impl ClassicNoise {
    /// Octaves evaluated (1 without a fractal).
    #[must_use]
    pub fn octaves(&self) -> u32 {
        self.fractal.as_ref().map_or(1, |f| f.octaves)
    }

    /// Cell side of octave `o`, pixels: `cell_size / λ^o` in f64.
    #[must_use]
    pub fn octave_cell(&self, o: u32) -> f64 {
        let lacunarity = self
            .fractal
            .as_ref()
            .map_or(1.0, |f| f64::from(f.lacunarity));
        f64::from(self.cell_size) / lacunarity.powi(o as i32)
    }

    /// Weight `gain^o` of octave `o` (1 without a fractal), f64 rounded to f32.
    #[must_use]
    pub fn octave_weight(&self, o: u32) -> f32 {
        let gain = self.fractal.as_ref().map_or(1.0, |f| f64::from(f.gain));
        gain.powi(o as i32) as f32
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "classic.dimensions".into(),
            f64::from(self.dimensions),
            2.0,
            3.0,
            "2 or 3",
        )?;
        check_range(
            || "classic.cell_size".into(),
            f64::from(self.cell_size),
            MIN_CELL_SIZE,
            1e6,
            "[1, 1e6] pixels",
        )?;
        check_level(|| "classic.amplitude".into(), self.amplitude)?;
        check_level(|| "classic.mean".into(), self.mean)?;
        if let Basis::Worley(w) = &self.basis {
            for (i, c) in w.coefficients.iter().enumerate() {
                check_range(
                    || format!("classic.basis.worley.coefficients[{i}]"),
                    f64::from(*c),
                    -1e3,
                    1e3,
                    "[-1000, 1000]",
                )?;
            }
            match w.points {
                FeaturePoints::Fixed(n) => check_range(
                    || "classic.basis.worley.points.fixed".into(),
                    f64::from(n),
                    1.0,
                    f64::from(WORLEY_MAX_POINTS),
                    "1 to 16 points per cell",
                )?,
                FeaturePoints::Poisson(mean) => check_range(
                    || "classic.basis.worley.points.poisson".into(),
                    f64::from(mean),
                    0.5,
                    4.0,
                    "[0.5, 4] points per cell on average",
                )?,
            }
        }
        if let Some(f) = &self.fractal {
            check_range(
                || "classic.fractal.octaves".into(),
                f64::from(f.octaves),
                1.0,
                f64::from(MAX_OCTAVES),
                "1 to 16",
            )?;
            check_range(
                || "classic.fractal.lacunarity".into(),
                f64::from(f.lacunarity),
                1.0,
                16.0,
                "[1, 16]",
            )?;
            check_range(
                || "classic.fractal.gain".into(),
                f64::from(f.gain),
                0.0,
                2.0,
                "[0, 2]",
            )?;
            if let FractalKind::Ridged {
                offset,
                weight_gain,
            } = f.kind
            {
                check_range(
                    || "classic.fractal.kind.ridged.offset".into(),
                    f64::from(offset),
                    0.0,
                    4.0,
                    "[0, 4]",
                )?;
                check_range(
                    || "classic.fractal.kind.ridged.weight_gain".into(),
                    f64::from(weight_gain),
                    0.0,
                    16.0,
                    "[0, 16]",
                )?;
            }
            let finest = self.octave_cell(f.octaves - 1);
            if finest < MIN_CELL_SIZE {
                return Err(ModelError::OutOfRange {
                    field: "classic.fractal.octaves".into(),
                    value: f64::from(f.octaves),
                    range: "at most as many as keep the finest cell, cell_size / lacunarity^(octaves − 1), at least 1 pixel",
                });
            }
        }
        Ok(())
    }
}

/// `6t⁵ − 15t⁴ + 10t³` by Horner's rule in f32 (Perlin 2002): `fade(0) = 0`, `fade(1) = 1`
/// exactly.
#[inline(always)]
#[must_use]
pub fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// `g · (x, y, z)` for the gradient chosen by the top four bits of the corner hash `h`:
/// Perlin's `grad(hash, x, y, z)` of "Improving Noise" (the 12 directions `(±1, ±1, 0)`,
/// `(±1, 0, ±1)`, `(0, ±1, ±1)`, with `(1, 1, 0)`, `(−1, 1, 0)`, `(0, −1, 1)`, `(0, −1, −1)`
/// repeated to make 16). Branch-free: selects and a sign-bit flip, so lanes vectorise.
#[inline(always)]
#[must_use]
pub fn gradient_dot(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let g = h >> 28;
    let u = if g < 8 { x } else { y };
    let v = if g < 4 {
        y
    } else if g == 12 || g == 14 {
        x
    } else {
        z
    };
    let u = f32::from_bits(u.to_bits() ^ ((g & 1) << 31));
    let v = f32::from_bits(v.to_bits() ^ ((g & 2) << 30));
    u + v
}

/// Kensler noise's radial kernel `w(r) = fade(1 − r²/4)` of the squared distance `r2` (cell
/// units), 0 for `r2 ≥ 4`: 1 at the corner, `C²` where it reaches 0.
#[inline(always)]
#[must_use]
pub fn kensler_weight(r2: f32) -> f32 {
    let t = 1.0 - r2 * 0.25;
    if t > 0.0 { fade(t) } else { 0.0 }
}

/// `(a_x, a_y, c)` of the 2D direction `k` (`k·45°`): the gradient is `c·(a_x, a_y)`, with
/// `a` in `{0, ±1}` so that `a·δ` is exact and `c` = 1 or `1/√2`.
const KENSLER2_DIRECTIONS: [(f32, f32); 8] = [
    (1.0, 0.0),
    (1.0, 1.0),
    (0.0, 1.0),
    (-1.0, 1.0),
    (-1.0, 0.0),
    (-1.0, -1.0),
    (0.0, -1.0),
    (1.0, -1.0),
];

/// Perlin's 12 cube-edge directions `(±1, ±1, 0)`, `(±1, 0, ±1)`, `(0, ±1, ±1)`, before the
/// `1/√2` that makes them unit.
const KENSLER3_DIRECTIONS: [(f32, f32, f32); 12] = [
    (1.0, 1.0, 0.0),
    (-1.0, 1.0, 0.0),
    (1.0, -1.0, 0.0),
    (-1.0, -1.0, 0.0),
    (1.0, 0.0, 1.0),
    (-1.0, 0.0, 1.0),
    (1.0, 0.0, -1.0),
    (-1.0, 0.0, -1.0),
    (0.0, 1.0, 1.0),
    (0.0, -1.0, 1.0),
    (0.0, 1.0, -1.0),
    (0.0, -1.0, -1.0),
];

/// Kensler noise's corner hash from its per-axis entries `P_x[i] ⊕ P_y[j] (⊕ P_z[k])`: `g · δ`
/// for the unit gradient `G[h]` chosen by `hash(h)`: in 2D (`three_d = false`) direction
/// `hash(h) >> 29` of 8 at multiples of 45°, in 3D direction `hash(h) % 12` of Perlin's cube
/// edges over `√2`. Both sets have `E[g gᵀ] = I/d`. `a·δ` is computed with `a ∈ {0, ±1}` (exact
/// products) in the order x, y, z, then multiplied by 1 or `1/√2` (f32).
#[inline(always)]
#[must_use]
pub fn kensler_dot(h: u32, x: f32, y: f32, z: f32, three_d: bool) -> f32 {
    let g = crate::random::hash(h);
    if three_d {
        let (ax, ay, az) = KENSLER3_DIRECTIONS[(g % 12) as usize];
        ((ax * x + ay * y) + az * z) * std::f32::consts::FRAC_1_SQRT_2
    } else {
        let k = (g >> 29) as usize;
        let (ax, ay) = KENSLER2_DIRECTIONS[k];
        let c = if k & 1 == 1 {
            std::f32::consts::FRAC_1_SQRT_2
        } else {
            1.0
        };
        (ax * x + ay * y) * c
    }
}

/// Value noise's lattice value `2·unit_f32(h) − 1 ∈ [−1, 1)`: exact in f32.
#[inline(always)]
#[must_use]
pub fn lattice_value(h: u32) -> f32 {
    ((h >> 8) as i32) as f32 * (2.0 / 16_777_216.0) - 1.0
}

impl crate::ModelKind for ClassicNoise {
    const PERIODIC: bool = true;

    /// Gradient, value and Worley noises whose every octave's cell divides the period (a whole
    /// number of cells per period along x and y: the lattice wraps); simplex noise's skewed
    /// lattice has no periodic form here.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let refuse = |requirement: String| {
            Err(ModelError::Period {
                period: period.to_string(),
                kind: "classic",
                requirement,
            })
        };
        if self.basis == Basis::Simplex {
            return refuse(
                "simplex noise has no periodic form (its lattice is skewed); use gradient, value \
                 or Worley noise"
                    .into(),
            );
        }
        for o in 0..self.octaves() {
            let side = self.octave_cell(o);
            for (axis, p) in [("width", period.width), ("height", period.height)] {
                if f64::from(p) % side != 0.0 {
                    return refuse(format!(
                        "octave {o}'s cell of {side} pixels does not divide the period's {axis} \
                         {p}; the period must be a multiple of every octave's cell (cell_size / \
                         lacunarity^o: take a whole lacunarity such as 2 and a period that is a \
                         multiple of cell_size)"
                    ));
                }
            }
        }
        Ok(())
    }

    const NAME: &'static str = "classic";

    fn validate(&self) -> Result<(), ModelError> {
        ClassicNoise::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    fn perlin() -> ClassicNoise {
        ClassicNoise {
            seed: 3,
            dimensions: 2,
            cell_size: 32.0,
            basis: Basis::Gradient,
            fractal: Some(Fractal {
                kind: FractalKind::Fbm,
                octaves: 6,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude: 1.0,
            mean: 0.0,
        }
    }

    /// Perlin's reference `grad` written with branches, as in "Improving Noise".
    fn perlin_grad(h: u32, x: f32, y: f32, z: f32) -> f32 {
        let h = h & 15;
        let u = if h < 8 { x } else { y };
        let v = if h < 4 {
            y
        } else if h == 12 || h == 14 {
            x
        } else {
            z
        };
        (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
    }

    pub fn gradient_dot_is_perlins_grad() {
        for g in 0..16u32 {
            for (x, y, z) in [(0.3f32, -0.7f32, 0.25f32), (-1.0, 0.5, 0.125)] {
                let got = gradient_dot(g << 28 | 12345, x, y, z);
                assert_eq!(got.to_bits(), perlin_grad(g, x, y, z).to_bits(), "g = {g}");
            }
        }
    }

    pub fn fade_and_lattice_values_hit_their_ends() {
        assert_eq!(fade(0.0), 0.0);
        assert_eq!(fade(1.0), 1.0);
        assert_eq!(fade(0.5), 0.5);
        assert_eq!(lattice_value(0), -1.0);
        assert_eq!(lattice_value(u32::MAX), 1.0 - 2.0 / 16_777_216.0);
    }

    pub fn poisson_cdf_matches_the_pmf_sum() {
        let cdf = FeaturePoints::Poisson(2.0).poisson_cdf().unwrap();
        // P(N ≤ 0) = e^{-2}, P(N ≤ 1) = 3e^{-2}, P(N ≤ 2) = 5e^{-2}.
        let e = (-2.0f64).exp();
        assert!((f64::from(cdf[0]) - e).abs() < 1e-7);
        assert!((f64::from(cdf[1]) - 3.0 * e).abs() < 1e-7);
        assert!((f64::from(cdf[2]) - 5.0 * e).abs() < 1e-7);
        assert!(cdf.windows(2).all(|w| w[0] <= w[1]) && cdf[15] <= 1.0);
        assert!(FeaturePoints::Fixed(3).poisson_cdf().is_none());
    }

    pub fn validation_names_the_field() {
        let mut cases: Vec<(ClassicNoise, &str)> = Vec::new();
        let mut m = perlin();
        m.dimensions = 4;
        cases.push((m, "classic.dimensions"));
        let mut m = perlin();
        m.cell_size = 0.5;
        cases.push((m, "classic.cell_size"));
        let mut m = perlin();
        m.fractal.as_mut().unwrap().octaves = 0;
        cases.push((m, "classic.fractal.octaves"));
        let mut m = perlin();
        m.fractal.as_mut().unwrap().gain = f32::NAN;
        cases.push((m, "classic.fractal.gain"));
        // 32 px / 2^6 = 0.5 px: too fine.
        let mut m = perlin();
        m.fractal.as_mut().unwrap().octaves = 7;
        cases.push((m, "classic.fractal.octaves"));
        let mut m = perlin();
        m.basis = Basis::Worley(Worley {
            metric: Metric::Euclidean,
            coefficients: [1.0, 0.0, 0.0, 0.0],
            points: FeaturePoints::Fixed(0),
        });
        cases.push((m, "classic.basis.worley.points.fixed"));
        let mut m = perlin();
        m.basis = Basis::Worley(Worley {
            metric: Metric::Euclidean,
            coefficients: [1.0, f32::INFINITY, 0.0, 0.0],
            points: FeaturePoints::Poisson(1.0),
        });
        cases.push((m, "classic.basis.worley.coefficients[1]"));
        for (m, field) in cases {
            match m.validate() {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
        assert!(perlin().validate().is_ok());
    }

    pub fn json_round_trip_and_unknown_fields() {
        let m = crate::Model::Classic(perlin());
        let text = crate::to_json(&m).unwrap();
        assert_eq!(crate::from_json(&text).unwrap(), m);
        let bad = text.replace("\"gain\"", "\"gian\"");
        assert!(matches!(crate::from_json(&bad), Err(ModelError::Json(_))));
    }

    pub fn worley_needs_the_last_non_zero_coefficient() {
        let w = |c| Worley {
            metric: Metric::Manhattan,
            coefficients: c,
            points: FeaturePoints::Fixed(1),
        };
        assert_eq!(w([1.0, 0.0, 0.0, 0.0]).needed(), 1);
        assert_eq!(w([-1.0, 1.0, 0.0, 0.0]).needed(), 2);
        assert_eq!(w([0.0, 0.0, 0.0, 2.0]).needed(), 4);
        assert_eq!(w([0.0; 4]).needed(), 1);
    }
}
