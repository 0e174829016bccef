//! Spectral fidelity of the classic noises, measured on renders with the Welch PSD: the
//! survey's 1/f^β fractal (Eq. (8)) built as LRP noise has a radial power spectrum falling as
//! f^(−2β), and fBm with gain g and lacunarity λ has the slope its self-similarity implies.
//!
//! `cargo test --release -p spectex-cli --test it classic_fidelity:: -- --nocapture` prints them.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(clippy::print_stdout, reason = "the measured slopes are reported")]

use ndarray::Array2;
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::classic::{Basis, ClassicNoise, Fractal, FractalKind};
use spectex_reproduce::survey::fractal_model;
use spectex_spectrum::{Fft2, log_log_fit, welch_psd_with_block};

/// Least-squares slope of log power against log frequency over the radial bins in `[lo, hi]`.
fn log_log_slope(model: &Model, side: usize, block: usize, lo: f64, hi: f64) -> f64 {
    let eval = Evaluator::new(model).unwrap();
    let v = eval
        .render(&Window::new(side, side).at([1.0e7, -2.0e3], 1.0))
        .unwrap();
    let img = Array2::from_shape_vec((side, side), v.into_iter().map(f64::from).collect()).unwrap();
    let mut fft = Fft2::new();
    let psd = welch_psd_with_block(img.view(), block, &mut fft).unwrap();
    log_log_fit(psd.view(), lo, hi).0
}

/// With the survey's convention (magnitude ∝ 1/f^β) the power falls as f^(−2β), within 0.1
/// (issue 7), for isotropic roll-offs from ½ to 2. The fit is the one `spectex noise fractal`
/// makes: J = 48 cosines in 12 strata of equal log-power spans (each about one octave;
/// equal-energy strata put the whole weak tail of a steep spectrum into one flat stratum:
/// β = 1.5 then measured −0.77).
///
/// Known limit, measured and not asserted: with the angular term (σ = 0.35 rad) the slope is
/// −2.34 for β = 1. A level set of an anisotropic spectrum is a thin crescent across radii;
/// §4.3's erosion (75% coverage) reduces it to its ridge, and the stratum's energy, spread
/// evenly over the ridge, moves towards low frequencies. Coverage 0.3 gives −2.01 (β = 1) but
/// −1.17 for β = ½, so no single coverage fixes it.
#[test]
fn spectral_fractal_power_falls_as_f_to_minus_two_beta() {
    for beta in [0.5f32, 1.0, 1.5, 2.0] {
        let slope = log_log_slope(&fractal_model(beta).unwrap(), 1024, 256, 0.03, 0.3);
        println!(
            "fractal β = {beta}: radial PSD slope {slope:.3} (expected {})",
            -2.0 * beta
        );
        assert!(
            (slope + 2.0 * f64::from(beta)).abs() < 0.1,
            "β = {beta}: slope {slope}, expected {}",
            -2.0 * beta
        );
    }
}

/// fBm `Σ gᵒ n(λᵒ x)` of independent octaves has `P(λf) = g²λ⁻² P(f)` away from the first and
/// last octaves (the 2D PSD of `n(λx)` is `λ⁻² P(f/λ)`), so its radial PSD falls as
/// `f^(−2 + 2 ln g / ln λ)`: −4 for g = ½, λ = 2; −3 for g = 1/√2, λ = 2.
#[test]
fn fbm_radial_slope_follows_gain_and_lacunarity() {
    for (gain, lacunarity) in [(0.5f32, 2.0f32), (std::f32::consts::FRAC_1_SQRT_2, 2.0)] {
        let model = Model::Classic(ClassicNoise {
            seed: 9,
            dimensions: 2,
            cell_size: 128.0,
            basis: Basis::Gradient,
            fractal: Some(Fractal {
                kind: FractalKind::Fbm,
                octaves: 8,
                lacunarity,
                gain,
            }),
            amplitude: 1.0,
            mean: 0.0,
        });
        let expected = -2.0 + 2.0 * f64::from(gain).ln() / f64::from(lacunarity).ln();
        // Octaves 2 to 5 (cells of 32 to 4 pixels) dominate [1/32, 1/8] from both sides.
        let slope = log_log_slope(&model, 1024, 256, 1.0 / 32.0, 1.0 / 8.0);
        println!(
            "fBm g = {gain}, λ = {lacunarity}: radial PSD slope {slope:.3} (expected {expected:.3})"
        );
        assert!(
            (slope - expected).abs() < 0.25,
            "g = {gain}, λ = {lacunarity}: slope {slope}, expected {expected}"
        );
    }
}
