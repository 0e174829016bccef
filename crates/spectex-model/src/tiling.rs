//! Tiling and blending by example (Heitz & Neyret, "High-Performance By-Example Noise using a
//! Histogram-Preserving Blending Operator", HPG 2018), with Deliot & Heitz's decorrelated
//! channels and prefiltered look-up tables ("Procedural Stochastic Textures by Tiling and
//! Blending", GPU Zen 2, 2019) and Mikkelsen's hex-tiling ("Practical Real-Time Hex-Tiling",
//! JCGT 2022) as an option.
//!
//! # Definition
//!
//! **The model** holds the exemplar's channels decorrelated by PCA (`colour = mean + basis·t`,
//! [`TilingTexture::basis`]) and each channel **Gaussianised**: `g = T(t) = Φ⁻¹(rank/n)`
//! ([`TilingTexture::gaussian`], a standard normal per channel), with `T⁻¹` tabulated on
//! [`LUT_ENTRIES`] values of `g` evenly spaced over `[−LUT_RANGE, LUT_RANGE]`
//! ([`TilingTexture::lut`], the channel's quantile at `Φ(g)`). The fit (`spectex_sampling`)
//! makes them; a model file stands alone.
//!
//! **The lattice** ([`Lattice`]) is the triangle grid of Heitz & Neyret: vertex `(m, k)` at
//! `((m + k/2)·side, k·row)` pixels, with `side` the even integer nearest
//! [`TilingTexture::tile`] and `row = round(side·√3/2)` (triangles within 0.3% of equilateral
//! from a side of 16, every vertex on a whole pixel: [`TilingTexture::lattice`] says why); a
//! periodic model takes the nearest such lattice that divides its period. A position is split
//! on the pixel grid ([`crate::grid::locate_cell`], side 1): `(X, φx)`, `(Y, φy)`; with
//! `h = side/2`, in integers `cy = ⌊Y/row⌋`, `ry = Y − cy·row`, `a = X − cy·h`,
//! `cx = ⌊a/side⌋`, `rx = a − cx·side`, and in f32 `v = (ry + φy)·ρ`,
//! `t = (rx + φx)·σ − ½·v` (`ρ`, `σ` the f32 of `1/row`, `1/side`). The rhombus is
//! `m₀ = cx + ⌊t⌋`, `k₀ = cy`, `u = t − ⌊t⌋`. If `u + v < 1` the triangle's vertices are
//! `(m₀, k₀)`, `(m₀+1, k₀)`, `(m₀, k₀+1)` with barycentric weights `(1 − u) − v`, `u`, `v`;
//! else `(m₀+1, k₀+1)`, `(m₀, k₀+1)`, `(m₀+1, k₀)` with `(u + v) − 1`, `1 − u`, `1 − v`. The
//! displacement from vertex `(m₀ + a′, k₀ + b)` to the position is `D + φ` with the whole
//! pixels `D = (rx − ⌊t⌋·side − a′·side − b·h, ry − b·row)`, exact at any distance from the
//! origin (`|X|, |Y| < 2³⁰`; beyond, or NaN, the value is the mean).
//!
//! **A tap** reads the Gaussianised exemplar at `o + D + φ` texels, `o` the vertex's offset
//! (below). At level 0 without rotation: the texel `o + D` and its neighbours weighed by `φ`
//! (bilinear; a render on the pixel grid reads the texel itself). Otherwise in f32 at
//! `q = f32(o + D) + φ`, or with the hex option's rotation `q = f32(o) + R(θ)·(f32(D) + φ)`
//! (`R(θ)` by `cos_turns(θ)`, `cos_turns(θ − ¼)`), read bilinearly at mip level `l`
//! ([`TilingTables`]): `q_l = q·2⁻ˡ − (1 − 2⁻ˡ)/2`, clamped to `[0, n_l − 1]`.
//!
//! **The blend** ([`Blend`]): Heitz & Neyret's variance-preserving blend of the three taps
//! `G = (w₀g₀ + w₁g₁ + w₂g₂) / √(w₀² + w₁² + w₂²)` per channel (their Eq. for a zero-mean
//! Gaussian: `G` is standard normal wherever the taps are independent, so `T⁻¹(G)` has the
//! exemplar's histogram), then `t = LUT_l(G)`; or Mikkelsen's linear blend of each tap's
//! `LUT_l(g_i)` with weights `w_iᵞ / Σ w_jᵞ` (his contrast `γ`, here an integer
//! [`Blend::Hex::sharpness`] computed by repeated products so that both evaluators compute it
//! alike, where his shader calls `pow`). The output is `mean + basis·t`.
//!
//! `LUT_l(g)`: `x = (clamp(g, −R, R) + R)·(LUT_ENTRIES − 1)/(2R)` (`R` = [`LUT_RANGE`]),
//! `i = min(⌊x⌋, LUT_ENTRIES − 2)`, the table's `lut[i] + (x − i)·(lut[i+1] − lut[i])`.
//!
//! **Minified renders** (Deliot & Heitz §"Prefiltering"): a window's footprint `f > 1` model
//! pixels selects `λ = log₂ f` clamped to the pyramid; levels `⌊λ⌋` and `⌊λ⌋ + 1` are evaluated
//! (each with its own filtered exemplar and look-up table) and mixed, `v₀ + (λ − ⌊λ⌋)·(v₁ − v₀)`.
//! Level `l + 1` of the exemplar averages `2 × 2` texels of level `l` (the last one repeated on
//! odd sides); its table is the expectation of `T⁻¹` over what filtering removed,
//! `LUT_l(g) = E[T⁻¹(g + σ_l Z)]`, `Z` standard normal, `σ_l² = var₀ − var_l` the channel's
//! variance lost from level 0 to level `l` ([`TilingTexture::tables`]).
//!
//! # Randomness contract (layers [`TILING_LAYER`], [`TILING_BLOCK_LAYER`])
//!
//! Vertex `(m, k)` (wrapped by a periodic lattice first, [`Lattice::key`]) lies in block
//! `(B_m, B_k) = (⌊m/4⌋, ⌊k/4⌋)` at index `j = (m − 4B_m) + 4(k − 4B_k)`. The block seeds
//! `Prng::new(cell_hash(B_m, B_k, TILING_BLOCK_LAYER, seed))` and draws `α = 2·(b₁ mod 8) + 1`,
//! `β = b₂ mod 16`: vertex `j` takes the stratum `s = (α·j + β) mod 16` of the 4 × 4 strata of
//! the offsets, so the 16 vertices of a block read 16 different parts of the exemplar (a random
//! affine permutation: the output's histogram converges faster than with independent offsets).
//! The vertex then seeds `Prng::new(cell_hash(m, k, TILING_LAYER, seed))` and draws its offset
//! `o = lo + ((s mod 4)·n_x + b₁ mod n_x) div 4`, `lo + (⌊s/4⌋·n_y + b₂ mod n_y) div 4` in whole
//! texels (`n = span + 1`, `lo = ⌈reach⌉`, `span = n − 1 − 2·lo` per axis, [`Lattice::spans`]:
//! uniform over `[lo, lo + span]` over the strata, and no tap leaves the exemplar or wraps;
//! the exemplar need not tile); with the hex option it then draws the angle
//! `θ = rotation·(2·unit_f32(b₃) − 1)` turns.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_level, check_range};
use crate::period::Period;

