// Output formats of a render: a tile's f32 values (channels interleaved, row-major) packed into
// 32-bit words on the device, so a render for an 8-bit PNG reads back a quarter of the bytes.
// Values go into each word from its lowest byte up, so the words' little-endian bytes are the
// values in order. The unorm formats take the CPU's quantisation, round(clamp(v, 0, 1) · max)
// with halves rounded up, exactly: the CPU computes it in f64, where v · max is exact, and so
// does `quantise` here, in integers. Each packing also counts the values its format clamps
// (`clipped`: outside [0, 1] or NaN for unorm, magnitudes past 65504 or NaN for binary16), the
// count the command line reports for a PNG. One invocation per word; a 2D grid of workgroups,
// `words_per_row` words per grid row, since one dimension of a dispatch is limited.

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
// Values the packing clamped, added to by each workgroup (cleared by the host per tile).
@group(0) @binding(3) var<storage, read_write> clipped: atomic<u32>;

// A workgroup's clamped values (workgroup memory starts zeroed).
var<workgroup> group_clipped: atomic<u32>;

// Value `i` of the tile, 0 past its end (the last word's unused lanes).
fn value_at(i: u32) -> f32 {
    if (i < pack.count) {
        return values[i];
    }
    return 0.0;
}

// round(clamp(v, 0, 1) · L) with halves rounded up, L = 2^bits − 1 (bits 8 or 16), exactly as
// the CPU's f64 `(clamp(v, 0, 1) · L + 0.5) as u` computes it (f32 arithmetic would round v · L
// first and could land a level apart next to a half level). NaN gives 0, as on the CPU.
// For v = m · 2^−s (m the 24-bit significand) the level is floor((m·L + 2^(s−1)) / 2^s); with
// m·L = 2^bits·m − m and A = m + 2^(s−1−bits), that is floor((A − m/2^bits) / 2^(s−bits)): the
// quotient q of A by 2^(s−bits), less one where its remainder is below m/2^bits. Below
// 2^(−bits−1) the level is 0 (v·L < ½), so 24 ≤ s ≤ 24 + bits: every shift is in 7..=24 and
// every term below 2^25.
fn quantise(v: f32, bits: u32) -> u32 {
    let levels = (1u << bits) - 1u;
    if (!(v >= ldexp(1.0f, -i32(bits) - 1))) {
        return 0u;
    }
    if (v >= 1.0f) {
        return levels;
    }
    let b = bitcast<u32>(v);
    let m = (b & 0x7fffffu) | 0x800000u;
    let s = 150u - (b >> 23u);
    let a = m + (1u << (s - 1u - bits));
    let q = a >> (s - bits);
    let r = a & ((1u << (s - bits)) - 1u);
    return q - select(0u, 1u, r < ((m + levels) >> bits));
}

// 1 when a unorm packing clamps `v` (outside [0, 1], or NaN), else 0.
fn clamped_unorm(v: f32) -> u32 {
    return select(1u, 0u, v >= 0.0f && v <= 1.0f);
}

// 1 when binary16 packing clamps `v` (a magnitude past 65504, or NaN), else 0.
fn clamped_half(v: f32) -> u32 {
    return select(1u, 0u, abs(v) <= 65504.0f);
}

fn word_index(gid: vec3<u32>) -> u32 {
    return gid.y * pack.words_per_row + gid.x;
}

// Adds an invocation's clamped values to the tile's count: once per workgroup to the buffer.
// Called in uniform control flow (every invocation of the workgroup reaches the barrier).
fn count_clipped(n: u32, local: u32) {
    if (n > 0u) {
        atomicAdd(&group_clipped, n);
    }
    workgroupBarrier();
    if (local == 0u) {
        let total = atomicLoad(&group_clipped);
        if (total > 0u) {
            atomicAdd(&clipped, total);
        }
    }
}

@compute @workgroup_size(64, 1, 1)
fn pack_unorm8(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let w = word_index(gid);
    let i = 4u * w;
    var n = 0u;
    if (i < pack.count) {
        var word = 0u;
        for (var k = 0u; k < 4u; k++) {
            let v = value_at(i + k);
            word |= quantise(v, 8u) << (8u * k);
            n += clamped_unorm(v);
        }
        words[w] = word;
    }
    count_clipped(n, local);
}

@compute @workgroup_size(64, 1, 1)
fn pack_unorm16(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let w = word_index(gid);
    let i = 2u * w;
    var n = 0u;
    if (i < pack.count) {
        let lo = value_at(i);
        let hi = value_at(i + 1u);
        words[w] = quantise(lo, 16u) | (quantise(hi, 16u) << 16u);
        n = clamped_unorm(lo) + clamped_unorm(hi);
    }
    count_clipped(n, local);
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
fn pack_f16(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let w = word_index(gid);
    let i = 2u * w;
    var n = 0u;
    if (i < pack.count) {
        let lo = value_at(i);
        let hi = value_at(i + 1u);
        words[w] = half_bits(clamp(lo, -65504.0, 65504.0))
            | (half_bits(clamp(hi, -65504.0, 65504.0)) << 16u);
        n = clamped_half(lo) + clamped_half(hi);
    }
    count_clipped(n, local);
}
