// texton.wgsl — texton placement / spot noise (survey §2.3, §3.1.5), the GPU twin of
// crates/spectex-cpu/src/texton.rs; the definition is the module doc of
// crates/spectex-model/src/texton.rs. Composed after common.wgsl.
//
// Cell (i, j) seeds Prng(cell_hash(i, j, TEXTON_LAYER, seed)) and draws: for Poisson placement
// one uniform u, the count being the number of k < 16 with u ≥ cdf[k]; then per texton its
// offsets, rotation (turns), scale and weight. A pixel visits the cells within `reach` of its
// own, rows outer and columns inner, textons in draw order, and adds (or keeps the largest of)
// w·g(q) with the CPU's expressions in the CPU's order, so on an adapter that rounds `/` and
// `sqrt` correctly and does not contract `a * b + c` the values are the CPU's bit for bit.
//
// Draws: for an undisplaced tile, `texton_draw` draws each cell of the tile's box once into
// `draws`, and `texton_main` reads them (`texton_value_drawn`) instead of every pixel drawing
// the cells around it (on lavapipe: texton-spots-max 1.8×, texton-image +44%); a displaced
// tile's pixels and the export draw per pixel (`texton_value`).
//
// Positions: the host computes, per column of the tile, p = x / C in f64, the cell ⌊p⌋ and the
// offset p − ⌊p⌋ rounded once to f32 (spectex_model::grid::locate_cell, the CPU's split), and a
// flag that is 0 where it is out of the i32 cell range. Rows likewise.

/// Per-dispatch values and the model's constants.
struct TextonParams {
    width: u32,
    height: u32,
    seed: u32,
    /// Cells beyond a pixel's own that its textons reach.
    reach: i32,
    /// 0: grid (one texton per cell), 1: Poisson count from `model_data[0..16]`.
    placement: u32,
    /// 0: ellipsoid, 1: Gaussian, 2: image (`model_data[16..]`, row-major).
    spot: u32,
    /// 0: sum, 1: maximum over a canvas of 0.
    combine: u32,
    image_width: u32,
    image_height: u32,
    /// Grid jitter, cells.
    jitter: f32,
    /// C, pixels per cell.
    cell_size: f32,
    /// 1 / C (f32 of the f64 value), for warping.
    inv_cell: f32,
    /// (a, b), pixels.
    radius_a: f32,
    radius_b: f32,
    rotation_lo: f32,
    rotation_hi: f32,
    scale_lo: f32,
    scale_hi: f32,
    intensity_lo: f32,
    intensity_hi: f32,
    mean: f32,
    _pad0: u32,
    /// The cell box's first column and row.
    box_i0: i32,
    box_j0: i32,
    /// Cells per period along x and y of a periodic model (cells enter the hash wrapped modulo
    /// them, wrap_cell in common.wgsl, as on the CPU); 0 when not periodic.
    cells_x: i32,
    cells_y: i32,
    /// The cell box's columns and rows (0 columns where `draws` holds nothing: the pixels
    /// draw for themselves); `texton_draw`'s invocations per row of its grid.
    box_cols: u32,
    box_rows: u32,
    draw_stride: u32,
    _pad1: u32,
    _pad2: u32,
    _pad3: u32,
}

@group(0) @binding(0) var<uniform> params: TextonParams;
/// The Poisson CDF (16 values, rounded to f32 by the host) then the image texels.
@group(0) @binding(1) var<storage, read> model_data: array<f32>;
/// When the box has columns, per cell of the box (row-major) a block of `texton_block()` records: the
/// count, then per texton (o_x, o_y, cos, sin) and (1/a, 1/b, weight, 0); `texton_draw`
/// writes them in `output`'s place.
@group(0) @binding(2) var<storage, read> draws: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(4) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(5) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes").
override TEXTON_COMBINE: u32 = 0xffffffffu;
override TEXTON_PLACEMENT: u32 = 0xffffffffu;
override TEXTON_SPOT: u32 = 0xffffffffu;
/// The cells searched beyond the pixel's own: the search loops' bound.
override TEXTON_REACH: u32 = 0xffffffffu;

