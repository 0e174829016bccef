//! Worley (cellular) noise in the lanes: per-row feature points, 3×3 search, exact ring search.

use spectex_model::Window;
use spectex_model::classic::{Metric, WORLEY_MAX_POINTS, WORLEY_MAX_RING};
use spectex_model::random::{cell_hash_in_row, layer_key, lcg_step, permute, row_key, unit_f32};

use super::ClassicEvaluator;
use super::cache::{buffer, recycle};
use super::fractal::{Octave, RowLanes, RowOctave};
use super::lanes::{Fetch, WINDOW, cell_units, fused, locate, locate_lanes, max, min};
use super::lattice::lattice;
use super::relaxed::locate_lanes_f32;
use super::tables::window;

/// `cell_hash(i, j, o, cell_hash(k, 0, o, seed))` from `key0 = row_key(0, layer_key(o, seed))`.
#[inline(always)]
pub(super) fn hash3(i: i32, j: i32, k: i32, o: u32, key0: u32) -> u32 {
    let seed3 = cell_hash_in_row(k, key0);
    cell_hash_in_row(i, row_key(j, layer_key(o, seed3)))
}

/// The Worley parameters in the form the lanes use.
#[derive(Debug, Clone)]
pub(super) struct WorleyParams {
    pub(super) metric: Metric,
    pub(super) coefficients: [f32; 4],
    /// Fixed count, or `None` for a Poisson count.
    pub(super) fixed: Option<u32>,
    pub(super) cdf: [f32; WORLEY_MAX_POINTS as usize],
    /// `n` of the largest needed `F_n`, minus one.
    pub(super) needed: usize,
    /// Largest distance kept (squared for the Euclidean metric).
    pub(super) cap: f32,
}

/// The feature points of one Worley octave with a fixed count along one row, for the lattice
/// columns `lo..` the row's 3×3 (×3) searches visit: entry `(q·keys + p)·len + c` of
/// `offsets[axis]` holds the f32 bits of point `q`'s offset along `axis` in column `lo + c` of
/// row key `p` (`p = 3·(dz + 1) + dy + 1`; 2D: `dy + 1`), drawn from the PRNG seeded with the
/// cell's hash exactly as the lanes draw them, so the lanes read the same floats instead of
/// hashing 9 (27) cells per pixel.
#[derive(Debug, Clone)]
pub(super) struct WorleyColumns {
    /// The first column (one left of the row's first cell).
    pub(super) lo: i32,
    /// Entries per (point, row key): the columns, then [`WINDOW`] of padding.
    pub(super) len: usize,
    /// Row keys per point: 3 (2D) or 9 (3D).
    pub(super) keys: usize,
    /// Offsets along x, y, z (z empty in 2D).
    pub(super) offsets: [Vec<u32>; 3],
}

