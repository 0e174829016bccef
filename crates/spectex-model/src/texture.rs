//! Texture by example (Gilet et al. 2014, §5 and the colour paragraph of §6): per channel, a
//! structure `n_R` with fixed phases (Eq. 4, complexity-reduced by blocks as in §5.3) plus
//! random-phase strata (Eq. 2); turbulence that distorts the structure (§5.2), random placement
//! of half-period blocks (§5.2), and a colour basis that maps decorrelated channels back to RGB.
//!
//! The per-pixel definition of the structure, the placement and the colour transform is written
//! once here, in `f32` with plain `*` and `+` (see [`crate::math`]), and used by the CPU
//! evaluator; `shaders/texture.wgsl` twins it operation for operation.
//!
//! ## The structure `n_R`
//! The structure image (the exemplar block's spectrum on the region `R`, inverse transformed)
//! has period `T` ([`TextureModel::period`]). It is cut into `b × b` blocks
//! ([`Structure::blocks`]) of side `Δ_R = T/b`. Lattice point `(i, j)` sits at `(iΔ_R, jΔ_R)`;
//! its cosines describe the structure image on the `N × N` square centred on it, `N = 2Δ_R`, as
//! `s_ij(u) = Σ_k A_k cos 2π(k·u/N + φ_k)`, `u` relative to the lattice point. A position `q` in
//! `[0, T)²` blends the 2×2 lattice points around it with the separable weights
//! `h(t) = cos²(πt/2)` of the offset `t ∈ [0, 1)` in lattice units: `h(t) + h(1 − t) = 1`, so the
//! weights are an exact partition of unity (the paper's Kaiser–Bessel windows sum to 1 only
//! within 5%, which would break the `r = 1` reproduction), and a block is weighted 0 where its
//! square wraps. With `b = 1` the one block is evaluated once, at `u = q`.
//!
//! ## Placement and turbulence
//! The plane is cut into placement cells of side `P = T/2` (the paper's blocks of size ½). Cell
//! `c` draws a shift `t_c ∈ [0, T)²` from `cell_hash(c, PLACEMENT_LAYER, seed)`. Near a cell
//! border (within `P/8`) the neighbours' shifted structures are cross-faded with `sin²` weights
//! and the sum divided by `√Σω²`, which keeps the variance of uncorrelated structures. The
//! turbulence displacement `d(x) = σ(Σ_S |n_S(x)| − centre)` (one field per axis) is evaluated at
//! the unshifted `x` and added after the shift, so the distortion is continuous everywhere
//! (§5.2: "random placement must be applied first").
//!
//! ## No builder
//! Unlike the procedural kinds, a [`TextureModel`] has no builder and no `DEFAULT_` constants:
//! its fields (strata of fitted cosines, the structure's blocks of phases, the colour basis)
//! are measured from an exemplar, not chosen, so there is no default texture to start from and
//! no field a caller would set by hand. It is made by `spectex_sampling::fit_texture`, whose
//! options are the settings with defaults (`FitOptions::DEFAULT_BUDGET`,
//! `TextureOptions::DEFAULT_STRUCTURE`, …, the `spectex fit` and `spectex synth` flags'
//! defaults), and read from model files; both validate it ([`TextureModel::validate`]).

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_level, check_range};
use crate::lrp::validate_strata;
use crate::math::cos_turns;
use crate::random::{Prng, cell_hash};
use crate::{MAX_COSINES, MAX_STRATA, Stratum};

/// Hash layer of the placement shifts.
pub const PLACEMENT_LAYER: u32 = 0x504c_4143; // "PLAC"
/// Half-width of the cross-fade at placement-cell borders, in cells (`P/8`).
pub const PLACEMENT_BLEND: f32 = 0.125;
/// Largest structure period `T`, pixels.
pub const MAX_PERIOD: u32 = 4096;
/// Most fixed cosines in one structure (all blocks together).
pub const MAX_STRUCTURE_COSINES: usize = 1 << 22;
/// Most channels of a texture (grey or a colour basis).
pub const MAX_CHANNELS: usize = 3;

