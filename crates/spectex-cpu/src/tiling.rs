//! Tiling and blending by example on the CPU; the definition, the lattice, the tables and the
//! randomness contract are in [`spectex_model::tiling`].
//!
//! A pixel is the model's integer and f32 formula step by step (no fused products), so any
//! window, band of rows, thread and SIMD level gives the same bits. The fast path
//! ([`TilingEvaluator`]'s `eval_rows`) draws the vertices of a row's two lattice rows once per
//! row instead of three times per pixel, divides each column by the lattice's side once per
//! band, and reads a tap's texel alone where the pixel's fraction is zero (the bilinear weights
//! are then exactly 0: the same bits). For the variance blend at scale 1 it works a row at a
//! time: runs of pixels in one triangle copy their taps from the exemplar's channel planes,
//! then the blend, the tables and the basis run across the row in SIMD lanes (AVX2 or AVX-512
//! where the CPU has them). The reference path does each step per pixel. A texel is four f32
//! lanes (the channels, then zeros), so the bilinear taps are the same operations on every
//! lane.

use spectex_model::grid::locate_cell;
use spectex_model::math::cos_turns;
use spectex_model::random::{Prng, cell_hash, unit_f32};
use spectex_model::tiling::{
    Blend, LUT_ENTRIES, LUT_RANGE, Lattice, TILING_BLOCK_LAYER, TILING_LAYER, TilingTables,
    TilingTexture, mip_level,
};
use spectex_model::{Period, Window};

use crate::lrp::Simd;
use crate::{CpuError, CpuKind, RowKernel};

/// Largest `|X|`, `|Y|` (pixels) a position may have: the integer split stays within `i32`.
const MAX_PIXEL: i32 = 1 << 30;

/// A vertex's draws: its offset in whole texels and, with the hex option, its rotation
/// `(cos, sin)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Vertex {
    offset: [i32; 2],
    rotation: [f32; 2],
}

/// A mip level as a tap reads it: `2⁻ˡ`, `(1 − 2⁻ˡ)/2`, its first texel and sides.
#[derive(Debug, Clone, Copy)]
struct TapLevel {
    inv: f32,
    bias: f32,
    offset: usize,
    width: u32,
    height: u32,
}

/// A pixel on the lattice: its rhombus, `(u, v)`, the whole pixels `(dx, dy)` from vertex
/// `(m₀, k₀)` and the fractions `φ`.
#[derive(Debug, Clone, Copy)]
struct Spot {
    m0: i32,
    k0: i32,
    u: f32,
    v: f32,
    dx: i32,
    dy: i32,
    phi: [f32; 2],
}

/// A row on the lattice: `cy`, `ry`, `v`, `φy`, and `cy·h` split as `q·side + r`.
#[derive(Debug, Clone, Copy)]
struct RowSpot {
    cy: i32,
    ry: i32,
    v: f32,
    phi: f32,
    shift_q: i32,
    shift_r: i32,
}

/// A column: `X = q·side + r` and `φx`.
#[derive(Debug, Clone, Copy)]
struct ColumnSpot {
    q: i32,
    r: i32,
    phi: f32,
}

/// A tiling-and-blending texture prepared for evaluation.
#[derive(Debug, Clone)]
pub struct TilingEvaluator {
    seed: u32,
    channels: usize,
    blend: Blend,
    rotates: bool,
    lattice: Lattice,
    side: i32,
    row: i32,
    inv_side: f32,
    inv_row: f32,
    lo: i32,
    spans: [u32; 2],
    tables: TilingTables,
    /// Level 0's texels channel by channel (`width·height` values each), for runs of taps.
    planes: Vec<f32>,
    /// Level 0's tables as arrays (channel 0's in the unused places of a grey model), so the
    /// lanes index them without bounds checks.
    luts0: Box<[[f32; LUT_ENTRIES]; 3]>,
    levels: Vec<TapLevel>,
    mean: [f32; 3],
    basis: [[f32; 3]; 3],
    simd: Simd,
}

/// A position on the pixel grid, `None` outside the usable range.
fn pixel(coord: f64) -> Option<(i32, f32)> {
    locate_cell(coord, 1.0).filter(|(c, _)| c.unsigned_abs() < MAX_PIXEL as u32)
}

