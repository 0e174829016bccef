// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a combination (spectex_model::combine), after
// its operands: each operand is exported as its own model (its own prefix), and the exporter
// writes `combine_sample_cell`, which evaluates them at the position and applies the
// operation per channel with the functions below: WGSL twins of `CombineOp::apply`. It declares
// `combine_knots` and `combine_table` (a histogram's table; one unused 0 otherwise) and
// `combine_stops`, `combine_stops_at`, `combine_stops_colour` (a ramp's stops, sorted; one
// unused stop otherwise).
//
// The functions compute in `arith_*` (add, sub, mul, div, clamp, is_nan, sin_turns), which
// whoever composes this file defines: the export with the shader's own operators
// (`export::emitter::SHADER_ARITHMETIC`, as cheap as WGSL makes it), the compute path's
// combination pass with `exact.wgsl`'s integer IEEE arithmetic (the CPU's roundings).

/// `CombineOp::Mix`: `a + (b − a)·t`.
fn combine_mix(a: f32, b: f32, t: f32) -> f32 {
    return arith_add(a, arith_mul(arith_sub(b, a), t));
}

/// `CombineOp::SinFold`: `sin_turns(gain·v)`.
fn combine_sin_fold(gain: f32, v: f32) -> f32 {
    return arith_sin_turns(arith_mul(gain, v));
}

/// spectex_model::combine::smoothstep: `s·s·(3 − 2s)`, a threshold for equal edges.
fn combine_smoothstep(e0: f32, e1: f32, v: f32) -> f32 {
    if (e0 >= e1) {
        return select(0.0f, 1.0f, v >= e0);
    }
    let s = arith_clamp(arith_div(arith_sub(v, e0), arith_sub(e1, e0)), 0.0f, 1.0f);
    return arith_mul(arith_mul(s, s), arith_sub(3.0f, arith_mul(2.0f, s)));
}

/// `CombineOp::AbsFold`: `v − offset`, then `folds` times `|v − step|`.
fn combine_abs_fold(value: f32, offset: f32, step: f32, folds: u32) -> f32 {
    var v = arith_sub(value, offset);
    for (var k = 0u; k < folds; k++) {
        v = abs(arith_sub(v, step));
    }
    return v;
}

/// spectex_model::combine::lookup: the table over `[d0, d1]`, linear between knots, clamped
/// (NaN gives the first entry).
fn combine_lookup(d0: f32, d1: f32, v: f32) -> f32 {
    let last = f32(combine_knots - 1u);
    var x = arith_clamp(arith_mul(arith_div(arith_sub(v, d0), arith_sub(d1, d0)), last), 0.0f, last);
    if (arith_is_nan(x)) {
        x = 0.0f;
    }
    let k = min(u32(floor(x)), combine_knots - 2u);
    let f = arith_sub(x, f32(k));
    let t0 = combine_table[k];
    return arith_add(t0, arith_mul(arith_sub(combine_table[k + 1u], t0), f));
}

/// spectex_model::combine::ramp: channel `c` at `v`, linear between the stops around it,
/// clamped at the ends.
fn combine_ramp(v: f32, c: u32) -> f32 {
    if (arith_is_nan(v) || v <= combine_stops_at[0]) {
        return combine_stops_colour[0][c];
    }
    for (var i = 0u; i + 1u < combine_stops; i++) {
        let a = combine_stops_at[i];
        let b = combine_stops_at[i + 1u];
        if (v < b) {
            let f = arith_div(arith_sub(v, a), arith_sub(b, a));
            let c0 = combine_stops_colour[i][c];
            return arith_add(c0, arith_mul(arith_sub(combine_stops_colour[i + 1u][c], c0), f));
        }
    }
    return combine_stops_colour[combine_stops - 1u][c];
}
