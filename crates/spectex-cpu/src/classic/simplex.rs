//! Simplex noise in the lanes (2D and 3D), with its per-row keys and 3D corner tables.

use spectex_model::Window;
use spectex_model::classic::{
    SIMPLEX_F2, SIMPLEX_F3, SIMPLEX_G2, SIMPLEX_G3, SIMPLEX2_R2, SIMPLEX2_SCALE, SIMPLEX3_R2,
    SIMPLEX3_SCALE, gradient_dot,
};
use spectex_model::random::{cell_hash_in_row, layer_key, row_key};

use super::ClassicEvaluator;
use super::cache::{KEPT_CORNER_TABLES, KEPT_CORNERS, buffer, recycle, scratch};
use super::fractal::{Octave, RowLanes, RowOctave};
use super::lanes::{Fetch, WINDOW, cell_units, fused, max, split, split_lanes};
use super::tables::{coded_gradient_dot, gradient_code, window};

/// The keys of simplex noise's skewed lattice along one row, for the skewed rows `lo..` its
/// lanes visit: 2D, `row_key(j, layer_key(o, seed))` of skewed row `j`; 3D, the layer key
/// `layer_key(o, cell_hash(k, 0, o, seed))` of skewed plane `k`. The lanes fetch those of `j`
/// (`k`) and `j + 1` (`k + 1`) instead of hashing them for every corner.
#[derive(Debug, Clone)]
pub(super) struct SimplexColumns {
    /// The first skewed row (plane).
    pub(super) lo: i32,
    /// Entries: the rows, then [`WINDOW`] of padding.
    pub(super) len: usize,
    pub(super) keys: Vec<u32>,
    /// 3D, cells wide enough: every corner's hash, read instead of the two hashes per corner
    /// that remain with the layer keys (`keys` is then empty, `len` 0).
    pub(super) corners: Option<SimplexCorners>,
    /// Whether every skewed coordinate of the row's lanes is below 2⁴⁸ in magnitude, where a
    /// floor instruction gives [`split`]'s floors (the AVX-512 kernel's `floor_pair`).
    pub(super) bounded: bool,
}

/// The gradients of the 3D simplex corners one row of one octave visits, so that the lanes read
/// a corner's gradient instead of computing `row_key` and `cell_hash_in_row` and its hash.
///
/// Each entry `(i', j', k')` packs the top four bits of the [`gradient_code`]s of the eight
/// corners of the cube there, corner `(i' + di, j' + dj, k' + dk)` at bits `4c..4c + 4` with
/// `c = di + 2dj + 4dk`: a lane reads its cell's entry once, and a corner's code is that word
/// shifted left by `28 − 4c` (the bits below the code's four are ignored).
///
/// Along a row (`py`, `pz` fixed) the skewed coordinates are `a = px + s`, `b = py + s`,
/// `c = pz + s` with `s = (px + py + pz)/3`, so `a − 4b = −5py − pz` and `c − b = pz − py` are
/// constants: a lane's `e = i − 4j` takes 5 values (`⌊a⌋ − 4⌊b⌋ = ⌊(a − 4b) + 4·frac b⌋`) and
/// `d = k − j` two, while `j` grows slowly with `x`. The table is laid out by `(j', d', e')`:
/// entry `((j' − j_lo)·D + (d' − d_lo))·E + (e' − e_lo)` with `D` = [`CORNER_D`] and `E` =
/// [`CORNER_E`] (a register of entries per `(j', d')`, so a row builds a register at a time):
/// a corner step `(di, dj, dk)` adds [`CORNER_STEP`]` · (di, dj, dk)` (its cube's corners are
/// [`CUBE_CORNERS`] after it). A lane uses the table when its corners all fall inside
/// ([`SimplexCorners::entries`]): `j − j_lo < rows − 1`, `d − d_lo ∈ {1, 2}` and
/// `e − e_lo ∈ 4..=14` (a corner moves `d` by −1..=1 and `e` by −4..=1).
#[derive(Debug, Clone)]
pub(super) struct SimplexCorners {
    /// The octave's layer and `key0`: the table's hashes are a function of them and of
    /// `j_lo`, `d_lo`, `e_lo`.
    pub(super) layer: u32,
    pub(super) key0: u32,
    /// The first skewed row `j_lo`, the lowest `d_lo = k − j` and `e_lo = i − 4j`.
    pub(super) j_lo: i32,
    pub(super) d_lo: i32,
    pub(super) e_lo: i32,
    /// Skewed rows `j_lo..j_lo + rows` of entries.
    pub(super) rows: u32,
    /// The cubes' packed codes, by entry (those a lane can read: see above).
    pub(super) cubes: Vec<u32>,
}

