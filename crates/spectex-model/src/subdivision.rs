//! Stochastic subdivision (survey Dong et al. 2020, §3.1.7): Fournier, Fussell & Carpenter's
//! midpoint displacement (1982) on a square lattice, and a smoother fixed stencil after Lewis's
//! generalised stochastic subdivision (1987), as a pointwise, infinite, tile-invariant kind.
//!
//! # Definition
//!
//! Level 0 is the square lattice of side `C = cell_size` pixels; level `ℓ` the lattice of side
//! `C/2^ℓ`, `ℓ = 0..=L` (`L = levels`). A level-`ℓ` point is named by its coarse cell `c ∈ ℤ²`
//! and its index `k ∈ [0, 2^ℓ)²` in that cell (position `(c + k/2^ℓ)·C`); an index outside
//! `[0, 2^ℓ)` names the same point as `c + ⌊k/2^ℓ⌋`, `k mod 2^ℓ` ([`normalise`]). Its value
//!
//! ```text
//! V₀(c)    = σ₀ · D(c, 0, 0)
//! V_ℓ(c,k) = I(V_{ℓ−1})(c, k/2) + [k_x or k_y odd] · σ_ℓ · D(c, k, ℓ),   σ_ℓ = a·2^(−Hℓ)
//! ```
//!
//! where `I` interpolates the parent level at the new point (the [`Stencil`]: bilinear, i.e.
//! Fournier's rule — an edge midpoint is the mean of its two ends, a centre the mean of its
//! four corners — or the tensor 4-point stencil `(−1, 9, 9, −1)/16`), `a = amplitude` and `H =
//! hurst`, so level `ℓ`'s displacements have variance `a²·2^(−2Hℓ)` (Fournier et al.'s fBm
//! scaling, spacing^H). A point of even index keeps its parent's value (both stencils
//! interpolate). The displacement `D` is a hash of the point ([`lattice_bits`]), layer
//! [`SUBDIVISION_LAYER`]` + ℓ`:
//!
//! ```text
//! h = cell_hash(k_x, k_y, SUBD + ℓ, cell_hash(c_x, c_y, SUBD, seed))
//! D = (b₀ + b₁ + b₂ + b₃ − 510) / √21845     (bᵢ the four bytes of h)
//! ```
//!
//! an Irwin–Hall sum of four uniform bytes: mean 0 and variance exactly 1 (each byte has
//! variance `(256² − 1)/12`), near-Gaussian as in Fournier et al., and an integer on both
//! evaluators. The texture at `p` is `mean + I(V_L)(p)`: bilinear between the level-`L` points
//! around `p` for the midpoint rule, Catmull–Rom (whose weights at `½` are the 4-point stencil)
//! for the cubic one.
//!
//! # Why it is pointwise and tile-invariant
//!
//! `V_ℓ` at a point depends on `V_{ℓ−1}` in a bounded block around it (2 points per axis for
//! the midpoint rule, 4 for the cubic), and the displacements are hashes of (level, lattice
//! point, seed), not draws in a traversal order. The points a pixel needs at level `ℓ` form a
//! block of `W` points per axis (`W` = 2 for the midpoint rule, 6 for the cubic: a block of 6
//! at level `ℓ` needs a block of 6 at level `ℓ − 1`, [`Stencil::window`]), so a pixel costs
//! `W²·(L + 1)` lattice values, whatever the window, tiling or thread. Positions are split
//! into the coarse cell (`i32`) and an f32 offset `t` ([`crate::grid::locate_cell`]); `t·2^L`
//! and its floor are exact in f32, so both evaluators find the same lattice points bit for bit
//! and differ only in the f64 (CPU) or f32 (GPU) sums.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_level, check_range};
use crate::random::cell_hash;

pub(crate) mod builder;
pub use builder::StochasticSubdivisionBuilder;

/// Most subdivision levels `L` (a level-`L` index `< 2^L` fits an `i32` with room for the
/// stencil).
pub const MAX_LEVELS: u32 = 16;
/// Smallest and largest coarse cell side, pixels.
pub const CELL_RANGE: (f32, f32) = (1.0, 4096.0);
/// The randomness layer of level 0 ("SUBD"); level `ℓ` uses `SUBDIVISION_LAYER + ℓ`.
pub const SUBDIVISION_LAYER: u32 = 0x5355_4244;
/// The mean of the four bytes' sum, subtracted from it.
pub const BYTE_SUM_MEAN: i32 = 510;
/// The variance of the four bytes' sum, `4·(256² − 1)/12`.
pub const BYTE_SUM_VARIANCE: f64 = 21_845.0;
/// The weights of the 4-point stencil at a midpoint, `(−1, 9, 9, −1)/16`.
pub const CUBIC_MIDPOINT: [f64; 4] = [-0.0625, 0.5625, 0.5625, -0.0625];

