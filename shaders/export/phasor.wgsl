// export/phasor.wgsl — the exported entry of a phasor noise (after phasor.wgsl and
// export/split.wgsl): lattice 0 of the export tables is the kernel grid (cell side r, the
// kernel radius). The compute shader reads impulses the host drew per tile
// (spectex_model::phasor_kernels); an exported module has no host, so this glue draws each of
// the 3×3 (3×3×3) cells a point reaches itself, with the randomness contract's WGSL twin, in
// the order `PhasorKernels::draw_cell` draws them: the Poisson count (Knuth's product against
// exp(−λ), capped), then per impulse its offsets, its direction's draws and ψ. What the host
// computes from the model's fields is a constant of the export (the exporter refuses models
// whose fields vary): the frequency magnitude `F·r` (turns per cell), the direction of an
// aligned model and the two directions of a two-lobe one, as the host rounds them. The
// exporter declares:
//     phasor_export_seed: u32         the model's seed,
//     phasor_export_threshold: f32    exp(−λ) rounded to f32 (λ impulses per cell),
//     phasor_export_cap: u32          ⌊4λ + 32⌋,
//     phasor_export_mode: u32         0 aligned (direction a), 1 two lobes, 2 isotropic,
//     phasor_export_fr: f32           F·r, the frequency magnitude (turns per cell unit),
//     phasor_export_f_a, _f_b: vec3   F·r times direction a (b): the impulse frequency vectors.
// The sum, outputs and profiles are phasor.wgsl's (the same f32 operations as the CPU).

/// The PRNG of kernel cell `c` (spectex_model::phasor_kernels, layer 0): a 3D model hashes
/// the layer k into the seed first.
fn phasor_export_prng(c: vec3<i32>) -> Prng {
    var seed = phasor_export_seed;
    if (params.three_d == 1u) {
        seed = cell_hash(c.z, 0i, 0u, seed);
    }
    return Prng(cell_hash(c.x, c.y, 0u, seed));
}

/// Knuth's Poisson count: uniforms multiplied until the product falls below exp(−λ).
fn phasor_export_count(prng: ptr<function, Prng>) -> u32 {
    var p = 1.0f;
    var n = 0u;
    while (n < phasor_export_cap) {
        p *= prng_next_f32(prng);
        if (p < phasor_export_threshold) {
            return n;
        }
        n += 1u;
    }
    return n;
}

/// An impulse's frequency vector (turns per cell unit), drawing what its orientation draws.
fn phasor_export_frequency(prng: ptr<function, Prng>) -> vec3<f32> {
    switch phasor_export_mode {
        case 0u: {
            return phasor_export_f_a;
        }
        case 1u: {
            if (prng_next_f32(prng) < 0.5f) {
                return phasor_export_f_a;
            }
            return phasor_export_f_b;
        }
        default: {
            let fr = phasor_export_fr;
            if (params.three_d == 1u) {
                let z = 2.0f * prng_next_f32(prng) - 1.0f;
                let s = sqrt(max(1.0f - z * z, 0.0f));
                let t = prng_next_f32(prng);
                return vec3<f32>(fr * (s * cos_turns(t)), fr * (s * sin_turns(t)), fr * z);
            }
            let t = prng_next_f32(prng);
            return vec3<f32>(fr * cos_turns(t), fr * sin_turns(t), fr * 0.0f);
        }
    }
}

/// The noise at the position `cell + offset` (pixels): the CPU's sum over the cells' impulses
/// in its order (layers, rows, columns ascending; impulses in draw order), then its output.
fn phasor_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let cx = export_locate(at.n.x, at.u.x, 0u);
    let cy = export_locate(at.n.y, at.u.y, 0u);
    // The CPU's offsets in cell units, `x/r − ⌊x/r⌋` rounded once from f64.
    let ux = (cx.rem + at.u.x) * export_inv_sides[0];
    let uy = (cy.rem + at.u.y) * export_inv_sides[0];
    if (params.z_valid == 0u) {
        return 0.0f;
    }
    var re = 0.0f;
    var im = 0.0f;
    let layers = select(1, 3, params.three_d == 1u);
    for (var l = 0; l < layers; l++) {
        let sz = select(0, l - 1, params.three_d == 1u);
        let dz = params.z_offset - f32(sz);
        for (var sy = -1; sy <= 1; sy++) {
            let dy = uy - f32(sy);
            for (var sx = -1; sx <= 1; sx++) {
                let dxs = ux - f32(sx);
                let c = vec3<i32>(
                    bitcast<i32>(bitcast<u32>(cx.cell) + bitcast<u32>(sx)),
                    bitcast<i32>(bitcast<u32>(cy.cell) + bitcast<u32>(sy)),
                    bitcast<i32>(bitcast<u32>(params.z_cell) + bitcast<u32>(sz)),
                );
                var prng = phasor_export_prng(c);
                let count = phasor_export_count(&prng);
                for (var k = 0u; k < count; k++) {
                    let ox = prng_next_f32(&prng);
                    let oy = prng_next_f32(&prng);
                    var oz = 0.0f;
                    if (params.three_d == 1u) {
                        oz = prng_next_f32(&prng);
                    }
                    let f = phasor_export_frequency(&prng);
                    let psi = prng_next_f32(&prng);
                    let d = vec3<f32>(dxs - ox, dy - oy, dz - oz);
                    let d2 = d.x * d.x + d.y * d.y + d.z * d.z;
                    if (d2 < 1.0f) {
                        let g = exp_poly(PHASOR_NEG_LN_20 * d2);
                        let t = f.x * d.x + f.y * d.y + f.z * d.z + psi;
                        re += g * cos_turns(t);
                        im += g * sin_turns(t);
                    }
                }
            }
        }
    }
    var v = 0.0f;
    switch params.output_kind {
        case 1u: {
            v = atan2_turns(im, re);
        }
        case 2u: {
            v = sqrt(re * re + im * im);
        }
        case 3u: {
            v = im;
        }
        default: {
            v = leaf(params.a_kind, params.a_start, params.a_len, params.duty_a, re, im, 0.0f);
            if (params.blend == 1u) {
                let b = leaf(params.b_kind, params.b_start, params.b_len, params.duty_b, re, im, 0.0f);
                v = (1.0f - params.weight) * v + params.weight * b;
            }
        }
    }
    return params.mean + params.amplitude * v;
}