/// The layer key of 3D simplex noise's skewed plane `k` in octave `o`, from which its rows'
/// keys and corners' hashes follow (`avx512::layer_key` in the lanes).
#[inline(always)]
pub(super) fn plane_key(o: &Octave, k: i32) -> u32 {
    layer_key(o.layer, cell_hash_in_row(k, o.key0))
}

/// Values of `e = i − 4j` per `(j', d')` in [`SimplexCorners`]: one register of 16.
pub(super) const CORNER_E: u32 = 16;
/// Values of `d = k − j` per `j'` in [`SimplexCorners`].
pub(super) const CORNER_D: u32 = 4;
/// What a step of `i`, `j`, `k` adds to a [`SimplexCorners`] entry: `e + 1`; `j + 1`, `d − 1`,
/// `e − 4`; `d + 1`.
pub(super) const CORNER_STEP: [u32; 3] = [1, CORNER_D * CORNER_E - CORNER_E - 4, CORNER_E];

/// How far corner `c = di + 2dj + 4dk` of a [`SimplexCorners`] entry's cube is from the entry:
/// [`CORNER_STEP`]` · (di, dj, dk)`.
pub(super) const CUBE_CORNERS: [usize; 8] = {
    let mut at = [0; 8];
    let mut c = 0;
    while c < 8 {
        let mut a = 0;
        while a < 3 {
            at[c] += (CORNER_STEP[a] as usize) * ((c >> a) & 1);
            a += 1;
        }
        c += 1;
    }
    at
};

impl SimplexCorners {
    /// The table of row `py` of octave `o` for the skewed rows `j_lo..=j_hi` (those of the
    /// lanes and the next): one an earlier row of this thread kept ([`keep`](Self::keep))
    /// where it covers them with the same `d_lo` and `e_lo`, else a new one, two skewed rows
    /// longer where that fits, so that the next rows find it; `None` when it would hold more
    /// than `most` entries.
    #[inline(always)]
    pub(super) fn for_row(o: &Octave, py: f64, j_lo: i32, j_hi: i32, most: usize) -> Option<Self> {
        // `d ∈ {⌊pz − py⌋, ⌊pz − py⌋ + 1}` and `e ∈ ⌊−5py − pz⌋ + 0..=4` on the whole row (the
        // margins of `entries` take the roundings of the lanes' f64 sums); `e_lo` a multiple of
        // 4 in `e − 7..=e − 4`, so that rows whose `e` differs by a little share it.
        let d = (o.pz - py).floor();
        let e = (-5.0 * py - o.pz).floor();
        if !(d.abs() < 2.0e9 && e.abs() < 2.0e9) {
            return None;
        }
        let d_lo = d as i64 - 1;
        let e_lo = (e as i64 - 4).div_euclid(4) * 4;
        let (d_lo, e_lo) = (i32::try_from(d_lo).ok()?, i32::try_from(e_lo).ok()?);
        let covers = |c: &Self| {
            c.layer == o.layer
                && c.key0 == o.key0
                && c.d_lo == d_lo
                && c.e_lo == e_lo
                && c.j_lo <= j_lo
                && i64::from(j_hi) < i64::from(c.j_lo) + i64::from(c.rows)
        };
        let kept = KEPT_CORNERS.with(|k| {
            let mut k = k.borrow_mut();
            let found = k.iter().position(covers);
            found.map(|i| k.swap_remove(i))
        });
        if kept.is_some() {
            return kept;
        }
        Self::new(o, d_lo, e_lo, j_lo, j_hi.saturating_add(2), most)
            .or_else(|| Self::new(o, d_lo, e_lo, j_lo, j_hi, most))
    }

