//! Lattice noises in the lanes: gradient (Perlin) and value noise, and Kensler noise.

use spectex_model::classic::{
    KENSLER2_SCALE, KENSLER3_SCALE, fade, gradient_dot, kensler_dot, kensler_weight, lattice_value,
};
use spectex_model::random::{cell_hash_in_row, row_key};

use super::ClassicEvaluator;
use super::fractal::{Octave, RowLanes};
use super::lanes::{Fetch, WINDOW, cell_units, fade_with, lerp, locate, locate_lanes};
use super::relaxed::locate_lanes_f32;
use super::tables::{Columns, window};

/// Lattice coordinate `v` as it enters the hash: wrapped into `0..n` for a periodic octave with
/// `n` cells per period (`spectex_model::period::wrap`), unchanged for `n = 0` (not periodic).
#[inline(always)]
pub(super) fn lattice(v: i32, n: i32) -> i32 {
    if n == 0 { v } else { v.rem_euclid(n) }
}

/// The lattice corners of row key `p` at columns `ix` and `ix + 1` of each lane (`ix` is the
/// column `lo + base + idx[l]`) from the [`Columns`] `t`; `ux`: the lanes' offsets in their
/// cells. `GRADIENT`: gradient noise, else value noise.
#[inline(always)]
pub(super) fn corners<const L: usize, F: Fetch<L>, const GRADIENT: bool>(
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

impl ClassicEvaluator {
    /// Gradient or value noise with the corner hashes read from the row's [`Columns`] `t`, the
    /// arithmetic of [`gradient2`] and [`gradient3`] otherwise; `false` (nothing written) when
    /// the lanes span `L` or more lattice columns, which one fetch cannot reach.
    #[inline(always)]
    pub(super) fn lattice_columns<
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
}

/// 2D gradient (`gradient = true`) or value noise in the lanes.
#[inline(always)]
pub(super) fn gradient2<const L: usize, R: RowLanes>(
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
pub(super) fn gradient3<const L: usize, R: RowLanes>(
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
pub(super) fn kensler<const L: usize, R: RowLanes>(
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
