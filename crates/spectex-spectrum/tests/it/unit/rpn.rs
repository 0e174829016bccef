//! Random Phase Noise's unit phasors against `sin_cos` (`src/rpn.rs`).

use num_complex::Complex64;
use spectex_model::random::Prng;
use spectex_model::random::unit_f64;
use spectex_spectrum::rpn::*;

#[test]
fn unit_phasor_matches_sin_cos() {
    let mut prng = Prng::new(5);
    let mut worst = 0.0f64;
    for i in 0..200_000u32 {
        let bits = if i < 64 {
            [0, 1, u32::MAX, 1 << 31, 1 << 30, 3 << 30][i as usize % 6]
        } else {
            prng.next_u32()
        };
        let (sin, cos) = (2.0 * std::f64::consts::PI * unit_f64(bits)).sin_cos();
        let got = unit_phasor(bits);
        worst = worst.max((got - Complex64::new(cos, sin)).norm());
    }
    // The reference itself rounds 2π·u (up to ~7e-16 of argument error near 2π).
    assert!(worst < 2e-15, "worst error {worst:e}");
}