    /// Keeps the table for this thread's next rows ([`for_row`](Self::for_row)); the oldest
    /// kept goes back to the buffers.
    pub(super) fn keep(self) {
        KEPT_CORNERS.with(|k| {
            let mut k = k.borrow_mut();
            if k.len() >= KEPT_CORNER_TABLES {
                recycle(k.remove(0).cubes);
            }
            k.push(self);
        });
    }

    /// The table of octave `o` with its lowest `d_lo` and `e_lo` for the skewed rows
    /// `j_lo..=j_hi`, or `None` when it would hold more than `most` entries.
    #[inline(always)]
    pub(super) fn new(
        o: &Octave,
        d_lo: i32,
        e_lo: i32,
        j_lo: i32,
        j_hi: i32,
        most: usize,
    ) -> Option<Self> {
        let rows = i64::from(j_hi) - i64::from(j_lo) + 1;
        if rows < 2 || rows as u64 * u64::from(CORNER_D * CORNER_E) > most as u64 {
            return None;
        }
        let rows = rows as usize;
        // The layer keys of the planes `k' = j' + d'`: `j_lo + d_lo + m`.
        let k0 = j_lo.wrapping_add(d_lo);
        let mut layers = scratch(rows + CORNER_D as usize);
        for (m, key) in layers.iter_mut().enumerate() {
            *key = plane_key(o, k0.wrapping_add(m as i32));
        }
        // Row keys by `d'`, then `j'`: `rk[d'·rows + w] = row_key(j_lo + w, layers[w + d'])`.
        let mut rk = scratch(rows * CORNER_D as usize);
        for d in 0..CORNER_D as usize {
            let (keys, layers) = (&mut rk[d * rows..(d + 1) * rows], &layers[d..d + rows]);
            for (w, (key, &layer)) in keys.iter_mut().zip(layers).enumerate() {
                *key = row_key(j_lo.wrapping_add(w as i32), layer);
            }
        }
        recycle(layers);
        let e_count = CORNER_E as usize;
        let mut hashes = scratch(rows * (CORNER_D * CORNER_E) as usize);
        for (w, block) in hashes
            .chunks_exact_mut((CORNER_D * CORNER_E) as usize)
            .enumerate()
        {
            // `i' = e' + 4j'`.
            let i0 = e_lo.wrapping_add(j_lo.wrapping_add(w as i32).wrapping_mul(4));
            for (d, entries) in block.chunks_exact_mut(e_count).enumerate() {
                let key = rk[d * rows + w];
                let entries: &mut [u32; 16] = entries.try_into().expect("CORNER_E entries");
                for (e, h) in entries.iter_mut().enumerate() {
                    *h = gradient_code(cell_hash_in_row(i0.wrapping_add(e as i32), key));
                }
            }
        }
        recycle(rk);
        // Each entry's cube: its corners' codes (the last entries, whose cubes leave the table,
        // are never read).
        let mut cubes = scratch(hashes.len());
        let (inner, outer) = cubes.split_at_mut(hashes.len() - CUBE_CORNERS[7]);
        for (at, cube) in inner.iter_mut().enumerate() {
            let mut word = 0;
            for (c, corner) in CUBE_CORNERS.iter().enumerate() {
                word |= (hashes[at + corner] >> 28) << (4 * c);
            }
            *cube = word;
        }
        outer.fill(0);
        recycle(hashes);
        Some(Self {
            layer: o.layer,
            key0: o.key0,
            j_lo,
            d_lo,
            e_lo,
            rows: rows as u32,
            cubes,
        })
    }

