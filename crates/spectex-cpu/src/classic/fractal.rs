//! The octave loop: per-octave state, the row and point loops, and the fractal sums.

use spectex_model::Window;
use spectex_model::classic::{Basis, FractalKind, Metric};
use spectex_model::filter::OctaveFade;
use spectex_model::random::row_key;

use super::lanes::{Fetch, Indexed, locate, max, min};
use super::lattice::{gradient2, gradient3, kensler, lattice};
use super::relaxed::simplex_relaxed;
use super::simplex::{simplex2, simplex2_table, simplex3};
use super::tables::RowTable;
use super::{ClassicEvaluator, GRADIENT, KENSLER, SIMPLEX, VALUE, WORLEY};

/// What one octave needs, computed once per evaluator.
#[derive(Debug, Clone)]
pub(super) struct Octave {
    /// Cell side, pixels.
    pub(super) side: f64,
    /// `1 / side` when that is exact (a power of two): `x · (1/side)` is then `x / side` bit
    /// for bit, without the division.
    pub(super) inv_side: Option<f64>,
    /// Cells per period along x and y of a periodic model, `[0, 0]` otherwise ([`lattice`]).
    pub(super) cells: [i32; 2],
    /// `gain^o`.
    pub(super) weight: f32,
    /// The octave's layer (its index).
    pub(super) layer: u32,
    /// `layer_key(o, seed)` (2D hashes).
    pub(super) key2: u32,
    /// `row_key(0, layer_key(o, seed))` (3D hashes from scratch).
    pub(super) key0: u32,
    /// `z / side` (3D).
    pub(super) pz: f64,
    /// Cell of the plane `z` and the offset in it (3D).
    pub(super) kz: i32,
    pub(super) uz: f32,
    /// `layer_key(o, cell_hash(kz + d, 0, o, seed))` for `d = −1, 0, 1` (3D).
    pub(super) zkeys: [u32; 3],
    /// Kensler noise's per-axis table entries of the plane `z`, `cell_hash(kz + d, 2, o, seed)`
    /// for `d = −1..=2` (3D; zeros in 2D, where the xor leaves the hash alone).
    pub(super) kensler_z: [u32; 4],
}

/// What one octave needs on one row.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct RowOctave {
    /// `y / side`.
    pub(super) py: f64,
    pub(super) iy: i32,
    pub(super) uy: f32,
    /// Row keys `[dz + 1][dy + 1]` of the rows `iy + dy` (2D: only `[1]` is used).
    pub(super) keys: [[u32; 3]; 3],
}

/// Where the lanes read what their octave needs along y: one row shared by every lane
/// ([`RowOctave`], a row of pixels) or one per lane ([`PointRows`], a batch of arbitrary
/// points). The lane code is generic over it, so both give each lane the same arithmetic.
pub(super) trait RowLanes {
    /// `y / side` of lane `l`.
    fn py(&self, l: usize) -> f64;
    /// The cell row of lane `l`.
    fn iy(&self, l: usize) -> i32;
    /// The offset in it.
    fn uy(&self, l: usize) -> f32;
    /// Row key `[dz + 1][dy + 1]` of lane `l` (see [`RowOctave::keys`]).
    fn key(&self, dz: usize, dy: usize, l: usize) -> u32;
}

impl RowLanes for RowOctave {
    #[inline(always)]
    fn py(&self, _: usize) -> f64 {
        self.py
    }
    #[inline(always)]
    fn iy(&self, _: usize) -> i32 {
        self.iy
    }
    #[inline(always)]
    fn uy(&self, _: usize) -> f32 {
        self.uy
    }
    #[inline(always)]
    fn key(&self, dz: usize, dy: usize, _: usize) -> u32 {
        self.keys[dz][dy]
    }
}

/// [`RowOctave`] per lane: what one octave needs at each point of a group of `L` points.
#[derive(Debug, Clone, Copy)]
pub(super) struct PointRows<const L: usize> {
    pub(super) py: [f64; L],
    pub(super) iy: [i32; L],
    pub(super) uy: [f32; L],
    /// `keys[dz + 1][dy + 1][l]`, those the basis reads ([`ClassicEvaluator::point_rows`]).
    pub(super) keys: [[[u32; L]; 3]; 3],
}