/// The randomness-contract layer of tiling and blending's vertices (`"TILE"`).
pub const TILING_LAYER: u32 = 0x5449_4c45;
/// The layer of its blocks of 4 × 4 vertices (`"TILB"`).
pub const TILING_BLOCK_LAYER: u32 = 0x5449_4c42;
/// Entries of each channel's inverse look-up table.
pub const LUT_ENTRIES: usize = 1024;
/// The tables span `g ∈ [−LUT_RANGE, LUT_RANGE]` (a standard normal exceeds 5 with probability
/// 3·10⁻⁷, fewer than one pixel of a 1024² render).
pub const LUT_RANGE: f32 = 5.0;
/// Smallest exemplar side, texels.
pub const MIN_SIDE: u32 = 8;
/// Largest exemplar side, texels.
pub const MAX_SIDE: u32 = 4096;
/// Most mip levels of the exemplar (a 4096 side has 13).
pub const MAX_LEVELS: usize = 13;
/// Largest hex-tiling sharpness `γ`.
pub const MAX_SHARPNESS: u32 = 32;
/// How far a periodic model's lattice may stretch from equilateral triangles of side `tile` to
/// divide the period: 25%, as a periodic Gabor noise's kernel.
pub const TILING_PERIOD_TOLERANCE: f64 = 0.25;