impl ClassicEvaluator {
    /// The [`WorleyColumns`] of octave `o` on the row `r`, or `None`: a Poisson count, cells
    /// under 2 pixels, or more columns than pixels.
    #[inline(always)]
    pub(super) fn worley_columns<const L: usize>(
        &self,
        o: &Octave,
        r: &RowOctave,
        window: &Window,
        width: usize,
    ) -> Option<WorleyColumns> {
        let w = self.worley.as_ref()?;
        let points = w.fixed? as usize;
        if width == 0 || o.side < 2.0 * window.scale {
            return None;
        }
        let (first, last) = Self::column_range::<L>(o, window, width);
        // Columns `first − 1 ..= last + 1`.
        let count = i64::from(last) - i64::from(first) + 3;
        if count > (width + L) as i64 + 3 {
            return None;
        }
        let count = count as usize;
        let lo = first.wrapping_sub(1);
        let len = count + WINDOW;
        let mut keys = Vec::with_capacity(9);
        for dz in if self.three_d { 0..3 } else { 1..2 } {
            for dy in 0..3 {
                keys.push(r.keys[dz][dy]);
            }
        }
        let size = points * keys.len() * len;
        let mut offsets = [buffer(size), buffer(size), Vec::new()];
        if self.three_d {
            offsets[2] = buffer(size);
        }
        let mut state = buffer(count);
        for (p, &key) in keys.iter().enumerate() {
            for (c, s) in state.iter_mut().enumerate() {
                *s = cell_hash_in_row(lattice(lo.wrapping_add(c as i32), o.cells[0]), key);
            }
            for q in 0..points {
                let at = (q * keys.len() + p) * len;
                for (c, s) in state.iter_mut().enumerate() {
                    // As `worley_lanes` draws them: x, y, then z.
                    *s = lcg_step(*s);
                    offsets[0][at + c] = unit_f32(permute(*s)).to_bits();
                    *s = lcg_step(*s);
                    offsets[1][at + c] = unit_f32(permute(*s)).to_bits();
                    if self.three_d {
                        *s = lcg_step(*s);
                        offsets[2][at + c] = unit_f32(permute(*s)).to_bits();
                    }
                }
            }
        }
        recycle(state);
        Some(WorleyColumns {
            lo,
            len,
            keys: keys.len(),
            offsets,
        })
    }

    /// Worley in the lanes: the 3×3 (×3) cells, then the exact search where it is not enough.
    #[inline(always)]
    pub(super) fn worley_lanes<
        const L: usize,
        const THREE_D: bool,
        const METRIC: u8,
        R: RowLanes,
    >(
        &self,
        w: &WorleyParams,
        o: &Octave,
        r: &R,
        x: &[f64; L],
        n: &mut [f32; L],
    ) {
        let three_d = THREE_D;
        let metric = match METRIC {
            0 => Metric::Euclidean,
            1 => Metric::Manhattan,
            _ => Metric::Chebyshev,
        };
        let mut ix = [0i32; L];
        let mut ux = [0.0f32; L];
        for l in 0..L {
            (ix[l], ux[l]) = locate(x[l] / o.side);
        }
        let mut f = [[w.cap; L]; 4];
        let dzs: &[i32] = if three_d { &[-1, 0, 1] } else { &[0] };
        for &dz in dzs {
            for dy in -1..=1i32 {
                let rz = o.uz - dz as f32;
                for dx in -1..=1i32 {
                    let mut state = [0u32; L];
                    let mut count = [0u32; L];
                    for l in 0..L {
                        let key = r.key((dz + 1) as usize, (dy + 1) as usize, l);
                        state[l] =
                            cell_hash_in_row(lattice(ix[l].wrapping_add(dx), o.cells[0]), key);
                    }
                    let most = match w.fixed {
                        Some(c) => {
                            count = [c; L];
                            c
                        }
                        None => {
                            for l in 0..L {
                                state[l] = lcg_step(state[l]);
                                let u = unit_f32(permute(state[l]));
                                let mut c = 0;
                                for &p in &w.cdf {
                                    c += u32::from(u >= p);
                                }
                                count[l] = c;
                            }
                            let mut most = 0;
                            for &c in &count {
                                most = most.max(c);
                            }
                            most
                        }
                    };
                    let rx = dx as f32;
                    for p in 0..most {
                        for l in 0..L {
                            state[l] = lcg_step(state[l]);
                            let ox = unit_f32(permute(state[l]));
                            state[l] = lcg_step(state[l]);
                            let oy = unit_f32(permute(state[l]));
                            let ddx = ux[l] - (rx + ox);
                            let ddy = (r.uy(l) - dy as f32) - oy;
                            let mut d = if three_d {
                                state[l] = lcg_step(state[l]);
                                let oz = unit_f32(permute(state[l]));
                                distance3(metric, ddx, ddy, rz - oz)
                            } else {
                                distance2(metric, ddx, ddy)
                            };
                            if p >= count[l] {
                                d = w.cap;
                            }
                            insert::<L, 4>(&mut f, l, d);
                        }
                    }
                }
            }
        }
        worley_finish(w, o, r, &ix, &ux, &f, three_d, n);
    }

