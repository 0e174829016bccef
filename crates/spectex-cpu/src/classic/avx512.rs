//! Hand-written AVX-512 kernels of the classic row, for the bases where LLVM's vectorisation of
//! the lane loops lost most of the machine: 3D simplex noise and 3D gradient and value noise,
//! two registers of 16 lanes at a time. Simplex gathers each lane's cube from the row's
//! `SimplexCorners` where every lane's corners are in it (one word, the gradient codes of its
//! eight corners) and shifts each corner's code out of it; gradient noise reads a row's gradient
//! indices and each row key's 16 terms (`GradientTerms`) by two permutes.
//!
//! Written with the lane loops' arrays, 3D simplex kept its skew's halves (16 f64 lanes are two
//! registers) and its offsets on the stack, and read them back as whole registers: a load
//! spanning several narrower stores cannot be forwarded from them, so it waited for them to
//! retire, and every group of lanes waited for the one before. Here every value stays in a
//! register from the position to the sum.
//!
//! Each function computes the very operations of its generic twin in the same order (`max` as
//! `_mm512_max_ps(0, t)`, which returns `t` wherever `t < 0` is false, as `lanes::max` does;
//! selects as masked operations), so the bits are the same, with two departures whose comments
//! show them exact: [`floor_pair`]'s floor instruction, and the coded gradient's `±x ± y` for
//! the reference's `±y ± x` (`tables::gradient_code`). `fast_paths` and the classic tests
//! compare this path with the portable and reference ones.

use std::arch::x86_64::{
    __m256, __m512, __m512d, __m512i, __mmask16, _CMP_GE_OQ, _CMP_GT_OQ, _mm_cvtsi128_si32,
    _mm_extract_epi32, _mm256_castps_pd, _mm256_setzero_ps, _mm512_add_epi32, _mm512_add_pd,
    _mm512_add_ps, _mm512_and_si512, _mm512_castpd_ps, _mm512_castpd_si512, _mm512_castps_pd,
    _mm512_castps_si512, _mm512_castps256_ps512, _mm512_castsi512_ps, _mm512_castsi512_si128,
    _mm512_cmp_pd_mask, _mm512_cmp_ps_mask, _mm512_cmpeq_epi32_mask, _mm512_cmplt_epi32_mask,
    _mm512_cvtpd_ps, _mm512_div_pd, _mm512_div_ps, _mm512_extracti32x4_epi32, _mm512_fmadd_ps,
    _mm512_i32gather_epi32, _mm512_insertf64x4, _mm512_loadu_pd, _mm512_loadu_ps,
    _mm512_loadu_si512, _mm512_mask_add_epi32, _mm512_mask_blend_epi32, _mm512_mask_blend_ps,
    _mm512_mask_cmplt_epu32_mask, _mm512_mask_sub_epi32, _mm512_mask_sub_pd, _mm512_mask_sub_ps,
    _mm512_max_ps, _mm512_mul_pd, _mm512_mul_ps, _mm512_mullo_epi32, _mm512_permutex2var_epi32,
    _mm512_permutexvar_epi32, _mm512_roundscale_pd, _mm512_set1_epi32, _mm512_set1_pd,
    _mm512_set1_ps, _mm512_setr_epi32, _mm512_setzero_pd, _mm512_setzero_ps, _mm512_setzero_si512,
    _mm512_slli_epi32, _mm512_sllv_epi32, _mm512_srli_epi32, _mm512_srlv_epi32, _mm512_storeu_ps,
    _mm512_sub_epi32, _mm512_sub_pd, _mm512_sub_ps, _mm512_ternarylogic_epi32,
    _mm512_test_epi32_mask, _mm512_testn_epi32_mask, _mm512_xor_si512,
};

use spectex_model::classic::{SIMPLEX_F3, SIMPLEX_G3, SIMPLEX3_R2, SIMPLEX3_SCALE};
use spectex_model::random::{LCG_INCREMENT, LCG_MULTIPLIER, RXS_M_XS_MULTIPLIER};

use super::fractal::{Octave, RowLanes};
use super::lanes::{ROUND_MAGIC, WIDE_LANES, WINDOW};
use super::relaxed::ROUND_MAGIC_F32;
use super::simplex::{CORNER_D, CORNER_E, SimplexColumns, SimplexCorners};
use super::tables::{Columns, GradientTerms, window};

/// The lanes of one register of f32.
const L: usize = WIDE_LANES;

// [`entries`] multiplies by the corner table's sizes as shifts.
const _: () = assert!(CORNER_E.is_power_of_two() && CORNER_D.is_power_of_two());

#[inline]
#[target_feature(enable = "avx512f")]
fn splat(v: u32) -> __m512i {
    _mm512_set1_epi32(v as i32)
}

/// [`spectex_model::random::hash`] in 16 lanes.
#[inline]
#[target_feature(enable = "avx512f")]
fn hash(v: __m512i) -> __m512i {
    let state = _mm512_add_epi32(
        _mm512_mullo_epi32(v, splat(LCG_MULTIPLIER)),
        splat(LCG_INCREMENT),
    );
    let shift = _mm512_add_epi32(_mm512_srli_epi32::<28>(state), splat(4));
    let word = _mm512_mullo_epi32(
        _mm512_xor_si512(_mm512_srlv_epi32(state, shift), state),
        splat(RXS_M_XS_MULTIPLIER),
    );
    _mm512_xor_si512(_mm512_srli_epi32::<22>(word), word)
}

