// voronoi.wgsl — Voronoi diagrams (survey §2.6), the GPU twin of
// crates/spectex-cpu/src/voronoi.rs; the definition is the module doc of
// crates/spectex-model/src/voronoi.rs. Composed after common.wgsl.
//
// The host computes, per tile, the sites of a box of lattice cells covering every pixel's
// search (jittered by the randomness contract and Lloyd-relaxed on the host, so the device
// reads the CPU's f32 offsets, IDs and colours), and each column's and row's cell and f32
// offset (spectex_model::grid::locate_cell). The search visits the cells within `reach`, rows
// outer and columns inner, with the CPU's expressions in the CPU's order (spectex_model::
// voronoi::search), so on an adapter that rounds `/` and `sqrt` correctly and does not
// contract `a * b + c` the values are the CPU's bit for bit. A 3D diagram (box_depth > 0) reads
// a box of planes around the plane z and runs spectex_model::voronoi::search3 (voronoi_main3).

/// Per-dispatch values.
struct VoronoiParams {
    width: u32,
    height: u32,
    /// Cells searched beyond the pixel's own.
    reach: i32,
    /// 0: cell ID, 1: F1, 2: border, 3: F2 − F1, 4: colour (3 values per pixel).
    output: u32,
    /// The site table's first cell and its extent.
    box_i0: i32,
    box_j0: i32,
    box_cols: u32,
    box_rows: u32,
    /// 1 / C (f32 of the f64 value), for warping.
    inv_cell: f32,
    /// 0 in 2D; in 3D the box's planes, 2·reach + 1 from z_cell − reach.
    box_depth: u32,
    /// A 3D model's plane z: its cell and offset (0 in 2D).
    z_cell: i32,
    z_offset: f32,
}

@group(0) @binding(0) var<uniform> params: VoronoiParams;
/// Six floats per site, row-major over the box: offset x, y, ID, colour r, g, b (3D: seven,
/// offset z last, plane by plane).
@group(0) @binding(1) var<storage, read> sites: array<f32>;
@group(0) @binding(2) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(3) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(4) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes").
override VORONOI_OUTPUT: u32 = 0xffffffffu;

fn voronoi_output() -> u32 {
    return shape_or(VORONOI_OUTPUT, params.output);
}

/// The search's reach and the dimension (1 for 3D) fold too: as uniforms, the search's loop
/// bounds and the 3D branch were data (cell ID ran at half this speed on lavapipe).
override VORONOI_REACH: u32 = 0xffffffffu;
override VORONOI_THREE_D: u32 = 0xffffffffu;

/// Cells searched beyond the pixel's own.
fn voronoi_reach() -> i32 {
    return i32(shape_or(VORONOI_REACH, u32(params.reach)));
}

/// A 3D diagram (its box has planes).
fn voronoi_three_d() -> bool {
    return shape_or(VORONOI_THREE_D, u32(params.box_depth > 0u)) == 1u;
}

const SITE_FLOATS: u32 = 6u;

/// Where the site of cell (cx, cy) starts in `sites`; the box covers every search.
fn site_base(cx: i32, cy: i32) -> u32 {
    let i = min(u32(cx - params.box_i0), params.box_cols - 1u);
    let j = min(u32(cy - params.box_j0), params.box_rows - 1u);
    return (j * params.box_cols + i) * SITE_FLOATS;
}

fn write_value(index: u32, base: u32, f1: f32, f2: f32, border: f32) {
    let channels = select(1u, 3u, voronoi_output() == 4u);
    let at = index * channels;
    switch voronoi_output() {
        case 0u: {
            output[at] = sites[base + 2u];
        }
        case 1u: {
            output[at] = f1;
        }
        case 2u: {
            output[at] = border;
        }
        case 3u: {
            output[at] = f2 - f1;
        }
        default: {
            output[at] = sites[base + 3u];
            output[at + 1u] = sites[base + 4u];
            output[at + 2u] = sites[base + 5u];
        }
    }
}

