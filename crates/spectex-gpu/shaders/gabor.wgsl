// gabor.wgsl — Gabor noise by sparse convolution (Lagae et al. 2009), the GPU twin of
// crates/spectex-cpu/src/gabor.rs (whose module doc is the specification). Composed after
// common.wgsl.
//
// The plane is cut into square cells of side r (the kernel radius). Cell (i, j) holds the
// impulses drawn from Prng(cell_hash(i, j, 0, seed)): a Poisson count by Knuth's method with
// renormalisation by exp(64) and a cap, then per impulse x offset, y offset, weight 2u − 1 and,
// for isotropic noise only, the direction u (turns t_min + u·span), or for a spectrum (Gabor
// noise by example) the component u: the number of cumulative entries ≤ u (binary search; any
// search of the monotone table gives the CPU's index). All of this is integer or exact f32
// work, so the impulses are the CPU's bit for bit.
//
// A pixel sums the three cell columns s = −1, 0, 1 separately; column i + s lists the impulses
// of the cells (i+s, j−1), (i+s, j), (i+s, j+1) in draw order, keeps those with d_y² < 1, and
// adds the k-th kept one to accumulator k mod 8; the column sum is
// ((a₀+a₁)+(a₂+a₃))+((a₄+a₅)+(a₆+a₇)) and the value mean + ((c₋₁ + c₀) + c₁), the CPU's order.
//
// Draws: for an undisplaced tile, `gabor_draw` draws each cell of the tile's box once (one
// invocation a cell) into `draws`, and `gabor_main` reads them (`gabor_value_drawn`): every
// pixel used to draw its 3×3 cells itself, so each cell was drawn by all the pixels around it
// (on lavapipe: gabor-by-example 1.9 → 3.8 Mpix/s, gabor-isotropic +27%, gabor-anisotropic
// +10%). A displaced tile's pixels and the export draw per pixel (`gabor_value`).
//
// Positions: the host computes, per column of the tile, p = x / r in f64, the cell ⌊p⌋ and the
// offset p − ⌊p⌋ rounded once to f32 (the CPU's expression, so the same bits), and a flag that
// is 0 where the CPU's evaluator returns `mean` (|p| beyond the i32 cell range). Rows likewise.

/// Per-dispatch values; the model's constants in the units of the kernel loop (cell units).
struct GaborParams {
    width: u32,
    height: u32,
    seed: u32,
    /// 0: one frequency vector (dir_a, dir_b) = (f_x, f_y); 1: random angle in turns
    /// dir_a + u·dir_b; 2: a component drawn from `components`.
    direction_kind: u32,
    mean: f32,
    /// K.
    amplitude: f32,
    /// exp(−ρ), the Knuth threshold once the exp(64) chunks are used up.
    poisson_threshold: f32,
    /// ⌊λ / 64⌋.
    poisson_chunks: u32,
    /// exp(64) and exp(−64) rounded to f32.
    chunk_up: f32,
    chunk_down: f32,
    /// N_max = ⌊4λ + 32⌋.
    max_impulses: u32,
    /// F₀·r, cycles per cell.
    frequency_cells: f32,
    dir_a: f32,
    dir_b: f32,
    /// 1 / r, cell units per pixel (f32 of the f64 value), for warping.
    inv_radius: f32,
    /// Entries of `components` (0 unless direction_kind is 2).
    components: u32,
    /// Cells per period along x and y of a periodic noise (cells enter the hash wrapped modulo
    /// them, wrap_cell in common.wgsl, as on the CPU); 0 when not periodic.
    cells_x: i32,
    cells_y: i32,
    _pad2: u32,
    /// The cell box: first column and row, columns, rows (`gabor_draw`'s invocations are its
    /// cells, `draw_stride` per row of its dispatch grid); 0 columns where `draws` holds
    /// nothing (the pixels draw for themselves).
    box_i0: i32,
    box_j0: i32,
    box_cols: u32,
    box_rows: u32,
    draw_stride: u32,
}