/// 16 lanes of f32 from two halves of 8.
#[inline]
#[target_feature(enable = "avx512f")]
fn join_ps(lo: __m256, hi: __m256) -> __m512 {
    _mm512_castpd_ps(_mm512_insertf64x4::<1>(
        _mm512_castps_pd(_mm512_castps256_ps512(lo)),
        _mm256_castps_pd(hi),
    ))
}

/// `lanes::split_lanes` of 16 f64 lanes in two halves of 8: the floors' `i32` cells (the low
/// words of `p + magic`, one less where that rounded up, as `lanes::split` takes them) and the
/// floors of each half.
#[inline]
#[target_feature(enable = "avx512f")]
fn split_pair(p: [__m512d; 2]) -> (__m512i, [__m512d; 2]) {
    let magic = _mm512_set1_pd(ROUND_MAGIC);
    let m = [_mm512_add_pd(p[0], magic), _mm512_add_pd(p[1], magic)];
    let mut up = [0u8; 2];
    let mut f = [_mm512_setzero_pd(); 2];
    for h in 0..2 {
        let r = _mm512_sub_pd(m[h], magic);
        up[h] = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(r, p[h]);
        f[h] = _mm512_mask_sub_pd(r, up[h], r, _mm512_set1_pd(1.0));
    }
    // The even 32-bit words of both halves: the low words of the 16 lanes.
    let low = _mm512_permutex2var_epi32(
        _mm512_castpd_si512(m[0]),
        _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30),
        _mm512_castpd_si512(m[1]),
    );
    let up = u16::from(up[0]) | (u16::from(up[1]) << 8);
    (_mm512_mask_sub_epi32(low, up, low, splat(1)), f)
}

/// [`split_pair`] by `vrndscalepd`, for `|p| < 2⁵¹` (`SimplexColumns::bounded`): two
/// instructions and a shorter chain than the magic number's four; the cells are the low words
/// of `f + magic`. The floors are `split`'s except at `p = −0` (−0 here, +0 there), which
/// never changes a cell or an offset of the simplex skew, `x0 = px − (fi − t)` with
/// `t = (fi + fj + fk)·G3`: `a = px + s` is −0 only where `px` and `s` are. Where `fj + fk`
/// is not zero, `fi − t = −t` for either floor. Where `fj = fk = 0`, `s = ((px + py) + pz)·F3`
/// is −0 only if `py + pz` is −0 (then all three floors are −0 and `fi − t` is
/// `−0 − (−0) = +0`, as `+0 − +0`) or a negative that small (`py`, `pz` tiny, one negative, so
/// its floor is −1, not 0). `fj = −fk ≠ 0` with `py + pz` tiny cannot be. Likewise for `fj`
/// and `fk`. (A valid window's `px` is never −0 anyway: `offset + (x0 + i)·scale`, `scale`
/// positive.)
#[inline]
#[target_feature(enable = "avx512f")]
fn floor_pair(p: [__m512d; 2]) -> (__m512i, [__m512d; 2]) {
    let magic = _mm512_set1_pd(ROUND_MAGIC);
    // Round down (1), no precision exception (8).
    let f = [
        _mm512_roundscale_pd::<0x09>(p[0]),
        _mm512_roundscale_pd::<0x09>(p[1]),
    ];
    // The even 32-bit words of both halves: the low words of the 16 lanes' `f + magic`.
    let low = _mm512_permutex2var_epi32(
        _mm512_castpd_si512(_mm512_add_pd(f[0], magic)),
        _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30),
        _mm512_castpd_si512(_mm512_add_pd(f[1], magic)),
    );
    (low, f)
}

/// The skew of 16 lanes in two halves of 8 (`simplex::simplex3_at`): cells `(i, j, k)` and
/// offsets `(x0, y0, z0)`; `BOUNDED`: the floors by [`floor_pair`].
#[inline]
#[target_feature(enable = "avx512f")]
fn skew3<const BOUNDED: bool>(
    px: [__m512d; 2],
    py: [__m512d; 2],
    pz: f64,
) -> ([__m512i; 3], [__m512; 3]) {
    let pz = _mm512_set1_pd(pz);
    let mut s = [_mm512_setzero_pd(); 2];
    for h in 0..2 {
        s[h] = _mm512_mul_pd(
            _mm512_add_pd(_mm512_add_pd(px[h], py[h]), pz),
            _mm512_set1_pd(SIMPLEX_F3),
        );
    }
    let split = if BOUNDED { floor_pair } else { split_pair };
    let (i, fi) = split([_mm512_add_pd(px[0], s[0]), _mm512_add_pd(px[1], s[1])]);
    let (j, fj) = split([_mm512_add_pd(py[0], s[0]), _mm512_add_pd(py[1], s[1])]);
    let (k, fk) = split([_mm512_add_pd(pz, s[0]), _mm512_add_pd(pz, s[1])]);
    let mut offsets = [[_mm256_setzero_ps(); 2]; 3];
    for h in 0..2 {
        let t = _mm512_mul_pd(
            _mm512_add_pd(_mm512_add_pd(fi[h], fj[h]), fk[h]),
            _mm512_set1_pd(SIMPLEX_G3),
        );
        offsets[0][h] = _mm512_cvtpd_ps(_mm512_sub_pd(px[h], _mm512_sub_pd(fi[h], t)));
        offsets[1][h] = _mm512_cvtpd_ps(_mm512_sub_pd(py[h], _mm512_sub_pd(fj[h], t)));
        offsets[2][h] = _mm512_cvtpd_ps(_mm512_sub_pd(pz, _mm512_sub_pd(fk[h], t)));
    }
    (
        [i, j, k],
        [
            join_ps(offsets[0][0], offsets[0][1]),
            join_ps(offsets[1][0], offsets[1][1]),
            join_ps(offsets[2][0], offsets[2][1]),
        ],
    )
}

