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
// For an undisplaced tile, `phasor_bin` first writes per 8×8-pixel block (the workgroup) and
// cell a mask of the impulses that can reach the block; a pixel then visits those only (a
// displaced tile's pixels leave their blocks and visit all). On lavapipe: 28 visits a pixel
// instead of 58 (phasor-two-lobes-phase); the graded models 15–17% faster.
//
// A pixel sums, in the CPU's order (cell layers, rows, columns ascending; impulses in draw
// order), g = exp_poly(−ln 20·s·|d|²) times cos and sin of t = f·d + ψ over the impulses with
// s·|d|² < 1 (s the kernel's sharpness, 1 unless the bandwidth varies), d = (u − s) − o in
// cell units; then intensity, phase (atan2_turns) or a profile of the phase. Profile
// parameters that vary in space (duty cycle, blend weight) are read per pixel from records per
// column and per row (`pixel_field`, in f32 where the CPU reads them in f64; the cross-check
// bounds the difference), or, for a displaced tile, come per pixel
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
    /// With per_pixel: 1 when `pixel_params` holds the fields' column and row records
    /// (`pixel_field`), 0 when it holds each pixel's values (a displaced tile).
    pixel_fields: u32,
    _pad1: u32,
    _pad2: u32,
    /// Blocks of PHASOR_BLOCK × PHASOR_BLOCK pixels across the tile.
    bin_blocks_x: u32,
    /// Cells per block along x and along y: its first column's (row's) cell − 1 on.
    bin_span: u32,
    /// Mask chunks per cell (16 impulses a chunk).
    bin_chunks: u32,
    /// `phasor_bin`'s invocations (one per block, layer and cell of its span; 0 where `bins`
    /// holds nothing and every pixel visits every impulse of its 3×3 (3×3×3) cells) and
    /// invocations per row of its dispatch grid.
    bin_masks: u32,
    bin_stride: u32,
    _pad0: u32,
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
/// When `per_pixel` = 1: per pixel the duty of A, the duty of B and the blend weight; or,
/// with `pixel_fields` = 1, those three fields' records (`pixel_field`).
@group(0) @binding(4) var<storage, read> pixel_params: array<f32>;
/// Per pixel (when `filtered` = 1): u = F(p)·s, the local frequency times the footprint, at
/// which every profile's harmonics are weighted.
@group(0) @binding(5) var<storage, read> harmonic_scale: array<f32>;
/// When `bin_masks` is not 0, the reach masks `phasor_bin` wrote (`phasor_main` reads the chunks of
/// the pixel's block; `phasor_bin` writes them in `output`'s place).
@group(0) @binding(6) var<storage, read> bins: array<f32>;
@group(0) @binding(7) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(8) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(9) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes"): its dimension, output, profiles and whether it
// reads per-pixel parameters.
override PHASOR_THREE_D: u32 = 0xffffffffu;
override PHASOR_OUTPUT_KIND: u32 = 0xffffffffu;
override PHASOR_PER_PIXEL: u32 = 0xffffffffu;
override PHASOR_A_KIND: u32 = 0xffffffffu;
override PHASOR_B_KIND: u32 = 0xffffffffu;
override PHASOR_BLEND: u32 = 0xffffffffu;

fn phasor_three_d() -> u32 {
    return shape_or(PHASOR_THREE_D, params.three_d);
}

fn phasor_output_kind() -> u32 {
    return shape_or(PHASOR_OUTPUT_KIND, params.output_kind);
}

fn phasor_per_pixel() -> u32 {
    return shape_or(PHASOR_PER_PIXEL, params.per_pixel);
}

fn phasor_a_kind() -> u32 {
    return shape_or(PHASOR_A_KIND, params.a_kind);
}

fn phasor_b_kind() -> u32 {
    return shape_or(PHASOR_B_KIND, params.b_kind);
}

fn phasor_blend() -> u32 {
    return shape_or(PHASOR_BLEND, params.blend);
}

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

