// texture.wgsl — texture by example (Gilet et al. 2014, §5–6): the per-pixel part of
// crates/spectex-model/src/texture.rs (`TextureModel::placement`, `Structure::eval`,
// `block_value`, `placement_shift`, `TextureModel::structure_at`, `colour_component`),
// transcribed operation for operation. Composed after common.wgsl.
//
// What the host does (crates/spectex-gpu/src/texture.rs), so this shader needs no f64:
// - each channel's random-phase strata (with its mean) and each turbulence stratum are rendered
//   by lrp.wgsl for the same tile, on the device in the tile's submission (or on the host's
//   request for a displaced tile), as planes of `values`: plane c < channels holds channel c's
//   strata, the next `turbulence_strata` planes the x turbulence strata, then those of y; this
//   shader sums |n_S| per axis in stratum order and applies `Turbulence::displacement` in f32,
//   exactly the CPU's operations (0 without turbulence, as on the CPU);
// - per column the placement cell and offset `(cx, sx) = locate_cell(x, T/2)` in f64, per row
//   `(cy, sy)` likewise (the CPU's expression, so the same bits);
// - per channel the structure's Δ_R = T/b, 1/Δ_R and 1/N as f32 (powers of two, exact).
// Everything from there on is here: placement taps (cell shifts from the randomness contract,
// cross-fade weights, 1/√Σω²), the structure n_R of each channel (2×2 blocks with cos² weights,
// or the one block at q when b = 1) and the colour basis. Output is interleaved, `channels`
// values per pixel, pixel-major over the tile.
//
// Bits: the taps' positions q are sums of exactly representable products (powers of two times
// small integers), so they equal the CPU's bit for bit; the weights use cos_turns (bit-identical
// on lavapipe) except 1/√Σω², whose sqrt and division WGSL bounds only to a few ulps; cosine
// sums and the colour transform may be contracted into FMAs by the compiler. The cross-check's
// `tolerance::texture` bounds these differences.

/// Per-dispatch values.
struct TextureParams {
    /// Tile width and height in pixels.
    width: u32,
    height: u32,
    /// 1 or 3.
    channels: u32,
    /// T, the structure period in pixels (a power of two).
    period: u32,
    /// Seed of the placement shifts.
    seed: u32,
    /// 1 when placement cells draw random shifts.
    random_placement: u32,
    /// 1 when a colour basis maps the channels to RGB.
    colour: u32,
    /// spectex_model::texture::PLACEMENT_LAYER (one definition, passed by the host).
    placement_layer: u32,
    /// 1: a minified render, the structure filtered over `footprint` pixels
    /// (`Structure::eval_filtered`).
    filtered: u32,
    footprint: f32,
    /// Turbulence::sigma and centre: the displacement σ·(Σ_S |n_S| − centre).
    turbulence_sigma: f32,
    turbulence_centre: f32,
    /// The colour basis' mean (xyz).
    colour_mean: vec4<f32>,
    /// Row i maps the channels to component i (xyz).
    basis: array<vec4<f32>, 3>,
    /// Placement cells per period along x and y of a periodic model (cells enter the hash
    /// wrapped modulo them, wrap_cell in common.wgsl, as on the CPU); 0 when not periodic.
    cells_x: i32,
    cells_y: i32,
    /// 1 when the model has turbulence (else the displacement is 0).
    turbulence: u32,
    /// Turbulence strata per axis (planes of `values` after the channels').
    turbulence_strata: u32,
}

/// One channel's structure, packed by the host.
struct ChannelStructure {
    /// b, blocks per period side.
    blocks: u32,
    /// Index in `blocks` of block 0 of this channel.
    first_block: u32,
    /// 0 when the channel has no structure (n_R = 0).
    present: u32,
    /// Index in `block_means` of this channel's mipmap level 0.
    first_mean: u32,
    /// Δ_R = T/b, 1/Δ_R and 1/N as the CPU rounds them (1/(2T) when b = 1).
    delta: f32,
    inv_delta: f32,
    inv_n: f32,
    _pad1: f32,
}

/// A column's (or row's) placement cell and offset in [0, 1) cells.
struct PlacementAxis {
    cell: i32,
    offset: f32,
}

/// Half-width of the placement cross-fade, in cells (spectex_model::texture::PLACEMENT_BLEND).
const PLACEMENT_BLEND: f32 = 0.125f;