/// How the three taps are blended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Blend {
    /// Heitz & Neyret's histogram-preserving blend: variance-preserving on the Gaussianised
    /// channels, then the inverse look-up table (the default).
    Variance,
    /// Mikkelsen's hex-tiling: each tap's colour blended linearly with sharpened weights, each
    /// tile rotated.
    Hex {
        /// `γ`: weights `w_iᵞ / Σ w_jᵞ` (1 to 32; 1 is plain barycentric blending).
        sharpness: u32,
        /// Largest rotation of a tile, turns (0 to 0.5; 0 keeps the exemplar's orientation).
        rotation: f32,
    },
}

/// Tiling and blending by example (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TilingTexture {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// Exemplar width, texels.
    pub width: u32,
    /// Exemplar height, texels.
    pub height: u32,
    /// Channels: 1 (grey) or 3 (colour).
    pub channels: u32,
    /// Side of the lattice's triangles, pixels (one exemplar texel per pixel).
    pub tile: f32,
    /// The blend.
    pub blend: Blend,
    /// The Gaussianised, decorrelated exemplar: `width·height·channels` values, row-major, top
    /// row first, channels interleaved.
    pub gaussian: Vec<f32>,
    /// Per channel, `T⁻¹` at the [`LUT_ENTRIES`] values of `g` (non-decreasing).
    pub lut: Vec<f32>,
    /// The colour mean, one value per channel.
    pub mean: Vec<f32>,
    /// `channels × channels`, row-major: output component `i` is `mean[i] + Σ_c basis[i·C + c]·t_c`.
    pub basis: Vec<f32>,
}

/// The triangle lattice of a model ([`TilingTexture::lattice`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    /// Cell side along `x`, pixels: the distance between neighbouring vertices of a lattice row
    /// (an even whole number, so that every vertex is a whole pixel).
    pub side: f64,
    /// Distance between lattice rows, pixels (a whole number).
    pub row: f64,
    /// A periodic lattice's vertices per row `C` and rows `K` (even), else `None`.
    pub wrap: Option<(i32, i32)>,
}

impl Lattice {
    /// The lattice of triangles of side `tile` on the pixel grid: an even side (at least 2) and
    /// a whole row spacing. Aligned so that every vertex is a whole pixel and a render at scale
    /// 1 reads whole texels. Heitz & Neyret place the lattice in the exemplar's uv space,
    /// unaligned: there every tap interpolates, and bilinear interpolation lowers the
    /// Gaussianised taps' variance (to ¼ halfway between four independent texels), so the
    /// blend's histogram narrows.
    #[must_use]
    pub fn of_tile(tile: f32) -> Self {
        let side = (2.0 * (f64::from(tile) / 2.0).round()).max(2.0);
        Self {
            side,
            row: (side * 3f64.sqrt() / 2.0).round(),
            wrap: None,
        }
    }

    /// The longest displacement from a vertex to a point of its six triangles: the longest
    /// edge, `max(side, √(side²/4 + row²))`.
    #[must_use]
    pub fn reach(&self) -> f64 {
        self.side
            .max((self.side * self.side / 4.0 + self.row * self.row).sqrt())
    }

    /// The smallest offset `lo = ⌈reach⌉` and the spans `n − 1 − 2·lo` per axis of an exemplar
    /// of `width × height` texels (`None` if either is negative: the exemplar is smaller than
    /// the tile).
    #[must_use]
    pub fn spans(&self, width: u32, height: u32) -> Option<(u32, [u32; 2])> {
        let lo = self.reach().ceil();
        let span = |n: u32| {
            let s = f64::from(n) - 1.0 - 2.0 * lo;
            (s >= 0.0).then_some(s as u32)
        };
        Some((lo as u32, [span(width)?, span(height)?]))
    }