/// The relaxed path's skew of 16 lanes (`relaxed::simplex_relaxed`): in f32 from the f32
/// positions `xf` (pixels) of register `s` on the rows of `r`, cells `(i, j, k)` and offsets.
#[inline]
#[target_feature(enable = "avx512f")]
fn skew3_f32<R: RowLanes>(
    o: &Octave,
    r: &R,
    xf: &[f32; L],
    s: usize,
) -> ([__m512i; 3], [__m512; 3]) {
    let mut py = [0.0f32; L];
    for (l, p) in py.iter_mut().enumerate() {
        *p = r.py(L * s + l) as f32;
    }
    #[allow(unsafe_code)]
    // SAFETY: each load reads an array of 16 f32.
    let (x, py) = unsafe { (_mm512_loadu_ps(xf.as_ptr()), _mm512_loadu_ps(py.as_ptr())) };
    let px = _mm512_mul_ps(x, _mm512_set1_ps((1.0 / o.side) as f32));
    let pz = _mm512_set1_ps(o.pz as f32);
    let sk = _mm512_mul_ps(
        _mm512_add_ps(_mm512_add_ps(px, py), pz),
        _mm512_set1_ps(SIMPLEX_F3 as f32),
    );
    let (i, fi) = split_f32(_mm512_add_ps(px, sk));
    let (j, fj) = split_f32(_mm512_add_ps(py, sk));
    let (k, fk) = split_f32(_mm512_add_ps(pz, sk));
    let t = _mm512_mul_ps(
        _mm512_add_ps(_mm512_add_ps(fi, fj), fk),
        _mm512_set1_ps(SIMPLEX_G3 as f32),
    );
    (
        [i, j, k],
        [
            _mm512_sub_ps(px, _mm512_sub_ps(fi, t)),
            _mm512_sub_ps(py, _mm512_sub_ps(fj, t)),
            _mm512_sub_ps(pz, _mm512_sub_ps(fk, t)),
        ],
    )
}

/// `relaxed::split_lanes_f32` in 16 lanes: the floors' cells and the floors.
#[inline]
#[target_feature(enable = "avx512f")]
fn split_f32(p: __m512) -> (__m512i, __m512) {
    let magic = _mm512_set1_ps(ROUND_MAGIC_F32);
    let r = _mm512_sub_ps(_mm512_add_ps(p, magic), magic);
    let up = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(r, p);
    let f = _mm512_mask_sub_ps(r, up, r, _mm512_set1_ps(1.0));
    let cell = _mm512_sub_epi32(
        _mm512_castps_si512(_mm512_add_ps(f, magic)),
        _mm512_set1_epi32(ROUND_MAGIC_F32.to_bits() as i32),
    );
    (cell, f)
}

/// [`spectex_model::classic::gradient_dot`] in 16 lanes, the index `g = h >> 28` read from the
/// top bits of `h` where it is compared.
#[inline]
#[target_feature(enable = "avx512f")]
fn gradient_dot(h: __m512i, x: __m512, y: __m512, z: __m512) -> __m512 {
    // `g ≥ 8`: bit 31.
    let u = _mm512_mask_blend_ps(_mm512_cmplt_epi32_mask(h, _mm512_setzero_si512()), x, y);
    // `g == 12 || g == 14`: bits 3 and 2 set, bit 0 clear.
    let x_second = _mm512_cmpeq_epi32_mask(
        _mm512_and_si512(h, splat(0b1101 << 28)),
        splat(0b1100 << 28),
    );
    // `g < 4`: bits 3 and 2 clear.
    let v = _mm512_mask_blend_ps(
        _mm512_testn_epi32_mask(h, splat(0b1100 << 28)),
        _mm512_mask_blend_ps(x_second, z, x),
        y,
    );
    // Bit 28 of `h` (`g & 1`) to the sign of `u`, bit 29 (`g & 2`) to the sign of `v`.
    _mm512_add_ps(
        flip(u, _mm512_slli_epi32::<3>(h)),
        flip(v, _mm512_slli_epi32::<2>(h)),
    )
}

/// `tables::coded_gradient_dot` in 16 lanes: the gradient of a corner of the row's
/// `SimplexCorners`, two selects instead of [`gradient_dot`]'s three and its index tests.
#[inline]
#[target_feature(enable = "avx512f")]
fn coded_gradient_dot(c: __m512i, x: __m512, y: __m512, z: __m512) -> __m512 {
    let u = _mm512_mask_blend_ps(_mm512_test_epi32_mask(c, splat(1 << 29)), x, y);
    let v = _mm512_mask_blend_ps(_mm512_test_epi32_mask(c, splat(1 << 28)), y, z);
    // Bit 31 of `c` to the sign of `u`, bit 30 to the sign of `v`.
    _mm512_add_ps(flip(u, c), flip(v, _mm512_slli_epi32::<1>(c)))
}