/// A texture by example.
///
/// It has no builder: its structure, strata and colour basis are measured from an exemplar,
/// so a texture comes from `spectex_sampling::fit_texture(exemplar, &TextureOptions { structure:
/// 0.2, turbulence: 3.0, random_placement: true, .. })`, which returns it with a report of what
/// the fit kept (`crates/spectex-cli/examples/02_fit_and_render.rs` does it and renders the
/// result). Its seeds can then be changed with [`crate::Model::reseeded`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureModel {
    /// Seed of the placement shifts.
    pub seed: u32,
    /// `T`, the period of the structure image in pixels: a power of two in `2..=4096` (the
    /// Welch block side of the exemplar).
    pub period: u32,
    /// One channel (grey) or three (the components of [`Self::colour`]).
    pub channels: Vec<TextureChannel>,
    /// Maps the channels to RGB; required with three channels, absent with one.
    pub colour: Option<ColourBasis>,
    /// Distortion of the structure (§5.2), absent for none.
    pub turbulence: Option<Turbulence>,
    /// Random placement of half-period blocks (§5.2).
    pub random_placement: bool,
}

/// One channel: `mean + Σ_S n_S(x) + n_R(placed(x))`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureChannel {
    /// Seed of the random-phase strata (an LRP noise with these strata and this seed).
    pub seed: u32,
    /// Constant of the channel.
    pub mean: f32,
    /// The random-phase strata (`(1 − r)J` cosines); may be empty (`r = 1`).
    pub strata: Vec<Stratum>,
    /// The fixed-phase structure `n_R`; absent for `r = 0`.
    pub structure: Option<Structure>,
}

/// The structure `n_R` of one channel, in blocks (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Structure {
    /// `b`, blocks per period side: a power of two in `1..=T`. `Δ_R = T/b`.
    pub blocks: u32,
    /// The cosines of each block, row-major (`b·j + i` for block column `i`, row `j`).
    pub cosines: Vec<Vec<FixedCosine>>,
}

/// One fixed cosine `A cos 2π(k·u/N + φ)` of a structure block.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedCosine {
    /// `k`, integer cycles per block square `N = 2T/b`, each in `(−N/2, N/2]`.
    pub frequency: [i32; 2],
    /// `A`.
    pub amplitude: f32,
    /// `φ`, turns, in `[0, 1)`.
    pub phase: f32,
}

/// `rgb_i = mean_i + Σ_c basis[i][c]·channel_c` (PCA of the exemplar's colours: the columns
/// are the principal axes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColourBasis {
    /// The exemplar's mean colour.
    pub mean: [f32; 3],
    /// Row `i` maps the channels to colour component `i`.
    pub basis: [[f32; 3]; 3],
}

/// Turbulence `n_T = Σ_S |n_S|` (§5.2), one field per axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Turbulence {
    /// `σ`, pixels: the displacement is `σ(n_T − centre)`.
    pub sigma: f32,
    /// Seeds of the x and y fields. Stratum `S` of axis `a` is the single-stratum LRP noise
    /// (mean 0) with seed `seeds[a] + S` (wrapping).
    pub seeds: [u32; 2],
    /// The strata, fitted from the exemplar's whole spectrum at unit variance.
    pub strata: Vec<Stratum>,
    /// `E[n_T]`, subtracted so the displacement has mean about 0.
    pub centre: f32,
}

impl Turbulence {
    /// The seed of stratum `s` of axis `axis`.
    #[must_use]
    pub fn seed(&self, axis: usize, s: usize) -> u32 {
        self.seeds[axis].wrapping_add(s as u32)
    }

    /// The displacement on one axis from its strata's values `Σ_S |n_S|` (summed in order).
    #[inline]
    #[must_use]
    pub fn displacement(&self, sum_abs: f32) -> f32 {
        self.sigma * (sum_abs - self.centre)
    }
}

impl Structure {
    /// Total fixed cosines over all blocks.
    #[must_use]
    pub fn total_cosines(&self) -> usize {
        self.cosines.iter().map(Vec::len).sum()
    }

    /// Cosines evaluated per pixel: the largest block's count, times 4 blocks unless `b = 1`.
    #[must_use]
    pub fn cosines_per_pixel(&self) -> usize {
        let most = self.cosines.iter().map(Vec::len).max().unwrap_or(0);
        if self.blocks == 1 { most } else { 4 * most }
    }

    /// `n_R` at `q ∈ [0, T)²` (pixels, reduced modulo the period) for period `period`.
    #[must_use]
    pub fn eval(&self, period: u32, q: [f32; 2]) -> f32 {
        let b = self.blocks;
        if b == 1 {
            return block_value(&self.cosines[0], 1.0 / (2 * period) as f32, q[0], q[1]);
        }
        let delta = (period / b) as f32;
        // 0.5·(1/Δ), as the WGSL twin rounds it.
        let inv_n = 0.5 * (1.0 / delta);
        cross_fade(b, delta, q, |row, col, ux, uy| {
            block_value(&self.cosines[(row * b + col) as usize], inv_n, ux, uy)
        })
    }
}

