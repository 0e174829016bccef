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
@group(0) @binding(1) var<storage, read> segments: array<f32>;
/// Per column: (frac(A00·x), frac(A10·x)).
@group(0) @binding(2) var<storage, read> columns: array<vec2<f32>>;
/// Per row: (frac(A01·y + c0), frac(A11·y + c1)).
@group(0) @binding(3) var<storage, read> rows: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read_write> output: array<f32>;

const SEGMENT_FLOATS: u32 = 7u;

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

/// The pattern at the lattice fractions `(s, t)` in `[0, 1]`: the CPU's segment loop over the
/// first `count` segments (IslamicGeometry::nearest) and output formula (output_value).
fn islamic_at(s: f32, t: f32, count: u32) -> f32 {
    let qx = s * params.e1x + t * params.e2x;
    let qy = s * params.e1y + t * params.e2y;
    var best = 3.4028235e38f;
    var odd = false;
    for (var k = 0u; k < count; k++) {
        let base = k * SEGMENT_FLOATS;
        let ax = segments[base];
        let ay = segments[base + 1u];
        let by = segments[base + 3u];
        let dx = segments[base + 4u];
        let dy = segments[base + 5u];
        let inv = segments[base + 6u];
        let px = qx - ax;
        let py = qy - ay;
        let h = clamp((px * dx + py * dy) * inv, 0.0f, 1.0f);
        let ex = px - dx * h;
        let ey = py - dy * h;
        let d2 = ex * ex + ey * ey;
        if (d2 < best) {
            best = d2;
        }
        let up = ay <= qy;
        if (up != (by <= qy)) {
            let cross = dx * py - dy * px;
            if ((up && cross > 0.0f) || (!up && cross < 0.0f)) {
                odd = !odd;
            }
        }
    }
    let d = sqrt(best) * params.cell;
    var value = 0.0f;
    switch params.output {
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