    /// The key of vertex `(m, k)`: itself, or on a periodic lattice its representative with
    /// `k mod K`, `m + n_y·⌊k/K⌋ mod C` (`n_y = K/2`: rows `K` apart are the period's height
    /// apart and shifted by `n_y` cells along `x`).
    #[must_use]
    pub fn key(&self, m: i32, k: i32) -> (i32, i32) {
        match self.wrap {
            None => (m, k),
            Some((c, rows)) => {
                let kk = k.rem_euclid(rows);
                let q = i64::from(k.div_euclid(rows));
                let mm = (i64::from(m) + q * i64::from(rows / 2)).rem_euclid(i64::from(c));
                (mm as i32, kk)
            }
        }
    }
}

/// One mip level of the exemplar in [`TilingTables::texels`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Level {
    /// First texel of the level.
    pub offset: u32,
    /// Width, texels.
    pub width: u32,
    /// Height, texels.
    pub height: u32,
}

/// What both evaluators read, built once on the host from a model ([`TilingTexture::tables`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TilingTables {
    /// The mip levels, level 0 first.
    pub levels: Vec<Level>,
    /// Every level's texels, 4 values each (the channels, then zeros).
    pub texels: Vec<[f32; 4]>,
    /// `LUT_l` per level and channel: `levels × channels × LUT_ENTRIES` values.
    pub luts: Vec<f32>,
}

impl TilingTables {
    /// Level `l`'s table of channel `c`.
    #[must_use]
    #[inline]
    pub fn lut(&self, level: usize, channel: usize, channels: usize) -> &[f32] {
        let start = (level * channels + channel) * LUT_ENTRIES;
        &self.luts[start..start + LUT_ENTRIES]
    }
}

/// `g` of entry `k` of a table: `−R + 2R·k/(LUT_ENTRIES − 1)`.
#[must_use]
pub fn lut_node(k: usize) -> f64 {
    let r = f64::from(LUT_RANGE);
    -r + 2.0 * r * k as f64 / (LUT_ENTRIES - 1) as f64
}

/// Linear interpolation of a table at `g` in f64 (clamped to the table), for the host.
#[must_use]
pub fn lut_f64(lut: &[f32], g: f64) -> f64 {
    let r = f64::from(LUT_RANGE);
    let x = (g.clamp(-r, r) + r) * (LUT_ENTRIES - 1) as f64 / (2.0 * r);
    let i = (x.floor() as usize).min(LUT_ENTRIES - 2);
    let f = x - i as f64;
    f64::from(lut[i]) + f * (f64::from(lut[i + 1]) - f64::from(lut[i]))
}

/// The mip level and mixing weight of a window's footprint (`None`: a point sample at level
/// 0): `λ = log₂ footprint` clamped to `[0, levels − 1]`, `(⌊λ⌋, λ − ⌊λ⌋)` (the weight 0 at the
/// last level).
#[must_use]
pub fn mip_level(footprint: Option<f64>, levels: usize) -> (usize, f32) {
    let Some(f) = footprint else {
        return (0, 0.0);
    };
    let last = levels.saturating_sub(1) as f64;
    let lambda = f.log2().clamp(0.0, last);
    let l0 = lambda.floor();
    if l0 >= last {
        (last as usize, 0.0)
    } else {
        (l0 as usize, (lambda - l0) as f32)
    }
}