/// One component of a spectrum: its frequency vector in cycles per cell unit and its
/// cumulative weight C_k.
struct GaborComponent {
    fx: f32,
    fy: f32,
    cumulative: f32,
    /// Where `pick_component` starts for u in [k/n, (k + 1)/n): the number of cumulative
    /// entries ≤ k/n, at most n − 1.
    guide: u32,
}

@group(0) @binding(0) var<uniform> params: GaborParams;
@group(0) @binding(1) var<storage, read> components: array<GaborComponent>;
/// When the box has columns, per cell of the box (row-major) a block of `1 + 2·max_impulses` records:
/// the count, then per impulse (o_x, o_y, w, f_x) and (f_y, 0, 0, 0); `gabor_draw` writes
/// them in `output`'s place.
@group(0) @binding(2) var<storage, read> draws: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(4) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(5) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes"): one direction, a range of angles or a spectrum's
// components.
override GABOR_DIRECTION_KIND: u32 = 0xffffffffu;

fn gabor_direction_kind() -> u32 {
    return shape_or(GABOR_DIRECTION_KIND, params.direction_kind);
}

/// The randomness-contract layer of Gabor impulses.
const GABOR_LAYER: u32 = 0u;
/// −ln 20 = ln 0.05: the Gaussian exponent per squared cell unit, −π a² r².
const NEG_LN_20: f32 = -2.9957323f;

/// Knuth's multiplication method with renormalisation (CPU: GaborEvaluator::poisson_count).
fn poisson_count(prng: ptr<function, Prng>) -> u32 {
    var p = 1.0f;
    var chunks = params.poisson_chunks;
    for (var k = 0u; k < params.max_impulses; k++) {
        p *= prng_next_f32(prng);
        while (chunks > 0u && p < params.chunk_down) {
            p *= params.chunk_up;
            chunks -= 1u;
        }
        if (chunks == 0u && p < params.poisson_threshold) {
            return k;
        }
    }
    return params.max_impulses;
}

/// The component u picks: the number of cumulative entries ≤ u, at most n − 1 (CPU:
/// spectex_model::pick_component). From the guide of u's bucket, up while the entry is ≤ u,
/// then down while the one before is > u: the count from any start (the entries do not
/// decrease), in a step or two from the guide's, where a binary search takes log₂ n.
fn pick_component(u: f32) -> u32 {
    let last = params.components - 1u;
    var i = components[min(u32(u * f32(params.components)), last)].guide;
    loop {
        if (i >= last || components[i].cumulative > u) {
            break;
        }
        i += 1u;
    }
    loop {
        if (i == 0u || components[i - 1u].cumulative <= u) {
            break;
        }
        i -= 1u;
    }
    return i;
}

/// One impulse's contribution at d_x = uxs − ox; 0 beyond the radius.
fn kernel_term(uxs: f32, ox: f32, fx: f32, dy2: f32, py: f32, kw: f32) -> f32 {
    let dx = uxs - ox;
    let d2 = dx * dx + dy2;
    if (d2 >= 1.0f) {
        return 0.0f;
    }
    let gauss = exp_poly(NEG_LN_20 * d2);
    let wave = cos_turns(fx * dx + py);
    return kw * gauss * wave;
}

