//! Wavelet noise (Cook & DeRose, "Wavelet Noise", SIGGRAPH 2005): a periodic tile of
//! band-limited random values, interpolated by quadratic B-splines and summed over octaves.
//!
//! # Definition
//!
//! **Tile** (the paper's `GenerateNoiseTile`, in f64, stored as f32). On a periodic grid of side
//! `n` (even) in `d = 2` or `3` dimensions:
//!
//! 1. `R` — independent standard Gaussians (randomness contract below).
//! 2. `R↓` — along each axis in turn, [`downsample`]: `c_i = Σ_{t=−16}^{15} a_t · r_{2i+t}`
//!    (indices mod `n`) with the paper's 32 analysis coefficients [`ANALYSIS`] of the quadratic
//!    B-spline (`a_t = ANALYSIS[t + 16]`). The paper's loop runs `t` to `+16` and so reads one
//!    coefficient past the end of its 32-entry array; the filter is the 32 listed taps.
//! 3. `R↓↑` — [`upsample`] after each axis's downsample: `r_{2k} = ¾ c_k + ¼ c_{k+1}`,
//!    `r_{2k+1} = ¼ c_k + ¾ c_{k+1}` (`pCoeffs = {¼, ¾, ¾, ¼}`, coarse indices mod `n/2`).
//!    Axis `x` is down- and upsampled first, then `y` (then `z`) on that result, as in the paper.
//! 4. `N = R − R↓↑`: the fine-scale detail, whose energy lies above half the tile's Nyquist
//!    frequency.
//! 5. The paper's even/odd correction: `N(c) ← N(c) + N(c + o)` with `o = n/2` in every axis,
//!    plus 1 if `n/2` is even (an odd shift). The paper's loop also transposes the shifted copy
//!    (its write index runs `z` fastest, its read index `x` fastest); the intended shift
//!    without transposition is used here.
//! 6. Scaled so that the noise it defines has unit spatial variance over one period: the exact
//!    mean of `W(p)²` over a period is `n^{−d} Σ_c N_c Σ_l N_{c+l} Π_k β(l_k)` with `β` the
//!    autocorrelation of the quadratic B-spline at integer lags (the quintic B-spline:
//!    `β(0) = 66/120`, `β(±1) = 26/120`, `β(±2) = 1/120`), and the tile is divided by its square
//!    root. (The paper divides by the constant `√0.210` measured for its 3D tiles; this is the
//!    same normalisation computed exactly for each tile, in 2D as in 3D.)
//!
//! **Evaluation** (the paper's `WNoise`). For a coordinate `p` in tile samples, `u = p + ½`,
//! `m = ⌊u⌋`, `f = u − m ∈ [0, 1)` (exact in f64, rounded to f32 once: [`locate_sample`]); the
//! three samples `m − 1, m, m + 1` (mod `n`) weigh `(1−f)²/2`, `1 − w₀ − w₂`, `f²/2`
//! ([`spline_weights`]; the paper's `t` is `1 − f`). The value is the tensor product over the
//! `3^d` samples, summed in a fixed order: for 3D the `z` weights first, then `y`, then `x`
//! (`Σ_i w_{x,i} Σ_j w_{y,j} Σ_k w_{z,k} N_{kji}`, each sum left to right).
//!
//! **Bands** (the paper's `WMultibandNoise`). Band `b` reads the tile at `p_b = x / c_b` with
//! `c_b = cell_size / 2^b` pixels per sample (exact in f64), shifted by a per-band integer
//! offset `o_b` (below), and weighs `a_b = amplitude · w_b / √(Σ w²)` (f64, rounded to f32): the
//! paper's variance normalisation, so the sum of uncorrelated unit-variance bands has variance
//! `amplitude²`. The value is `mean + Σ_b a_b · N_b`, bands accumulated in order from 0. A 3D
//! noise is evaluated on the plane `z` (pixels), like the classic noises.
//!
//! # Randomness contract (layer [`WAVELET_LAYER`])
//!
//! Tile sample `(i, j)` of a 2D tile seeds `Prng::new(cell_hash(i, j, WAVELET_LAYER, seed))`, of a
//! 3D tile `(i, j, k)` `Prng::new(cell_hash(i, j, WAVELET_LAYER, cell_hash(k, 0, WAVELET_LAYER,
//! seed)))`, and draws two words `b₁, b₂`: `R = √(−2 ln open_unit_f64(b₁)) · cos(2π·unit_f64(b₂))`
//! (Box–Muller in f64). All bands share the one tile, as in the paper; to decorrelate them
//! (the paper leaves "decorrelating bands" out), band `b` seeds
//! `Prng::new(cell_hash(b, −1, WAVELET_LAYER, seed))` and draws its offset along `x`, `y` (and
//! `z`) as `next_u32 % n`; tile rows are never negative, so these seeds are not tile seeds.
//! The tile is built on the host once, by [`WaveletNoise::tile`], for both evaluators.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_level, check_range};
use crate::random::{Prng, cell_hash, open_unit_f64, unit_f64};