    /// The metric of a Worley octave with a [`WorleyColumns`] table as a constant, for
    /// [`worley_table_lanes`](Self::worley_table_lanes); `false` (nothing written) when the
    /// lanes span too many columns for one fetch.
    #[inline(always)]
    pub(super) fn worley_table<
        const L: usize,
        F: Fetch<L>,
        R: RowLanes,
        const RELAXED: bool,
        const D3: bool,
    >(
        &self,
        o: &Octave,
        r: &R,
        x: &[f64; L],
        xf: &[f32; L],
        t: &WorleyColumns,
        n: &mut [f32; L],
    ) -> bool {
        let Some(w) = &self.worley else {
            return false;
        };
        // Metric and kept distances as constants: one distance where only `F₁` is needed.
        macro_rules! lanes {
            ($metric:literal) => {
                if w.needed == 0 {
                    self.worley_table_lanes::<L, F, R, D3, $metric, RELAXED, 1>(
                        w, o, r, x, xf, t, n,
                    )
                } else {
                    self.worley_table_lanes::<L, F, R, D3, $metric, RELAXED, 4>(
                        w, o, r, x, xf, t, n,
                    )
                }
            };
        }
        match w.metric {
            Metric::Euclidean => lanes!(0),
            Metric::Manhattan => lanes!(1),
            Metric::Chebyshev => lanes!(2),
        }
    }

    /// [`worley_lanes`](Self::worley_lanes) with the feature points read from the row's
    /// [`WorleyColumns`] `t` (a fixed count): the same cells, points and arithmetic in the same
    /// order. `K`: the smallest distances kept, 1 where only `F₁` is needed (one `min` per
    /// point instead of the insertion network), else 4 ([`insert`]).
    #[inline(always)]
    #[allow(
        clippy::too_many_arguments,
        reason = "the lanes' state, passed unpacked"
    )]
    pub(super) fn worley_table_lanes<
        const L: usize,
        F: Fetch<L>,
        R: RowLanes,
        const THREE_D: bool,
        const METRIC: u8,
        const RELAXED: bool,
        const K: usize,
    >(
        &self,
        w: &WorleyParams,
        o: &Octave,
        r: &R,
        x: &[f64; L],
        xf: &[f32; L],
        t: &WorleyColumns,
        n: &mut [f32; L],
    ) -> bool {
        let metric = match METRIC {
            0 => Metric::Euclidean,
            1 => Metric::Manhattan,
            _ => Metric::Chebyshev,
        };
        let mut ix = [0i32; L];
        let mut ux = [0.0f32; L];
        if RELAXED {
            locate_lanes_f32(o, xf, &mut ix, &mut ux);
        } else {
            locate_lanes(&cell_units(o, x), &mut ix, &mut ux);
        }
        let span = i64::from(ix[L - 1]) - i64::from(ix[0]);
        // Column `ix − 1` of lane 0 is entry `base`.
        let base = i64::from(ix[0]) - 1 - i64::from(t.lo);
        if !(0..L as i64).contains(&span) || base < 0 || base as usize + WINDOW > t.len {
            return false;
        }
        let base = base as usize;
        let fetch = F::fetch;
        let mut idx = [0u32; L];
        for l in 0..L {
            idx[l] = ix[l].wrapping_sub(ix[0]) as u32;
        }
        let points = t.offsets[0].len() / (t.keys * t.len);
        let mut f = [[w.cap; L]; 4];
        let dzs: &[i32] = if THREE_D { &[-1, 0, 1] } else { &[0] };
        for &dz in dzs {
            for dy in -1..=1i32 {
                let rz = o.uz - dz as f32;
                let key = if THREE_D {
                    3 * (dz + 1) + dy + 1
                } else {
                    dy + 1
                } as usize;
                let mut ry = [0.0f32; L];
                for l in 0..L {
                    ry[l] = r.uy(l) - dy as f32;
                }
                for dx in -1..=1i32 {
                    let rx = dx as f32;
                    let from = (dx + 1) as usize;
                    for q in 0..points {
                        let at = (q * t.keys + key) * t.len + base;
                        let ox = fetch(&window(&t.offsets[0], at)[from..from + L], &idx);
                        let oy = fetch(&window(&t.offsets[1], at)[from..from + L], &idx);
                        let oz = if THREE_D {
                            fetch(&window(&t.offsets[2], at)[from..from + L], &idx)
                        } else {
                            [0; L]
                        };
                        for l in 0..L {
                            let ddx = ux[l] - (rx + f32::from_bits(ox[l]));
                            let ddy = ry[l] - f32::from_bits(oy[l]);
                            let d = match (THREE_D, RELAXED && metric == Metric::Euclidean) {
                                (true, false) => {
                                    distance3(metric, ddx, ddy, rz - f32::from_bits(oz[l]))
                                }
                                (false, false) => distance2(metric, ddx, ddy),
                                (true, true) => {
                                    let ddz = rz - f32::from_bits(oz[l]);
                                    fused(ddx, ddx, fused(ddy, ddy, ddz * ddz))
                                }
                                (false, true) => fused(ddx, ddx, ddy * ddy),
                            };
                            insert::<L, K>(&mut f, l, d);
                        }
                    }
                }
            }
        }
        worley_finish(w, o, r, &ix, &ux, &f, THREE_D, n);
        true
    }
}

