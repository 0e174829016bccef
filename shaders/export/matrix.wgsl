// export/matrix.wgsl — the exported entry of a matrix transformation (after matrix.wgsl and
// export/split.wgsl; no lattice: the pixel grid has side 1). The compute path's host gives
// each column and row its cell ⌊x⌋; here the position's integer part is that cell exactly
// (`export_normalise`), and the texel is read as `matrix_main` reads it: the cell reduced
// modulo N, mapped by A = (M⁻¹)^k mod N in integers.

/// The transformation at the position `cell + offset` (pixels).
fn matrix_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let n = i32(params.size);
    let qx = u32(wrap_cell(at.n.x, n));
    let qy = u32(wrap_cell(at.n.y, n));
    let s = vec2<u32>(
        (params.a00 * qx + params.a01 * qy) % params.size,
        (params.a10 * qx + params.a11 * qy) % params.size,
    );
    var v: f32;
    if (params.image == 1u) {
        v = texels[s.y * params.size + s.x];
    } else {
        v = matrix_rings(s);
    }
    return params.mean + params.amplitude * v;
}
