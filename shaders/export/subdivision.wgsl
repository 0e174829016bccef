// export/subdivision.wgsl — the exported entry of a stochastic subdivision (after
// subdivision.wgsl and export/split.wgsl): lattice 0 of the export tables is the coarse lattice
// (cell side C).

/// The texture at the position `cell + offset` (pixels).
fn subdivision_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let column = export_grid_axis(at.n.x, at.u.x, 0u);
    let row = export_grid_axis(at.n.y, at.u.y, 0u);
    return subdivision_value(column.cell, column.offset, row.cell, row.offset);
}