impl Structure {
    /// The mipmap of block means (LRP §6: the zero frequencies of the fixed-phase blocks
    /// cannot be faded out, so a minified render averages them): level 0 holds each block's
    /// zero-frequency cosines, `Σ A·cos 2πφ` over `k = (0, 0)` (row-major, `b × b`), level
    /// `ℓ + 1` the means of level `ℓ`'s aligned 2×2 groups, down to one value; all levels
    /// concatenated. f32 sums in a fixed order, shared by both evaluators.
    #[must_use]
    pub fn mean_mipmap(&self) -> Vec<f32> {
        let b = self.blocks as usize;
        let mut all: Vec<f32> = self
            .cosines
            .iter()
            .map(|block| {
                block
                    .iter()
                    .filter(|c| c.frequency == [0, 0])
                    .map(|c| c.amplitude * cos_turns(c.phase))
                    .sum()
            })
            .collect();
        let (mut start, mut side) = (0, b);
        while side > 1 {
            let half = side / 2;
            for j in 0..half {
                for i in 0..half {
                    let at = |di: usize, dj: usize| all[start + (2 * j + dj) * side + 2 * i + di];
                    let m = 0.25 * (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1));
                    all.push(m);
                }
            }
            start += side * side;
            side = half;
        }
        all
    }

    /// `n_R` at `q` in a minified render of footprint `s` pixels: every block's non-zero
    /// cosines weighted by [`crate::filter::response_f32`] of `|k_x|·s/N` times that of
    /// `|k_y|·s/N` (LRP §6 frequency clamping), and its zero frequencies read from the mipmap
    /// `mip` ([`Self::mean_mipmap`]) at level `λ = log₂(s/Δ_R)` (clamped to `[0, log₂ b]`),
    /// linearly between the two levels around it, each level cross-faded on its own grid of
    /// side `2^ℓ·Δ_R` as [`Self::eval`] cross-fades blocks. At `s ≤ Δ_R` the zero frequencies
    /// are [`Self::eval`]'s.
    #[must_use]
    pub fn eval_filtered(&self, period: u32, q: [f32; 2], s: f32, mip: &[f32]) -> f32 {
        let b = self.blocks;
        if b == 1 {
            let inv_n = 1.0 / (2 * period) as f32;
            return block_value_filtered(&self.cosines[0], inv_n, q[0], q[1], s) + mip[0];
        }
        let delta = (period / b) as f32;
        let inv_delta = 1.0 / delta;
        let inv_n = 0.5 * inv_delta;
        let mut sum = cross_fade(b, delta, q, |row, col, ux, uy| {
            block_value_filtered(&self.cosines[(row * b + col) as usize], inv_n, ux, uy, s)
        });
        let top = b.trailing_zeros();
        let lambda = (s * inv_delta).log2().clamp(0.0, top as f32);
        let low = (lambda as u32).min(top);
        let f = lambda - low as f32;
        let level = |l: u32| {
            let side = b >> l;
            // Levels before `l`: b², (b/2)², …
            let start: usize = (0..l).map(|k| ((b >> k) * (b >> k)) as usize).sum();
            if side == 1 {
                return mip[start];
            }
            let d = delta * (1u32 << l) as f32;
            cross_fade(side, d, q, |row, col, _, _| {
                mip[start + (row * side + col) as usize]
            })
        };
        sum += level(low) * (1.0 - f);
        if f > 0.0 {
            sum += level(low + 1) * f;
        }
        sum
    }
}

