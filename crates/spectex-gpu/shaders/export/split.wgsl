// export/split.wgsl — locating an integer pixel coordinate on a lattice without f64, for the
// modules `spectex export --wgsl` writes (one copy per exported model, under its prefix).
//
// The CPU locates a position x (f64, pixels) on a lattice of side Δ as the cell c = ⌊x/Δ⌋ and
// offsets f32(x − (c + k)·Δ). A fragment shader has only f32 and i32, so the exported entry
// points take x as an integer n (i32) plus an f32 fraction u, and the integer part is located
// here from tables the exporter computes in f64 for each lattice l of the model:
//     export_sides[l]                  Δ_l rounded to f32,
//     export_inv_sides[l]              1/Δ_l rounded to f32 (for offsets in lattice units),
//     export_quotients[32·l + k]       ⌊w_k / Δ_l⌋ mod 2³² (u32, wrapping),
//     export_remainders[32·l + k]      w_k − ⌊w_k / Δ_l⌋·Δ_l in [0, Δ_l), rounded to f32,
//     export_whole[l / 32] bit l % 32  Δ_l is a whole number of pixels up to 2²⁴ (then the
//                                      split is an integer division instead),
// with w_k = 2^k the weight of bit k of n's two's complement (w_31 = −2^31). Summing the terms
// of n's set bits, the remainder reduced by Δ at each step, gives n = q·Δ + r with q wrapped to
// 32 bits like the CPU's i32 cells. That sum is a 32-step loop reading the tables at a
// data-dependent index: the fallback, for lattices below 1 pixel or above 2²⁴ (whose tables
// are the only ones emitted). Every other lattice is split in closed form (`export_modular`):
//     export_modular[l]                Δ_l rounded to f32 as M·2^−s (M an integer ≤ 2²⁴,
//                                      0 ≤ s ≤ 23), 2^s mod M, ⌊2^s / M⌋, f32(Δ_l − f32(Δ_l)),
// n = q_a·M + a in integers, then a·2^s = (a·⌊2^s/M⌋)·M + a·(2^s mod M) with the last product
// reduced mod M from an f32 estimate of its quotient and the exact u32 residue: the exact
// quotient and remainder of n by f32(Δ_l), what the tables sum where Δ_l is an f32; where
// it is not, the remainder then takes `q·(Δ_l − f32(Δ_l))` off (a number below 2⁻²⁴·|n|) in
// one rounding and carries into the neighbouring cell if that crosses it.
//
// Exactness: where Δ is an f32 (LRP's Δ_s, a texton cell), every remainder is a multiple of
// Δ's last-bit unit below Δ, hence an f32, and each step (r + r_k, or r − (Δ − r_k) when that
// reaches Δ) is exact: r is n mod Δ exactly, whatever n; the closed form's integer remainder
// times 2^−s is the same number. Where Δ is only an f64 (a Gabor kernel radius, simplex's skew
// lattices), each table remainder carries at most half an f32 ulp of Δ, so r is within 16
// ulp(Δ) of the truth; the closed form's, within two roundings of a number below Δ plus
// 2⁻⁴⁸·|n|. Either way the error does not grow with |n| beyond that: a point at 10⁷ pixels is
// located as precisely as one at the origin.

/// A lattice's closed-form split (see the header): `f32(Δ) = modulus·2^−s`.
struct ExportModular {
    /// M (0: the lattice is split by the tables).
    modulus: i32,
    /// 1/M rounded to f32 (the estimates of quotients by M).
    inv_modulus: f32,
    /// 2^s.
    power: u32,
    /// 2^s mod M.
    power_rem: u32,
    /// ⌊2^s / M⌋.
    power_quot: u32,
    /// (2^s mod M)/M rounded to f32.
    power_frac: f32,
    /// 2^−s.
    scale: f32,
    /// Δ − f32(Δ) rounded to f32 (0 where Δ is an f32).
    low: f32,
}

/// An integer coordinate's lattice cell and its remainder `n − cell·Δ` in `[0, Δ)`.
struct ExportSplit {
    cell: i32,
    rem: f32,
}

