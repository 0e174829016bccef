// phasor.wgsl — phasor noise (Tricard et al. 2019), the GPU twin of
// crates/spectex-cpu/src/phasor.rs (whose module doc is the specification). Composed after
// common.wgsl.
//
// The kernels are not drawn here: the host draws, with spectex_model::phasor_kernels (the
// randomness contract, the very code the CPU evaluator calls), every cell the tile's pixels can
// reach — a box of cells around the tile, 3 layers deep for a 3D model — and uploads them as a
// cell table (start, count) and an impulse table (offset xyz, phase offset ψ; frequency xyz in
// turns per cell). Fields (graded frequency, angle, image gradients, the coherent direction
// field) are therefore evaluated once, on the host, exactly as on the CPU.
//
// A pixel sums, in the CPU's order (cell layers, rows, columns ascending; impulses in draw
// order), g = exp_poly(−ln 20·s·|d|²) times cos and sin of t = f·d + ψ over the impulses with
// s·|d|² < 1 (s the kernel's sharpness, 1 unless the bandwidth varies), d = (u − s) − o in cell units; then intensity, phase (atan2_turns) or a profile of
// the phase. Profile parameters that vary in space (duty cycle, blend weight) come per pixel
// from the host, computed in f64 as the CPU does.

struct PhasorParams {
    width: u32,
    height: u32,
    /// 1 for a 3D model (cells k − 1, k, k + 1), else 0.
    three_d: u32,
    /// 0 profiled, 1 phase, 2 intensity, 3 Gabor (Im 𝒢).
    output_kind: u32,
    /// The cell box: first column and row, columns, rows.
    box_i0: i32,
    box_j0: i32,
    box_cols: u32,
    box_rows: u32,
    /// The plane's cell layer and offset (3D), and whether it is in range.
    z_cell: i32,
    z_offset: f32,
    z_valid: u32,
    /// 1 when per-pixel profile parameters are bound (else the constants below are used).
    per_pixel: u32,
    mean: f32,
    amplitude: f32,
    /// Profile leaves A and B: kind (0 sine, 1 square, 2 triangle, 3 sawtooth, 4 samples,
    /// 5 harmonics), start and length in `profile_data`.
    a_kind: u32,
    a_start: u32,
    a_len: u32,
    b_kind: u32,
    b_start: u32,
    b_len: u32,
    /// 1 when the profile is a blend (1 − s)·A + s·B.
    blend: u32,
    duty_a: f32,
    duty_b: f32,
    weight: f32,
    /// 1 / side of the kernel cells, for warping (the host's box then covers the displaced
    /// pixels' cells).
    inv_side: f32,
    /// 1: a minified render, whose square profiles are filtered at `harmonic_scale[pixel]`.
    filtered: u32,
}

