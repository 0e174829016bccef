// export/gabor.wgsl — the exported entry of a Gabor model (after gabor.wgsl and
// export/split.wgsl): lattice 0 of the export tables is the kernel radius r (cell side).

/// The noise at the position `cell + offset` (pixels).
fn gabor_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    return gabor_value(export_grid_axis(at.n.x, at.u.x, 0u), export_grid_axis(at.n.y, at.u.y, 0u));
}