@group(0) @binding(0) var<uniform> params: TextureParams;
@group(0) @binding(1) var<storage, read> structures: array<ChannelStructure>;
/// (start in `cosines`, count) of every block, channels in order, blocks row-major.
@group(0) @binding(2) var<storage, read> blocks: array<vec2<u32>>;
/// (k_x, k_y, A, φ) of every fixed cosine; k as f32 (exact, |k| ≤ 4096).
@group(0) @binding(3) var<storage, read> cosines: array<vec4<f32>>;
/// Every channel's mipmap of block means (`Structure::mean_mipmap`): levels b², (b/2)², …, 1.
@group(0) @binding(4) var<storage, read> block_means: array<f32>;
/// (channels + 2·turbulence_strata) planes of width·height values: strata per channel, then
/// the turbulence strata of x, then of y.
@group(0) @binding(5) var<storage, read> values: array<f32>;
@group(0) @binding(6) var<storage, read> columns: array<PlacementAxis>;
@group(0) @binding(7) var<storage, read> rows: array<PlacementAxis>;
@group(0) @binding(8) var<storage, read_write> output: array<f32>;

/// `block_value_filtered`: one block's non-zero cosines, each weighted for footprint `s`.
fn block_value_filtered(span: vec2<u32>, inv_n: f32, ux: f32, uy: f32, s: f32) -> f32 {
    var sum = 0.0f;
    for (var k = span.x; k < span.x + span.y; k++) {
        let c = cosines[k];
        if (c.x == 0.0f && c.y == 0.0f) {
            continue;
        }
        let gain = filter_response(abs(c.x) * inv_n * s) * filter_response(abs(c.y) * inv_n * s);
        if (gain == 0.0f) {
            continue;
        }
        let t = (c.x * ux + c.y * uy) * inv_n + c.w;
        sum += gain * c.z * cos_turns(t);
    }
    return sum;
}

/// The 2×2 cross-fade of `Structure::eval` (spectex_model's `cross_fade`) around q on a grid of
/// cells of side 1/inv_delta: q's place t ∈ [0, 1)² in its cell, the cell, and the weights h.
struct CrossFade {
    t: vec2<f32>,
    cell: vec2<i32>,
    h: vec2<f32>,
}

fn cross_fade(q: vec2<f32>, inv_delta: f32) -> CrossFade {
    let gx = q.x * inv_delta;
    let gy = q.y * inv_delta;
    let fx = floor(gx);
    let fy = floor(gy);
    let t = vec2<f32>(gx - fx, gy - fy);
    let h = vec2<f32>(0.5f + 0.5f * cos_turns(0.5f * t.x), 0.5f + 0.5f * cos_turns(0.5f * t.y));
    return CrossFade(t, vec2<i32>(i32(fx), i32(fy)), h);
}

/// The weight `wx·wy` of tap (di, dj) ∈ {0, 1}².
fn cross_fade_weight(cf: CrossFade, di: i32, dj: i32) -> f32 {
    let wy = select(1.0f - cf.h.y, cf.h.y, dj == 0);
    let wx = select(1.0f - cf.h.x, cf.h.x, di == 0);
    return wx * wy;
}

/// The (column, row) of tap (di, dj) on a grid of `side` cells, a power of two: rem_euclid by
/// a power of two is the two's-complement low bits.
fn cross_fade_cell(cf: CrossFade, di: i32, dj: i32, side: u32) -> vec2<u32> {
    let mask = side - 1u;
    return vec2<u32>(bitcast<u32>(cf.cell.x + di) & mask, bitcast<u32>(cf.cell.y + dj) & mask);
}

/// Level `level` of a channel's mipmap of block means at q, cross-faded on its grid
/// (`eval_filtered`'s `level`).
fn mean_level(st: ChannelStructure, level: u32, q: vec2<f32>) -> f32 {
    let b = st.blocks;
    let side = b >> level;
    var start = st.first_mean;
    for (var l = 0u; l < level; l++) {
        start += (b >> l) * (b >> l);
    }
    if (side == 1u) {
        return block_means[start];
    }
    let delta = st.delta * f32(1u << level);
    let inv_delta = 1.0f / delta;
    let cf = cross_fade(q, inv_delta);
    var sum = 0.0f;
    for (var dj = 0; dj < 2; dj++) {
        for (var di = 0; di < 2; di++) {
            let cell = cross_fade_cell(cf, di, dj, side);
            sum += cross_fade_weight(cf, di, dj) * block_means[start + cell.y * side + cell.x];
        }
    }
    return sum;
}

