//! Phasor noise against the paper's claims (Tricard et al. 2019), measured on 1024² CPU renders:
//! the PWM profile's mean equals its duty cycle (Fig. 16), the phasor sine wave's power spectrum
//! peaks at the kernel frequency, and its spectrum of variance has (nearly) no low-frequency
//! energy where Gabor noise's has a central lobe (§3.1.3, Figs. 4, 7, 11, 12).
//!
//! `cargo test -p spectex-cli --test it phasor_fidelity:: -- --nocapture` prints the measured
//! table.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(clippy::print_stdout, reason = "the tests report what they measured")]

use ndarray::Array2;
use spectex_cpu::{Evaluator, Window};
use spectex_model::{Field, Model, PhasorNoise, PhasorOrientation, PhasorOutput, Profile};
use spectex_reproduce::phasor::{F, model, settings};
use spectex_spectrum::{
    Fft2, fraction_above_gaussian_quantile, ring_power_peak, variance_low_fraction,
};

/// Renders are 1024²: the kernel frequency `F` (1/16) then falls on a bin.
const SIDE: usize = 1024;

fn render(m: &PhasorNoise) -> Array2<f64> {
    let v = Evaluator::new(&Model::Phasor(m.clone()))
        .unwrap()
        .render(&Window::new(SIDE, SIDE).at([-2.0e4, 5.0e3], 1.0))
        .unwrap();
    Array2::from_shape_vec((SIDE, SIDE), v.into_iter().map(f64::from).collect()).unwrap()
}

fn mean(a: &Array2<f64>) -> f64 {
    a.sum() / a.len() as f64
}

/// Paper Fig. 16: "phasor noise through a PWM profile having 25% white (global average
/// verified at 25.007%)" against Gabor noise thresholded to 25%. The phasor's phase is uniform
/// and its stripes complete, so the white fraction is the duty cycle up to boundary effects;
/// we require 25% ± 0.1% as the issue asks. Gabor noise is thresholded where a user would, at the
/// 75% quantile of the Gaussian with its theoretical variance `ρ·∫a² sin²/…`, measured here on
/// the render's own variance so that only the non-Gaussian shape counts against it.
#[test]
fn pwm_mean_is_the_duty_cycle() {
    println!("| setting | phasor PWM white | thresholded Gabor white |");
    println!("|---|---|---|");
    for (name, orientation) in settings() {
        let pwm = render(&model(
            orientation.clone(),
            Profile::Square {
                duty: Field::constant(0.25),
            },
            PhasorOutput::Profiled,
        ));
        assert!(
            pwm.iter().all(|&v| v == 0.0 || v == 1.0),
            "{name}: not binary"
        );
        let white = mean(&pwm);
        let gabor = render(&model(orientation, Profile::Sine, PhasorOutput::Gabor));
        let g_white = fraction_above_gaussian_quantile(gabor.view(), 0.75);
        println!(
            "| {name} | {:.3}% | {:.3}% |",
            100.0 * white,
            100.0 * g_white
        );
        assert!(
            (white - 0.25).abs() <= 0.001,
            "{name}: white fraction {white}"
        );
    }
}

/// The phasor sine wave keeps the kernels' frequency: its radially summed power spectrum peaks
/// at `F` within one bin (`1/1024` cycles per pixel).
#[test]
fn sine_wave_spectrum_peaks_at_the_kernel_frequency() {
    for (name, orientation) in settings() {
        let img = render(&model(orientation, Profile::Sine, PhasorOutput::Profiled));
        let peak_f = ring_power_peak(img.view(), &mut Fft2::new());
        println!("{name}: power peaks at {peak_f:.5} cycles/px (F = {F})");
        assert!(
            (peak_f - f64::from(F)).abs() <= 1.0 / SIDE as f64,
            "{name}: peak at {peak_f}"
        );
    }
}