pub(crate) mod builder;
pub use builder::WaveletNoiseBuilder;

/// The randomness-contract layer of wavelet noise (`"WAVE"`).
pub const WAVELET_LAYER: u32 = 0x5741_5645;
/// Most bands.
pub const MAX_BANDS: usize = 16;
/// Smallest tile side.
pub const MIN_TILE: u32 = 16;
/// Largest tile side of a 2D tile (`256²` samples).
pub const MAX_TILE_2D: u32 = 256;
/// Largest tile side of a 3D tile (`64³` samples).
pub const MAX_TILE_3D: u32 = 64;
/// Smallest cell (pixels per tile sample) of the finest band.
pub const MIN_CELL_SIZE: f64 = 1.0;

/// The quadratic B-spline analysis filter of Cook & DeRose's appendix (`aCoeffs`, `ARAD = 16`),
/// as published (the paper prints `0.003546` where symmetry would give `0.003545`).
pub const ANALYSIS: [f64; 32] = [
    0.000334, -0.001528, 0.000410, 0.003545, -0.000938, -0.008233, 0.002172, 0.019120, -0.005040,
    -0.044412, 0.011655, 0.103311, -0.025936, -0.243780, 0.033979, 0.655340, 0.655340, 0.033979,
    -0.243780, -0.025936, 0.103311, 0.011655, -0.044412, -0.005040, 0.019120, 0.002172, -0.008233,
    -0.000938, 0.003546, 0.000410, -0.001528, 0.000334,
];

/// The refinement filter `pCoeffs` of the quadratic B-spline (sums to 2: each fine sample gets 1).
pub const REFINEMENT: [f64; 4] = [0.25, 0.75, 0.75, 0.25];

/// Autocorrelation of the quadratic B-spline at lags 0, 1, 2 (the quintic B-spline at integers).
pub const SPLINE_AUTOCORRELATION: [f64; 3] = [66.0 / 120.0, 26.0 / 120.0, 1.0 / 120.0];

/// Wavelet noise: a band-limited tile, B-spline interpolated, summed over octave bands.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaveletNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// 2 (a plane) or 3 (a volume, rendered on a plane `z`).
    pub dimensions: u32,
    /// Side `n` of the periodic tile, samples: even, 16 to 256 in 2D, 16 to 64 in 3D.
    pub tile_size: u32,
    /// Pixels per tile sample of the first (coarsest) band.
    pub cell_size: f32,
    /// Weight `w_b` of band `b` (1 to 16 bands); band `b` has `2^b` times the first one's
    /// frequency.
    pub bands: Vec<f32>,
    /// Standard deviation of the sum (the bands are normalised by `√Σw²`).
    pub amplitude: f32,
    /// Constant added.
    pub mean: f32,
}

/// A band of a [`WaveletNoise`], as both evaluators use it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// Pixels per tile sample, `cell_size / 2^b` (exact).
    pub side: f64,
    /// `amplitude · w_b / √Σw²`, rounded to f32.
    pub amplitude: f32,
    /// Integer tile offset along x, y, z (`z` is 0 in 2D).
    pub offset: [u32; 3],
}