/// The end of a Worley octave in the lanes: where the 3×3 (×3) block's needed `F_n` is
/// farther than the unsearched cells, [`worley_search`] goes on; then the combination.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the lanes' state, passed unpacked"
)]
pub(super) fn worley_finish<const L: usize, R: RowLanes>(
    w: &WorleyParams,
    o: &Octave,
    r: &R,
    ix: &[i32; L],
    ux: &[f32; L],
    f: &[[f32; L]; 4],
    three_d: bool,
    n: &mut [f32; L],
) {
    for l in 0..L {
        let gap = gap(ux[l], r.uy(l), o.uz, three_d, 1);
        let gap = if w.metric == Metric::Euclidean {
            gap * gap
        } else {
            gap
        };
        let mut fl = [f[0][l], f[1][l], f[2][l], f[3][l]];
        if fl[w.needed] > gap {
            fl = worley_search(
                w,
                fl,
                (ix[l], ux[l]),
                (r.iy(l), r.uy(l)),
                (o.kz, o.uz),
                three_d,
                o,
            );
        }
        n[l] = combine(w, fl);
    }
}

/// Distance to the cells outside the `(2ring + 1)^d` block around the point's cell, per axis.
#[inline(always)]
pub(super) fn gap(ux: f32, uy: f32, uz: f32, three_d: bool, ring: i32) -> f32 {
    let r = ring as f32;
    let mut g = min(min(ux + r, (r + 1.0) - ux), min(uy + r, (r + 1.0) - uy));
    if three_d {
        g = min(g, min(uz + r, (r + 1.0) - uz));
    }
    g
}

#[inline(always)]
pub(super) fn distance2(metric: Metric, dx: f32, dy: f32) -> f32 {
    match metric {
        Metric::Euclidean => dx * dx + dy * dy,
        Metric::Manhattan => dx.abs() + dy.abs(),
        Metric::Chebyshev => max(dx.abs(), dy.abs()),
    }
}

#[inline(always)]
pub(super) fn distance3(metric: Metric, dx: f32, dy: f32, dz: f32) -> f32 {
    match metric {
        Metric::Euclidean => dx * dx + dy * dy + dz * dz,
        Metric::Manhattan => dx.abs() + dy.abs() + dz.abs(),
        Metric::Chebyshev => max(max(dx.abs(), dy.abs()), dz.abs()),
    }
}