/// Spectrum of variance (the power spectrum of the squared, zero-mean noise, §3.1.3): the
/// fraction of its energy inside the low-frequency disc `|f| < F/2` (DC excluded). Gabor noise's
/// local loss of contrast puts a central lobe there; the phasor sine wave `sin φ` has
/// `sin² φ = ½ − ½ cos 2φ`, whose spectrum sits around `2F` apart from what the phase's own
/// variations bring back. Reported for the bi-lobe, isotropic and coherent isotropic settings.
#[test]
fn spectrum_of_variance_loses_its_central_lobe() {
    let mut fft = Fft2::new();
    let mut low_fraction =
        |a: &Array2<f64>| variance_low_fraction(a.view(), f64::from(F) / 2.0, &mut fft);
    // Limits: the bi-lobe phasor keeps no central lobe (Fig. 4; measured ratio 0.001); the
    // coherent isotropic field keeps "close to perfect" (Fig. 12; measured 0.008); independent
    // isotropic directions mix bi-lobes more than π/2 apart and keep part of it (Fig. 11;
    // measured 0.50).
    let [bilobe, isotropic, coherent] = settings();
    for ((name, orientation), limit) in [(bilobe, 0.02), (isotropic, 0.75), (coherent, 0.05)] {
        let phasor = low_fraction(&render(&model(
            orientation.clone(),
            Profile::Sine,
            PhasorOutput::Profiled,
        )));
        let gabor = low_fraction(&render(&model(
            orientation,
            Profile::Sine,
            PhasorOutput::Gabor,
        )));
        let ratio = phasor / gabor;
        println!(
            "{name}: low-frequency energy of the spectrum of variance: phasor {phasor:.4}, Gabor {gabor:.4}, ratio {ratio:.3}"
        );
        assert!(ratio < limit, "{name}: ratio {ratio}");
    }
}

/// A graded bandwidth sets the kernels' size where they are: with `b` = 0.02 on the left half
/// and 0.04 on the right (an image field), the intensity `I` varies on the scale of the kernel
/// envelope `1/b`, so `√(E|∇I|² / Var I)` must be twice as large on the right (within 20%:
/// two 384×512 regions hold a few hundred envelopes each; measured 1.93). Without the per-kernel
/// sharpness every kernel would have the widest envelope and the ratio would be 1.
#[test]
fn graded_bandwidth_sets_the_local_envelope() {
    let grey = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let mut m = model(
        PhasorOrientation::Aligned {
            angle: Field::constant(0.3),
        },
        Profile::Sine,
        PhasorOutput::Intensity,
    );
    m.bandwidth = Field::Image {
        width: 8,
        height: 1,
        grey,
        pixel_size: 128.0,
        min: 0.02,
        max: 0.04,
    };
    m.impulses_per_kernel = 12.0;
    let v = Evaluator::new(&Model::Phasor(m))
        .unwrap()
        .render(&Window::new(SIDE, 512).at([0.0, 0.0], 1.0))
        .unwrap();
    let at = |x: usize, y: usize| f64::from(v[y * SIDE + x]);
    let envelope = |x0: usize, x1: usize| {
        let (mut s, mut s2, mut g2, mut n) = (0.0, 0.0, 0.0, 0.0);
        for y in 0..511 {
            for x in x0..x1 {
                let i = at(x, y);
                s += i;
                s2 += i * i;
                g2 += (at(x + 1, y) - i).powi(2) + (at(x, y + 1) - i).powi(2);
                n += 1.0;
            }
        }
        let mean = s / n;
        ((g2 / n) / (s2 / n - mean * mean)).sqrt()
    };
    let (left, right) = (envelope(64, 448), envelope(576, 960));
    let ratio = right / left;
    println!("graded bandwidth 0.02 → 0.04: envelope scale ratio {ratio:.3} (expected 2)");
    assert!((ratio - 2.0).abs() < 0.4, "ratio {ratio}");
}