/// The noise at the pixel whose column and row are located by `column` and `row` (both valid):
/// the per-pixel evaluation, shared by `gabor_main` and the exported module
/// (the export glue at the end of this file, which locates the pixel itself).
fn gabor_value(column: GridAxis, row: GridAxis) -> f32 {
    let key = layer_key(GABOR_LAYER, params.seed);
    var sums = array<f32, 3>(0.0f, 0.0f, 0.0f);
    for (var s = 0; s < 3; s++) {
        let uxs = column.offset - f32(s - 1);
        let cell_x = bitcast<i32>(bitcast<u32>(column.cell) + bitcast<u32>(s - 1));
        // The 8 accumulators as two vectors, the k-th kept term added to accumulator k mod 8
        // by a select: the others add +0, which leaves them as they are (a sum that starts at
        // +0 is never −0). An array indexed by `kept & 7` lived in per-invocation memory.
        var acc_lo = vec4<f32>(0.0f);
        var acc_hi = vec4<f32>(0.0f);
        var kept = 0u;
        for (var t = 0; t < 3; t++) {
            let uyt = row.offset - f32(t - 1);
            let cell_y = bitcast<i32>(bitcast<u32>(row.cell) + bitcast<u32>(t - 1));
            var prng = Prng(cell_hash_in_row(wrap_cell(cell_x, params.cells_x),
                row_key(wrap_cell(cell_y, params.cells_y), key)));
            let count = poisson_count(&prng);
            for (var n = 0u; n < count; n++) {
                let imp = gabor_impulse(&prng);
                let dy = uyt - imp.oy;
                let dy2 = dy * dy;
                if (dy2 < 1.0f) {
                    let term = vec4<f32>(kernel_term(uxs, imp.ox, imp.fx, dy2, imp.fy * dy, params.amplitude * imp.w));
                    let lane = vec4<u32>(kept & 7u);
                    acc_lo += select(vec4<f32>(0.0f), term, lane == vec4<u32>(0u, 1u, 2u, 3u));
                    acc_hi += select(vec4<f32>(0.0f), term, lane == vec4<u32>(4u, 5u, 6u, 7u));
                    kept += 1u;
                }
            }
        }
        sums[s] = ((acc_lo.x + acc_lo.y) + (acc_lo.z + acc_lo.w)) + ((acc_hi.x + acc_hi.y) + (acc_hi.z + acc_hi.w));
    }
    return params.mean + ((sums[0] + sums[1]) + sums[2]);
}

/// The impulses of cell (cell_x, cell_y) as `gabor_value` draws them: its count, then per
/// impulse the offsets, weight and frequency vector.
struct GaborImpulse {
    ox: f32,
    oy: f32,
    w: f32,
    fx: f32,
    fy: f32,
}

/// The next impulse of `prng` (after its count): `gabor_value`'s draws, in its order.
fn gabor_impulse(prng: ptr<function, Prng>) -> GaborImpulse {
    let ox = prng_next_f32(prng);
    let oy = prng_next_f32(prng);
    let w = 2.0f * prng_next_f32(prng) - 1.0f;
    var fx = params.dir_a;
    var fy = params.dir_b;
    if (gabor_direction_kind() == 1u) {
        let turns = params.dir_a + prng_next_f32(prng) * params.dir_b;
        fx = params.frequency_cells * cos_turns(turns);
        fy = params.frequency_cells * cos_turns(turns - 0.25f);
    } else if (gabor_direction_kind() == 2u) {
        let c = components[pick_component(prng_next_f32(prng))];
        fx = c.fx;
        fy = c.fy;
    }
    return GaborImpulse(ox, oy, w, fx, fy);
}

/// Records a cell block of `draws` holds (`1 + 2·max_impulses`).
fn gabor_block() -> u32 {
    return 1u + 2u * params.max_impulses;
}