/// `v` with its sign flipped where `bits` has bit 31.
#[inline]
#[target_feature(enable = "avx512f")]
fn flip(v: __m512, bits: __m512i) -> __m512 {
    // `v ^ (bits & sign)` in one instruction (truth table `A ^ (B & C)`).
    _mm512_castsi512_ps(_mm512_ternarylogic_epi32::<0x78>(
        _mm512_castps_si512(v),
        bits,
        splat(1 << 31),
    ))
}

/// `simplex::simplex_term` in 16 lanes, `d²` fused when `FMA` (the relaxed path), `h` a hash
/// or, `CODED`, its `gradient_code`.
#[inline]
#[target_feature(enable = "avx512f")]
fn term<const FMA: bool, const CODED: bool>(
    h: __m512i,
    dx: __m512,
    dy: __m512,
    dz: __m512,
) -> __m512 {
    let d2 = if FMA {
        _mm512_fmadd_ps(dx, dx, _mm512_fmadd_ps(dy, dy, _mm512_mul_ps(dz, dz)))
    } else {
        _mm512_add_ps(
            _mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)),
            _mm512_mul_ps(dz, dz),
        )
    };
    let t = _mm512_max_ps(
        _mm512_setzero_ps(),
        _mm512_sub_ps(_mm512_set1_ps(SIMPLEX3_R2), d2),
    );
    let t2 = _mm512_mul_ps(t, t);
    let dot = if CODED {
        coded_gradient_dot(h, dx, dy, dz)
    } else {
        gradient_dot(h, dx, dy, dz)
    };
    _mm512_mul_ps(_mm512_mul_ps(t2, t2), dot)
}

/// 3D simplex noise of `S` registers of 16 lanes (`simplex::simplex3_table`, else
/// `simplex::simplex3`): positions `x` (pixels) on the rows of `r` and the octave's plane, the
/// layer keys of the skewed planes read from the row's table `t` where one permute reaches
/// them, else hashed. The skew and the ranking run over the `S` registers before the next
/// step, so that their independent chains of latency overlap; the corners then go register by
/// register ([`sum`]). Plain loops
/// and functions, no closures: a closure does not inherit the `target_feature`, and its
/// register arguments went through memory.
#[inline]
#[target_feature(enable = "avx512f")]
pub(super) fn simplex3<const S: usize, R: RowLanes, const RELAXED: bool>(
    o: &Octave,
    r: &R,
    x: &[[f64; L]; S],
    xf: &[[f32; L]; S],
    t: Option<&SimplexColumns>,
    n: &mut [[f32; L]; S],
) {
    let zero = _mm512_setzero_si512();
    let mut cells = [[zero; 3]; S];
    let mut offsets = [[_mm512_setzero_ps(); 3]; S];
    for s in 0..S {
        (cells[s], offsets[s]) = if RELAXED {
            skew3_f32(o, r, &xf[s], s)
        } else {
            let px = [cell_units(o, x, s, 0), cell_units(o, x, s, 1)];
            let py = [rows_py(r, s, 0), rows_py(r, s, 1)];
            if t.is_some_and(|t| t.bounded) {
                skew3::<true>(px, py, o.pz)
            } else {
                skew3::<false>(px, py, o.pz)
            }
        };
    }

    // The corners' gradients: read from the row's corner table where every lane's corners
    // are in it, else hashed from the layer keys of the planes `k`, `k + 1`.
    if let Some(c) = t.and_then(|t| t.corners.as_ref())
        && let Some(entry) = entries::<S>(c, &cells)
    {
        let layers = [[zero; 2]; S];
        return sum::<S, true, RELAXED>(&c.cubes, &entry, &cells, &layers, &offsets, n);
    }
    hashed::<S, RELAXED>(o, t, &cells, &offsets, n);
}

/// The corners of [`simplex3`] hashed from the layer keys of the planes `k`, `k + 1`: read from
/// the row's plane keys where one permute reaches them, else hashed. Not inlined: merged into
/// [`simplex3`], LLVM shared the two paths' corner code behind a flag tested at every corner.
#[inline(never)]
#[target_feature(enable = "avx512f")]
fn hashed<const S: usize, const RELAXED: bool>(
    o: &Octave,
    t: Option<&SimplexColumns>,
    cells: &[[__m512i; 3]; S],
    offsets: &[[__m512; 3]; S],
    n: &mut [[f32; L]; S],
) {
    let zero = _mm512_setzero_si512();
    let one = splat(1);
    let mut layers = [[zero; 2]; S];
    if let Some((keys, first)) = t.and_then(|t| reach::<S>(t, cells)) {
        #[allow(unsafe_code)]
        // SAFETY: `reach` checked that `keys` holds `WINDOW` (≥ 33) entries.
        let (a0, b0, a1, b1) = unsafe {
            (
                _mm512_loadu_si512(keys.as_ptr().cast()),
                _mm512_loadu_si512(keys[L..].as_ptr().cast()),
                _mm512_loadu_si512(keys[1..].as_ptr().cast()),
                _mm512_loadu_si512(keys[L + 1..].as_ptr().cast()),
            )
        };
        for s in 0..S {
            let idx = _mm512_sub_epi32(cells[s][2], _mm512_set1_epi32(first));
            layers[s] = [
                _mm512_permutex2var_epi32(a0, idx, b0),
                _mm512_permutex2var_epi32(a1, idx, b1),
            ];
        }
    } else {
        for s in 0..S {
            let k = cells[s][2];
            layers[s] = [layer_key(o, k), layer_key(o, _mm512_add_epi32(k, one))];
        }
    }
    sum::<S, false, RELAXED>(&[], &[zero; S], cells, &layers, offsets, n);
}

