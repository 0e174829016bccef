// lrp.wgsl — Local Random-Phase noise (Gilet et al. 2014, Eqs. 1–2), the GPU twin of
// crates/spectex-cpu/src/lrp.rs. Composed after common.wgsl.
//
// For stratum s (lattice period Δ_s, amplitude A_s) a pixel sums over the lattice points
// (cx, cy) within 1.5·Δ_s, in ascending (cy, cx) order,
//     A_s · w(r²) · Σ_j cos_turns(f_x·dx + (f_y·dy + φ_j))
// where (dx, dy) is the pixel's position minus the lattice point's, in pixels, and the draws of
// a lattice point are Prng(cell_hash(cx, cy, s, seed)): per cosine j in order, the table index
// next_u32() % len_j, then the phase next_f32() in turns. The value is Σ_s (in order) + mean.
//
// Positions (invariant 2 of docs/ARCHITECTURE.md). WGSL has no f64, so the host does the f64 part: for each
// stratum and each column i of the tile it computes the window position x_i (f64, the CPU's
// expression), the lattice column c_i = ⌊x_i / Δ⌋, and the four offsets
// d_k = f32(x_i − (c_i + k − 1)·Δ) for k = 0..3, i.e. to the lattice columns c_i − 1 … c_i + 2,
// which hold every lattice point within 1.5·Δ of x_i. Rows likewise. Each offset is the f64
// difference rounded once to f32 — the same expression, hence the same bits, as the CPU's
// `(x − cx·Δ) as f32` — so the error is at most half an f32 ulp of a number below 2.5·Δ,
// whatever the window's offset: a window at (10⁷, 10⁷) is exactly as precise as one at 0.
// Tiles carry the values of their own pixels only, so any tiling gives the same bits.
//
// Draws made once per lattice point (the compute path). Every pixel within 1.5·Δ of a lattice
// point repeats that point's J index and phase draws, `% len` and table read: per cosine two
// hashes, an integer remainder by a runtime length and a gather, several times a cosine's own
// arithmetic. (The paper draws on the fly per evaluation, §4 "Sampling"; its timed implementation
// kept "amplitudes, frequencies and phases" in GPU storage buffers, §6. The values are the
// contract's either way: this only changes where they are drawn.)
// So `lrp_draw` first draws every lattice point of the tile's box once, stratum by stratum, into
// `draws` as (f_x, f_y, φ, gain) — the same f32 values the pixel would draw — and `lrp_main`
// reads them there, in the same order and with the same arithmetic: the same bits. The host
// sizes each stratum's box (`boxes`, from its columns' and rows' cells) and leaves a stratum
// whose box does not fit the tile's budget, and any displaced tile (whose cells move), to the
// per-pixel draws of `lrp_stratum`, which the exported module uses too.

/// Per-dispatch values.
struct LrpParams {
    /// Tile width and height in pixels (the output is row-major, `width` values per row).
    width: u32,
    height: u32,
    /// Number of strata.
    strata: u32,
    /// Seed of the randomness contract.
    seed: u32,
    /// Constant added to the noise.
    mean: f32,
    /// 1: a minified render, each cosine multiplied by its entry's gain in `gains`.
    filtered: u32,
    /// `lrp_draw`: the lattice points of every box (invocations beyond it return).
    draw_points: u32,
    /// `lrp_draw`: invocations per row of its dispatch grid (a 2D grid of workgroups).
    draw_stride: u32,
}

/// One stratum, packed by the host.
struct LrpStratum {
    /// 1 / Δ², rounded to f32 from f64 (as the CPU's inv_delta2).
    inv_delta2: f32,
    /// A_s.
    amplitude: f32,
    /// Index in `tables` of the table of cosine 0; cosine j uses tables[table_first + j].
    table_first: u32,
    /// J_s, the cosines per lattice point.
    cosines: u32,
    /// Δ_s, the lattice period in pixels (f32 of the model's value), for warping; along x
    /// when the lattice is fitted to a period (spectex_model::Period::fit_lattice).
    delta: f32,
    /// The lattice period along y: `delta` unless fitted to a period of another height.
    delta_y: f32,
    /// (Δ_x/Δ_y)², scaling dy² so that r² = (dx² + dy²·aspect2)/Δ_x² (1 for a square lattice).
    aspect2: f32,
    /// Lattice points per period along x and y of a periodic model (0: not periodic): point
    /// (cx, cy) draws the randomness of (cx mod n_x, cy mod n_y), via wrap_cell.
    cells_x: i32,
    cells_y: i32,
}