impl TilingTexture {
    /// The lattice: nearly equilateral triangles of side `tile` on the pixel grid (module docs),
    /// or with `period` the nearest such lattice dividing it (`None` when none is within
    /// [`TILING_PERIOD_TOLERANCE`] of the model's side and row spacing).
    #[must_use]
    pub fn lattice(&self, period: Option<Period>) -> Option<Lattice> {
        let Some(period) = period else {
            return Some(Lattice::of_tile(self.tile));
        };
        // A periodic lattice stays on the pixel grid: its side the even divisor of the period's
        // width nearest the model's, its row spacing the divisor of half the period's height
        // nearest the model's (an even number of rows), each within the tolerance.
        let base = Lattice::of_tile(self.tile);
        let nearest = |n: u32, want: f64, even: bool| -> Option<f64> {
            let mut best: Option<f64> = None;
            let mut consider = |d: u32| {
                let d = f64::from(d);
                if (!even || d % 2.0 == 0.0)
                    && (d / want - 1.0).abs() <= TILING_PERIOD_TOLERANCE
                    && best.is_none_or(|b| (d - want).abs() < (b - want).abs())
                {
                    best = Some(d);
                }
            };
            let mut i = 1u32;
            while u64::from(i) * u64::from(i) <= u64::from(n) {
                if n.is_multiple_of(i) {
                    consider(i);
                    consider(n / i);
                }
                i += 1;
            }
            best
        };
        if !period.height.is_multiple_of(2) {
            return None;
        }
        let side = nearest(period.width, base.side, true)?;
        let row = nearest(period.height / 2, base.row, false)?;
        Some(Lattice {
            side,
            row,
            wrap: Some((
                (f64::from(period.width) / side) as i32,
                (f64::from(period.height) / row) as i32,
            )),
        })
    }

    /// The colour mean and basis by rows, padded to 3 channels with zeros (what both evaluators
    /// apply: `out_i = mean_i + Σ_c basis[i][c]·t_c`).
    #[must_use]
    pub fn colour(&self) -> ([f32; 3], [[f32; 3]; 3]) {
        let nc = (self.channels as usize).min(3);
        let mut mean = [0.0f32; 3];
        let mut basis = [[0.0f32; 3]; 3];
        for i in 0..nc {
            mean[i] = self.mean[i];
            for c in 0..nc {
                basis[i][c] = self.basis[i * nc + c];
            }
        }
        (mean, basis)
    }

    /// Number of mip levels: while both sides stay at least 2 texels, up to [`MAX_LEVELS`].
    #[must_use]
    pub fn level_count(&self) -> usize {
        let mut levels = 1;
        while levels < MAX_LEVELS && (self.width >> levels) >= 2 && (self.height >> levels) >= 2 {
            levels += 1;
        }
        levels
    }