    /// The entries of the lanes' corners `(i, j, k)`, or `None` when a corner of a lane falls
    /// outside the table: with `w = j − j_lo`, `d = k − j − d_lo − 1`, `e = i − 4j − e_lo − 4`
    /// (those the range check compares), the layout's `(w·D + d + 1)·E + e + 4`
    /// (`avx512::entries` in the lanes).
    #[inline(always)]
    pub(super) fn entries<const L: usize>(
        &self,
        i: &[i32; L],
        j: &[i32; L],
        k: &[i32; L],
    ) -> Option<[u32; L]> {
        let mut inside = [false; L];
        let mut entry = [0u32; L];
        let (j_lo, d_lo, e_lo) = (self.j_lo as u32, self.d_lo as u32, self.e_lo as u32);
        for l in 0..L {
            let (i, j, k) = (i[l] as u32, j[l] as u32, k[l] as u32);
            let w = j.wrapping_sub(j_lo);
            let d = k.wrapping_sub(j).wrapping_sub(d_lo.wrapping_add(1));
            let e = i.wrapping_sub(j << 2).wrapping_sub(e_lo.wrapping_add(4));
            inside[l] = (w < self.rows - 1) & (d < 2) & (e < 11);
            entry[l] = (w.wrapping_mul(CORNER_D).wrapping_add(d).wrapping_add(1))
                .wrapping_mul(CORNER_E)
                .wrapping_add(e)
                .wrapping_add(4);
        }
        inside.iter().all(|&v| v).then_some(entry)
    }
}

impl ClassicEvaluator {
    /// The skew `s` of simplex noise at `x` on the row `r`, as [`simplex2`] and [`simplex3`]
    /// compute it: the skewed row is `⌊py + s⌋`, in 3D the plane `⌊pz + s⌋`.
    #[inline(always)]
    pub(super) fn simplex_skew(&self, o: &Octave, r: &RowOctave, x: f64) -> f64 {
        let px = x / o.side;
        if self.three_d {
            ((px + r.py) + o.pz) * SIMPLEX_F3
        } else {
            (px + r.py) * SIMPLEX_F2
        }
    }

    /// The [`SimplexColumns`] of octave `o` on the row `r`, or `None`: cells under 2 pixels or
    /// more skewed rows than pixels. In 3D, where `corners` asks for them ([`Fetch::CORNERS`])
    /// and they fit, the [`SimplexCorners`] alone: the lanes then need no plane keys.
    #[inline(always)]
    pub(super) fn simplex_columns<const L: usize>(
        &self,
        o: &Octave,
        r: &RowOctave,
        window: &Window,
        width: usize,
        corners: bool,
    ) -> Option<SimplexColumns> {
        if width == 0 || o.side < 2.0 * window.scale {
            return None;
        }
        // The skewed coordinate grows with x along a row (a sum of non-decreasing terms).
        let last_start = (width - 1) / L * L;
        let first = window.offset[0] + (window.x0 as f64) * window.scale;
        let last = window.offset[0]
            + ((window.x0 + last_start as i64) as f64 + (L - 1) as f64) * window.scale;
        let (s_first, s_last) = (
            self.simplex_skew(o, r, first),
            self.simplex_skew(o, r, last),
        );
        // `|px + s|` and the others are at most `2·(|px| + |py| + |pz|)`, `px` at its largest at
        // an end of the row (an affine function of the lane); false for NaN and infinities.
        let bounded = 2.0 * (first.abs().max(last.abs()) / o.side + r.py.abs() + o.pz.abs())
            < (1u64 << 48) as f64;
        // The corners' table where it holds at most two entries per pixel (it saves the lanes
        // eight hashes per pixel): the skewed rows of the first and last lanes, one more on
        // each side for the rounding of the lanes' `x / side`, and the corners' `j + 1`.
        if self.three_d && corners {
            let (j_lo, j_hi) = (split(r.py + s_first).0, split(r.py + s_last).0);
            let most = 2 * (width + L);
            let corners = SimplexCorners::for_row(
                o,
                r.py,
                j_lo.saturating_sub(1),
                j_hi.saturating_add(2),
                most,
            );
            if corners.is_some() {
                return Some(SimplexColumns {
                    lo: 0,
                    len: 0,
                    keys: Vec::new(),
                    corners,
                    bounded,
                });
            }
        }
        let along = if self.three_d { o.pz } else { r.py };
        let (lo, hi) = (split(along + s_first).0, split(along + s_last).0);
        let count = i64::from(hi) - i64::from(lo) + 2;
        if count > (width + L) as i64 + 2 {
            return None;
        }
        let count = count as usize;
        let len = count + WINDOW;
        let mut keys = buffer(len);
        for (c, key) in keys[..count].iter_mut().enumerate() {
            let cell = lo.wrapping_add(c as i32);
            *key = if self.three_d {
                plane_key(o, cell)
            } else {
                row_key(cell, o.key2)
            };
        }
        Some(SimplexColumns {
            lo,
            len,
            keys,
            corners: None,
            bounded,
        })
    }
}