fn texton_combine() -> u32 {
    return shape_or(TEXTON_COMBINE, params.combine);
}

fn texton_placement() -> u32 {
    return shape_or(TEXTON_PLACEMENT, params.placement);
}

fn texton_spot() -> u32 {
    return shape_or(TEXTON_SPOT, params.spot);
}

fn texton_reach() -> i32 {
    return i32(shape_or(TEXTON_REACH, u32(params.reach)));
}

/// The randomness-contract layer of texton cells ("TEXT").
const TEXTON_LAYER: u32 = 0x54455854u;
/// Most textons in one cell.
const MAX_TEXTONS_PER_CELL: u32 = 16u;
/// −ln 20 = ln 0.05: the Gaussian spot's exponent at ρ = 1.
const NEG_LN_20: f32 = -2.9957323f;
/// Where the image texels start in `model_data`.
const IMAGE_START: u32 = 16u;

fn lerp_range(lo: f32, hi: f32, u: f32) -> f32 {
    return lo + (hi - lo) * u;
}

/// Bilinear sample of the image stretched over [−1, 1]², edges clamped (CPU: texton::bilinear).
fn bilinear(qu: f32, qv: f32) -> f32 {
    let w = params.image_width;
    let h = params.image_height;
    let x = (qu + 1.0f) * 0.5f * f32(w) - 0.5f;
    let y = (qv + 1.0f) * 0.5f * f32(h) - 0.5f;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let xa = min(u32(max(x0, 0.0f)), w - 1u);
    let xb = min(u32(max(x0 + 1.0f, 0.0f)), w - 1u);
    let ya = min(u32(max(y0, 0.0f)), h - 1u);
    let yb = min(u32(max(y0 + 1.0f, 0.0f)), h - 1u);
    let v00 = model_data[IMAGE_START + ya * w + xa];
    let v01 = model_data[IMAGE_START + ya * w + xb];
    let v10 = model_data[IMAGE_START + yb * w + xa];
    let v11 = model_data[IMAGE_START + yb * w + xb];
    let top = v00 + (v01 - v00) * fx;
    let bottom = v10 + (v11 - v10) * fx;
    return top + (bottom - top) * fy;
}

/// The texton's shape at (t_x, t_y) cell units from its centre (CPU: TextonNoise::spot_at).
fn spot_at(tx: f32, ty: f32, c: f32, s: f32, inv_a: f32, inv_b: f32) -> f32 {
    let dx = tx * params.cell_size;
    let dy = ty * params.cell_size;
    let u = c * dx + s * dy;
    let v = c * dy - s * dx;
    let qu = u * inv_a;
    let qv = v * inv_b;
    let r2 = qu * qu + qv * qv;
    if (r2 >= 1.0f) {
        return 0.0f;
    }
    if (texton_spot() == 0u) {
        return sqrt(1.0f - r2);
    }
    if (texton_spot() == 1u) {
        return exp_poly(NEG_LN_20 * r2);
    }
    return bilinear(qu, qv);
}

@compute @workgroup_size(8, 8, 1)
fn texton_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let at = grid_point(columns[gid.x], rows[gid.y], index, params.inv_cell);
    let column = at.column;
    let row = at.row;
    if (params.box_cols != 0u) {
        output[index] = texton_value_drawn(column, row);
    } else {
        output[index] = texton_value(column, row);
    }
}

/// One texton as `texton_value` draws it: its offsets in the cell, the cosine and sine of its
/// rotation, `1/a` and `1/b` at its scale, and its weight.
struct Texton {
    ox: f32,
    oy: f32,
    c: f32,
    s: f32,
    inv_a: f32,
    inv_b: f32,
    weight: f32,
}

/// Cell (cell_x, cell_y)'s stream.
fn texton_prng(cell_x: i32, cell_y: i32) -> Prng {
    return Prng(cell_hash(wrap_cell(cell_x, params.cells_x),
        wrap_cell(cell_y, params.cells_y), TEXTON_LAYER, params.seed));
}

