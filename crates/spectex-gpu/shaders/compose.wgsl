// compose.wgsl — passes that compose other kernels' values on the device, between their
// dispatches in one submission, in the CPU's f32 operations (so the composition adds no
// difference of its own).
//
// `warp_displace`: a domain warp's displacement field from its x and y models' values,
// D(v) = clamp(strength·v, −MAX_WARP, MAX_WARP), 0 for NaN (spectex_model::Warp::displacement),
// interleaved (dx, dy) per pixel: the displacement `common.wgsl`'s group 1 gives the base's
// dispatch.
//
// `warp_displace_range`: the same, and the exact range of the displacements in `range`, for a
// base whose host part reads it (a phasor's cell box, a Voronoi search): the host reads back
// these 16 bytes instead of the field. Each value is kept as an order-preserving u32
// (`ordered`), the maxima of `ordered(d)` and of `~ordered(d)` (the minimum's), so a
// zero-initialised buffer starts the four maxima; atomic maxima are exact and their order does
// not matter.

struct ComposeParams {
    /// Pixels of the tile.
    count: u32,
    /// Pixels per row of the dispatch grid (workgroups along x times 64), since one dimension
    /// of a dispatch is limited.
    per_row: u32,
    /// The warp's strength (pixels per unit of x and y).
    strength: f32,
    /// spectex_model::warp::MAX_WARP.
    max_warp: f32,
}

@group(0) @binding(0) var<uniform> compose: ComposeParams;
@group(0) @binding(1) var<storage, read> x_values: array<f32>;
@group(0) @binding(2) var<storage, read> y_values: array<f32>;
@group(0) @binding(3) var<storage, read_write> displacement: array<vec2<f32>>;

/// spectex_model::Warp::displacement. NaN is told by a comparison with itself, which a shader
/// compiler that assumes no NaN may fold: the warp's inputs are finite model values, so that
/// case is a guard.
fn warp_displacement_of(v: f32) -> f32 {
    let d = compose.strength * v;
    if (!(d == d)) {
        return 0.0f;
    }
    return clamp(d, -compose.max_warp, compose.max_warp);
}

@compute @workgroup_size(64, 1, 1)
fn warp_displace(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.y * compose.per_row + gid.x;
    if (k >= compose.count) {
        return;
    }
    displacement[k] = vec2<f32>(warp_displacement_of(x_values[k]), warp_displacement_of(y_values[k]));
}

/// Binding 4 of `warp_displace_range`: the maxima of `ordered(dx)`, `~ordered(dx)`,
/// `ordered(dy)` and `~ordered(dy)`, zero before the pass.
@group(0) @binding(4) var<storage, read_write> range: array<atomic<u32>, 4>;

/// The workgroup's maxima, reduced before one thread adds them to `range`.
var<workgroup> group_range: array<atomic<u32>, 4>;

/// `v`'s bits mapped so that unsigned order is numeric order (−0 just below +0): a negative
/// value's bits flipped, a positive one's sign bit set.
fn ordered(v: f32) -> u32 {
    let bits = bitcast<u32>(v);
    if ((bits & 0x80000000u) != 0u) {
        return ~bits;
    }
    return bits | 0x80000000u;
}

@compute @workgroup_size(64, 1, 1)
fn warp_displace_range(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let k = gid.y * compose.per_row + gid.x;
    // No early return: every invocation reaches the barriers.
    if (k < compose.count) {
        let d = vec2<f32>(warp_displacement_of(x_values[k]), warp_displacement_of(y_values[k]));
        displacement[k] = d;
        let x = ordered(d.x);
        let y = ordered(d.y);
        atomicMax(&group_range[0], x);
        atomicMax(&group_range[1], ~x);
        atomicMax(&group_range[2], y);
        atomicMax(&group_range[3], ~y);
    }
    workgroupBarrier();
    if (lane < 4u) {
        atomicMax(&range[lane], atomicLoad(&group_range[lane]));
    }
}
