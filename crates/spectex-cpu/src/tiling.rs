//! Tiling and blending by example on the CPU; the definition, the lattice, the tables and the
//! randomness contract are in [`spectex_model::tiling`].
//!
//! A pixel is the model's f32 formula step by step (no fused products), so any window, band of
//! rows and thread gives the same bits. The fast path ([`TilingEvaluator`]'s `eval_rows`) draws
//! the vertices of a row's two lattice rows once per row instead of three times per pixel; the
//! reference path draws them per pixel. A texel is four f32 lanes (the channels, then zeros),
//! so the bilinear taps are the same operations on every lane.

use spectex_model::grid::locate_cell;
use spectex_model::math::cos_turns;
use spectex_model::random::{Prng, cell_hash, unit_f32};
use spectex_model::tiling::{
    Blend, LUT_ENTRIES, LUT_RANGE, Lattice, TILING_LAYER, TilingTables, TilingTexture, mip_level,
};
use spectex_model::{Period, Window};

use crate::{CpuError, CpuKind, RowKernel};

/// A vertex's draws: its offset in texels and, with the hex option, its rotation `(cos, sin)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Vertex {
    offset: [f32; 2],
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

/// A tiling-and-blending texture prepared for evaluation.
#[derive(Debug, Clone)]
pub struct TilingEvaluator {
    seed: u32,
    channels: usize,
    blend: Blend,
    lattice: Lattice,
    side: f32,
    row: f32,
    lo: u32,
    spans: [u32; 2],
    tables: TilingTables,
    levels: Vec<TapLevel>,
    mean: [f32; 3],
    basis: [[f32; 3]; 3],
}

