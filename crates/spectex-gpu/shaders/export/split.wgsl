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
// 32 bits like the CPU's i32 cells.
//
// Exactness: where Δ is an f32 (LRP's Δ_s, a texton cell), every remainder is a multiple of
// Δ's last-bit unit below Δ, hence an f32, and each step (r + r_k, or r − (Δ − r_k) when that
// reaches Δ) is exact: r is n mod Δ exactly, whatever n. Where Δ is only an f64 (a Gabor
// kernel radius), each table remainder carries at most half an f32 ulp of Δ, so r is within
// 16 ulp(Δ) of the truth. Either way the error does not grow with |n|: a point at 10⁷ pixels is
// located as precisely as one at the origin.

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
