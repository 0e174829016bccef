// tiling.wgsl — tiling and blending by example (Heitz & Neyret 2018), the GPU twin of
// crates/spectex-cpu/src/tiling.rs; the definition is the module doc of
// crates/spectex-model/src/tiling.rs. Composed after common.wgsl.
//
// The host builds the exemplar's mip pyramid and each level's prefiltered look-up tables
// (`TilingTexture::tables`, f64 rounded to f32, the CPU's bytes), and per tile each column's and
// row's whole pixel and fraction (the CPU's split, side 1). A pixel takes its rhombus and
// triangle in integers and f32, draws its three vertices with the randomness
// contract, reads three bilinear taps and blends them with the CPU's f32 operations in the
// CPU's order; a compiler may contract a product-add the CPU rounds twice.

/// Per-dispatch values and the model's constants.
struct TilingParams {
    width: u32,
    height: u32,
    seed: u32,
    /// 1 or 3.
    channels: u32,
    /// The smallest offset and the spans of the offsets along x and y, texels.
    lo: u32,
    span_x: u32,
    span_y: u32,
    /// 0: variance-preserving, 1: hex.
    blend: u32,
    /// The hex blend's exponent γ.
    sharpness: u32,
    /// The hex blend's largest rotation, turns (0: none).
    rotation: f32,
    /// The lattice's side (even) and row spacing, whole pixels.
    side: i32,
    row: i32,
    /// A periodic lattice's vertices per row and rows (0: not periodic).
    wrap_c: i32,
    wrap_rows: i32,
    /// 1 when the tile mixes level1 into level0 with weight mix.
    two_levels: u32,
    mix: f32,
    /// (LUT_ENTRIES − 1)/(2·LUT_RANGE) and LUT_RANGE.
    lut_scale: f32,
    lut_range: f32,
    /// spectex_model::tiling::TILING_LAYER and TILING_BLOCK_LAYER (one definition each,
    /// passed by the host).
    layer: u32,
    block_layer: u32,
    /// Levels as (first texel, width, height, level index).
    level0: vec4<u32>,
    level1: vec4<u32>,
    /// The colour mean (w unused) and the basis by rows.
    mean: vec4<f32>,
    basis0: vec4<f32>,
    basis1: vec4<f32>,
    basis2: vec4<f32>,
    /// 1/side and 1/row (f32 of the f64 values).
    inv_side: f32,
    inv_row: f32,
    /// The exemplar's sides (level 0), texels.
    ex_width: u32,
    ex_height: u32,
}

/// Entries of each look-up table (spectex_model::tiling::LUT_ENTRIES).
const TILING_LUT_ENTRIES: u32 = 1024u;

@group(0) @binding(0) var<uniform> params: TilingParams;
/// Every level's texels: the Gaussianised channels, then zeros.
@group(0) @binding(1) var<storage, read> texels: array<vec4<f32>>;
/// Per level and channel, LUT_l (TILING_LUT_ENTRIES values each).
@group(0) @binding(2) var<storage, read> luts: array<f32>;
@group(0) @binding(3) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(4) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(5) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes"). The channel count bounds every per-channel
// loop: as a uniform it kept the taps, the blended values and the basis in per-invocation
// memory, indexed at run time.
override TILING_BLEND: u32 = 0xffffffffu;
override TILING_CHANNELS: u32 = 0xffffffffu;

fn tiling_blend() -> u32 {
    return shape_or(TILING_BLEND, params.blend);
}

fn tiling_channels() -> u32 {
    return shape_or(TILING_CHANNELS, params.channels);
}

/// A vertex's draws: its offset (whole texels) and rotation (cos, sin).
struct TilingVertex {
    offset: vec2<i32>,
    rotation: vec2<f32>,
}

fn tiling_rotates() -> bool {
    return tiling_blend() == 1u && params.rotation > 0.0f;
}

/// The draws of vertex (m, k), keyed modulo a periodic lattice (Lattice::key).
fn tiling_vertex(m: i32, k: i32) -> TilingVertex {
    var mm = m;
    var kk = k;
    if (params.wrap_rows != 0) {
        kk = wrap_cell(k, params.wrap_rows);
        // max(…, 1): an export's constant wrap_rows is 0, and naga refuses a constant division
        // by zero even in a branch that never runs.
        let q = (k - kk) / max(params.wrap_rows, 1);
        mm = wrap_cell(m + q * (params.wrap_rows / 2), params.wrap_c);
    }
    let bm = tiling_div(mm, 4);
    let bk = tiling_div(kk, 4);
    let j = u32((mm - 4 * bm) + 4 * (kk - 4 * bk));
    var block = Prng(cell_hash(bm, bk, params.block_layer, params.seed));
    let alpha = 2u * (prng_next_u32(&block) % 8u) + 1u;
    let beta = prng_next_u32(&block) % 16u;
    let stratum = (alpha * j + beta) % 16u;
    var prng = Prng(cell_hash(mm, kk, params.layer, params.seed));
    let nx = params.span_x + 1u;
    let ny = params.span_y + 1u;
    let ox = params.lo + ((stratum % 4u) * nx + prng_next_u32(&prng) % nx) / 4u;
    let oy = params.lo + ((stratum / 4u) * ny + prng_next_u32(&prng) % ny) / 4u;
    var rotation = vec2<f32>(1.0f, 0.0f);
    if (tiling_rotates()) {
        let theta = params.rotation * (2.0f * unit_f32(prng_next_u32(&prng)) - 1.0f);
        rotation = vec2<f32>(cos_turns(theta), cos_turns(theta - 0.25f));
    }
    return TilingVertex(vec2<i32>(i32(ox), i32(oy)), rotation);
}

