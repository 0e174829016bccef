//! The classic pointwise noises (gradient, simplex, value, Kensler, Worley) and their fractal sums
//! on the CPU; the definitions and the randomness contract are in [`spectex_model::classic`].
//! Kensler noise's 4×4 (4×4×4) stencil runs one lane at a time (`kensler`: no per-row tables).
//!
//! Every pixel is independent: a row is evaluated `L` consecutive pixels at a time (8 lanes, or
//! 16 or 32 with AVX-512: `ClassicEvaluator::avx512_lanes`; 3D gradient, value and simplex
//! noise through the hand-written kernels of `avx512`), the basis and dimension as constants of
//! the row loop, every octave of a group of lanes before the next group, with the lattice
//! hashes computed in the lanes (wrapping `u32` arithmetic vectorises). Positions are built per
//! lane in f64 exactly as [`Window::x`] builds them, divided by the octave's cell side and split
//! into an `i32` cell and an f32 offset by the round-to-nearest magic constant (two exact IEEE
//! operations, no `floor` library call, so the portable build vectorises too). All f32 arithmetic
//! is plain `*`, `+`, `sqrt`, selects and sign-bit flips, so the AVX2, AVX-512 and portable copies
//! of the row give the same bits, and any tiling of a window gives the same bits (a pixel never
//! depends on its neighbours).
//!
//! What depends only on a lattice column of a row is computed once per row and octave, in
//! tables the lanes read by column (a register permute with AVX2 and AVX-512): gradient and value
//! noise's corners (the gradient's dot product folded into a mask, a sign and a constant), simplex
//! noise's keys of its skewed rows (planes), Worley noise's feature points for a fixed count. A
//! row of cells 32 pixels wide then hashes each cell once instead of once per pixel; the tables
//! hold the very integers and floats the lanes would compute, so the bits do not change, and
//! [`ClassicEvaluator::eval_rows_reference`] keeps the per-pixel path they are tested against.
//! Gradient and value octaves with cells under a pixel (a table would be longer than the row),
//! simplex and Worley octaves with cells under 2 pixels, Poisson counts and batches of points
//! hash in the lanes. Lane code is written as one simple loop per step over arrays of `L`
//! lanes, so that the compiler vectorises each step at the full width.
//!
//! A row's tables live in buffers this thread reuses from row to row (a table of one-pixel
//! cells is as long as the row). A bench-only relaxed evaluator
//! ([`ClassicEvaluator::set_relaxed`], which no model selects) splits positions in f32 and
//! fuses multiply-adds, to measure what those two guarantees cost.
//!
//! A minified render (a window with a [`footprint`](Window::footprint)) fades each octave as
//! [`spectex_model::filter::classic_fade`] says (turbulence and ridged toward their expected
//! values, fBm of Worley distances toward their mean) and skips the basis of the octaves faded
//! to 0.
//!
//! Worley noise evaluates the 3×3 (3×3×3) cells around the point in the lanes and keeps the
//! four smallest distances with a min/max insertion network; a lane whose needed `F_n` exceeds
//! the distance to the unsearched cells is redone by `worley_search`, which searches ring after
//! ring with the same arithmetic (the four smallest of a set do not depend on the visiting order,
//! so both paths agree bit for bit wherever the 3×3 search suffices).
//!
//! ```
//! use spectex_cpu::classic::ClassicEvaluator;
//! use spectex_model::classic::{Basis, ClassicNoise};
//!
//! let model = ClassicNoise {
//!     seed: 1,
//!     dimensions: 2,
//!     cell_size: 16.0,
//!     basis: Basis::Gradient,
//!     fractal: None,
//!     amplitude: 1.0,
//!     mean: 0.0,
//! };
//! model.validate()?;
//! let eval = ClassicEvaluator::new(&model, 0.0);
//! // Gradient noise vanishes at lattice points.
//! assert_eq!(eval.eval(48.0, -16.0), 0.0);
//! # Ok::<(), spectex_model::ModelError>(())
//! ```

use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, FractalKind, KENSLER2_SCALE, KENSLER3_SCALE, Metric,
    SIMPLEX_F2, SIMPLEX_F3, SIMPLEX_G2, SIMPLEX_G3, SIMPLEX2_R2, SIMPLEX2_SCALE, SIMPLEX3_R2,
    SIMPLEX3_SCALE, WORLEY_MAX_POINTS, WORLEY_MAX_RING, fade, gradient_dot, kensler_dot,
    kensler_weight, lattice_value,
};
use spectex_model::filter::{BasisStatistics, OctaveFade};
use spectex_model::random::{
    cell_hash, cell_hash_in_row, layer_key, lcg_step, permute, row_key, unit_f32,
};
use spectex_model::{Period, Window};

use crate::lrp::Simd;

#[cfg(target_arch = "x86_64")]
mod avx512;

/// Pixels evaluated together by the portable and AVX2 paths.
const LANES: usize = 8;
/// Pixels of one AVX-512 register.
const WIDE_LANES: usize = 16;
/// Pixels evaluated together by the AVX-512 row: two registers per step, so that two
/// independent chains of lerps overlap (one register's chain left the core waiting).
const WIDER_LANES: usize = 32;
/// Entries of a [`Columns`] table the lanes read at once (at least `WIDER_LANES + 1`), and the
/// padding after its columns.
const WINDOW: usize = 64;

/// `1.5·2⁵²`: `(p + M) − M` rounds an f64 of magnitude below 2⁵¹ to the nearest integer, and
/// the low 32 bits of `p + M` are that integer in two's complement.
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;

/// `(⌊p⌋ as i32, ⌊p⌋)` for `|p| < 2³¹`, without a `floor` call (the same value as `f64::floor`).
#[inline(always)]
fn split(p: f64) -> (i32, f64) {
    let m = p + ROUND_MAGIC;
    let r = m - ROUND_MAGIC;
    let above = r > p;
    let i = (m.to_bits() as u32 as i32).wrapping_sub(i32::from(above));
    (i, if above { r - 1.0 } else { r })
}

/// Cell and f32 offset of `p` (cell units).
#[inline(always)]
fn locate(p: f64) -> (i32, f32) {
    let (i, f) = split(p);
    (i, (p - f) as f32)
}

/// [`locate`] in the lanes, written as one simple loop per step so that it vectorises (the
/// same operations, so the same bits).
#[inline(always)]
fn locate_lanes<const L: usize>(p: &[f64; L], ix: &mut [i32; L], ux: &mut [f32; L]) {
    let mut m = [0.0f64; L];
    for l in 0..L {
        m[l] = p[l] + ROUND_MAGIC;
    }
    let mut f = [0.0f64; L];
    for l in 0..L {
        let r = m[l] - ROUND_MAGIC;
        f[l] = if r > p[l] { r - 1.0 } else { r };
    }
    floor_cells(&f, ix);
    for l in 0..L {
        ux[l] = (p[l] - f[l]) as f32;
    }
}

#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a < b { b } else { a }
}

/// `cell_hash(i, j, o, cell_hash(k, 0, o, seed))` from `key0 = row_key(0, layer_key(o, seed))`.
#[inline(always)]
fn hash3(i: i32, j: i32, k: i32, o: u32, key0: u32) -> u32 {
    let seed3 = cell_hash_in_row(k, key0);
    cell_hash_in_row(i, row_key(j, layer_key(o, seed3)))
}

/// Lattice coordinate `v` as it enters the hash: wrapped into `0..n` for a periodic octave with
/// `n` cells per period (`spectex_model::period::wrap`), unchanged for `n = 0` (not periodic).
#[inline(always)]
fn lattice(v: i32, n: i32) -> i32 {
    if n == 0 { v } else { v.rem_euclid(n) }
}

/// What one octave needs, computed once per evaluator.
#[derive(Debug, Clone)]
struct Octave {
    /// Cell side, pixels.
    side: f64,
    /// `1 / side` when that is exact (a power of two): `x · (1/side)` is then `x / side` bit
    /// for bit, without the division.
    inv_side: Option<f64>,
    /// Cells per period along x and y of a periodic model, `[0, 0]` otherwise ([`lattice`]).
    cells: [i32; 2],
    /// `gain^o`.
    weight: f32,
    /// The octave's layer (its index).
    layer: u32,
    /// `layer_key(o, seed)` (2D hashes).
    key2: u32,
    /// `row_key(0, layer_key(o, seed))` (3D hashes from scratch).
    key0: u32,
    /// `z / side` (3D).
    pz: f64,
    /// Cell of the plane `z` and the offset in it (3D).
    kz: i32,
    uz: f32,
    /// `layer_key(o, cell_hash(kz + d, 0, o, seed))` for `d = −1, 0, 1` (3D).
    zkeys: [u32; 3],
    /// Kensler noise's per-axis table entries of the plane `z`, `cell_hash(kz + d, 2, o, seed)`
    /// for `d = −1..=2` (3D; zeros in 2D, where the xor leaves the hash alone).
    kensler_z: [u32; 4],
}

/// What one octave needs on one row.
#[derive(Debug, Clone, Copy, Default)]
struct RowOctave {
    /// `y / side`.
    py: f64,
    iy: i32,
    uy: f32,
    /// Row keys `[dz + 1][dy + 1]` of the rows `iy + dy` (2D: only `[1]` is used).
    keys: [[u32; 3]; 3],
}