/// Field `f` (0 duty of A, 1 duty of B, 2 blend weight) at column `x` and row `y` of the tile,
/// from the records of spectex_gpu::phasor::device_fields: a header (kind, grey start, min,
/// max − min) per field, then a record per field and column and per field and row. Kind 1
/// (linear): the column's and the row's terms, each (·, ·, lo, hi), added as two-float
/// numbers (Knuth's two-sum of the high parts, then the low parts) and rounded once, clamped;
/// kind 2 (image): the bilinear interpolation of the image's grey samples between the
/// records' taps (i0, i1, t) and (j0·w, j1·w, t) in spectex_model's order, min + g·(max − min),
/// clamped; kind 0: `fallback`.
fn pixel_field(f: u32, x: u32, y: u32, fallback: f32) -> f32 {
    let header = 4u * f;
    let column = 12u + 4u * (f * params.width + x);
    let row = 12u + 12u * params.width + 4u * (f * params.height + y);
    switch u32(pixel_params[header]) {
        case 1u: {
            let a = pixel_params[column + 3u];
            let b = pixel_params[row + 3u];
            let s = a + b;
            let bb = s - a;
            let err = (a - (s - bb)) + (b - bb);
            let low = (err + pixel_params[column + 2u]) + pixel_params[row + 2u];
            return clamp(s + low, 0.0f, 1.0f);
        }
        case 2u: {
            let start = u32(pixel_params[header + 1u]);
            let i0 = u32(pixel_params[column]);
            let i1 = u32(pixel_params[column + 1u]);
            let tx = pixel_params[column + 2u];
            let j0 = start + u32(pixel_params[row]);
            let j1 = start + u32(pixel_params[row + 1u]);
            let ty = pixel_params[row + 2u];
            let top = profile_data[j0 + i0] * (1.0f - tx) + profile_data[j0 + i1] * tx;
            let bottom = profile_data[j1 + i0] * (1.0f - tx) + profile_data[j1 + i1] * tx;
            let g = top * (1.0f - ty) + bottom * ty;
            return clamp(pixel_params[header + 2u] + g * pixel_params[header + 3u], 0.0f, 1.0f);
        }
        default: {
            return fallback;
        }
    }
}

/// A neighbour cell whose squared gap to the pixel (`cell_gap2`) is at least this holds no impulse within
/// the kernel's support (s·|d|² < 1 with s ≥ 1), whatever the f32 roundings of |d|² (a few
/// ulps, far below the 10⁻⁴ margin): `phasor_main` skips it, which adds exactly what its
/// impulses would (nothing). A corner cell is out of reach for 21% of a cell's pixels in 2D;
/// in 3D edge cells 21% and corner cells 48%.
const PHASOR_CELL_REACH2: f32 = 1.0001f;

/// Side of a bin block, pixels: `phasor_main`'s workgroup, whose pixels share their masks.
const PHASOR_BLOCK: u32 = 8u;
/// Impulses per mask chunk: a chunk is an f32 holding an integer below 2¹⁶ (exact), written
/// by `phasor_bin` in `output`'s place.
const PHASOR_CHUNK: u32 = 16u;

