// wavelet.wgsl — wavelet noise (Cook & DeRose 2005), the GPU twin of
// crates/spectex-cpu/src/wavelet.rs; the definition is the module doc of
// crates/spectex-model/src/wavelet.rs. Composed after common.wgsl (only for the shared header;
// no random draws happen here, only the warp displacement convention: the host builds the band-limited tile once, in f64, with the
// function the CPU uses, and uploads it as f32).
//
// Positions: the host computes, per band and per column (row) of the tile, u = x / c_b + ½ in
// f64, m = ⌊u⌋, the first tile index (m − 1 + o_b) mod n and the fraction f32(u − m)
// (`spectex_model::wavelet::locate_sample`, the CPU's call). So the device needs only integer
// indices below n and f32 fractions in [0, 1], and the precision does not depend on the
// distance from the origin.
//
// Sum order (the CPU's): z weights first (3D), then y, then x, each sum left to right, then
// acc = acc + a_b · s over bands in order and mean + acc. The z sum is the host's: a band reads
// an n × n plane, the tile itself in 2D, in 3D the tile summed over the plane z once per band
// (`WaveletTile::plane`, as the CPU evaluator does), where the shader summed three layers at
// each of a pixel's 9 taps (27 tile reads a band; wavelet-3d-multiband's export ran at
// 2.8–4.1 calibration cosines an evaluation that way on lavapipe). Plain `*` and `+`; a
// compiler may still contract them into FMAs (crosscheck tolerance `tolerance::wavelet`).

struct WaveletParams {
    width: u32,
    height: u32,
    /// Number of bands.
    bands: u32,
    /// Tile side n.
    n: u32,
    /// 2 or 3.
    dimensions: u32,
    mean: f32,
    _pad0: u32,
    _pad1: u32,
}

/// One band: its weight a_b and where its n × n plane starts in `planes`.
struct WaveletBand {
    amplitude: f32,
    first: u32,
    /// 1 / c_b, samples per pixel (f32 of the f64 value), for domain warping.
    inv_side: f32,
    _pad: u32,
}

/// One column (or row) of one band: the first of its three tile indices and the fraction.
struct WaveletAxis {
    index: u32,
    fraction: f32,
}

@group(0) @binding(0) var<uniform> params: WaveletParams;
/// The bands' planes (one, shared, in 2D), x fastest.
@group(0) @binding(1) var<storage, read> planes: array<f32>;
@group(0) @binding(2) var<storage, read> bands: array<WaveletBand>;
@group(0) @binding(3) var<storage, read> columns: array<WaveletAxis>;
@group(0) @binding(4) var<storage, read> rows: array<WaveletAxis>;
@group(0) @binding(5) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes"): its dimension and tile side. Read from the
// uniform, they made lavapipe run wavelet-2d at under half this speed (a branch and the index
// arithmetic by a runtime side), bit for bit the same.
override WAVELET_DIMENSIONS: u32 = 0xffffffffu;
override WAVELET_TILE: u32 = 0xffffffffu;

fn wavelet_dimensions() -> u32 {
    return shape_or(WAVELET_DIMENSIONS, params.dimensions);
}

/// The tile side `n`.
fn wavelet_tile() -> u32 {
    return shape_or(WAVELET_TILE, params.n);
}

/// Quadratic B-spline weights of samples m − 1, m, m + 1 (spectex_model::wavelet::spline_weights).
fn spline_weights(f: f32) -> vec3<f32> {
    let g = 1.0f - f;
    let w0 = 0.5f * g * g;
    let w2 = 0.5f * f * f;
    return vec3<f32>(w0, (1.0f - w0) - w2, w2);
}

/// i + 1 mod n for i < n.
fn next_index(i: u32) -> u32 {
    return select(i + 1u, 0u, i + 1u == wavelet_tile());
}

/// The value at (i, j) of a band's plane (in 2D every band's plane is the tile, at 0: the
/// shape constant folds the band's offset away, which kept wavelet-2d 5% faster on lavapipe).
fn plane(i: u32, j: u32, band: WaveletBand) -> f32 {
    let o = j * wavelet_tile() + i;
    if (wavelet_dimensions() == 2u) {
        return planes[o];
    }
    return planes[band.first + o];
}

/// Σ_j w_{y,j} · plane(i, j).
fn row_value(i: u32, j0: u32, wy: vec3<f32>, band: WaveletBand) -> f32 {
    let j1 = next_index(j0);
    let j2 = next_index(j1);
    return (wy.x * plane(i, j0, band) + wy.y * plane(i, j1, band)) + wy.z * plane(i, j2, band);
}

/// An axis entry moved by `d` pixels (domain warping, common.wgsl): the fraction plus `d` in
/// samples, the first index shifted by its floor modulo n (in i64-free i32 arithmetic: the
/// shift is at most MAX_WARP samples, the index below n ≤ 256).
fn displaced(a: WaveletAxis, d: f32, inv_side: f32) -> WaveletAxis {
    let moved = warp_relocate(i32(a.index), a.fraction, d * inv_side);
    let n = i32(wavelet_tile());
    return WaveletAxis(u32(((moved.cell % n) + n) % n), moved.offset);
}

@compute @workgroup_size(8, 8, 1)
fn wavelet_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    var acc = 0.0f;
    var d = vec2<f32>(0.0f);
    if (warp_params.enabled == 1u) {
        d = warp_displacement[gid.y * params.width + gid.x];
    }
    for (var b = 0u; b < params.bands; b++) {
        let band = bands[b];
        var column = columns[b * params.width + gid.x];
        var row = rows[b * params.height + gid.y];
        if (warp_params.enabled == 1u) {
            column = displaced(column, d.x, band.inv_side);
            row = displaced(row, d.y, band.inv_side);
        }
        acc = acc + band.amplitude * band_value(band, column, row);
    }
    output[gid.y * params.width + gid.x] = params.mean + acc;
}

/// One band's B-spline sum at the point `column`, `row` (before its amplitude).
fn band_value(band: WaveletBand, column: WaveletAxis, row: WaveletAxis) -> f32 {
    let wx = spline_weights(column.fraction);
    let wy = spline_weights(row.fraction);
    let i0 = column.index;
    let i1 = next_index(i0);
    let i2 = next_index(i1);
    return (wx.x * row_value(i0, row.index, wy, band) + wx.y * row_value(i1, row.index, wy, band))
        + wx.z * row_value(i2, row.index, wy, band);
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a wavelet noise (after the kernel above and
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
    let tile_n = wavelet_tile();
    let wrapped = u32(((m % i32(tile_n)) + i32(tile_n)) % i32(tile_n));
    let index = (wrapped + wavelet_export_offsets[2u * b + axis] + tile_n - 1u) % tile_n;
    return WaveletAxis(index, fraction);
}

/// Band `b`'s term `a_b · s_b` at the point `at`.
fn wavelet_export_band(at: ExportPoint, b: u32) -> f32 {
    let column = wavelet_export_axis(at.n.x, at.u.x, b, 0u);
    let row = wavelet_export_axis(at.n.y, at.u.y, b, 1u);
    return bands[b].amplitude * band_value(bands[b], column, row);
}

/// The noise at the position `cell + offset` (pixels), bands summed in the CPU's order. The
/// exporter writes the bands out, `WAVELET_EXPORT_BANDS` = one `wavelet_export_band` term per
/// band with its index as a literal (as classic.wgsl's octaves): a band's lattice, offsets
/// and record are then constants, where a band loop's counter would read them from
/// per-invocation memory.
fn wavelet_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    var acc = 0.0f;
    WAVELET_EXPORT_BANDS
    return params.mean + acc;
}
