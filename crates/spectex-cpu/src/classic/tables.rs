//! Per-row lattice tables the lanes read by column, and the gradient terms folded into them.

use spectex_model::Window;
use spectex_model::classic::{Basis, lattice_value};
use spectex_model::random::cell_hash_in_row;

use super::cache::{KEPT, recycle, scratch};
use super::fractal::{Octave, RowOctave};
use super::lanes::{WINDOW, locate};
use super::lattice::lattice;
use super::simplex::SimplexColumns;
use super::worley::WorleyColumns;
use super::{ClassicEvaluator, GRADIENT, SIMPLEX, VALUE, WORLEY};

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
pub(super) struct Columns {
    /// The first column.
    pub(super) lo: i32,
    /// Entries per row key: the columns `lo..=hi + 1`, then [`WINDOW`] of padding so that the
    /// window of entries a group of lanes reads is in the table.
    pub(super) len: usize,
    /// Gradient noise: all ones where the corner's sum takes `X`, else 0 (empty for value
    /// noise).
    pub(super) mask: Vec<u32>,
    /// Gradient noise: the sign bit flipping `X` (or the zero's sign, see above).
    pub(super) sign: Vec<u32>,
    /// The f32 bits of the constant term (value noise: the lattice value); with `terms`, the
    /// corner's gradient index `g = h >> 28` instead.
    pub(super) constant: Vec<u32>,
    /// 3D gradient noise read by gradient index ([`Fetch::GRADIENT_INDEX`]): `[mask, sign,
    /// constant]` of each `g` for each row key, `mask` and `sign` empty. A row's entries then
    /// are the kept hashes shifted (no `gradient_terms` per column, 22% of a 3D fBm's time
    /// with cells down to a pixel), and the lanes read their terms by a second permute.
    pub(super) terms: Option<Box<GradientTerms>>,
}

/// `[mask, sign, constant]` of [`gradient_terms`] for each gradient index `g < 16`, of each of
/// the four row keys of a 3D row.
pub(super) type GradientTerms = [[[u32; 16]; 3]; 4];

/// `cell_hash_in_row(lattice(lo + c, cells), key)` of the columns `c` of `out`, in a loop
/// that vectorises (the wrap of a periodic octave is hoisted out of it).
#[inline(always)]
pub(super) fn column_hashes(lo: i32, cells: i32, key: u32, out: &mut [u32]) {
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
pub(super) fn window(table: &[u32], at: usize) -> &[u32; WINDOW] {
    <&[u32; WINDOW]>::try_from(&table[at..at + WINDOW]).expect("a slice of WINDOW entries")
}

/// A row's table for one octave: lattice corners, Worley feature points or simplex keys.
#[derive(Debug, Clone)]
pub(super) enum RowTable {
    Lattice(Columns),
    Worley(WorleyColumns),
    Simplex(SimplexColumns),
}

impl RowTable {
    /// Gives the table's buffers back ([`recycle`]), the last taken first.
    pub(super) fn recycle(self) {
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
pub(super) fn gradient_terms(h: u32, y: f32, z: f32) -> (u32, u32, u32) {
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
pub(super) fn gradient_code(h: u32) -> u32 {
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
pub(super) fn coded_gradient_dot(c: u32, x: f32, y: f32, z: f32) -> f32 {
    let u = if c & (1 << 29) != 0 { y } else { x };
    let v = if c & (1 << 28) != 0 { z } else { y };
    let u = f32::from_bits(u.to_bits() ^ (c & (1 << 31)));
    let v = f32::from_bits(v.to_bits() ^ ((c << 1) & (1 << 31)));
    u + v
}

impl ClassicEvaluator {
    /// The [`Columns`] of octave `o` on the row `r` of `window` (`width` pixels, evaluated `L`
    /// at a time), or `None` where the basis hashes in the lanes (simplex, Worley) or the row
    /// visits more lattice columns than it has pixels (a minified render of small cells);
    /// `corners`: with 3D simplex noise's [`SimplexCorners`] ([`Fetch::CORNERS`]);
    /// `gradient_index`: 3D gradient noise by gradient index ([`Fetch::GRADIENT_INDEX`]).
    #[inline(always)]
    pub(super) fn columns<const L: usize, const B: u8>(
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
    pub(super) fn column_range<const L: usize>(
        o: &Octave,
        window: &Window,
        width: usize,
    ) -> (i32, i32) {
        let last_start = (width - 1) / L * L;
        let first = window.offset[0] + (window.x0 as f64) * window.scale;
        let last = window.offset[0]
            + ((window.x0 + last_start as i64) as f64 + (L - 1) as f64) * window.scale;
        (locate(first / o.side).0, locate(last / o.side).0)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use spectex_model::classic::gradient_dot;

    use super::{coded_gradient_dot, gradient_code, gradient_terms};

    /// The folded corner `((x & mask) ^ sign) + constant` is `gradient_dot` bit for bit, for
    /// every gradient index and signed zeros among the coordinates (the case `−0 + −0`).
    pub fn gradient_terms_fold_gradient_dot_exactly() {
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
    pub fn coded_gradient_dot_is_gradient_dot_exactly() {
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
