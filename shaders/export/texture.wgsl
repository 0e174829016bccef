// export/texture.wgsl — the exported entry of a texture by example (after texture.wgsl and
// export/split.wgsl): lattice 0 of the export tables is the placement cell P = T/2 (a power
// of two, so the split and the offsets in cell units are exact up to the one rounding of
// `rem + u`). The exporter writes `texture_inputs(cell, offset)`: each channel's random-phase
// strata (an LRP model exported under its own prefix, or the channel's mean) and the
// turbulence displacement σ·(Σ_S |n_S| − centre) per axis (the turbulence strata, LRP models
// too, summed in order in f32, as the GPU evaluator's host does), and replaces TEXTURE_VALUE
// with the return type.

/// The `PlacementAxis` of `texture.wgsl` for the coordinate `n + u`: its placement cell and
/// the offset in cells (the CPU's `locate_cell(x, P)`).
fn texture_export_axis(n: i32, u: f32) -> PlacementAxis {
    let at = export_locate(n, u, 0u);
    return PlacementAxis(at.cell, (at.rem + u) * export_inv_sides[0]);
}

/// The texture at the position `cell + offset` (pixels).
fn texture_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> TEXTURE_VALUE {
    let inputs = texture_inputs(cell, offset);
    let at = export_normalise(cell, offset);
    let v = texture_value(
        texture_export_axis(at.n.x, at.u.x),
        texture_export_axis(at.n.y, at.u.y),
        inputs.strata,
        inputs.d,
    );
    return TEXTURE_RESULT;
}

/// What the LRP models give a pixel: each channel's strata and the displacement.
struct TextureInputs {
    strata: array<f32, 3>,
    d: vec2<f32>,
}