/// One simplex corner's term `max(0, r² − |δ|²)⁴ · (g · δ)`, `h` a hash or, `CODED`, its
/// [`gradient_code`].
#[inline(always)]
pub(super) fn simplex_term<const FMA: bool, const CODED: bool>(
    h: u32,
    r2: f32,
    dx: f32,
    dy: f32,
    dz: f32,
) -> f32 {
    let d2 = if FMA {
        fused(dx, dx, fused(dy, dy, dz * dz))
    } else {
        dx * dx + dy * dy + dz * dz
    };
    let t = max(r2 - d2, 0.0);
    let t2 = t * t;
    let dot = if CODED {
        coded_gradient_dot(h, dx, dy, dz)
    } else {
        gradient_dot(h, dx, dy, dz)
    };
    t2 * t2 * dot
}

/// Where 2D simplex noise's lanes stand: the cells `(i, j)` of the skewed lattice and the
/// offsets `(x0, y0)` from its first corner.
pub(super) struct Simplex2At<const L: usize> {
    pub(super) i: [i32; L],
    pub(super) j: [i32; L],
    pub(super) x0: [f32; L],
    pub(super) y0: [f32; L],
}

/// The skew of 2D simplex noise at the lanes' positions `px` (cell units) on the rows of `r`.
#[inline(always)]
pub(super) fn simplex2_at<const L: usize, R: RowLanes>(r: &R, px: &[f64; L]) -> Simplex2At<L> {
    let mut py = [0.0f64; L];
    for l in 0..L {
        py[l] = r.py(l);
    }
    let (mut a, mut b) = ([0.0f64; L], [0.0f64; L]);
    for l in 0..L {
        let s = (px[l] + py[l]) * SIMPLEX_F2;
        a[l] = px[l] + s;
        b[l] = py[l] + s;
    }
    let mut at = Simplex2At {
        i: [0; L],
        j: [0; L],
        x0: [0.0; L],
        y0: [0.0; L],
    };
    let (mut fi, mut fj) = ([0.0f64; L], [0.0f64; L]);
    split_lanes(&a, &mut at.i, &mut fi);
    split_lanes(&b, &mut at.j, &mut fj);
    for l in 0..L {
        let t = (fi[l] + fj[l]) * SIMPLEX_G2;
        at.x0[l] = (px[l] - (fi[l] - t)) as f32;
        at.y0[l] = (py[l] - (fj[l] - t)) as f32;
    }
    at
}

/// 2D simplex noise's sum at `at`, from the row keys `k0`, `k1` of each lane's skewed rows
/// `j` and `j + 1`: one simple loop per step, so that it vectorises.
#[inline(always)]
pub(super) fn simplex2_sum<const L: usize, const FMA: bool>(
    at: &Simplex2At<L>,
    k0: &[u32; L],
    k1: &[u32; L],
    n: &mut [f32; L],
) {
    let g2 = SIMPLEX_G2 as f32;
    let mut sum = [0.0f32; L];
    // Corner 0, then the middle corner (x first where `x0 > y0`), then corner (1, 1).
    for l in 0..L {
        let h = cell_hash_in_row(at.i[l], k0[l]);
        sum[l] = simplex_term::<FMA, false>(h, SIMPLEX2_R2, at.x0[l], at.y0[l], 0.0);
    }
    for l in 0..L {
        let step_x = at.x0[l] > at.y0[l];
        let (i1, j1) = if step_x { (1, 0) } else { (0, 1) };
        let x1 = (at.x0[l] - i1 as f32) + g2;
        let y1 = (at.y0[l] - j1 as f32) + g2;
        let h = cell_hash_in_row(at.i[l].wrapping_add(i1), if step_x { k0[l] } else { k1[l] });
        sum[l] += simplex_term::<FMA, false>(h, SIMPLEX2_R2, x1, y1, 0.0);
    }
    for l in 0..L {
        let x2 = (at.x0[l] - 1.0) + 2.0 * g2;
        let y2 = (at.y0[l] - 1.0) + 2.0 * g2;
        let h = cell_hash_in_row(at.i[l].wrapping_add(1), k1[l]);
        n[l] = SIMPLEX2_SCALE * (sum[l] + simplex_term::<FMA, false>(h, SIMPLEX2_R2, x2, y2, 0.0));
    }
}