@compute @workgroup_size(8, 8, 1)
fn voronoi_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let at = grid_point(columns[gid.x], rows[gid.y], index, params.inv_cell);
    let column = at.column;
    let row = at.row;
    if (column.valid == 0u || row.valid == 0u || params.box_cols == 0u) {
        let channels = select(1u, 3u, voronoi_output() == 4u);
        for (var c = 0u; c < channels; c++) {
            output[index * channels + c] = 0.0f;
        }
        return;
    }
    if (voronoi_three_d()) {
        voronoi_main3(index, vec3<i32>(column.cell, row.cell, params.z_cell),
            vec3<f32>(column.offset, row.offset, params.z_offset));
        return;
    }
    let reach = voronoi_reach();
    let f = vec2<f32>(column.offset, row.offset);
    var best = 3.4028235e38f;
    var second = 3.4028235e38f;
    var nearest = 0u;
    var dn = vec2<f32>(0.0f, 0.0f);
    for (var dj = -reach; dj <= reach; dj++) {
        for (var di = -reach; di <= reach; di++) {
            let base = site_base(column.cell + di, row.cell + dj);
            let dx = (f32(di) + sites[base]) - f.x;
            let dy = (f32(dj) + sites[base + 1u]) - f.y;
            let d2 = dx * dx + dy * dy;
            if (d2 < best) {
                second = best;
                best = d2;
                nearest = base;
                dn = vec2<f32>(dx, dy);
            } else if (d2 < second) {
                second = d2;
            }
        }
    }
    let f1 = sqrt(best);
    // The border's search, pruned as voronoi_main3 prunes the 3D one: the 3 × 3 cells first,
    // then the others whose bound can beat the border found (search3's limit and margin).
    // Every seed lies in its own cell, relaxed or not, so the skipped ones lie beyond the
    // minimum: the full search's value bit for bit (lavapipe: voronoi-border-lloyd 1.25×).
    // The nearest seed's search above stays whole, unrolled at its constant bounds: pruned
    // the same way (ties then kept by a key, as in 3D) F1 and cell ID ran 20% slower.
    var border = 3.4028235e38f;
    if (voronoi_output() == 2u) {
        var limit = 3.4028235e38f;
        for (var sweep = 0; sweep < 2; sweep++) {
            let r = select(reach, 1, sweep == 0);
            let span_j = voronoi_span(f.y, limit, r);
            for (var dj = span_j.x; dj <= span_j.y; dj++) {
                let gj = cell_gap2(f.y, dj);
                if (gj > limit) {
                    continue;
                }
                let span_i = voronoi_span(f.x, limit - gj, r);
                for (var di = span_i.x; di <= span_i.y; di++) {
                    if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1) {
                        continue;
                    }
                    if (cell_gap2(f.x, di) + gj > limit) {
                        continue;
                    }
                    let base = site_base(column.cell + di, row.cell + dj);
                    let dx = (f32(di) + sites[base]) - f.x;
                    let dy = (f32(dj) + sites[base + 1u]) - f.y;
                    let q = voronoi_bisector2(vec2<f32>(dx, dy), dn);
                    voronoi_border_update(q, f1, &border, &limit);
                }
            }
        }
    }
    write_value(index, nearest, f1, sqrt(second), border);
}

const VORONOI_SITE3_FLOATS: u32 = 7u;
/// spectex_model::voronoi::BORDER_PRUNE_MARGIN.
const VORONOI_BORDER_PRUNE_MARGIN: f32 = 1e-3f;

/// The distance from the pixel to the bisector of the seeds at `d` and `dn` (the nearest),
/// `((d + dn)·(d − dn))·½ / |d − dn|` in the CPU's order; the largest f32 where the seeds
/// coincide (the nearest itself), which no border takes.
fn voronoi_bisector2(d: vec2<f32>, dn: vec2<f32>) -> f32 {
    let ex = d.x - dn.x;
    let ey = d.y - dn.y;
    let e2 = ex * ex + ey * ey;
    if (e2 == 0.0f) {
        return 3.4028235e38f;
    }
    let num = (d.x + dn.x) * ex + (d.y + dn.y) * ey;
    return num * 0.5f / sqrt(e2);
}

/// `voronoi_bisector2` in 3D.
fn voronoi_bisector3(d: vec3<f32>, dn: vec3<f32>) -> f32 {
    let e = d - dn;
    let e2 = e.x * e.x + e.y * e.y + e.z * e.z;
    if (e2 == 0.0f) {
        return 3.4028235e38f;
    }
    let s = d + dn;
    let num = s.x * e.x + s.y * e.y + s.z * e.z;
    return num * 0.5f / sqrt(e2);
}

/// Takes the bisector distance `q` into the border found so far and, where it is the new
/// minimum, narrows the search's limit on d² to (2(q + margin) + F1)²: a seed farther than
/// 2q + F1 has its bisector farther than q (spectex_model::voronoi's `bisector`).
fn voronoi_border_update(q: f32, f1: f32, border: ptr<function, f32>, limit: ptr<function, f32>) {
    if (q < *border) {
        *border = q;
        let far = 2.0f * (q + VORONOI_BORDER_PRUNE_MARGIN) + f1;
        *limit = far * far;
    }
}

