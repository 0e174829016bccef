//! SIMD plumbing: lane widths, positions split into cells, shared arithmetic, table fetches.

use spectex_model::classic::fade;

use super::ClassicEvaluator;
#[cfg(target_arch = "x86_64")]
use super::avx512;
use super::fractal::{Octave, RowLanes};
use super::relaxed::simplex_relaxed;
use super::simplex::{SimplexColumns, simplex3, simplex3_table};
use super::tables::Columns;

/// Pixels evaluated together by the portable and AVX2 paths.
pub(super) const LANES: usize = 8;
/// Pixels of one AVX-512 register.
pub(super) const WIDE_LANES: usize = 16;
/// Pixels evaluated together by the AVX-512 row: two registers per step, so that two
/// independent chains of lerps overlap (one register's chain left the core waiting).
pub(super) const WIDER_LANES: usize = 32;
/// Entries of a [`Columns`] table the lanes read at once (at least `WIDER_LANES + 1`), and the
/// padding after its columns.
pub(super) const WINDOW: usize = 64;

/// `1.5·2⁵²`: `(p + M) − M` rounds an f64 of magnitude below 2⁵¹ to the nearest integer, and
/// the low 32 bits of `p + M` are that integer in two's complement.
pub(super) const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;

/// `(⌊p⌋ as i32, ⌊p⌋)` for `|p| < 2³¹`, without a `floor` call (the same value as `f64::floor`).
#[inline(always)]
pub(super) fn split(p: f64) -> (i32, f64) {
    let m = p + ROUND_MAGIC;
    let r = m - ROUND_MAGIC;
    let above = r > p;
    let i = (m.to_bits() as u32 as i32).wrapping_sub(i32::from(above));
    (i, if above { r - 1.0 } else { r })
}

/// Cell and f32 offset of `p` (cell units).
#[inline(always)]
pub(super) fn locate(p: f64) -> (i32, f32) {
    let (i, f) = split(p);
    (i, (p - f) as f32)
}

/// [`locate`] in the lanes, written as one simple loop per step so that it vectorises (the
/// same operations, so the same bits).
#[inline(always)]
pub(super) fn locate_lanes<const L: usize>(p: &[f64; L], ix: &mut [i32; L], ux: &mut [f32; L]) {
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
pub(super) fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

#[inline(always)]
pub(super) fn max(a: f32, b: f32) -> f32 {
    if a < b { b } else { a }
}

/// How a group of `L` lanes reads `window[idx[l]]` (`idx[l] < L`, `window.len() ≥ L`): by
/// index in the portable build, by one register permute with AVX2 or AVX-512. All three give
/// the same integers; only the instructions differ.
pub(super) trait Fetch<const L: usize> {
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
pub(super) struct Indexed;

impl<const L: usize> Fetch<L> for Indexed {
    #[inline(always)]
    fn fetch(window: &[u32], idx: &[u32; L]) -> [u32; L] {
        std::array::from_fn(|l| window[idx[l] as usize % L])
    }
}

/// [`Fetch`] by `vpermd` (AVX2, 8 lanes).
#[cfg(target_arch = "x86_64")]
pub(super) struct Permute8;

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
pub(super) fn permute8(window: &[u32], idx: &[u32; LANES]) -> [u32; LANES] {
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
        pub(super) struct $name;

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
pub(super) fn registers<T>(lanes: &[T; WIDER_LANES]) -> &[[T; WIDE_LANES]; 2] {
    <&[[T; WIDE_LANES]; 2]>::try_from(lanes.as_chunks().0)
        .unwrap_or_else(|_| unreachable!("32 lanes are two chunks of 16"))
}

/// [`registers`] of lanes to write.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn registers_mut<T>(lanes: &mut [T; WIDER_LANES]) -> &mut [[T; WIDE_LANES]; 2] {
    <&mut [[T; WIDE_LANES]; 2]>::try_from(lanes.as_chunks_mut().0)
        .unwrap_or_else(|_| unreachable!("32 lanes are two chunks of 16"))
}

/// [`Fetch::accumulate`] as one multiply and one add per 16 lanes (AVX-512F; `L` a multiple
/// of 16): LLVM's own vectorisation of the loop split it into 8-, 4- and 1-lane pieces that
/// reread `n` from the stack, a quarter of a Perlin row's time.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
pub(super) fn accumulate512<const L: usize>(acc: &mut [f32; L], w: f32, n: &[f32; L]) {
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
pub(super) fn permute32(window: &[u32], idx: &[u32; WIDER_LANES]) -> [u32; WIDER_LANES] {
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
pub(super) fn permute16(window: &[u32], idx: &[u32; WIDE_LANES]) -> [u32; WIDE_LANES] {
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

/// `a·b + c`, fused (one rounding) when `FMA`: only the bench-only relaxed path
/// ([`ClassicEvaluator::set_relaxed`]) passes `true`.
#[inline(always)]
#[allow(
    clippy::disallowed_methods,
    reason = "the bench-only relaxed path measures what giving up the no-FMA guarantee saves"
)]
pub(super) fn fused_if<const FMA: bool>(a: f32, b: f32, c: f32) -> f32 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// `a·b + c` with one rounding (the relaxed path only).
#[inline(always)]
pub(super) fn fused(a: f32, b: f32, c: f32) -> f32 {
    fused_if::<true>(a, b, c)
}

/// `a + t·(b − a)`, the product and sum fused when `FMA`.
#[inline(always)]
pub(super) fn lerp<const FMA: bool>(a: f32, b: f32, t: f32) -> f32 {
    if FMA {
        fused(t, b - a, a)
    } else {
        a + t * (b - a)
    }
}

/// [`fade`], its polynomial's steps fused when `FMA`.
#[inline(always)]
pub(super) fn fade_with<const FMA: bool>(t: f32) -> f32 {
    if FMA {
        t * t * t * fused(t, fused(t, 6.0, -15.0), 10.0)
    } else {
        fade(t)
    }
}

/// [`split`] in the lanes, one simple loop per step so that it vectorises (the same
/// operations, so the same bits): the cells `i` and their floors `f`.
#[inline(always)]
pub(super) fn split_lanes<const L: usize>(p: &[f64; L], i: &mut [i32; L], f: &mut [f64; L]) {
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
pub(super) fn floor_cells<const L: usize>(f: &[f64; L], i: &mut [i32; L]) {
    for l in 0..L {
        i[l] = (f[l] + ROUND_MAGIC).to_bits() as u32 as i32;
    }
}

/// `x / side` in the lanes (by the exact reciprocal where the octave has one).
#[inline(always)]
pub(super) fn cell_units<const L: usize>(o: &Octave, x: &[f64; L]) -> [f64; L] {
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