/// The 2×2 cross-fade of [`Structure::eval`] on a grid of `b × b` cells of side `delta` (the
/// period): `value(row, col, u_x, u_y)` of each cell around `q`, `u` relative to the cell,
/// weighted by `cos²`-shaped weights, summed in [`Structure::eval`]'s order.
fn cross_fade(b: u32, delta: f32, q: [f32; 2], value: impl Fn(u32, u32, f32, f32) -> f32) -> f32 {
    let inv_delta = 1.0 / delta;
    let gx = q[0] * inv_delta;
    let gy = q[1] * inv_delta;
    let fx = gx.floor();
    let fy = gy.floor();
    let tx = gx - fx;
    let ty = gy - fy;
    let i0 = fx as i32;
    let j0 = fy as i32;
    let hx = 0.5 + 0.5 * cos_turns(0.5 * tx);
    let hy = 0.5 + 0.5 * cos_turns(0.5 * ty);
    let mut sum = 0.0f32;
    for dj in 0..2 {
        let wy = if dj == 0 { hy } else { 1.0 - hy };
        let uy = (ty - dj as f32) * delta;
        let row = (j0 + dj).rem_euclid(b as i32) as u32;
        for di in 0..2 {
            let wx = if di == 0 { hx } else { 1.0 - hx };
            let ux = (tx - di as f32) * delta;
            let col = (i0 + di).rem_euclid(b as i32) as u32;
            sum += wx * wy * value(row, col, ux, uy);
        }
    }
    sum
}

/// [`block_value`] without the zero frequency, each cosine weighted for a footprint of `s`
/// pixels (see [`Structure::eval_filtered`]).
#[must_use]
pub fn block_value_filtered(cosines: &[FixedCosine], inv_n: f32, ux: f32, uy: f32, s: f32) -> f32 {
    use crate::filter::response_f32;
    let mut sum = 0.0f32;
    for c in cosines {
        if c.frequency == [0, 0] {
            continue;
        }
        let (kx, ky) = (c.frequency[0] as f32, c.frequency[1] as f32);
        let gain = response_f32(kx.abs() * inv_n * s) * response_f32(ky.abs() * inv_n * s);
        if gain == 0.0 {
            continue;
        }
        let t = (kx * ux + ky * uy) * inv_n + c.phase;
        sum += gain * c.amplitude * cos_turns(t);
    }
    sum
}

/// `Σ_k A_k cos 2π(k·u·inv_n + φ_k)`, in the order of the list.
#[inline]
#[must_use]
pub fn block_value(cosines: &[FixedCosine], inv_n: f32, ux: f32, uy: f32) -> f32 {
    let mut sum = 0.0f32;
    for c in cosines {
        let t = (c.frequency[0] as f32 * ux + c.frequency[1] as f32 * uy) * inv_n + c.phase;
        sum += c.amplitude * cos_turns(t);
    }
    sum
}

/// Where one pixel reads the structure: up to four `(weight, q)` pairs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// How many of [`Self::taps`] are used.
    pub count: usize,
    /// `(weight, q)`, `q` in `[0, T)²` pixels.
    pub taps: [(f32, [f32; 2]); 4],
}

/// The shift of placement cell `(cx, cy)`, pixels in `[0, T)²`.
#[must_use]
pub fn placement_shift(seed: u32, period: u32, cx: i32, cy: i32) -> [f32; 2] {
    let mut rng = Prng::new(cell_hash(cx, cy, PLACEMENT_LAYER, seed));
    let t = period as f32;
    let sx = rng.next_f32() * t;
    let sy = rng.next_f32() * t;
    [sx, sy]
}

/// `sin²(πa/2)`, the cross-fade weight of the cell being entered.
#[inline]
fn fade(a: f32) -> f32 {
    0.5 - 0.5 * cos_turns(0.5 * a)
}

/// The cells along one axis and their weights for a local coordinate `s ∈ [0, 1)` in cell `c`.
fn axis_taps(c: i32, s: f32, blend: bool) -> ([(i32, f32); 2], usize) {
    if blend && s < PLACEMENT_BLEND {
        let g = fade((s + PLACEMENT_BLEND) / (2.0 * PLACEMENT_BLEND));
        ([(c, g), (c.wrapping_sub(1), 1.0 - g)], 2)
    } else if blend && s >= 1.0 - PLACEMENT_BLEND {
        let g = fade((s - (1.0 - PLACEMENT_BLEND)) / (2.0 * PLACEMENT_BLEND));
        ([(c, 1.0 - g), (c.wrapping_add(1), g)], 2)
    } else {
        ([(c, 1.0), (c, 0.0)], 1)
    }
}

/// Reduces `q` modulo `t` (a power of two) to `[0, t]` (`t` itself only by rounding).
#[inline]
fn wrap(q: f32, t: f32) -> f32 {
    q - t * (q * (1.0 / t)).floor()
}

impl TextureModel {
    /// Placement cell side `P = T/2`, pixels.
    #[must_use]
    pub fn placement_cell(&self) -> f64 {
        f64::from(self.period) / 2.0
    }

