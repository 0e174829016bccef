//! Welch power spectra, radial profiles and the spectrum of variance (`src/welch.rs`).

use ndarray::Array2;
use ndarray::s;
use num_complex::Complex64;
use spectex_model::random::{Prng, cell_hash};
use spectex_spectrum::Fft2;
use spectex_spectrum::SpectrumError;
use spectex_spectrum::welch::*;

#[test]
fn block_size_is_the_largest_power_of_two_strictly_below() {
    for (side, t) in [
        (3, 2),
        (4, 2),
        (5, 4),
        (8, 4),
        (9, 8),
        (300, 256),
        (512, 256),
        (513, 512),
    ] {
        assert_eq!(welch_block_size(side, side + 10).unwrap(), t, "side {side}");
    }
    assert!(matches!(
        welch_block_size(2, 100),
        Err(SpectrumError::TooSmall { .. })
    ));
}

#[test]
fn blocks_cover_the_axis_with_half_overlap() {
    for (n, t) in [(512, 256), (300, 256), (45, 32), (9, 8), (1000, 512)] {
        let starts = welch_block_starts(n, t);
        assert_eq!(starts[0], 0);
        assert_eq!(
            *starts.last().unwrap() + t,
            n,
            "n {n}: last block ends at the edge"
        );
        for w in starts.windows(2) {
            assert!(w[1] > w[0] && w[1] - w[0] <= t / 2, "n {n}: hop {w:?}");
        }
    }
}

/// Slow reference: the average of windowed periodograms computed with the DFT definition.
#[test]
fn matches_a_direct_periodogram_average() {
    let (h, w) = (13, 11);
    let mut prng = Prng::new(cell_hash(1, 2, 3, 4));
    let img = Array2::from_shape_fn((h, w), |_| prng.next_f64());
    let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
    let t = 8;
    let win = hann(t);
    let e: f64 = win.iter().map(|a| a * a).sum::<f64>().powi(2);
    let (ys, xs) = (welch_block_starts(h, t), welch_block_starts(w, t));
    for k in 0..t {
        for l in 0..t {
            let mut total = 0.0;
            for &y0 in &ys {
                for &x0 in &xs {
                    let block = img.slice(s![y0..y0 + t, x0..x0 + t]);
                    let ws: f64 = win.iter().sum::<f64>().powi(2);
                    let m = block
                        .indexed_iter()
                        .map(|((y, x), v)| v * win[y] * win[x])
                        .sum::<f64>()
                        / ws;
                    let mut c = Complex64::new(0.0, 0.0);
                    for y in 0..t {
                        for x in 0..t {
                            let a = -2.0 * std::f64::consts::PI * ((k * y + l * x) % t) as f64
                                / t as f64;
                            c += (block[[y, x]] - m)
                                * win[y]
                                * win[x]
                                * Complex64::from_polar(1.0, a);
                        }
                    }
                    total += c.norm_sqr();
                }
            }
            let want = total / (ys.len() * xs.len()) as f64 / e;
            assert!(
                (psd[[k, l]] - want).abs() < 1e-12 * want.max(1.0),
                "({k}, {l})"
            );
        }
    }
}

/// Parseval: the mean of P over the frequencies is the window-weighted block variance;
/// for white noise of variance σ² that is σ² in expectation.
#[test]
fn white_noise_is_flat_at_its_variance() {
    let n = 256;
    let mut prng = Prng::new(77);
    // Uniform on [0, 1): variance 1/12.
    let img = Array2::from_shape_fn((n, n), |_| prng.next_f64());
    let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
    let sigma2 = 1.0 / 12.0;
    let mean = psd.mean().unwrap();
    // 9 blocks × 16384 frequencies of χ²₂-like values: the mean is within ~1%.
    assert!(
        (mean / sigma2 - 1.0).abs() < 0.03,
        "mean PSD {mean} vs σ² {sigma2}"
    );
    let profile = radial_profile(psd.view());
    for b in profile.iter().filter(|b| b.radius > 0.05 && b.count > 100) {
        assert!(
            (b.power / sigma2 - 1.0).abs() < 0.25,
            "ring {} at {}",
            b.radius,
            b.power
        );
    }
}

#[test]
fn a_cosine_peaks_at_its_frequency() {
    let n = 128;
    let (fy, fx) = (5.0 / 64.0, 12.0 / 64.0); // on the 64-point block grid
    let img = Array2::from_shape_fn((n, n), |(y, x)| {
        (2.0 * std::f64::consts::PI * (fy * y as f64 + fx * x as f64)).cos()
    });
    let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
    let (mut best, mut at) = (0.0, (0, 0));
    for (idx, &p) in psd.indexed_iter() {
        if p > best {
            best = p;
            at = idx;
        }
    }
    assert!(at == (5, 12) || at == (59, 52), "peak at {at:?}");
}

#[test]
fn radial_profile_counts_every_frequency_once() {
    let psd = Array2::from_elem((16, 16), 2.0);
    let p = radial_profile(psd.view());
    assert_eq!(p.iter().map(|b| b.count).sum::<usize>(), 256);
    assert!(p.iter().all(|b| b.power == 2.0));
    assert_eq!(p[0].radius, 0.0);
    assert_eq!(p[0].count, 1);
}

#[test]
fn variance_spectrum_of_constant_contrast_has_no_low_frequency_bump() {
    // A pure cosine has constant envelope: (cos)² = ½ + ½cos(2·), no energy near 0.
    let n = 128;
    let img = Array2::from_shape_fn((n, n), |(_, x)| {
        (2.0 * std::f64::consts::PI * 8.0 * x as f64 / 64.0).cos()
    });
    let v = variance_spectrum(img.view(), &mut Fft2::new()).unwrap();
    let low: f64 = radial_profile(v.view())
        .iter()
        .filter(|b| b.radius > 0.0 && b.radius < 0.1)
        .map(|b| b.power)
        .sum();
    let all: f64 = v.sum();
    assert!(low < 1e-6 * all, "low {low} all {all}");
}
