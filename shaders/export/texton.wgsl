// export/texton.wgsl — the exported entry of a texton model (after texton.wgsl and
// export/split.wgsl): lattice 0 of the export tables is the texton grid (cell side C).

/// The texture at the position `cell + offset` (pixels).
fn texton_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    return texton_value(export_grid_axis(at.n.x, at.u.x, 0u), export_grid_axis(at.n.y, at.u.y, 0u));
}