/// The three vertices `(a, b)` relative to the rhombus and their barycentric weights.
#[inline(always)]
fn triangle(u: f32, v: f32) -> ([(i32, i32); 3], [f32; 3]) {
    if u + v < 1.0 {
        ([(0, 0), (1, 0), (0, 1)], [(1.0 - u) - v, u, v])
    } else {
        ([(1, 1), (0, 1), (1, 0)], [(u + v) - 1.0, 1.0 - u, 1.0 - v])
    }
}

impl TilingEvaluator {
    /// Prepares a validated model, its lattice fitted to `period` when given (`None` if the
    /// model refuses that period or is invalid).
    #[must_use]
    pub fn new(model: &TilingTexture, period: Option<Period>) -> Option<Self> {
        let lattice = model.lattice(period)?;
        let (lo, spans) = lattice.spans(model.width, model.height)?;
        let nc = model.channels as usize;
        let (mean, basis) = model.colour();
        let tables = model.tables();
        let levels = tables
            .levels
            .iter()
            .enumerate()
            .map(|(l, lv)| {
                let inv = 1.0 / (1u32 << l) as f32;
                TapLevel {
                    inv,
                    bias: 0.5 * (1.0 - inv),
                    offset: lv.offset as usize,
                    width: lv.width,
                    height: lv.height,
                }
            })
            .collect();
        Some(Self {
            seed: model.seed,
            channels: nc,
            blend: model.blend,
            rotates: matches!(model.blend, Blend::Hex { rotation, .. } if rotation > 0.0),
            lattice,
            side: lattice.side as i32,
            row: lattice.row as i32,
            inv_side: (1.0 / lattice.side) as f32,
            inv_row: (1.0 / lattice.row) as f32,
            lo: lo as i32,
            spans,
            planes: (0..nc)
                .flat_map(|c| {
                    let n = (model.width * model.height) as usize;
                    tables.texels[..n].iter().map(move |t| t[c])
                })
                .collect(),
            luts0: Box::new(std::array::from_fn(|c| {
                let lut = tables.lut(0, c.min(nc - 1), nc);
                std::array::from_fn(|k| lut[k])
            })),
            tables,
            levels,
            mean,
            basis,
            simd: Simd::detect(),
        })
    }

    /// Forces the portable path (`false`) or AVX2 when the CPU has it (`true`); for tests
    /// comparing the code paths.
    #[doc(hidden)]
    pub fn set_avx2(&mut self, enabled: bool) {
        self.simd = Simd::up_to_avx2(enabled);
    }

    /// Uses AVX-512 when the CPU has it (`true`, the default), else the level below; for tests
    /// comparing the code paths. Returns whether AVX-512 is in use.
    #[doc(hidden)]
    pub fn set_avx512(&mut self, enabled: bool) -> bool {
        self.simd = Simd::with_avx512(enabled);
        self.simd == Simd::Avx512
    }

    /// The draws of vertex `(m, k)` (the randomness contract).
    #[inline]
    fn vertex(&self, m: i32, k: i32) -> Vertex {
        let (m, k) = self.lattice.key(m, k);
        let (bm, bk) = (m.div_euclid(4), k.div_euclid(4));
        let j = ((m - 4 * bm) + 4 * (k - 4 * bk)) as u32;
        let mut block = Prng::new(cell_hash(bm, bk, TILING_BLOCK_LAYER, self.seed));
        let a = 2 * (block.next_u32() % 8) + 1;
        let b = block.next_u32() % 16;
        let stratum = (a * j + b) % 16;
        let mut prng = Prng::new(cell_hash(m, k, TILING_LAYER, self.seed));
        let (nx, ny) = (self.spans[0] + 1, self.spans[1] + 1);
        let ox = self.lo as u32 + ((stratum % 4) * nx + prng.next_u32() % nx) / 4;
        let oy = self.lo as u32 + ((stratum / 4) * ny + prng.next_u32() % ny) / 4;
        let rotation = match self.blend {
            Blend::Hex { rotation, .. } if rotation > 0.0 => {
                let theta = rotation * (2.0 * unit_f32(prng.next_u32()) - 1.0);
                [cos_turns(theta), cos_turns(theta - 0.25)]
            }
            _ => [1.0, 0.0],
        };
        Vertex {
            offset: [ox as i32, oy as i32],
            rotation,
        }
    }

