// export/texton.wgsl — the exported entry of a texton model (after texton.wgsl and
// export/split.wgsl): lattice 0 of the export tables is the texton grid (cell side C).

/// The `TextonAxis` of `texton.wgsl` for the coordinate `n + u`: its cell and the offset in
/// cell units, `(rem + u)·(1/C)` (the CPU rounds `x/C − ⌊x/C⌋` from f64 once). Always in
/// range: |n| < 2³¹ and C ≥ 1 keep the cell an i32.
fn texton_export_axis(n: i32, u: f32) -> TextonAxis {
    let at = export_locate(n, u, 0u);
    return TextonAxis(at.cell, (at.rem + u) * export_inv_sides[0], 1u);
}

/// The texture at the position `cell + offset` (pixels).
fn texton_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    return texton_value(texton_export_axis(at.n.x, at.u.x), texton_export_axis(at.n.y, at.u.y));
}