    /// The structure taps of a pixel whose placement cells are `(cx, sx)`, `(cy, sy)` (from
    /// [`crate::grid::locate_cell`] with side [`Self::placement_cell`]) and whose turbulence
    /// displacement is `d` pixels.
    #[must_use]
    pub fn placement(&self, cx: i32, sx: f32, cy: i32, sy: f32, d: [f32; 2]) -> Placement {
        self.placement_in(cx, sx, cy, sy, d, None)
    }

    /// [`Self::placement`] of a model made periodic with `cells` placement cells per period
    /// along x and y (an even number: the period is a multiple of `T`): a cell's shift is drawn
    /// for its index modulo `cells`, so that cells one period apart move the structure alike.
    #[must_use]
    pub fn placement_in(
        &self,
        cx: i32,
        sx: f32,
        cy: i32,
        sy: f32,
        d: [f32; 2],
        cells: Option<[i64; 2]>,
    ) -> Placement {
        let t = self.period as f32;
        let p = 0.5 * t;
        let bx = ((cx & 1) as f32 + sx) * p;
        let by = ((cy & 1) as f32 + sy) * p;
        let mut out = Placement {
            count: 0,
            taps: [(0.0, [0.0, 0.0]); 4],
        };
        if !self.random_placement {
            out.count = 1;
            out.taps[0] = (1.0, [wrap(bx + d[0], t), wrap(by + d[1], t)]);
            return out;
        }
        let (xs, nx) = axis_taps(cx, sx, true);
        let (ys, ny) = axis_taps(cy, sy, true);
        let mut norm = 0.0f32;
        for &(ccy, wy) in &ys[..ny] {
            for &(ccx, wx) in &xs[..nx] {
                let (hx, hy) = match cells {
                    None => (ccx, ccy),
                    Some([nx, ny]) => (
                        crate::period::wrap(i64::from(ccx), nx) as i32,
                        crate::period::wrap(i64::from(ccy), ny) as i32,
                    ),
                };
                let shift = placement_shift(self.seed, self.period, hx, hy);
                let w = wx * wy;
                norm += w * w;
                out.taps[out.count] = (
                    w,
                    [wrap(bx + shift[0] + d[0], t), wrap(by + shift[1] + d[1], t)],
                );
                out.count += 1;
            }
        }
        if out.count > 1 {
            let inv = 1.0 / norm.sqrt();
            for tap in &mut out.taps[..out.count] {
                tap.0 *= inv;
            }
        }
        out
    }

    /// The structure of channel `c` at a pixel with these taps in a minified render of footprint
    /// `s` pixels, `mip` the channel's [`Structure::mean_mipmap`].
    #[must_use]
    pub fn structure_at_filtered(&self, c: usize, taps: &Placement, s: f32, mip: &[f32]) -> f32 {
        let Some(structure) = &self.channels[c].structure else {
            return 0.0;
        };
        let mut sum = 0.0f32;
        for &(w, q) in &taps.taps[..taps.count] {
            sum += w * structure.eval_filtered(self.period, q, s, mip);
        }
        sum
    }

    /// The structure of channel `c` at a pixel with these taps.
    #[must_use]
    pub fn structure_at(&self, c: usize, taps: &Placement) -> f32 {
        let Some(structure) = &self.channels[c].structure else {
            return 0.0;
        };
        let mut sum = 0.0f32;
        for &(w, q) in &taps.taps[..taps.count] {
            sum += w * structure.eval(self.period, q);
        }
        sum
    }

    /// Colour component `i` of channel values `v` (the identity with one channel).
    #[must_use]
    pub fn colour_component(&self, i: usize, v: &[f32]) -> f32 {
        match &self.colour {
            None => v[i],
            Some(c) => {
                let row = c.basis[i];
                c.mean[i] + row[0] * v[0] + row[1] * v[1] + row[2] * v[2]
            }
        }
    }

    /// Output values per pixel: 1 (grey) or 3 (RGB).
    #[must_use]
    pub fn output_channels(&self) -> usize {
        self.channels.len()
    }

