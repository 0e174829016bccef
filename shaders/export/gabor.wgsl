// export/gabor.wgsl — the exported entry of a Gabor model (after gabor.wgsl and
// export/split.wgsl): lattice 0 of the export tables is the kernel radius r (cell side).

/// The `GaborAxis` of `gabor.wgsl` for the coordinate `n + u`: its cell and the offset in cell
/// units, `(rem + u)·(1/r)` (the CPU rounds `x/r − ⌊x/r⌋` from f64 once).
fn gabor_export_axis(n: i32, u: f32) -> GaborAxis {
    let at = export_locate(n, u, 0u);
    return GaborAxis(at.cell, (at.rem + u) * params.inv_radius, 1u);
}

/// The noise at the position `cell + offset` (pixels).
fn gabor_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    return gabor_value(gabor_export_axis(at.n.x, at.u.x), gabor_export_axis(at.n.y, at.u.y));
}