impl<const L: usize> RowLanes for PointRows<L> {
    #[inline(always)]
    fn py(&self, l: usize) -> f64 {
        self.py[l]
    }
    #[inline(always)]
    fn iy(&self, l: usize) -> i32 {
        self.iy[l]
    }
    #[inline(always)]
    fn uy(&self, l: usize) -> f32 {
        self.uy[l]
    }
    #[inline(always)]
    fn key(&self, dz: usize, dy: usize, l: usize) -> u32 {
        self.keys[dz][dy][l]
    }
}

impl ClassicEvaluator {
    pub(super) fn row_octave(&self, o: &Octave, y: f64) -> RowOctave {
        let py = y / o.side;
        let (iy, uy) = locate(py);
        let mut keys = [[0u32; 3]; 3];
        for (dz, k) in keys.iter_mut().enumerate() {
            let layer = if self.three_d { o.zkeys[dz] } else { o.key2 };
            for (dy, key) in k.iter_mut().enumerate() {
                *key = row_key(lattice(iy.wrapping_add(dy as i32 - 1), o.cells[1]), layer);
            }
        }
        RowOctave { py, iy, uy, keys }
    }

    /// One row, `L` pixels at a time; `inline(always)` so each SIMD wrapper gets its own copy.
    /// `fade`: how a minified render takes each octave (`classic_fade`), else `None`.
    /// `columns`: read lattice hashes from per-row [`Columns`] tables where the basis allows.
    /// `RELAXED`: the bench-only f32 split and FMA ([`set_relaxed`](Self::set_relaxed)).
    #[inline(always)]
    pub(super) fn row<
        const L: usize,
        F: Fetch<L>,
        const RELAXED: bool,
        const B: u8,
        const D3: bool,
    >(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        fade: Option<&OctaveFade>,
        columns: bool,
    ) {
        let width = out.len();
        let mut lane_index = [0.0f64; L];
        for (l, v) in lane_index.iter_mut().enumerate() {
            *v = l as f64;
        }
        // A plain loop, not an iterator adapter: the tables are built in this function's
        // instruction set (an adapter's `fold` is compiled apart, without AVX2).
        let mut tables: Vec<Option<RowTable>> = Vec::with_capacity(rows.len());
        if columns {
            for (o, r) in self.octaves.iter().zip(rows) {
                tables.push(self.columns::<L, B>(
                    o,
                    r,
                    window,
                    width,
                    F::CORNERS,
                    F::GRADIENT_INDEX,
                ));
            }
        }
        let mut start = 0;
        while start < width {
            // `window.x(i)` lane by lane: the integer `x0 + i` is exact in f64 either way.
            let base = (window.x0 + start as i64) as f64;
            let mut x = [0.0f64; L];
            let mut xf = [0.0f32; L];
            if RELAXED {
                // In f32 from the start, as an f32 library computes positions.
                let (offset, scale) = (window.offset[0] as f32, window.scale as f32);
                for l in 0..L {
                    xf[l] = offset + (base as f32 + l as f32) * scale;
                }
            } else {
                for l in 0..L {
                    x[l] = window.offset[0] + (base + lane_index[l]) * window.scale;
                }
            }
            let acc = self.octave_sum::<L, _, F, RELAXED, B, D3>(&x, &xf, rows, fade, &tables);
            let end = (start + L).min(width);
            if let Some(full) = out[start..end].first_chunk_mut::<L>() {
                for l in 0..L {
                    full[l] = self.mean + self.amplitude * acc[l];
                }
            } else {
                for (l, v) in out[start..end].iter_mut().enumerate() {
                    *v = self.mean + self.amplitude * acc[l];
                }
            }
            start += L;
        }
        // In the reverse of the order they were taken, so that the next row, taking the same
        // sizes in the same order, gets the same buffers back ([`scratch`] grows none).
        for t in tables.into_iter().rev().flatten() {
            t.recycle();
        }
    }

    /// The points of `points` (pixels), `L` at a time, into `out`: each lane at its own
    /// position, as lane 0 of a one-pixel window there ([`crate::point_window`]) computes it.
    #[inline(always)]
    pub(super) fn points<const L: usize>(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let mut rows = vec![
            PointRows::<L> {
                py: [0.0; L],
                iy: [0; L],
                uy: [0.0; L],
                keys: [[[0; L]; 3]; 3],
            };
            self.octaves.len()
        ];
        for (group, values) in points.chunks(L).zip(out.chunks_mut(L)) {
            // A short last group repeats its last point (lanes are independent).
            let lane = |l: usize| group[l.min(group.len() - 1)];
            let mut x = [0.0f64; L];
            let mut y = [0.0f64; L];
            for l in 0..L {
                // The one-pixel window's `x(0)` and `y(0)`: `p + 0·1`.
                let window = crate::point_window(lane(l));
                (x[l], y[l]) = (window.x(0), window.y(0));
            }
            for (r, o) in rows.iter_mut().zip(&self.octaves) {
                self.point_rows(o, &y, r);
            }
            let acc = by_basis!(
                self.octave_sum,
                [L, _, Indexed, false],
                (&x, &[0.0; L], &rows, None, &[])
            );
            for (l, v) in values.iter_mut().enumerate() {
                *v = self.mean + self.amplitude * acc[l];
            }
        }
    }

