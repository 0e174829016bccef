// subdivision.wgsl — stochastic subdivision (survey §3.1.7), the GPU twin of
// crates/spectex-cpu/src/subdivision.rs; the definition is the module doc of
// crates/spectex-model/src/subdivision.rs. Composed after common.wgsl.
//
// The host sends each column's and row's coarse cell and f32 offset (spectex_model::grid::
// locate_cell, the CPU's split) and the level scales σ_ℓ/√21845 (f32 of the CPU's f64). A pixel
// finds its finest cell ⌊t·2^L⌋ (exact in f32), the W × W block of lattice points each level
// needs (W = 2 midpoint, 6 cubic), and computes the blocks from level 0 to L: the stencil along
// x, then along y, plus the hashed displacement of each new point (integers, bit-identical to
// the CPU's). Only the sums differ from the CPU: f32 here, f64 there.

/// Per-dispatch values and the model's constants.
struct SubdivisionParams {
    width: u32,
    height: u32,
    seed: u32,
    /// L.
    levels: u32,
    /// 0: midpoint (bilinear), 1: cubic (4-point stencil, Catmull–Rom).
    cubic: u32,
    mean: f32,
    /// 1 / C (f32 of the f64 value), for warping.
    inv_cell: f32,
    _pad0: u32,
}

@group(0) @binding(0) var<uniform> params: SubdivisionParams;
/// σ_ℓ/√21845 for ℓ = 0..=L.
@group(0) @binding(1) var<storage, read> scales: array<f32>;
@group(0) @binding(2) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(3) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(4) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes").
override SUBDIVISION_CUBIC: u32 = 0xffffffffu;

fn subdivision_cubic() -> u32 {
    return shape_or(SUBDIVISION_CUBIC, params.cubic);
}

/// spectex_model::subdivision::SUBDIVISION_LAYER ("SUBD").
const SUBDIVISION_LAYER: u32 = 0x53554244u;

/// spectex_model::subdivision::normalise: (c + ⌊k/2^ℓ⌋ wrapping, k mod 2^ℓ).
fn subdivision_normalise(c: i32, k: i32, level: u32) -> vec2<i32> {
    let carry = k >> level;
    return vec2<i32>(bitcast<i32>(bitcast<u32>(c) + bitcast<u32>(carry)), k & ((1i << level) - 1i));
}

/// The part of spectex_model::subdivision::lattice_bits shared by the level-`level` points of
/// coarse cell `c`: `layer_key(SUBDIVISION_LAYER + level, cell_hash(c, SUBDIVISION_LAYER,
/// seed))`, four of its six hashes.
fn subdivision_key(level: u32, c: vec2<i32>) -> u32 {
    return layer_key(SUBDIVISION_LAYER + level, cell_hash(c.x, c.y, SUBDIVISION_LAYER, params.seed));
}

/// The displacement's centred byte sum at index `k` (normalised) of the points whose
/// `subdivision_key` is `key`: spectex_model::subdivision::{lattice_bits, centred_byte_sum},
/// exact in f32.
fn subdivision_displacement(key: u32, k: vec2<i32>) -> f32 {
    let b = cell_hash_in_row(k.x, row_key(k.y, key));
    let sum = (b & 0xffu) + ((b >> 8u) & 0xffu) + ((b >> 16u) & 0xffu) + (b >> 24u);
    return f32(i32(sum) - 510i);
}

/// Stencil::final_weights at u: (1 − u, u) or Catmull–Rom's.
fn subdivision_final_weights(u: f32) -> vec4<f32> {
    if (subdivision_cubic() == 1u) {
        let u2 = u * u;
        let u3 = u * u * u;
        return vec4<f32>(
            0.5f * (-u3 + 2.0f * u2 - u),
            0.5f * (3.0f * u3 - 5.0f * u2 + 2.0f),
            0.5f * (-3.0f * u3 + 4.0f * u2 + u),
            0.5f * (u3 - u2),
        );
    }
    return vec4<f32>(1.0f - u, u, 0.0f, 0.0f);
}

/// One refinement of the parent values `p` along an axis (spectex_model's `Stencil::taps`):
/// the values at level indexes o … o + W − 1 from the parents at (o >> 1) − r …, `odd` the
/// parity of o. An even index takes its parent, an odd one the stencil S_k at parent k:
/// - cubic (W = 6, r = 1), S_k = (−p_k + 9p_{k+1} + 9p_{k+2} − p_{k+3})/16: for an even o
///   [p₁, S₀, p₂, S₁, p₃, S₂], for an odd o [S₀, p₂, S₁, p₃, S₂, p₄];
/// - midpoint (W = 2, r = 0), S₀ = (p₀ + p₁)/2: [p₀, S₀] or [S₀, p₁] (the rest unused).
/// Each value is the stencil's sum in the CPU's order, from +0 over the taps (a taken parent's
/// other taps weigh 0 and add ±0, hence `0 + p`), in f32, at indexes that are constants: a
/// loop over the taps read the parents at a data-dependent index, by five selects a tap, and
/// ran the cubic model at 0.48 Mpix/s on lavapipe where this runs at 0.79.
fn subdivision_refine(p: array<f32, 6>, odd: bool) -> array<f32, 6> {
    if (subdivision_cubic() == 1u) {
        let s0 = subdivision_cubic_tap(p[0], p[1], p[2], p[3]);
        let s1 = subdivision_cubic_tap(p[1], p[2], p[3], p[4]);
        let s2 = subdivision_cubic_tap(p[2], p[3], p[4], p[5]);
        return array<f32, 6>(
            select(0.0f + p[1], s0, odd),
            select(s0, 0.0f + p[2], odd),
            select(0.0f + p[2], s1, odd),
            select(s1, 0.0f + p[3], odd),
            select(0.0f + p[3], s2, odd),
            select(s2, 0.0f + p[4], odd),
        );
    }
    let s0 = (0.0f + 0.5f * p[0]) + 0.5f * p[1];
    return array<f32, 6>(select(0.0f + p[0], s0, odd), select(s0, 0.0f + p[1], odd), 0.0f, 0.0f, 0.0f, 0.0f);
}