/// Stratum s's box of lattice points drawn once for the tile (`lrp_draw`): columns x0 … x0 +
/// width − 1, rows y0 … y0 + height − 1; the draws of point (x0 + i, y0 + k) start at record
/// `first_record + (k·width + i)·J_s` of `draws`, its index among every box's points is
/// `first_point + k·width + i`. width = 0: the stratum's pixels draw for themselves.
struct LrpBox {
    x0: i32,
    y0: i32,
    width: u32,
    height: u32,
    first_record: u32,
    first_point: u32,
}

/// One column (or row) of the tile for one stratum: its lattice cell and the offsets to the
/// lattice points cell − 1 … cell + 2, in pixels.
struct LatticeAxis {
    cell: i32,
    offset: array<f32, 4>,
}

@group(0) @binding(0) var<uniform> params: LrpParams;
@group(0) @binding(1) var<storage, read> strata: array<LrpStratum>;
/// Every frequency table, concatenated: (f_x, f_y) in cycles per pixel.
@group(0) @binding(2) var<storage, read> frequencies: array<vec2<f32>>;
/// (start in `frequencies`, length) of each sub-stratum's table.
@group(0) @binding(3) var<storage, read> tables: array<vec2<u32>>;
/// strata × width entries: index s·width + i.
@group(0) @binding(4) var<storage, read> columns: array<LatticeAxis>;
/// strata × height entries: index s·height + j.
@group(0) @binding(5) var<storage, read> rows: array<LatticeAxis>;
/// Per entry of `frequencies`: its gain in a minified render (LRP §6 frequency clamping; the
/// host computes it in f64 with spectex_model::filter::lrp_gains, as the CPU does). Read only
/// when params.filtered == 1.
@group(0) @binding(6) var<storage, read> gains: array<f32>;
/// One box per stratum (per tile).
@group(0) @binding(7) var<storage, read> boxes: array<LrpBox>;
/// The drawn lattice points' cosines, (f_x, f_y, φ, gain): written by `lrp_draw` (into the
/// buffer it binds as `output`) before `lrp_main` reads them here.
@group(0) @binding(8) var<storage, read> draws: array<vec4<f32>>;
@group(0) @binding(9) var<storage, read_write> output: array<f32>;

/// An axis entry moved by `d` pixels (domain warping, common.wgsl): offset k = 1 is the pixel's
/// offset in its lattice cell, so it moves to u = offset + d, the cell by ⌊u/Δ⌋, and the four
/// offsets are rebuilt from the remainder r = u − ⌊u/Δ⌋·Δ as r − (k − 1)·Δ. r lies in [0, Δ) up
/// to roundings, and the cells c − 1 … c + 2 cover every lattice point within 1.5·Δ of any r in
/// (−½Δ, 1.5Δ), so the support is always complete.
fn lrp_displaced(axis: LatticeAxis, d: f32, delta: f32) -> LatticeAxis {
    let u = axis.offset[1] + d;
    let shift = floor(u / delta);
    let r = u - shift * delta;
    var moved: LatticeAxis;
    moved.cell = bitcast<i32>(bitcast<u32>(axis.cell) + bitcast<u32>(i32(shift)));
    moved.offset = array<f32, 4>(r + delta, r, r - delta, r - 2.0f * delta);
    return moved;
}

/// Lattice index `cell + k − 1` with the CPU's wrapping i64 → i32 arithmetic.
fn lattice_index(cell: i32, k: u32) -> i32 {
    return bitcast<i32>(bitcast<u32>(cell) + k - 1u);
}