    /// The row's split (`y` on the pixel grid).
    fn row_spot(&self, (y, phi): (i32, f32)) -> RowSpot {
        let cy = y.div_euclid(self.row);
        let ry = y - cy * self.row;
        let shift = cy * (self.side / 2);
        RowSpot {
            cy,
            ry,
            v: (ry as f32 + phi) * self.inv_row,
            phi,
            shift_q: shift.div_euclid(self.side),
            shift_r: shift.rem_euclid(self.side),
        }
    }

    /// The column's split (`x` on the pixel grid).
    fn column_spot(&self, (x, phi): (i32, f32)) -> ColumnSpot {
        ColumnSpot {
            q: x.div_euclid(self.side),
            r: x.rem_euclid(self.side),
            phi,
        }
    }

    /// The pixel at column `c` of row `r`: `a = X − cy·h = (q_X − q_h)·side + (r_X − r_h)`.
    #[inline(always)]
    fn spot(&self, c: &ColumnSpot, r: &RowSpot) -> Spot {
        let (mut cx, mut rx) = (c.q - r.shift_q, c.r - r.shift_r);
        if rx < 0 {
            rx += self.side;
            cx -= 1;
        }
        let t = (rx as f32 + c.phi) * self.inv_side - 0.5 * r.v;
        let ft: i32 = if t < 0.0 {
            -1
        } else if t >= 1.0 {
            1
        } else {
            0
        };
        Spot {
            m0: cx.wrapping_add(ft),
            k0: r.cy,
            u: t - ft as f32,
            v: r.v,
            dx: rx - ft * self.side,
            dy: r.ry,
            phi: [c.phi, r.phi],
        }
    }

    /// The texel at whole texels `(x, y)` of level 0 and its right and lower neighbours
    /// weighed by `φ` (bilinear; `φ = 0` reads the texel alone: the same bits).
    #[inline(always)]
    fn tap_texel(&self, x: i32, y: i32, phi: [f32; 2]) -> [f32; 4] {
        let level = &self.levels[0];
        let w = level.width as usize;
        let t = &self.tables.texels;
        let (x, y) = (x as usize, y as usize);
        let t00 = t[y * w + x];
        if phi == [0.0, 0.0] {
            return t00;
        }
        let x1 = (x + 1).min(w - 1);
        let y1 = (y + 1).min(level.height as usize - 1);
        let (t10, t01, t11) = (t[y * w + x1], t[y1 * w + x], t[y1 * w + x1]);
        let mut out = [0.0f32; 4];
        for c in 0..4 {
            let top = t00[c] + phi[0] * (t10[c] - t00[c]);
            let bottom = t01[c] + phi[0] * (t11[c] - t01[c]);
            out[c] = top + phi[1] * (bottom - top);
        }
        out
    }

    /// The bilinear tap of `level` at `q` texels of level 0 (`⌊x⌋` of the clamped,
    /// non-negative coordinates as a truncation: the same value without a libm call).
    #[inline(always)]
    fn tap(&self, level: &TapLevel, q: [f32; 2]) -> [f32; 4] {
        let axis = |q: f32, n: u32| {
            let x = (q * level.inv - level.bias).clamp(0.0, (n - 1) as f32);
            let i = (x as u32).min(n - 2);
            (i as usize, x - i as f32)
        };
        let (ix, fx) = axis(q[0], level.width);
        let (iy, fy) = axis(q[1], level.height);
        let w = level.width as usize;
        let at = level.offset + iy * w + ix;
        let t = &self.tables.texels[at..at + w + 2];
        let (t00, t10, t01, t11) = (t[0], t[1], t[w], t[w + 1]);
        let mut out = [0.0f32; 4];
        for c in 0..4 {
            let top = t00[c] + fx * (t10[c] - t00[c]);
            let bottom = t01[c] + fx * (t11[c] - t01[c]);
            out[c] = top + fy * (bottom - top);
        }
        out
    }

    /// `LUT_l` of channel `c` at `g`.
    #[inline(always)]
    fn lookup(&self, level: usize, c: usize, g: f32) -> f32 {
        let lut = self.tables.lut(level, c, self.channels);
        let scale = (LUT_ENTRIES - 1) as f32 / (2.0 * LUT_RANGE);
        let x = (g.clamp(-LUT_RANGE, LUT_RANGE) + LUT_RANGE) * scale;
        // x ≥ 0: the truncation is ⌊x⌋.
        let i = (x as usize).min(LUT_ENTRIES - 2);
        let f = x - i as f32;
        lut[i] + f * (lut[i + 1] - lut[i])
    }