    /// Special-function calls (cosines and windows) per pixel of the random-phase strata, the
    /// structure and the turbulence, for reports: `9(J_S + 1)` per stratum as in the paper's
    /// §6.2, the structure's cosines (times 4 placement taps at most, counted once), and `9(J+1)`
    /// per turbulence stratum and axis.
    #[must_use]
    pub fn special_calls_per_pixel(&self) -> usize {
        let strata = |s: &[Stratum]| s.iter().map(|st| 9 * (st.cosines() + 1)).sum::<usize>();
        let mut n = 0;
        for ch in &self.channels {
            n += strata(&ch.strata);
            if let Some(st) = &ch.structure {
                n += st.cosines_per_pixel();
            }
        }
        if let Some(t) = &self.turbulence {
            n += 2 * strata(&t.strata);
        }
        n
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        if !(self.period.is_power_of_two() && (2..=MAX_PERIOD).contains(&self.period)) {
            return Err(ModelError::OutOfRange {
                field: "texture.period".into(),
                value: f64::from(self.period),
                range: "a power of two in 2..=4096 pixels",
            });
        }
        check_len(
            || "texture.channels".into(),
            self.channels.len(),
            1,
            MAX_CHANNELS,
            "1 (grey) or 3 (colour) channels",
        )?;
        match (&self.colour, self.channels.len()) {
            (None, 1) => {}
            (Some(c), 3) => {
                for i in 0..3 {
                    check_level(|| format!("texture.colour.mean[{i}]"), c.mean[i])?;
                    for j in 0..3 {
                        check_range(
                            || format!("texture.colour.basis[{i}][{j}]"),
                            f64::from(c.basis[i][j]),
                            -1e3,
                            1e3,
                            "[-1e3, 1e3]",
                        )?;
                    }
                }
            }
            (_, n) => {
                return Err(ModelError::Length {
                    field: "texture.channels".into(),
                    len: n,
                    range: "1 without a colour basis, 3 with one",
                });
            }
        }
        for (c, ch) in self.channels.iter().enumerate() {
            check_level(|| format!("texture.channels[{c}].mean"), ch.mean)?;
            check_len(
                || format!("texture.channels[{c}].strata"),
                ch.strata.len(),
                0,
                MAX_STRATA,
                "0 to 64 strata",
            )?;
            validate_strata(&format!("texture.channels[{c}].strata"), &ch.strata)?;
            if let Some(s) = &ch.structure {
                self.validate_structure(c, s)?;
            }
        }
        if let Some(t) = &self.turbulence {
            check_range(
                || "texture.turbulence.sigma".into(),
                f64::from(t.sigma),
                0.0,
                1e6,
                "[0, 1e6] pixels",
            )?;
            check_level(|| "texture.turbulence.centre".into(), t.centre)?;
            check_len(
                || "texture.turbulence.strata".into(),
                t.strata.len(),
                1,
                MAX_STRATA,
                "1 to 64 strata",
            )?;
            validate_strata("texture.turbulence.strata", &t.strata)?;
        }
        Ok(())
    }

    fn validate_structure(&self, c: usize, s: &Structure) -> Result<(), ModelError> {
        if !(s.blocks.is_power_of_two() && s.blocks <= self.period) {
            return Err(ModelError::OutOfRange {
                field: format!("texture.channels[{c}].structure.blocks"),
                value: f64::from(s.blocks),
                range: "a power of two in 1..=period",
            });
        }
        let blocks = (s.blocks * s.blocks) as usize;
        if s.cosines.len() != blocks {
            return Err(ModelError::Length {
                field: format!("texture.channels[{c}].structure.cosines"),
                len: s.cosines.len(),
                range: "blocks² lists (one per block)",
            });
        }
        let total = s.total_cosines();
        if total > MAX_STRUCTURE_COSINES {
            return Err(ModelError::Length {
                field: format!("texture.channels[{c}].structure.cosines"),
                len: total,
                range: "at most 4194304 cosines over all blocks",
            });
        }
        let n = (2 * self.period / s.blocks) as i32;
        for (k, block) in s.cosines.iter().enumerate() {
            check_len(
                || format!("texture.channels[{c}].structure.cosines[{k}]"),
                block.len(),
                0,
                MAX_COSINES,
                "0 to 1024 cosines",
            )?;
            for (j, cos) in block.iter().enumerate() {
                for axis in 0..2 {
                    let f = cos.frequency[axis];
                    if !(f > -n / 2 && f <= n / 2) {
                        return Err(ModelError::OutOfRange {
                            field: format!(
                                "texture.channels[{c}].structure.cosines[{k}][{j}].frequency[{axis}]"
                            ),
                            value: f64::from(f),
                            range: "(−N/2, N/2] with N = 2·period/blocks",
                        });
                    }
                }
                check_range(
                    || format!("texture.channels[{c}].structure.cosines[{k}][{j}].amplitude"),
                    f64::from(cos.amplitude),
                    0.0,
                    1e9,
                    "[0, 1e9]",
                )?;
                check_range(
                    || format!("texture.channels[{c}].structure.cosines[{k}][{j}].phase"),
                    f64::from(cos.phase),
                    0.0,
                    1.0,
                    "[0, 1] turns",
                )?;
            }
        }
        Ok(())
    }
}