/// The cell's texton count: one on a grid; for Poisson placement, drawn from `prng`.
fn texton_count(prng: ptr<function, Prng>) -> u32 {
    if (texton_placement() != 1u) {
        return 1u;
    }
    let u = prng_next_f32(prng);
    var count = 0u;
    for (var k = 0u; k < MAX_TEXTONS_PER_CELL; k++) {
        if (u >= model_data[k]) {
            count += 1u;
        }
    }
    return count;
}

/// The next texton of `prng`: its draws in the contract's order.
fn texton_next(prng: ptr<function, Prng>) -> Texton {
    var ox: f32;
    var oy: f32;
    if (texton_placement() == 1u) {
        ox = prng_next_f32(prng);
        oy = prng_next_f32(prng);
    } else {
        ox = 0.5f + params.jitter * (prng_next_f32(prng) - 0.5f);
        oy = 0.5f + params.jitter * (prng_next_f32(prng) - 0.5f);
    }
    let turns = lerp_range(params.rotation_lo, params.rotation_hi, prng_next_f32(prng));
    let scale = lerp_range(params.scale_lo, params.scale_hi, prng_next_f32(prng));
    let weight = lerp_range(params.intensity_lo, params.intensity_hi, prng_next_f32(prng));
    let inv_a = 1.0f / (params.radius_a * scale);
    let inv_b = 1.0f / (params.radius_b * scale);
    return Texton(ox, oy, cos_turns(turns), sin_turns(turns), inv_a, inv_b, weight);
}

/// Records a cell block of `draws` holds: the count, then two per texton (one texton a grid
/// cell, at most MAX_TEXTONS_PER_CELL a Poisson one).
fn texton_block() -> u32 {
    return 1u + 2u * select(1u, MAX_TEXTONS_PER_CELL, texton_placement() == 1u);
}

/// Draws each cell of the tile's box once (one invocation a cell) into `output` (the buffer
/// `texton_main` then binds as `draws`): the values every pixel's own draws give.
@compute @workgroup_size(64, 1, 1)
fn texton_draw(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.draw_stride + gid.x;
    if (c >= params.box_cols * params.box_rows) {
        return;
    }
    let cell_x = bitcast<i32>(bitcast<u32>(params.box_i0) + c % params.box_cols);
    let cell_y = bitcast<i32>(bitcast<u32>(params.box_j0) + c / params.box_cols);
    var prng = texton_prng(cell_x, cell_y);
    let count = texton_count(&prng);
    let base = 4u * c * texton_block();
    output[base] = f32(count);
    output[base + 1u] = 0.0f;
    output[base + 2u] = 0.0f;
    output[base + 3u] = 0.0f;
    for (var n = 0u; n < count; n++) {
        let t = texton_next(&prng);
        let at = base + 4u + 8u * n;
        output[at] = t.ox;
        output[at + 1u] = t.oy;
        output[at + 2u] = t.c;
        output[at + 3u] = t.s;
        output[at + 4u] = t.inv_a;
        output[at + 5u] = t.inv_b;
        output[at + 6u] = t.weight;
        output[at + 7u] = 0.0f;
    }
}

/// `texton_value` with each cell's textons read from `draws` (the cells of the tile's box):
/// its own copy of the loop, the same sum in the same order (`gabor_value_drawn`'s reason).
fn texton_value_drawn(column: GridAxis, row: GridAxis) -> f32 {
    if (column.valid == 0u || row.valid == 0u) {
        return params.mean;
    }
    let reach = texton_reach();
    let half = select(0.5f * abs(params.jitter), 0.5f, texton_placement() == 1u) + 1e-5f;
    let support = texton_support();
    var acc = 0.0f;
    for (var dj = -reach; dj <= reach; dj++) {
        let gy = texton_gap(row.offset, dj, half);
        let j = bitcast<u32>(row.cell) + bitcast<u32>(dj) - bitcast<u32>(params.box_j0);
        for (var di = -reach; di <= reach; di++) {
            let gx = texton_gap(column.offset, di, half);
            if (gx * gx + gy * gy >= support * support) {
                continue;
            }
            let i = bitcast<u32>(column.cell) + bitcast<u32>(di) - bitcast<u32>(params.box_i0);
            // The box holds every cell within `reach` of the tile's pixels.
            let base = (j * params.box_cols + i) * texton_block();
            var count = 1u;
            if (texton_placement() == 1u) {
                count = u32(draws[base].x);
            }
            for (var n = 0u; n < count; n++) {
                let a = draws[base + 1u + 2u * n];
                let b = draws[base + 2u + 2u * n];
                let tx = column.offset - (f32(di) + a.x);
                let ty = row.offset - (f32(dj) + a.y);
                let contribution = b.z * spot_at(tx, ty, a.z, a.w, b.x, b.y);
                if (texton_combine() == 0u) {
                    acc += contribution;
                } else if (contribution > acc) {
                    acc = contribution;
                }
            }
        }
    }
    return params.mean + acc;
}