/// The sum of the four corners' terms of `S` registers of 16 lanes, scaled, into `n`: the
/// corners' codes from the row's corner table `cubes` at the lanes' `entry` (`TABLE`), else
/// their hashes from the layer keys `layers`.
#[inline]
#[target_feature(enable = "avx512f")]
fn sum<const S: usize, const TABLE: bool, const FMA: bool>(
    cubes: &[u32],
    entry: &[__m512i; S],
    cells: &[[__m512i; 3]; S],
    layers: &[[__m512i; 2]; S],
    offsets: &[[__m512; 3]; S],
    n: &mut [[f32; L]; S],
) {
    // Gustavson's ranking as masks: the steps of the middle corners.
    let mut steps = [[[0; 3]; 2]; S];
    for s in 0..S {
        let [x0, y0, z0] = offsets[s];
        let a: __mmask16 = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(x0, y0);
        let b: __mmask16 = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(y0, z0);
        let c: __mmask16 = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(x0, z0);
        steps[s] = [
            [a & (b | c), !a & b, !b & (!a | !c)],
            [a | (b & c), b | !a, !b | (!a & !c)],
        ];
    }
    let g3 = SIMPLEX_G3 as f32;
    // One register's four corners, then the next's: interleaved, the registers' corners kept
    // more values live than the 32 vector and 7 mask registers hold (about 5% of a 3D simplex
    // row). The rankings of both come first: ranking each register just before its corners
    // lost as much.
    for s in 0..S {
        // The lanes' cubes, read once for the four corners (the hashed path has none).
        let cube = if TABLE {
            #[allow(unsafe_code)]
            // SAFETY: `entries` checked that every lane's entry is below the table's length.
            unsafe {
                _mm512_i32gather_epi32::<4>(entry[s], cubes.as_ptr().cast())
            }
        } else {
            _mm512_setzero_si512()
        };
        let h = corner_hash::<TABLE>(cube, &cells[s], &layers[s], [0; 3], 0);
        let mut total = corner_term::<FMA, TABLE>(h, &offsets[s], [0; 3], 0.0);
        for step in 0..2 {
            let off = (step + 1) as f32 * g3;
            let st = steps[s][step];
            let h = corner_hash::<TABLE>(cube, &cells[s], &layers[s], st, step as u32 + 1);
            total = _mm512_add_ps(total, corner_term::<FMA, TABLE>(h, &offsets[s], st, off));
        }
        let all = [u16::MAX; 3];
        let h = corner_hash::<TABLE>(cube, &cells[s], &layers[s], all, 3);
        let last = corner_term::<FMA, TABLE>(h, &offsets[s], all, 3.0 * g3);
        let v = _mm512_mul_ps(_mm512_set1_ps(SIMPLEX3_SCALE), _mm512_add_ps(total, last));
        #[allow(unsafe_code)]
        // SAFETY: the store writes 16 f32 (64 bytes) into a 16-lane array.
        unsafe {
            _mm512_storeu_ps(n[s].as_mut_ptr(), v);
        }
    }
}

/// The hash of corner `(i + di, j + dj, k + dk)` of 16 lanes, `steps` of `di, dj, dk` set in
/// every lane: its code from the lanes' `cube` of the row's corner table (`TABLE`), else its
/// hash from the layer keys of planes `k`, `k + 1`.
#[inline]
#[target_feature(enable = "avx512f")]
fn corner_hash<const TABLE: bool>(
    cube: __m512i,
    cells: &[__m512i; 3],
    layers: &[__m512i; 2],
    step: [__mmask16; 3],
    steps: u32,
) -> __m512i {
    if TABLE {
        table_code(cube, step, steps)
    } else {
        layer_hash(cells, layers, step)
    }
}

/// The rows' `py` of lanes `8h..8h + 8` of register `s`.
#[inline]
#[target_feature(enable = "avx512f")]
fn rows_py<R: RowLanes>(r: &R, s: usize, h: usize) -> __m512d {
    let mut py = [0.0f64; 8];
    for (l, p) in py.iter_mut().enumerate() {
        *p = r.py(L * s + 8 * h + l);
    }
    #[allow(unsafe_code)]
    // SAFETY: the load reads an array of 8 f64.
    unsafe {
        _mm512_loadu_pd(py.as_ptr())
    }
}

/// The positions of lanes `8h..8h + 8` of register `s` (`x` in pixels) in cell units
/// (`lanes::cell_units`).
#[inline]
#[target_feature(enable = "avx512f")]
fn cell_units<const S: usize>(o: &Octave, x: &[[f64; L]; S], s: usize, h: usize) -> __m512d {
    #[allow(unsafe_code)]
    // SAFETY: the load reads lanes `8h..8h + 8` of an array of 16 f64, `h` ≤ 1.
    let x = unsafe { _mm512_loadu_pd(x[s][8 * h..].as_ptr()) };
    match o.inv_side {
        Some(inv) => _mm512_mul_pd(x, _mm512_set1_pd(inv)),
        None => _mm512_div_pd(x, _mm512_set1_pd(o.side)),
    }
}