    /// The texture at `level` at the pixel `spot`, the vertices' draws from `draw`.
    #[inline(always)]
    fn eval_level(
        &self,
        level: usize,
        spot: &Spot,
        draw: &impl Fn(i32, i32) -> Vertex,
    ) -> [f32; 3] {
        let (corners, w) = triangle(spot.u, spot.v);
        let half = self.side / 2;
        let mut taps = [[0.0f32; 4]; 3];
        for (tap, &(a, b)) in taps.iter_mut().zip(&corners) {
            let vertex = draw(spot.m0.wrapping_add(a), spot.k0.wrapping_add(b));
            let dx = spot.dx - a * self.side - b * half;
            let dy = spot.dy - b * self.row;
            let [ox, oy] = vertex.offset;
            *tap = if self.rotates {
                let (fx, fy) = (dx as f32 + spot.phi[0], dy as f32 + spot.phi[1]);
                let [c, s] = vertex.rotation;
                let q = [ox as f32 + (c * fx - s * fy), oy as f32 + (s * fx + c * fy)];
                self.tap(&self.levels[level], q)
            } else if level == 0 {
                self.tap_texel(ox + dx, oy + dy, spot.phi)
            } else {
                let q = [
                    (ox + dx) as f32 + spot.phi[0],
                    (oy + dy) as f32 + spot.phi[1],
                ];
                self.tap(&self.levels[level], q)
            };
        }
        let nc = self.channels;
        let mut t = [0.0f32; 3];
        match self.blend {
            Blend::Variance => {
                let norm = ((w[0] * w[0] + w[1] * w[1]) + w[2] * w[2]).sqrt();
                for (c, tc) in t.iter_mut().enumerate().take(nc) {
                    let g = (w[0] * taps[0][c] + w[1] * taps[1][c]) + w[2] * taps[2][c];
                    *tc = self.lookup(level, c, g / norm);
                }
            }
            Blend::Hex { sharpness, .. } => {
                let mut p = w;
                for _ in 1..sharpness {
                    for (p, w) in p.iter_mut().zip(&w) {
                        *p *= *w;
                    }
                }
                let sum = (p[0] + p[1]) + p[2];
                for (c, tc) in t.iter_mut().enumerate().take(nc) {
                    let l = [0, 1, 2].map(|i| self.lookup(level, c, taps[i][c]));
                    *tc = ((p[0] * l[0] + p[1] * l[1]) + p[2] * l[2]) / sum;
                }
            }
        }
        let mut out = [0.0f32; 3];
        for (i, o) in out.iter_mut().enumerate().take(nc) {
            let mut acc = self.mean[i];
            for (c, tc) in t.iter().enumerate().take(nc) {
                acc += self.basis[i][c] * tc;
            }
            *o = acc;
        }
        out
    }

    /// A row of the variance blend at level 0 without rotation, on the SIMD level chosen
    /// (every level the same operations in the order of [`Self::eval_level`]: the same bits).
    fn variance_row(
        &self,
        cols: &Columns,
        row: &RowSpot,
        draw: &impl Fn(i32, i32) -> Vertex,
        lanes: &mut RowLanes,
        out: &mut [f32],
    ) {
        match (self.simd, self.channels) {
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
            (Simd::Avx512, 3) => unsafe {
                variance_row_avx512::<3>(self, cols, row, draw, lanes, out)
            },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: as above.
            (Simd::Avx512, _) => unsafe {
                variance_row_avx512::<1>(self, cols, row, draw, lanes, out)
            },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
            (Simd::Avx2, 3) => unsafe { variance_row_avx2::<3>(self, cols, row, draw, lanes, out) },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            // SAFETY: as above.
            (Simd::Avx2, _) => unsafe { variance_row_avx2::<1>(self, cols, row, draw, lanes, out) },
            (_, 3) => self.variance_lanes::<3>(cols, row, draw, lanes, out),
            _ => self.variance_lanes::<1>(cols, row, draw, lanes, out),
        }
    }