/// The cubic stencil's weights (−1, 9, 9, −1)/16 at a, b, c, d, summed from +0 in order.
fn subdivision_cubic_tap(a: f32, b: f32, c: f32, d: f32) -> f32 {
    return (((0.0f + -0.0625f * a) + 0.5625f * b) + 0.5625f * c) + -0.0625f * d;
}

/// The texture at offset (tx, ty) of coarse cell (cx, cy): the W × W block of each level from
/// 0 to L (`subdivision_refine`, then the new points' displacements), then the final weights'
/// sum over its first `n_final` × `n_final` values, in loops of constant length that a
/// compiler unrolls, so `block` and `tmp` are read at constant indexes.
fn subdivision_value(cx: i32, tx: f32, cy: i32, ty: f32) -> f32 {
    let levels = params.levels;
    let side = f32(1u << levels);
    let fx = tx * side;
    let fy = ty * side;
    let kx = floor(fx);
    let ky = floor(fy);
    var w = 2i;
    var r = 0i;
    var n_final = 2i;
    if (subdivision_cubic() == 1u) {
        w = 6i;
        r = 1i;
        n_final = 4i;
    }
    // Level l's block origin: o_L = k − r and o_{l−1} = (o_l >> 1) − r, that is
    // o_l = ((k + r) >> (L − l)) − 2r (x_l = o_l + 2r halves: x_{l−1} = x_l >> 1), where an
    // array of the origins indexed by the runtime level lived in per-invocation memory.
    let k = vec2<i32>(i32(kx), i32(ky)) + vec2<i32>(r);
    var block: array<array<f32, 6>, 6>;
    var tmp: array<array<f32, 6>, 6>;
    let o0 = (k >> vec2<u32>(levels)) - vec2<i32>(2i * r);
    for (var j = 0i; j < w; j = j + 1i) {
        let py = subdivision_normalise(cy, o0.y + j, 0u).x;
        for (var i = 0i; i < w; i = i + 1i) {
            let px = subdivision_normalise(cx, o0.x + i, 0u).x;
            block[j][i] = scales[0] * subdivision_displacement(subdivision_key(0u, vec2<i32>(px, py)), vec2<i32>(0i, 0i));
        }
    }
    for (var l = 1u; l <= levels; l = l + 1u) {
        let o = (k >> vec2<u32>(levels - l)) - vec2<i32>(2i * r);
        // Along x, row by row, then along y, column by column (`subdivision_refine`), and the
        // new points' displacements.
        for (var j = 0i; j < w; j = j + 1i) {
            tmp[j] = subdivision_refine(block[j], (o.x & 1i) == 1i);
        }
        // The key of the last new point's coarse cell: a level's block lies in one or a few
        // coarse cells, so most of its new points reuse it (two hashes each, not six).
        var key_cell = vec2<i32>(0i, 0i);
        var key = 0u;
        var have_key = false;
        for (var i = 0i; i < w; i = i + 1i) {
            let column = subdivision_refine(
                array<f32, 6>(tmp[0][i], tmp[1][i], tmp[2][i], tmp[3][i], tmp[4][i], tmp[5][i]),
                (o.y & 1i) == 1i,
            );
            let qx = o.x + i;
            for (var j = 0i; j < w; j = j + 1i) {
                let qy = o.y + j;
                var s = column[j];
                if (((qx | qy) & 1i) == 1i) {
                    let nx = subdivision_normalise(cx, qx, l);
                    let ny = subdivision_normalise(cy, qy, l);
                    let c = vec2<i32>(nx.x, ny.x);
                    if (!have_key || any(c != key_cell)) {
                        key = subdivision_key(l, c);
                        key_cell = c;
                        have_key = true;
                    }
                    s = s + scales[l] * subdivision_displacement(key, vec2<i32>(nx.y, ny.y));
                }
                block[j][i] = s;
            }
        }
    }
    let wx = subdivision_final_weights(fx - kx);
    let wy = subdivision_final_weights(fy - ky);
    var sum = 0.0f;
    for (var b = 0i; b < n_final; b = b + 1i) {
        var row = 0.0f;
        for (var a = 0i; a < n_final; a = a + 1i) {
            row = row + wx[a] * block[b][a];
        }
        sum = sum + wy[b] * row;
    }
    return params.mean + sum;
}

@compute @workgroup_size(8, 8, 1)
fn subdivision_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let at = grid_point(columns[gid.x], rows[gid.y], index, params.inv_cell);
    let column = at.column;
    let row = at.row;
    let cx = select(0i, column.cell, column.valid == 1u);
    let tx = select(0.0f, column.offset, column.valid == 1u);
    let cy = select(0i, row.cell, row.valid == 1u);
    let ty = select(0.0f, row.offset, row.valid == 1u);
    output[index] = subdivision_value(cx, tx, cy, ty);
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a stochastic subdivision (after
// the kernel above and export/split.wgsl): lattice 0 of the export tables is the coarse lattice
// (cell side C).

/// The texture at the position `cell + offset` (pixels).
fn subdivision_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let column = export_grid_axis(at.n.x, at.u.x, 0u);
    let row = export_grid_axis(at.n.y, at.u.y, 0u);
    return subdivision_value(column.cell, column.offset, row.cell, row.offset);
}
