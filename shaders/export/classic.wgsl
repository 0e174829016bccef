// export/classic.wgsl — the exported entry of a classic noise (after classic.wgsl and
// export/split.wgsl): octave o's lattices are the export's 3o (cell side c_o: the cell and
// offset), 3o + 1 (c_o/(1 + F): simplex's own skew part p·(1 + F)) and 3o + 2 (c_o/F: the
// other part p·F); the last two are read by simplex noise only.

/// The `ClassicAxis` of `classic.wgsl` for the coordinate `n + u` on octave `o`: each part is
/// the cell and the fraction `(rem + u)/side` of its lattice (the CPU rounds `p − ⌊p⌋` from f64
/// once).
fn classic_export_axis(n: i32, u: f32, o: u32) -> ClassicAxis {
    let l = 3u * o;
    let base = export_locate(n, u, l);
    var axis = ClassicAxis(base.cell, (base.rem + u) * export_inv_sides[l], 0i, 0.0f, 0i, 0.0f);
    if (params.basis == 1u) {
        let own = export_locate(n, u, l + 1u);
        let other = export_locate(n, u, l + 2u);
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
    for (var o = 0u; o < params.octaves; o++) {
        let column = classic_export_axis(at.n.x, at.u.x, o);
        let row = classic_export_axis(at.n.y, at.u.y, o);
        classic_octave(o, column, row, vec2<f32>(0.0f), &acc, &previous);
    }
    return params.mean + params.amplitude * acc;
}