/// `layer_key(o.layer, cell_hash_in_row(k, o.key0))` of the planes `k`.
#[inline]
#[target_feature(enable = "avx512f")]
fn layer_key(o: &Octave, k: __m512i) -> __m512i {
    let seed = hash(_mm512_add_epi32(k, splat(o.key0)));
    hash(_mm512_add_epi32(splat(o.layer), hash(seed)))
}

/// The hash of corner `(i + di, j + dj, k + dk)` of the cells of 16 lanes, from the layer keys
/// `[l0, l1]` of planes `k`, `k + 1`.
#[inline]
#[target_feature(enable = "avx512f")]
fn layer_hash(
    [i, j, _]: &[__m512i; 3],
    [l0, l1]: &[__m512i; 2],
    [di, dj, dk]: [__mmask16; 3],
) -> __m512i {
    let one = splat(1);
    let layer = _mm512_mask_blend_epi32(dk, *l0, *l1);
    let row = hash(_mm512_add_epi32(
        _mm512_mask_add_epi32(*j, dj, *j, one),
        layer,
    ));
    hash(_mm512_add_epi32(
        _mm512_mask_add_epi32(*i, di, *i, one),
        row,
    ))
}

/// `SimplexCorners::entries` of 16 lanes of each of `S` registers, or `None` when a corner of a
/// lane falls outside the table.
#[inline]
#[target_feature(enable = "avx512f")]
fn entries<const S: usize>(c: &SimplexCorners, cells: &[[__m512i; 3]; S]) -> Option<[__m512i; S]> {
    let mut inside: __mmask16 = u16::MAX;
    let mut entry = [_mm512_setzero_si512(); S];
    for s in 0..S {
        let [i, j, k] = cells[s];
        let w = _mm512_sub_epi32(j, splat(c.j_lo as u32));
        let d = _mm512_sub_epi32(_mm512_sub_epi32(k, j), splat(c.d_lo.wrapping_add(1) as u32));
        let e = _mm512_sub_epi32(
            _mm512_sub_epi32(i, _mm512_slli_epi32::<2>(j)),
            splat(c.e_lo.wrapping_add(4) as u32),
        );
        inside = _mm512_mask_cmplt_epu32_mask(inside, w, splat(c.rows - 1));
        inside = _mm512_mask_cmplt_epu32_mask(inside, d, splat(2));
        inside = _mm512_mask_cmplt_epu32_mask(inside, e, splat(11));
        // `(w·D + d + 1)·E + e + 4` (`SimplexCorners::entries`), by shifts.
        entry[s] = _mm512_add_epi32(
            _mm512_add_epi32(e, splat(4 + CORNER_E)),
            _mm512_add_epi32(
                _mm512_slli_epi32::<{ CORNER_E.trailing_zeros() }>(d),
                _mm512_slli_epi32::<{ (CORNER_D * CORNER_E).trailing_zeros() }>(w),
            ),
        );
    }
    (inside == u16::MAX).then_some(entry)
}

/// The code of corner `(i + di, j + dj, k + dk)` of 16 lanes from their `cube` of the row's
/// corner table: the cube shifted left by `28 − 4·(di + 2dj + 4dk)` (`SimplexCorners`). Each
/// lane steps along `steps` of the three axes (Gustavson's ranking steps along exactly one,
/// then exactly two, whatever the comparisons), so `dk = steps − di − dj` and the shift is
/// `28 − 16·steps + 12di + 8dj`: two masked adds.
#[inline]
#[target_feature(enable = "avx512f")]
fn table_code(cube: __m512i, [di, dj, _]: [__mmask16; 3], steps: u32) -> __m512i {
    let base = splat(28u32.wrapping_sub(16 * steps));
    let shift = _mm512_mask_add_epi32(base, di, base, splat(12));
    let shift = _mm512_mask_add_epi32(shift, dj, shift, splat(8));
    _mm512_sllv_epi32(cube, shift)
}

/// One corner's term of 16 lanes: corner `(i + di, j + dj, k + dk)` of hash `h` (`CODED`:
/// its `gradient_code`, read from the row's table), its offsets `(x0 − di) + off`.
#[inline]
#[target_feature(enable = "avx512f")]
fn corner_term<const FMA: bool, const CODED: bool>(
    h: __m512i,
    [x0, y0, z0]: &[__m512; 3],
    [di, dj, dk]: [__mmask16; 3],
    off: f32,
) -> __m512 {
    let off = _mm512_set1_ps(off);
    let onef = _mm512_set1_ps(1.0);
    term::<FMA, CODED>(
        h,
        _mm512_add_ps(_mm512_mask_sub_ps(*x0, di, *x0, onef), off),
        _mm512_add_ps(_mm512_mask_sub_ps(*y0, dj, *y0, onef), off),
        _mm512_add_ps(_mm512_mask_sub_ps(*z0, dk, *z0, onef), off),
    )
}

