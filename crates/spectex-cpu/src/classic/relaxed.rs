//! The bench-only relaxed path (f32 cell split, FMA), to measure what the guarantees cost.
//!
//! Its entry points (`ClassicEvaluator::set_relaxed`, the relaxed rows) exist only with the
//! `relaxed` feature; the helpers below stay compiled, as the lane code names them under
//! `if RELAXED`, which no instantiation sets without it.

#[cfg(feature = "relaxed")]
use spectex_model::Window;
use spectex_model::classic::{SIMPLEX_F2, SIMPLEX_F3, SIMPLEX_G2, SIMPLEX_G3};
#[cfg(feature = "relaxed")]
use spectex_model::filter::OctaveFade;

#[cfg(feature = "relaxed")]
use super::ClassicEvaluator;
#[cfg(feature = "relaxed")]
use super::fractal::RowOctave;
use super::fractal::{Octave, RowLanes};
use super::lanes::Fetch;
#[cfg(all(feature = "relaxed", target_arch = "x86_64"))]
use super::lanes::{LANES, Permute8};
use super::simplex::{
    Simplex2At, Simplex3At, SimplexColumns, simplex_window, simplex2_sum, simplex3_corners,
    simplex3_sum,
};
use super::tables::window;
#[cfg(all(feature = "relaxed", target_arch = "x86_64"))]
use super::{GRADIENT, KENSLER, SIMPLEX, VALUE, WORLEY};
#[cfg(feature = "relaxed")]
use crate::lrp::Simd;
#[cfg(all(feature = "relaxed", target_arch = "x86_64"))]
use spectex_model::classic::Basis;

#[cfg(feature = "relaxed")]
impl ClassicEvaluator {
    /// Bench only, never reachable from a model (no model field or constructor sets it): gives
    /// up two of the guarantees to measure what they cost. Positions are split into cells in
    /// f32 (`x as f32 / side`, exact only while `x / side` keeps its fraction in 24 bits: far
    /// from the origin the offsets lose precision) instead of f64, and the interpolations,
    /// fades and distances use fused multiply-adds (other bits than the portable path). Lattice
    /// and simplex octaves with per-row tables and Worley octaves with a fixed count change; the
    /// rest keep the exact path. Needs AVX2 and FMA: returns whether the CPU has them (nothing
    /// changes where it does not). Only with the bench-only `relaxed` feature.
    #[doc(hidden)]
    pub fn set_relaxed(&mut self, relaxed: bool) -> bool {
        #[cfg(target_arch = "x86_64")]
        let available = Simd::detect() != Simd::Portable && is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let available = false;
        self.relaxed = relaxed && available;
        available
    }

    /// [`row_avx2`](Self::row_avx2) with the f32 split and FMA ([`set_relaxed`](Self::set_relaxed)).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn row_relaxed(
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
    pub(super) fn row_relaxed_avx512(
        &self,
        window: &Window,
        rows: &[RowOctave],
        out: &mut [f32],
        w: Option<&OctaveFade>,
        columns: bool,
    ) {
        self.row_wide::<true>(window, rows, out, w, columns);
    }
}

/// `1.5·2²³`: `(p + M) − M` rounds an f32 of magnitude below 2²² to the nearest integer (the
/// relaxed path's split).
pub(super) const ROUND_MAGIC_F32: f32 = 12_582_912.0;

/// The relaxed path's [`locate_lanes`]: `x / side` and its split in f32 (`x` already f32).
#[inline(always)]
pub(super) fn locate_lanes_f32<const L: usize>(
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
pub(super) fn split_lanes_f32<const L: usize>(p: &[f32; L], i: &mut [i32; L], f: &mut [f32; L]) {
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
pub(super) fn simplex_relaxed<const L: usize, F: Fetch<L>, R: RowLanes>(
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
