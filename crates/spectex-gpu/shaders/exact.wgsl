// exact.wgsl — IEEE 754 binary32 addition, subtraction, multiplication and division in integer
// arithmetic, rounded to nearest, ties to even, with subnormals: the CPU's f32 operations bit
// for bit on any device. A shader's own float operations are not that: WGSL lets a compiler
// fuse a multiply and an add into one rounding (lavapipe does), divides within 2.5 ulp and may
// flush subnormals. The combination pass (`combine.rs`) applies the operations that multiply
// and add or divide (mix, smoothstep, a table lookup, a ramp, a sine), and the others, with
// these: the end of this file defines the combination glue's `arith_*` with them, so the
// device composes exactly what `CombineOp::apply` computes. A port of Berkeley SoftFloat 3e's
// `f32_add`, `f32_sub`, `f32_mul` and `f32_div` (round-near-even only; a NaN result is the
// quiet NaN 0x7FC00000). Composed after common.wgsl; a library, no entry point.

/// The quiet NaN every invalid operation returns.
const EXACT_NAN: u32 = 0x7fc00000u;

fn exact_is_nan(a: u32) -> bool {
    return (a & 0x7fffffffu) > 0x7f800000u;
}

fn exact_is_inf(a: u32) -> bool {
    return (a & 0x7fffffffu) == 0x7f800000u;
}

fn exact_is_zero(a: u32) -> bool {
    return (a & 0x7fffffffu) == 0u;
}

/// `a >> dist`, with a 1 in bit 0 if any bit shifted out was 1 ("jamming").
fn exact_shift_right_jam(a: u32, dist: u32) -> u32 {
    if (dist == 0u) {
        return a;
    }
    if (dist >= 31u) {
        return select(0u, 1u, a != 0u);
    }
    return (a >> dist) | select(0u, 1u, (a << (32u - dist)) != 0u);
}

/// Sign, biased exponent minus one and a significand whose leading 1 is at bit 30 (7 bits for
/// rounding below bit 23 of the result), rounded to nearest even and packed (SoftFloat's
/// `softfloat_roundPackToF32`). The exponent may be below 0 (a subnormal result) or above
/// 0xFD (an overflow to infinity).
fn exact_round_pack(sign: u32, exp_in: i32, sig_in: u32) -> u32 {
    var exp = exp_in;
    var sig = sig_in;
    var round_bits = sig & 0x7fu;
    if (exp < 0) {
        sig = exact_shift_right_jam(sig, u32(-exp));
        exp = 0;
        round_bits = sig & 0x7fu;
    } else if (exp > 0xfd || (exp == 0xfd && sig + 0x40u >= 0x80000000u)) {
        return sign | 0x7f800000u;
    }
    sig = (sig + 0x40u) >> 7u;
    if (round_bits == 0x40u) {
        sig = sig & ~1u;
    }
    if (sig == 0u) {
        exp = 0;
    }
    return sign + (u32(exp) << 23u) + sig;
}

/// [`exact_round_pack`] of a significand with its leading 1 anywhere (SoftFloat's
/// `softfloat_normRoundPackToF32`).
fn exact_norm_round_pack(sign: u32, exp_in: i32, sig: u32) -> u32 {
    let shift = i32(countLeadingZeros(sig)) - 1;
    let exp = exp_in - shift;
    if (shift >= 7 && exp >= 0 && exp < 0xfd) {
        return sign + (u32(select(0, exp, sig != 0u)) << 23u) + (sig << u32(shift - 7));
    }
    return exact_round_pack(sign, exp, sig << u32(shift));
}

/// The sum of the magnitudes of `a` and `b` (same sign), with `a`'s sign.
fn exact_add_mags(a: u32, b: u32) -> u32 {
    let exp_a = i32((a >> 23u) & 0xffu);
    var sig_a = a & 0x007fffffu;
    let exp_b = i32((b >> 23u) & 0xffu);
    var sig_b = b & 0x007fffffu;
    let sign = a & 0x80000000u;
    let diff = exp_a - exp_b;
    var exp_z: i32;
    var sig_z: u32;
    if (diff == 0) {
        if (exp_a == 0) {
            return a + sig_b;
        }
        if (exp_a == 0xff) {
            if ((sig_a | sig_b) != 0u) {
                return EXACT_NAN;
            }
            return a;
        }
        exp_z = exp_a;
        sig_z = 0x01000000u + sig_a + sig_b;
        if ((sig_z & 1u) == 0u && exp_z < 0xfe) {
            return sign + (u32(exp_z) << 23u) + (sig_z >> 1u);
        }
        sig_z = sig_z << 6u;
    } else {
        sig_a = sig_a << 6u;
        sig_b = sig_b << 6u;
        if (diff < 0) {
            if (exp_b == 0xff) {
                if (sig_b != 0u) {
                    return EXACT_NAN;
                }
                return sign | 0x7f800000u;
            }
            exp_z = exp_b;
            sig_a = sig_a + select(sig_a, 0x20000000u, exp_a != 0);
            sig_a = exact_shift_right_jam(sig_a, u32(-diff));
        } else {
            if (exp_a == 0xff) {
                if (sig_a != 0u) {
                    return EXACT_NAN;
                }
                return a;
            }
            exp_z = exp_a;
            sig_b = sig_b + select(sig_b, 0x20000000u, exp_b != 0);
            sig_b = exact_shift_right_jam(sig_b, u32(diff));
        }
        sig_z = 0x20000000u + sig_a + sig_b;
        if (sig_z < 0x40000000u) {
            exp_z = exp_z - 1;
            sig_z = sig_z << 1u;
        }
    }
    return exact_round_pack(sign, exp_z, sig_z);
}

