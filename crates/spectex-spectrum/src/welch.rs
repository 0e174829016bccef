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

#[cfg(test)]
mod tests {
    use super::*;
    use spectex_model::random::{Prng, cell_hash};

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
}