/// Where the site of 3D cell c starts in `sites`; the box covers every search.
fn site_base3(c: vec3<i32>) -> u32 {
    let i = min(u32(c.x - params.box_i0), params.box_cols - 1u);
    let j = min(u32(c.y - params.box_j0), params.box_rows - 1u);
    let k = min(u32(c.z - (params.z_cell - voronoi_reach())), params.box_depth - 1u);
    return ((k * params.box_rows + j) * params.box_cols + i) * VORONOI_SITE3_FLOATS;
}

/// Slack (squared cell units) of `voronoi_span`: far above the roundings of the sums the
/// per-cell tests compare (three squares below 16 each: under 10⁻⁵), so a span never drops a
/// cell those tests keep.
const VORONOI_SPAN_SLACK: f32 = 0.015625f;

/// The offsets `[lo, hi]` ⊆ `[−r, r]` along an axis that can pass a test `cell_gap2(f, d) +
/// rest ≤ bound` with `budget = bound − rest`: every `d` with `gap² ≤ budget + slack` (for
/// `d > 0` the gap is `d − f`, for `d < 0` it is `f + |d| − 1`, both growing with `|d|`).
/// Looping over the span and keeping the per-cell test visits exactly the cells a loop over
/// `−r..r` visits, in the same order, since the bound only falls while the loop runs; the
/// offsets left out were tested one by one and skipped (lavapipe: voronoi-3d-border's export
/// 1.7× faster, most of its 9 × 9 × 9 box being rows and cells far beyond the bound).
fn voronoi_span(f: f32, budget: f32, r: i32) -> vec2<i32> {
    let s = sqrt(max(budget, 0.0f) + VORONOI_SPAN_SLACK);
    let rf = f32(r);
    return vec2<i32>(-i32(min(floor((1.0f - f) + s), rf)), i32(min(floor(f + s), rf)));
}

/// The vector d from the pixel at offset f to the seed of the cell `o` away from cell c.
fn voronoi_delta3(c: vec3<i32>, o: vec3<i32>, f: vec3<f32>) -> vec3<f32> {
    let base = site_base3(c + o);
    return vec3<f32>(
        (f32(o.x) + sites[base]) - f.x,
        (f32(o.y) + sites[base + 1u]) - f.y,
        (f32(o.z) + sites[base + 6u]) - f.z,
    );
}