/// The difference of the magnitudes of `a` and `b` (same sign), signed from `a`'s sign.
fn exact_sub_mags(a: u32, b: u32) -> u32 {
    var exp_a = i32((a >> 23u) & 0xffu);
    var sig_a = a & 0x007fffffu;
    let exp_b = i32((b >> 23u) & 0xffu);
    var sig_b = b & 0x007fffffu;
    var sign = a & 0x80000000u;
    let diff = exp_a - exp_b;
    if (diff == 0) {
        if (exp_a == 0xff) {
            return EXACT_NAN;
        }
        var d = i32(sig_a) - i32(sig_b);
        if (d == 0) {
            return 0u;
        }
        if (exp_a != 0) {
            exp_a = exp_a - 1;
        }
        if (d < 0) {
            sign = sign ^ 0x80000000u;
            d = -d;
        }
        var shift = i32(countLeadingZeros(u32(d))) - 8;
        var exp_z = exp_a - shift;
        if (exp_z < 0) {
            shift = exp_a;
            exp_z = 0;
        }
        return sign + (u32(exp_z) << 23u) + (u32(d) << u32(shift));
    }
    sig_a = sig_a << 7u;
    sig_b = sig_b << 7u;
    var exp_z: i32;
    var sig_x: u32;
    var sig_y: u32;
    var dist: u32;
    if (diff < 0) {
        sign = sign ^ 0x80000000u;
        if (exp_b == 0xff) {
            if (sig_b != 0u) {
                return EXACT_NAN;
            }
            return sign | 0x7f800000u;
        }
        exp_z = exp_b - 1;
        sig_x = sig_b | 0x40000000u;
        sig_y = sig_a + select(sig_a, 0x40000000u, exp_a != 0);
        dist = u32(-diff);
    } else {
        if (exp_a == 0xff) {
            if (sig_a != 0u) {
                return EXACT_NAN;
            }
            return a;
        }
        exp_z = exp_a - 1;
        sig_x = sig_a | 0x40000000u;
        sig_y = sig_b + select(sig_b, 0x40000000u, exp_b != 0);
        dist = u32(diff);
    }
    return exact_norm_round_pack(sign, exp_z, sig_x - exact_shift_right_jam(sig_y, dist));
}

/// `a + b` as the CPU rounds it.
fn exact_add(x: f32, y: f32) -> f32 {
    let a = bitcast<u32>(x);
    let b = bitcast<u32>(y);
    if (exact_is_nan(a) || exact_is_nan(b)) {
        return bitcast<f32>(EXACT_NAN);
    }
    if (((a ^ b) & 0x80000000u) == 0u) {
        return bitcast<f32>(exact_add_mags(a, b));
    }
    return bitcast<f32>(exact_sub_mags(a, b));
}

/// `a − b` as the CPU rounds it.
fn exact_sub(x: f32, y: f32) -> f32 {
    return exact_add(x, bitcast<f32>(bitcast<u32>(y) ^ 0x80000000u));
}

/// The exponent and the significand (its leading 1 at bit 23) of a finite, non-zero `a`, a
/// subnormal normalised (its exponent then below 1).
fn exact_unpack(a: u32) -> vec2<i32> {
    let exp = i32((a >> 23u) & 0xffu);
    let sig = a & 0x007fffffu;
    if (exp != 0) {
        return vec2<i32>(exp, i32(sig | 0x00800000u));
    }
    let shift = i32(countLeadingZeros(sig)) - 8;
    return vec2<i32>(1 - shift, i32(sig << u32(shift)));
}

/// The 64-bit product of `a` and `b` as (high word, low word).
fn exact_mul_wide(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let p11 = a1 * b1;
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let lo = (p00 & 0xffffu) | (mid << 16u);
    let hi = p11 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(hi, lo);
}

