// export/subdivision.wgsl — the exported entry of a stochastic subdivision (after
// subdivision.wgsl and export/split.wgsl): lattice 0 of the export tables is the coarse lattice
// (cell side C).

/// The coordinate `n + u` on the coarse lattice: its cell and the offset in cell units,
/// `(rem + u)·(1/C)` (the CPU rounds `x/C − ⌊x/C⌋` from f64 once).
fn subdivision_export_axis(n: i32, u: f32) -> SubdivisionAxis {
    let at = export_locate(n, u, 0u);
    return SubdivisionAxis(at.cell, (at.rem + u) * export_inv_sides[0], 1u);
}

/// The texture at the position `cell + offset` (pixels).
fn subdivision_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let column = subdivision_export_axis(at.n.x, at.u.x);
    let row = subdivision_export_axis(at.n.y, at.u.y);
    return subdivision_value(column.cell, column.offset, row.cell, row.offset);
}