/// Inserts `d` into lane `l` of the ascending list `f` (the four smallest so far), or of its
/// first `K`: the `K` smallest are the same either way, and the entries after them keep their
/// start, `cap`. Where only `F₁` is needed (`K` = 1) that is one `min`; the combination's zero
/// coefficients take `+0` from `cap` as from a distance, and the exact search finds the same
/// `F₁` from either list.
#[inline(always)]
pub(super) fn insert<const L: usize, const K: usize>(f: &mut [[f32; L]; 4], l: usize, d: f32) {
    let mut d = d;
    for fk in f.iter_mut().take(K) {
        let a = min(fk[l], d);
        d = max(fk[l], d);
        fk[l] = a;
    }
}

/// `C₁F₁ + C₂F₂ + C₃F₃ + C₄F₄` from the sorted list (squared distances for the Euclidean metric).
#[inline(always)]
pub(super) fn combine(w: &WorleyParams, f: [f32; 4]) -> f32 {
    let f = if w.metric == Metric::Euclidean {
        f.map(f32::sqrt)
    } else {
        f
    };
    let c = w.coefficients;
    ((c[0] * f[0] + c[1] * f[1]) + c[2] * f[2]) + c[3] * f[3]
}

/// The exact search for one point, continuing from `f`, the four smallest distances over the
/// 3×3 (×3) block: ring after ring of cells until the needed `F_n` is no farther than the
/// unsearched cells, or [`WORLEY_MAX_RING`] rings. Returns the four smallest distances (squared
/// for the Euclidean metric), as the lanes keep them; the four smallest of a set do not depend
/// on the order it is visited in.
pub(super) fn worley_search(
    w: &WorleyParams,
    f: [f32; 4],
    (ix, ux): (i32, f32),
    (iy, uy): (i32, f32),
    (kz, uz): (i32, f32),
    three_d: bool,
    o: &Octave,
) -> [f32; 4] {
    let mut list = f.map(|v| [v]);
    let mut f = f;
    for ring in 2..=WORLEY_MAX_RING {
        let zr = if three_d { ring } else { 0 };
        for dz in -zr..=zr {
            for dy in -ring..=ring {
                for dx in -ring..=ring {
                    // Only the cells of this ring: the inner ones are in `list` already.
                    if dx.abs().max(dy.abs()).max(dz.abs()) != ring {
                        continue;
                    }
                    let (cx, cy, cz) = (
                        lattice(ix.wrapping_add(dx), o.cells[0]),
                        lattice(iy.wrapping_add(dy), o.cells[1]),
                        kz.wrapping_add(dz),
                    );
                    let h = if three_d {
                        hash3(cx, cy, cz, o.layer, o.key0)
                    } else {
                        cell_hash_in_row(cx, row_key(cy, o.key2))
                    };
                    let mut state = h;
                    let count = match w.fixed {
                        Some(c) => c,
                        None => {
                            state = lcg_step(state);
                            let u = unit_f32(permute(state));
                            w.cdf.iter().map(|&p| u32::from(u >= p)).sum()
                        }
                    };
                    for _ in 0..count {
                        state = lcg_step(state);
                        let ox = unit_f32(permute(state));
                        state = lcg_step(state);
                        let oy = unit_f32(permute(state));
                        let ddx = ux - (dx as f32 + ox);
                        let ddy = (uy - dy as f32) - oy;
                        let d = if three_d {
                            state = lcg_step(state);
                            let oz = unit_f32(permute(state));
                            distance3(w.metric, ddx, ddy, (uz - dz as f32) - oz)
                        } else {
                            distance2(w.metric, ddx, ddy)
                        };
                        insert::<1, 4>(&mut list, 0, d);
                    }
                }
            }
        }
        f = [list[0][0], list[1][0], list[2][0], list[3][0]];
        let g = gap(ux, uy, uz, three_d, ring);
        let g = if w.metric == Metric::Euclidean {
            g * g
        } else {
            g
        };
        if f[w.needed] <= g {
            break;
        }
    }
    f
}
