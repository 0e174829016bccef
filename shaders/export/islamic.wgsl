// export/islamic.wgsl — the exported entry of an Islamic star pattern (after islamic.wgsl
// and export/split.wgsl; no lattice). The compute path's host splits each column and row in
// f64 into the lattice fractions frac(A·p + c) (spectex_model::islamic::LatticeMap). Here the
// position is an integer part n and a fraction u in [0, 1), and the fractions of A·n + c are
// summed in 32-bit fixed point (units of 2⁻³²), wrapping, which is arithmetic modulo 1: the
// exporter writes, per coefficient A_rc and bit k of n's two's complement (weight w_k = 2^k,
// w_31 = −2^31), `islamic_export_fixed[32·(2c + r) + k]` = frac(A_rc·w_k)·2³² rounded, and
// `islamic_export_c` the fractions of c the same way. The fraction A·u is added in f32 and
// the sum reduced to [0, 1) as the compute shader reduces it, then `islamic_at` runs the
// CPU's segment loop and output formula.
//
// Precision: each of the at most 65 fixed-point terms is within 2⁻³³ of its exact fraction
// (the sum within 2⁻²⁶, whatever |n|), its conversion to f32 and the f32 terms A·u (A rounded
// to f32, a product, a sum: 2·|A|·2⁻²⁴ per term) and the sum add a few units of 2⁻²⁴: the
// fractions s, t lie within (6 + 6·|A|)·2⁻²⁴ of the exact ones, as the CPU's lie within
// 2·2⁻²⁴, at (10⁷, 10⁷) as at the origin.

/// `Σ` over the set bits of `n` of the fixed-point table `table` (wrapping: modulo 1).
fn islamic_export_fixed_sum(n: i32, table: u32) -> u32 {
    let bits = bitcast<u32>(n);
    var acc = 0u;
    for (var k = 0u; k < 32u; k++) {
        if (((bits >> k) & 1u) == 1u) {
            acc += islamic_export_fixed[32u * table + k];
        }
    }
    return acc;
}

/// The pattern at the position `cell + offset` (pixels).
fn islamic_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let sf = islamic_export_fixed_sum(at.n.x, 0u) + islamic_export_fixed_sum(at.n.y, 1u)
        + islamic_export_c.x;
    let tf = islamic_export_fixed_sum(at.n.x, 2u) + islamic_export_fixed_sum(at.n.y, 3u)
        + islamic_export_c.y;
    var s = f32(sf) * 0x1p-32f + (params.a00 * at.u.x + params.a01 * at.u.y);
    var t = f32(tf) * 0x1p-32f + (params.a10 * at.u.x + params.a11 * at.u.y);
    s = s - floor(s);
    t = t - floor(t);
    // The segment count plus an opaque zero (the sign bit of u, which is never negative), so
    // that a compiler does not unroll the loop over hundreds of constant segments. (A
    // precaution: lavapipe's slow compile of islamic-31212-filled, over 8 minutes, persisted
    // with it and came from the 3024-float table as a private array; through the storage
    // buffer the module compiles and renders in about a second.)
    let opaque = bitcast<u32>(at.u.x) >> 31u;
    return islamic_at(s, t, params.segments + opaque);
}