/// One impulse: offset in its cell and ψ; frequency vector (turns per cell unit) and the
/// sharpness s = (b_j/b_min)² (the kernel is exp(−ln 20·s·|d|²) for s·|d|² < 1).
struct PhasorImpulse {
    o_psi: vec4<f32>,
    f: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: PhasorParams;
/// Samples of sampled profiles; (k, weight, shift in turns) triples of additive ones.
@group(0) @binding(1) var<storage, read> profile_data: array<f32>;
/// (start, count) in `impulses` of each cell of the box, layer-major then row-major.
@group(0) @binding(2) var<storage, read> cells: array<vec2<u32>>;
@group(0) @binding(3) var<storage, read> impulses: array<PhasorImpulse>;
/// Per pixel (when `per_pixel` = 1): duty of A, duty of B, blend weight.
@group(0) @binding(4) var<storage, read> pixel_params: array<f32>;
/// Per pixel (when `filtered` = 1): u = F(p)·s, the local frequency times the footprint, at
/// which every profile's harmonics are weighted.
@group(0) @binding(5) var<storage, read> harmonic_scale: array<f32>;
@group(0) @binding(6) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(7) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(8) var<storage, read_write> output: array<f32>;

/// spectex_model::filter's MAX_SQUARE_HARMONICS (`filter_response` is common.wgsl's).
const MAX_SQUARE_HARMONICS: u32 = 64u;

/// spectex_model::filter::filtered_square: the square profile's Fourier series, harmonic k
/// weighted by filter_response(k·u).
fn square_filtered(t: f32, duty: f32, u: f32) -> f32 {
    let shift = t - 0.5f * duty;
    var sum = duty;
    for (var k = 1u; k <= MAX_SQUARE_HARMONICS; k++) {
        let kf = f32(k);
        let v = kf * u;
        if (!(v < FILTER_FADE_END)) {
            break;
        }
        let c = 2.0f / (FILTER_PI * kf) * sin_turns(0.5f * kf * duty);
        sum += filter_response(v) * c * cos_turns(kf * shift);
    }
    return sum;
}

/// spectex_model::filter::filtered_triangle: harmonic n (odd) weighted by filter_response(n·u).
fn triangle_filtered(t: f32, u: f32) -> f32 {
    var sum = 0.0f;
    for (var k = 1u; k <= MAX_SQUARE_HARMONICS; k += 2u) {
        let kf = f32(k);
        let v = kf * u;
        if (!(v < FILTER_FADE_END)) {
            break;
        }
        let sign = select(-1.0f, 1.0f, k % 4u == 1u);
        let c = sign * 8.0f / (FILTER_PI * FILTER_PI * kf * kf);
        sum += filter_response(v) * c * sin_turns(kf * t);
    }
    return sum;
}

/// spectex_model::filter::filtered_sawtooth: harmonic k weighted by filter_response(k·u).
fn sawtooth_filtered(t: f32, u: f32) -> f32 {
    var sum = 0.0f;
    for (var k = 1u; k <= MAX_SQUARE_HARMONICS; k++) {
        let kf = f32(k);
        let v = kf * u;
        if (!(v < FILTER_FADE_END)) {
            break;
        }
        sum += filter_response(v) * (-2.0f / (FILTER_PI * kf)) * sin_turns(kf * t);
    }
    return sum;
}

/// spectex_model::filter::filtered_samples: the series [c0, a1, b1, …] stored at `start`,
/// harmonic k weighted by filter_response(k·u).
fn samples_filtered(start: u32, t: f32, u: f32) -> f32 {
    var sum = profile_data[start];
    for (var k = 1u; k <= MAX_SQUARE_HARMONICS; k++) {
        let kf = f32(k);
        let v = kf * u;
        if (!(v < FILTER_FADE_END)) {
            break;
        }
        let base = start + 2u * k - 1u;
        sum += filter_response(v)
            * (profile_data[base] * cos_turns(kf * t) + profile_data[base + 1u] * sin_turns(kf * t));
    }
    return sum;
}

/// −ln 20: the Gaussian exponent per squared cell unit (NEG_LN_20).
const PHASOR_NEG_LN_20: f32 = -2.9957323f;

/// The phase in turns in [0, 1).
fn phase01(re: f32, im: f32) -> f32 {
    let p = atan2_turns(im, re);
    var t = select(p, p + 1.0f, p < 0.0f);
    if (t >= 1.0f) {
        t = 0.0f;
    }
    return t;
}

/// A profile leaf of the phase of (re, im).
fn leaf(kind: u32, start: u32, len: u32, duty: f32, re: f32, im: f32, u: f32) -> f32 {
    let filtered = params.filtered == 1u;
    switch kind {
        case 0u: {
            let i = sqrt(re * re + im * im);
            let sine = select(0.0f, im / i, i > 0.0f);
            if (filtered) {
                return filter_response(u) * sine;
            }
            return sine;
        }
        case 1u: {
            if (filtered) {
                return square_filtered(phase01(re, im), duty, u);
            }
            return select(0.0f, 1.0f, phase01(re, im) < duty);
        }
        case 2u: {
            if (filtered) {
                return triangle_filtered(phase01(re, im), u);
            }
            var s = phase01(re, im) + 0.25f;
            if (s >= 1.0f) {
                s -= 1.0f;
            }
            return 1.0f - 4.0f * abs(s - 0.5f);
        }
        case 3u: {
            if (filtered) {
                return sawtooth_filtered(phase01(re, im), u);
            }
            return 2.0f * phase01(re, im) - 1.0f;
        }
        case 4u: {
            if (filtered) {
                return samples_filtered(start + len, phase01(re, im), u);
            }
            let pos = phase01(re, im) * f32(len);
            let i = min(u32(pos), len - 1u);
            let frac = pos - f32(i);
            return profile_data[start + i] * (1.0f - frac)
                + profile_data[start + (i + 1u) % len] * frac;
        }
        default: {
            let t = phase01(re, im);
            var sum = 0.0f;
            for (var h = 0u; h < len; h++) {
                let base = start + 3u * h;
                let term = profile_data[base + 1u] * sin_turns(profile_data[base] * t + profile_data[base + 2u]);
                if (filtered) {
                    sum += filter_response(profile_data[base] * u) * term;
                } else {
                    sum += term;
                }
            }
            return sum;
        }
    }
}

@compute @workgroup_size(8, 8, 1)
fn phasor_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let at = grid_point(columns[gid.x], rows[gid.y], index, params.inv_side);
    let column = at.column;
    let row = at.row;
    if (column.valid == 0u || row.valid == 0u || params.z_valid == 0u) {
        output[index] = 0.0f;
        return;
    }
    var re = 0.0f;
    var im = 0.0f;
    let layers = select(1, 3, params.three_d == 1u);
    for (var l = 0; l < layers; l++) {
        let sz = select(0, l - 1, params.three_d == 1u);
        let dz = params.z_offset - f32(sz);
        for (var sy = -1; sy <= 1; sy++) {
            let dy = row.offset - f32(sy);
            let j = u32(row.cell + sy - params.box_j0);
            for (var sx = -1; sx <= 1; sx++) {
                let dxs = column.offset - f32(sx);
                let i = u32(column.cell + sx - params.box_i0);
                // Never outside the host's box (it covers every pixel's cells); a guard, not a
                // case: an out-of-box read would be a wrong cell, so it is skipped.
                if (i >= params.box_cols || j >= params.box_rows) {
                    continue;
                }
                let cell = cells[(u32(l) * params.box_rows + j) * params.box_cols + i];
                for (var n = cell.x; n < cell.x + cell.y; n++) {
                    let imp = impulses[n];
                    let d = vec3<f32>(dxs - imp.o_psi.x, dy - imp.o_psi.y, dz - imp.o_psi.z);
                    let d2 = (d.x * d.x + d.y * d.y + d.z * d.z) * imp.f.w;
                    if (d2 < 1.0f) {
                        let g = exp_poly(PHASOR_NEG_LN_20 * d2);
                        let t = imp.f.x * d.x + imp.f.y * d.y + imp.f.z * d.z + imp.o_psi.w;
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
            var duty_a = params.duty_a;
            var duty_b = params.duty_b;
            var s = params.weight;
            if (params.per_pixel == 1u) {
                duty_a = pixel_params[3u * index];
                duty_b = pixel_params[3u * index + 1u];
                s = pixel_params[3u * index + 2u];
            }
            var u = 0.0f;
            if (params.filtered == 1u) {
                u = harmonic_scale[index];
            }
            v = leaf(params.a_kind, params.a_start, params.a_len, duty_a, re, im, u);
            if (params.blend == 1u) {
                let b = leaf(params.b_kind, params.b_start, params.b_len, duty_b, re, im, u);
                v = (1.0f - s) * v + s * b;
            }
        }
    }
    output[index] = params.mean + params.amplitude * v;
}