/// `n` on lattice `lattice`: `n = cell·Δ + rem` (see the header). A loop of 32 steps with
/// the bit index as its counter: a driver that unrolls it (and inlines a constant `lattice`)
/// reads the tables at constant indices and keeps them out of memory, which a data-dependent
/// index (iterating the set bits only, say) would not.
fn export_split(n: i32, lattice: u32) -> ExportSplit {
    let side = export_sides[lattice];
    if (((export_whole[lattice >> 5u] >> (lattice & 31u)) & 1u) == 1u) {
        // Δ a whole number of pixels (1 to 2²⁴, exactly): floor division in integers, the
        // exact `n mod Δ` the tables would sum, in a few operations (and, where `lattice` is
        // a constant, a division by a constant).
        let d = i32(side);
        var q = n / d;
        var r = n - q * d;
        if (r < 0i) {
            q -= 1i;
            r += d;
        }
        return ExportSplit(q, f32(r));
    }
    if (export_modular[lattice].modulus != 0i) {
        return export_split_modular(n, lattice);
    }
    let bits = bitcast<u32>(n);
    var q = 0u;
    var r = 0.0f;
    for (var k = 0u; k < 32u; k++) {
        if (((bits >> k) & 1u) == 1u) {
            let i = lattice * 32u + k;
            q += export_quotients[i];
            let rk = export_remainders[i];
            let room = side - rk;
            if (r >= room) {
                r = r - room;
                q += 1u;
            } else {
                r = r + rk;
            }
        }
    }
    return ExportSplit(bitcast<i32>(q), r);
}

/// `export_split` of a lattice of side 1 to 2²⁴ pixels in closed form (see the header).
fn export_split_modular(n: i32, lattice: u32) -> ExportSplit {
    let k = export_modular[lattice];
    let m = k.modulus;
    // n = qa·M + a, 0 ≤ a < M: an f32 estimate of the quotient (off by at most 2⁻²²·|n|/M + 1),
    // the exact residue under it (i32 wrapping), a second estimate from that residue (below
    // 2²⁴ in magnitude, so off by at most one) and a last compare.
    var qa = i32(floor(f32(n) * k.inv_modulus));
    var a = n - qa * m;
    let qb = i32(floor(f32(a) * k.inv_modulus));
    a -= qb * m;
    qa += qb;
    if (a < 0i) {
        a += m;
        qa -= 1i;
    } else if (a >= m) {
        a -= m;
        qa += 1i;
    }
    // a·2^s = (a·⌊2^s/M⌋ + t)·M + r with a·(2^s mod M) = t·M + r: t estimated in f32 (a·b/M <
    // 2²⁴, off by at most 3), r the exact u32 residue a·b − t·M (true value below 2²⁶ in
    // magnitude), corrected by one more estimate (off by at most one) and a compare.
    let au = bitcast<u32>(a);
    var t = i32(floor(f32(a) * k.power_frac));
    var r = bitcast<i32>(au * k.power_rem - bitcast<u32>(t) * bitcast<u32>(m));
    let tc = i32(floor(f32(r) * k.inv_modulus));
    r -= tc * m;
    t += tc;
    if (r < 0i) {
        r += m;
        t -= 1i;
    } else if (r >= m) {
        r -= m;
        t += 1i;
    }
    // ⌊n·2^s / M⌋ = qa·2^s + a·⌊2^s/M⌋ + t (wrapping, like the CPU's i32 cells).
    var at = ExportSplit(
        bitcast<i32>(bitcast<u32>(qa) * k.power + au * k.power_quot + bitcast<u32>(t)),
        f32(r) * k.scale,
    );
    if (k.low != 0.0f) {
        // Δ = f32(Δ) + low: n = cell·Δ + (rem − cell·low), moved into [0, f32(Δ)).
        let side = export_sides[lattice];
        at.rem = at.rem - f32(at.cell) * k.low;
        for (var guard = 0u; guard < 4096u; guard++) {
            if (at.rem < 0.0f) {
                at.rem = at.rem + side;
                at.cell = bitcast<i32>(bitcast<u32>(at.cell) - 1u);
            } else if (at.rem >= side) {
                at.rem = at.rem - side;
                at.cell = bitcast<i32>(bitcast<u32>(at.cell) + 1u);
            } else {
                break;
            }
        }
    }
    return at;
}

