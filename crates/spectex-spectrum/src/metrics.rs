//! Measurements on images and spectra that the fidelity tests and `spectex-reproduce` share:
//! the spectral shape distance, moments, radial log–log slopes and the low-frequency share of
//! the spectrum of variance. One definition each, so a claim measured in a test and in the
//! reproduction report is the same number.

use ndarray::{Array2, ArrayView2};
use num_complex::Complex64;

use crate::{Fft2, RadialBin, radial_profile, signed_frequency};

/// Mean and (population) variance of an image.
#[must_use]
pub fn mean_variance(a: ArrayView2<'_, f64>) -> (f64, f64) {
    let n = a.len().max(1) as f64;
    let m = a.sum() / n;
    (m, a.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n)
}

/// `E[(v − μ)⁴]/σ⁴ − 3`: 0 for a Gaussian noise; sparse convolution with few impulses is
/// heavy-tailed, a sum of many random-phase cosines is not.
#[must_use]
pub fn excess_kurtosis(a: ArrayView2<'_, f64>) -> f64 {
    let (m, v) = mean_variance(a);
    a.iter().map(|x| (x - m).powi(4)).sum::<f64>() / a.len().max(1) as f64 / (v * v) - 3.0
}

/// An uncentred power spectrum scaled to unit sum with the zero frequency removed and smoothed
/// with a periodic 5×5 box: a periodogram average still fluctuates bin to bin; smoothing
/// compares shapes.
#[must_use]
pub fn normalised_smoothed(p: ArrayView2<'_, f64>) -> Array2<f64> {
    let (h, w) = p.dim();
    let mut q = p.to_owned();
    q[[0, 0]] = 0.0;
    let s = Array2::from_shape_fn((h, w), |(y, x)| {
        let mut acc = 0.0;
        for dy in 0..5 {
            for dx in 0..5 {
                acc += q[[(y + h + dy - 2) % h, (x + w + dx - 2) % w]];
            }
        }
        acc
    });
    let total = s.sum();
    s.mapv(|v| v / total)
}

/// The spectral shape distance: `Σ|a − b|` of the two spectra after [`normalised_smoothed`], in
/// `[0, 2]` (0: same shape; 2: disjoint supports). Both spectra on the same frequency grid.
#[must_use]
pub fn shape_distance(a: ArrayView2<'_, f64>, b: ArrayView2<'_, f64>) -> f64 {
    let (a, b) = (normalised_smoothed(a), normalised_smoothed(b));
    a.iter().zip(b.iter()).map(|(x, y)| (x - y).abs()).sum()
}

/// The least-squares line through `(ln radius, ln power)` of the radial profile bins whose
/// radius lies in `[lo, hi]` cycles per pixel (bins of zero power left out): `(slope,
/// intercept, bins used)`. A spectrum `P ∝ f^(−2β)` has slope `−2β`.
#[must_use]
pub fn log_log_fit(psd: ArrayView2<'_, f64>, lo: f64, hi: f64) -> (f64, f64, Vec<RadialBin>) {
    let bins: Vec<RadialBin> = radial_profile(psd)
        .into_iter()
        .filter(|b| b.radius >= lo && b.radius <= hi && b.power > 0.0)
        .collect();
    let n = bins.len() as f64;
    let (mx, my) = (
        bins.iter().map(|b| b.radius.ln()).sum::<f64>() / n,
        bins.iter().map(|b| b.power.ln()).sum::<f64>() / n,
    );
    let sxy: f64 = bins
        .iter()
        .map(|b| (b.radius.ln() - mx) * (b.power.ln() - my))
        .sum();
    let sxx: f64 = bins.iter().map(|b| (b.radius.ln() - mx).powi(2)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx, bins)
}

/// Spectrum of variance, low-frequency share (Tricard et al. 2019, §3.1.3): the image is
/// centred and scaled to unit variance, squared, and the fraction of the squared signal's
/// `|DFT|²` (zero frequency excluded) that lies strictly inside the disc `|f| < cutoff` cycles
/// per pixel. A noise whose local contrast fluctuates (Gabor noise) has a central lobe there.
#[must_use]
pub fn variance_low_fraction(a: ArrayView2<'_, f64>, cutoff: f64, fft: &mut Fft2<f64>) -> f64 {
    let (h, w) = a.dim();
    let (m, v) = mean_variance(a);
    let sd = v.sqrt();
    let mut c = a.mapv(|x| Complex64::new(((x - m) / sd).powi(2), 0.0));
    let mean_sq = c.iter().map(|z| z.re).sum::<f64>() / c.len() as f64;
    c.mapv_inplace(|z| Complex64::new(z.re - mean_sq, 0.0));
    fft.forward(&mut c);
    let (mut low, mut total) = (0.0, 0.0);
    for ((y, x), z) in c.indexed_iter() {
        if y == 0 && x == 0 {
            continue;
        }
        let p = z.norm_sqr();
        total += p;
        if signed_frequency(x, w).hypot(signed_frequency(y, h)) < cutoff {
            low += p;
        }
    }
    low / total
}

