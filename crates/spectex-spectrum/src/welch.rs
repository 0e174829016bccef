//! Power-spectrum estimates: Welch's averaged periodogram, the centred log-magnitude spectrum,
//! the radial power profile and the spectrum of variance.
//!
//! Conventions (used throughout spectex, so that fitted models and metrics agree):
//! - **Block size** `T`: the largest power of two strictly below the image's smaller side
//!   (a 512² exemplar gives `T = 256`), so there are always at least two blocks per axis.
//! - **Block placement**: along each axis, `n = ⌈(N − T)/(T/2)⌉ + 1` blocks whose starts are
//!   spread evenly from `0` to `N − T` (rounded), so consecutive blocks overlap by at least 50%
//!   and the whole image is used.
//! - **Window**: separable periodic Hann, `w(n) = ½ − ½cos(2πn/T)`.
//! - **Mean**: each block's window-weighted mean `μ = Σwb / Σw` is removed before windowing,
//!   so `P(0) = 0` exactly: the PSD describes the fluctuation; every model carries the mean
//!   separately.
//! - **Normalisation**: `P(ξ) = mean over blocks of |DFT(w·(b − μ))(ξ)|² / Σw²`, so the
//!   mean of `P` over the `T²` frequencies equals the window-weighted variance of the blocks
//!   (Parseval), and white noise of variance σ² has `P ≈ σ²` everywhere.
//! - `P` is returned uncentred (zero frequency at `[0, 0]`); [`crate::centered`] shifts it.

use ndarray::{Array2, ArrayView2, s};
use num_complex::Complex64;

use crate::{Fft2, SpectrumError, fft::signed_frequency};

/// The Welch block size `T` for an image of `height × width`: the largest power of two strictly
/// below `min(height, width)`.
///
/// # Errors
/// [`SpectrumError::TooSmall`] when the smaller side is below 3 (no block of at least 2×2 fits).
pub fn welch_block_size(height: usize, width: usize) -> Result<usize, SpectrumError> {
    let side = height.min(width);
    if side < 3 {
        return Err(SpectrumError::TooSmall {
            parameter: "image for a Welch power spectrum",
            width,
            height,
            min_width: 3,
            min_height: 3,
        });
    }
    // Largest power of two < side  ⇔  the one below the next power of two ≥ side.
    Ok(side.next_power_of_two() / 2)
}

/// Block start positions along an axis of length `n` for blocks of length `t` (see the module
/// documentation).
#[must_use]
pub fn welch_block_starts(n: usize, t: usize) -> Vec<usize> {
    if n <= t {
        return vec![0];
    }
    let hop = (t / 2).max(1);
    let count = (n - t).div_ceil(hop) + 1;
    (0..count)
        .map(|i| ((i * (n - t)) as f64 / (count - 1) as f64).round() as usize)
        .collect()
}

/// The periodic Hann window of length `t`.
#[must_use]
pub fn hann(t: usize) -> Vec<f64> {
    (0..t)
        .map(|n| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * n as f64 / t as f64).cos())
        .collect()
}

/// Welch's power spectrum estimate of one channel, `T × T`, zero frequency at `[0, 0]`.
///
/// ```
/// use ndarray::Array2;
/// use spectex_spectrum::{Fft2, welch_psd};
///
/// let img = Array2::from_shape_fn((40, 40), |(y, x)| ((x * 7 + y * 3) % 5) as f64);
/// let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
/// assert_eq!(psd.dim(), (32, 32));
/// assert!(psd[[0, 0]].abs() < 1e-9); // every block's mean is removed
/// ```
///
/// # Errors
/// [`SpectrumError::TooSmall`] when the smaller side is below 3.
pub fn welch_psd(
    channel: ArrayView2<'_, f64>,
    fft: &mut Fft2<f64>,
) -> Result<Array2<f64>, SpectrumError> {
    let (h, w) = channel.dim();
    let t = welch_block_size(h, w)?;
    welch_psd_with_block(channel, t, fft)
}