/// `simplex::simplex_window` for the planes `cells[s][2]` of `S` registers: the table's entries
/// from the first lane's plane (at least [`WINDOW`]) and that plane, or `None` when one
/// permute of 32 entries cannot reach them.
#[inline]
#[target_feature(enable = "avx512f")]
fn reach<'t, const S: usize>(
    t: &'t SimplexColumns,
    cells: &[[__m512i; 3]; S],
) -> Option<(&'t [u32], i32)> {
    let first = _mm_cvtsi128_si32(_mm512_castsi512_si128(cells[0][2]));
    let last = _mm_extract_epi32::<3>(_mm512_extracti32x4_epi32::<3>(cells[S - 1][2]));
    let span = i64::from(last) - i64::from(first);
    let base = i64::from(first) - i64::from(t.lo);
    if !(0..(S * L) as i64).contains(&span) || base < 0 || base as usize + WINDOW > t.len {
        return None;
    }
    Some((&window(&t.keys, base as usize)[..], first))
}

/// [`spectex_model::classic::fade`] in 16 lanes: `t·t·t·(t·(t·6 − 15) + 10)`, the
/// polynomial's steps fused when `FMA` (`lanes::fade_with`).
#[inline]
#[target_feature(enable = "avx512f")]
fn fade<const FMA: bool>(t: __m512) -> __m512 {
    let inner = if FMA {
        _mm512_fmadd_ps(
            t,
            _mm512_fmadd_ps(t, _mm512_set1_ps(6.0), _mm512_set1_ps(-15.0)),
            _mm512_set1_ps(10.0),
        )
    } else {
        _mm512_add_ps(
            _mm512_mul_ps(
                t,
                _mm512_sub_ps(_mm512_mul_ps(t, _mm512_set1_ps(6.0)), _mm512_set1_ps(15.0)),
            ),
            _mm512_set1_ps(10.0),
        )
    };
    _mm512_mul_ps(_mm512_mul_ps(_mm512_mul_ps(t, t), t), inner)
}

/// `a + t·(b − a)` in 16 lanes (`lanes::lerp`), the product and sum fused when `FMA`.
#[inline]
#[target_feature(enable = "avx512f")]
fn lerp<const FMA: bool>(a: __m512, b: __m512, t: __m512) -> __m512 {
    if FMA {
        _mm512_fmadd_ps(t, _mm512_sub_ps(b, a), a)
    } else {
        _mm512_add_ps(a, _mm512_mul_ps(t, _mm512_sub_ps(b, a)))
    }
}

/// `relaxed::locate_lanes_f32` of 16 lanes: the relaxed path's cells and offsets from the f32
/// positions `xf`.
#[inline]
#[target_feature(enable = "avx512f")]
fn locate_f32(o: &Octave, xf: &[f32; L]) -> (__m512i, __m512) {
    #[allow(unsafe_code)]
    // SAFETY: the load reads an array of 16 f32.
    let x = unsafe { _mm512_loadu_ps(xf.as_ptr()) };
    let p = match o.inv_side {
        Some(inv) => _mm512_mul_ps(x, _mm512_set1_ps(inv as f32)),
        None => _mm512_div_ps(x, _mm512_set1_ps(o.side as f32)),
    };
    let (cell, f) = split_f32(p);
    (cell, _mm512_sub_ps(p, f))
}

/// `lanes::locate_lanes` of the 16 lanes of register `s` (`x` in pixels): their cells and f32
/// offsets in them.
#[inline]
#[target_feature(enable = "avx512f")]
fn locate<const S: usize>(o: &Octave, x: &[[f64; L]; S], s: usize) -> (__m512i, __m512) {
    let p = [cell_units(o, x, s, 0), cell_units(o, x, s, 1)];
    let (cell, f) = split_pair(p);
    let u = [
        _mm512_cvtpd_ps(_mm512_sub_pd(p[0], f[0])),
        _mm512_cvtpd_ps(_mm512_sub_pd(p[1], f[1])),
    ];
    (cell, join_ps(u[0], u[1]))
}

/// 3D gradient (`GRADIENT`) or value noise of `S` registers of 16 lanes with the corners read
/// from the row's [`Columns`] `t` (`super::ClassicEvaluator::lattice_columns`); `false`
/// (nothing written) when the lanes span 32 or more lattice columns, which one two-register
/// permute cannot reach. Each step runs over the `S` registers before the next, so that their
/// chains of lerps overlap.
///
/// `RELAXED`: the bench-only relaxed evaluator's arithmetic (`relaxed::locate_lanes_f32` from the
/// f32 positions `xf`, fused fades and lerps), so that what the guarantees cost is measured
/// against the same kernel.
#[inline]
#[target_feature(enable = "avx512f")]
pub(super) fn lattice3<
    const S: usize,
    R: RowLanes,
    const GRADIENT: bool,
    const RELAXED: bool,
    const BY_INDEX: bool,