/// The normalised band-limited tile: `n^d` values, `x` fastest (`index = (k·n + j)·n + i`).
#[derive(Debug, Clone, PartialEq)]
pub struct WaveletTile {
    /// Side `n`.
    pub side: usize,
    /// 2 or 3.
    pub dimensions: usize,
    /// The values, f32.
    pub values: Vec<f32>,
}

impl WaveletTile {
    /// The `n × n` plane band `band` reads at the plane `z` (pixels), `x` fastest: the tile
    /// itself in 2D; in 3D the sum over `z` done first, once (the sum order of the definition),
    /// `(w₀·L₀ + w₁·L₁) + w₂·L₂` per sample over the three layers from the band's
    /// [`locate_sample`] of `z`, weighted by [`spline_weights`], in plain f32 `*` and `+`. The
    /// CPU evaluator and the GPU's tables both read these planes.
    #[must_use]
    pub fn plane(&self, band: &Band, z: f64) -> Vec<f32> {
        let n = self.side;
        if self.dimensions == 2 {
            return self.values.clone();
        }
        let (k0, f) = locate_sample(z, band.side, band.offset[2], n as u32);
        let w = spline_weights(f);
        let layer = |t: usize| {
            let k = (k0 as usize + t) % n;
            &self.values[k * n * n..(k + 1) * n * n]
        };
        let (a, c, e) = (layer(0), layer(1), layer(2));
        (0..n * n)
            .map(|i| (w[0] * a[i] + w[1] * c[i]) + w[2] * e[i])
            .collect()
    }
}

impl WaveletNoise {
    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "wavelet.dimensions".into(),
            f64::from(self.dimensions),
            2.0,
            3.0,
            "2 or 3",
        )?;
        let (max, range) = if self.dimensions == 2 {
            (MAX_TILE_2D, "an even number from 16 to 256 (2D)")
        } else {
            (MAX_TILE_3D, "an even number from 16 to 64 (3D)")
        };
        if !self.tile_size.is_multiple_of(2) || !(MIN_TILE..=max).contains(&self.tile_size) {
            return Err(ModelError::OutOfRange {
                field: "wavelet.tile_size".into(),
                value: f64::from(self.tile_size),
                range,
            });
        }
        check_range(
            || "wavelet.cell_size".into(),
            f64::from(self.cell_size),
            MIN_CELL_SIZE,
            1e6,
            "[1, 1e6] pixels",
        )?;
        crate::error::check_len(
            || "wavelet.bands".into(),
            self.bands.len(),
            1,
            MAX_BANDS,
            "1 to 16 weights",
        )?;
        for (b, w) in self.bands.iter().enumerate() {
            check_range(
                || format!("wavelet.bands[{b}]"),
                f64::from(*w),
                -1e3,
                1e3,
                "[-1000, 1000]",
            )?;
        }
        if self.bands.iter().all(|&w| w == 0.0) {
            return Err(ModelError::OutOfRange {
                field: "wavelet.bands".into(),
                value: 0.0,
                range: "weights with at least one that is not 0",
            });
        }
        let finest = f64::from(self.cell_size) / f64::from(1u32 << (self.bands.len() - 1));
        if finest < MIN_CELL_SIZE {
            return Err(ModelError::Length {
                field: "wavelet.bands".into(),
                len: self.bands.len(),
                range: "at most as many as keep the finest band's cell, cell_size / 2^(bands − 1), \
                        at least 1 pixel",
            });
        }
        check_level(|| "wavelet.amplitude".into(), self.amplitude)?;
        check_level(|| "wavelet.mean".into(), self.mean)?;
        Ok(())
    }

    /// The bands: side, normalised amplitude and tile offset (randomness contract above).
    #[must_use]
    pub fn bands(&self) -> Vec<Band> {
        let n = self.tile_size.max(1);
        let norm: f64 = self
            .bands
            .iter()
            .map(|&w| f64::from(w) * f64::from(w))
            .sum::<f64>()
            .sqrt();
        self.bands
            .iter()
            .enumerate()
            .map(|(b, &w)| {
                let mut prng = Prng::new(cell_hash(b as i32, -1, WAVELET_LAYER, self.seed));
                let mut offset = [0u32; 3];
                for o in offset.iter_mut().take(self.dimensions as usize) {
                    *o = prng.next_u32() % n;
                }
                Band {
                    side: f64::from(self.cell_size) / f64::from(1u32 << b.min(31)),
                    amplitude: (f64::from(self.amplitude) * f64::from(w) / norm) as f32,
                    offset,
                }
            })
            .collect()
    }

    /// The normalised band-limited tile (steps 1–6 of the module doc), f64 rounded to f32.
    /// Call on a validated model.
    #[must_use]
    pub fn tile(&self) -> WaveletTile {
        let n = self.tile_size as usize;
        let d = self.dimensions as usize;
        let tile = band_pass_tile(&gaussian_tile(self.seed, n, d), n, d);
        let scale = 1.0 / spatial_variance(&tile, n, d).sqrt();
        WaveletTile {
            side: n,
            dimensions: d,
            values: tile.iter().map(|&v| (v * scale) as f32).collect(),
        }
    }
}