/// `a · b` as the CPU rounds it.
fn exact_mul(x: f32, y: f32) -> f32 {
    let a = bitcast<u32>(x);
    let b = bitcast<u32>(y);
    if (exact_is_nan(a) || exact_is_nan(b)) {
        return bitcast<f32>(EXACT_NAN);
    }
    let sign = (a ^ b) & 0x80000000u;
    let inf_a = exact_is_inf(a);
    let inf_b = exact_is_inf(b);
    let zero = exact_is_zero(a) || exact_is_zero(b);
    if (inf_a || inf_b) {
        // Infinity times zero is invalid, times anything else infinite.
        return bitcast<f32>(select(sign | 0x7f800000u, EXACT_NAN, zero));
    }
    if (zero) {
        return bitcast<f32>(sign);
    }
    let ua = exact_unpack(a);
    let ub = exact_unpack(b);
    var exp_z = ua.x + ub.x - 0x7f;
    let wide = exact_mul_wide(u32(ua.y) << 7u, u32(ub.y) << 8u);
    var sig_z = wide.x | select(0u, 1u, wide.y != 0u);
    if (sig_z < 0x40000000u) {
        exp_z = exp_z - 1;
        sig_z = sig_z << 1u;
    }
    return bitcast<f32>(exact_round_pack(sign, exp_z, sig_z));
}

/// `a / b` as the CPU rounds it.
fn exact_div(x: f32, y: f32) -> f32 {
    let a = bitcast<u32>(x);
    let b = bitcast<u32>(y);
    if (exact_is_nan(a) || exact_is_nan(b)) {
        return bitcast<f32>(EXACT_NAN);
    }
    let sign = (a ^ b) & 0x80000000u;
    let inf_a = exact_is_inf(a);
    let inf_b = exact_is_inf(b);
    let zero_a = exact_is_zero(a);
    let zero_b = exact_is_zero(b);
    // ∞/∞ and 0/0 are invalid; ∞/y and x/0 infinite; x/∞ and 0/y zero.
    if ((inf_a && inf_b) || (zero_a && zero_b)) {
        return bitcast<f32>(EXACT_NAN);
    }
    if (inf_a || zero_b) {
        return bitcast<f32>(sign | 0x7f800000u);
    }
    if (inf_b || zero_a) {
        return bitcast<f32>(sign);
    }
    let ua = exact_unpack(a);
    let ub = exact_unpack(b);
    var exp_z = ua.x - ub.x + 0x7e;
    let sig_a = u32(ua.y);
    let sig_b = u32(ub.y);
    // The quotient ⌊sig_a·2^s / sig_b⌋ (s = 31, or 30 when sig_a ≥ sig_b: 31 bits either way)
    // by long division in 8-bit steps: the remainder stays below sig_b < 2^24, so shifted by 8
    // it fits a u32.
    var bits = 31u;
    if (sig_a < sig_b) {
        exp_z = exp_z - 1;
    } else {
        bits = 30u;
    }
    var q = sig_a / sig_b;
    var r = sig_a % sig_b;
    while (bits > 0u) {
        let step = min(bits, 8u);
        let t = r << step;
        q = (q << step) | (t / sig_b);
        r = t % sig_b;
        bits = bits - step;
    }
    if ((q & 0x3fu) == 0u && r != 0u) {
        q = q | 1u;
    }
    return bitcast<f32>(exact_round_pack(sign, exp_z, q));
}

// ---- The combination glue's arithmetic (shaders/combine.wgsl's `arith_*`), exactly ----

fn arith_add(a: f32, b: f32) -> f32 {
    return exact_add(a, b);
}

fn arith_sub(a: f32, b: f32) -> f32 {
    return exact_sub(a, b);
}

fn arith_mul(a: f32, b: f32) -> f32 {
    return exact_mul(a, b);
}

fn arith_div(a: f32, b: f32) -> f32 {
    return exact_div(a, b);
}

/// `f32::clamp`: NaN stays NaN (WGSL's clamp may not keep it).
fn arith_clamp(v: f32, lo: f32, hi: f32) -> f32 {
    var r = v;
    if (v < lo) {
        r = lo;
    }
    if (v > hi) {
        r = hi;
    }
    return r;
}

/// NaN told by its bits (a comparison with itself may be folded by a compiler assuming none).
fn arith_is_nan(v: f32) -> bool {
    return exact_is_nan(bitcast<u32>(v));
}

/// spectex_model::math::sin_turns, `cos_turns(t − ¼)`.
fn arith_sin_turns(t: f32) -> f32 {
    return exact_cos_turns(exact_sub(t, 0.25f));
}

/// spectex_model::math::cos_turns (its magic-number rounding, then the polynomial).
fn exact_cos_turns(t: f32) -> f32 {
    let rounded = exact_sub(exact_add(t, 12582912.0f), 12582912.0f);
    let a = abs(exact_sub(t, rounded));
    let far = a > 0.25f;
    let b = select(a, exact_sub(0.5f, a), far);
    let x = exact_mul(b, b);
    var p = COS_TURNS_4;
    p = exact_add(exact_mul(p, x), COS_TURNS_3);
    p = exact_add(exact_mul(p, x), COS_TURNS_2);
    p = exact_add(exact_mul(p, x), COS_TURNS_1);
    p = exact_add(exact_mul(p, x), COS_TURNS_0);
    return select(p, -p, far);
}