/// The bilinear tap of `level` at q texels of level 0.
fn tiling_tap(level: vec4<u32>, q: vec2<f32>) -> vec4<f32> {
    let inv = 1.0f / f32(1u << level.w);
    let bias = 0.5f * (1.0f - inv);
    let x = clamp(q.x * inv - bias, 0.0f, f32(level.y - 1u));
    let y = clamp(q.y * inv - bias, 0.0f, f32(level.z - 1u));
    let ix = min(u32(floor(x)), level.y - 2u);
    let iy = min(u32(floor(y)), level.z - 2u);
    let fx = x - f32(ix);
    let fy = y - f32(iy);
    let at = level.x + iy * level.y + ix;
    let t00 = texels[at];
    let t10 = texels[at + 1u];
    let t01 = texels[at + level.y];
    let t11 = texels[at + level.y + 1u];
    let top = t00 + fx * (t10 - t00);
    let bottom = t01 + fx * (t11 - t01);
    return top + fy * (bottom - top);
}

/// The texel (x, y) of level 0 and its right and lower neighbours weighed by phi (bilinear:
/// phi = 0 gives the texel's own bits, as the CPU's shortcut does).
fn tiling_texel(x: i32, y: i32, phi: vec2<f32>) -> vec4<f32> {
    let w = params.ex_width;
    let xu = u32(x);
    let yu = u32(y);
    let x1 = min(xu + 1u, w - 1u);
    let y1 = min(yu + 1u, params.ex_height - 1u);
    let t00 = texels[yu * w + xu];
    let t10 = texels[yu * w + x1];
    let t01 = texels[y1 * w + xu];
    let t11 = texels[y1 * w + x1];
    let top = t00 + phi.x * (t10 - t00);
    let bottom = t01 + phi.x * (t11 - t01);
    return top + phi.y * (bottom - top);
}

/// LUT_l of channel c at g.
fn tiling_lookup(l: u32, c: u32, g: f32) -> f32 {
    let base = (l * tiling_channels() + c) * TILING_LUT_ENTRIES;
    let x = (clamp(g, -params.lut_range, params.lut_range) + params.lut_range) * params.lut_scale;
    let i = min(u32(floor(x)), TILING_LUT_ENTRIES - 2u);
    let f = x - f32(i);
    let a = luts[base + i];
    let b = luts[base + i + 1u];
    return a + f * (b - a);
}

fn tiling_add(a: i32, b: i32) -> i32 {
    return bitcast<i32>(bitcast<u32>(a) + bitcast<u32>(b));
}

/// ⌊a/b⌋ for b > 0.
fn tiling_div(a: i32, b: i32) -> i32 {
    let q = a / b;
    return select(q, q - 1, a - q * b < 0);
}