/// Step 1: the Gaussian tile `R` of the randomness contract, `x` fastest.
#[must_use]
pub fn gaussian_tile(seed: u32, n: usize, dimensions: usize) -> Vec<f64> {
    let depth = if dimensions == 3 { n } else { 1 };
    let mut values = Vec::with_capacity(n * n * depth);
    for k in 0..depth {
        let key = if dimensions == 3 {
            cell_hash(k as i32, 0, WAVELET_LAYER, seed)
        } else {
            seed
        };
        for j in 0..n {
            for i in 0..n {
                let mut prng = Prng::new(cell_hash(i as i32, j as i32, WAVELET_LAYER, key));
                let radius = (-2.0 * open_unit_f64(prng.next_u32()).ln()).sqrt();
                let angle = std::f64::consts::TAU * unit_f64(prng.next_u32());
                values.push(radius * angle.cos());
            }
        }
    }
    values
}

/// The paper's `Downsample`: `n/2` coarse values from `n` periodic fine ones.
pub fn downsample(from: &[f64], to: &mut [f64]) {
    let n = from.len() as isize;
    for (i, c) in to.iter_mut().enumerate() {
        let mut sum = 0.0;
        for (t, a) in ANALYSIS.iter().enumerate() {
            let k = (2 * i as isize + t as isize - 16).rem_euclid(n);
            sum += a * from[k as usize];
        }
        *c = sum;
    }
}

/// The paper's `Upsample`: `n` fine values from `n/2` periodic coarse ones.
pub fn upsample(from: &[f64], to: &mut [f64]) {
    let half = from.len();
    for (i, r) in to.iter_mut().enumerate() {
        let k = i / 2;
        let next = (k + 1) % half;
        *r = if i % 2 == 0 {
            REFINEMENT[2] * from[k] + REFINEMENT[0] * from[next]
        } else {
            REFINEMENT[3] * from[k] + REFINEMENT[1] * from[next]
        };
    }
}

/// Steps 2–5: `N = R − R↓↑` with the odd-shift correction, from the Gaussian tile `r`.
#[must_use]
pub fn band_pass_tile(r: &[f64], n: usize, dimensions: usize) -> Vec<f64> {
    let mut coarse = r.to_vec();
    let mut line = vec![0.0; n];
    let mut half = vec![0.0; n / 2];
    let mut up = vec![0.0; n];
    let lines = coarse.len() / n;
    for axis in 0..dimensions {
        let stride = n.pow(axis as u32);
        for l in 0..lines {
            // The first element of line `l` along `axis`.
            let start = (l / stride) * stride * n + l % stride;
            for (t, v) in line.iter_mut().enumerate() {
                *v = coarse[start + t * stride];
            }
            downsample(&line, &mut half);
            upsample(&half, &mut up);
            for (t, v) in up.iter().enumerate() {
                coarse[start + t * stride] = *v;
            }
        }
    }
    let detail: Vec<f64> = r.iter().zip(&coarse).map(|(a, b)| a - b).collect();
    let mut shift = n / 2;
    if shift.is_multiple_of(2) {
        shift += 1;
    }
    let depth = if dimensions == 3 { n } else { 1 };
    let mut out = vec![0.0; detail.len()];
    for k in 0..depth {
        let ks = if dimensions == 3 { (k + shift) % n } else { 0 };
        for j in 0..n {
            let js = (j + shift) % n;
            for i in 0..n {
                let is = (i + shift) % n;
                out[(k * n + j) * n + i] =
                    detail[(k * n + j) * n + i] + detail[(ks * n + js) * n + is];
            }
        }
    }
    out
}

