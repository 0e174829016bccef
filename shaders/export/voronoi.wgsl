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

/// The diagram at the position `cell + offset` (pixels).
fn voronoi_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> VORONOI_VALUE {
    let v = voronoi_export_value(cell, offset);
    return VORONOI_RESULT;
}
