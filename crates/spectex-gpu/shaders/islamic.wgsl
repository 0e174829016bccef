// islamic.wgsl — Islamic star patterns (survey §2.7), the GPU twin of
// crates/spectex-cpu/src/islamic.rs; the definition is the module doc of
// crates/spectex-model/src/islamic.rs. Composed after common.wgsl.
//
// The host uploads the model's f32 segment table once, and per tile each column's and row's
// lattice fractions (split in f64, spectex_model::islamic::LatticeMap). Per pixel the shader
// sums them, reduces to [0, 1), maps to the fundamental parallelogram and runs the CPU's
// segment loop (IslamicGeometry::nearest) and output formula (output_value) with the CPU's
// expressions in the CPU's order. A warp's displacement (pixels) moves the fractions by
// A·d in f32 before the reduction, so the arithmetic stays on numbers below 2.

/// Per-dispatch values.
struct IslamicParams {
    width: u32,
    height: u32,
    /// Segments in the table.
    segments: u32,
    /// 0: band, 1: distance, 2: filled.
    output: u32,
    /// C, pixels.
    cell: f32,
    /// w, pixels.
    line_width: f32,
    /// f, pixels.
    footprint: f32,
    /// f32(1 / f).
    inv_footprint: f32,
    /// The lattice basis e1, e2.
    e1x: f32,
    e1y: f32,
    e2x: f32,
    e2y: f32,
    /// A (f32), for a warp's displacement.
    a00: f32,
    a01: f32,
    a10: f32,
    a11: f32,
}

@group(0) @binding(0) var<uniform> params: IslamicParams;
/// Seven floats per segment: a.x, a.y, b.x, b.y, d.x, d.y, 1/|d|².
/// Two vec4 per segment, (a_x, a_y, b_x, b_y) and (d_x, d_y, ι, 0), read at the loop's counter
/// by every invocation alike: a uniform (lavapipe read the storage table lane by lane, at a
/// third of this speed). 2048 segments at most, 64 KiB (`UNIFORM_SEGMENTS` of islamic.rs).
@group(0) @binding(1) var<uniform> segments: array<vec4<f32>, 4096>;
/// Per column: (frac(A00·x), frac(A10·x)).
@group(0) @binding(2) var<storage, read> columns: array<vec2<f32>>;
/// Per row: (frac(A01·y + c0), frac(A11·y + c1)).
@group(0) @binding(3) var<storage, read> rows: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes").
override ISLAMIC_OUTPUT: u32 = 0xffffffffu;

fn islamic_output() -> u32 {
    return shape_or(ISLAMIC_OUTPUT, params.output);
}

@compute @workgroup_size(8, 8, 1)
fn islamic_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let column = columns[gid.x];
    let row = rows[gid.y];
    var s = column.x + row.x;
    var t = column.y + row.y;
    if (warp_params.enabled == 1u) {
        let d = warp_displacement[index];
        s = s + (params.a00 * d.x + params.a01 * d.y);
        t = t + (params.a10 * d.x + params.a11 * d.y);
    }
    s = s - floor(s);
    t = t - floor(t);
    output[index] = islamic_at(s, t, params.segments);
}

/// The point of the lattice fractions `(s, t)` in the pattern's unit cell.
fn islamic_point(s: f32, t: f32) -> vec2<f32> {
    return vec2<f32>(s * params.e1x + t * params.e2x, s * params.e1y + t * params.e2y);
}

/// One step of the CPU's segment loop (IslamicGeometry::nearest) at the point `q`, for the
/// segment from `a` along `d` (`inv` = 1/|d|², `by` the y of its end): the squared distance
/// kept in `best` where smaller, and the parity of the crossings of a ray from `q` towards +x
/// flipped in `odd`.
fn islamic_segment(
    q: vec2<f32>,
    a: vec2<f32>,
    by: f32,
    d: vec2<f32>,
    inv: f32,
    best: ptr<function, f32>,
    odd: ptr<function, bool>,
) {
    let px = q.x - a.x;
    let py = q.y - a.y;
    let h = clamp((px * d.x + py * d.y) * inv, 0.0f, 1.0f);
    let ex = px - d.x * h;
    let ey = py - d.y * h;
    let d2 = ex * ex + ey * ey;
    if (d2 < *best) {
        *best = d2;
    }
    let up = a.y <= q.y;
    if (up != (by <= q.y)) {
        let cross = d.x * py - d.y * px;
        if ((up && cross > 0.0f) || (!up && cross < 0.0f)) {
            *odd = !*odd;
        }
    }
}

