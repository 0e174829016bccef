// compose.wgsl — passes that compose other kernels' values on the device, between their
// dispatches in one submission, in the CPU's f32 operations (so the composition adds no
// difference of its own).
//
// `warp_displace`: a domain warp's displacement field from its x and y models' values,
// D(v) = clamp(strength·v, −MAX_WARP, MAX_WARP), 0 for NaN (spectex_model::Warp::displacement),
// interleaved (dx, dy) per pixel: the displacement `common.wgsl`'s group 1 gives the base's
// dispatch.

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
