//! Distances between spectra, log-log fits, quantiles and moments (`src/metrics.rs`).

use ndarray::Array2;
use spectex_spectrum::Fft2;
use spectex_spectrum::metrics::*;
use spectex_spectrum::signed_frequency;

#[test]
fn shape_distance_is_zero_for_one_shape_and_two_for_disjoint_ones() {
    let a = Array2::from_shape_fn((16, 16), |(y, x)| if (y, x) == (3, 3) { 1.0 } else { 0.0 });
    let b = Array2::from_shape_fn(
        (16, 16),
        |(y, x)| if (y, x) == (10, 10) { 5.0 } else { 0.0 },
    );
    assert!(shape_distance(a.view(), (a.clone() * 7.0).view()) < 1e-12);
    assert!((shape_distance(a.view(), b.view()) - 2.0).abs() < 1e-12);
}

#[test]
fn log_log_fit_recovers_a_power_law() {
    let n = 64;
    let psd = Array2::from_shape_fn((n, n), |(y, x)| {
        let f = signed_frequency(x, n).hypot(signed_frequency(y, n));
        if f == 0.0 { 0.0 } else { 3.0 * f.powf(-1.5) }
    });
    let (slope, _, bins) = log_log_fit(psd.view(), 0.05, 0.4);
    assert!(bins.len() > 10);
    // Ring means of f^(−1.5) over rings of finite width: close to, not exactly, −1.5.
    assert!((slope + 1.5).abs() < 0.02, "slope {slope}");
}

#[test]
fn normal_quantiles() {
    assert!(standard_normal_quantile(0.5).abs() < 1e-12);
    assert!((standard_normal_quantile(0.75) - 0.674_489_750).abs() < 1e-8);
    assert!((standard_normal_quantile(0.975) - 1.959_963_985).abs() < 1e-8);
}

#[test]
fn moments_of_a_two_level_signal() {
    let a = Array2::from_shape_fn((4, 4), |(y, _)| if y < 2 { -1.0 } else { 1.0 });
    assert_eq!(mean_variance(a.view()), (0.0, 1.0));
    assert!((excess_kurtosis(a.view()) + 2.0).abs() < 1e-12);
}

#[test]
fn a_constant_contrast_cosine_has_no_low_variance_energy() {
    let n = 64;
    let mut fft = Fft2::new();
    let cosine = Array2::from_shape_fn((n, n), |(_, x)| {
        (std::f64::consts::TAU * x as f64 / 8.0).cos()
    });
    let beat = Array2::from_shape_fn((n, n), |(_, x)| {
        (std::f64::consts::TAU * x as f64 / 8.0).cos()
            * (std::f64::consts::TAU * x as f64 / 64.0).cos()
    });
    assert!(variance_low_fraction(cosine.view(), 1.0 / 16.0, &mut fft) < 1e-12);
    assert!(variance_low_fraction(beat.view(), 1.0 / 16.0, &mut fft) > 0.3);
    assert!((ring_power_peak(cosine.view(), &mut fft) - 0.125).abs() < 1e-12);
}

#[test]
fn wasserstein1_of_a_shift_is_the_shift_and_of_a_copy_zero() {
    let a: Vec<f64> = (0..1000).map(|k| ((k * 37) % 101) as f64).collect();
    let shifted: Vec<f64> = a.iter().map(|v| v + 2.5).collect();
    assert!((wasserstein1(&a, &shifted) - 2.5).abs() < 1e-9);
    assert!(wasserstein1(&a, &a).abs() < 1e-12);
    // A sample and the same values twice over have one distribution.
    let twice: Vec<f64> = a.iter().chain(&a).copied().collect();
    assert!(wasserstein1(&a, &twice) < 0.05);
    // Uniform on [0, 1] against the point mass at 0: E|U| = 1/2.
    let u: Vec<f64> = (0..10_000).map(|k| (k as f64 + 0.5) / 10_000.0).collect();
    assert!((wasserstein1(&u, &[0.0]) - 0.5).abs() < 1e-3);
}

#[test]
fn gradient_magnitude_of_a_plane_is_its_slope() {
    let a = Array2::from_shape_fn((6, 7), |(y, x)| 3.0 * x as f64 - 4.0 * y as f64);
    let g = gradient_magnitudes(a.view());
    assert_eq!(g.dim(), (4, 5));
    assert!(g.iter().all(|v| (v - 5.0).abs() < 1e-12));
}

/// The fast quantile (Acklam and one Halley step on `erfc`) against an independent reference:
/// bisection on `Φ(z) = ½ + φ(z)·Σ z^{2k+1}/(1·3·…·(2k+1))`, the series that converges for every
/// `z`, and the CDF it inverts.
#[test]
fn normal_quantile_matches_bisection_on_the_series_and_inverts_the_cdf() {
    let series_cdf = |z: f64| {
        let (mut term, mut sum) = (z, z);
        for k in 1..200 {
            term *= z * z / (2 * k + 1) as f64;
            sum += term;
        }
        0.5 + (-z * z / 2.0).exp() / (2.0 * std::f64::consts::PI).sqrt() * sum
    };
    let bisect = |p: f64| {
        let (mut lo, mut hi) = (-8.0f64, 8.0f64);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if series_cdf(mid) < p {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    for &p in &[1e-6, 1e-4, 0.02, 0.3, 0.5, 0.77, 0.99, 1.0 - 1e-5] {
        let x = standard_normal_quantile(p);
        assert!((x - bisect(p)).abs() < 1e-9, "{p}: {x} vs {}", bisect(p));
        assert!(
            (standard_normal_cdf(x) - p).abs() < 1e-14 * p.max(1e-3),
            "{p}"
        );
    }
}
