// probe.wgsl — dumps the functions of common.wgsl for given inputs, so a test can compare them
// with `spectex_model::random` and the CPU's scalar functions on the host. Composed after
// common.wgsl; not used by rendering.

/// Number of u32 words `probe_integers` writes per input record.
const INTEGER_OUTPUTS: u32 = 16u;
/// Number of f32 values `probe_floats` writes per input.
const FLOAT_OUTPUTS: u32 = 6u;

/// Integer probe: 4 words (a, b, c, d) per record.
@group(0) @binding(0) var<storage, read> integer_inputs: array<vec4<u32>>;
/// INTEGER_OUTPUTS words per record: hash(a), permute(a), lcg_step(a), layer_key(c, d),
/// row_key(i32(b), a), cell_hash_in_row(i32(a), b), cell_hash(i32(a), i32(b), c, d), then the
/// PRNG seeded with that cell hash: 4 × next_u32, 4 × next_f32 (bits), and unit_f32(a) (bits).
@group(0) @binding(1) var<storage, read_write> integer_outputs: array<u32>;
/// Float probe: one f32 per input, used as t (turns), r² and z alike.
@group(0) @binding(2) var<storage, read> float_inputs: array<f32>;
/// FLOAT_OUTPUTS values per input: fract_turns(t), the CPU's magic-number form of it (to see
/// whether this compiler keeps it), cos_turns(t), kaiser_bessel_r2(t), exp_poly(t), round(t).
@group(0) @binding(3) var<storage, read_write> float_outputs: array<f32>;

/// The CPU's rounding by 1.5·2²³, written here only to observe what the compiler does with it.
fn fract_turns_magic(t: f32) -> f32 {
    return t - ((t + 12582912.0f) - 12582912.0f);
}

@compute @workgroup_size(64, 1, 1)
fn probe_integers(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= arrayLength(&integer_inputs)) {
        return;
    }
    let v = integer_inputs[i];
    let o = i * INTEGER_OUTPUTS;
    integer_outputs[o + 0u] = hash(v.x);
    integer_outputs[o + 1u] = permute(v.x);
    integer_outputs[o + 2u] = lcg_step(v.x);
    integer_outputs[o + 3u] = layer_key(v.z, v.w);
    integer_outputs[o + 4u] = row_key(bitcast<i32>(v.y), v.x);
    integer_outputs[o + 5u] = cell_hash_in_row(bitcast<i32>(v.x), v.y);
    let cell = cell_hash(bitcast<i32>(v.x), bitcast<i32>(v.y), v.z, v.w);
    integer_outputs[o + 6u] = cell;
    var prng = Prng(cell);
    for (var k = 0u; k < 4u; k++) {
        integer_outputs[o + 7u + k] = prng_next_u32(&prng);
    }
    for (var k = 0u; k < 4u; k++) {
        integer_outputs[o + 11u + k] = bitcast<u32>(prng_next_f32(&prng));
    }
    integer_outputs[o + 15u] = bitcast<u32>(unit_f32(v.x));
}

@compute @workgroup_size(64, 1, 1)
fn probe_floats(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= arrayLength(&float_inputs)) {
        return;
    }
    let t = float_inputs[i];
    let o = i * FLOAT_OUTPUTS;
    float_outputs[o + 0u] = fract_turns(t);
    float_outputs[o + 1u] = fract_turns_magic(t);
    float_outputs[o + 2u] = cos_turns(t);
    float_outputs[o + 3u] = kaiser_bessel_r2(t);
    float_outputs[o + 4u] = exp_poly(t);
    float_outputs[o + 5u] = round(t);
}
