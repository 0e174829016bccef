// export/voronoi.wgsl — the exported entry of a Voronoi diagram (after voronoi.wgsl and
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
    if (params.box_depth > 0u) {
        return voronoi_export_value3(vec3<i32>(cx.cell, cy.cell, params.z_cell), vec3<f32>(fx, fy, params.z_offset));
    }
    let reach = params.reach;
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
    switch params.output {
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
                    let ex = dx - dn.x;
                    let ey = dy - dn.y;
                    let e2 = ex * ex + ey * ey;
                    if (e2 == 0.0f) {
                        continue;
                    }
                    let num = (dx + dn.x) * ex + (dy + dn.y) * ey;
                    let q = num * 0.5f / sqrt(e2);
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

/// The site of the 3D cell `c`: offset x, y, z (cell units) and the ID
/// (`VoronoiNoise::jittered3`).
fn voronoi_export_site3(c: vec3<i32>) -> vec4<f32> {
    let plane = cell_hash(c.z, 0, VORONOI_EXPORT_LAYER, voronoi_export_seed);
    var prng = Prng(cell_hash(c.x, c.y, VORONOI_EXPORT_LAYER, plane));
    let ox = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let oy = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let oz = 0.5f + voronoi_export_jitter * (prng_next_f32(&prng) - 0.5f);
    let id = prng_next_f32(&prng);
    return vec4<f32>(ox, oy, oz, id);
}

/// The 3D cell `c + o` with i32 wrapping per axis.
fn voronoi_export_add3(c: vec3<i32>, o: vec3<i32>) -> vec3<i32> {
    return vec3<i32>(voronoi_export_add(c.x, o.x), voronoi_export_add(c.y, o.y), voronoi_export_add(c.z, o.z));
}

/// The 3D diagram at offset `f` in cell `c` (voronoi_main3's search).
fn voronoi_export_value3(c: vec3<i32>, f: vec3<f32>) -> vec3<f32> {
    let reach = params.reach;
    let want_second = params.output == 3u;
    var best = 3.4028235e38f;
    var second = 3.4028235e38f;
    var key = 2147483647;
    var nearest = vec4<f32>(0.0f);
    var dn = vec3<f32>(0.0f);
    for (var sweep = 0; sweep < 2; sweep++) {
        let r = select(reach, 1, sweep == 0);
        for (var dk = -r; dk <= r; dk++) {
            // A plane (row) whose own gap exceeds the bound holds no cell under it: every
            // cell's bound, `(gap_i + gap_j) + gap_k` in f32, is at least `gap_k`
            // (`gap_j + gap_k`), rounding being monotonic, and the bound only falls. Skipping
            // it whole visits exactly the cells the per-cell test visits, in the same order.
            let gk = voronoi_gap2(dk, f.z);
            if (gk > select(best, second, want_second)) {
                continue;
            }
            for (var dj = -r; dj <= r; dj++) {
                if (voronoi_gap2(dj, f.y) + gk > select(best, second, want_second)) {
                    continue;
                }
                for (var di = -r; di <= r; di++) {
                    if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1 && abs(dk) <= 1) {
                        continue;
                    }
                    let bound = voronoi_gap2(di, f.x) + voronoi_gap2(dj, f.y) + voronoi_gap2(dk, f.z);
                    if (bound > select(best, second, want_second)) {
                        continue;
                    }
                    let site = voronoi_export_site3(voronoi_export_add3(c, vec3<i32>(di, dj, dk)));
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
    switch params.output {
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
                for (var dk = -r; dk <= r; dk++) {
                    // Whole planes and rows over the limit skipped, as in the first search.
                    let gk = voronoi_gap2(dk, f.z);
                    if (gk > limit) {
                        continue;
                    }
                    for (var dj = -r; dj <= r; dj++) {
                        if (voronoi_gap2(dj, f.y) + gk > limit) {
                            continue;
                        }
                        for (var di = -r; di <= r; di++) {
                            if (sweep == 1 && abs(di) <= 1 && abs(dj) <= 1 && abs(dk) <= 1) {
                                continue;
                            }
                            let bound = voronoi_gap2(di, f.x) + voronoi_gap2(dj, f.y) + voronoi_gap2(dk, f.z);
                            if (bound > limit) {
                                continue;
                            }
                            let site = voronoi_export_site3(voronoi_export_add3(c, vec3<i32>(di, dj, dk)));
                            let d = vec3<f32>((f32(di) + site.x) - f.x, (f32(dj) + site.y) - f.y, (f32(dk) + site.z) - f.z);
                            let e = d - dn;
                            let e2 = e.x * e.x + e.y * e.y + e.z * e.z;
                            if (e2 == 0.0f) {
                                continue;
                            }
                            let s = d + dn;
                            let num = s.x * e.x + s.y * e.y + s.z * e.z;
                            let q = num * 0.5f / sqrt(e2);
                            if (q < border) {
                                border = q;
                                let far = 2.0f * (q + VORONOI_BORDER_PRUNE_MARGIN) + f1;
                                limit = far * far;
                            }
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