    /// [`Self::variance_row`]'s work in three passes over the row: the pixels' spots and
    /// weights (lanes), their taps, then the blend, the tables and the basis (lanes).
    /// `inline(always)` so that each SIMD wrapper compiles its own copy.
    #[inline(always)]
    fn variance_lanes<const NC: usize>(
        &self,
        cols: &Columns,
        row: &RowSpot,
        draw: &impl Fn(i32, i32) -> Vertex,
        lanes: &mut RowLanes,
        out: &mut [f32],
    ) {
        let n = cols.q.len();
        let RowLanes { u, w, m0, dx, g } = lanes;
        let (u, m0, dx) = (&mut u[..n], &mut m0[..n], &mut dx[..n]);
        let [w0, w1, w2] = w;
        let (w0, w1, w2) = (&mut w0[..n], &mut w1[..n], &mut w2[..n]);
        let (q, r, phi) = (&cols.q[..n], &cols.r[..n], &cols.phi[..n]);
        for i in 0..n {
            let spot = self.spot(
                &ColumnSpot {
                    q: q[i],
                    r: r[i],
                    phi: phi[i],
                },
                row,
            );
            let (_, wt) = triangle(spot.u, spot.v);
            (u[i], m0[i], dx[i]) = (spot.u, spot.m0, spot.dx);
            (w0[i], w1[i], w2[i]) = (wt[0], wt[1], wt[2]);
        }
        self.variance_taps::<NC>(cols, row, draw, u, m0, dx, g);
        blend_row::<NC>(
            &BlendRow {
                luts: &self.luts0,
                mean: self.mean,
                basis: self.basis,
                w: [w0, w1, w2],
                g,
            },
            out,
        );
    }

    /// The row's taps into `g`: per channel the three taps, `n` values each. Pixels in one
    /// triangle whose columns are consecutive whole pixels (`φ = 0`: a render at scale 1 on
    /// the pixel grid) read consecutive texels of the same three rows of the exemplar: such a
    /// run's taps are copied from the channels' planes at once. In any other row each pixel
    /// reads its taps alone ([`Self::tap_texel`]). Either way the values are the texels' bits
    /// or the same bilinear operations.
    #[inline(always)]
    #[allow(
        clippy::too_many_arguments,
        reason = "the row's lanes, split for the passes"
    )]
    fn variance_taps<const NC: usize>(
        &self,
        cols: &Columns,
        row: &RowSpot,
        draw: &impl Fn(i32, i32) -> Vertex,
        u: &[f32],
        m0: &[i32],
        dx: &[i32],
        g: &mut [f32],
    ) {
        let n = u.len();
        let half = self.side / 2;
        let corners = |i: usize| triangle(u[i], row.v).0;
        if !(cols.whole && row.phi == 0.0) {
            for i in 0..n {
                for (k, &(a, b)) in corners(i).iter().enumerate() {
                    let vertex = draw(m0[i].wrapping_add(a), row.cy.wrapping_add(b));
                    let [ox, oy] = vertex.offset;
                    let x = ox + dx[i] - a * self.side - b * half;
                    let y = oy + row.ry - b * self.row;
                    let tap = self.tap_texel(x, y, [cols.phi[i], row.phi]);
                    for (ch, v) in tap.iter().enumerate().take(NC) {
                        g[(3 * ch + k) * n + i] = *v;
                    }
                }
            }
            return;
        }
        let plane = self.levels[0].width as usize * self.levels[0].height as usize;
        let stride = self.levels[0].width as i32;
        let mut i = 0;
        while i < n {
            // A run: the pixels after `i` in its triangle at the next texels.
            let upper = u[i] + row.v >= 1.0;
            let mut end = i + 1;
            while end < n
                && m0[end] == m0[i]
                && (u[end] + row.v >= 1.0) == upper
                && dx[end] == dx[i] + (end - i) as i32
            {
                end += 1;
            }
            for (k, &(a, b)) in corners(i).iter().enumerate() {
                let [ox, oy] = draw(m0[i].wrapping_add(a), row.cy.wrapping_add(b)).offset;
                let at =
                    (oy + row.ry - b * self.row) * stride + ox + dx[i] - a * self.side - b * half;
                let at = at as usize;
                for ch in 0..NC {
                    g[(3 * ch + k) * n + i..][..end - i]
                        .copy_from_slice(&self.planes[ch * plane + at..][..end - i]);
                }
            }
            i = end;
        }
    }

    /// One pixel from its spot (`None`: outside the usable range), the window's level and
    /// mixing weight.
    #[inline(always)]
    fn pixel(
        &self,
        spot: Option<Spot>,
        (level, mix): (usize, f32),
        draw: &impl Fn(i32, i32) -> Vertex,
        out: &mut [f32],
    ) {
        let Some(spot) = spot else {
            out.copy_from_slice(&self.mean[..self.channels]);
            return;
        };
        let v0 = self.eval_level(level, &spot, draw);
        if mix > 0.0 {
            let v1 = self.eval_level(level + 1, &spot, draw);
            for (o, (a, b)) in out.iter_mut().zip(v0.iter().zip(&v1)) {
                *o = a + mix * (b - a);
            }
        } else {
            out.copy_from_slice(&v0[..self.channels]);
        }
    }
}