    /// The mip pyramid and the prefiltered tables of every level (module docs), in f64 rounded
    /// to f32: the same for both evaluators.
    #[must_use]
    pub fn tables(&self) -> TilingTables {
        let nc = self.channels as usize;
        let (w0, h0) = (self.width as usize, self.height as usize);
        let mut texels: Vec<[f32; 4]> = (0..w0 * h0)
            .map(|i| {
                let mut t = [0.0f32; 4];
                t[..nc].copy_from_slice(&self.gaussian[i * nc..(i + 1) * nc]);
                t
            })
            .collect();
        let mut levels = vec![Level {
            offset: 0,
            width: self.width,
            height: self.height,
        }];
        for _ in 1..self.level_count() {
            let prev = *levels.last().unwrap_or(&levels[0]);
            let (pw, ph) = (prev.width as usize, prev.height as usize);
            let (w, h) = ((pw / 2).max(1), (ph / 2).max(1));
            let base = prev.offset as usize;
            let offset = texels.len();
            for y in 0..h {
                for x in 0..w {
                    let mut acc = [0.0f64; 4];
                    for (dy, dx) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                        let (sx, sy) = ((2 * x + dx).min(pw - 1), (2 * y + dy).min(ph - 1));
                        let t = texels[base + sy * pw + sx];
                        for (a, v) in acc.iter_mut().zip(t) {
                            *a += f64::from(v);
                        }
                    }
                    texels.push(acc.map(|a| (a / 4.0) as f32));
                }
            }
            levels.push(Level {
                offset: offset as u32,
                width: w as u32,
                height: h as u32,
            });
        }
        let variance = |level: &Level, c: usize| {
            let start = level.offset as usize;
            let n = (level.width * level.height) as usize;
            let values = texels[start..start + n].iter().map(|t| f64::from(t[c]));
            let (s, s2) = values.fold((0.0, 0.0), |(s, s2), v| (s + v, s2 + v * v));
            s2 / n as f64 - (s / n as f64).powi(2)
        };
        // The standard normal on [−6, 6] in steps of 1/16, weights normalised to sum 1.
        let z: Vec<f64> = (-96..=96).map(|i| f64::from(i) / 16.0).collect();
        let phi: Vec<f64> = z.iter().map(|z| (-0.5 * z * z).exp()).collect();
        let phi_sum: f64 = phi.iter().sum();
        let mut luts = Vec::with_capacity(levels.len() * nc * LUT_ENTRIES);
        for level in &levels {
            for c in 0..nc {
                let base = &self.lut[c * LUT_ENTRIES..(c + 1) * LUT_ENTRIES];
                let lost = (variance(&levels[0], c) - variance(level, c)).max(0.0);
                let sigma = lost.sqrt();
                if sigma < 1e-6 {
                    luts.extend_from_slice(base);
                    continue;
                }
                for k in 0..LUT_ENTRIES {
                    let g = lut_node(k);
                    let e: f64 = z
                        .iter()
                        .zip(&phi)
                        .map(|(z, p)| p * lut_f64(base, g + sigma * z))
                        .sum();
                    luts.push((e / phi_sum) as f32);
                }
            }
        }
        TilingTables {
            levels,
            texels,
            luts,
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        for (name, side) in [("width", self.width), ("height", self.height)] {
            check_range(
                || format!("tiling.{name}"),
                f64::from(side),
                f64::from(MIN_SIDE),
                f64::from(MAX_SIDE),
                "8 to 4096 texels",
            )?;
        }
        if self.channels != 1 && self.channels != 3 {
            return Err(ModelError::OutOfRange {
                field: "tiling.channels".into(),
                value: f64::from(self.channels),
                range: "1 (grey) or 3 (colour)",
            });
        }
        check_range(
            || "tiling.tile".into(),
            f64::from(self.tile),
            1.0,
            f64::from(MAX_SIDE),
            "1 to 4096 pixels",
        )?;
        let lattice = self.lattice(None).ok_or_else(|| ModelError::OutOfRange {
            field: "tiling.tile".into(),
            value: f64::from(self.tile),
            range: "1 to 4096 pixels",
        })?;
        if lattice.spans(self.width, self.height).is_none() {
            return Err(ModelError::OutOfRange {
                field: "tiling.tile".into(),
                value: f64::from(self.tile),
                range: "at most (min(width, height) − 1)/2 pixels: the exemplar must hold a \
                        whole tile around each lattice vertex",
            });
        }
        match self.blend {
            Blend::Variance => {}
            Blend::Hex {
                sharpness,
                rotation,
            } => {
                check_range(
                    || "tiling.blend.hex.sharpness".into(),
                    f64::from(sharpness),
                    1.0,
                    f64::from(MAX_SHARPNESS),
                    "1 to 32",
                )?;
                check_range(
                    || "tiling.blend.hex.rotation".into(),
                    f64::from(rotation),
                    0.0,
                    0.5,
                    "0 to 0.5 turns",
                )?;
            }
        }
        let nc = self.channels as usize;
        let n = self.width as usize * self.height as usize * nc;
        check_len(
            || "tiling.gaussian".into(),
            self.gaussian.len(),
            n,
            n,
            "width·height·channels values",
        )?;
        for (k, &g) in self.gaussian.iter().enumerate() {
            check_range(
                || format!("tiling.gaussian[{k}]"),
                f64::from(g),
                -10.0,
                10.0,
                "[-10, 10] (standard normal values)",
            )?;
        }
        check_len(
            || "tiling.lut".into(),
            self.lut.len(),
            nc * LUT_ENTRIES,
            nc * LUT_ENTRIES,
            "channels × 1024 values",
        )?;
        for (k, &v) in self.lut.iter().enumerate() {
            check_level(|| format!("tiling.lut[{k}]"), v)?;
            if k % LUT_ENTRIES != 0 && v < self.lut[k - 1] {
                return Err(ModelError::OutOfRange {
                    field: format!("tiling.lut[{k}]"),
                    value: f64::from(v),
                    range: "at least the entry before it (a quantile function never decreases)",
                });
            }
        }
        check_len(
            || "tiling.mean".into(),
            self.mean.len(),
            nc,
            nc,
            "one value per channel",
        )?;
        for (k, &v) in self.mean.iter().enumerate() {
            check_level(|| format!("tiling.mean[{k}]"), v)?;
        }
        check_len(
            || "tiling.basis".into(),
            self.basis.len(),
            nc * nc,
            nc * nc,
            "channels × channels values",
        )?;
        for (k, &v) in self.basis.iter().enumerate() {
            check_level(|| format!("tiling.basis[{k}]"), v)?;
        }
        Ok(())
    }
}