/// The reach masks of a tile's pixel blocks. Invocation m is block b's layer l and cell
/// (u_x, u_y) of its span, `m = ((b·layers + l)·span_y + u_y)·span_x + u_x`, the cell
/// `(c₀ − 1 + u_x, r₀ − 1 + u_y)` for the block's first column's cell c₀ and first row's r₀.
/// Its chunks hold one bit per impulse of that cell (in draw order): set unless the impulse
/// lies beyond the kernel's support (`s·gap² ≥ PHASOR_CELL_REACH2`, the cell skip's bound)
/// from the block's box of pixel positions (its first and last columns and rows; positions
/// increase with the column). `phasor_main` then visits only set bits, in order, and adds
/// exactly what visiting every impulse adds: a cleared impulse's `s·|d|²` is at least 1 at
/// every pixel of the block, whatever its roundings. A block whose corner pixels are invalid
/// or out of order (a periodic wrap) sets every bit.
@compute @workgroup_size(64, 1, 1)
fn phasor_bin(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = gid.y * params.bin_stride + gid.x;
    if (m >= params.bin_masks) {
        return;
    }
    let ux = m % params.bin_span;
    let uy = (m / params.bin_span) % params.bin_span;
    let layers = select(1u, 3u, phasor_three_d() == 1u);
    let l = (m / (params.bin_span * params.bin_span)) % layers;
    let block = m / (params.bin_span * params.bin_span * layers);
    let x0 = (block % params.bin_blocks_x) * PHASOR_BLOCK;
    let y0 = (block / params.bin_blocks_x) * PHASOR_BLOCK;
    let c0 = columns[x0];
    let c1 = columns[min(x0 + PHASOR_BLOCK - 1u, params.width - 1u)];
    let r0 = rows[y0];
    let r1 = rows[min(y0 + PHASOR_BLOCK - 1u, params.height - 1u)];
    let cell_x = bitcast<i32>(bitcast<u32>(c0.cell) + ux - 1u);
    let cell_y = bitcast<i32>(bitcast<u32>(r0.cell) + uy - 1u);
    let i = bitcast<u32>(cell_x) - bitcast<u32>(params.box_i0);
    let j = bitcast<u32>(cell_y) - bitcast<u32>(params.box_j0);
    var cell = vec2<u32>(0u);
    if (i < params.box_cols && j < params.box_rows) {
        cell = cells[(l * params.box_rows + j) * params.box_cols + i];
    }
    // The block's pixels relative to this cell, cell units.
    let lo_x = f32(bitcast<i32>(bitcast<u32>(c0.cell) - bitcast<u32>(cell_x))) + c0.offset;
    let hi_x = f32(bitcast<i32>(bitcast<u32>(c1.cell) - bitcast<u32>(cell_x))) + c1.offset;
    let lo_y = f32(bitcast<i32>(bitcast<u32>(r0.cell) - bitcast<u32>(cell_y))) + r0.offset;
    let hi_y = f32(bitcast<i32>(bitcast<u32>(r1.cell) - bitcast<u32>(cell_y))) + r1.offset;
    let all = c0.valid == 0u || c1.valid == 0u || r0.valid == 0u || r1.valid == 0u
        || !(lo_x <= hi_x) || !(lo_y <= hi_y);
    let sz = select(0, i32(l) - 1, phasor_three_d() == 1u);
    let dz = params.z_offset - f32(sz);
    for (var k = 0u; k < params.bin_chunks; k++) {
        var bits = 0u;
        for (var b = 0u; b < PHASOR_CHUNK; b++) {
            let n = k * PHASOR_CHUNK + b;
            if (n >= cell.y) {
                break;
            }
            let imp = impulses[cell.x + n];
            let o = imp.o_psi;
            let gx = max(max(lo_x - o.x, o.x - hi_x), 0.0f);
            let gy = max(max(lo_y - o.y, o.y - hi_y), 0.0f);
            let gz = dz - o.z;
            let reach = (gx * gx + gy * gy + gz * gz) * imp.f.w;
            if (all || reach < PHASOR_CELL_REACH2) {
                bits |= 1u << b;
            }
        }
        output[m * params.bin_chunks + k] = f32(bits);
    }
}