/// The rhombus of a position: `(m₀, k₀, u, v)` (module docs of `spectex_model::tiling`).
#[inline(always)]
fn rhombus(cx: i32, fx: f32, cy: i32, fy: f32) -> (i32, i32, f32, f32) {
    let e = cy.rem_euclid(2);
    let t = fx - 0.5 * (e as f32 + fy);
    // ⌊t⌋ for t in (−1, 1] without a libm call.
    let ft = if t < 0.0 {
        -1.0
    } else if t >= 1.0 {
        1.0
    } else {
        0.0
    };
    let m0 = cx
        .wrapping_sub(cy.wrapping_sub(e) / 2)
        .wrapping_add(ft as i32);
    (m0, cy, t - ft, fy)
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
        let mut mean = [0.0f32; 3];
        let mut basis = [[0.0f32; 3]; 3];
        for i in 0..nc {
            mean[i] = model.mean[i];
            for c in 0..nc {
                basis[i][c] = model.basis[i * nc + c];
            }
        }
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
            lattice,
            side: lattice.side as f32,
            row: lattice.row as f32,
            lo,
            spans,
            tables,
            levels,
            mean,
            basis,
        })
    }

    /// The draws of vertex `(m, k)` (the randomness contract).
    #[inline]
    fn vertex(&self, m: i32, k: i32) -> Vertex {
        let (m, k) = self.lattice.key(m, k);
        let mut prng = Prng::new(cell_hash(m, k, TILING_LAYER, self.seed));
        let ox = self.lo + prng.next_u32() % (self.spans[0] + 1);
        let oy = self.lo + prng.next_u32() % (self.spans[1] + 1);
        let rotation = match self.blend {
            Blend::Hex { rotation, .. } if rotation > 0.0 => {
                let theta = rotation * (2.0 * unit_f32(prng.next_u32()) - 1.0);
                [cos_turns(theta), cos_turns(theta - 0.25)]
            }
            _ => [1.0, 0.0],
        };
        Vertex {
            offset: [ox as f32, oy as f32],
            rotation,
        }
    }

    /// The bilinear tap of level `level` at `q` texels of level 0 (`⌊x⌋` of the clamped,
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

    /// The texture at level `level` in the rhombus `(m0, k0)` at `(u, v)`, the vertices' draws
    /// from `draw` (output components in `out[..channels]`).
    #[inline(always)]
    fn eval_level(
        &self,
        level: usize,
        (m0, k0, u, v): (i32, i32, f32, f32),
        draw: &impl Fn(i32, i32) -> Vertex,
    ) -> [f32; 3] {
        let (corners, w) = triangle(u, v);
        let tap_level = &self.levels[level];
        let mut taps = [[0.0f32; 4]; 3];
        for (tap, &(a, b)) in taps.iter_mut().zip(&corners) {
            let vertex = draw(m0.wrapping_add(a), k0.wrapping_add(b));
            let (da, db) = (u - a as f32, v - b as f32);
            let dx = (da + 0.5 * db) * self.side;
            let dy = db * self.row;
            let [c, s] = vertex.rotation;
            let (rx, ry) = if matches!(self.blend, Blend::Hex { rotation, .. } if rotation > 0.0) {
                (c * dx - s * dy, s * dx + c * dy)
            } else {
                (dx, dy)
            };
            *tap = self.tap(tap_level, [vertex.offset[0] + rx, vertex.offset[1] + ry]);
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

    /// One pixel from its split position, the window's level and mixing weight.
    fn pixel(
        &self,
        x: Option<(i32, f32)>,
        y: Option<(i32, f32)>,
        (level, mix): (usize, f32),
        draw: &impl Fn(i32, i32) -> Vertex,
        out: &mut [f32],
    ) {
        let (Some((cx, fx)), Some((cy, fy))) = (x, y) else {
            out.copy_from_slice(&self.mean[..self.channels]);
            return;
        };
        let r = rhombus(cx, fx, cy, fy);
        let v0 = self.eval_level(level, r, draw);
        if mix > 0.0 {
            let v1 = self.eval_level(level + 1, r, draw);
            for (o, (a, b)) in out.iter_mut().zip(v0.iter().zip(&v1)) {
                *o = a + mix * (b - a);
            }
        } else {
            out.copy_from_slice(&v0[..self.channels]);
        }
    }

    /// The window's columns split on the lattice's side.
    fn columns(&self, window: &Window) -> Vec<Option<(i32, f32)>> {
        (0..window.width)
            .map(|i| locate_cell(window.x(i), self.lattice.side))
            .collect()
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
        let columns = self.columns(window);
        let cells = columns.iter().flatten().map(|c| c.0);
        let (Some(lo), Some(hi)) = (cells.clone().min(), cells.max()) else {
            return self.eval_rows_reference(window, first, out);
        };
        // The vertices of a row lie in lattice rows k₀ and k₀ + 1, at m within
        // `[lo − half − 1, hi − half + 2]`: drawn once per row unless the row spans far more
        // vertices than pixels (a minified window), where each pixel draws its own.
        let span = i64::from(hi) - i64::from(lo) + 4;
        if span > 4 * width as i64 + 16 {
            return self.eval_rows_reference(window, first, out);
        }
        let mut cache: Vec<Vertex> = Vec::with_capacity(2 * span as usize);
        for (r, line) in out.chunks_exact_mut(width * nc).enumerate() {
            let y = locate_cell(window.y(first + r), self.lattice.row);
            let Some((cy, _)) = y else {
                for px in line.chunks_exact_mut(nc) {
                    px.copy_from_slice(&self.mean[..nc]);
                }
                continue;
            };
            let half = cy.wrapping_sub(cy.rem_euclid(2)) / 2;
            let m_lo = lo.wrapping_sub(half).wrapping_sub(1);
            cache.clear();
            for k in [cy, cy.wrapping_add(1)] {
                for i in 0..span as i32 {
                    cache.push(self.vertex(m_lo.wrapping_add(i), k));
                }
            }
            let draw = |m: i32, k: i32| {
                let i = m.wrapping_sub(m_lo) as usize + if k == cy { 0 } else { span as usize };
                cache[i]
            };
            for (px, x) in line.chunks_exact_mut(nc).zip(&columns) {
                self.pixel(*x, y, level, &draw, px);
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
        let columns = self.columns(window);
        let draw = |m: i32, k: i32| self.vertex(m, k);
        for (r, line) in out.chunks_exact_mut(width * nc).enumerate() {
            let y = locate_cell(window.y(first + r), self.lattice.row);
            for (px, x) in line.chunks_exact_mut(nc).zip(&columns) {
                self.pixel(*x, y, level, &draw, px);
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
    /// displacement is `p − Vᵢ` for the vertex's exact position, within the reach, and the
    /// weights are barycentric (`Σ wᵢ·(p − Vᵢ) = 0`), at the origin and at 10⁷.
    pub fn barycentric_weights_reproduce_the_position() {
        let side = 7.0f64;
        let row = side * 3f64.sqrt() / 2.0;
        for &(x, y) in &[
            (0.3, 0.2),
            (5.9, 6.0),
            (-3.2, 11.7),
            (1.0e7 + 0.37, 1.0e7 - 2.9),
        ] {
            let (cx, fx) = locate_cell(x, side).unwrap();
            let (cy, fy) = locate_cell(y, row).unwrap();
            let (m0, k0, u, v) = rhombus(cx, fx, cy, fy);
            let (corners, w) = triangle(u, v);
            assert!(
                w.iter().all(|&w| (-1e-6..=1.0 + 1e-6).contains(&w)),
                "{w:?}"
            );
            assert!((f64::from(w.iter().sum::<f32>()) - 1.0).abs() < 1e-6);
            let (mut sx, mut sy) = (0.0, 0.0);
            for (&(a, b), &w) in corners.iter().zip(&w) {
                let (m, k) = (f64::from(m0 + a), f64::from(k0 + b));
                let exact = (x - (m + k / 2.0) * side, y - k * row);
                let (da, db) = (u - a as f32, v - b as f32);
                let d = ((da + 0.5 * db) * side as f32, db * row as f32);
                let tol = 1e-5 * side;
                assert!(
                    (f64::from(d.0) - exact.0).abs() < tol
                        && (f64::from(d.1) - exact.1).abs() < tol,
                    "({x}, {y}): {d:?} against {exact:?}"
                );
                assert!(exact.0.hypot(exact.1) <= side * (1.0 + 1e-9));
                sx += f64::from(w) * exact.0;
                sy += f64::from(w) * exact.1;
            }
            assert!(
                sx.abs() < 1e-5 * side && sy.abs() < 1e-5 * side,
                "({sx}, {sy})"
            );
        }
    }
}