/// Stratum `s`'s term `A_s · Σ w(r²) · Σ_j cos(…)` at the pixel whose column and row axes (for
/// this stratum) are given: the per-pixel evaluation, shared by `lrp_main` and the exported
/// module (the export glue at the end of this file, which builds the axes from a position
/// itself).
fn lrp_stratum(s: u32, column: LatticeAxis, row: LatticeAxis) -> f32 {
    let stratum = strata[s];
    let key = layer_key(s, params.seed);
    var stratum_sum = 0.0f;
    for (var ky = 0u; ky < 4u; ky++) {
        let dy = row.offset[ky];
        let dy2 = dy * dy * stratum.aspect2;
        // A whole lattice row beyond the support contributes exactly 0: skip it.
        if (dy2 * stratum.inv_delta2 >= KB_SUPPORT2) {
            continue;
        }
        let rkey = row_key(wrap_cell(lattice_index(row.cell, ky), stratum.cells_y), key);
        for (var kx = 0u; kx < 4u; kx++) {
            let dx = column.offset[kx];
            let r2 = (dx * dx + dy2) * stratum.inv_delta2;
            if (r2 >= KB_SUPPORT2) {
                continue;
            }
            let w = kaiser_bessel_r2(r2);
            let cx = wrap_cell(lattice_index(column.cell, kx), stratum.cells_x);
            var prng = Prng(cell_hash_in_row(cx, rkey));
            var cosines = 0.0f;
            // The filtered test outside the cosine loop (see `lrp_main`).
            if (params.filtered == 1u) {
                for (var j = 0u; j < stratum.cosines; j++) {
                    let table = tables[stratum.table_first + j];
                    let index = table.x + prng_next_u32(&prng) % table.y;
                    let f = frequencies[index];
                    let phase = prng_next_f32(&prng);
                    let c = f.y * dy + phase;
                    cosines += gains[index] * cos_turns(f.x * dx + c);
                }
            } else {
                for (var j = 0u; j < stratum.cosines; j++) {
                    let table = tables[stratum.table_first + j];
                    let index = table.x + prng_next_u32(&prng) % table.y;
                    let f = frequencies[index];
                    let phase = prng_next_f32(&prng);
                    let c = f.y * dy + phase;
                    cosines += cos_turns(f.x * dx + c);
                }
            }
            stratum_sum += w * cosines;
        }
    }
    return stratum.amplitude * stratum_sum;
}

/// Draws the lattice points of the tile's boxes, one invocation per point: its J cosines'
/// (f_x, f_y, φ, gain) in `lrp_stratum`'s order, into `output` (the buffer `lrp_main` then
/// binds as `draws`).
@compute @workgroup_size(64, 1, 1)
fn lrp_draw(@builtin(global_invocation_id) gid: vec3<u32>) {
    let point = gid.y * params.draw_stride + gid.x;
    if (point >= params.draw_points) {
        return;
    }
    var s = 0u;
    while (s + 1u < params.strata && point >= boxes[s + 1u].first_point) {
        s++;
    }
    let b = boxes[s];
    let stratum = strata[s];
    let local = point - b.first_point;
    let cy = bitcast<i32>(bitcast<u32>(b.y0) + local / b.width);
    let cx = bitcast<i32>(bitcast<u32>(b.x0) + local % b.width);
    let rkey = row_key(wrap_cell(cy, stratum.cells_y), layer_key(s, params.seed));
    var prng = Prng(cell_hash_in_row(wrap_cell(cx, stratum.cells_x), rkey));
    let first = b.first_record + local * stratum.cosines;
    for (var j = 0u; j < stratum.cosines; j++) {
        let table = tables[stratum.table_first + j];
        let index = table.x + prng_next_u32(&prng) % table.y;
        let f = frequencies[index];
        let phase = prng_next_f32(&prng);
        var gain = 1.0f;
        if (params.filtered == 1u) {
            gain = gains[index];
        }
        let at = 4u * (first + j);
        output[at] = f.x;
        output[at + 1u] = f.y;
        output[at + 2u] = phase;
        output[at + 3u] = gain;
    }
}