/// A band's columns for the row lanes: [`ColumnSpot`]'s fields, one array each, and whether
/// every `φx` is 0.
struct Columns {
    q: Vec<i32>,
    r: Vec<i32>,
    phi: Vec<f32>,
    whole: bool,
}

/// A row's lanes: the pixels' `u`, weights, `m₀` and `dx`, and per channel the three taps
/// (`3·channels` arrays, one after the other).
struct RowLanes {
    u: Vec<f32>,
    w: [Vec<f32>; 3],
    m0: Vec<i32>,
    dx: Vec<i32>,
    g: Vec<f32>,
}

impl RowLanes {
    fn new(n: usize, channels: usize) -> Self {
        Self {
            u: vec![0.0; n],
            w: std::array::from_fn(|_| vec![0.0; n]),
            m0: vec![0; n],
            dx: vec![0; n],
            g: vec![0.0; 3 * channels * n],
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn variance_row_avx2<const NC: usize>(
    e: &TilingEvaluator,
    cols: &Columns,
    row: &RowSpot,
    draw: &impl Fn(i32, i32) -> Vertex,
    lanes: &mut RowLanes,
    out: &mut [f32],
) {
    e.variance_lanes::<NC>(cols, row, draw, lanes, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn variance_row_avx512<const NC: usize>(
    e: &TilingEvaluator,
    cols: &Columns,
    row: &RowSpot,
    draw: &impl Fn(i32, i32) -> Vertex,
    lanes: &mut RowLanes,
    out: &mut [f32],
) {
    e.variance_lanes::<NC>(cols, row, draw, lanes, out);
}

/// What [`blend_row`] reads: level 0's tables, the colour basis, and a row's weights and taps.
struct BlendRow<'a> {
    luts: &'a [[f32; LUT_ENTRIES]; 3],
    mean: [f32; 3],
    basis: [[f32; 3]; 3],
    w: [&'a [f32]; 3],
    g: &'a [f32],
}

/// The variance blend of `NC` channels over a row: `Σ wₖ·gₖ / ‖w‖`, the table, then the basis,
/// each pixel by the operations of [`TilingEvaluator::eval_level`] in its order (plain `*`,
/// `+`, `/`, `sqrt`, min/max and truncation: no contraction, the same bits in any lane).
/// A table index is `min(⌊x⌋, N − 2)` with `0 ≤ x`, so masking it by `N − 1` (a power of two)
/// changes nothing and lets the compiler drop the bounds checks from the gathers.
#[inline(always)]
fn blend_row<const NC: usize>(row: &BlendRow<'_>, out: &mut [f32]) {
    const MASK: usize = LUT_ENTRIES - 1;
    let n = out.len() / NC;
    let [w0, w1, w2] = row.w.map(|w| &w[..n]);
    let g: [[&[f32]; 3]; NC] =
        std::array::from_fn(|c| std::array::from_fn(|k| &row.g[(3 * c + k) * n..][..n]));
    let table_scale = (LUT_ENTRIES - 1) as f32 / (2.0 * LUT_RANGE);
    let out = &mut out[..n * NC];
    for (i, px) in out.chunks_exact_mut(NC).enumerate() {
        let scale = ((w0[i] * w0[i] + w1[i] * w1[i]) + w2[i] * w2[i]).sqrt();
        let mut t = [0.0f32; NC];
        for (c, tc) in t.iter_mut().enumerate() {
            let blended = ((w0[i] * g[c][0][i] + w1[i] * g[c][1][i]) + w2[i] * g[c][2][i]) / scale;
            // `clamp` by `max` then `min`, which also turn a NaN (impossible: the taps of a
            // valid model are finite) into −R: the same values, and 0 ≤ x ≤ N − 1 always.
            #[allow(clippy::manual_clamp, reason = "clamp keeps a NaN; max and min do not")]
            let x = (blended.max(-LUT_RANGE).min(LUT_RANGE) + LUT_RANGE) * table_scale;
            // SAFETY: 0 ≤ x ≤ N − 1 (above), so x is finite and within i32; the plain truncation
            // is ⌊x⌋ without the saturating cast's checks.
            #[allow(unsafe_code)]
            let j = unsafe { x.to_int_unchecked::<i32>() }.min(LUT_ENTRIES as i32 - 2);
            let f = x - j as f32;
            let lut = &row.luts[c];
            let (a, b) = (lut[j as usize & MASK], lut[(j + 1) as usize & MASK]);
            *tc = a + f * (b - a);
        }
        for (o, v) in px.iter_mut().enumerate() {
            let mut acc = row.mean[o];
            for (c, tc) in t.iter().enumerate() {
                acc += row.basis[o][c] * tc;
            }
            *v = acc;
        }
    }
}

impl CpuKind for TilingTexture {
    /// The bench case: `testdata/models/tiling-colour.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("tiling-colour.json")
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        TilingEvaluator::new(self, None)
            .map(|e| Box::new(e) as Box<dyn RowKernel>)
            .ok_or_else(|| refused(self))
    }

    /// The lattice fitted to the period and its vertices keyed modulo it
    /// (`spectex_model::tiling::Lattice::key`); `Evaluator::periodic` reduces the positions.
    fn cpu_kernel_periodic(&self, _z: f64, period: Period) -> Result<Box<dyn RowKernel>, CpuError> {
        spectex_model::ModelKind::check_period(self, period)?;
        TilingEvaluator::new(self, Some(period))
            .map(|e| Box::new(e) as Box<dyn RowKernel>)
            .ok_or_else(|| refused(self))
    }
}

/// The validation error of a model the evaluator cannot prepare.
fn refused(model: &TilingTexture) -> CpuError {
    CpuError::Model(
        model
            .validate()
            .err()
            .unwrap_or(spectex_model::ModelError::OutOfRange {
                field: "tiling.tile".into(),
                value: f64::from(model.tile),
                range: "a tile the exemplar holds",
            }),
    )
}

impl RowKernel for TilingEvaluator {
    fn output_channels(&self) -> usize {
        self.channels
    }

    /// Three taps a pixel (six when a minified window mixes two levels).
    fn cost_per_pixel(&self) -> f64 {
        3.0
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let nc = self.channels;
        let level = mip_level(window.footprint(), self.tables.levels.len());
        let columns: Vec<Option<ColumnSpot>> = (0..width)
            .map(|i| pixel(window.x(i)).map(|c| self.column_spot(c)))
            .collect();
        let xs = columns.iter().flatten().map(|c| c.q);
        let (Some(lo), Some(hi)) = (xs.clone().min(), xs.max()) else {
            return self.eval_rows_reference(window, first, out);
        };
        // A row's vertices lie in lattice rows cy and cy + 1 at m within
        // `[q_lo − q_h − 2, q_hi − q_h + 2]`: drawn once per lattice row unless the row spans far more
        // vertices than pixels (a minified window), where each pixel draws its own.
        let span = i64::from(hi) - i64::from(lo) + 5;
        if span > 4 * width as i64 + 16 {
            return self.eval_rows_reference(window, first, out);
        }
        let mut cache: Vec<Vertex> = Vec::with_capacity(2 * span as usize);
        let mut cached: Option<i32> = None;
        // The common case in lanes: the variance blend at level 0 without rotation, every
        // column within the usable range.
        let lanes = matches!(self.blend, Blend::Variance)
            && !self.rotates
            && level == (0, 0.0)
            && columns.iter().all(Option::is_some);
        let (cols, mut scratch) = if lanes {
            let valid = || columns.iter().flatten();
            let cols = Columns {
                q: valid().map(|c| c.q).collect(),
                r: valid().map(|c| c.r).collect(),
                phi: valid().map(|c| c.phi).collect(),
                whole: valid().all(|c| c.phi == 0.0),
            };
            (Some(cols), Some(RowLanes::new(width, nc)))
        } else {
            (None, None)
        };
        for (r, line) in out.chunks_exact_mut(width * nc).enumerate() {
            let Some(row) = pixel(window.y(first + r)).map(|y| self.row_spot(y)) else {
                for px in line.chunks_exact_mut(nc) {
                    px.copy_from_slice(&self.mean[..nc]);
                }
                continue;
            };
            let m_lo = lo.wrapping_sub(row.shift_q).wrapping_sub(2);
            // Rows of one lattice row (`m_lo` follows from `cy`) share their vertices: drawn
            // when `cy` changes.
            if cached != Some(row.cy) {
                cache.clear();
                for k in [row.cy, row.cy.wrapping_add(1)] {
                    for i in 0..span as i32 {
                        cache.push(self.vertex(m_lo.wrapping_add(i), k));
                    }
                }
                cached = Some(row.cy);
            }
            let cy = row.cy;
            let draw = |m: i32, k: i32| {
                let i = m.wrapping_sub(m_lo) as usize + if k == cy { 0 } else { span as usize };
                cache[i]
            };
            if let (Some(cols), Some(scratch)) = (&cols, &mut scratch) {
                self.variance_row(cols, &row, &draw, scratch, line);
                continue;
            }
            for (px, column) in line.chunks_exact_mut(nc).zip(&columns) {
                let spot = column.as_ref().map(|c| self.spot(c, &row));
                self.pixel(spot, level, &draw, px);
            }
        }
    }

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let nc = self.channels;
        let level = mip_level(window.footprint(), self.tables.levels.len());
        let draw = |m: i32, k: i32| self.vertex(m, k);
        for (r, line) in out.chunks_exact_mut(width * nc).enumerate() {
            let y = pixel(window.y(first + r));
            for (i, px) in line.chunks_exact_mut(nc).enumerate() {
                let spot = match (pixel(window.x(i)), y) {
                    (Some(x), Some(y)) => Some(self.spot(&self.column_spot(x), &self.row_spot(y))),
                    _ => None,
                };
                self.pixel(spot, level, &draw, px);
            }
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// The rhombus, triangle and displacements of a point agree with f64 geometry: each
    /// displacement `D + φ` is `p − Vᵢ` for the vertex's exact position, within the reach, and
    /// the weights are barycentric (`Σ wᵢ·(p − Vᵢ) = 0`), at the origin and at 10⁷.
    pub fn barycentric_weights_reproduce_the_position() {
        let model = TilingTexture {
            seed: 3,
            width: 64,
            height: 64,
            channels: 1,
            tile: 14.0,
            blend: Blend::Variance,
            gaussian: (0..64 * 64).map(|i| (i % 7) as f32 - 3.0).collect(),
            lut: (0..LUT_ENTRIES)
                .map(|k| spectex_model::tiling::lut_node(k) as f32)
                .collect(),
            mean: vec![0.5],
            basis: vec![0.1],
        };
        let e = TilingEvaluator::new(&model, None).unwrap();
        let (side, row) = (f64::from(e.side), f64::from(e.row));
        assert_eq!((side, row), (14.0, 12.0));
        for &(x, y) in &[
            (0.3, 0.2),
            (5.9, 6.0),
            (-3.2, 11.7),
            (-29.0, -13.0),
            (1.0e7 + 0.37, 1.0e7 - 2.9),
        ] {
            let spot = e.spot(
                &e.column_spot(pixel(x).unwrap()),
                &e.row_spot(pixel(y).unwrap()),
            );
            let (corners, w) = triangle(spot.u, spot.v);
            assert!(
                w.iter().all(|&w| (-1e-6..=1.0 + 1e-6).contains(&w)),
                "{w:?}"
            );
            assert!((f64::from(w.iter().sum::<f32>()) - 1.0).abs() < 1e-6);
            let (mut sx, mut sy) = (0.0, 0.0);
            for (&(a, b), &w) in corners.iter().zip(&w) {
                let (m, k) = (f64::from(spot.m0 + a), f64::from(spot.k0 + b));
                let exact = (x - (m + k / 2.0) * side, y - k * row);
                let dx = spot.dx - a * e.side - b * e.side / 2;
                let dy = spot.dy - b * e.row;
                let d = (
                    f64::from(dx) + f64::from(spot.phi[0]),
                    f64::from(dy) + f64::from(spot.phi[1]),
                );
                assert!(
                    (d.0 - exact.0).abs() < 1e-6 && (d.1 - exact.1).abs() < 1e-6,
                    "({x}, {y}): {d:?} against {exact:?}"
                );
                assert!(
                    exact.0.hypot(exact.1)
                        <= side.max((side * side / 4.0 + row * row).sqrt()) + 1e-9
                );
                sx += f64::from(w) * exact.0;
                sy += f64::from(w) * exact.1;
            }
            assert!(
                sx.abs() < 1e-4 * side && sy.abs() < 1e-4 * side,
                "({sx}, {sy})"
            );
        }
    }
}