>(
    o: &Octave,
    r: &R,
    x: &[[f64; L]; S],
    xf: &[[f32; L]; S],
    t: &Columns,
    terms: &GradientTerms,
    n: &mut [[f32; L]; S],
) -> bool {
    let mut cells = [_mm512_setzero_si512(); S];
    let mut ux = [_mm512_setzero_ps(); S];
    for s in 0..S {
        if RELAXED {
            (cells[s], ux[s]) = locate_f32(o, &xf[s]);
        } else {
            (cells[s], ux[s]) = locate(o, x, s);
        }
    }
    let first = _mm_cvtsi128_si32(_mm512_castsi512_si128(cells[0]));
    let last = _mm_extract_epi32::<3>(_mm512_extracti32x4_epi32::<3>(cells[S - 1]));
    let span = i64::from(last) - i64::from(first);
    let base = i64::from(first) - i64::from(t.lo);
    if !(0..(S * L) as i64).contains(&span) || base < 0 || base as usize + WINDOW > t.len {
        return false;
    }
    let base = base as usize;
    let mut idx = [_mm512_setzero_si512(); S];
    let mut sx = [_mm512_setzero_ps(); S];
    let mut sy = [_mm512_setzero_ps(); S];
    for s in 0..S {
        idx[s] = _mm512_sub_epi32(cells[s], _mm512_set1_epi32(first));
        sx[s] = fade::<RELAXED>(ux[s]);
        let mut uy = [0.0f32; L];
        for (l, u) in uy.iter_mut().enumerate() {
            *u = r.uy(L * s + l);
        }
        #[allow(unsafe_code)]
        // SAFETY: the load reads an array of 16 f32.
        let uy = unsafe { _mm512_loadu_ps(uy.as_ptr()) };
        sy[s] = fade::<RELAXED>(uy);
    }
    let sz = fade::<RELAXED>(_mm512_set1_ps(o.uz));
    let onef = _mm512_set1_ps(1.0);
    // Row key `p = 2·dz + dy` at a time, its corners lerped along x at once, so that few
    // registers are live (the corners of all four held at once spilled).
    let mut y = [[_mm512_setzero_ps(); S]; 2];
    for (dz, yz) in y.iter_mut().enumerate() {
        let mut ex = [[_mm512_setzero_ps(); S]; 2];
        for (dy, ey) in ex.iter_mut().enumerate() {
            let p = 2 * dz + dy;
            let at = p * t.len + base;
            // By gradient index: row key `p`'s terms of each `g`, read by a second permute.
            let by_index = if BY_INDEX {
                #[allow(unsafe_code)]
                // SAFETY: each load reads 16 `u32`, an array of 16.
                unsafe {
                    terms[p].map(|v| _mm512_loadu_si512(v.as_ptr().cast()))
                }
            } else {
                [_mm512_setzero_si512(); 3]
            };
            let mut c = [[_mm512_setzero_ps(); S]; 2];
            for (dx, cx) in c.iter_mut().enumerate() {
                let constant = load_pair(window(&t.constant, at), dx);
                for s in 0..S {
                    let entry = pick(&constant, idx[s]);
                    cx[s] = if GRADIENT {
                        let (mask, sign, k) = if BY_INDEX {
                            (
                                _mm512_permutexvar_epi32(entry, by_index[0]),
                                _mm512_permutexvar_epi32(entry, by_index[1]),
                                _mm512_permutexvar_epi32(entry, by_index[2]),
                            )
                        } else {
                            let (mask, sign) = (
                                load_pair(window(&t.mask, at), dx),
                                load_pair(window(&t.sign, at), dx),
                            );
                            (pick(&mask, idx[s]), pick(&sign, idx[s]), entry)
                        };
                        let u = if dx == 0 {
                            ux[s]
                        } else {
                            _mm512_sub_ps(ux[s], onef)
                        };
                        // `((u & mask) ^ sign) + constant`.
                        let bits =
                            _mm512_ternarylogic_epi32::<0x6A>(_mm512_castps_si512(u), mask, sign);
                        _mm512_add_ps(_mm512_castsi512_ps(bits), _mm512_castsi512_ps(k))
                    } else {
                        _mm512_castsi512_ps(entry)
                    };
                }
            }
            for s in 0..S {
                ey[s] = lerp::<RELAXED>(c[0][s], c[1][s], sx[s]);
            }
        }
        for s in 0..S {
            yz[s] = lerp::<RELAXED>(ex[0][s], ex[1][s], sy[s]);
        }
    }
    for s in 0..S {
        #[allow(unsafe_code)]
        // SAFETY: the store writes 16 f32 (64 bytes) into a 16-lane array.
        unsafe {
            _mm512_storeu_ps(n[s].as_mut_ptr(), lerp::<RELAXED>(y[0][s], y[1][s], sz));
        }
    }
    true
}

/// Entries `dx..dx + 16` and `dx + 16..dx + 32` of a table window: the two sources of a
/// 32-entry permute.
#[inline]
#[target_feature(enable = "avx512f")]
fn load_pair(w: &[u32; WINDOW], dx: usize) -> [__m512i; 2] {
    #[allow(unsafe_code)]
    // SAFETY: each load reads 16 `u32` from an offset of at most 17 in a window of 64
    // (`dx` ≤ 1).
    unsafe {
        [
            _mm512_loadu_si512(w[dx..].as_ptr().cast()),
            _mm512_loadu_si512(w[dx + L..].as_ptr().cast()),
        ]
    }
}

/// Entry `idx[l]` (< 32) of the 32 entries `v` in each lane.
#[inline]
#[target_feature(enable = "avx512f")]
fn pick(v: &[__m512i; 2], idx: __m512i) -> __m512i {
    _mm512_permutex2var_epi32(v[0], idx, v[1])
}