/// Adds impulse `imp`'s term at `d = (dxs, dy, dz) − o` to `re` and `im` where `s·|d|² < 1`.
fn phasor_add(imp: PhasorImpulse, dxs: f32, dy: f32, dz: f32, re: ptr<function, f32>, im: ptr<function, f32>) {
    let d = vec3<f32>(dxs - imp.o_psi.x, dy - imp.o_psi.y, dz - imp.o_psi.z);
    let d2 = (d.x * d.x + d.y * d.y + d.z * d.z) * imp.f.w;
    if (d2 < 1.0f) {
        let g = exp_poly(PHASOR_NEG_LN_20 * d2);
        let t = imp.f.x * d.x + imp.f.y * d.y + imp.f.z * d.z + imp.o_psi.w;
        *re += g * cos_turns(t);
        *im += g * sin_turns(t);
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
    let layers = select(1, 3, phasor_three_d() == 1u);
    // The pixel's block and the cell its span starts at (`phasor_bin`).
    let block = (gid.y / PHASOR_BLOCK) * params.bin_blocks_x + gid.x / PHASOR_BLOCK;
    var span_i = 0u;
    var span_j = 0u;
    let binned = params.bin_masks != 0u;
    if (binned) {
        span_i = bitcast<u32>(columns[gid.x - gid.x % PHASOR_BLOCK].cell) - 1u;
        span_j = bitcast<u32>(rows[gid.y - gid.y % PHASOR_BLOCK].cell) - 1u;
    }
    for (var l = 0; l < layers; l++) {
        let sz = select(0, l - 1, phasor_three_d() == 1u);
        let dz = params.z_offset - f32(sz);
        let gz = cell_gap2(params.z_offset, sz);
        for (var sy = -1; sy <= 1; sy++) {
            let dy = row.offset - f32(sy);
            let j = u32(row.cell + sy - params.box_j0);
            let gyz = cell_gap2(row.offset, sy) + gz;
            let uy = bitcast<u32>(row.cell + sy) - span_j;
            for (var sx = -1; sx <= 1; sx++) {
                let dxs = column.offset - f32(sx);
                let i = u32(column.cell + sx - params.box_i0);
                // Never outside the host's box (it covers every pixel's cells); a guard, not a
                // case: an out-of-box read would be a wrong cell, so it is skipped.
                if (i >= params.box_cols || j >= params.box_rows) {
                    continue;
                }
                if (cell_gap2(column.offset, sx) + gyz >= PHASOR_CELL_REACH2) {
                    continue;
                }
                let cell = cells[(u32(l) * params.box_rows + j) * params.box_cols + i];
                let ux = bitcast<u32>(column.cell + sx) - span_i;
                if (binned && ux < params.bin_span && uy < params.bin_span) {
                    // The impulses that can reach the block, in draw order.
                    let first = (((block * u32(layers) + u32(l)) * params.bin_span + uy)
                        * params.bin_span + ux) * params.bin_chunks;
                    for (var k = 0u; k < params.bin_chunks; k++) {
                        var bits = u32(bins[first + k]);
                        while (bits != 0u) {
                            let b = countTrailingZeros(bits);
                            bits &= bits - 1u;
                            phasor_add(impulses[cell.x + k * PHASOR_CHUNK + b], dxs, dy, dz, &re, &im);
                        }
                    }
                } else {
                    for (var n = cell.x; n < cell.x + cell.y; n++) {
                        phasor_add(impulses[n], dxs, dy, dz, &re, &im);
                    }
                }
            }
        }
    }
    var v = 0.0f;
    switch phasor_output_kind() {
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
            if (phasor_per_pixel() == 1u && params.pixel_fields == 1u) {
                duty_a = pixel_field(0u, gid.x, gid.y, duty_a);
                duty_b = pixel_field(1u, gid.x, gid.y, duty_b);
                s = pixel_field(2u, gid.x, gid.y, s);
            } else if (phasor_per_pixel() == 1u) {
                duty_a = pixel_params[3u * index];
                duty_b = pixel_params[3u * index + 1u];
                s = pixel_params[3u * index + 2u];
            }
            var u = 0.0f;
            if (params.filtered == 1u) {
                u = harmonic_scale[index];
            }
            v = leaf(phasor_a_kind(), params.a_start, params.a_len, duty_a, re, im, u);
            if (phasor_blend() == 1u) {
                let b = leaf(phasor_b_kind(), params.b_start, params.b_len, duty_b, re, im, u);
                v = (1.0f - s) * v + s * b;
            }
        }
    }
    output[index] = params.mean + params.amplitude * v;
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a phasor noise (after the kernel above and
// export/split.wgsl): lattice 0 of the export tables is the kernel grid (cell side r, the
// kernel radius). The compute shader reads impulses the host drew per tile
// (spectex_model::phasor_kernels); an exported module has no host, so this glue draws each of
// the 3×3 (3×3×3) cells a point reaches itself, with the randomness contract's WGSL twin, in
// the order `PhasorKernels::draw_cell` draws them: the Poisson count (Knuth's product against
// exp(−λ), capped), then per impulse its offsets, where the bandwidth varies its thinning
// uniform, its direction's draws and ψ. The exporter declares:
//     phasor_export_seed: u32         the model's seed,
//     phasor_export_threshold: f32    exp(−λ) rounded to f32 (λ impulses per cell),
//     phasor_export_cap: u32          ⌊4λ + 32⌋,
//     phasor_export_mode: u32         0 aligned at a constant angle (direction a), 1 two lobes,
//                                     2 isotropic, 3 aligned at a varying angle, 4 along an
//                                     image's gradient, 5 coherent,
//     phasor_export_fr: f32           F·r, the frequency magnitude (turns per cell unit) of a
//                                     constant frequency,
//     phasor_export_f_a, _f_b: vec3   F·r times direction a (b): the impulse frequency vectors,
//     phasor_export_u_a, _u_b: vec3   directions a and b (for a varying frequency),
//     phasor_export_graded: u32       1 where the bandwidth varies (impulses thinned),
//     phasor_export_b_min, _b_max     its range, f32,
//     phasor_export_varying_f: u32    1 where the frequency varies (F·r per impulse),
//     phasor_export_side: f32         r rounded to f32,
//     phasor_export_offset_cos, _sin: f32  cos and sin of a gradient orientation's offset,
//     phasor_export_dir_threshold, _dir_cap, _spread_turns, _cap_cos: the coherent direction
//                                     process (lattice 1 is its grid, side r_f),
//     phasor_export_per_pixel: u32    1 where a duty cycle or the blend weight varies,
// and, per field, `phasor_export_<field>(n, r)`: the field at the pixel position `n + r`
// (`n` integer, `r` an f32 below a few cells), for bandwidth, frequency, angle, duty_a,
// duty_b and weight, and `phasor_export_steer(n, r)`: a gradient orientation's central
// differences at `n + r` (`phasor_export_differences`; 0 for a field that is not an image, whose
// CPU `gradient_angle` is none). A constant field returns its value; a
// linear one `value + g·n + g·r`; an image field locates `n` on the lattice of its repeat
// (`width·pixel_size` along x, `height·pixel_size` along y: n = q·R + rem exactly where R is
// an f32) and interpolates its grey samples (after the profile data in `profile_data`) at
// `(rem + r)/pixel_size − ½` as the CPU does at `x/pixel_size − ½`, so a point at 10⁷ pixels
// reads its texel as precisely as one at the origin. The pixel's splits on the fields' lattices (and on the
// coherent direction grid) are taken once per pixel, `phasor_export_locate_fields`, not per
// impulse. Fields are read where the CPU reads them:
// kernel parameters at the impulse `((i, j) + o)·r`, which is `n + (s + o)·r − rem` for the
// pixel's cell split `n = cell·r + rem − u`; profile parameters at the pixel. They are f32
// here and f64 on the CPU: the export test bounds the difference and leaves out the pixels
// where it can decide a discontinuous use (a thinning comparison within its error of the
// threshold, a gradient or coherent sum within its error of zero).
// The sum, outputs and profiles are phasor.wgsl's (the same f32 operations as the CPU).

/// Where sample coordinate `u` falls on a periodic axis of `n` samples: the sample ⌊u⌋
/// wrapped into 0 … n − 1, with one remainder (`%` keeps the dividend's sign, so a negative
/// one takes +n), and the fraction `u − ⌊u⌋`.
struct PhasorExportTap {
    i: i32,
    t: f32,
}

fn phasor_export_tap(u: f32, n: i32) -> PhasorExportTap {
    let f = floor(u);
    let m = i32(f) % n;
    return PhasorExportTap(select(m, m + n, m < 0), u - f);
}

/// The sample after `i` on a periodic axis of `n` samples (a compare, not a remainder).
fn phasor_export_next(i: i32, n: i32) -> i32 {
    return select(i + 1, 0, i + 1 == n);
}

/// The bilinear interpolation of `w × h` grey samples at `profile_data[start..]` (row-major,
/// periodic), at sample coordinates `(u, v)`: spectex_model's `bilinear_periodic`.
fn phasor_export_bilinear(start: u32, w: i32, h: i32, u: f32, v: f32) -> f32 {
    let x = phasor_export_tap(u, w);
    let y = phasor_export_tap(v, h);
    let i1 = phasor_export_next(x.i, w);
    let j1 = phasor_export_next(y.i, h);
    let s00 = profile_data[start + u32(y.i * w + x.i)];
    let s10 = profile_data[start + u32(y.i * w + i1)];
    let s01 = profile_data[start + u32(j1 * w + x.i)];
    let s11 = profile_data[start + u32(j1 * w + i1)];
    let top = s00 * (1.0f - x.t) + s10 * x.t;
    let bottom = s01 * (1.0f - x.t) + s11 * x.t;
    return top * (1.0f - y.t) + bottom * y.t;
}

/// The central differences `(g(u + 1, v) − g(u − 1, v), g(u, v + 1) − g(u, v − 1))` of the
/// bilinear interpolation `g` of a periodic grey image at sample coordinates `(u, v)`: the
/// CPU's `gradient_angle` (one sample apart). They are the bilinear interpolation, with `g`'s
/// weights at `(u, v)`, of the samples' own central differences `(s[i+1, j] − s[i−1, j],
/// s[i, j+1] − s[i, j−1])` (the weights are the same at `u ± 1`, so each tap's term
/// regroups), which the exporter takes in f64 and stores as `w × h` pairs at
/// `profile_data[start..]` (row-major): four pairs, one tap per axis, where differencing
/// interpolated grey levels read twelve samples.
fn phasor_export_differences(start: u32, w: i32, h: i32, u: f32, v: f32) -> vec2<f32> {
    let x = phasor_export_tap(u, w);
    let y = phasor_export_tap(v, h);
    let i1 = phasor_export_next(x.i, w);
    let j1 = phasor_export_next(y.i, h);
    let r0 = start + 2u * u32(y.i * w);
    let r1 = start + 2u * u32(j1 * w);
    let c0 = 2u * u32(x.i);
    let c1 = 2u * u32(i1);
    let su = 1.0f - x.t;
    let sv = 1.0f - y.t;
    let d00 = vec2<f32>(profile_data[r0 + c0], profile_data[r0 + c0 + 1u]);
    let d10 = vec2<f32>(profile_data[r0 + c1], profile_data[r0 + c1 + 1u]);
    let d01 = vec2<f32>(profile_data[r1 + c0], profile_data[r1 + c0 + 1u]);
    let d11 = vec2<f32>(profile_data[r1 + c1], profile_data[r1 + c1 + 1u]);
    let top = d00 * su + d10 * x.t;
    let bottom = d01 * su + d11 * x.t;
    return top * sv + bottom * y.t;
}

/// The unit direction at `t` turns in the plane.
fn phasor_export_planar(t: f32) -> vec3<f32> {
    return vec3<f32>(cos_turns(t), sin_turns(t), 0.0f);
}

/// A gradient orientation's direction at the impulse `n + r`: the grey level's central
/// differences turned by the offset, the offset alone on a flat spot. The CPU takes `atan2` of
/// them in f64, adds the offset and its cosine and sine; here the differences are normalised
/// and rotated by the offset's cosine and sine (constants): the same direction, in a
/// division, a square root and four products where `atan2_turns`, `cos_turns` and `sin_turns`
/// cost three polynomials. Scaled by the larger component first, so that a tiny gradient
/// neither underflows to 0 nor divides by it.
fn phasor_export_gradient(n: vec2<i32>, r: vec2<f32>) -> vec3<f32> {
    let g = phasor_export_steer(n, r);
    let big = max(abs(g.x), abs(g.y));
    if (big == 0.0f) {
        return vec3<f32>(phasor_export_offset_cos, phasor_export_offset_sin, 0.0f);
    }
    let a = g / big;
    let inv = 1.0f / sqrt(a.x * a.x + a.y * a.y);
    let ux = a.x * inv;
    let uy = a.y * inv;
    return vec3<f32>(
        phasor_export_offset_cos * ux - phasor_export_offset_sin * uy,
        phasor_export_offset_sin * ux + phasor_export_offset_cos * uy,
        0.0f,
    );
}

/// The coherent direction field at the impulse `n + r` (§3.2.2): the normalised sum of the
/// direction process's kernels around it (lattice 1, DIRECTION_LAYER), as
/// `PhasorKernels::coherent_direction` sums them in f32.
fn phasor_export_coherent(n: vec2<i32>, r: vec2<f32>) -> vec3<f32> {
    // `n` (the pixel's) split on lattice 1, once per pixel by `phasor_sample_cell`.
    let ax = phasor_export_dir_x;
    let ay = phasor_export_dir_y;
    let wx = (ax.rem + r.x) * export_inv_sides[1];
    let wy = (ay.rem + r.y) * export_inv_sides[1];
    let fx = floor(wx);
    let fy = floor(wy);
    let cell = vec2<i32>(
        bitcast<i32>(bitcast<u32>(ax.cell) + bitcast<u32>(i32(fx))),
        bitcast<i32>(bitcast<u32>(ay.cell) + bitcast<u32>(i32(fy))),
    );
    let ux = wx - fx;
    let uy = wy - fy;
    var sum = vec3<f32>(0.0f);
    for (var sy = -1; sy <= 1; sy++) {
        let gy = cell_gap2(uy, sy);
        for (var sx = -1; sx <= 1; sx++) {
            // A cell of the direction process out of its kernels' reach (`PHASOR_CELL_REACH2`).
            if (cell_gap2(ux, sx) + gy >= PHASOR_CELL_REACH2) {
                continue;
            }
            let c = vec2<i32>(
                bitcast<i32>(bitcast<u32>(cell.x) + bitcast<u32>(sx)),
                bitcast<i32>(bitcast<u32>(cell.y) + bitcast<u32>(sy)),
            );
            var prng = Prng(cell_hash(c.x, c.y, 1u, phasor_export_seed));
            var p = 1.0f;
            var count = 0u;
            while (count < phasor_export_dir_cap) {
                p *= prng_next_f32(&prng);
                if (p < phasor_export_dir_threshold) {
                    break;
                }
                count += 1u;
            }
            for (var k = 0u; k < count; k++) {
                let ox = prng_next_f32(&prng);
                let oy = prng_next_f32(&prng);
                let t = (2.0f * prng_next_f32(&prng) - 1.0f) * phasor_export_spread_turns;
                let dx = (ux - f32(sx)) - ox;
                let dy = (uy - f32(sy)) - oy;
                let d2 = dx * dx + dy * dy + 0.0f * 0.0f;
                if (d2 < 1.0f) {
                    let g = exp_poly(PHASOR_NEG_LN_20 * d2);
                    sum.x += g * cos_turns(t);
                    sum.y += g * sin_turns(t);
                    sum.z += g * 0.0f;
                }
            }
        }
    }
    let norm = sqrt(sum.x * sum.x + sum.y * sum.y + sum.z * sum.z);
    if (norm > 0.0f) {
        return vec3<f32>(sum.x / norm, sum.y / norm, sum.z / norm);
    }
    return vec3<f32>(1.0f, 0.0f, 0.0f);
}

/// The pixel's integer position split on the direction grid (lattice 1), set by
/// `phasor_sample_cell` where the orientation is coherent: every impulse's direction sum reads
/// it, instead of splitting the same position again (a 32-step table loop per axis).
var<private> phasor_export_dir_x: ExportSplit;
var<private> phasor_export_dir_y: ExportSplit;

/// The PRNG of kernel cell `c` (spectex_model::phasor_kernels, layer 0): a 3D model hashes
/// the layer k into the seed first.
fn phasor_export_prng(c: vec3<i32>) -> Prng {
    var seed = phasor_export_seed;
    if (phasor_three_d() == 1u) {
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

/// An impulse's frequency vector (turns per cell unit) at `n + r` pixels, drawing what its
/// orientation draws: `F·r` (a constant, or the field at the impulse clamped to [0, ½] times
/// r in f32, as the CPU rounds it) times its direction.
fn phasor_export_frequency(prng: ptr<function, Prng>, n: vec2<i32>, r: vec2<f32>) -> vec3<f32> {
    var fr = phasor_export_fr;
    if (phasor_export_varying_f == 1u) {
        fr = clamp(phasor_export_frequency_field(n, r), 0.0f, 0.5f) * phasor_export_side;
    }
    var u = vec3<f32>(1.0f, 0.0f, 0.0f);
    switch phasor_export_mode {
        case 0u: {
            if (phasor_export_varying_f == 0u) {
                return phasor_export_f_a;
            }
            u = phasor_export_u_a;
        }
        case 1u: {
            let first = prng_next_f32(prng) < 0.5f;
            if (phasor_export_varying_f == 0u) {
                return select(phasor_export_f_b, phasor_export_f_a, first);
            }
            u = select(phasor_export_u_b, phasor_export_u_a, first);
        }
        case 3u: {
            u = phasor_export_planar(fract(phasor_export_angle(n, r) * PHASOR_EXPORT_INV_TAU));
        }
        case 4u: {
            u = phasor_export_gradient(n, r);
        }
        case 5u: {
            u = phasor_export_coherent(n, r);
        }
        default: {
            if (phasor_three_d() == 1u) {
                let z = 2.0f * prng_next_f32(prng) - 1.0f;
                let s = sqrt(max(1.0f - z * z, 0.0f));
                let t = prng_next_f32(prng);
                return vec3<f32>(fr * (s * cos_turns(t)), fr * (s * sin_turns(t)), fr * z);
            }
            let t = prng_next_f32(prng);
            return vec3<f32>(fr * cos_turns(t), fr * sin_turns(t), fr * 0.0f);
        }
    }
    return vec3<f32>(fr * u.x, fr * u.y, fr * u.z);
}

/// 1/2π rounded to f32: a varying angle's turns (the CPU divides by 2π in f64).
const PHASOR_EXPORT_INV_TAU: f32 = 0.15915494f;

/// The noise at the position `cell + offset` (pixels): the CPU's sum over the cells' impulses
/// in its order (layers, rows, columns ascending; impulses in draw order), then its output.
fn phasor_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    // Per-pixel splits that the fields and directions read per impulse.
    phasor_export_locate_fields(at.n);
    if (phasor_export_mode == 5u) {
        phasor_export_dir_x = export_split(at.n.x, 1u);
        phasor_export_dir_y = export_split(at.n.y, 1u);
    }
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
    let layers = select(1, 3, phasor_three_d() == 1u);
    for (var l = 0; l < layers; l++) {
        let sz = select(0, l - 1, phasor_three_d() == 1u);
        let dz = params.z_offset - f32(sz);
        let gz = cell_gap2(params.z_offset, sz);
        for (var sy = -1; sy <= 1; sy++) {
            let dy = uy - f32(sy);
            let gyz = cell_gap2(uy, sy) + gz;
            for (var sx = -1; sx <= 1; sx++) {
                let dxs = ux - f32(sx);
                // A cell out of reach (`PHASOR_CELL_REACH2`): its draws are its own PRNG's,
                // so skipping them changes no other cell's.
                if (cell_gap2(ux, sx) + gyz >= PHASOR_CELL_REACH2) {
                    continue;
                }
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
                    if (phasor_three_d() == 1u) {
                        oz = prng_next_f32(&prng);
                    }
                    // The impulse relative to the integer position `at.n`, pixels.
                    let r = vec2<f32>(
                        (f32(sx) + ox) * phasor_export_side - cx.rem,
                        (f32(sy) + oy) * phasor_export_side - cy.rem,
                    );
                    var sharp = 1.0f;
                    if (phasor_export_graded == 1u) {
                        // Thinning: kept with probability (b/b_max)², a discarded impulse draws
                        // nothing more.
                        let b = clamp(
                            phasor_export_bandwidth(at.n, r),
                            phasor_export_b_min,
                            phasor_export_b_max,
                        );
                        let q = b / phasor_export_b_max;
                        if (!(prng_next_f32(&prng) < q * q)) {
                            continue;
                        }
                        let s = b / phasor_export_b_min;
                        sharp = s * s;
                    }
                    let d = vec3<f32>(dxs - ox, dy - oy, dz - oz);
                    let d2 = (d.x * d.x + d.y * d.y + d.z * d.z) * sharp;
                    // The coherent direction, which draws from its own process's PRNGs (ψ is
                    // the next draw either way), only for an impulse in reach: it sums that
                    // process's kernels in loops over its cells, which no compiler moves into
                    // the branch below (pure arithmetic it does move: a gradient's direction
                    // taken here ran 1.5% slower on lavapipe).
                    var f = vec3<f32>(0.0f);
                    if (phasor_export_mode != 5u || d2 < 1.0f) {
                        f = phasor_export_frequency(&prng, at.n, r);
                    }
                    let psi = prng_next_f32(&prng);
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
    switch phasor_output_kind() {
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
            var w = params.weight;
            if (phasor_export_per_pixel == 1u) {
                // The CPU's `field.at(p).clamp(0, 1) as f32` at the pixel.
                duty_a = clamp(phasor_export_duty_a(at.n, at.u), 0.0f, 1.0f);
                duty_b = clamp(phasor_export_duty_b(at.n, at.u), 0.0f, 1.0f);
                w = clamp(phasor_export_weight(at.n, at.u), 0.0f, 1.0f);
            }
            v = leaf(phasor_a_kind(), params.a_start, params.a_len, duty_a, re, im, 0.0f);
            if (phasor_blend() == 1u) {
                let b = leaf(phasor_b_kind(), params.b_start, params.b_len, duty_b, re, im, 0.0f);
                v = (1.0f - w) * v + w * b;
            }
        }
    }
    return params.mean + params.amplitude * v;
}
