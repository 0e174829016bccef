// export/lrp.wgsl — the exported entry of an LRP model (after lrp.wgsl and export/split.wgsl):
// lattice l of the export tables is stratum l's Δ_s.

/// The `LatticeAxis` of `lrp.wgsl` for the coordinate `n + u` on stratum `s`'s lattice: the
/// cell and the offsets `(rem − (k − 1)·Δ) + u` to the lattice points cell − 1 … cell + 2 (the
/// CPU's `f32(x − (c + k − 1)·Δ)`, rounded once where `rem − (k − 1)·Δ` is exact).
fn lrp_export_axis(n: i32, u: f32, s: u32) -> LatticeAxis {
    let at = export_locate(n, u, s);
    let delta = strata[s].delta;
    var axis: LatticeAxis;
    axis.cell = at.cell;
    axis.offset = array<f32, 4>(
        (at.rem + delta) + u,
        at.rem + u,
        (at.rem - delta) + u,
        (at.rem - 2.0f * delta) + u,
    );
    return axis;
}

/// The noise at the position `cell + offset` (pixels), the strata summed in the CPU's order.
fn lrp_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    var total = 0.0f;
    for (var s = 0u; s < params.strata; s++) {
        let column = lrp_export_axis(at.n.x, at.u.x, s);
        let row = lrp_export_axis(at.n.y, at.u.y, s);
        total += lrp_stratum(s, column, row);
    }
    return total + params.mean;
}