/// Draws each cell of the tile's box once (one invocation a cell): its count and impulses,
/// into `output` (the buffer `gabor_main` then binds as `draws`), the same f32 values every
/// pixel's own draws give, so the tile renders the same bits.
@compute @workgroup_size(64, 1, 1)
fn gabor_draw(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.draw_stride + gid.x;
    if (c >= params.box_cols * params.box_rows) {
        return;
    }
    let cell_x = bitcast<i32>(bitcast<u32>(params.box_i0) + c % params.box_cols);
    let cell_y = bitcast<i32>(bitcast<u32>(params.box_j0) + c / params.box_cols);
    var prng = Prng(cell_hash_in_row(wrap_cell(cell_x, params.cells_x),
        row_key(wrap_cell(cell_y, params.cells_y), layer_key(GABOR_LAYER, params.seed))));
    let count = poisson_count(&prng);
    let base = 4u * c * gabor_block();
    output[base] = f32(count);
    output[base + 1u] = 0.0f;
    output[base + 2u] = 0.0f;
    output[base + 3u] = 0.0f;
    for (var n = 0u; n < count; n++) {
        let imp = gabor_impulse(&prng);
        let at = base + 4u + 8u * n;
        output[at] = imp.ox;
        output[at + 1u] = imp.oy;
        output[at + 2u] = imp.w;
        output[at + 3u] = imp.fx;
        output[at + 4u] = imp.fy;
        output[at + 5u] = 0.0f;
        output[at + 6u] = 0.0f;
        output[at + 7u] = 0.0f;
    }
}

/// `gabor_value` with each cell's impulses read from `draws` (the cells of the tile's box):
/// its own copy of the loop, the same accumulation in the same order, as `lrp_main` keeps its
/// drawn loop apart (one loop taking both ways is slower on lavapipe).
fn gabor_value_drawn(column: GridAxis, row: GridAxis) -> f32 {
    var sums = array<f32, 3>(0.0f, 0.0f, 0.0f);
    for (var s = 0; s < 3; s++) {
        let uxs = column.offset - f32(s - 1);
        let i = bitcast<u32>(column.cell) + bitcast<u32>(s - 1) - bitcast<u32>(params.box_i0);
        var acc_lo = vec4<f32>(0.0f);
        var acc_hi = vec4<f32>(0.0f);
        var kept = 0u;
        for (var t = 0; t < 3; t++) {
            let uyt = row.offset - f32(t - 1);
            let j = bitcast<u32>(row.cell) + bitcast<u32>(t - 1) - bitcast<u32>(params.box_j0);
            // The box holds every cell of the tile's pixels and their neighbours.
            let base = (j * params.box_cols + i) * gabor_block();
            let count = u32(draws[base].x);
            for (var n = 0u; n < count; n++) {
                let a = draws[base + 1u + 2u * n];
                let dy = uyt - a.y;
                let dy2 = dy * dy;
                if (dy2 < 1.0f) {
                    let fy = draws[base + 2u + 2u * n].x;
                    let term = vec4<f32>(kernel_term(uxs, a.x, a.w, dy2, fy * dy, params.amplitude * a.z));
                    let lane = vec4<u32>(kept & 7u);
                    acc_lo += select(vec4<f32>(0.0f), term, lane == vec4<u32>(0u, 1u, 2u, 3u));
                    acc_hi += select(vec4<f32>(0.0f), term, lane == vec4<u32>(4u, 5u, 6u, 7u));
                    kept += 1u;
                }
            }
        }
        sums[s] = ((acc_lo.x + acc_lo.y) + (acc_lo.z + acc_lo.w)) + ((acc_hi.x + acc_hi.y) + (acc_hi.z + acc_hi.w));
    }
    return params.mean + ((sums[0] + sums[1]) + sums[2]);
}

@compute @workgroup_size(8, 8, 1)
fn gabor_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let at = grid_point(columns[gid.x], rows[gid.y], index, params.inv_radius);
    let column = at.column;
    let row = at.row;
    if (column.valid == 0u || row.valid == 0u) {
        output[index] = params.mean;
        return;
    }
    if (params.box_cols != 0u) {
        output[index] = gabor_value_drawn(column, row);
    } else {
        output[index] = gabor_value(column, row);
    }
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a Gabor model (after the kernel above and
// export/split.wgsl): lattice 0 of the export tables is the kernel radius r (cell side).

/// The noise at the position `cell + offset` (pixels).
fn gabor_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    return gabor_value(export_grid_axis(at.n.x, at.u.x, 0u), export_grid_axis(at.n.y, at.u.y, 0u));
}