/// The distance along one axis, cell units, from a point at `offset` in its cell to the
/// texton centres of the cell `s` away, which lie within `half` of that cell's middle.
fn texton_gap(offset: f32, s: i32, half: f32) -> f32 {
    let middle = f32(s) + 0.5f;
    return max(abs(offset - middle) - half, 0.0f);
}

/// How far from its centre a texton can contribute, cell units: `max(a, b)·max s / C`
/// (spectex_model's `support_radius`), grown by 10⁻³, far beyond the roundings of `spot_at`'s
/// `r²` (a few ulps, and cos_turns' and sin_turns' 10⁻⁶). A cell whose centres all lie at
/// least this far from the pixel holds only textons that add exactly 0 (their `spot_at` is
/// 0, and a sum or a maximum over a canvas of +0 ignores ±0): `texton_value` skips it, and
/// its draws, its own PRNG's, change no other cell's.
fn texton_support() -> f32 {
    let radius = max(params.radius_a, params.radius_b)
        * max(abs(params.scale_lo), abs(params.scale_hi));
    return radius / params.cell_size * 1.001f;
}

/// The texture at the point `column`, `row` (its cells and offsets in cell units): the mean
/// outside the usable range, else the mean plus the textons of the cells within `reach`.
fn texton_value(column: GridAxis, row: GridAxis) -> f32 {
    if (column.valid == 0u || row.valid == 0u) {
        return params.mean;
    }
    let reach = texton_reach();
    // Where a cell's texton centres lie along an axis (a grid's jitter around ½, anywhere for
    // Poisson placement), widened by far more than their roundings.
    let half = select(0.5f * abs(params.jitter), 0.5f, texton_placement() == 1u) + 1e-5f;
    let support = texton_support();
    var acc = 0.0f;
    for (var dj = -reach; dj <= reach; dj++) {
        let cell_y = bitcast<i32>(bitcast<u32>(row.cell) + bitcast<u32>(dj));
        let gy = texton_gap(row.offset, dj, half);
        for (var di = -reach; di <= reach; di++) {
            let cell_x = bitcast<i32>(bitcast<u32>(column.cell) + bitcast<u32>(di));
            let gx = texton_gap(column.offset, di, half);
            if (gx * gx + gy * gy >= support * support) {
                continue;
            }
            var prng = texton_prng(cell_x, cell_y);
            let count = texton_count(&prng);
            for (var n = 0u; n < count; n++) {
                let t = texton_next(&prng);
                let tx = column.offset - (f32(di) + t.ox);
                let ty = row.offset - (f32(dj) + t.oy);
                let contribution = t.weight * spot_at(tx, ty, t.c, t.s, t.inv_a, t.inv_b);
                if (texton_combine() == 0u) {
                    acc += contribution;
                } else if (contribution > acc) {
                    acc = contribution;
                }
            }
        }
    }
    return params.mean + acc;
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a texton model (after the kernel above and
// export/split.wgsl): lattice 0 of the export tables is the texton grid (cell side C).

/// The texture at the position `cell + offset` (pixels).
fn texton_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    return texton_value(export_grid_axis(at.n.x, at.u.x, 0u), export_grid_axis(at.n.y, at.u.y, 0u));
}