    /// [`row_octave`](Self::row_octave) for each lane's `y`.
    #[inline(always)]
    pub(super) fn point_rows<const L: usize>(
        &self,
        o: &Octave,
        y: &[f64; L],
        r: &mut PointRows<L>,
    ) {
        for l in 0..L {
            r.py[l] = y[l] / o.side;
            (r.iy[l], r.uy[l]) = locate(r.py[l]);
        }
        // Only the keys the basis reads: gradient and value noise the rows `iy` and `iy + 1`
        // (and planes `kz`, `kz + 1`), Worley every neighbour, simplex none (it hashes its own).
        let (planes, rows) = match (&self.basis, self.three_d) {
            (Basis::Simplex | Basis::Kensler, _) => (0..0, 0..0),
            (Basis::Gradient | Basis::Value, false) => (1..2, 1..3),
            (Basis::Gradient | Basis::Value, true) => (1..3, 1..3),
            (Basis::Worley(_), false) => (1..2, 0..3),
            (Basis::Worley(_), true) => (0..3, 0..3),
        };
        for dz in planes {
            let layer = if self.three_d { o.zkeys[dz] } else { o.key2 };
            for dy in rows.clone() {
                for l in 0..L {
                    let iy = lattice(r.iy[l].wrapping_add(dy as i32 - 1), o.cells[1]);
                    r.keys[dz][dy][l] = row_key(iy, layer);
                }
            }
        }
    }