/// The mean of `W(p)²` over one period for the tile `values` (step 6): `n^{−d} Σ_c N_c (β ∗ N)_c`
/// with the separable 5-tap autocorrelation `β` of the quadratic B-spline.
#[must_use]
pub fn spatial_variance(values: &[f64], n: usize, dimensions: usize) -> f64 {
    let mut filtered = values.to_vec();
    let mut line = vec![0.0; n];
    let lines = values.len() / n;
    let beta = |l: isize| SPLINE_AUTOCORRELATION[l.unsigned_abs()];
    for axis in 0..dimensions {
        let stride = n.pow(axis as u32);
        for l in 0..lines {
            let start = (l / stride) * stride * n + l % stride;
            for (t, v) in line.iter_mut().enumerate() {
                *v = (-2isize..=2)
                    .map(|lag| {
                        let s = (t as isize + lag).rem_euclid(n as isize) as usize;
                        beta(lag) * filtered[start + s * stride]
                    })
                    .sum();
            }
            for (t, v) in line.iter().enumerate() {
                filtered[start + t * stride] = *v;
            }
        }
    }
    values
        .iter()
        .zip(&filtered)
        .map(|(a, b)| a * b)
        .sum::<f64>()
        / values.len() as f64
}

/// The first of the three tile samples a coordinate `coord` (pixels) reads on a band of `side`
/// pixels per sample, shifted by `offset` and reduced mod `n`, and the B-spline fraction `f`:
/// `u = coord/side + ½` in f64, `m = ⌊u⌋`, index `(m − 1 + offset) mod n`, `f = f32(u − m)`
/// (exact in f64 for `|coord| ≤ 2³⁰` and `side ≥ 1`, rounded once). Both evaluators locate
/// samples with this one function, so they agree on indices and fractions bit for bit.
#[inline]
#[must_use]
pub fn locate_sample(coord: f64, side: f64, offset: u32, n: u32) -> (u32, f32) {
    let u = coord / side + 0.5;
    let m = u.floor();
    // A saturating cast; positions are validated to |coord| ≤ 2³⁰ before this is called.
    let index = (m as i64 - 1 + i64::from(offset)).rem_euclid(i64::from(n.max(1)));
    (index as u32, (u - m) as f32)
}

/// The quadratic B-spline weights of the samples `m − 1, m, m + 1` at fraction `f`:
/// `(1−f)²/2`, `1 − w₀ − w₂`, `f²/2` (the paper's `WNoise`, `t = 1 − f`), f32 products and
/// differences only (the GPU writes the same expressions).
#[inline(always)]
#[must_use]
pub fn spline_weights(f: f32) -> [f32; 3] {
    let g = 1.0 - f;
    let w0 = 0.5 * g * g;
    let w2 = 0.5 * f * f;
    [w0, (1.0 - w0) - w2, w2]
}

impl crate::ModelKind for WaveletNoise {
    const PERIODIC: bool = true;

    const NAME: &'static str = "wavelet";