impl TilingTexture {
    /// Triangles of 64 pixels: the tile Heitz & Neyret's figures use on 256–512 exemplars
    /// (a quarter of the exemplar), large enough to keep its features whole.
    pub const DEFAULT_TILE: f32 = 64.0;
    /// The histogram-preserving blend.
    pub const DEFAULT_BLEND: Blend = Blend::Variance;
    /// Mikkelsen's contrast, as an integer exponent: his default fall-off gives weights close
    /// to the 7th power of the barycentric ones.
    pub const DEFAULT_SHARPNESS: u32 = 7;
}

impl crate::ModelKind for TilingTexture {
    const NAME: &'static str = "tiling";

    const PERIODIC: bool = true;

    fn validate(&self) -> Result<(), ModelError> {
        TilingTexture::validate(self)
    }

    fn output_channels(&self) -> usize {
        self.channels as usize
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }

    /// A period the lattice can be fitted to (within [`TILING_PERIOD_TOLERANCE`]) whose
    /// stretched tile still fits the exemplar.
    fn check_period(&self, period: Period) -> Result<(), ModelError> {
        let fits = self
            .lattice(Some(period))
            .is_some_and(|l| l.spans(self.width, self.height).is_some());
        if fits {
            Ok(())
        } else {
            Err(ModelError::Period {
                period: period.to_string(),
                kind: "tiling",
                requirement: {
                    let (side, row) = self.lattice(None).map_or((0.0, 0.0), |l| (l.side, l.row));
                    format!(
                        "the triangle lattice (side {side} px, rows {row} px apart) must divide \
                         the period, with a side within 25% of {side} dividing its width and a \
                         row spacing within 25% of {row} dividing half its height, and still \
                         fit the {}×{} exemplar: use a period of a multiple of {side} × {}",
                        self.width,
                        self.height,
                        2.0 * row
                    )
                },
            })
        }
    }
}