/// [`welch_psd`] with an explicit block size `t` (to compare images of different sizes on one
/// frequency grid: a large render against its exemplar's `T`, say).
///
/// # Errors
/// [`SpectrumError::TooSmall`] when `t < 2` or the image is smaller than `t` on a side.
pub fn welch_psd_with_block(
    channel: ArrayView2<'_, f64>,
    t: usize,
    fft: &mut Fft2<f64>,
) -> Result<Array2<f64>, SpectrumError> {
    let (h, w) = channel.dim();
    if t < 2 || h < t || w < t {
        return Err(SpectrumError::TooSmall {
            parameter: "image for a Welch power spectrum with this block size",
            width: w,
            height: h,
            min_width: t.max(2),
            min_height: t.max(2),
        });
    }
    let win = hann(t);
    let win_energy: f64 = win.iter().map(|a| a * a).sum::<f64>().powi(2);
    let win_sum: f64 = win.iter().sum::<f64>().powi(2);
    let mut acc = Array2::<f64>::zeros((t, t));
    let mut buf = Array2::<Complex64>::zeros((t, t));
    let (ys, xs) = (welch_block_starts(h, t), welch_block_starts(w, t));
    for &y0 in &ys {
        for &x0 in &xs {
            let block = channel.slice(s![y0..y0 + t, x0..x0 + t]);
            let mean = block
                .indexed_iter()
                .map(|((y, x), v)| v * win[y] * win[x])
                .sum::<f64>()
                / win_sum;
            for ((idx, b), v) in buf.indexed_iter_mut().zip(block.iter()) {
                *b = Complex64::new((v - mean) * win[idx.0] * win[idx.1], 0.0);
            }
            fft.forward(&mut buf);
            acc.zip_mut_with(&buf, |a, c| *a += c.norm_sqr());
        }
    }
    let blocks = (ys.len() * xs.len()) as f64;
    acc.mapv_inplace(|a| a / (blocks * win_energy));
    Ok(acc)
}

/// The spectrum of variance: the Welch power spectrum of the squared, centred signal
/// `(h − mean h)²`. Where the plain spectrum shows which frequencies oscillate, this one shows
/// how the local energy (the "intensity") fluctuates: a stationary noise of constant contrast
/// has little low-frequency energy here (Tricard et al. 2019, §3.1.3).
///
/// # Errors
/// As [`welch_psd`].
pub fn variance_spectrum(
    channel: ArrayView2<'_, f64>,
    fft: &mut Fft2<f64>,
) -> Result<Array2<f64>, SpectrumError> {
    let mean = channel.mean().unwrap_or(0.0);
    let sq = channel.mapv(|v| (v - mean) * (v - mean));
    welch_psd(sq.view(), fft)
}

/// The centred log-magnitude spectrum `ln(1 + |DFT(channel)|)` with the zero frequency at
/// `(H/2, W/2)`, for display.
#[must_use]
pub fn log_magnitude_spectrum(channel: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> Array2<f64> {
    let mut z = channel.mapv(|v| Complex64::new(v, 0.0));
    fft.forward(&mut z);
    crate::centered(z.mapv(|c| c.norm().ln_1p()).view())
}

/// One ring of a [`radial_profile`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialBin {
    /// Centre of the ring, in cycles per pixel.
    pub radius: f64,
    /// Mean power over the frequencies of the ring.
    pub power: f64,
    /// Number of frequencies in the ring.
    pub count: usize,
}

/// The radial power profile of an uncentred power spectrum: the mean power over rings of width
/// `1/max(H, W)` cycles per pixel. Ring `i` holds the frequencies whose radius
/// `|ξ| = √(f_y² + f_x²)` (signed frequencies in cycles per pixel) rounds to `i / max(H, W)`; it
/// runs out to the corner frequency (½√2 cycles per pixel for a square spectrum). Empty rings
/// are left out.
#[must_use]
pub fn radial_profile(psd: ArrayView2<'_, f64>) -> Vec<RadialBin> {
    let (h, w) = psd.dim();
    let n = h.max(w) as f64;
    let mut sums: Vec<(f64, usize)> = Vec::new();
    for ((k, l), &p) in psd.indexed_iter() {
        let (fy, fx) = (signed_frequency(k, h), signed_frequency(l, w));
        let bin = ((fy * fy + fx * fx).sqrt() * n).round() as usize;
        if sums.len() <= bin {
            sums.resize(bin + 1, (0.0, 0));
        }
        sums[bin].0 += p;
        sums[bin].1 += 1;
    }
    sums.into_iter()
        .enumerate()
        .filter(|(_, (_, c))| *c > 0)
        .map(|(i, (s, c))| RadialBin {
            radius: i as f64 / n,
            power: s / c as f64,
            count: c,
        })
        .collect()
}