/// n_R of one channel at q in a minified render of footprint s (`Structure::eval_filtered`).
fn structure_eval_filtered(st: ChannelStructure, q: vec2<f32>, s: f32) -> f32 {
    let b = st.blocks;
    if (b == 1u) {
        return block_value_filtered(blocks[st.first_block], st.inv_n, q.x, q.y, s)
            + block_means[st.first_mean];
    }
    let cf = cross_fade(q, st.inv_delta);
    var sum = 0.0f;
    for (var dj = 0; dj < 2; dj++) {
        let uy = (cf.t.y - f32(dj)) * st.delta;
        for (var di = 0; di < 2; di++) {
            let ux = (cf.t.x - f32(di)) * st.delta;
            let cell = cross_fade_cell(cf, di, dj, b);
            let span = blocks[st.first_block + cell.y * b + cell.x];
            sum += cross_fade_weight(cf, di, dj) * block_value_filtered(span, st.inv_n, ux, uy, s);
        }
    }
    let top = countTrailingZeros(b);
    let lambda = clamp(log2(s * st.inv_delta), 0.0f, f32(top));
    let low = min(u32(lambda), top);
    let f = lambda - f32(low);
    sum += mean_level(st, low, q) * (1.0f - f);
    if (f > 0.0f) {
        sum += mean_level(st, low + 1u, q) * f;
    }
    return sum;
}

/// Σ_k A_k cos 2π(k·u·inv_n + φ_k) over one block's cosines, in order (`block_value`).
fn block_value(span: vec2<u32>, inv_n: f32, ux: f32, uy: f32) -> f32 {
    var sum = 0.0f;
    for (var k = span.x; k < span.x + span.y; k++) {
        let c = cosines[k];
        let t = (c.x * ux + c.y * uy) * inv_n + c.w;
        sum += c.z * cos_turns(t);
    }
    return sum;
}

/// n_R of one channel at q ∈ [0, T)² (`Structure::eval`).
fn structure_eval(s: ChannelStructure, q: vec2<f32>) -> f32 {
    let b = s.blocks;
    if (b == 1u) {
        return block_value(blocks[s.first_block], s.inv_n, q.x, q.y);
    }
    let cf = cross_fade(q, s.inv_delta);
    var sum = 0.0f;
    for (var dj = 0; dj < 2; dj++) {
        let uy = (cf.t.y - f32(dj)) * s.delta;
        for (var di = 0; di < 2; di++) {
            let ux = (cf.t.x - f32(di)) * s.delta;
            let cell = cross_fade_cell(cf, di, dj, b);
            let span = blocks[s.first_block + cell.y * b + cell.x];
            sum += cross_fade_weight(cf, di, dj) * block_value(span, s.inv_n, ux, uy);
        }
    }
    return sum;
}

/// `sin²(πa/2)`, the cross-fade weight of the cell being entered.
fn fade(a: f32) -> f32 {
    return 0.5f - 0.5f * cos_turns(0.5f * a);
}

/// The cells along one axis and their weights (`axis_taps` with blending on).
struct AxisTaps {
    cell: array<i32, 2>,
    weight: array<f32, 2>,
    count: u32,
}

fn axis_taps(c: i32, s: f32) -> AxisTaps {
    // The CPU divides by 2·PLACEMENT_BLEND = 0.25, which is exactly a product by 4.
    if (s < PLACEMENT_BLEND) {
        let g = fade((s + PLACEMENT_BLEND) * 4.0f);
        let before = bitcast<i32>(bitcast<u32>(c) - 1u);
        return AxisTaps(array<i32, 2>(c, before), array<f32, 2>(g, 1.0f - g), 2u);
    }
    if (s >= 1.0f - PLACEMENT_BLEND) {
        let g = fade((s - (1.0f - PLACEMENT_BLEND)) * 4.0f);
        let after = bitcast<i32>(bitcast<u32>(c) + 1u);
        return AxisTaps(array<i32, 2>(c, after), array<f32, 2>(1.0f - g, g), 2u);
    }
    return AxisTaps(array<i32, 2>(c, c), array<f32, 2>(1.0f, 0.0f), 1u);
}

/// Reduces q modulo t (a power of two; inv_t = 1/t exactly), as the CPU's `wrap`.
fn wrap(q: f32, t: f32, inv_t: f32) -> f32 {
    return q - t * floor(q * inv_t);
}

