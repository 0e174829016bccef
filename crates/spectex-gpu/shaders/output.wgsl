// Output formats of a render: a tile's f32 values (channels interleaved, row-major) packed into
// 32-bit words on the device, so a render for an 8-bit PNG reads back a quarter of the bytes.
// Values go into each word from its lowest byte up, so the words' little-endian bytes are the
// values in order. The unorm formats take the CPU's quantisation, round(clamp(v, 0, 1) · max)
// with halves rounded up (the CPU does it in f64 from the same f32 value, so a value within an
// f32 rounding of a half level may land one level apart). One invocation per word; a 2D grid of
// workgroups, `words_per_row` words per grid row, since one dimension of a dispatch is limited.

struct PackParams {
    // Values in the tile.
    count: u32,
    // Words per row of the dispatch grid (workgroups along x times 64).
    words_per_row: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> pack: PackParams;
@group(0) @binding(1) var<storage, read> values: array<f32>;
@group(0) @binding(2) var<storage, read_write> words: array<u32>;

// Value `i` of the tile, 0 past its end (the last word's unused lanes).
fn value_at(i: u32) -> f32 {
    if (i < pack.count) {
        return values[i];
    }
    return 0.0;
}

fn quantise(v: f32, levels: f32) -> u32 {
    return u32(floor(clamp(v, 0.0, 1.0) * levels + 0.5));
}

fn word_index(gid: vec3<u32>) -> u32 {
    return gid.y * pack.words_per_row + gid.x;
}

@compute @workgroup_size(64, 1, 1)
fn pack_unorm8(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = word_index(gid);
    let i = 4u * w;
    if (i >= pack.count) {
        return;
    }
    words[w] = quantise(value_at(i), 255.0)
        | (quantise(value_at(i + 1u), 255.0) << 8u)
        | (quantise(value_at(i + 2u), 255.0) << 16u)
        | (quantise(value_at(i + 3u), 255.0) << 24u);
}

@compute @workgroup_size(64, 1, 1)
fn pack_unorm16(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = word_index(gid);
    let i = 2u * w;
    if (i >= pack.count) {
        return;
    }
    words[w] = quantise(value_at(i), 65535.0) | (quantise(value_at(i + 1u), 65535.0) << 16u);
}

// IEEE binary16 bits of `v` (|v| ≤ 65504), rounded to nearest, ties to even, in integer
// arithmetic: WGSL's pack2x16float needs a shader capability not every device has.
fn half_bits(v: f32) -> u32 {
    let x = bitcast<u32>(v);
    let sign = (x >> 16u) & 0x8000u;
    let magnitude = x & 0x7fffffffu;
    if (magnitude >= 0x38800000u) {
        // A normal half: rebias the exponent by 127 - 15 = 112, then round away 13 bits (a
        // carry into the exponent is the correct rounding up to the next binade).
        let rebiased = magnitude - 0x38000000u;
        return sign | ((rebiased + 0x0fffu + ((rebiased >> 13u) & 1u)) >> 13u);
    }
    // Below 2^-14: a multiple of 2^-24, exact after scaling by a power of two; round() takes
    // ties to even. (2^-14 itself may come out of it: 1024 is its normal encoding.)
    return sign | u32(round(abs(v) * 16777216.0));
}

// IEEE binary16, round to nearest even; magnitudes past 65504 (the largest half) are clamped to
// it first.
@compute @workgroup_size(64, 1, 1)
fn pack_f16(@builtin(global_invocation_id) gid: vec3<u32>) {
    let w = word_index(gid);
    let i = 2u * w;
    if (i >= pack.count) {
        return;
    }
    let lo = half_bits(clamp(value_at(i), -65504.0, 65504.0));
    let hi = half_bits(clamp(value_at(i + 1u), -65504.0, 65504.0));
    words[w] = lo | (hi << 16u);
}
