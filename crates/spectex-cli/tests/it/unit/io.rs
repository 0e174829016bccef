//! `spectex_cli::io`: the PNG levels of f32 values, computed without `round`, against
//! `quantise` of the values as f64.

use spectex_cli::io::{level8, level16, quantise};

fn check(v: f32) {
    let q8 = quantise(f64::from(v), 255.0) as u8;
    let q16 = quantise(f64::from(v), 65535.0) as u16;
    assert_eq!(
        level8(v),
        q8,
        "8-bit level of {v:e} ({:#010x})",
        v.to_bits()
    );
    assert_eq!(
        level16(v),
        q16,
        "16-bit level of {v:e} ({:#010x})",
        v.to_bits()
    );
}

#[test]
fn levels_round_half_away_from_zero_as_quantise() {
    // Each level's rounding boundary (k + ½)/max and the f32 values around it.
    for max in [255.0f64, 65535.0] {
        for k in 0..max as u32 {
            let boundary = ((f64::from(k) + 0.5) / max) as f32;
            for d in -4i32..=4 {
                check(f32::from_bits(boundary.to_bits().wrapping_add_signed(d)));
            }
        }
    }
    // Values of every magnitude and sign (a stride through the bit patterns), and the tiny
    // values whose sum with ½ rounds.
    for bits in (0..=u32::MAX).step_by(4099) {
        check(f32::from_bits(bits));
    }
    for v in [
        0.0,
        -0.0,
        0.5,
        1.0,
        1.0 + f32::EPSILON,
        1.0 - f32::EPSILON / 2.0,
        -1.0,
        1e-45,
        f32::MIN_POSITIVE,
        1e-20,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
    ] {
        check(v);
    }
}