@compute @workgroup_size(8, 8, 1)
fn texture_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let n = params.width * params.height;
    let pixel = gid.y * params.width + gid.x;
    let nc = params.channels;
    var column = columns[gid.x];
    var row = rows[gid.y];
    if (warp_params.enabled == 1u) {
        // Domain warping (common.wgsl): the placement cells move by the displacement in cells
        // of side T/2 (a power of two, so the scaling is exact).
        let dw = warp_displacement[pixel] * (2.0f / f32(params.period));
        let x = warp_relocate(column.cell, column.offset, dw.x);
        let y = warp_relocate(row.cell, row.offset, dw.y);
        column = PlacementAxis(x.cell, x.offset);
        row = PlacementAxis(y.cell, y.offset);
    }
    // Σ_S |n_S| per axis in stratum order, then σ·(Σ − centre): the CPU's f32 operations.
    var d = vec2<f32>(0.0f, 0.0f);
    if (params.turbulence == 1u) {
        let strata_per_axis = params.turbulence_strata;
        for (var axis = 0u; axis < 2u; axis++) {
            var sum = 0.0f;
            for (var s = 0u; s < strata_per_axis; s++) {
                sum += abs(values[(nc + axis * strata_per_axis + s) * n + pixel]);
            }
            d[axis] = params.turbulence_sigma * (sum - params.turbulence_centre);
        }
    }
    var strata = array<f32, 3>(0.0f, 0.0f, 0.0f);
    for (var c = 0u; c < nc; c++) {
        strata[c] = values[c * n + pixel];
    }
    let out = texture_value(column, row, strata, d);
    for (var i = 0u; i < nc; i++) {
        output[pixel * nc + i] = out[i];
    }
}

/// The texture's components (the first `channels`) at the placement cells `column`, `row`,
/// with the random-phase strata's value per channel `strata` and the turbulence displacement
/// `d` (pixels) there.
fn texture_value(column: PlacementAxis, row: PlacementAxis, strata: array<f32, 3>, d: vec2<f32>) -> array<f32, 3> {
    let nc = params.channels;
    // Placement taps (`TextureModel::placement`).
    let t = f32(params.period);
    // 1/T exactly (T is a power of two; WGSL's division is only accurate to 2.5 ulps).
    let inv_t = ldexp(1.0f, -i32(countTrailingZeros(params.period)));
    let p = 0.5f * t;
    let bx = (f32(column.cell & 1) + column.offset) * p;
    let by = (f32(row.cell & 1) + row.offset) * p;
    var weights = array<f32, 4>(0.0f, 0.0f, 0.0f, 0.0f);
    var qs = array<vec2<f32>, 4>();
    var count = 0u;
    if (params.random_placement == 0u) {
        count = 1u;
        weights[0] = 1.0f;
        qs[0] = vec2<f32>(wrap(bx + d.x, t, inv_t), wrap(by + d.y, t, inv_t));
    } else {
        var xs = axis_taps(column.cell, column.offset);
        var ys = axis_taps(row.cell, row.offset);
        var norm = 0.0f;
        for (var ky = 0u; ky < ys.count; ky++) {
            for (var kx = 0u; kx < xs.count; kx++) {
                var prng = Prng(cell_hash(wrap_cell(xs.cell[kx], params.cells_x),
                    wrap_cell(ys.cell[ky], params.cells_y), params.placement_layer, params.seed));
                let sx = prng_next_f32(&prng) * t;
                let sy = prng_next_f32(&prng) * t;
                let w = xs.weight[kx] * ys.weight[ky];
                norm += w * w;
                weights[count] = w;
                qs[count] = vec2<f32>(wrap(bx + sx + d.x, t, inv_t), wrap(by + sy + d.y, t, inv_t));
                count += 1u;
            }
        }
        if (count > 1u) {
            let inv = 1.0f / sqrt(norm);
            for (var k = 0u; k < count; k++) {
                weights[k] *= inv;
            }
        }
    }

    // v_c = strata_c + n_R,c at the taps (`structure_at`).
    var v = array<f32, 3>(0.0f, 0.0f, 0.0f);
    for (var c = 0u; c < nc; c++) {
        let s = structures[c];
        var structure = 0.0f;
        if (s.present != 0u) {
            for (var k = 0u; k < count; k++) {
                if (params.filtered == 1u) {
                    structure += weights[k] * structure_eval_filtered(s, qs[k], params.footprint);
                } else {
                    structure += weights[k] * structure_eval(s, qs[k]);
                }
            }
        }
        v[c] = strata[c] + structure;
    }

    // Colour (`colour_component`).
    var out = array<f32, 3>(0.0f, 0.0f, 0.0f);
    for (var i = 0u; i < nc; i++) {
        var component = v[i];
        if (params.colour != 0u) {
            let r = params.basis[i];
            component = params.colour_mean[i] + r.x * v[0] + r.y * v[1] + r.z * v[2];
        }
        out[i] = component;
    }
    return out;
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a texture by example (after the kernel above and
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
