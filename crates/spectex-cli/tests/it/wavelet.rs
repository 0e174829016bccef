//! Wavelet noise (its end-to-end run is in `tests/it/cli.rs`, with the classic noises, and its
//! bad inputs in `tests/it/bad_inputs.rs`): the science of Cook & DeRose 2005 measured with `spectex_spectrum::Fft2`: the tile is
//! band-limited (little energy below half its Nyquist frequency), it has zero mean up to the
//! analysis filter's DC gain (an identity), and the multiband sum's spectrum is the
//! weighted sum of its bands' spectra, one octave apart.
//!
//! Run with `--nocapture` to see the measured energy fractions.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stderr,
    reason = "the measured fractions are the test's report"
)]

use ndarray::Array2;
use num_complex::Complex;
use spectex_cpu::{Evaluator, Window};
use spectex_model::wavelet::{ANALYSIS, band_pass_tile, gaussian_tile};
use spectex_model::{Model, WaveletNoise};
use spectex_spectrum::Fft2;

/// `|X(k, l)|²` of a real `n × n` image (row-major), mean removed.
fn power(values: &[f64], n: usize) -> Array2<f64> {
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mut a = Array2::from_shape_fn((n, n), |(j, i)| Complex::new(values[j * n + i] - mean, 0.0));
    Fft2::<f64>::new().forward(&mut a);
    a.mapv(|c| c.norm_sqr())
}

/// Signed integer frequency of DFT index `k` of `n`.
fn freq(k: usize, n: usize) -> f64 {
    if k <= n / 2 {
        k as f64
    } else {
        k as f64 - n as f64
    }
}

/// Share of the power at radial frequency `|f| < limit` (index units).
fn low_fraction(p: &Array2<f64>, limit: f64) -> f64 {
    let n = p.nrows();
    let total: f64 = p.sum();
    let low: f64 = p
        .indexed_iter()
        .filter(|((k, l), _)| freq(*k, n).hypot(freq(*l, n)) < limit)
        .map(|(_, v)| v)
        .sum();
    low / total
}

#[test]
fn the_tile_is_band_limited() {
    let n = 128;
    for seed in [1, 2, 3] {
        let r = gaussian_tile(seed, n, 2);
        let tile = band_pass_tile(&r, n, 2);
        let white = low_fraction(&power(&r, n), n as f64 / 4.0);
        let band = low_fraction(&power(&tile, n), n as f64 / 4.0);
        eprintln!(
            "wavelet tile n = {n}, seed {seed}: energy below half Nyquist (|f| < n/4) {:.2}% \
             (the white noise R it came from: {:.2}%, expected π/16 = 19.6%)",
            100.0 * band,
            100.0 * white
        );
        // White noise puts π/16 of its energy there; N = R − R↓↑ removes the coarse part.
        assert!(
            (white - std::f64::consts::PI / 16.0).abs() < 0.02,
            "{white}"
        );
        assert!(band < 0.05, "seed {seed}: {band} of the energy below n/4");
    }
}

#[test]
fn the_tile_has_zero_mean_up_to_the_filters_dc_gain() {
    // Along one axis, sample k enters the coarse values with the sum S_{k mod 2} of the analysis
    // taps of its parity, and upsampling keeps means (each coarse value is spread with
    // ¾ + ¼ + ¼ + ¾ = 2 over n fine ones), so mean(R↓↑) = n⁻² Σ_{k,l} 4 S_{k mod 2} S_{l mod 2}
    // R_{lk}; the shifted copy doubles mean(R − R↓↑). With S_even = S_odd = ½ this would be
    // exactly 0; the paper's 6-digit taps leave ~1e-6 of mean(R).
    let parity = [
        ANALYSIS.iter().step_by(2).sum::<f64>(),
        ANALYSIS.iter().skip(1).step_by(2).sum::<f64>(),
    ];
    for (n, seed) in [(64, 4), (128, 5)] {
        let r = gaussian_tile(seed, n, 2);
        let tile = band_pass_tile(&r, n, 2);
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let coarse: f64 = (0..n * n)
            .map(|c| 4.0 * parity[(c % n) % 2] * parity[(c / n) % 2] * r[c])
            .sum::<f64>()
            / (n * n) as f64;
        let want = 2.0 * (mean(&r) - coarse);
        assert!(
            (mean(&tile) - want).abs() < 1e-12,
            "{} vs {want}",
            mean(&tile)
        );
        let rms = (tile.iter().map(|v| v * v).sum::<f64>() / tile.len() as f64).sqrt();
        assert!(
            mean(&tile).abs() < 1e-4 * rms,
            "mean {} rms {rms}",
            mean(&tile)
        );
    }
}

/// Renders one period (`n·cell` pixels) of a 2D wavelet noise on the CPU, in f64.
fn render(bands: Vec<f32>) -> Vec<f64> {
    let m = Model::Wavelet(WaveletNoise {
        seed: 9,
        dimensions: 2,
        tile_size: 32,
        cell_size: 16.0,
        bands,
        amplitude: 1.0,
        mean: 0.0,
    });
    let eval = Evaluator::new(&m).unwrap();
    eval.render(&Window::new(512, 512))
        .unwrap()
        .into_iter()
        .map(f64::from)
        .collect()
}

/// Power in octave rings `[2^o, 2^{o+1})` (index units) of a 512² periodogram, `o = 0..8`.
fn octaves(p: &Array2<f64>) -> Vec<f64> {
    let n = p.nrows();
    let mut e = vec![0.0; 9];
    for ((k, l), v) in p.indexed_iter() {
        let f = freq(k, n).hypot(freq(l, n));
        if f >= 1.0 {
            e[(f.log2().floor() as usize).min(8)] += v;
        }
    }
    e
}

#[test]
fn the_multiband_spectrum_follows_the_band_weights() {
    // One period of every band (512 = 32·16 px): periodic, so the periodogram has no leakage.
    let weights = [1.0f32, 0.5, 0.25];
    let singles: Vec<Vec<f64>> = (0..3)
        .map(|b| {
            let mut w = vec![0.0f32; 3];
            w[b] = 1.0;
            octaves(&power(&render(w), 512))
        })
        .collect();
    // Band b alone peaks one octave above band b − 1: its spectral centroid in log2 frequency.
    let centroid = |e: &[f64]| {
        e.iter().enumerate().map(|(o, v)| o as f64 * v).sum::<f64>() / e.iter().sum::<f64>()
    };
    for b in 1..3 {
        let step = centroid(&singles[b]) - centroid(&singles[b - 1]);
        assert!(
            (step - 1.0).abs() < 0.1,
            "band {b}: centroid step {step} octaves"
        );
    }
    // The sum's octave energies are Σ_b w_b²/Σw² times the bands' (their cross terms vanish
    // because the bands occupy different octaves).
    let sum = octaves(&power(&render(weights.to_vec()), 512));
    let norm: f64 = weights.iter().map(|&w| f64::from(w * w)).sum();
    let total: f64 = sum.iter().sum();
    for o in 0..9 {
        let predicted: f64 = (0..3)
            .map(|b| f64::from(weights[b] * weights[b]) / norm * singles[b][o])
            .sum();
        let share = sum[o] / total;
        eprintln!(
            "octave [{}, {}) cycles per 512 px: measured {:.4}, predicted {:.4} of the energy",
            1 << o,
            2 << o,
            share,
            predicted / total
        );
        assert!(
            (sum[o] - predicted).abs() <= 0.1 * sum[o] + 1e-3 * total,
            "octave {o}: {} vs predicted {predicted}",
            sum[o]
        );
    }
}
