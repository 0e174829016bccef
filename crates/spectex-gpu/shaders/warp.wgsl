// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a domain warp `base(p + D(x(p), y(p)))`
// (spectex_model::warp), after its three models. The exporter replaces WARP_X, WARP_Y and
// WARP_BASE with the displacement models' and the base's `…_sample_cell` functions, WARP_VALUE
// with the base's value type, and declares `warp_strength` (pixels per unit of x and y).
//
// Positions: the CPU adds the f32 displacement to the f64 position and the base locates the
// sum. Here the position is an integer part and a fraction in [0, 1): the displacement's
// whole pixels (|D| ≤ 2¹⁶, exact in f32 and i32) go to the integer part and its fraction to
// the offset, a sum below 2 with one rounding, so a warp at (10⁷, 10⁷) keeps its precision.

/// `D(v) = clamp(strength·v, −2¹⁶, 2¹⁶)`, 0 for NaN (spectex_model::Warp::displacement; a
/// shader compiler may assume no NaN and drop that case).
fn warp_displacement_of(v: f32) -> f32 {
    let d = warp_strength * v;
    if (!(d == d)) {
        return 0.0f;
    }
    return clamp(d, -65536.0f, 65536.0f);
}

/// The warp at the position `cell + offset` (pixels).
fn warp_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> WARP_VALUE {
    let whole = floor(offset);
    let n = vec2<i32>(
        bitcast<i32>(bitcast<u32>(cell.x) + bitcast<u32>(i32(whole.x))),
        bitcast<i32>(bitcast<u32>(cell.y) + bitcast<u32>(i32(whole.y))),
    );
    let u = offset - whole;
    let d = vec2<f32>(warp_displacement_of(WARP_X(n, u)), warp_displacement_of(WARP_Y(n, u)));
    let shift = floor(d);
    let moved = vec2<i32>(
        bitcast<i32>(bitcast<u32>(n.x) + bitcast<u32>(i32(shift.x))),
        bitcast<i32>(bitcast<u32>(n.y) + bitcast<u32>(i32(shift.y))),
    );
    return WARP_BASE(moved, u + (d - shift));
}