/// 2D simplex noise in the lanes, every row key hashed in them.
#[inline(always)]
pub(super) fn simplex2<const L: usize, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    n: &mut [f32; L],
) {
    let at = simplex2_at(r, &cell_units(o, x));
    let (mut k0, mut k1) = ([0u32; L], [0u32; L]);
    for l in 0..L {
        k0[l] = row_key(at.j[l], o.key2);
        k1[l] = row_key(at.j[l].wrapping_add(1), o.key2);
    }
    simplex2_sum::<L, false>(&at, &k0, &k1, n);
}

/// Where lanes with skewed rows (planes) `cell` read the row's [`SimplexColumns`] `t`: the
/// entry of lane 0 and each lane's distance from it, or `None` when one fetch cannot reach them.
#[inline(always)]
pub(super) fn simplex_window<const L: usize>(
    t: &SimplexColumns,
    cell: &[i32; L],
) -> Option<(usize, [u32; L])> {
    let span = i64::from(cell[L - 1]) - i64::from(cell[0]);
    let base = i64::from(cell[0]) - i64::from(t.lo);
    if !(0..L as i64).contains(&span) || base < 0 || base as usize + WINDOW > t.len {
        return None;
    }
    let mut idx = [0u32; L];
    for l in 0..L {
        idx[l] = cell[l].wrapping_sub(cell[0]) as u32;
    }
    Some((base as usize, idx))
}

/// [`simplex2`] with the row keys of the skewed rows `j`, `j + 1` read from the row's
/// [`SimplexColumns`]; `false` (nothing written) when one fetch cannot reach them.
#[inline(always)]
pub(super) fn simplex2_table<const L: usize, F: Fetch<L>, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    t: &SimplexColumns,
    n: &mut [f32; L],
) -> bool {
    let at = simplex2_at(r, &cell_units(o, x));
    let Some((base, idx)) = simplex_window(t, &at.j) else {
        return false;
    };
    let keys = window(&t.keys, base);
    let (k0, k1) = (F::fetch(&keys[..L], &idx), F::fetch(&keys[1..=L], &idx));
    simplex2_sum::<L, false>(&at, &k0, &k1, n);
    true
}

/// Where 3D simplex noise's lanes stand: the cells `(i, j, k)` of the skewed lattice and the
/// offsets `(x0, y0, z0)` from its first corner.
pub(super) struct Simplex3At<const L: usize> {
    pub(super) i: [i32; L],
    pub(super) j: [i32; L],
    pub(super) k: [i32; L],
    pub(super) x0: [f32; L],
    pub(super) y0: [f32; L],
    pub(super) z0: [f32; L],
}

/// The skew of 3D simplex noise at the lanes' positions `px` (cell units) on the rows of `r`
/// and the octave's plane.
#[inline(always)]
pub(super) fn simplex3_at<const L: usize, R: RowLanes>(
    o: &Octave,
    r: &R,
    px: &[f64; L],
) -> Simplex3At<L> {
    let pz = o.pz;
    let mut py = [0.0f64; L];
    for l in 0..L {
        py[l] = r.py(l);
    }
    let (mut a, mut b, mut c) = ([0.0f64; L], [0.0f64; L], [0.0f64; L]);
    for l in 0..L {
        let s = ((px[l] + py[l]) + pz) * SIMPLEX_F3;
        a[l] = px[l] + s;
        b[l] = py[l] + s;
        c[l] = pz + s;
    }
    let mut at = Simplex3At {
        i: [0; L],
        j: [0; L],
        k: [0; L],
        x0: [0.0; L],
        y0: [0.0; L],
        z0: [0.0; L],
    };
    let (mut fi, mut fj, mut fk) = ([0.0f64; L], [0.0f64; L], [0.0f64; L]);
    split_lanes(&a, &mut at.i, &mut fi);
    split_lanes(&b, &mut at.j, &mut fj);
    split_lanes(&c, &mut at.k, &mut fk);
    for l in 0..L {
        let t = ((fi[l] + fj[l]) + fk[l]) * SIMPLEX_G3;
        at.x0[l] = (px[l] - (fi[l] - t)) as f32;
        at.y0[l] = (py[l] - (fj[l] - t)) as f32;
        at.z0[l] = (pz - (fk[l] - t)) as f32;
    }
    at
}

