// export/wavelet.wgsl — the exported entry of a wavelet noise (after wavelet.wgsl and
// export/split.wgsl): lattice b of the export tables is band b's sample spacing c_b, and
// `wavelet_export_offsets[2b + axis]` its tile offset o_b along x (axis 0) and y (axis 1).

/// The `WaveletAxis` of band `b` for the coordinate `n + u` on `axis`: the CPU's
/// `locate_sample` (u' = x/c_b + ½, m = ⌊u'⌋, index (m − 1 + o_b) mod n, fraction u' − m) with
/// x = cell·c_b + rem + u from the split: the half sample is added to the remainder (exact
/// where c_b is an f32, as `cell_size / 2^b` is), a carry moves m to the next cell.
fn wavelet_export_axis(n: i32, u: f32, b: u32, axis: u32) -> WaveletAxis {
    let at = export_locate(n, u, b);
    let side = export_sides[b];
    let r = at.rem + 0.5f * side;
    var m = at.cell;
    var fraction: f32;
    if (u >= side - r) {
        m = bitcast<i32>(bitcast<u32>(m) + 1u);
        fraction = ((r - side) + u) * export_inv_sides[b];
    } else {
        fraction = (r + u) * export_inv_sides[b];
    }
    let tile = i32(params.n);
    let wrapped = u32(((m % tile) + tile) % tile);
    let index = (wrapped + wavelet_export_offsets[2u * b + axis] + params.n - 1u) % params.n;
    return WaveletAxis(index, fraction);
}

/// The noise at the position `cell + offset` (pixels), bands summed in the CPU's order.
fn wavelet_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    var acc = 0.0f;
    for (var b = 0u; b < params.bands; b++) {
        let column = wavelet_export_axis(at.n.x, at.u.x, b, 0u);
        let row = wavelet_export_axis(at.n.y, at.u.y, b, 1u);
        acc = acc + bands[b].amplitude * band_value(bands[b], column, row);
    }
    return params.mean + acc;
}