    /// The octaves' fractal sum at the lanes' positions `x` along x, their rows (one per
    /// octave) along y; `fade`: how a minified render takes each octave, else `None`;
    /// `tables`: each octave's [`Columns`] of the row, where it has one (else empty).
    #[inline(always)]
    pub(super) fn octave_sum<
        const L: usize,
        R: RowLanes,
        F: Fetch<L>,
        const RELAXED: bool,
        const B: u8,
        const D3: bool,
    >(
        &self,
        x: &[f64; L],
        xf: &[f32; L],
        rows: &[R],
        fade: Option<&OctaveFade>,
        tables: &[Option<RowTable>],
    ) -> [f32; L] {
        let mut acc = [0.0f32; L];
        let mut previous = [0.0f32; L];
        for (o, (oct, ro)) in self.octaves.iter().zip(rows).enumerate() {
            let w = oct.weight;
            // A minified render's (scale, constant) of this octave.
            let faded = fade.map(|f| (f.scale[o], f.constant[o]));
            if let Some((scale, constant)) = faded
                && scale == 0.0
            {
                // Faded out: the basis is not evaluated, its expected term stays.
                match self.kind {
                    None | Some(FractalKind::Fbm) | Some(FractalKind::Turbulence) => {
                        for l in 0..L {
                            acc[l] += constant;
                        }
                    }
                    Some(FractalKind::Ridged { weight_gain, .. }) => {
                        for l in 0..L {
                            let mut s = constant;
                            if o > 0 {
                                s *= min(max(previous[l] * weight_gain, 0.0), 1.0);
                            }
                            previous[l] = s;
                            acc[l] += w * s;
                        }
                    }
                }
                continue;
            }
            let mut n = [0.0f32; L];
            let from_table = match tables.get(o).and_then(Option::as_ref) {
                Some(RowTable::Worley(t)) if B == WORLEY => {
                    self.worley_table::<L, F, R, RELAXED, D3>(oct, ro, x, xf, t, &mut n)
                }
                Some(RowTable::Simplex(t)) if B == SIMPLEX => {
                    if RELAXED && D3 {
                        F::simplex3_relaxed(oct, ro, xf, t, &mut n)
                    } else if RELAXED {
                        simplex_relaxed::<L, F, R>(oct, ro, xf, t, false, &mut n)
                    } else if D3 {
                        F::simplex3(oct, ro, x, Some(t), &mut n);
                        true
                    } else {
                        simplex2_table::<L, F, R>(oct, ro, x, t, &mut n)
                    }
                }
                Some(RowTable::Lattice(t)) if B == GRADIENT && D3 => {
                    F::lattice3::<R, true, RELAXED>(oct, ro, x, xf, t, &mut n)
                }
                Some(RowTable::Lattice(t)) if B == VALUE && D3 => {
                    F::lattice3::<R, false, RELAXED>(oct, ro, x, xf, t, &mut n)
                }
                Some(RowTable::Lattice(t)) if B == GRADIENT => {
                    Self::lattice_columns::<L, F, R, true, D3, RELAXED>(oct, ro, x, xf, t, &mut n)
                }
                Some(RowTable::Lattice(t)) if B == VALUE => {
                    Self::lattice_columns::<L, F, R, false, D3, RELAXED>(oct, ro, x, xf, t, &mut n)
                }
                None if !RELAXED && D3 && B == SIMPLEX => {
                    F::simplex3(oct, ro, x, None, &mut n);
                    true
                }
                _ => false,
            };
            if !from_table {
                n = self.basis_lanes::<L, R, B, D3>(oct, ro, x);
            }
            match (self.kind, faded) {
                (None | Some(FractalKind::Fbm), None) => F::accumulate(&mut acc, w, &n),
                (None | Some(FractalKind::Fbm), Some((scale, constant))) => {
                    for l in 0..L {
                        acc[l] += scale * n[l] + constant;
                    }
                }
                (Some(FractalKind::Turbulence), None) => {
                    for l in 0..L {
                        acc[l] += w * n[l].abs();
                    }
                }
                (Some(FractalKind::Turbulence), Some((scale, constant))) => {
                    for l in 0..L {
                        acc[l] += scale * n[l].abs() + constant;
                    }
                }
                (
                    Some(FractalKind::Ridged {
                        offset,
                        weight_gain,
                    }),
                    faded,
                ) => {
                    for l in 0..L {
                        let s = offset - n[l].abs();
                        let mut s = s * s;
                        if let Some((scale, constant)) = faded {
                            s = scale * s + constant;
                        }
                        if o > 0 {
                            s *= min(max(previous[l] * weight_gain, 0.0), 1.0);
                        }
                        previous[l] = s;
                        acc[l] += w * s;
                    }
                }
            }
        }
        acc
    }

    #[inline(always)]
    pub(super) fn basis_lanes<const L: usize, R: RowLanes, const B: u8, const D3: bool>(
        &self,
        o: &Octave,
        r: &R,
        x: &[f64; L],
    ) -> [f32; L] {
        let mut n = [0.0f32; L];
        match (B, D3) {
            (GRADIENT, false) => gradient2(o, r, x, &mut n, true),
            (VALUE, false) => gradient2(o, r, x, &mut n, false),
            (GRADIENT, true) => gradient3(o, r, x, &mut n, true),
            (VALUE, true) => gradient3(o, r, x, &mut n, false),
            (SIMPLEX, false) => simplex2(o, r, x, &mut n),
            (SIMPLEX, true) => simplex3(o, r, x, &mut n),
            (KENSLER, three_d) => kensler(o, r, x, &mut n, three_d),
            (_, three_d) => {
                if let Some(w) = &self.worley {
                    // Metric and dimension as constants, so each inner loop is one straight
                    // vectorisable body.
                    match (w.metric, three_d) {
                        (Metric::Euclidean, false) => {
                            self.worley_lanes::<L, false, 0, R>(w, o, r, x, &mut n)
                        }
                        (Metric::Manhattan, false) => {
                            self.worley_lanes::<L, false, 1, R>(w, o, r, x, &mut n)
                        }
                        (Metric::Chebyshev, false) => {
                            self.worley_lanes::<L, false, 2, R>(w, o, r, x, &mut n)
                        }
                        (Metric::Euclidean, true) => {
                            self.worley_lanes::<L, true, 0, R>(w, o, r, x, &mut n)
                        }
                        (Metric::Manhattan, true) => {
                            self.worley_lanes::<L, true, 1, R>(w, o, r, x, &mut n)
                        }
                        (Metric::Chebyshev, true) => {
                            self.worley_lanes::<L, true, 2, R>(w, o, r, x, &mut n)
                        }
                    }
                }
            }
        }
        n
    }
}
