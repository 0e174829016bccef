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
    _pad1: u32,
    _pad2: u32,
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
@group(0) @binding(7) var<storage, read_write> output: array<f32>;

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
            for (var j = 0u; j < stratum.cosines; j++) {
                let table = tables[stratum.table_first + j];
                let index = table.x + prng_next_u32(&prng) % table.y;
                let f = frequencies[index];
                let phase = prng_next_f32(&prng);
                let c = f.y * dy + phase;
                if (params.filtered == 1u) {
                    cosines += gains[index] * cos_turns(f.x * dx + c);
                } else {
                    cosines += cos_turns(f.x * dx + c);
                }
            }
            stratum_sum += w * cosines;
        }
    }
    return stratum.amplitude * stratum_sum;
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
        if (warp_params.enabled == 1u) {
            let d = warp_displacement[gid.y * params.width + gid.x];
            column = lrp_displaced(column, d.x, strata[s].delta);
            row = lrp_displaced(row, d.y, strata[s].delta_y);
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