/// The texture at `level` at the pixel in rhombus (m0, k0) at (u, v), (dx, dy) whole pixels
/// from vertex (m0, k0) and fractions phi.
fn tiling_level(level: vec4<u32>, m0: i32, k0: i32, u: f32, v: f32, dx: i32, dy: i32, phi: vec2<f32>) -> vec3<f32> {
    var corners = array<vec2<i32>, 3>(vec2<i32>(0, 0), vec2<i32>(1, 0), vec2<i32>(0, 1));
    var w = vec3<f32>((1.0f - u) - v, u, v);
    if (!(u + v < 1.0f)) {
        corners = array<vec2<i32>, 3>(vec2<i32>(1, 1), vec2<i32>(0, 1), vec2<i32>(1, 0));
        w = vec3<f32>((u + v) - 1.0f, 1.0f - u, 1.0f - v);
    }
    let half = params.side / 2;
    var taps: array<vec4<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        let a = corners[i];
        let vertex = tiling_vertex(tiling_add(m0, a.x), tiling_add(k0, a.y));
        let ddx = dx - a.x * params.side - a.y * half;
        let ddy = dy - a.y * params.row;
        let o = vertex.offset;
        if (tiling_rotates()) {
            let fx = f32(ddx) + phi.x;
            let fy = f32(ddy) + phi.y;
            let c = vertex.rotation.x;
            let s = vertex.rotation.y;
            taps[i] = tiling_tap(level, vec2<f32>(f32(o.x) + (c * fx - s * fy), f32(o.y) + (s * fx + c * fy)));
        } else if (level.w == 0u) {
            taps[i] = tiling_texel(o.x + ddx, o.y + ddy, phi);
        } else {
            taps[i] = tiling_tap(level, vec2<f32>(f32(o.x + ddx) + phi.x, f32(o.y + ddy) + phi.y));
        }
    }
    let nc = tiling_channels();
    var t = vec3<f32>(0.0f, 0.0f, 0.0f);
    if (tiling_blend() == 0u) {
        let norm = sqrt((w.x * w.x + w.y * w.y) + w.z * w.z);
        for (var c = 0u; c < nc; c++) {
            let g = (w.x * taps[0][c] + w.y * taps[1][c]) + w.z * taps[2][c];
            t[c] = tiling_lookup(level.w, c, g / norm);
        }
    } else {
        var p = w;
        for (var e = 1u; e < params.sharpness; e++) {
            p = p * w;
        }
        let sum = (p.x + p.y) + p.z;
        for (var c = 0u; c < nc; c++) {
            let l0 = tiling_lookup(level.w, c, taps[0][c]);
            let l1 = tiling_lookup(level.w, c, taps[1][c]);
            let l2 = tiling_lookup(level.w, c, taps[2][c]);
            t[c] = ((p.x * l0 + p.y * l1) + p.z * l2) / sum;
        }
    }
    var basis = array<vec4<f32>, 3>(params.basis0, params.basis1, params.basis2);
    var out = vec3<f32>(0.0f, 0.0f, 0.0f);
    for (var i = 0u; i < nc; i++) {
        var acc = params.mean[i];
        for (var c = 0u; c < nc; c++) {
            acc += basis[i][c] * t[c];
        }
        out[i] = acc;
    }
    return out;
}

/// The texture at a pixel located on the pixel grid (its column and row: whole pixel and
/// fraction), split on the lattice in integers as the CPU splits it.
fn tiling_value(column: GridAxis, row: GridAxis) -> vec3<f32> {
    if (column.valid == 0u || row.valid == 0u) {
        return params.mean.xyz;
    }
    let cy = tiling_div(row.cell, params.row);
    let ry = row.cell - cy * params.row;
    let v = (f32(ry) + row.offset) * params.inv_row;
    let a = column.cell - cy * (params.side / 2);
    let cx = tiling_div(a, params.side);
    let rx = a - cx * params.side;
    let t = (f32(rx) + column.offset) * params.inv_side - 0.5f * v;
    var ft = 0;
    if (t < 0.0f) {
        ft = -1;
    } else if (t >= 1.0f) {
        ft = 1;
    }
    let m0 = tiling_add(cx, ft);
    let u = t - f32(ft);
    let dx = rx - ft * params.side;
    let phi = vec2<f32>(column.offset, row.offset);
    let v0 = tiling_level(params.level0, m0, cy, u, v, dx, ry, phi);
    if (params.two_levels == 1u) {
        let v1 = tiling_level(params.level1, m0, cy, u, v, dx, ry, phi);
        return v0 + params.mix * (v1 - v0);
    }
    return v0;
}

@compute @workgroup_size(8, 8, 1)
fn tiling_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    var column = columns[gid.x];
    var row = rows[gid.y];
    if (warp_params.enabled == 1u) {
        let d = warp_displacement[index];
        let cx = warp_relocate(column.cell, column.offset, d.x);
        let cy = warp_relocate(row.cell, row.offset, d.y);
        column.cell = cx.cell;
        column.offset = cx.offset;
        row.cell = cy.cell;
        row.offset = cy.offset;
    }
    let v = tiling_value(column, row);
    let nc = tiling_channels();
    for (var c = 0u; c < nc; c++) {
        output[index * nc + c] = v[c];
    }
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of tiling and blending (after the kernel above and export/split.wgsl):
// lattice 0 of the export tables is the pixel grid (side 1: the whole pixel and its fraction,
// which the kernel splits on the triangle lattice in integers). The texels and tables are the storage buffer's `texels` and `luts` (its layout is in
// the module's header); the export evaluates level 0 (a point sample: a caller minifying the
// texture filters it as it would any texture). The exporter replaces TILING_VALUE with the
// return type (f32 or vec3<f32>) and TILING_RESULT with the value's components.

/// The texture at the position `cell + offset` (pixels).
fn tiling_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> TILING_VALUE {
    let at = export_normalise(cell, offset);
    let v = tiling_value(export_grid_axis(at.n.x, at.u.x, 0u), export_grid_axis(at.n.y, at.u.y, 0u));
    return TILING_RESULT;
}