/// How a level interpolates its parent (and the texture its finest level).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stencil {
    /// Fournier et al.'s rule: bilinear (an edge midpoint is the mean of its ends, a centre
    /// the mean of its four corners); the texture is bilinear between the finest points.
    Midpoint,
    /// The tensor 4-point stencil `(−1, 9, 9, −1)/16` (a fixed instance of Lewis's estimation
    /// filter for a smooth autocorrelation); the texture is Catmull–Rom between the finest
    /// points.
    Cubic,
}

impl Stencil {
    /// `(W, r)`: the block of points per axis a level keeps and how far its origin lies before
    /// the parent's (`o_{ℓ−1} = ⌊o_ℓ/2⌋ − r`, and the finest block starts `r` before the
    /// pixel's cell).
    #[must_use]
    pub const fn window(self) -> (usize, i32) {
        match self {
            Self::Midpoint => (2, 0),
            Self::Cubic => (6, 1),
        }
    }

    /// The taps interpolating level-`ℓ` index `q` from level `ℓ − 1`: `(first parent index,
    /// weights, count)`. An even `q` is its parent `q/2` with weight 1.
    #[must_use]
    pub fn taps(self, q: i32) -> (i32, [f64; 4], usize) {
        if q & 1 == 0 {
            (q >> 1, [1.0, 0.0, 0.0, 0.0], 1)
        } else {
            match self {
                Self::Midpoint => (q >> 1, [0.5, 0.5, 0.0, 0.0], 2),
                Self::Cubic => ((q >> 1) - 1, CUBIC_MIDPOINT, 4),
            }
        }
    }

    /// The final interpolation's weights at the offset `u ∈ [0, 1]` in a finest cell, for the
    /// points from `−r` (`count` of them): `(1 − u, u)` or Catmull–Rom's.
    #[must_use]
    pub fn final_weights(self, u: f64) -> ([f64; 4], usize) {
        match self {
            Self::Midpoint => ([1.0 - u, u, 0.0, 0.0], 2),
            Self::Cubic => {
                let (u2, u3) = (u * u, u * u * u);
                (
                    [
                        0.5 * (-u3 + 2.0 * u2 - u),
                        0.5 * (3.0 * u3 - 5.0 * u2 + 2.0),
                        0.5 * (-3.0 * u3 + 4.0 * u2 + u),
                        0.5 * (u3 - u2),
                    ],
                    4,
                )
            }
        }
    }
}

/// A stochastic subdivision texture (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StochasticSubdivision {
    /// Seed.
    pub seed: u32,
    /// `C`, the coarse lattice side in pixels, in `[1, 4096]`.
    pub cell_size: f32,
    /// `L`, the subdivision levels, `0..=16` (the finest lattice side is `C/2^L`).
    pub levels: u32,
    /// `H`, the roughness exponent in `[0, 1]`: level `ℓ`'s displacements have standard
    /// deviation `amplitude·2^(−Hℓ)`.
    pub hurst: f32,
    /// `a`, the standard deviation of the coarse values (level 0).
    pub amplitude: f32,
    /// Constant added to the texture.
    pub mean: f32,
    /// The interpolation rule.
    pub stencil: Stencil,
}

/// `(c + ⌊k/2^ℓ⌋, k mod 2^ℓ)` per axis: the canonical name of a level-`ℓ` point (wrapping in
/// the coarse cell, like every lattice kind's `i32` cells).
#[must_use]
pub const fn normalise(c: i32, k: i32, level: u32) -> (i32, i32) {
    (
        c.wrapping_add(k >> level),
        k & ((1i32 << level).wrapping_sub(1)),
    )
}

/// The hash of level-`ℓ` point `(c, k)` (`k` normalised, [`normalise`]).
#[must_use]
pub const fn lattice_bits(seed: u32, level: u32, c: [i32; 2], k: [i32; 2]) -> u32 {
    let cell = cell_hash(c[0], c[1], SUBDIVISION_LAYER, seed);
    cell_hash(k[0], k[1], SUBDIVISION_LAYER.wrapping_add(level), cell)
}

/// `b₀ + b₁ + b₂ + b₃ − 510` of the hash's bytes: mean 0, variance 21845.
#[must_use]
pub const fn centred_byte_sum(bits: u32) -> i32 {
    ((bits & 0xff) + ((bits >> 8) & 0xff) + ((bits >> 16) & 0xff) + (bits >> 24)) as i32
        - BYTE_SUM_MEAN
}