impl crate::ModelKind for TextureModel {
    const PERIODIC: bool = true;

    /// A period that is a multiple of the structure's period `T` along x and y: the structure
    /// (cosines of integer frequencies over `T`) repeats within it, the placement cells (`T/2`)
    /// wrap, and the random-phase strata and turbulence are LRP lattices fitted to it.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        if period.width.is_multiple_of(self.period) && period.height.is_multiple_of(self.period) {
            return Ok(());
        }
        Err(ModelError::Period {
            period: period.to_string(),
            kind: "texture",
            requirement: format!(
                "its structure repeats every T = {} pixels; the period's width and height must \
                 be multiples of it",
                self.period
            ),
        })
    }

    const NAME: &'static str = "texture";

    fn validate(&self) -> Result<(), ModelError> {
        TextureModel::validate(self)
    }

    fn output_channels(&self) -> usize {
        TextureModel::output_channels(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
        for channel in &mut self.channels {
            visit(&mut channel.seed);
        }
        if let Some(turbulence) = &mut self.turbulence {
            for seed in &mut turbulence.seeds {
                visit(seed);
            }
        }
    }
}

impl From<TextureModel> for crate::Model {
    fn from(texture: TextureModel) -> Self {
        Self::Texture(texture)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// A structure of `b × b` blocks whose zero frequency (block mean) is `0.1·(index + 1)`,
    /// with one non-zero cosine each.
    fn blocks_with_means(b: u32) -> Structure {
        Structure {
            blocks: b,
            cosines: (0..b * b)
                .map(|k| {
                    vec![
                        FixedCosine {
                            frequency: [0, 0],
                            amplitude: 0.1 * (k + 1) as f32,
                            phase: 0.0,
                        },
                        FixedCosine {
                            frequency: [3, -1],
                            amplitude: 0.2,
                            phase: 0.3,
                        },
                    ]
                })
                .collect(),
        }
    }

    /// Level 1 holds the means of aligned 2×2 groups, the last level the mean of all blocks
    /// (sums of the values `0.1·(k + 1)` by hand).
    pub fn mean_mipmap_averages_aligned_groups() {
        let mip = blocks_with_means(4).mean_mipmap();
        assert_eq!(mip.len(), 16 + 4 + 1);
        // Group (0, 0): blocks 0, 1, 4, 5 → 0.1·(1 + 2 + 5 + 6)/4 = 0.35.
        assert!((mip[16] - 0.35).abs() < 1e-6, "{}", mip[16]);
        // All: 0.1·(1 + … + 16)/16 = 0.85.
        assert!((mip[20] - 0.85).abs() < 1e-6, "{}", mip[20]);
    }

    /// A footprint past the whole period leaves only the global mean (every cosine faded, the
    /// top mipmap level); a moderate one keeps the mean of the field over the period.
    pub fn filtered_structure_fades_to_the_mean() {
        let st = blocks_with_means(4);
        let mip = st.mean_mipmap();
        for q in [[0.0f32, 0.0], [3.7, 25.1], [31.9, 8.0]] {
            let v = st.eval_filtered(32, q, 1000.0, &mip);
            assert!((v - 0.85).abs() < 1e-6, "{q:?}: {v}");
        }
        let n = 256;
        let mut mean = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let q = [
                    (i as f32 + 0.5) * 32.0 / n as f32,
                    (j as f32 + 0.5) * 32.0 / n as f32,
                ];
                mean += f64::from(st.eval_filtered(32, q, 12.0, &mip));
            }
        }
        mean /= f64::from(n * n);
        assert!((mean - 0.85).abs() < 1e-3, "mean {mean}");
    }

    fn structure_model(blocks: u32, period: u32, placement: bool) -> TextureModel {
        let n = (2 * period / blocks) as i32;
        let cosines = (0..blocks * blocks)
            .map(|k| {
                vec![
                    FixedCosine {
                        frequency: [2, -2 * (k as i32 % 2)],
                        amplitude: 0.1,
                        phase: 0.25,
                    },
                    FixedCosine {
                        frequency: [n / 2, 0],
                        amplitude: 0.05,
                        phase: 0.0,
                    },
                ]
            })
            .collect();
        TextureModel {
            seed: 9,
            period,
            channels: vec![TextureChannel {
                seed: 1,
                mean: 0.5,
                strata: vec![],
                structure: Some(Structure { blocks, cosines }),
            }],
            colour: None,
            turbulence: None,
            random_placement: placement,
        }
    }

    pub fn block_weights_are_a_partition_of_unity() {
        // Every block holds the constant 1 (the zero frequency, phase 0): n_R must be 1
        // everywhere, up to f32 rounding of a few additions.
        for blocks in [2u32, 4, 8] {
            let s = Structure {
                blocks,
                cosines: vec![
                    vec![FixedCosine {
                        frequency: [0, 0],
                        amplitude: 1.0,
                        phase: 0.0
                    }];
                    (blocks * blocks) as usize
                ],
            };
            for i in 0..200 {
                let q = [i as f32 * 0.3137 % 32.0, i as f32 * 0.7771 % 32.0];
                let v = s.eval(32, q);
                assert!((v - 1.0).abs() < 1e-6, "blocks {blocks}, q {q:?}: {v}");
            }
        }
    }

    pub fn one_block_is_a_fourier_series_of_the_period() {
        // b = 1, N = 2T: k = (2, 0) is cos 2π(x/T + φ) and k = (N/2, 0) is cos πx.
        let m = structure_model(1, 16, false);
        let s = m.channels[0].structure.as_ref().unwrap();
        for i in 0..64 {
            let x = i as f32 * 0.25;
            let want = 0.1 * (2.0 * std::f64::consts::PI * (f64::from(x) / 16.0 + 0.25)).cos()
                + 0.05 * (std::f64::consts::PI * f64::from(x)).cos();
            let got = s.eval(16, [x, 0.0]);
            assert!(
                (f64::from(got) - want).abs() < 2e-6,
                "x {x}: {got} vs {want}"
            );
        }
    }

    pub fn placement_cross_fade_keeps_unit_energy_and_is_continuous() {
        let m = structure_model(2, 64, true);
        for i in 0..400 {
            let s = i as f32 / 400.0;
            let p = m.placement(3, s, -2, 0.5, [0.0, 0.0]);
            let e: f32 = p.taps[..p.count].iter().map(|t| t.0 * t.0).sum();
            assert!((e - 1.0).abs() < 1e-5, "s {s}: Σω² = {e}");
        }
        // Crossing a cell border gives the same taps from both sides (weights continuous; the
        // neighbour that fades in carries its own shift).
        let before = m.placement(3, 1.0 - 1e-6, 0, 0.5, [0.0, 0.0]);
        let after = m.placement(4, 0.0, 0, 0.5, [0.0, 0.0]);
        let v0 = m.structure_at(0, &before);
        let v1 = m.structure_at(0, &after);
        assert!((v0 - v1).abs() < 1e-3, "{v0} vs {v1}");
        // Deep inside a cell only that cell counts, with weight 1.
        let inside = m.placement(3, 0.5, 7, 0.5, [0.0, 0.0]);
        assert_eq!(inside.count, 1);
        assert_eq!(inside.taps[0].0, 1.0);
    }

    pub fn without_placement_the_structure_is_periodic() {
        let m = structure_model(4, 32, false);
        let p0 = m.placement(0, 0.3, 0, 0.7, [1.5, -2.0]);
        let p1 = m.placement(6, 0.3, -4, 0.7, [1.5, -2.0]);
        assert_eq!(m.structure_at(0, &p0), m.structure_at(0, &p1));
    }

    pub fn validation_names_the_field_and_range() {
        let mut m = structure_model(2, 32, false);
        m.validate().unwrap();
        m.period = 48;
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("texture.period")
        );
        let mut m = structure_model(2, 32, false);
        m.channels[0].structure.as_mut().unwrap().cosines[1][0].frequency = [17, 0];
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("cosines[1][0].frequency[0]"), "{e}");
        let mut m = structure_model(2, 32, false);
        m.channels[0].structure.as_mut().unwrap().cosines[0][0].amplitude = f32::NAN;
        assert!(m.validate().unwrap_err().to_string().contains("amplitude"));
        let mut m = structure_model(2, 32, false);
        m.channels.push(m.channels[0].clone());
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("texture.channels")
        );
    }
}