/// Where 3D simplex noise's lanes find their corners' hashes.
pub(super) enum Corners3<'a, const L: usize> {
    /// The layer keys of each lane's skewed planes `k` and `k + 1`.
    Layers([u32; L], [u32; L]),
    /// The row's [`SimplexCorners`] cubes and each lane's entry ([`SimplexCorners::entries`]).
    Table(&'a [u32], [u32; L]),
}

/// Gustavson's ranking of the lanes' `x0, y0, z0`, written as selects: the steps
/// `(i1, j1, k1)` and `(i2, j2, k2)` of the middle corners of 3D simplex noise.
#[inline(always)]
pub(super) fn simplex3_steps<const L: usize>(at: &Simplex3At<L>) -> [[[i32; L]; 3]; 2] {
    // The comparisons as 0/1 integers and the logic as bitwise operations (`1 ^ a` is `!a`):
    // short-circuit `&&` and `||` would compile to a branch per lane.
    let (mut a, mut b, mut c) = ([0i32; L], [0i32; L], [0i32; L]);
    for l in 0..L {
        a[l] = i32::from(at.x0[l] >= at.y0[l]);
        b[l] = i32::from(at.y0[l] >= at.z0[l]);
        c[l] = i32::from(at.x0[l] >= at.z0[l]);
    }
    let mut step = [[[0i32; L]; 3]; 2];
    for l in 0..L {
        let (a, b, c) = (a[l], b[l], c[l]);
        let (na, nb, nc) = (1 ^ a, 1 ^ b, 1 ^ c);
        step[0][0][l] = a & (b | c);
        step[0][1][l] = na & b;
        step[0][2][l] = nb & (na | nc);
        step[1][0][l] = a | (b & c);
        step[1][1][l] = b | na;
        step[1][2][l] = nb | (na & nc);
    }
    step
}

/// 3D simplex noise's sum at `at`, from each lane's corner hashes `corners`: one simple loop
/// per corner, so that it vectorises.
#[inline(always)]
pub(super) fn simplex3_sum<const L: usize, const FMA: bool>(
    at: &Simplex3At<L>,
    corners: &Corners3<'_, L>,
    n: &mut [f32; L],
) {
    let step = simplex3_steps(at);
    match corners {
        Corners3::Layers(l0, l1) => {
            // `hash3` of corner `(i + di, j + dj, k + dk)` from the layer keys, in the lanes.
            let hash = |l: usize, _: usize, di: i32, dj: i32, dk: i32| {
                // `l0` where `dk` is 0, `l1` where it is 1, by a mask: a select of two loads
                // would compile to a scalar load per lane.
                let layer = l0[l] ^ ((l0[l] ^ l1[l]) & 0u32.wrapping_sub(dk as u32));
                cell_hash_in_row(
                    at.i[l].wrapping_add(di),
                    row_key(at.j[l].wrapping_add(dj), layer),
                )
            };
            simplex3_terms::<L, FMA, false>(at, &step, hash, n);
        }
        Corners3::Table(cubes, entry) => {
            // Each lane's cube, then one loop per corner: read in the term's loop, the reads
            // kept it scalar.
            let mut cube = [0u32; L];
            for l in 0..L {
                #[allow(unsafe_code)]
                // SAFETY: `SimplexCorners::entries` checked that every lane's cube is an entry
                // of the table (a checked index keeps the loop scalar).
                unsafe {
                    cube[l] = *cubes.get_unchecked(entry[l] as usize);
                }
            }
            let mut h = [[0u32; L]; 4];
            for (c, h) in h.iter_mut().enumerate() {
                for l in 0..L {
                    let [di, dj, dk] = match c {
                        0 => [0; 3],
                        3 => [1; 3],
                        _ => [step[c - 1][0][l], step[c - 1][1][l], step[c - 1][2][l]],
                    };
                    // The corner's code at the top of the word (`SimplexCorners`).
                    h[l] = cube[l] << (28 - 4 * (di + 2 * dj + 4 * dk)) as u32;
                }
            }
            let hash = |l: usize, c: usize, _, _, _| h[c][l];
            simplex3_terms::<L, FMA, true>(at, &step, hash, n);
        }
    }
}