impl StochasticSubdivision {
    /// `σ_ℓ/√21845` for `ℓ = 0..=L`: the factor of level `ℓ`'s centred byte sum, in f64
    /// (`L` capped at [`MAX_LEVELS`] for an unvalidated model).
    #[must_use]
    pub fn level_scales(&self) -> Vec<f64> {
        (0..=self.levels.min(MAX_LEVELS))
            .map(|l| {
                f64::from(self.amplitude) * (-f64::from(self.hurst) * f64::from(l)).exp2()
                    / BYTE_SUM_VARIANCE.sqrt()
            })
            .collect()
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range, with its dotted path.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "subdivision.cell_size".into(),
            f64::from(self.cell_size),
            f64::from(CELL_RANGE.0),
            f64::from(CELL_RANGE.1),
            "1 to 4096 pixels",
        )?;
        check_range(
            || "subdivision.levels".into(),
            f64::from(self.levels),
            0.0,
            f64::from(MAX_LEVELS),
            "0 to 16",
        )?;
        check_range(
            || "subdivision.hurst".into(),
            f64::from(self.hurst),
            0.0,
            1.0,
            "[0, 1]",
        )?;
        check_level(|| "subdivision.amplitude".into(), self.amplitude)?;
        check_level(|| "subdivision.mean".into(), self.mean)
    }

    /// `max |V_L|`: `M₀ = σ₀·510/√21845`, `M_ℓ = S·M_{ℓ−1} + σ_ℓ·510/√21845` with `S` the
    /// stencil's `(Σ|w|)²` (1 for the midpoint rule, `1.25² = 1.5625` for the cubic), and the
    /// final interpolation's `(Σ|w|)²` once more (Catmull–Rom's `Σ|w| ≤ 1.25`).
    #[must_use]
    pub fn magnitude_bound(&self) -> f64 {
        let gain = self.stencil_gain();
        let peak = f64::from(BYTE_SUM_MEAN);
        let mut m = 0.0;
        for s in self.level_scales() {
            m = gain * m + s.abs() * peak;
        }
        gain * m
    }

    /// `(Σ|w|)²` of one 2D interpolation by the stencil.
    #[must_use]
    pub fn stencil_gain(&self) -> f64 {
        match self.stencil {
            Stencil::Midpoint => 1.0,
            Stencil::Cubic => 1.5625,
        }
    }
}

impl crate::ModelKind for StochasticSubdivision {
    const NAME: &'static str = "subdivision";

    fn validate(&self) -> Result<(), ModelError> {
        StochasticSubdivision::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}

impl From<StochasticSubdivision> for crate::Model {
    fn from(m: StochasticSubdivision) -> Self {
        Self::Subdivision(m)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn byte_sum_has_mean_zero_and_variance_21845() {
        // Over all 2^16 pairs of two bytes the sum's moments are exact; four bytes are two
        // independent pairs, so the mean and variance add.
        let (mut s1, mut s2) = (0i64, 0i64);
        for b in 0..65_536u32 {
            let v = i64::from((b & 0xff) + (b >> 8)) - 255;
            s1 += v;
            s2 += v * v;
        }
        assert_eq!(s1, 0);
        assert_eq!(2.0 * s2 as f64 / 65_536.0, BYTE_SUM_VARIANCE);
        assert_eq!(centred_byte_sum(0), -510);
        assert_eq!(centred_byte_sum(u32::MAX), 510);
    }

    pub fn catmull_rom_at_a_half_is_the_four_point_stencil() {
        let (w, n) = Stencil::Cubic.final_weights(0.5);
        assert_eq!(n, 4);
        assert_eq!(w, CUBIC_MIDPOINT);
        for u in [0.0, 0.25, 0.7, 1.0] {
            for s in [Stencil::Midpoint, Stencil::Cubic] {
                let (w, n) = s.final_weights(u);
                let sum: f64 = w[..n].iter().sum();
                assert!((sum - 1.0).abs() < 1e-15, "{s:?} {u}: weights sum to {sum}");
            }
        }
    }

    pub fn the_window_covers_every_tap_of_the_next_level() {
        for s in [Stencil::Midpoint, Stencil::Cubic] {
            let (w, r) = s.window();
            for o in -20..20 {
                let parent = (o >> 1) - r;
                for q in o..o + w as i32 {
                    let (first, _, n) = s.taps(q);
                    assert!(
                        first >= parent && first + n as i32 <= parent + w as i32,
                        "{s:?}: child {q} of block {o} reads {first}..+{n} outside {parent}..+{w}"
                    );
                }
            }
        }
    }

    pub fn normalise_names_one_point_once() {
        assert_eq!(normalise(3, 5, 2), (4, 1));
        assert_eq!(normalise(3, -1, 2), (2, 3));
        assert_eq!(normalise(0, 4, 2), (1, 0));
        assert_eq!(normalise(7, 0, 0), (7, 0));
        assert_eq!(normalise(7, -2, 0), (5, 0));
    }

    pub fn validation_names_the_field() {
        type Break = fn(&mut StochasticSubdivision);
        let cases: [(Break, &str); 6] = [
            (|m| m.cell_size = 0.5, "subdivision.cell_size"),
            (|m| m.levels = 17, "subdivision.levels"),
            (|m| m.hurst = 1.5, "subdivision.hurst"),
            (|m| m.hurst = f32::NAN, "subdivision.hurst"),
            (|m| m.amplitude = f32::INFINITY, "subdivision.amplitude"),
            (|m| m.mean = 2e9, "subdivision.mean"),
        ];
        StochasticSubdivision::midpoint()
            .validate()
            .expect("defaults are valid");
        for (break_it, field) in cases {
            let mut m = StochasticSubdivision::midpoint();
            break_it(&mut m);
            let e = m.validate().expect_err(field);
            assert!(e.to_string().contains(field), "{e} names {field}");
        }
    }
}