/// The point `n + u` (`u` in `[0, 1)`, see `export_normalise`) on lattice `lattice`: its cell
/// and `rem` such that the point's offset from the cell's corner is `rem + u`, in `[0, Δ)`
/// (the carry of `u` into the next cells is taken here, exactly: `Δ − rem` and `rem − Δ` are
/// exact where `rem` is).
fn export_locate(n: i32, u: f32, lattice: u32) -> ExportSplit {
    return export_carry(export_split(n, lattice), u, lattice);
}

/// [`export_locate`] of a point whose integer part's split on `lattice` is `at`.
fn export_carry(split: ExportSplit, u: f32, lattice: u32) -> ExportSplit {
    var at = split;
    let side = export_sides[lattice];
    if (side > 1.0f) {
        // At most one carry, the loop's first step without a loop: after it `rem` is at most
        // 0, so the loop's next test `u < Δ − rem` holds (`Δ − rem` ≥ Δ > 1 ≥ u).
        let carry = u >= side - at.rem;
        at.rem = select(at.rem, at.rem - side, carry);
        at.cell = select(at.cell, bitcast<i32>(bitcast<u32>(at.cell) + 1u), carry);
        return at;
    }
    // At most ⌈1/Δ⌉ + 1 carries for u < 1; the bound only guards against a non-finite u.
    for (var guard = 0u; guard < 4096u; guard++) {
        if (u < side - at.rem) {
            break;
        }
        at.rem = at.rem - side;
        at.cell = bitcast<i32>(bitcast<u32>(at.cell) + 1u);
    }
    return at;
}

/// The split on `lattice` from the split `at` on a lattice of twice its side (the exporter
/// checks that the f64 sides, hence the f32 ones, halve exactly): the cell doubles and takes
/// one more where `at.rem` reaches the half side, whence `rem − Δ` is exact (Sterbenz). Where
/// both sides are f32 this is exactly `export_split(n, lattice)`; elsewhere `at`'s error,
/// carried over (not grown: no rounding).
fn export_halve(at: ExportSplit, lattice: u32) -> ExportSplit {
    let side = export_sides[lattice];
    let doubled = bitcast<u32>(at.cell) * 2u;
    if (at.rem >= side) {
        return ExportSplit(bitcast<i32>(doubled + 1u), at.rem - side);
    }
    return ExportSplit(bitcast<i32>(doubled), at.rem);
}

/// The point `n + u` on lattice `lattice` as the compute shaders' `GridAxis` (common.wgsl): its
/// cell and the offset in cell units, `(rem + u)·(1/Δ)` (the CPU rounds `x/Δ − ⌊x/Δ⌋` from f64
/// once), always valid (|n| < 2³¹ and Δ ≥ 1 keep the cell an i32).
fn export_grid_axis(n: i32, u: f32, lattice: u32) -> GridAxis {
    let at = export_locate(n, u, lattice);
    return GridAxis(at.cell, (at.rem + u) * export_inv_sides[lattice], 1u);
}

/// A position given as an integer part and any f32 offset, moved to the form the lattice
/// functions take: `n + ⌊offset⌋` and the fraction in `[0, 1)` (exact for |offset| < 2²³).
fn export_normalise(cell: vec2<i32>, offset: vec2<f32>) -> ExportPoint {
    let whole = floor(offset);
    let n = vec2<i32>(
        bitcast<i32>(bitcast<u32>(cell.x) + bitcast<u32>(i32(whole.x))),
        bitcast<i32>(bitcast<u32>(cell.y) + bitcast<u32>(i32(whole.y))),
    );
    return ExportPoint(n, offset - whole);
}

/// An integer pixel position and its fraction in `[0, 1)`.
struct ExportPoint {
    n: vec2<i32>,
    u: vec2<f32>,
}