/// The peak of the ring-summed power spectrum `|DFT|²` of a square image (mean removed), in
/// cycles per pixel: the radius (a multiple of `1/side`) whose ring holds the most power.
#[must_use]
pub fn ring_power_peak(a: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> f64 {
    let (h, w) = a.dim();
    let side = h.max(w);
    let (m, _) = mean_variance(a);
    let mut c = a.mapv(|x| Complex64::new(x - m, 0.0));
    fft.forward(&mut c);
    let mut rings = vec![0.0; side / 2];
    for ((y, x), z) in c.indexed_iter() {
        let r = signed_frequency(x, w).hypot(signed_frequency(y, h));
        let k = (r * side as f64).round() as usize;
        if k < rings.len() {
            rings[k] += z.norm_sqr();
        }
    }
    let peak = (1..rings.len())
        .max_by(|&a, &b| rings[a].total_cmp(&rings[b]))
        .unwrap_or(0);
    peak as f64 / side as f64
}

/// `Φ(x)`, the standard normal CDF, from `erfc`.
#[must_use]
pub fn standard_normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// `Φ⁻¹(p)` for `p ∈ (0, 1)`: Acklam's rational approximation (relative error 1.2·10⁻⁹) and one
/// Halley step on `Φ` (full f64 precision).
#[must_use]
pub fn standard_normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < 0.024_25 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.024_25 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    let e = standard_normal_cdf(x) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

/// The fraction of pixels above the threshold a user would set to keep `1 − p` of a Gaussian
/// noise white: `mean + σ·Φ⁻¹(p)`, with the image's own mean and standard deviation (so only
/// its departure from a Gaussian shape moves the fraction away from `1 − p`).
#[must_use]
pub fn fraction_above_gaussian_quantile(a: ArrayView2<'_, f64>, p: f64) -> f64 {
    let (m, v) = mean_variance(a);
    let t = m + v.sqrt() * standard_normal_quantile(p);
    a.iter().filter(|&&x| x > t).count() as f64 / a.len().max(1) as f64
}

/// Rec. 709 luminance of a `(channel, row, column)` colour image (`0.2126 R + 0.7152 G +
/// 0.0722 B`, summed in that order), or the single channel of a grey one: what the `spectex`
/// command and the Python package analyse and use as grey levels.
#[must_use]
pub fn luminance(img: ndarray::ArrayView3<'_, f64>) -> Array2<f64> {
    use ndarray::Axis;
    if img.dim().0 == 1 {
        return img.index_axis(Axis(0), 0).to_owned();
    }
    let mut y = Array2::zeros((img.dim().1, img.dim().2));
    for (c, wc) in [0.2126, 0.7152, 0.0722].iter().enumerate() {
        y.scaled_add(*wc, &img.index_axis(Axis(0), c));
    }
    y
}

/// The Wasserstein-1 distance between the empirical distributions of two samples (any sizes):
/// `∫₀¹ |Q_a(p) − Q_b(p)| dp` of their quantile functions, each the sorted sample read at rank
/// `p·n − ½` (linear between ranks, clamped), by the midpoint rule on `4·max(n_a, n_b)` points.
/// In the samples' unit (grey levels for values scaled to 0–255); 0 for an empty sample.
#[must_use]
pub fn wasserstein1(a: &[f64], b: &[f64]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 0.0;
    }
    let sorted = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        s
    };
    let (a, b) = (sorted(a), sorted(b));
    let quantile = |s: &[f64], p: f64| {
        let n = s.len();
        let r = (p * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
        let i = (r.floor() as usize).min(n.saturating_sub(2));
        let hi = s[(i + 1).min(n - 1)];
        s[i] + (r - i as f64) * (hi - s[i])
    };
    let m = 4 * a.len().max(b.len());
    (0..m)
        .map(|k| {
            let p = (k as f64 + 0.5) / m as f64;
            (quantile(&a, p) - quantile(&b, p)).abs()
        })
        .sum::<f64>()
        / m as f64
}

/// Gradient magnitudes `√(∂x² + ∂y²)` of an image by central differences
/// (`∂x = (a[y][x+1] − a[y][x−1])/2`) at its interior pixels: `(h − 2) × (w − 2)` values.
#[must_use]
pub fn gradient_magnitudes(a: ArrayView2<'_, f64>) -> Array2<f64> {
    let (h, w) = a.dim();
    if h < 3 || w < 3 {
        return Array2::zeros((0, 0));
    }
    Array2::from_shape_fn((h - 2, w - 2), |(y, x)| {
        let (y, x) = (y + 1, x + 1);
        let dx = (a[[y, x + 1]] - a[[y, x - 1]]) / 2.0;
        let dy = (a[[y + 1, x]] - a[[y - 1, x]]) / 2.0;
        dx.hypot(dy)
    })
}