/// Where the lanes read what their octave needs along y: one row shared by every lane
/// ([`RowOctave`], a row of pixels) or one per lane ([`PointRows`], a batch of arbitrary
/// points). The lane code is generic over it, so both give each lane the same arithmetic.
trait RowLanes {
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
struct PointRows<const L: usize> {
    py: [f64; L],
    iy: [i32; L],
    uy: [f32; L],
    /// `keys[dz + 1][dy + 1][l]`, those the basis reads ([`ClassicEvaluator::point_rows`]).
    keys: [[[u32; L]; 3]; 3],
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

/// The Worley parameters in the form the lanes use.
#[derive(Debug, Clone)]
struct WorleyParams {
    metric: Metric,
    coefficients: [f32; 4],
    /// Fixed count, or `None` for a Poisson count.
    fixed: Option<u32>,
    cdf: [f32; WORLEY_MAX_POINTS as usize],
    /// `n` of the largest needed `F_n`, minus one.
    needed: usize,
    /// Largest distance kept (squared for the Euclidean metric).
    cap: f32,
}

/// What the lattice corners of one octave contribute along one row, for the lattice columns
/// the row's lanes visit. Entry `p·len + c` belongs to column `lo + c` in row key `p` (the rows
/// `iy`, `iy + 1` times, in 3D, the planes `kz`, `kz + 1`, as `p = 2·dz + dy`), whose corner
/// hash is `h = cell_hash_in_row(lo + c, key_p)`. A row of cells 32 pixels wide hashes each
/// corner once instead of once per pixel, and the lanes fetch the entries by column ([`Fetch`]).
///
/// Value noise stores `lattice_value(h)`. Gradient noise stores `gradient_dot(h, X, Y, Z)` with
/// the row's constants `Y = uy − dy`, `Z = uz − dz` folded in, as the bits of
/// `((X & mask) ^ sign) + constant`: `gradient_dot` is `u' + v'`, two coordinates with their
/// sign bits flipped by `h`; when one of them is `X`, `mask` keeps it, `sign` flips it and
/// `constant` is the other (IEEE addition commutes, so the order of `u' + v'` does not
/// matter); when neither is, `mask` is 0 and `constant` the whole sum, with `sign` giving the
/// `±0` that leaves it unchanged (`−0 + −0 = −0`). Every value is bit for bit the one the lanes
/// compute from the hash.
#[derive(Debug, Clone)]
struct Columns {
    /// The first column.
    lo: i32,
    /// Entries per row key: the columns `lo..=hi + 1`, then [`WINDOW`] of padding so that the
    /// window of entries a group of lanes reads is in the table.
    len: usize,
    /// Gradient noise: all ones where the corner's sum takes `X`, else 0 (empty for value
    /// noise).
    mask: Vec<u32>,
    /// Gradient noise: the sign bit flipping `X` (or the zero's sign, see above).
    sign: Vec<u32>,
    /// The f32 bits of the constant term (value noise: the lattice value); with `terms`, the
    /// corner's gradient index `g = h >> 28` instead.
    constant: Vec<u32>,
    /// 3D gradient noise read by gradient index ([`Fetch::GRADIENT_INDEX`]): `[mask, sign,
    /// constant]` of each `g` for each row key, `mask` and `sign` empty. A row's entries then
    /// are the kept hashes shifted (no `gradient_terms` per column, 22% of a 3D fBm's time
    /// with cells down to a pixel), and the lanes read their terms by a second permute.
    terms: Option<Box<GradientTerms>>,
}

/// `[mask, sign, constant]` of [`gradient_terms`] for each gradient index `g < 16`, of each of
/// the four row keys of a 3D row.
type GradientTerms = [[[u32; 16]; 3]; 4];

/// The lattice corners of row key `p` at columns `ix` and `ix + 1` of each lane (`ix` is the
/// column `lo + base + idx[l]`) from the [`Columns`] `t`; `ux`: the lanes' offsets in their
/// cells. `GRADIENT`: gradient noise, else value noise.
#[inline(always)]
fn corners<const L: usize, F: Fetch<L>, const GRADIENT: bool>(
    t: &Columns,
    p: usize,
    base: usize,
    idx: &[u32; L],
    ux: &[f32; L],
) -> [[f32; L]; 2] {
    // Called by name, not through a function pointer: each fetch inlines into the SIMD copy
    // of the row (a pointer was a call per fetch, the permute's target feature lost behind it).
    let fetch = F::fetch;
    // The entries the two fetches read (`L + 1 ≤ WINDOW`), as arrays: one bounds check each.
    let at = p * t.len + base;
    let constant = window(&t.constant, at);
    let mut out = [[0.0f32; L]; 2];
    if GRADIENT {
        let (mask, sign) = (window(&t.mask, at), window(&t.sign, at));
        for (dx, corner) in out.iter_mut().enumerate() {
            let c = fetch(&constant[dx..dx + L], idx);
            let m = fetch(&mask[dx..dx + L], idx);
            let s = fetch(&sign[dx..dx + L], idx);
            for l in 0..L {
                let x = ux[l] - dx as f32;
                corner[l] = f32::from_bits((x.to_bits() & m[l]) ^ s[l]) + f32::from_bits(c[l]);
            }
        }
    } else {
        for (dx, corner) in out.iter_mut().enumerate() {
            let c = fetch(&constant[dx..dx + L], idx);
            for l in 0..L {
                corner[l] = f32::from_bits(c[l]);
            }
        }
    }
    out
}

/// `cell_hash_in_row(lattice(lo + c, cells), key)` of the columns `c` of `out`, in a loop
/// that vectorises (the wrap of a periodic octave is hoisted out of it).
#[inline(always)]
fn column_hashes(lo: i32, cells: i32, key: u32, out: &mut [u32]) {
    if cells == 0 {
        for (c, h) in out.iter_mut().enumerate() {
            *h = cell_hash_in_row(lo.wrapping_add(c as i32), key);
        }
    } else {
        for (c, h) in out.iter_mut().enumerate() {
            *h = cell_hash_in_row(lattice(lo.wrapping_add(c as i32), cells), key);
        }
    }
}

/// The [`WINDOW`] entries of `table` from `at`.
#[inline(always)]
fn window(table: &[u32], at: usize) -> &[u32; WINDOW] {
    <&[u32; WINDOW]>::try_from(&table[at..at + WINDOW]).expect("a slice of WINDOW entries")
}

/// The feature points of one Worley octave with a fixed count along one row, for the lattice
/// columns `lo..` the row's 3×3 (×3) searches visit: entry `(q·keys + p)·len + c` of
/// `offsets[axis]` holds the f32 bits of point `q`'s offset along `axis` in column `lo + c` of
/// row key `p` (`p = 3·(dz + 1) + dy + 1`; 2D: `dy + 1`), drawn from the PRNG seeded with the
/// cell's hash exactly as the lanes draw them, so the lanes read the same floats instead of
/// hashing 9 (27) cells per pixel.
#[derive(Debug, Clone)]
struct WorleyColumns {
    /// The first column (one left of the row's first cell).
    lo: i32,
    /// Entries per (point, row key): the columns, then [`WINDOW`] of padding.
    len: usize,
    /// Row keys per point: 3 (2D) or 9 (3D).
    keys: usize,
    /// Offsets along x, y, z (z empty in 2D).
    offsets: [Vec<u32>; 3],
}

/// The keys of simplex noise's skewed lattice along one row, for the skewed rows `lo..` its
/// lanes visit: 2D, `row_key(j, layer_key(o, seed))` of skewed row `j`; 3D, the layer key
/// `layer_key(o, cell_hash(k, 0, o, seed))` of skewed plane `k`. The lanes fetch those of `j`
/// (`k`) and `j + 1` (`k + 1`) instead of hashing them for every corner.
#[derive(Debug, Clone)]
struct SimplexColumns {
    /// The first skewed row (plane).
    lo: i32,
    /// Entries: the rows, then [`WINDOW`] of padding.
    len: usize,
    keys: Vec<u32>,
    /// 3D, cells wide enough: every corner's hash, read instead of the two hashes per corner
    /// that remain with the layer keys (`keys` is then empty, `len` 0).
    corners: Option<SimplexCorners>,
    /// Whether every skewed coordinate of the row's lanes is below 2⁴⁸ in magnitude, where a
    /// floor instruction gives [`split`]'s floors (the AVX-512 kernel's `floor_pair`).
    bounded: bool,
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
struct SimplexCorners {
    /// The octave's layer and `key0`: the table's hashes are a function of them and of
    /// `j_lo`, `d_lo`, `e_lo`.
    layer: u32,
    key0: u32,
    /// The first skewed row `j_lo`, the lowest `d_lo = k − j` and `e_lo = i − 4j`.
    j_lo: i32,
    d_lo: i32,
    e_lo: i32,
    /// Skewed rows `j_lo..j_lo + rows` of entries.
    rows: u32,
    /// The cubes' packed codes, by entry (those a lane can read: see above).
    cubes: Vec<u32>,
}

thread_local! {
    /// The [`SimplexCorners`] of this thread's last rows: rows a few pixels apart share their
    /// skewed rows, `d_lo` and `e_lo`, and building the table cost about 3–6% of a 3D simplex
    /// row.
    static KEPT_CORNERS: std::cell::RefCell<Vec<SimplexCorners>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// [`SimplexCorners`] tables [`KEPT_CORNERS`] keeps at most.
const KEPT_CORNER_TABLES: usize = 16;

/// The layer key of 3D simplex noise's skewed plane `k` in octave `o`, from which its rows'
/// keys and corners' hashes follow (`avx512::layer_key` in the lanes).
#[inline(always)]
fn plane_key(o: &Octave, k: i32) -> u32 {
    layer_key(o.layer, cell_hash_in_row(k, o.key0))
}

/// Values of `e = i − 4j` per `(j', d')` in [`SimplexCorners`]: one register of 16.
const CORNER_E: u32 = 16;
/// Values of `d = k − j` per `j'` in [`SimplexCorners`].
const CORNER_D: u32 = 4;
/// What a step of `i`, `j`, `k` adds to a [`SimplexCorners`] entry: `e + 1`; `j + 1`, `d − 1`,
/// `e − 4`; `d + 1`.
const CORNER_STEP: [u32; 3] = [1, CORNER_D * CORNER_E - CORNER_E - 4, CORNER_E];

/// How far corner `c = di + 2dj + 4dk` of a [`SimplexCorners`] entry's cube is from the entry:
/// [`CORNER_STEP`]` · (di, dj, dk)`.
const CUBE_CORNERS: [usize; 8] = {
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
    fn for_row(o: &Octave, py: f64, j_lo: i32, j_hi: i32, most: usize) -> Option<Self> {
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
    fn keep(self) {
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
    fn new(o: &Octave, d_lo: i32, e_lo: i32, j_lo: i32, j_hi: i32, most: usize) -> Option<Self> {
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
    fn entries<const L: usize>(
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

/// A row's table for one octave: lattice corners, Worley feature points or simplex keys.
#[derive(Debug, Clone)]
enum RowTable {
    Lattice(Columns),
    Worley(WorleyColumns),
    Simplex(SimplexColumns),
}

thread_local! {
    /// Buffers of the tables of the rows this thread evaluated before: a table of cells of
    /// one pixel is as long as its row, and allocating it afresh for each row (zeroed pages
    /// from the system) cost about a sixth of a 3D fBm's time.
    static BUFFERS: std::cell::RefCell<Vec<Vec<u32>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Buffers [`BUFFERS`] keeps at most (a row's tables: up to 3 per octave).
const KEPT_BUFFERS: usize = 64;

/// `size` zeros in a buffer of an earlier row where this thread has one.
fn buffer(size: usize) -> Vec<u32> {
    let mut v = scratch(size);
    v.fill(0);
    v
}

/// `size` entries of unspecified values (an earlier row's, or zeros) in a buffer of an earlier
/// row where this thread has one, for a table whose builder writes every entry it reads:
/// zeroing a row's tables first cost 8% of a 3D fBm's time.
fn scratch(size: usize) -> Vec<u32> {
    // Growing a buffer zeroes its new entries only; a row gives its buffers back in reverse,
    // so the next row's tables get the buffers of the same sizes.
    let mut v = BUFFERS.with(|b| b.borrow_mut().pop()).unwrap_or_default();
    v.resize(size, 0);
    v
}

thread_local! {
    /// The column hashes of the row keys this thread's last rows used ([`KeptHashes`]).
    static KEPT: std::cell::RefCell<KeptHashes> = std::cell::RefCell::new(KeptHashes::default());
}

/// Row keys whose column hashes [`KEPT`] keeps at most (direct-mapped by the key's low bits).
const KEPT_KEYS: usize = 64;
/// Columns of the rows whose hashes [`KEPT`] keeps at most (a thread keeps at most 4 MiB);
/// longer rows hash their columns for each row.
const KEPT_COLUMNS: usize = 1 << 14;

/// The [`column_hashes`] of the row keys of this thread's last rows, by row key, first column
/// and period: rows in one cell share their row keys, and a row's `j + 1` (`k + 1`) is the next
/// cell's `j` (`k`), so a 3D fBm's rows hashed most of their columns again (a pure function of
/// the three, so a kept entry is the very hashes).
#[derive(Debug, Default)]
struct KeptHashes {
    /// `(key, lo, cells)` of each entry ([`KEPT_KEYS`] once used).
    ids: Vec<Option<(u32, i32, i32)>>,
    hashes: Vec<Vec<u32>>,
    /// The hashes of a row longer than [`KEPT_COLUMNS`], not kept.
    spare: Vec<u32>,
}

impl KeptHashes {
    /// `column_hashes(lo, cells, key)` of `count` columns, kept or computed.
    #[inline(always)]
    fn get(&mut self, lo: i32, cells: i32, key: u32, count: usize) -> &[u32] {
        if count > KEPT_COLUMNS {
            self.spare.resize(count, 0);
            column_hashes(lo, cells, key, &mut self.spare);
            return &self.spare;
        }
        if self.ids.is_empty() {
            self.ids = vec![None; KEPT_KEYS];
            self.hashes = vec![Vec::new(); KEPT_KEYS];
        }
        // One entry per key's low bits (a row key is a hash): a lookup is one comparison, where
        // a search of every entry cost rows of 256 pixels a fifth of their time.
        let id = (key, lo, cells);
        let e = (key ^ lo as u32 ^ (cells as u32).wrapping_mul(0x9E37_79B9)) as usize % KEPT_KEYS;
        let v = &mut self.hashes[e];
        if self.ids[e] != Some(id) || v.len() < count {
            self.ids[e] = Some(id);
            v.resize(count, 0);
            column_hashes(lo, cells, key, v);
        }
        &v[..count]
    }
}

/// Gives `v` back for a later row's [`buffer`].
fn recycle(v: Vec<u32>) {
    if v.capacity() > 0 {
        BUFFERS.with(|b| {
            let mut b = b.borrow_mut();
            if b.len() < KEPT_BUFFERS {
                b.push(v);
            }
        });
    }
}

impl RowTable {
    /// Gives the table's buffers back ([`recycle`]), the last taken first.
    fn recycle(self) {
        match self {
            Self::Lattice(c) => {
                recycle(c.constant);
                recycle(c.sign);
                recycle(c.mask);
            }
            Self::Worley(w) => {
                for v in w.offsets.into_iter().rev() {
                    recycle(v);
                }
            }
            Self::Simplex(t) => {
                if let Some(c) = t.corners {
                    c.keep();
                }
                recycle(t.keys);
            }
        }
    }
}

/// `(mask, sign, constant bits)` of [`Columns`] for corner hash `h` and the row constants
/// `y`, `z`: `f32::from_bits((x.to_bits() & mask) ^ sign) + f32::from_bits(constant)` is
/// `gradient_dot(h, x, y, z)` for every `x`.
#[inline(always)]
fn gradient_terms(h: u32, y: f32, z: f32) -> (u32, u32, u32) {
    // Selects only, so that a row's table is built in the lanes.
    let g = h >> 28;
    let flip = |v: f32, bit: u32| f32::from_bits(v.to_bits() ^ bit);
    let (s1, s2) = ((g & 1) << 31, (g & 2) << 30);
    let x_first = g < 8; // u = x, v = y (g < 4) or z
    let x_second = g == 12 || g == 14; // u = y, v = x
    let first = flip(if g < 4 { y } else { z }, s2).to_bits();
    let second = flip(y, s1).to_bits();
    // u = y, v = z: no x.
    let k = (flip(y, s1) + flip(z, s2)).to_bits();
    let mask = if x_first || x_second { u32::MAX } else { 0 };
    let sign = if x_first {
        s1
    } else if x_second {
        s2
    } else {
        k & (1 << 31)
    };
    let constant = if x_first {
        first
    } else if x_second {
        second
    } else {
        k
    };
    (mask, sign, constant)
}

/// The gradient of 3D simplex corner hash `h` as [`SimplexCorners`] keeps it, so that the
/// lanes select it in fewer steps: `gradient_dot(h, x, y, z)` is `±u ± v` with `(u, v)` one of
/// `(x, y)`, `(x, z)`, `(y, z)` (`g = h >> 28` of 12 and 14 give `±y ± x`, the same sum: IEEE
/// addition commutes, signed zeros included). Bit 29: `u` is `y`; bit 28: `v` is `z`; bit 31:
/// `u`'s sign flips; bit 30: `v`'s ([`coded_gradient_dot`]).
#[inline(always)]
fn gradient_code(h: u32) -> u32 {
    let g = h >> 28;
    let (s1, s2) = ((g & 1) << 31, (g & 2) << 29);
    if g == 12 || g == 14 {
        // `flip(y, g & 1) + flip(x, g & 2)` as `flip(x, g & 2) + flip(y, g & 1)`.
        return ((g & 2) << 30) | ((g & 1) << 30);
    }
    let u_is_y = u32::from(g >= 8) << 29;
    let v_is_z = u32::from(g >= 4) << 28;
    s1 | s2 | u_is_y | v_is_z
}

/// `gradient_dot(h, x, y, z)` from `gradient_code(h)`.
#[inline(always)]
fn coded_gradient_dot(c: u32, x: f32, y: f32, z: f32) -> f32 {
    let u = if c & (1 << 29) != 0 { y } else { x };
    let v = if c & (1 << 28) != 0 { z } else { y };
    let u = f32::from_bits(u.to_bits() ^ (c & (1 << 31)));
    let v = f32::from_bits(v.to_bits() ^ ((c << 1) & (1 << 31)));
    u + v
}

/// How a group of `L` lanes reads `window[idx[l]]` (`idx[l] < L`, `window.len() ≥ L`): by
/// index in the portable build, by one register permute with AVX2 or AVX-512. All three give
/// the same integers; only the instructions differ.
trait Fetch<const L: usize> {
    fn fetch(window: &[u32], idx: &[u32; L]) -> [u32; L];

    /// Whether 3D simplex noise's lanes read their corners' gradients from the row's
    /// [`SimplexCorners`] (a gather of each lane's cube) rather than hash them from the layer
    /// keys: not with AVX2, whose 8-lane gathers lose to the hashes (70 against 78 Mpix/s on a
    /// 1024² slice of cells of 32 pixels, one thread; 50 against 81 with a gather per corner).
    const CORNERS: bool = true;

    /// Whether 3D gradient noise's [`Columns`] hold gradient indices and their
    /// [`GradientTerms`] (read by the AVX-512 kernel) rather than each column's terms.
    const GRADIENT_INDEX: bool = false;

    /// `acc[l] += w * n[l]`: a product, then a sum (never fused), in every copy.
    #[inline(always)]
    fn accumulate(acc: &mut [f32; L], w: f32, n: &[f32; L]) {
        for l in 0..L {
            acc[l] += w * n[l];
        }
    }

    /// 3D simplex noise of the lanes: [`simplex3_table`] where the row has a table `t` and
    /// one fetch reaches the lanes' planes, else [`simplex3`].
    #[inline(always)]
    fn simplex3<R: RowLanes>(
        o: &Octave,
        r: &R,
        x: &[f64; L],
        t: Option<&SimplexColumns>,
        n: &mut [f32; L],
    ) where
        Self: Sized,
    {
        if !t.is_some_and(|t| simplex3_table::<L, Self, R>(o, r, x, t, n)) {
            simplex3(o, r, x, n);
        }
    }

    /// The relaxed path's 3D simplex noise of the lanes ([`simplex_relaxed`]); `false`
    /// (nothing written) where the row's table cannot serve them.
    #[inline(always)]
    fn simplex3_relaxed<R: RowLanes>(
        o: &Octave,
        r: &R,
        xf: &[f32; L],
        t: &SimplexColumns,
        n: &mut [f32; L],
    ) -> bool
    where
        Self: Sized,
    {
        simplex_relaxed::<L, Self, R>(o, r, xf, t, true, n)
    }

    /// 3D gradient (`GRADIENT`) or value noise of the lanes from the row's table `t`
    /// ([`ClassicEvaluator::lattice_columns`], `RELAXED` as there); `false` (nothing written)
    /// where one fetch cannot reach the lanes' columns.
    #[inline(always)]
    fn lattice3<R: RowLanes, const GRADIENT: bool, const RELAXED: bool>(
        o: &Octave,
        r: &R,
        x: &[f64; L],
        xf: &[f32; L],
        t: &Columns,
        n: &mut [f32; L],
    ) -> bool
    where
        Self: Sized,
    {
        ClassicEvaluator::lattice_columns::<L, Self, R, GRADIENT, true, RELAXED>(o, r, x, xf, t, n)
    }
}

/// [`Fetch`] by indexing.
struct Indexed;

impl<const L: usize> Fetch<L> for Indexed {
    #[inline(always)]
    fn fetch(window: &[u32], idx: &[u32; L]) -> [u32; L] {
        std::array::from_fn(|l| window[idx[l] as usize % L])
    }
}

/// [`Fetch`] by `vpermd` (AVX2, 8 lanes).
#[cfg(target_arch = "x86_64")]
struct Permute8;

#[cfg(target_arch = "x86_64")]
impl Fetch<LANES> for Permute8 {
    const CORNERS: bool = false;

    #[inline(always)]
    fn fetch(window: &[u32], idx: &[u32; LANES]) -> [u32; LANES] {
        #[allow(unsafe_code)]
        // SAFETY: `Permute8` is used only by `row_avx2`, which runs only when the CPU reports
        // AVX2 at run time.
        unsafe {
            permute8(window, idx)
        }
    }
}

/// `window[idx[l] % 8]` by one `vpermd`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn permute8(window: &[u32], idx: &[u32; LANES]) -> [u32; LANES] {
    use std::arch::x86_64::{__m256i, _mm256_loadu_si256, _mm256_permutevar8x32_epi32};
    let window = &window[..LANES];
    #[allow(unsafe_code)]
    // SAFETY: both loads read 8 `u32` (32 bytes) from slices of at least that length
    // (unaligned loads), and `__m256i` and `[u32; 8]` have the same size, every bit pattern
    // valid for both.
    unsafe {
        let t = _mm256_loadu_si256(window.as_ptr().cast::<__m256i>());
        let i = _mm256_loadu_si256(idx.as_ptr().cast::<__m256i>());
        std::mem::transmute::<__m256i, [u32; LANES]>(_mm256_permutevar8x32_epi32(t, i))
    }
}

/// A [`Fetch`] of the AVX-512 row: `$name` reads `$lanes` lanes with `$permute` and accumulates
/// with [`accumulate512`]; used only by `row_avx512` and `row_relaxed_avx512`, which run only
/// when the CPU reports AVX-512F at run time.
macro_rules! avx512_fetch {
    ($(#[$doc:meta])* $name:ident, $lanes:ident, $permute:ident $(, $kernels:item)*) => {
        $(#[$doc])*
        #[cfg(target_arch = "x86_64")]
        struct $name;

        #[cfg(target_arch = "x86_64")]
        impl Fetch<$lanes> for $name {
            #[inline(always)]
            fn fetch(window: &[u32], idx: &[u32; $lanes]) -> [u32; $lanes] {
                #[allow(unsafe_code)]
                // SAFETY: used only by the AVX-512 row (the macro's doc).
                unsafe {
                    $permute(window, idx)
                }
            }

            #[inline(always)]
            fn accumulate(acc: &mut [f32; $lanes], w: f32, n: &[f32; $lanes]) {
                #[allow(unsafe_code)]
                // SAFETY: as for `fetch`.
                unsafe {
                    accumulate512(acc, w, n);
                }
            }

            $($kernels)*
        }
    };
}

avx512_fetch!(
    /// [`Fetch`] by `vpermd` (AVX-512 row of 3D Kensler and Worley noise, 16 lanes).
    Permute16,
    WIDE_LANES,
    permute16
);
avx512_fetch!(
    /// [`Fetch`] by two-source `vpermt2d` (AVX-512 row of 2D noise and of the 3D kernels of
    /// `avx512`, 32 lanes: two registers).
    Permute32,
    WIDER_LANES,
    permute32,
    const GRADIENT_INDEX: bool = true;,
    #[inline(always)]
    fn simplex3<R: RowLanes>(
        o: &Octave,
        r: &R,
        x: &[f64; WIDER_LANES],
        t: Option<&SimplexColumns>,
        n: &mut [f32; WIDER_LANES],
    ) {
        #[allow(unsafe_code)]
        // SAFETY: as for `fetch`.
        unsafe {
            avx512::simplex3::<2, R, false>(o, r, registers(x), &[[0.0; 16]; 2], t, registers_mut(n));
        }
    },
    #[inline(always)]
    fn simplex3_relaxed<R: RowLanes>(
        o: &Octave,
        r: &R,
        xf: &[f32; WIDER_LANES],
        t: &SimplexColumns,
        n: &mut [f32; WIDER_LANES],
    ) -> bool {
        #[allow(unsafe_code)]
        // SAFETY: as for `fetch`.
        unsafe {
            avx512::simplex3::<2, R, true>(o, r, &[[0.0; 16]; 2], registers(xf), Some(t), registers_mut(n));
        }
        true
    },
    #[inline(always)]
    fn lattice3<R: RowLanes, const GRADIENT: bool, const RELAXED: bool>(
        o: &Octave,
        r: &R,
        x: &[f64; WIDER_LANES],
        xf: &[f32; WIDER_LANES],
        t: &Columns,
        n: &mut [f32; WIDER_LANES],
    ) -> bool {
        #[allow(unsafe_code)]
        // SAFETY: as for `fetch`.
        unsafe {
            let (x, xf, n) = (registers(x), registers(xf), registers_mut(n));
            match &t.terms {
                Some(terms) if GRADIENT => {
                    avx512::lattice3::<2, R, true, RELAXED, true>(o, r, x, xf, t, terms, n)
                }
                _ => avx512::lattice3::<2, R, GRADIENT, RELAXED, false>(
                    o,
                    r,
                    x,
                    xf,
                    t,
                    &[[[0; 16]; 3]; 4],
                    n,
                ),
            }
        }
    }
);

/// 32 lanes as the two registers of 16 the `avx512` kernels take.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn registers<T>(lanes: &[T; WIDER_LANES]) -> &[[T; WIDE_LANES]; 2] {
    <&[[T; WIDE_LANES]; 2]>::try_from(lanes.as_chunks().0)
        .unwrap_or_else(|_| unreachable!("32 lanes are two chunks of 16"))
}

/// [`registers`] of lanes to write.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn registers_mut<T>(lanes: &mut [T; WIDER_LANES]) -> &mut [[T; WIDE_LANES]; 2] {
    <&mut [[T; WIDE_LANES]; 2]>::try_from(lanes.as_chunks_mut().0)
        .unwrap_or_else(|_| unreachable!("32 lanes are two chunks of 16"))
}

/// [`Fetch::accumulate`] as one multiply and one add per 16 lanes (AVX-512F; `L` a multiple
/// of 16): LLVM's own vectorisation of the loop split it into 8-, 4- and 1-lane pieces that
/// reread `n` from the stack, a quarter of a Perlin row's time.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn accumulate512<const L: usize>(acc: &mut [f32; L], w: f32, n: &[f32; L]) {
    use std::arch::x86_64::{
        _mm512_add_ps, _mm512_loadu_ps, _mm512_mul_ps, _mm512_set1_ps, _mm512_storeu_ps,
    };
    for (a, v) in acc
        .chunks_exact_mut(WIDE_LANES)
        .zip(n.chunks_exact(WIDE_LANES))
    {
        #[allow(unsafe_code)]
        // SAFETY: the loads and the store touch the 16 `f32` of a chunk of 16.
        unsafe {
            let sum = _mm512_add_ps(
                _mm512_loadu_ps(a.as_ptr()),
                _mm512_mul_ps(_mm512_set1_ps(w), _mm512_loadu_ps(v.as_ptr())),
            );
            _mm512_storeu_ps(a.as_mut_ptr(), sum);
        }
    }
}

/// `window[idx[l] % 32]` for 32 lanes: per register of 16 lanes, one two-source `vpermt2d`
/// over the window's first 32 entries (AVX-512F).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn permute32(window: &[u32], idx: &[u32; WIDER_LANES]) -> [u32; WIDER_LANES] {
    use std::arch::x86_64::{__m512i, _mm512_loadu_si512, _mm512_permutex2var_epi32};
    let window = &window[..WIDER_LANES];
    #[allow(unsafe_code)]
    // SAFETY: every load reads 16 `u32` (64 bytes) from slices of at least that length
    // (unaligned loads); `[__m512i; 2]` and `[u32; 32]` have the same size, every bit pattern
    // valid for both.
    unsafe {
        let a = _mm512_loadu_si512(window.as_ptr().cast::<__m512i>());
        let b = _mm512_loadu_si512(window[WIDE_LANES..].as_ptr().cast::<__m512i>());
        let i0 = _mm512_loadu_si512(idx.as_ptr().cast::<__m512i>());
        let i1 = _mm512_loadu_si512(idx[WIDE_LANES..].as_ptr().cast::<__m512i>());
        std::mem::transmute::<[__m512i; 2], [u32; WIDER_LANES]>([
            _mm512_permutex2var_epi32(a, i0, b),
            _mm512_permutex2var_epi32(a, i1, b),
        ])
    }
}

/// `window[idx[l] % 16]` by one 16-lane `vpermd` (AVX-512F).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn permute16(window: &[u32], idx: &[u32; WIDE_LANES]) -> [u32; WIDE_LANES] {
    use std::arch::x86_64::{__m512i, _mm512_loadu_si512, _mm512_permutexvar_epi32};
    let window = &window[..WIDE_LANES];
    #[allow(unsafe_code)]
    // SAFETY: both loads read 16 `u32` (64 bytes) from slices of at least that length
    // (unaligned loads), and `__m512i` and `[u32; 16]` have the same size, every bit pattern
    // valid for both.
    unsafe {
        let t = _mm512_loadu_si512(window.as_ptr().cast::<__m512i>());
        let i = _mm512_loadu_si512(idx.as_ptr().cast::<__m512i>());
        std::mem::transmute::<__m512i, [u32; WIDE_LANES]>(_mm512_permutexvar_epi32(i, t))
    }
}

/// The basis as a const parameter of the row loop (`B`), beside its dimension (`D3`): each
/// basis and dimension gets its own loop, so that LLVM allocates its registers for that basis
/// alone (one loop holding every basis kept the lane arrays of each on the stack, and a kernel
/// added for one basis slowed the others).
const GRADIENT: u8 = 0;
const VALUE: u8 = 1;
const SIMPLEX: u8 = 2;
const KENSLER: u8 = 3;
const WORLEY: u8 = 4;

/// `$self.$method::<$g…, B, D3>($arg…)` with the evaluator's basis and dimension as the
/// constants `B` and `D3`: `$g2` are the leading generic arguments of 2D bases, `$wide3` those
/// of 3D gradient, value and simplex noise (the AVX-512 row's two-register kernels), `$g3`
/// those of the other 3D bases; one list `$g` serves all three.
macro_rules! by_basis {
    ($self:ident.$method:ident, [$($g:tt),*], ($($arg:expr),*)) => {
        by_basis!($self.$method, [$($g),*], [$($g),*], [$($g),*], ($($arg),*))
    };
    ($self:ident.$method:ident, [$($g2:tt),*], [$($g3:tt),*], [$($wide3:tt),*], ($($arg:expr),*)) => {
        match (&$self.basis, $self.three_d) {
            (Basis::Gradient, false) => $self.$method::<$($g2,)* GRADIENT, false>($($arg),*),
            (Basis::Gradient, true) => $self.$method::<$($wide3,)* GRADIENT, true>($($arg),*),
            (Basis::Value, false) => $self.$method::<$($g2,)* VALUE, false>($($arg),*),
            (Basis::Value, true) => $self.$method::<$($wide3,)* VALUE, true>($($arg),*),
            (Basis::Simplex, false) => $self.$method::<$($g2,)* SIMPLEX, false>($($arg),*),
            (Basis::Simplex, true) => $self.$method::<$($wide3,)* SIMPLEX, true>($($arg),*),
            (Basis::Kensler, false) => $self.$method::<$($g2,)* KENSLER, false>($($arg),*),
            (Basis::Kensler, true) => $self.$method::<$($g3,)* KENSLER, true>($($arg),*),
            (Basis::Worley(_), false) => $self.$method::<$($g2,)* WORLEY, false>($($arg),*),
            (Basis::Worley(_), true) => $self.$method::<$($g3,)* WORLEY, true>($($arg),*),
        }
    };
}

/// A classic noise ready to evaluate.
#[derive(Debug, Clone)]
pub struct ClassicEvaluator {
    /// The model, for the octave weights of a footprint.
    model: ClassicNoise,
    three_d: bool,
    basis: Basis,
    worley: Option<WorleyParams>,
    kind: Option<FractalKind>,
    octaves: Vec<Octave>,
    amplitude: f32,
    mean: f32,
    simd: Simd,
    /// Bench only ([`set_relaxed`](Self::set_relaxed)): the f32 cell split and FMA.
    relaxed: bool,
    /// The basis's statistics for a minified render's fade, measured on first use (a Worley
    /// basis's take milliseconds).
    statistics: std::sync::OnceLock<BasisStatistics>,
}

impl ClassicEvaluator {
    /// Prepares a validated `model` on the plane `z` (ignored in 2D).
    #[must_use]
    pub fn new(model: &ClassicNoise, z: f64) -> Self {
        Self::prepare(model, z, None)
    }

    /// Prepares a validated `model` that accepts `period` ([`ClassicNoise::check_period`]:
    /// every octave's cell divides it) made periodic: each octave's lattice coordinates are
    /// wrapped modulo its cells per period where they enter the hash.
    #[must_use]
    pub fn new_periodic(model: &ClassicNoise, z: f64, period: Period) -> Self {
        Self::prepare(model, z, Some(period))
    }

    fn prepare(model: &ClassicNoise, z: f64, period: Option<Period>) -> Self {
        let octaves = (0..model.octaves())
            .map(|o| {
                let side = model.octave_cell(o);
                let pz = z / side;
                let (kz, uz) = locate(pz);
                let zkeys = [-1, 0, 1]
                    .map(|d| layer_key(o, cell_hash(kz.wrapping_add(d), 0, o, model.seed)));
                let inv = 1.0 / side;
                let mantissa = (1u64 << 52) - 1;
                let exact = side.to_bits() & mantissa == 0
                    && inv.to_bits() & mantissa == 0
                    && side.is_normal()
                    && inv.is_normal();
                Octave {
                    side,
                    inv_side: exact.then_some(inv),
                    cells: period.map_or([0, 0], |p| p.cells(side).map(|n| n as i32)),
                    weight: model.octave_weight(o),
                    layer: o,
                    key2: layer_key(o, model.seed),
                    key0: row_key(0, layer_key(o, model.seed)),
                    pz,
                    kz,
                    uz,
                    zkeys,
                    kensler_z: if model.dimensions == 3 {
                        [-1, 0, 1, 2].map(|d| cell_hash(kz.wrapping_add(d), 2, o, model.seed))
                    } else {
                        [0; 4]
                    },
                }
            })
            .collect();
        let worley = match &model.basis {
            Basis::Worley(w) => {
                let cap = (WORLEY_MAX_RING + 1) as f32;
                Some(WorleyParams {
                    metric: w.metric,
                    coefficients: w.coefficients,
                    fixed: match w.points {
                        FeaturePoints::Fixed(n) => Some(n),
                        FeaturePoints::Poisson(_) => None,
                    },
                    cdf: w.points.poisson_cdf().unwrap_or([0.0; 16]),
                    needed: w.needed() - 1,
                    cap: if w.metric == Metric::Euclidean {
                        cap * cap
                    } else {
                        cap
                    },
                })
            }
            _ => None,
        };
        Self {
            model: model.clone(),
            three_d: model.dimensions == 3,
            basis: model.basis.clone(),
            worley,
            kind: model.fractal.as_ref().map(|f| f.kind),
            octaves,
            amplitude: model.amplitude,
            mean: model.mean,
            statistics: std::sync::OnceLock::new(),
            simd: Simd::detect(),
            relaxed: false,
        }
    }

    /// Basis evaluations per pixel (octaves, times the cells searched for Worley), for reports.
    #[must_use]
    pub fn evaluations_per_pixel(&self) -> f64 {
        let per = match (&self.basis, self.three_d) {
            (Basis::Worley(_), false) => 9.0,
            (Basis::Worley(_), true) => 27.0,
            // 16 (64) corners against the gradient basis's 4 (8).
            (Basis::Kensler, false) => 4.0,
            (Basis::Kensler, true) => 8.0,
            _ => 1.0,
        };
        per * self.octaves.len() as f64
    }

    /// Pixels the AVX-512 row evaluates together: 32 (two registers, two independent chains)
    /// for 2D noise and for the hand-written 3D kernels (gradient, value, simplex: `avx512`),
    /// 16 for 3D Kensler and Worley noise, whose larger lane state spilled at 32 (measured on
    /// the grid bench: 2D Perlin 455 -> 515, simplex 248 -> 297 Mpix/s; 3D cellular 60 -> 50 at
    /// 32). Lanes are independent, so the bits are the same at either width.
    fn avx512_lanes(&self) -> usize {
        if self.three_d && matches!(self.basis, Basis::Kensler | Basis::Worley(_)) {
            WIDE_LANES
        } else {
            WIDER_LANES
        }
    }

    /// Forces the portable path (`false`) or the widest level the CPU has (`true`, the
    /// default); for tests comparing the code paths. Returns the level's lane count.
    #[doc(hidden)]
    pub fn set_simd(&mut self, enabled: bool) -> usize {
        self.simd = if enabled {
            Simd::detect()
        } else {
            Simd::Portable
        };
        if self.simd == Simd::Avx512 {
            self.avx512_lanes()
        } else {
            LANES
        }
    }

    /// Forces AVX2 when the CPU has it (for tests comparing the code paths).
    #[doc(hidden)]
    pub fn set_avx2(&mut self) -> bool {
        if Simd::detect() == Simd::Portable {
            return false;
        }
        self.simd = Simd::Avx2;
        true
    }

    /// Bench only, never reachable from a model (no model field or constructor sets it): gives
    /// up two of the guarantees to measure what they cost. Positions are split into cells in
    /// f32 (`x as f32 / side`, exact only while `x / side` keeps its fraction in 24 bits: far
    /// from the origin the offsets lose precision) instead of f64, and the interpolations,
    /// fades and distances use fused multiply-adds (other bits than the portable path). Lattice
    /// and simplex octaves with per-row tables and Worley octaves with a fixed count change; the
    /// rest keep the exact path. Needs AVX2 and FMA: returns whether the CPU has them (nothing
    /// changes where it does not).
    #[doc(hidden)]
    pub fn set_relaxed(&mut self, relaxed: bool) -> bool {
        #[cfg(target_arch = "x86_64")]
        let available = Simd::detect() != Simd::Portable && is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let available = false;
        self.relaxed = relaxed && available;
        available
    }

    /// Evaluates rows `first..` of `window` into `out` (a whole number of rows).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval_rows_with(window, first, out, true);
    }

    /// [`eval_rows`](Self::eval_rows) with every lattice hash computed in the lanes, pixel by
    /// pixel: the path the per-row tables of the fast path are tested and benched against.
    pub fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval_rows_with(window, first, out, false);
    }

    /// `columns`: read lattice hashes from per-row [`Columns`] tables where the basis allows.
    fn eval_rows_with(&self, window: &Window, first: usize, out: &mut [f32], columns: bool) {
        if window.width == 0 {
            return;
        }
        let fade = self.fade(window);
        for (r, line) in out.chunks_exact_mut(window.width).enumerate() {
            self.eval_row_faded(window, first + r, line, fade.as_ref(), columns);
        }
    }

    /// How a minified render takes each octave ([`spectex_model::filter::classic_fade`]), or
    /// `None`: unfiltered.
    fn fade(&self, window: &Window) -> Option<OctaveFade> {
        let side = window.footprint()?;
        let statistics = self.statistics.get_or_init(|| {
            spectex_model::filter::basis_statistics(&self.model.basis, self.model.dimensions)
        });
        Some(spectex_model::filter::classic_fade(
            &self.model,
            side,
            statistics,
        ))
    }

    /// Evaluates row `row` of `window` into `out` (`window.width` values).
    pub fn eval_row(&self, window: &Window, row: usize, out: &mut [f32]) {
        self.eval_row_faded(window, row, out, self.fade(window).as_ref(), true);
    }

    /// [`eval_row`](Self::eval_row) with the octave fade of a minified render (`None`:
    /// unfiltered).
    /// `columns`: read lattice hashes from per-row [`Columns`] tables where the basis allows.
    fn eval_row_faded(
        &self,
        window: &Window,
        row: usize,
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        let y = window.y(row);
        let rows: Vec<RowOctave> = self.octaves.iter().map(|o| self.row_octave(o, y)).collect();
        #[cfg(target_arch = "x86_64")]
        if self.relaxed {
            #[allow(unsafe_code)]
            // SAFETY: `relaxed` is set only when the CPU reports AVX2 and FMA at run time, and
            // `Simd::Avx512` only when it reports AVX-512F.
            unsafe {
                if self.simd == Simd::Avx512 {
                    self.row_relaxed_avx512(window, &rows, out, w, columns);
                } else {
                    self.row_relaxed(window, &rows, out, w, columns);
                }
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
            Simd::Avx512 => unsafe { self.row_avx512(window, &rows, out, w, columns) },
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
            Simd::Avx2 => unsafe { self.row_avx2(window, &rows, out, w, columns) },
            Simd::Portable => by_basis!(
                self.row,
                [LANES, Indexed, false],
                (window, &rows, out, w, columns)
            ),
        }
        #[cfg(not(target_arch = "x86_64"))]
        by_basis!(
            self.row,
            [LANES, Indexed, false],
            (window, &rows, out, w, columns)
        );
    }

    /// The noise at one position (the same bits as any render).
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let w = Window::new(1, 1).at([x, y], 1.0);
        let mut out = [0.0f32];
        self.eval_row(&w, 0, &mut out);
        out[0]
    }

    fn row_octave(&self, o: &Octave, y: f64) -> RowOctave {
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

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn row_avx2(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        by_basis!(
            self.row,
            [LANES, Permute8, false],
            (window, rows, out, w, columns)
        );
    }

    /// [`row_avx2`](Self::row_avx2) with the f32 split and FMA ([`set_relaxed`](Self::set_relaxed)).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn row_relaxed(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        by_basis!(
            self.row,
            [LANES, Permute8, true],
            (window, rows, out, w, columns)
        );
    }

    /// [`row_avx512`](Self::row_avx512) with the f32 split and FMA, so that the guarantees'
    /// cost is measured at the exact path's width.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,fma")]
    fn row_relaxed_avx512(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        self.row_wide::<true>(window, rows, out, w, columns);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn row_avx512(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        self.row_wide::<false>(window, rows, out, w, columns);
    }

    /// The AVX-512 row at [`avx512_lanes`](Self::avx512_lanes)' width; `inline(always)` into
    /// each AVX-512 wrapper.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn row_wide<const RELAXED: bool>(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        // The widths of `avx512_lanes`.
        by_basis!(
            self.row,
            [WIDER_LANES, Permute32, RELAXED],
            [WIDE_LANES, Permute16, RELAXED],
            [WIDER_LANES, Permute32, RELAXED],
            (window, rows, out, w, columns)
        );
    }

    /// One row, `L` pixels at a time; `inline(always)` so each SIMD wrapper gets its own copy.
    /// `fade`: how a minified render takes each octave (`classic_fade`), else `None`.
    /// `columns`: read lattice hashes from per-row [`Columns`] tables where the basis allows.
    /// `RELAXED`: the bench-only f32 split and FMA ([`set_relaxed`](Self::set_relaxed)).
    #[inline(always)]
    fn row<const L: usize, F: Fetch<L>, const RELAXED: bool, const B: u8, const D3: bool>(
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

    /// The [`Columns`] of octave `o` on the row `r` of `window` (`width` pixels, evaluated `L`
    /// at a time), or `None` where the basis hashes in the lanes (simplex, Worley) or the row
    /// visits more lattice columns than it has pixels (a minified render of small cells);
    /// `corners`: with 3D simplex noise's [`SimplexCorners`] ([`Fetch::CORNERS`]);
    /// `gradient_index`: 3D gradient noise by gradient index ([`Fetch::GRADIENT_INDEX`]).
    #[inline(always)]
    fn columns<const L: usize, const B: u8>(
        &self,
        o: &Octave,
        r: &RowOctave,
        window: &Window,
        width: usize,
        corners: bool,
        gradient_index: bool,
    ) -> Option<RowTable> {
        // The basis as the constant `B`: each row loop builds only its own basis's tables.
        if B == WORLEY {
            return self
                .worley_columns::<L>(o, r, window, width)
                .map(RowTable::Worley);
        }
        if B == SIMPLEX {
            return self
                .simplex_columns::<L>(o, r, window, width, corners)
                .map(RowTable::Simplex);
        }
        if !(B == GRADIENT || B == VALUE) || width == 0 {
            return None;
        }
        // Cells under a pixel: the table would hold more columns than the row has pixels.
        if o.side < window.scale {
            return None;
        }
        let (lo, hi) = Self::column_range::<L>(o, window, width);
        let count = i64::from(hi) - i64::from(lo) + 2;
        if count > (width + L) as i64 + 2 {
            return None;
        }
        let count = count as usize;
        let len = count + WINDOW;
        let keys: &[u32] = if self.three_d {
            &[r.keys[1][1], r.keys[1][2], r.keys[2][1], r.keys[2][2]]
        } else {
            &[r.keys[1][1], r.keys[1][2]]
        };
        let gradient = self.basis == Basis::Gradient;
        let by_index = gradient && self.three_d && gradient_index;
        let size = keys.len() * len;
        let per_column = gradient && !by_index;
        let mut t = Columns {
            lo,
            len,
            mask: scratch(if per_column { size } else { 0 }),
            sign: scratch(if per_column { size } else { 0 }),
            constant: scratch(size),
            terms: None,
        };
        if by_index {
            let mut terms = Box::new([[[0u32; 16]; 3]; 4]);
            for (p, terms) in terms.iter_mut().enumerate() {
                // As the lanes compute them: `uy − dy`, `uz − dz`.
                let (dz, dy) = (p / 2, p % 2);
                let (y, z) = (r.uy - dy as f32, o.uz - dz as f32);
                for g in 0..16 {
                    let (m, s, k) = gradient_terms((g as u32) << 28, y, z);
                    (terms[0][g], terms[1][g], terms[2][g]) = (m, s, k);
                }
            }
            t.terms = Some(terms);
        }
        // Plain `take` and `set`, not `with`: a closure's loops would be compiled apart from
        // this function's instruction set.
        let mut kept = KEPT.take();
        for (p, &key) in keys.iter().enumerate() {
            let hashes = kept.get(lo, o.cells[0], key, count);
            let at = p * len;
            // The padding after the columns: zeros, as the lanes may load (not use) it.
            for table in [&mut t.mask, &mut t.sign, &mut t.constant] {
                if let Some(padding) = table.get_mut(at + count..at + len) {
                    padding.fill(0);
                }
            }
            // One loop per table over slices of one length, so that each vectorises (a row
            // of cells of one pixel builds as many entries as it has pixels).
            let constant = &mut t.constant[at..at + count];
            if by_index {
                for (&h, k) in hashes.iter().zip(constant) {
                    *k = h >> 28;
                }
            } else if gradient {
                // As the lanes compute them: `uy − dy`, `uz − dz` (2D: `uy`, `uy − 1`, 0).
                let (dz, dy) = (p / 2, p % 2);
                let y = r.uy - dy as f32;
                let z = if self.three_d { o.uz - dz as f32 } else { 0.0 };
                let mask = &mut t.mask[at..at + count];
                let sign = &mut t.sign[at..at + count];
                for (((&h, m), s), k) in hashes.iter().zip(mask).zip(sign).zip(constant) {
                    (*m, *s, *k) = gradient_terms(h, y, z);
                }
            } else {
                for (&h, k) in hashes.iter().zip(constant) {
                    *k = lattice_value(h).to_bits();
                }
            }
        }
        KEPT.set(kept);
        Some(RowTable::Lattice(t))
    }

    /// The first and last lattice columns of the lanes of a row of `window` (`width` pixels,
    /// `L` at a time) on octave `o`: positions grow along the row, and so do their cells.
    #[inline(always)]
    fn column_range<const L: usize>(o: &Octave, window: &Window, width: usize) -> (i32, i32) {
        let last_start = (width - 1) / L * L;
        let first = window.offset[0] + (window.x0 as f64) * window.scale;
        let last = window.offset[0]
            + ((window.x0 + last_start as i64) as f64 + (L - 1) as f64) * window.scale;
        (locate(first / o.side).0, locate(last / o.side).0)
    }

    /// The skew `s` of simplex noise at `x` on the row `r`, as [`simplex2`] and [`simplex3`]
    /// compute it: the skewed row is `⌊py + s⌋`, in 3D the plane `⌊pz + s⌋`.
    #[inline(always)]
    fn simplex_skew(&self, o: &Octave, r: &RowOctave, x: f64) -> f64 {
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
    fn simplex_columns<const L: usize>(
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

    /// The [`WorleyColumns`] of octave `o` on the row `r`, or `None`: a Poisson count, cells
    /// under 2 pixels, or more columns than pixels.
    #[inline(always)]
    fn worley_columns<const L: usize>(
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

    /// Gradient or value noise with the corner hashes read from the row's [`Columns`] `t`, the
    /// arithmetic of [`gradient2`] and [`gradient3`] otherwise; `false` (nothing written) when
    /// the lanes span `L` or more lattice columns, which one fetch cannot reach.
    #[inline(always)]
    fn lattice_columns<
        const L: usize,
        F: Fetch<L>,
        R: RowLanes,
        const GRADIENT: bool,
        const THREE_D: bool,
        const RELAXED: bool,
    >(
        o: &Octave,
        r: &R,
        x: &[f64; L],
        xf: &[f32; L],
        t: &Columns,
        n: &mut [f32; L],
    ) -> bool {
        let mut ix = [0i32; L];
        let mut ux = [0.0f32; L];
        if RELAXED {
            locate_lanes_f32(o, xf, &mut ix, &mut ux);
        } else {
            locate_lanes(&cell_units(o, x), &mut ix, &mut ux);
        }
        let span = i64::from(ix[L - 1]) - i64::from(ix[0]);
        let base = i64::from(ix[0]) - i64::from(t.lo);
        if !(0..L as i64).contains(&span) || base < 0 || base as usize + WINDOW > t.len {
            return false;
        }
        let base = base as usize;
        let mut idx = [0u32; L];
        for l in 0..L {
            idx[l] = ix[l].wrapping_sub(ix[0]) as u32;
        }
        let lerp = lerp::<RELAXED>;
        let fade = fade_with::<RELAXED>;
        if THREE_D {
            let mut c = [[[[0.0f32; L]; 2]; 2]; 2];
            for (dz, cz) in c.iter_mut().enumerate() {
                for (dy, cy) in cz.iter_mut().enumerate() {
                    *cy = corners::<L, F, GRADIENT>(t, 2 * dz + dy, base, &idx, &ux);
                }
            }
            let sz = fade(o.uz);
            for l in 0..L {
                let sy = fade(r.uy(l));
                let sx = fade(ux[l]);
                let y0 = lerp(
                    lerp(c[0][0][0][l], c[0][0][1][l], sx),
                    lerp(c[0][1][0][l], c[0][1][1][l], sx),
                    sy,
                );
                let y1 = lerp(
                    lerp(c[1][0][0][l], c[1][0][1][l], sx),
                    lerp(c[1][1][0][l], c[1][1][1][l], sx),
                    sy,
                );
                n[l] = lerp(y0, y1, sz);
            }
        } else {
            let mut c = [[[0.0f32; L]; 2]; 2];
            for (dy, cy) in c.iter_mut().enumerate() {
                *cy = corners::<L, F, GRADIENT>(t, dy, base, &idx, &ux);
            }
            for l in 0..L {
                let sy = fade(r.uy(l));
                let sx = fade(ux[l]);
                let a = lerp(c[0][0][l], c[0][1][l], sx);
                let b = lerp(c[1][0][l], c[1][1][l], sx);
                n[l] = lerp(a, b, sy);
            }
        }
        true
    }

    /// The points of `points` (pixels), `L` at a time, into `out`: each lane at its own
    /// position, as lane 0 of a one-pixel window there ([`crate::point_window`]) computes it.
    #[inline(always)]
    fn points<const L: usize>(&self, points: &[[f64; 2]], out: &mut [f32]) {
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
    fn point_rows<const L: usize>(&self, o: &Octave, y: &[f64; L], r: &mut PointRows<L>) {
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

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn points_avx2(&self, points: &[[f64; 2]], out: &mut [f32]) {
        self.points::<LANES>(points, out);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn points_avx512(&self, points: &[[f64; 2]], out: &mut [f32]) {
        self.points::<WIDE_LANES>(points, out);
    }

    /// Evaluates the noise at each of `points` (pixels) into `out` (one value per point), in
    /// the lanes: the same bits as a one-pixel window at each point.
    pub fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let out = &mut out[..points.len()];
        #[cfg(target_arch = "x86_64")]
        match self.simd {
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx512` is chosen only when the CPU reports AVX-512F at run time.
            Simd::Avx512 => unsafe { self.points_avx512(points, out) },
            #[allow(unsafe_code)]
            // SAFETY: `Simd::Avx2` is chosen only when the CPU reports AVX2 at run time.
            Simd::Avx2 => unsafe { self.points_avx2(points, out) },
            Simd::Portable => self.points::<LANES>(points, out),
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.points::<LANES>(points, out);
    }

    /// The octaves' fractal sum at the lanes' positions `x` along x, their rows (one per
    /// octave) along y; `fade`: how a minified render takes each octave, else `None`;
    /// `tables`: each octave's [`Columns`] of the row, where it has one (else empty).
    #[inline(always)]
    fn octave_sum<
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
    fn basis_lanes<const L: usize, R: RowLanes, const B: u8, const D3: bool>(
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

    /// Worley in the lanes: the 3×3 (×3) cells, then the exact search where it is not enough.
    #[inline(always)]
    fn worley_lanes<const L: usize, const THREE_D: bool, const METRIC: u8, R: RowLanes>(
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
    fn worley_table<
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
    fn worley_table_lanes<
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
fn worley_finish<const L: usize, R: RowLanes>(
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
fn gap(ux: f32, uy: f32, uz: f32, three_d: bool, ring: i32) -> f32 {
    let r = ring as f32;
    let mut g = min(min(ux + r, (r + 1.0) - ux), min(uy + r, (r + 1.0) - uy));
    if three_d {
        g = min(g, min(uz + r, (r + 1.0) - uz));
    }
    g
}

#[inline(always)]
fn distance2(metric: Metric, dx: f32, dy: f32) -> f32 {
    match metric {
        Metric::Euclidean => dx * dx + dy * dy,
        Metric::Manhattan => dx.abs() + dy.abs(),
        Metric::Chebyshev => max(dx.abs(), dy.abs()),
    }
}

#[inline(always)]
fn distance3(metric: Metric, dx: f32, dy: f32, dz: f32) -> f32 {
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
fn insert<const L: usize, const K: usize>(f: &mut [[f32; L]; 4], l: usize, d: f32) {
    let mut d = d;
    for fk in f.iter_mut().take(K) {
        let a = min(fk[l], d);
        d = max(fk[l], d);
        fk[l] = a;
    }
}

/// `C₁F₁ + C₂F₂ + C₃F₃ + C₄F₄` from the sorted list (squared distances for the Euclidean metric).
#[inline(always)]
fn combine(w: &WorleyParams, f: [f32; 4]) -> f32 {
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
fn worley_search(
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

/// 2D gradient (`gradient = true`) or value noise in the lanes.
#[inline(always)]
fn gradient2<const L: usize, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    n: &mut [f32; L],
    gradient: bool,
) {
    for l in 0..L {
        let (k0, k1) = (r.key(1, 1, l), r.key(1, 2, l));
        let uy = r.uy(l);
        let sy = fade(uy);
        let (ix, ux) = locate(x[l] / o.side);
        let (ix0, ix1) = (
            lattice(ix, o.cells[0]),
            lattice(ix.wrapping_add(1), o.cells[0]),
        );
        let h00 = cell_hash_in_row(ix0, k0);
        let h10 = cell_hash_in_row(ix1, k0);
        let h01 = cell_hash_in_row(ix0, k1);
        let h11 = cell_hash_in_row(ix1, k1);
        let (n00, n10, n01, n11) = if gradient {
            (
                gradient_dot(h00, ux, uy, 0.0),
                gradient_dot(h10, ux - 1.0, uy, 0.0),
                gradient_dot(h01, ux, uy - 1.0, 0.0),
                gradient_dot(h11, ux - 1.0, uy - 1.0, 0.0),
            )
        } else {
            (
                lattice_value(h00),
                lattice_value(h10),
                lattice_value(h01),
                lattice_value(h11),
            )
        };
        let sx = fade(ux);
        let a = n00 + sx * (n10 - n00);
        let b = n01 + sx * (n11 - n01);
        n[l] = a + sy * (b - a);
    }
}

/// 3D gradient or value noise on the plane of the octave's `z`, in the lanes.
#[inline(always)]
fn gradient3<const L: usize, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    n: &mut [f32; L],
    gradient: bool,
) {
    for l in 0..L {
        let (uy, uz) = (r.uy(l), o.uz);
        let (sy, sz) = (fade(uy), fade(uz));
        // keys[z][y]: z cells kz, kz + 1 are indices 1, 2; so are y cells iy, iy + 1.
        let k = [
            [r.key(1, 1, l), r.key(1, 2, l)],
            [r.key(2, 1, l), r.key(2, 2, l)],
        ];
        let (ix, ux) = locate(x[l] / o.side);
        let mut c = [[[0.0f32; 2]; 2]; 2];
        for dz in 0..2 {
            for dy in 0..2 {
                for dx in 0..2 {
                    let cx = lattice(ix.wrapping_add(dx as i32), o.cells[0]);
                    let h = cell_hash_in_row(cx, k[dz][dy]);
                    c[dz][dy][dx] = if gradient {
                        gradient_dot(h, ux - dx as f32, uy - dy as f32, uz - dz as f32)
                    } else {
                        lattice_value(h)
                    };
                }
            }
        }
        let sx = fade(ux);
        let lerp = |a: f32, b: f32, t: f32| a + t * (b - a);
        let y0 = lerp(
            lerp(c[0][0][0], c[0][0][1], sx),
            lerp(c[0][1][0], c[0][1][1], sx),
            sy,
        );
        let y1 = lerp(
            lerp(c[1][0][0], c[1][0][1], sx),
            lerp(c[1][1][0], c[1][1][1], sx),
            sy,
        );
        n[l] = lerp(y0, y1, sz);
    }
}

/// Kensler noise in the lanes, one lane at a time (a scalar kernel: no per-row tables, no
/// vectorised form yet). Corners `(ix + dx, iy + dy (, kz + dz))`, `dx, dy, dz ∈ −1..=2`,
/// visited z, then y, then x, each adding `kensler_weight(r²)·kensler_dot(h, δ)` with
/// `r² = (δx·δx + δy·δy) + δz·δz` and `h = P_x ⊕ P_y (⊕ P_z)` (in 2D the z loop is one
/// plane with `δz = 0`, `P_z = 0`); the sum times the output scale. `shaders/classic.wgsl`'s
/// `kensler` is the same sequence of operations.
#[inline(always)]
fn kensler<const L: usize, R: RowLanes>(
    o: &Octave,
    r: &R,
    x: &[f64; L],
    n: &mut [f32; L],
    three_d: bool,
) {
    let (kx, ky) = (row_key(0, o.key2), row_key(1, o.key2));
    let (planes, scale) = if three_d {
        (4, KENSLER3_SCALE)
    } else {
        (1, KENSLER2_SCALE)
    };
    for l in 0..L {
        let (ix, ux) = locate(x[l] / o.side);
        let (iy, uy) = (r.iy(l), r.uy(l));
        let mut px = [0u32; 4];
        let mut py = [0u32; 4];
        for d in 0..4 {
            let step = d as i32 - 1;
            px[d] = cell_hash_in_row(lattice(ix.wrapping_add(step), o.cells[0]), kx);
            py[d] = cell_hash_in_row(lattice(iy.wrapping_add(step), o.cells[1]), ky);
        }
        let mut sum = 0.0f32;
        for dz in 0..planes {
            let (pz, vz) = if three_d {
                (o.kensler_z[dz], o.uz - (dz as f32 - 1.0))
            } else {
                (0, 0.0)
            };
            for dy in 0..4 {
                let vy = uy - (dy as f32 - 1.0);
                for dx in 0..4 {
                    let vx = ux - (dx as f32 - 1.0);
                    let r2 = (vx * vx + vy * vy) + vz * vz;
                    let w = kensler_weight(r2);
                    let h = (px[dx] ^ py[dy]) ^ pz;
                    sum += w * kensler_dot(h, vx, vy, vz, three_d);
                }
            }
        }
        n[l] = scale * sum;
    }
}

/// `a·b + c`, fused (one rounding) when `FMA`: only the bench-only relaxed path
/// ([`ClassicEvaluator::set_relaxed`]) passes `true`.
#[inline(always)]
#[allow(
    clippy::disallowed_methods,
    reason = "the bench-only relaxed path measures what giving up the no-FMA guarantee saves"
)]
fn fused_if<const FMA: bool>(a: f32, b: f32, c: f32) -> f32 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// `a·b + c` with one rounding (the relaxed path only).
#[inline(always)]
fn fused(a: f32, b: f32, c: f32) -> f32 {
    fused_if::<true>(a, b, c)
}

/// `a + t·(b − a)`, the product and sum fused when `FMA`.
#[inline(always)]
fn lerp<const FMA: bool>(a: f32, b: f32, t: f32) -> f32 {
    if FMA {
        fused(t, b - a, a)
    } else {
        a + t * (b - a)
    }
}

/// [`fade`], its polynomial's steps fused when `FMA`.
#[inline(always)]
fn fade_with<const FMA: bool>(t: f32) -> f32 {
    if FMA {
        t * t * t * fused(t, fused(t, 6.0, -15.0), 10.0)
    } else {
        fade(t)
    }
}

/// `1.5·2²³`: `(p + M) − M` rounds an f32 of magnitude below 2²² to the nearest integer (the
/// relaxed path's split).
const ROUND_MAGIC_F32: f32 = 12_582_912.0;

/// The relaxed path's [`locate_lanes`]: `x / side` and its split in f32 (`x` already f32).
#[inline(always)]
fn locate_lanes_f32<const L: usize>(
    o: &Octave,
    x: &[f32; L],
    ix: &mut [i32; L],
    ux: &mut [f32; L],
) {
    let mut p = [0.0f32; L];
    match o.inv_side {
        Some(inv) => {
            let inv = inv as f32;
            for l in 0..L {
                p[l] = x[l] * inv;
            }
        }
        None => {
            let side = o.side as f32;
            for l in 0..L {
                p[l] = x[l] / side;
            }
        }
    }
    let mut f = [0.0f32; L];
    split_lanes_f32(&p, ix, &mut f);
    for l in 0..L {
        ux[l] = p[l] - f[l];
    }
}

/// [`split_lanes`] in f32 (magnitudes below 2²²): the cells and their floors.
#[inline(always)]
fn split_lanes_f32<const L: usize>(p: &[f32; L], i: &mut [i32; L], f: &mut [f32; L]) {
    for l in 0..L {
        let r = (p[l] + ROUND_MAGIC_F32) - ROUND_MAGIC_F32;
        f[l] = if r > p[l] { r - 1.0 } else { r };
    }
    let magic = ROUND_MAGIC_F32.to_bits() as i32;
    for l in 0..L {
        i[l] = ((f[l] + ROUND_MAGIC_F32).to_bits() as i32).wrapping_sub(magic);
    }
}

/// The relaxed path's simplex noise with a [`SimplexColumns`] table: the skew in f32, the
/// corner terms with FMA; `false` when one fetch cannot reach the keys.
#[inline(always)]
fn simplex_relaxed<const L: usize, F: Fetch<L>, R: RowLanes>(
    o: &Octave,
    r: &R,
    xf: &[f32; L],
    t: &SimplexColumns,
    three_d: bool,
    n: &mut [f32; L],
) -> bool {
    let mut px = [0.0f32; L];
    let inv = (1.0 / o.side) as f32;
    for l in 0..L {
        px[l] = xf[l] * inv;
    }
    let mut py = [0.0f32; L];
    for l in 0..L {
        py[l] = r.py(l) as f32;
    }
    if three_d {
        let pz = o.pz as f32;
        let (f3, g3) = (SIMPLEX_F3 as f32, SIMPLEX_G3 as f32);
        let (mut a, mut b, mut c) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
        for l in 0..L {
            let s = ((px[l] + py[l]) + pz) * f3;
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
        let (mut fi, mut fj, mut fk) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
        split_lanes_f32(&a, &mut at.i, &mut fi);
        split_lanes_f32(&b, &mut at.j, &mut fj);
        split_lanes_f32(&c, &mut at.k, &mut fk);
        for l in 0..L {
            let t = ((fi[l] + fj[l]) + fk[l]) * g3;
            at.x0[l] = px[l] - (fi[l] - t);
            at.y0[l] = py[l] - (fj[l] - t);
            at.z0[l] = pz - (fk[l] - t);
        }
        let Some(corners) = simplex3_corners::<L, F>(t, &at) else {
            return false;
        };
        simplex3_sum::<L, true>(&at, &corners, n);
    } else {
        let (f2, g2) = (SIMPLEX_F2 as f32, SIMPLEX_G2 as f32);
        let (mut a, mut b) = ([0.0f32; L], [0.0f32; L]);
        for l in 0..L {
            let s = (px[l] + py[l]) * f2;
            a[l] = px[l] + s;
            b[l] = py[l] + s;
        }
        let mut at = Simplex2At {
            i: [0; L],
            j: [0; L],
            x0: [0.0; L],
            y0: [0.0; L],
        };
        let (mut fi, mut fj) = ([0.0f32; L], [0.0f32; L]);
        split_lanes_f32(&a, &mut at.i, &mut fi);
        split_lanes_f32(&b, &mut at.j, &mut fj);
        for l in 0..L {
            let t = (fi[l] + fj[l]) * g2;
            at.x0[l] = px[l] - (fi[l] - t);
            at.y0[l] = py[l] - (fj[l] - t);
        }
        let Some((base, idx)) = simplex_window(t, &at.j) else {
            return false;
        };
        let keys = window(&t.keys, base);
        let (k0, k1) = (F::fetch(&keys[..L], &idx), F::fetch(&keys[1..=L], &idx));
        simplex2_sum::<L, true>(&at, &k0, &k1, n);
    }
    true
}

/// One simplex corner's term `max(0, r² − |δ|²)⁴ · (g · δ)`, `h` a hash or, `CODED`, its
/// [`gradient_code`].
#[inline(always)]
fn simplex_term<const FMA: bool, const CODED: bool>(
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

/// [`split`] in the lanes, one simple loop per step so that it vectorises (the same
/// operations, so the same bits): the cells `i` and their floors `f`.
#[inline(always)]
fn split_lanes<const L: usize>(p: &[f64; L], i: &mut [i32; L], f: &mut [f64; L]) {
    let mut m = [0.0f64; L];
    for l in 0..L {
        m[l] = p[l] + ROUND_MAGIC;
    }
    for l in 0..L {
        let r = m[l] - ROUND_MAGIC;
        f[l] = if r > p[l] { r - 1.0 } else { r };
    }
    floor_cells(f, i);
}

/// The `i32` cells of the floors `f` (integers of magnitude below 2⁵¹): the low 32 bits of
/// `f + M` ([`ROUND_MAGIC`], exact), which are those [`split`] takes, `p + M` less one where
/// it rounded up. No compare mask crosses from the f64 lanes to the i32 ones, so the step
/// stays a vector add and a shuffle.
#[inline(always)]
fn floor_cells<const L: usize>(f: &[f64; L], i: &mut [i32; L]) {
    for l in 0..L {
        i[l] = (f[l] + ROUND_MAGIC).to_bits() as u32 as i32;
    }
}

/// Where 2D simplex noise's lanes stand: the cells `(i, j)` of the skewed lattice and the
/// offsets `(x0, y0)` from its first corner.
struct Simplex2At<const L: usize> {
    i: [i32; L],
    j: [i32; L],
    x0: [f32; L],
    y0: [f32; L],
}

/// The skew of 2D simplex noise at the lanes' positions `px` (cell units) on the rows of `r`.
#[inline(always)]
fn simplex2_at<const L: usize, R: RowLanes>(r: &R, px: &[f64; L]) -> Simplex2At<L> {
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
fn simplex2_sum<const L: usize, const FMA: bool>(
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
fn simplex2<const L: usize, R: RowLanes>(o: &Octave, r: &R, x: &[f64; L], n: &mut [f32; L]) {
    let at = simplex2_at(r, &cell_units(o, x));
    let (mut k0, mut k1) = ([0u32; L], [0u32; L]);
    for l in 0..L {
        k0[l] = row_key(at.j[l], o.key2);
        k1[l] = row_key(at.j[l].wrapping_add(1), o.key2);
    }
    simplex2_sum::<L, false>(&at, &k0, &k1, n);
}

/// `x / side` in the lanes (by the exact reciprocal where the octave has one).
#[inline(always)]
fn cell_units<const L: usize>(o: &Octave, x: &[f64; L]) -> [f64; L] {
    let mut p = [0.0f64; L];
    match o.inv_side {
        Some(inv) => {
            for l in 0..L {
                p[l] = x[l] * inv;
            }
        }
        None => {
            for l in 0..L {
                p[l] = x[l] / o.side;
            }
        }
    }
    p
}

/// Where lanes with skewed rows (planes) `cell` read the row's [`SimplexColumns`] `t`: the
/// entry of lane 0 and each lane's distance from it, or `None` when one fetch cannot reach them.
#[inline(always)]
fn simplex_window<const L: usize>(
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
fn simplex2_table<const L: usize, F: Fetch<L>, R: RowLanes>(
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
struct Simplex3At<const L: usize> {
    i: [i32; L],
    j: [i32; L],
    k: [i32; L],
    x0: [f32; L],
    y0: [f32; L],
    z0: [f32; L],
}

/// The skew of 3D simplex noise at the lanes' positions `px` (cell units) on the rows of `r`
/// and the octave's plane.
#[inline(always)]
fn simplex3_at<const L: usize, R: RowLanes>(o: &Octave, r: &R, px: &[f64; L]) -> Simplex3At<L> {
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
enum Corners3<'a, const L: usize> {
    /// The layer keys of each lane's skewed planes `k` and `k + 1`.
    Layers([u32; L], [u32; L]),
    /// The row's [`SimplexCorners`] cubes and each lane's entry ([`SimplexCorners::entries`]).
    Table(&'a [u32], [u32; L]),
}

/// Gustavson's ranking of the lanes' `x0, y0, z0`, written as selects: the steps
/// `(i1, j1, k1)` and `(i2, j2, k2)` of the middle corners of 3D simplex noise.
#[inline(always)]
fn simplex3_steps<const L: usize>(at: &Simplex3At<L>) -> [[[i32; L]; 3]; 2] {
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
fn simplex3_sum<const L: usize, const FMA: bool>(
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
fn simplex3_terms<const L: usize, const FMA: bool, const CODED: bool>(
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
fn simplex3_table<const L: usize, F: Fetch<L>, R: RowLanes>(
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
fn simplex3_corners<'t, const L: usize, F: Fetch<L>>(
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
fn simplex3<const L: usize, R: RowLanes>(o: &Octave, r: &R, x: &[f64; L], n: &mut [f32; L]) {
    let at = simplex3_at(o, r, &cell_units(o, x));
    let (mut l0, mut l1) = ([0u32; L], [0u32; L]);
    for l in 0..L {
        l0[l] = plane_key(o, at.k[l]);
        l1[l] = plane_key(o, at.k[l].wrapping_add(1));
    }
    simplex3_sum::<L, false>(&at, &Corners3::Layers(l0, l1), n);
}

impl crate::CpuKind for ClassicNoise {
    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(ClassicEvaluator::new(self, z)))
    }

    fn cpu_kernel_periodic(
        &self,
        z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(ClassicEvaluator::new_periodic(self, z, period)))
    }
}

impl crate::RowKernel for ClassicEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.evaluations_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        ClassicEvaluator::eval_rows(self, window, first, out);
    }

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        ClassicEvaluator::eval_rows_reference(self, window, first, out);
    }

    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        ClassicEvaluator::eval_points(self, points, out);
    }
}

#[cfg(test)]
mod tests {
    use super::{coded_gradient_dot, gradient_code, gradient_dot, gradient_terms};

    /// The folded corner `((x & mask) ^ sign) + constant` is `gradient_dot` bit for bit, for
    /// every gradient index and signed zeros among the coordinates (the case `−0 + −0`).
    #[test]
    fn gradient_terms_fold_gradient_dot_exactly() {
        let values = [0.0f32, -0.0, 0.375, -0.625, 1.0, -1.0, 0.999_999_9, 1.0e-30];
        for g in 0..16u32 {
            // Low bits too: only the top four choose the gradient.
            let h = (g << 28) | 0x0123_4567;
            for &y in &values {
                for &z in &values {
                    let (mask, sign, constant) = gradient_terms(h, y, z);
                    for &x in &values {
                        let folded =
                            f32::from_bits((x.to_bits() & mask) ^ sign) + f32::from_bits(constant);
                        let direct = gradient_dot(h, x, y, z);
                        assert_eq!(
                            folded.to_bits(),
                            direct.to_bits(),
                            "g {g}, (x, y, z) = ({x:e}, {y:e}, {z:e}): {folded:e} vs {direct:e}"
                        );
                    }
                }
            }
        }
    }

    /// The coded gradient of the simplex corner tables is `gradient_dot` bit for bit, for every
    /// gradient index and signed zeros among the coordinates, whatever the bits below the code
    /// (a cube's other corners).
    #[test]
    fn coded_gradient_dot_is_gradient_dot_exactly() {
        let values = [
            0.0f32,
            -0.0,
            0.375,
            -0.625,
            1.0,
            -1.0,
            0.999_999_9,
            1.0e-30,
            -3.5e-38,
        ];
        let below = [0, 0x0FFF_FFFF, 0x0765_4321, 0x0800_0001];
        for (g, below) in (0..16u32).flat_map(|g| below.map(|b| (g, b))) {
            let h = (g << 28) | 0x0765_4321;
            let c = (gradient_code(h) & 0xF000_0000) | below;
            for &x in &values {
                for &y in &values {
                    for &z in &values {
                        let coded = coded_gradient_dot(c, x, y, z);
                        let direct = gradient_dot(h, x, y, z);
                        assert_eq!(
                            coded.to_bits(),
                            direct.to_bits(),
                            "g {g}, below {below:#x}, (x, y, z) = ({x:e}, {y:e}, {z:e}): \
                             {coded:e} vs {direct:e}"
                        );
                    }
                }
            }
        }
    }
}