    /// Wavelet noise is periodic already: band `b` repeats every `n · cell_size / 2^b` pixels
    /// (its tile, sampled modulo `n`), so the sum repeats every `n · cell_size`. A period that
    /// is a multiple of it along x and y needs nothing more than exact evaluation.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let tile = f64::from(self.tile_size) * f64::from(self.cell_size);
        if period.sides().iter().all(|&p| p % tile == 0.0) {
            return Ok(());
        }
        Err(ModelError::Period {
            period: period.to_string(),
            kind: "wavelet",
            requirement: format!(
                "its tile repeats every tile_size · cell_size = {tile} pixels; the period's \
                 width and height must be multiples of it"
            ),
        })
    }

    fn validate(&self) -> Result<(), ModelError> {
        WaveletNoise::validate(self)
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

    fn model() -> WaveletNoise {
        WaveletNoise {
            seed: 7,
            dimensions: 2,
            tile_size: 32,
            cell_size: 16.0,
            bands: vec![1.0, 0.5, 0.25],
            amplitude: 1.0,
            mean: 0.0,
        }
    }

    /// The 1D operator `x ↦ x↓↑` as a dense `n × n` matrix, written from the definitions
    /// `c_i = Σ_t a_t r_{2i+t}` and `r_{2k} = ¾c_k + ¼c_{k+1}`, `r_{2k+1} = ¼c_k + ¾c_{k+1}`
    /// independently of the fast code: `M = U·D`.
    fn projection_matrix(n: usize) -> Vec<Vec<f64>> {
        let h = n / 2;
        let mut d = vec![vec![0.0; n]; h];
        for (i, row) in d.iter_mut().enumerate() {
            for t in -16i64..16 {
                let k = (2 * i as i64 + t).rem_euclid(n as i64) as usize;
                row[k] += ANALYSIS[(t + 16) as usize];
            }
        }
        let mut u = vec![vec![0.0; h]; n];
        for k in 0..h {
            u[2 * k][k] += 0.75;
            u[2 * k][(k + 1) % h] += 0.25;
            u[2 * k + 1][k] += 0.25;
            u[2 * k + 1][(k + 1) % h] += 0.75;
        }
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| (0..h).map(|k| u[i][k] * d[k][j]).sum())
                    .collect()
            })
            .collect()
    }

    pub fn band_pass_tile_matches_a_dense_matrix_reference() {
        for n in [16usize, 18, 32] {
            let r = gaussian_tile(3, n, 2);
            let m = projection_matrix(n);
            // R↓↑ = M R Mᵀ (x along rows of R's index i, y along j).
            let at = |j: usize, i: usize| r[j * n + i];
            let mut coarse = vec![0.0; n * n];
            for j in 0..n {
                for i in 0..n {
                    let mut s = 0.0;
                    for jj in 0..n {
                        for ii in 0..n {
                            s += m[j][jj] * m[i][ii] * at(jj, ii);
                        }
                    }
                    coarse[j * n + i] = s;
                }
            }
            let shift = if (n / 2) % 2 == 0 { n / 2 + 1 } else { n / 2 };
            let tile = band_pass_tile(&r, n, 2);
            for j in 0..n {
                for i in 0..n {
                    let detail = |j: usize, i: usize| r[j * n + i] - coarse[j * n + i];
                    let want = detail(j, i) + detail((j + shift) % n, (i + shift) % n);
                    let got = tile[j * n + i];
                    assert!(
                        (got - want).abs() < 1e-12,
                        "n = {n}, ({i}, {j}): {got} vs {want}"
                    );
                }
            }
        }
    }

    pub fn spatial_variance_matches_the_double_sum() {
        let n = 16;
        let t = band_pass_tile(&gaussian_tile(9, n, 2), n, 2);
        let mut want = 0.0;
        for j in 0..n {
            for i in 0..n {
                for lj in -2i64..=2 {
                    for li in -2i64..=2 {
                        let jj = (j as i64 + lj).rem_euclid(n as i64) as usize;
                        let ii = (i as i64 + li).rem_euclid(n as i64) as usize;
                        want += t[j * n + i]
                            * t[jj * n + ii]
                            * SPLINE_AUTOCORRELATION[lj.unsigned_abs() as usize]
                            * SPLINE_AUTOCORRELATION[li.unsigned_abs() as usize];
                    }
                }
            }
        }
        want /= (n * n) as f64;
        let got = spatial_variance(&t, n, 2);
        assert!((got - want).abs() < 1e-12 * want, "{got} vs {want}");
    }

    pub fn spline_weights_partition_unity_and_hit_the_knots() {
        assert_eq!(spline_weights(0.5), [0.125, 0.75, 0.125]);
        assert_eq!(spline_weights(0.0), [0.5, 0.5, 0.0]);
        for f in [0.0f32, 0.1, 0.37, 0.5, 0.99] {
            let w = spline_weights(f);
            assert!((w[0] + w[1] + w[2] - 1.0).abs() < 2e-7, "{f}");
        }
        assert_eq!(locate_sample(-0.5, 2.0, 0, 16), (15, 0.25));
        assert_eq!(locate_sample(16.0, 16.0, 3, 16), (3, 0.5));
        // Exact far from the origin: 1e7 + 0.25 px at 1 px per sample.
        assert_eq!(
            locate_sample(1.0e7 + 0.25, 1.0, 0, 32),
            (((1e7 as i64 - 1) % 32) as u32, 0.75)
        );
    }

    pub fn bands_are_normalised_and_offsets_drawn_by_the_contract() {
        let m = model();
        let bands = m.bands();
        let norm = (1.0f64 + 0.25 + 0.0625).sqrt();
        assert_eq!(bands[1].amplitude, (0.5 / norm) as f32);
        assert_eq!(bands[2].side, 4.0);
        let mut prng = Prng::new(cell_hash(2, -1, WAVELET_LAYER, 7));
        assert_eq!(bands[2].offset[0], prng.next_u32() % 32);
        assert_eq!(bands[2].offset[1], prng.next_u32() % 32);
        assert_eq!(bands[2].offset[2], 0);
    }

    pub fn validation_names_the_field() {
        let mut cases: Vec<(WaveletNoise, &str)> = Vec::new();
        let mut m = model();
        m.dimensions = 1;
        cases.push((m, "wavelet.dimensions"));
        let mut m = model();
        m.tile_size = 33;
        cases.push((m, "wavelet.tile_size"));
        let mut m = model();
        m.tile_size = 258;
        cases.push((m, "wavelet.tile_size"));
        let mut m = model();
        m.dimensions = 3;
        m.tile_size = 128;
        cases.push((m, "wavelet.tile_size"));
        let mut m = model();
        m.cell_size = 0.5;
        cases.push((m, "wavelet.cell_size"));
        let mut m = model();
        m.bands[1] = f32::NAN;
        cases.push((m, "wavelet.bands[1]"));
        let mut m = model();
        m.bands = vec![0.0, 0.0];
        cases.push((m, "wavelet.bands"));
        let mut m = model();
        m.amplitude = f32::INFINITY;
        cases.push((m, "wavelet.amplitude"));
        for (m, field) in cases {
            match m.validate() {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
        let mut m = model();
        m.bands = vec![1.0; 17];
        assert!(matches!(m.validate(), Err(ModelError::Length { .. })));
        // 16 px / 2^5 = 0.5 px: too fine.
        let mut m = model();
        m.bands = vec![1.0; 6];
        assert!(matches!(m.validate(), Err(ModelError::Length { .. })));
        assert!(model().validate().is_ok());
    }

    pub fn json_round_trip_and_unknown_fields() {
        let m = crate::Model::Wavelet(model());
        let text = crate::to_json(&m).unwrap();
        assert!(text.contains("\"wavelet\""));
        assert_eq!(crate::from_json(&text).unwrap(), m);
        let bad = text.replace("\"tile_size\"", "\"tile\"");
        assert!(matches!(crate::from_json(&bad), Err(ModelError::Json(_))));
    }

    pub fn tile_has_unit_spatial_variance_and_is_deterministic() {
        let m = model();
        let t = m.tile();
        assert_eq!(t.values.len(), 32 * 32);
        let v: Vec<f64> = t.values.iter().map(|&x| f64::from(x)).collect();
        let var = spatial_variance(&v, 32, 2);
        assert!((var - 1.0).abs() < 1e-6, "{var}");
        assert_eq!(m.tile(), t);
        let mut other = m.clone();
        other.seed = 8;
        assert_ne!(other.tile().values, t.values);
    }
}
