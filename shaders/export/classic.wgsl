// export/classic.wgsl — the exported entry of a classic noise (after classic.wgsl and
// export/split.wgsl): octave o's lattices are the export's 3o (cell side c_o: the cell and
// offset), 3o + 1 (c_o/(1 + F): simplex's own skew part p·(1 + F)) and 3o + 2 (c_o/F: the
// other part p·F); the last two are read by simplex noise only. The exporter declares
// `classic_export_halving`: 1 where every octave's lattices are the previous one's halved
// exactly (lacunarity 2), so that a coordinate is split once, on octave 0, and each further
// octave's split follows from the previous one in a compare (`export_halve`) instead of a
// split of its own.

/// A coordinate's splits on one octave's lattices (the skew ones for simplex noise only).
struct ClassicExportSplits {
    base: ExportSplit,
    own: ExportSplit,
    other: ExportSplit,
}

/// The integer coordinate `n` split on octave `o`'s lattices.
fn classic_export_splits(n: i32, o: u32) -> ClassicExportSplits {
    let l = 3u * o;
    var s = ClassicExportSplits(export_split(n, l), ExportSplit(0i, 0.0f), ExportSplit(0i, 0.0f));
    if (params.basis == 1u) {
        s.own = export_split(n, l + 1u);
        s.other = export_split(n, l + 2u);
    }
    return s;
}

/// Octave `o`'s splits from octave `o − 1`'s `s`, its lattices halved.
fn classic_export_halve_splits(s: ClassicExportSplits, o: u32) -> ClassicExportSplits {
    let l = 3u * o;
    var h = ClassicExportSplits(export_halve(s.base, l), s.own, s.other);
    if (params.basis == 1u) {
        h.own = export_halve(s.own, l + 1u);
        h.other = export_halve(s.other, l + 2u);
    }
    return h;
}

/// The `ClassicAxis` of `classic.wgsl` for the coordinate `n + u` on octave `o`, from `n`'s
/// splits `s` on its lattices: each part is the cell and the fraction `(rem + u)/side` of its
/// lattice (the CPU rounds `p − ⌊p⌋` from f64 once).
fn classic_export_axis(s: ClassicExportSplits, u: f32, o: u32) -> ClassicAxis {
    let l = 3u * o;
    let base = export_carry(s.base, u, l);
    var axis = ClassicAxis(base.cell, (base.rem + u) * export_inv_sides[l], 0i, 0.0f, 0i, 0.0f);
    if (params.basis == 1u) {
        let own = export_carry(s.own, u, l + 1u);
        let other = export_carry(s.other, u, l + 2u);
        axis.own_cell = own.cell;
        axis.own_frac = (own.rem + u) * export_inv_sides[l + 1u];
        axis.other_cell = other.cell;
        axis.other_frac = (other.rem + u) * export_inv_sides[l + 2u];
    }
    return axis;
}

/// The noise at the position `cell + offset` (pixels), octaves summed in the CPU's order.
fn classic_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    var acc = 0.0f;
    var previous = 0.0f;
    var sx = classic_export_splits(at.n.x, 0u);
    var sy = classic_export_splits(at.n.y, 0u);
    for (var o = 0u; o < params.octaves; o++) {
        if (o > 0u) {
            if (classic_export_halving == 1u) {
                sx = classic_export_halve_splits(sx, o);
                sy = classic_export_halve_splits(sy, o);
            } else {
                sx = classic_export_splits(at.n.x, o);
                sy = classic_export_splits(at.n.y, o);
            }
        }
        let column = classic_export_axis(sx, at.u.x, o);
        let row = classic_export_axis(sy, at.u.y, o);
        classic_octave(o, column, row, vec2<f32>(0.0f), &acc, &previous);
    }
    return params.mean + params.amplitude * acc;
}