/// The 3D search of spectex_model::voronoi::search3: the 3 × 3 × 3 cells around the pixel's,
/// then the others within the reach whose bound can beat what was found, each in (dk, dj, di)
/// order; the nearest is the smallest d², ties to the first cell in that order.
fn voronoi_main3(index: u32, c: vec3<i32>, f: vec3<f32>) {
    let reach = voronoi_reach();
    let want_second = voronoi_output() == 3u;
    var best = 3.4028235e38f;
    var second = 3.4028235e38f;
    var key = 2147483647;
    var nearest = 0u;
    var dn = vec3<f32>(0.0f);
    for (var sweep = 0; sweep < 2; sweep++) {
        let r = select(reach, 1, sweep == 0);
        let span_k = voronoi_span(f.z, select(best, second, want_second), r);
        for (var dk = span_k.x; dk <= span_k.y; dk++) {
            // A plane (row) whose own gap exceeds the bound holds no cell under it: every
            // cell's bound, `(gap_i + gap_j) + gap_k` in f32, is at least `gap_k`
            // (`gap_j + gap_k`), rounding being monotonic, and the bound only falls. Skipping
            // it whole visits exactly the cells the per-cell test visits, in the same order
            // (the CPU's `walk3`). Without it, the border's reach of 4 tested 702 cells a
            // pixel one by one (lavapipe: voronoi-3d-border 7× slower).
            let gk = cell_gap2(f.z, dk);
            if (gk > select(best, second, want_second)) {
                continue;
            }
            let span_j = voronoi_span(f.y, select(best, second, want_second) - gk, r);
            for (var dj = span_j.x; dj <= span_j.y; dj++) {
                let gj = cell_gap2(f.y, dj);
                if (gj + gk > select(best, second, want_second)) {
                    continue;
                }
                let span_i = voronoi_span(f.x, select(best, second, want_second) - (gj + gk), r);
                for (var di = span_i.x; di <= span_i.y; di++) {
                    if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1 && abs(dk) <= 1) {
                        continue;
                    }
                    let bound = cell_gap2(f.x, di) + gj + gk;
                    if (bound > select(best, second, want_second)) {
                        continue;
                    }
                    let o = vec3<i32>(di, dj, dk);
                    let d = voronoi_delta3(c, o, f);
                    let d2 = d.x * d.x + d.y * d.y + d.z * d.z;
                    let k = ((dk + 4) * 9 + (dj + 4)) * 9 + (di + 4);
                    if (d2 < best || (d2 == best && k < key)) {
                        second = best;
                        best = d2;
                        key = k;
                        nearest = site_base3(c + o);
                        dn = d;
                    } else if (d2 < second) {
                        second = d2;
                    }
                }
            }
        }
    }
    let f1 = sqrt(best);
    var border = 3.4028235e38f;
    var limit = 3.4028235e38f;
    if (voronoi_output() == 2u) {
        for (var sweep = 0; sweep < 2; sweep++) {
            let r = select(reach, 1, sweep == 0);
            let span_k = voronoi_span(f.z, limit, r);
            for (var dk = span_k.x; dk <= span_k.y; dk++) {
                // Whole planes and rows over the limit skipped, as in the first search.
                let gk = cell_gap2(f.z, dk);
                if (gk > limit) {
                    continue;
                }
                let span_j = voronoi_span(f.y, limit - gk, r);
                for (var dj = span_j.x; dj <= span_j.y; dj++) {
                    let gj = cell_gap2(f.y, dj);
                    if (gj + gk > limit) {
                        continue;
                    }
                    let span_i = voronoi_span(f.x, limit - (gj + gk), r);
                    for (var di = span_i.x; di <= span_i.y; di++) {
                        if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1 && abs(dk) <= 1) {
                            continue;
                        }
                        let bound = cell_gap2(f.x, di) + gj + gk;
                        if (bound > limit) {
                            continue;
                        }
                        let d = voronoi_delta3(c, vec3<i32>(di, dj, dk), f);
                        let q = voronoi_bisector3(d, dn);
                        voronoi_border_update(q, f1, &border, &limit);
                    }
                }
            }
        }
    }
    write_value(index, nearest, f1, sqrt(second), border);
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a Voronoi diagram (after the kernel above and
// export/split.wgsl): lattice 0 of the export tables is the seed lattice (cell side C, an
// f32, so the split is exact). The compute path's host draws the sites of a box of cells per
// tile (spectex_model::voronoi::VoronoiNoise::sites); here each searched cell's site is drawn
// in the shader with the randomness contract's WGSL twin, as `VoronoiNoise::jittered` draws
// it: o = ½ + jitter·(u − ½) per axis, then the ID. (Lloyd-relaxed seeds are refused by the
// exporter.) The search is `voronoi_main`'s (spectex_model::voronoi::search): cells within
// the reach, rows outer and columns inner, the CPU's expressions in the CPU's order. The
// exporter declares `voronoi_export_seed`, `voronoi_export_jitter`, the palette
// (`voronoi_export_palette`, `voronoi_export_colours`; one unused black entry for the grey
// outputs) and replaces VORONOI_VALUE and VORONOI_RESULT with the return type and value.
// A 3D diagram (params.box_depth > 0) is evaluated on the exported plane z (params.z_cell,
// params.z_offset): its sites are drawn as `VoronoiNoise::jittered3` draws them and searched as
// voronoi_main3 searches them (voronoi_export_value3).

/// The randomness-contract layer of Voronoi seeds ("VORO", spectex_model::voronoi).
const VORONOI_EXPORT_LAYER: u32 = 0x564F524Fu;

/// The site of cell `(cx, cy)`: offset x, y (cell units) and the ID.
fn voronoi_export_site(cx: i32, cy: i32) -> vec3<f32> {
    var prng = Prng(cell_hash(cx, cy, VORONOI_EXPORT_LAYER, voronoi_export_seed));
    let ox = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let oy = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let id = prng_next_f32(&prng);
    return vec3<f32>(ox, oy, id);
}

/// `a + b` with i32 wrapping, as the CPU's i64 cells cast to i32 for the hash.
fn voronoi_export_add(a: i32, b: i32) -> i32 {
    return bitcast<i32>(bitcast<u32>(a) + bitcast<u32>(b));
}

/// The diagram at the position `cell + offset` (pixels): the output's value(s) in x (y, z).
fn voronoi_export_value(cell: vec2<i32>, offset: vec2<f32>) -> vec3<f32> {
    let at = export_normalise(cell, offset);
    let cx = export_locate(at.n.x, at.u.x, 0u);
    let cy = export_locate(at.n.y, at.u.y, 0u);
    // The CPU's offsets in cell units, `x/C − ⌊x/C⌋` rounded once from f64.
    let fx = (cx.rem + at.u.x) * export_inv_sides[0];
    let fy = (cy.rem + at.u.y) * export_inv_sides[0];
    if (voronoi_three_d()) {
        return voronoi_export_value3(vec3<i32>(cx.cell, cy.cell, params.z_cell), vec3<f32>(fx, fy, params.z_offset));
    }
    let reach = voronoi_reach();
    var best = 3.4028235e38f;
    var second = 3.4028235e38f;
    var nearest = vec3<f32>(0.0f);
    var dn = vec2<f32>(0.0f, 0.0f);
    for (var dj = -reach; dj <= reach; dj++) {
        for (var di = -reach; di <= reach; di++) {
            let site = voronoi_export_site(voronoi_export_add(cx.cell, di), voronoi_export_add(cy.cell, dj));
            let dx = (f32(di) + site.x) - fx;
            let dy = (f32(dj) + site.y) - fy;
            let d2 = dx * dx + dy * dy;
            if (d2 < best) {
                second = best;
                best = d2;
                nearest = site;
                dn = vec2<f32>(dx, dy);
            } else if (d2 < second) {
                second = d2;
            }
        }
    }
    switch voronoi_output() {
        case 0u: {
            return vec3<f32>(nearest.z, 0.0f, 0.0f);
        }
        case 1u: {
            return vec3<f32>(sqrt(best), 0.0f, 0.0f);
        }
        case 2u: {
            var border = 3.4028235e38f;
            for (var dj = -reach; dj <= reach; dj++) {
                for (var di = -reach; di <= reach; di++) {
                    let site = voronoi_export_site(voronoi_export_add(cx.cell, di), voronoi_export_add(cy.cell, dj));
                    let dx = (f32(di) + site.x) - fx;
                    let dy = (f32(dj) + site.y) - fy;
                    let q = voronoi_bisector2(vec2<f32>(dx, dy), dn);
                    if (q < border) {
                        border = q;
                    }
                }
            }
            return vec3<f32>(border, 0.0f, 0.0f);
        }
        case 3u: {
            return vec3<f32>(sqrt(second) - sqrt(best), 0.0f, 0.0f);
        }
        default: {
            // The palette entry ⌊id·N⌋ (VoronoiNoise's colour).
            let k = min(u32(nearest.z * f32(voronoi_export_colours)), voronoi_export_colours - 1u);
            return voronoi_export_palette[k];
        }
    }
}

/// The plane key of the 3D cells `(·, ·, z)`: `cell_hash(x, y, VORO, plane)` is
/// `cell_hash_in_row(x, row_key(y, key))` with the plane's hash `plane = cell_hash(z, 0, VORO,
/// seed)` (`VoronoiNoise::jittered3`), so the key is taken once per plane searched and the row
/// key once per row (four hashes a row before: voronoi-3d-border's export 4% slower).
fn voronoi_export_plane3(z: i32) -> u32 {
    let plane = cell_hash(z, 0, VORONOI_EXPORT_LAYER, voronoi_export_seed);
    return layer_key(VORONOI_EXPORT_LAYER, plane);
}

/// The site of the 3D cell `(x, y, z)` whose row key (`row_key(y, voronoi_export_plane3(z))`)
/// is `row`:
/// offset x, y, z (cell units) and the ID (`VoronoiNoise::jittered3`).
fn voronoi_export_site3(x: i32, row: u32) -> vec4<f32> {
    var prng = Prng(cell_hash_in_row(x, row));
    let ox = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let oy = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let oz = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let id = prng_next_f32(&prng);
    return vec4<f32>(ox, oy, oz, id);
}

/// The 3D diagram at offset `f` in cell `c` (voronoi_main3's search).
fn voronoi_export_value3(c: vec3<i32>, f: vec3<f32>) -> vec3<f32> {
    let reach = voronoi_reach();
    let want_second = voronoi_output() == 3u;
    var best = 3.4028235e38f;
    var second = 3.4028235e38f;
    var key = 2147483647;
    var nearest = vec4<f32>(0.0f);
    var dn = vec3<f32>(0.0f);
    for (var sweep = 0; sweep < 2; sweep++) {
        let r = select(reach, 1, sweep == 0);
        let span_k = voronoi_span(f.z, select(best, second, want_second), r);
        for (var dk = span_k.x; dk <= span_k.y; dk++) {
            // Whole planes and rows over the bound skipped, as `voronoi_main3` skips them.
            let gk = cell_gap2(f.z, dk);
            if (gk > select(best, second, want_second)) {
                continue;
            }
            let plane = voronoi_export_plane3(voronoi_export_add(c.z, dk));
            let span_j = voronoi_span(f.y, select(best, second, want_second) - gk, r);
            for (var dj = span_j.x; dj <= span_j.y; dj++) {
                let gj = cell_gap2(f.y, dj);
                if (gj + gk > select(best, second, want_second)) {
                    continue;
                }
                let row = row_key(voronoi_export_add(c.y, dj), plane);
                let span_i = voronoi_span(f.x, select(best, second, want_second) - (gj + gk), r);
                for (var di = span_i.x; di <= span_i.y; di++) {
                    if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1 && abs(dk) <= 1) {
                        continue;
                    }
                    let bound = cell_gap2(f.x, di) + gj + gk;
                    if (bound > select(best, second, want_second)) {
                        continue;
                    }
                    let site = voronoi_export_site3(voronoi_export_add(c.x, di), row);
                    let d = vec3<f32>((f32(di) + site.x) - f.x, (f32(dj) + site.y) - f.y, (f32(dk) + site.z) - f.z);
                    let d2 = d.x * d.x + d.y * d.y + d.z * d.z;
                    let k = ((dk + 4) * 9 + (dj + 4)) * 9 + (di + 4);
                    if (d2 < best || (d2 == best && k < key)) {
                        second = best;
                        best = d2;
                        key = k;
                        nearest = site;
                        dn = d;
                    } else if (d2 < second) {
                        second = d2;
                    }
                }
            }
        }
    }
    let f1 = sqrt(best);
    switch voronoi_output() {
        case 0u: {
            return vec3<f32>(nearest.w, 0.0f, 0.0f);
        }
        case 1u: {
            return vec3<f32>(f1, 0.0f, 0.0f);
        }
        case 2u: {
            var border = 3.4028235e38f;
            var limit = 3.4028235e38f;
            for (var sweep = 0; sweep < 2; sweep++) {
                let r = select(reach, 1, sweep == 0);
                let span_k = voronoi_span(f.z, limit, r);
                for (var dk = span_k.x; dk <= span_k.y; dk++) {
                    // Whole planes and rows over the limit skipped, as in the first search.
                    let gk = cell_gap2(f.z, dk);
                    if (gk > limit) {
                        continue;
                    }
                    let plane = voronoi_export_plane3(voronoi_export_add(c.z, dk));
                    let span_j = voronoi_span(f.y, limit - gk, r);
                    for (var dj = span_j.x; dj <= span_j.y; dj++) {
                        let gj = cell_gap2(f.y, dj);
                        if (gj + gk > limit) {
                            continue;
                        }
                        let row = row_key(voronoi_export_add(c.y, dj), plane);
                        let span_i = voronoi_span(f.x, limit - (gj + gk), r);
                        for (var di = span_i.x; di <= span_i.y; di++) {
                            if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1 && abs(dk) <= 1) {
                                continue;
                            }
                            let bound = cell_gap2(f.x, di) + gj + gk;
                            if (bound > limit) {
                                continue;
                            }
                            let site = voronoi_export_site3(voronoi_export_add(c.x, di), row);
                            let d = vec3<f32>((f32(di) + site.x) - f.x, (f32(dj) + site.y) - f.y, (f32(dk) + site.z) - f.z);
                            let q = voronoi_bisector3(d, dn);
                            voronoi_border_update(q, f1, &border, &limit);
                        }
                    }
                }
            }
            return vec3<f32>(border, 0.0f, 0.0f);
        }
        case 3u: {
            return vec3<f32>(sqrt(second) - f1, 0.0f, 0.0f);
        }
        default: {
            let k = min(u32(nearest.w * f32(voronoi_export_colours)), voronoi_export_colours - 1u);
            return voronoi_export_palette[k];
        }
    }
}

/// The diagram at the position `cell + offset` (pixels).
fn voronoi_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> VORONOI_VALUE {
    let v = voronoi_export_value(cell, offset);
    return VORONOI_RESULT;
}