impl From<TilingTexture> for crate::Model {
    fn from(m: TilingTexture) -> Self {
        Self::Tiling(m)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// A valid grey model: a 16² exemplar of a ramp of standard-normal-ish values and the
    /// identity table (`T⁻¹(g) = g`).
    fn ramp(side: u32, tile: f32) -> TilingTexture {
        let n = (side * side) as usize;
        TilingTexture {
            seed: 3,
            width: side,
            height: side,
            channels: 1,
            tile,
            blend: Blend::Variance,
            gaussian: (0..n).map(|i| (i % 7) as f32 - 3.0).collect(),
            lut: (0..LUT_ENTRIES).map(|k| lut_node(k) as f32).collect(),
            mean: vec![0.5],
            basis: vec![0.1],
        }
    }

    pub fn validation_names_the_field_and_range() {
        assert!(ramp(16, 4.0).validate().is_ok());
        let field = |m: TilingTexture| match m.validate() {
            Err(ModelError::OutOfRange { field, .. } | ModelError::Length { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        // Reach 8: offsets from 8 to 15 − 8 = 7, none: the exemplar is smaller than the tile.
        assert_eq!(field(ramp(16, 8.0)), "tiling.tile");
        // Side 6, rows 5 apart, reach 6: offsets 6..=9.
        assert!(ramp(16, 6.0).validate().is_ok());
        // 7 rounds to an even side of 8: no room.
        assert_eq!(field(ramp(16, 7.0)), "tiling.tile");
        assert_eq!(field(ramp(4, 1.0)), "tiling.width");
        let mut m = ramp(16, 4.0);
        m.gaussian[5] = f32::NAN;
        assert_eq!(field(m), "tiling.gaussian[5]");
        let mut m = ramp(16, 4.0);
        m.lut[9] = -100.0;
        assert_eq!(field(m), "tiling.lut[9]");
        let mut m = ramp(16, 4.0);
        m.channels = 4;
        assert_eq!(field(m), "tiling.channels");
        let mut m = ramp(16, 4.0);
        m.blend = Blend::Hex {
            sharpness: 0,
            rotation: 0.1,
        };
        assert_eq!(field(m), "tiling.blend.hex.sharpness");
        let mut m = ramp(16, 4.0);
        m.basis.push(1.0);
        assert_eq!(field(m), "tiling.basis");
    }

    pub fn periodic_lattice_keys_repeat_with_the_period() {
        let m = ramp(64, 8.0);
        let period = Period::new(96, 84).unwrap();
        let l = m.lattice(Some(period)).unwrap();
        // Side 8 divides 96; rows round(8·√3/2) = 7 apart divide 42.
        assert_eq!((l.side, l.row), (8.0, 7.0));
        let (c, rows) = l.wrap.unwrap();
        assert_eq!(c as f64 * l.side, 96.0);
        assert_eq!(f64::from(rows) * l.row, 84.0);
        // 100 = 10 × 10 (side 10, 25% above 8); 64/2 = 32: rows 8 apart (7 + 14%).
        let other = m.lattice(Some(Period::new(100, 64).unwrap())).unwrap();
        assert_eq!(
            (other.side, other.row, other.wrap),
            (10.0, 8.0, Some((10, 8)))
        );
        for (mm, k) in [(0, 0), (3, 5), (-2, -1), (7, 13)] {
            // The vertex one period to the right, and one period down (n_y cells further left
            // along the row index), have the same key.
            assert_eq!(l.key(mm, k), l.key(mm + c, k));
            assert_eq!(l.key(mm, k), l.key(mm - rows / 2, k + rows));
        }
        assert!(m.lattice(Some(Period::new(11, 84).unwrap())).is_none());
    }

    pub fn pyramid_averages_and_tables_keep_the_identity_mean() {
        let m = ramp(16, 4.0);
        let t = m.tables();
        assert_eq!(t.levels.len(), 4, "16, 8, 4, 2");
        let l1 = t.levels[1];
        assert_eq!((l1.width, l1.height, l1.offset), (8, 8, 256));
        // Texel (1, 2) of level 1 averages level-0 texels (2..4, 4..6).
        let expect: f64 = [(2, 4), (3, 4), (2, 5), (3, 5)]
            .iter()
            .map(|&(x, y)| f64::from(m.gaussian[y * 16 + x]))
            .sum::<f64>()
            / 4.0;
        assert!((f64::from(t.texels[256 + 2 * 8 + 1][0]) - expect).abs() < 1e-6);
        // E[g + σZ] = g: a linear table stays linear inside the range whatever σ.
        for level in 0..4 {
            let lut = t.lut(level, 0, 1);
            let mid = LUT_ENTRIES / 2;
            assert!(
                (f64::from(lut[mid]) - lut_node(mid)).abs() < 1e-4,
                "level {level}"
            );
        }
    }

    pub fn mip_level_follows_the_footprint() {
        assert_eq!(mip_level(None, 5), (0, 0.0));
        assert_eq!(mip_level(Some(4.0), 5), (2, 0.0));
        let (l, t) = mip_level(Some(6.0), 5);
        assert_eq!(l, 2);
        assert!((f64::from(t) - (6f64.log2() - 2.0)).abs() < 1e-6);
        assert_eq!(mip_level(Some(1e6), 5), (4, 0.0));
    }

    pub fn json_round_trip() {
        let m = crate::Model::Tiling(ramp(16, 4.0));
        let text = crate::to_json(&m).unwrap();
        assert_eq!(crate::from_json(&text).unwrap(), m);
    }
}