/// The CPU's output formula (output_value) of the nearest squared distance `best` (in cell
/// units) and the crossings' parity `odd`.
fn islamic_value(best: f32, odd: bool) -> f32 {
    let d = sqrt(best) * params.cell;
    var value = 0.0f;
    switch islamic_output() {
        case 0u: {
            let half = 0.5f * params.line_width;
            let hi = min(d + 0.5f * params.footprint, half);
            let lo = max(d - 0.5f * params.footprint, -half);
            value = max(hi - lo, 0.0f) * params.inv_footprint;
        }
        case 1u: {
            value = select(d, -d, odd);
        }
        default: {
            let sd = select(d, -d, odd);
            value = clamp(0.5f - sd * params.inv_footprint, 0.0f, 1.0f);
        }
    }
    return value;
}

/// The pattern at the lattice fractions `(s, t)` in `[0, 1]`: the CPU's segment loop over the
/// first `count` segments of the table and its output formula.
fn islamic_at(s: f32, t: f32, count: u32) -> f32 {
    let q = islamic_point(s, t);
    var best = 3.4028235e38f;
    var odd = false;
    for (var k = 0u; k < count; k++) {
        let ab = segments[2u * k];
        let d = segments[2u * k + 1u];
        islamic_segment(q, ab.xy, ab.w, d.xy, d.z, &best, &odd);
    }
    return islamic_value(best, odd);
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of an Islamic star pattern (after the kernel above
// and export/split.wgsl; no lattice). The compute path's host splits each column and row in
// f64 into the lattice fractions frac(A·p + c) (spectex_model::islamic::LatticeMap). Here the
// position is an integer part n and a fraction u in [0, 1), and the fractions of A·n + c are
// summed in 32-bit fixed point (units of 2⁻³²), wrapping, which is arithmetic modulo 1: the
// exporter writes, per coefficient A_rc and bit k of n's two's complement (weight w_k = 2^k,
// w_31 = −2^31), `islamic_export_fixed[32·(2c + r) + k]` = frac(A_rc·w_k)·2³² rounded, and
// `islamic_export_c` the fractions of c the same way. The fraction A·u is added in f32 and
// the sum reduced to [0, 1) as the compute shader reduces it, then `islamic_at` runs the
// CPU's segment loop and output formula.
//
// Precision: each of the at most 65 fixed-point terms is within 2⁻³³ of its exact fraction
// (the sum within 2⁻²⁶, whatever |n|), its conversion to f32 and the f32 terms A·u (A rounded
// to f32, a product, a sum: 2·|A|·2⁻²⁴ per term) and the sum add a few units of 2⁻²⁴: the
// fractions s, t lie within (6 + 6·|A|)·2⁻²⁴ of the exact ones, as the CPU's lie within
// 2·2⁻²⁴, at (10⁷, 10⁷) as at the origin.

/// `Σ` over the set bits of `n` of the fixed-point table `table` (wrapping: modulo 1).
fn islamic_export_fixed_sum(n: i32, table: u32) -> u32 {
    let bits = bitcast<u32>(n);
    var acc = 0u;
    for (var k = 0u; k < 32u; k++) {
        if (((bits >> k) & 1u) == 1u) {
            acc += islamic_export_fixed[32u * table + k];
        }
    }
    return acc;
}

/// The pattern at the lattice fractions `(s, t)`: `islamic_at` with its loop written out by
/// the exporter, `ISLAMIC_EXPORT_SEGMENTS` = one `islamic_segment` call per segment with the
/// segment's values as literals, which a driver folds into the arithmetic. A loop would read
/// the segment table from per-invocation memory at its counter (about 5 calibration cosines a
/// segment on lavapipe, against 1 written out), and lavapipe compiled the 3024-float private
/// table of islamic-31212-filled for minutes where a loop could be unrolled.
fn islamic_export_at(s: f32, t: f32) -> f32 {
    let q = islamic_point(s, t);
    var best = 3.4028235e38f;
    var odd = false;
    ISLAMIC_EXPORT_SEGMENTS
    return islamic_value(best, odd);
}

/// The pattern at the position `cell + offset` (pixels).
fn islamic_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let sf = islamic_export_fixed_sum(at.n.x, 0u) + islamic_export_fixed_sum(at.n.y, 1u)
        + islamic_export_c.x;
    let tf = islamic_export_fixed_sum(at.n.x, 2u) + islamic_export_fixed_sum(at.n.y, 3u)
        + islamic_export_c.y;
    var s = f32(sf) * 0x1p-32f + (params.a00 * at.u.x + params.a01 * at.u.y);
    var t = f32(tf) * 0x1p-32f + (params.a10 * at.u.x + params.a11 * at.u.y);
    s = s - floor(s);
    t = t - floor(t);
    return islamic_export_at(s, t);
}