/// The terms of the four corners of 3D simplex noise summed in the lanes, corner
/// `c = 0..4`, `(i + di, j + dj, k + dk)`, with hash `hash(l, c, di, dj, dk)` and offsets
/// `(x0 − di) + off`.
#[inline(always)]
pub(super) fn simplex3_terms<const L: usize, const FMA: bool, const CODED: bool>(
    at: &Simplex3At<L>,
    step: &[[[i32; L]; 3]; 2],
    hash: impl Fn(usize, usize, i32, i32, i32) -> u32,
    n: &mut [f32; L],
) {
    let g3 = SIMPLEX_G3 as f32;
    let term = |l: usize, c: usize, di: i32, dj: i32, dk: i32, off: f32| {
        simplex_term::<FMA, CODED>(
            hash(l, c, di, dj, dk),
            SIMPLEX3_R2,
            (at.x0[l] - di as f32) + off,
            (at.y0[l] - dj as f32) + off,
            (at.z0[l] - dk as f32) + off,
        )
    };
    // `((c0 + c1) + c2) + c3`.
    let mut sum = [0.0f32; L];
    for l in 0..L {
        sum[l] = term(l, 0, 0, 0, 0, 0.0);
    }
    for (corner, s) in step.iter().enumerate() {
        let off = (corner + 1) as f32 * g3;
        for l in 0..L {
            sum[l] += term(l, corner + 1, s[0][l], s[1][l], s[2][l], off);
        }
    }
    for l in 0..L {
        n[l] = SIMPLEX3_SCALE * (sum[l] + term(l, 3, 1, 1, 1, 3.0 * g3));
    }
}

/// [`simplex3`] with the layer keys of the skewed planes `k`, `k + 1` read from the row's
/// [`SimplexColumns`]; `false` (nothing written) when one fetch cannot reach them.
#[inline(always)]
pub(super) fn simplex3_table<const L: usize, F: Fetch<L>, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    t: &SimplexColumns,
    n: &mut [f32; L],
) -> bool {
    let at = simplex3_at(o, r, &cell_units(o, x));
    let Some(corners) = simplex3_corners::<L, F>(t, &at) else {
        return false;
    };
    simplex3_sum::<L, false>(&at, &corners, n);
    true
}

/// The corner hashes of lanes `at` from the row's table `t`: its [`SimplexCorners`] where
/// every lane's corners are in it, else the layer keys where one fetch reaches them, else
/// `None`.
#[inline(always)]
pub(super) fn simplex3_corners<'t, const L: usize, F: Fetch<L>>(
    t: &'t SimplexColumns,
    at: &Simplex3At<L>,
) -> Option<Corners3<'t, L>> {
    if F::CORNERS
        && let Some(c) = &t.corners
        && let Some(entry) = c.entries(&at.i, &at.j, &at.k)
    {
        return Some(Corners3::Table(&c.cubes, entry));
    }
    let (base, idx) = simplex_window(t, &at.k)?;
    let keys = window(&t.keys, base);
    Some(Corners3::Layers(
        F::fetch(&keys[..L], &idx),
        F::fetch(&keys[1..=L], &idx),
    ))
}

/// 3D simplex noise on the plane of the octave's `z`, in the lanes: corner `(i, j, k)`'s hash
/// is `hash3(i, j, k, o, key0)`, the layer keys of the planes hashed in the lanes.
#[inline(always)]
pub(super) fn simplex3<const L: usize, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    n: &mut [f32; L],
) {
    let at = simplex3_at(o, r, &cell_units(o, x));
    let (mut l0, mut l1) = ([0u32; L], [0u32; L]);
    for l in 0..L {
        l0[l] = plane_key(o, at.k[l]);
        l1[l] = plane_key(o, at.k[l].wrapping_add(1));
    }
    simplex3_sum::<L, false>(&at, &Corners3::Layers(l0, l1), n);
}