@compute @workgroup_size(8, 8, 1)
fn lrp_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    var total = 0.0f;
    for (var s = 0u; s < params.strata; s++) {
        var column = columns[s * params.width + gid.x];
        var row = rows[s * params.height + gid.y];
        let b = boxes[s];
        if (warp_params.enabled == 1u) {
            let d = warp_displacement[gid.y * params.width + gid.x];
            column = lrp_displaced(column, d.x, strata[s].delta);
            row = lrp_displaced(row, d.y, strata[s].delta_y);
        } else if (b.width != 0u) {
            // `lrp_stratum` with the point's draws read from `draws` (see the header). Its own
            // copy of the window loop: one function taking both ways, the way chosen per
            // lattice point, ran the J = 50 bench model at 0.32–0.35 Mpix/s on lavapipe where
            // this runs at 0.38–0.58 (models bench, 256², alternating).
            let stratum = strata[s];
            var stratum_sum = 0.0f;
            for (var ky = 0u; ky < 4u; ky++) {
                let dy = row.offset[ky];
                let dy2 = dy * dy * stratum.aspect2;
                if (dy2 * stratum.inv_delta2 >= KB_SUPPORT2) {
                    continue;
                }
                let k = bitcast<u32>(lattice_index(row.cell, ky)) - bitcast<u32>(b.y0);
                for (var kx = 0u; kx < 4u; kx++) {
                    let dx = column.offset[kx];
                    let r2 = (dx * dx + dy2) * stratum.inv_delta2;
                    if (r2 >= KB_SUPPORT2) {
                        continue;
                    }
                    let w = kaiser_bessel_r2(r2);
                    let i = bitcast<u32>(lattice_index(column.cell, kx)) - bitcast<u32>(b.x0);
                    let first = b.first_record + (k * b.width + i) * stratum.cosines;
                    var cosines = 0.0f;
                    // The filtered test outside the cosine loop: inside it, the J = 50 bench
                    // model ran at 0.54–0.59 Mpix/s on lavapipe, outside at 1.00–1.02.
                    if (params.filtered == 1u) {
                        for (var j = 0u; j < stratum.cosines; j++) {
                            let draw = draws[first + j];
                            let c = draw.y * dy + draw.z;
                            cosines += draw.w * cos_turns(draw.x * dx + c);
                        }
                    } else {
                        for (var j = 0u; j < stratum.cosines; j++) {
                            let draw = draws[first + j];
                            let c = draw.y * dy + draw.z;
                            cosines += cos_turns(draw.x * dx + c);
                        }
                    }
                    stratum_sum += w * cosines;
                }
            }
            total += stratum.amplitude * stratum_sum;
            continue;
        }
        total += lrp_stratum(s, column, row);
    }
    output[gid.y * params.width + gid.x] = total + params.mean;
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of an LRP model (after the kernel above and export/split.wgsl):
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

/// Stratum `s`'s term at the position `n + u` (`lrp_stratum` on the axes located there).
fn lrp_export_stratum(n: vec2<i32>, u: vec2<f32>, s: u32) -> f32 {
    return lrp_stratum(s, lrp_export_axis(n.x, u.x, s), lrp_export_axis(n.y, u.y, s));
}

/// The noise at the position `cell + offset` (pixels), the strata summed in the CPU's order.
/// The exporter writes the strata out, `LRP_EXPORT_STRATA` = one `lrp_export_stratum` call
/// per stratum with its index as a literal (as classic.wgsl's octaves): a stratum's record
/// and its sub-strata's table bounds are then constants, which a driver folds into the
/// cosine loop (its trip count and each `% len` a constant), where a strata loop's counter
/// would read them from per-invocation memory at every cosine.
fn lrp_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    var total = 0.0f;
    LRP_EXPORT_STRATA
    return total + params.mean;
}
