//! Random Phase Noise (Galerne, Gousseau & Morel, IPOL): texture synthesis by randomising the
//! Fourier phase of a sample's periodic component, at the sample's size or larger through the
//! spot extension, and the asymptotic discrete spot noise (ADSN) variant.
//!
//! All colour channels share **one** random phase field, which keeps the phase displacements
//! between channels and so creates no false colours. Channels are transformed two at a time,
//! packed as the real and imaginary parts of one complex image: since every spectrum involved
//! is Hermitian and the phase factor is too, `IDFT((P̂₀ + iP̂₁)·e^{iθ}) = u₀ + i·u₁` with `u₀, u₁`
//! real, so an RGB same-size RPN costs four FFTs (two per pair) instead of six.
//!
//! Randomness follows the contract of `spectex_model::random`: the phase at frequency `(k, l)`
//! is a pure function of `(l, k, seed)`, so a result never depends on thread count or order.

use ndarray::{Array2, Array3, ArrayView2, ArrayView3, Zip, s};
use num_complex::Complex64;
use rayon::prelude::*;
use spectex_model::random::{
    Prng, cell_hash, cell_hash_in_row, layer_key, open_unit_f64, row_key, unit_f64,
};

use crate::periodic::{periodic_pair, periodic_spectrum_packed_times};
use crate::{Fft2, SpectrumError};

/// Layer of the randomness contract used for RPN phases.
pub const PHASE_LAYER: u32 = 0;
/// Layer of the randomness contract used for the Gaussian white noise of ADSN.
pub const ADSN_NOISE_LAYER: u32 = 1;

/// Largest side of an RPN output, in pixels.
pub const MAX_SIDE: usize = 16_384;
/// Largest pixel count of an RPN output (8192²). The synthesis holds about 40 bytes per pixel
/// per channel pair in complex f64 buffers, so this stays near 2.7 GiB for RGB.
pub const MAX_PIXELS: usize = 8192 * 8192;
/// Most channels accepted (grey, grey + alpha, RGB, RGBA all fit).
pub const MAX_CHANNELS: usize = 4;

/// The paper's value of the spot extension's transition width `a` ("fixed to a = 0.1").
pub const DEFAULT_TRANSITION: f64 = 0.1;

/// What kind of noise to synthesise from the (extended) spot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum NoiseKind {
    /// Random Phase Noise: the spot's DFT modulus with a uniform random phase.
    #[default]
    RandomPhase,
    /// Asymptotic discrete spot noise: the normalised spot convolved with Gaussian white noise,
    /// `u = m + (s − m) ⊛ W / √(HW)`; the modulus is then random too (Rayleigh-distributed).
    Adsn,
}

/// Options of [`Rpn::synthesize`].
#[derive(Debug, Clone, PartialEq)]
pub struct RpnOptions {
    /// Output `(width, height)`; `None` keeps the input's size. A larger size uses the spot
    /// extension; each side must be at least the input's.
    pub size: Option<(usize, usize)>,
    /// Seed of the random phase (or of the white noise for ADSN).
    pub seed: u32,
    /// Random phase noise or ADSN.
    pub kind: NoiseKind,
    /// Width `a` of the spot extension's smooth transition, as a fraction of each side,
    /// in `(0, 0.5]`.
    pub transition: f64,
}

impl Default for RpnOptions {
    fn default() -> Self {
        Self {
            size: None,
            seed: 0,
            kind: NoiseKind::RandomPhase,
            transition: DEFAULT_TRANSITION,
        }
    }
}

/// Checks an image given as `(channel, row, column)` before synthesis or analysis.
///
/// # Errors
/// Too few channels or too many, fewer than 2×2 pixels, beyond [`MAX_SIDE`] / [`MAX_PIXELS`],
/// or a non-finite value.
pub fn validate_image(
    parameter: &'static str,
    image: ArrayView3<'_, f64>,
) -> Result<(), SpectrumError> {
    let (c, h, w) = image.dim();
    if c == 0 || c > MAX_CHANNELS {
        return Err(SpectrumError::Channels {
            parameter,
            channels: c,
            max: MAX_CHANNELS,
        });
    }
    check_size(parameter, w, h, 2, 2)?;
    // A quick pass over the values first; the slow indexed search runs only on failure.
    if image.iter().all(|v| v.is_finite()) {
        return Ok(());
    }
    if let Some(((channel, row, column), &value)) =
        image.indexed_iter().find(|(_, v)| !v.is_finite())
    {
        return Err(SpectrumError::NonFinite {
            parameter,
            value,
            channel,
            row,
            column,
        });
    }
    Ok(())
}

fn check_size(
    parameter: &'static str,
    width: usize,
    height: usize,
    min_width: usize,
    min_height: usize,
) -> Result<(), SpectrumError> {
    if width < min_width || height < min_height {
        return Err(SpectrumError::TooSmall {
            parameter,
            width,
            height,
            min_width,
            min_height,
        });
    }
    if width > MAX_SIDE || height > MAX_SIDE || width.saturating_mul(height) > MAX_PIXELS {
        return Err(SpectrumError::TooLarge {
            parameter,
            width,
            height,
            max_side: MAX_SIDE,
            max_pixels: MAX_PIXELS,
        });
    }
    Ok(())
}

/// The random phase factor `e^{iθ(ξ)}` of an `height × width` DFT grid (zero frequency at
/// `[0, 0]`).
///
/// `θ` is uniform on `[0, 2π)` and odd: `θ(−ξ) = −θ(ξ)` (indices mod size), so adding it to a
/// Hermitian spectrum keeps the inverse transform real. Of each pair `{ξ, −ξ}` the
/// lexicographically smaller index `(k, l)` draws `θ = 2π · unit_f64(cell_hash(l, k, 0, seed))`.
/// A self-symmetric frequency (`ξ = −ξ`: the zero frequency and, for even sides, the
/// Nyquist ones) must have a real factor: the zero frequency gets `1`, which keeps the mean,
/// and the others `±1`, uniform, from the top bit of the same hash.
#[must_use]
pub fn random_phase_field(height: usize, width: usize, seed: u32) -> Array2<Complex64> {
    let mut out = Array2::<Complex64>::zeros((height, width));
    let key = layer_key(PHASE_LAYER, seed);
    // Rows `k ≤ H/2` are computed; the rest mirror them. Each row is a pure function of its
    // index, so the rows are filled in parallel with the same result for any thread count.
    let canonical_rows = height / 2 + 1;
    let (top, bottom) = out
        .as_slice_mut()
        .expect("fresh arrays are contiguous")
        .split_at_mut(canonical_rows.min(height) * width);
    top.par_chunks_mut(width.max(1))
        .enumerate()
        .for_each(|(k, row)| {
            let km = (height - k) % height;
            let rk = row_key(k as i32, key);
            for (l, v) in row.iter_mut().enumerate() {
                let bits = cell_hash_in_row(l as i32, rk);
                *v = unit_phasor(bits);
            }
            if k == km {
                // A self-mirrored row (k = 0, or k = H/2 for even H): its own second half
                // mirrors its first, and the self-symmetric frequencies get a real factor.
                for l in 0..width {
                    let lm = (width - l) % width;
                    if l == lm {
                        let bits = cell_hash_in_row(l as i32, rk);
                        let negative = (k, l) != (0, 0) && bits >> 31 == 1;
                        row[l] = Complex64::new(if negative { -1.0 } else { 1.0 }, 0.0);
                    } else if l > lm {
                        row[l] = row[lm].conj();
                    }
                }
            }
        });
    let top: &[Complex64] = top;
    bottom
        .par_chunks_mut(width.max(1))
        .enumerate()
        .for_each(|(i, row)| {
            let km = height - (canonical_rows + i);
            let source = &top[km * width..(km + 1) * width];
            for (l, v) in row.iter_mut().enumerate() {
                *v = source[(width - l) % width].conj();
            }
        });
    out
}

/// `e^{2πi·bits/2³²}`: the phase factor of a uniform 32-bit turn, to within 2e-15 (a few ulps).
///
/// Splits the 32 bits into 11 + 11 + 10 and multiplies three table entries
/// `e^{2πi·a/2¹¹}·e^{2πi·b/2²²}·e^{2πi·c/2³²}`, each computed once by `sin_cos` of an angle below
/// 2π. Two complex products cost a few nanoseconds where a libm `sin_cos` costs ~40, which keeps
/// the phase field cheaper than one FFT; the result differs from `sin_cos(2π·bits/2³²)` by a
/// few ulps (see the test `unit_phasor_matches_sin_cos`).
#[must_use]
pub fn unit_phasor(bits: u32) -> Complex64 {
    static TABLES: std::sync::OnceLock<[Vec<Complex64>; 3]> = std::sync::OnceLock::new();
    let [hi, mid, lo] = TABLES.get_or_init(|| {
        let table = |len: usize, denominator: f64| -> Vec<Complex64> {
            (0..len)
                .map(|j| {
                    let (sin, cos) =
                        (2.0 * std::f64::consts::PI * j as f64 / denominator).sin_cos();
                    Complex64::new(cos, sin)
                })
                .collect()
        };
        [
            table(1 << 11, 2048.0),
            table(1 << 11, 4_194_304.0),
            table(1 << 10, 4_294_967_296.0),
        ]
    });
    hi[(bits >> 21) as usize] * mid[((bits >> 10) & 0x7ff) as usize] * lo[(bits & 0x3ff) as usize]
}

/// The rows of a freshly created (standard-layout) array, as a parallel iterator.
fn rows_mut<T: Send>(a: &mut Array2<T>) -> rayon::slice::ChunksMut<'_, T> {
    let width = a.ncols().max(1);
    a.as_slice_mut()
        .expect("arrays created by Array2::zeros are contiguous")
        .par_chunks_mut(width)
}

/// Standard Gaussian white noise of the randomness contract: pixel `(x, y)` draws two uniforms
/// from `Prng::new(cell_hash(x, y, ADSN_NOISE_LAYER, seed))` and applies Box–Muller.
#[must_use]
pub fn gaussian_white_noise(height: usize, width: usize, seed: u32) -> Array2<f64> {
    let mut out = Array2::<f64>::zeros((height, width));
    rows_mut(&mut out).enumerate().for_each(|(y, row)| {
        for (x, v) in row.iter_mut().enumerate() {
            let mut prng = Prng::new(cell_hash(x as i32, y as i32, ADSN_NOISE_LAYER, seed));
            let u1 = open_unit_f64(prng.next_u32());
            let u2 = unit_f64(prng.next_u32());
            *v = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
        }
    });
    out
}

/// The smooth transition function `ψ_a` of the spot extension on `[0, 1]`.
///
/// On `[0, a]` it is the primitive of the C^∞ bump `t ↦ exp(−1/(1 − (2t/a − 1)²))`, scaled so
/// that `ψ_a(0) = 0` and `ψ_a(a) = 1`; it is `1` on `[a, 1 − a]` and symmetric on `[1 − a, 1]`.
/// Outside `[0, 1]` it is 0. The primitive is integrated by composite Simpson's rule on 512
/// intervals of the rescaled variable `u = 2t/a − 1 ∈ [−1, 1]`; the integrand is flat to all
/// orders at `±1`, so the rule converges far below f64 display precision.
#[must_use]
pub fn transition(t: f64, a: f64) -> f64 {
    if !(0.0..=1.0).contains(&t) {
        return 0.0;
    }
    let t = t.min(1.0 - t);
    if t >= a {
        return 1.0;
    }
    let v = 2.0 * t / a - 1.0;
    bump_integral(-1.0, v) / bump_integral(-1.0, 1.0)
}

fn bump(u: f64) -> f64 {
    let d = 1.0 - u * u;
    if d <= 0.0 { 0.0 } else { (-1.0 / d).exp() }
}

fn bump_integral(from: f64, to: f64) -> f64 {
    const N: usize = 512;
    let h = (to - from) / N as f64;
    let mut sum = bump(from) + bump(to);
    for i in 1..N {
        sum += bump(from + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0
}

/// `ψ_a((i + ½)/n)` for `i` in `0..n`: the transition sampled at pixel centres.
fn transition_axis(n: usize, a: f64) -> Vec<f64> {
    (0..n)
        .map(|i| transition((i as f64 + 0.5) / n as f64, a))
        .collect()
}

/// The extended spot of a periodic component `p` (channels × rows × columns) for an output of
/// `width × height` (spot extension of the RPN paper).
///
/// Each channel is `m` (the channel's mean) everywhere except in a centred `M × N` window
/// holding `m + g · ψ_a(x) ψ_a(y) · (p − m)`.
///
/// The paper takes `g = √(HW/(MN))` with the window normalised to unit mean square, which keeps
/// the variance only in a window-weighted sense: measured on the shared water photograph, that
/// output's variance is 10% above the sample's. Here the variance normalisation is made exact:
/// `g` is chosen per channel so that the spot's variance over the `width × height` domain is
/// `target_variance[c]`. By Parseval, and because the synthesis sets the zero frequency to the
/// mean, that is then exactly the variance of the RPN output. A per-channel gain leaves every
/// correlation coefficient between channels of the spot unchanged.
///
/// # Panics
/// If `target_variance` has fewer entries than there are channels, or the output is smaller
/// than `p` (caller bugs; [`Rpn::synthesize`] validates both).
#[must_use]
pub fn extended_spot(
    periodic: ArrayView3<'_, f64>,
    target_variance: &[f64],
    width: usize,
    height: usize,
    a: f64,
) -> Array3<f64> {
    let (channels, m, n) = periodic.dim();
    assert!(target_variance.len() >= channels && width >= n && height >= m);
    let (wy, wx) = (transition_axis(m, a), transition_axis(n, a));
    let (oy, ox) = ((height - m) / 2, (width - n) / 2);
    let area = (width * height) as f64;
    let mut spot = Array3::<f64>::zeros((channels, height, width));
    for ch in 0..channels {
        let p = periodic.slice(s![ch, .., ..]);
        let mean = p.mean().unwrap_or(0.0);
        // d = ψ(x)ψ(y)(p − m); the spot is m + g·d, whose variance over the output is
        // g²·(Σd²/HW − (Σd/HW)²).
        let d = Zip::indexed(&p).map_collect(|(y, x), &v| wy[y] * wx[x] * (v - mean));
        let (sum, sum_sq) = d.iter().fold((0.0, 0.0), |(s, q), v| (s + v, q + v * v));
        let unit_variance = sum_sq / area - (sum / area).powi(2);
        let gain = if unit_variance > 0.0 {
            (target_variance[ch] / unit_variance).sqrt()
        } else {
            0.0
        };
        let mut out = spot.slice_mut(s![ch, .., ..]);
        out.fill(mean);
        Zip::from(out.slice_mut(s![oy..oy + m, ox..ox + n]))
            .and(&d)
            .for_each(|o, &v| *o = mean + gain * v);
    }
    spot
}

/// Random Phase Noise engine: owns the FFT plans and buffers so repeated syntheses reuse them.
///
/// ```
/// use ndarray::Array3;
/// use spectex_spectrum::{Rpn, RpnOptions};
///
/// let sample = Array3::from_shape_fn((3, 32, 48), |(c, y, x)| ((x * 3 + y * 5 + c) % 7) as f64 / 7.0);
/// let mut rpn = Rpn::new();
/// let same = rpn.synthesize(sample.view(), &RpnOptions { seed: 7, ..Default::default() }).unwrap();
/// assert_eq!(same.dim(), (3, 32, 48));
/// let large = rpn.synthesize(sample.view(), &RpnOptions { size: Some((100, 80)), ..Default::default() }).unwrap();
/// assert_eq!(large.dim(), (3, 80, 100));
/// // The mean of every channel is kept.
/// for c in 0..3 {
///     let m0 = sample.index_axis(ndarray::Axis(0), c).mean().unwrap();
///     let m1 = large.index_axis(ndarray::Axis(0), c).mean().unwrap();
///     assert!((m0 - m1).abs() < 1e-9);
/// }
/// ```
#[derive(Debug, Default)]
pub struct Rpn {
    fft: Fft2<f64>,
}

impl Rpn {
    /// A new engine.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The FFT engine, for callers that want to share its plans.
    pub fn fft(&mut self) -> &mut Fft2<f64> {
        &mut self.fft
    }

    /// Synthesises a texture from `sample` (channels × rows × columns, any real values).
    ///
    /// At the sample's size: `DFT(p)·e^{iθ}` for each channel's periodic component `p` and one
    /// phase field `θ`; the output's variance is the periodic component's. Larger: the same on
    /// the [`extended_spot`], whose variance is normalised to the sample's, with the zero
    /// frequency set so that each channel's mean is exactly the sample's. With [`NoiseKind::Adsn`] the phase
    /// factor is replaced by `DFT(W)/√(HW)` of one Gaussian white noise `W` shared by all
    /// channels.
    ///
    /// # Errors
    /// A bad sample (see [`validate_image`]), an output side smaller than the sample's or beyond
    /// the limits, or a transition width outside `(0, 0.5]`.
    pub fn synthesize(
        &mut self,
        sample: ArrayView3<'_, f64>,
        options: &RpnOptions,
    ) -> Result<Array3<f64>, SpectrumError> {
        validate_image("sample", sample)?;
        let (channels, m, n) = sample.dim();
        let (width, height) = options.size.unwrap_or((n, m));
        check_size("output size", width, height, n, m)?;
        if !(options.transition > 0.0 && options.transition <= 0.5) {
            return Err(SpectrumError::OutOfRange {
                parameter: "transition width a",
                value: options.transition,
                range: "(0, 0.5]",
            });
        }
        let same_size = (width, height) == (n, m);
        let means: Vec<f64> = (0..channels)
            .map(|c| sample.slice(s![c, .., ..]).mean().unwrap_or(0.0))
            .collect();

        // The per-frequency factor shared by all channels.
        let factor = match options.kind {
            NoiseKind::RandomPhase => random_phase_field(height, width, options.seed),
            NoiseKind::Adsn => {
                let noise = gaussian_white_noise(height, width, options.seed);
                let mut z = noise.mapv(|v| Complex64::new(v, 0.0));
                self.fft.forward(&mut z);
                let scale = 1.0 / ((width * height) as f64).sqrt();
                z.mapv_inplace(|c| c * scale);
                z
            }
        };

        let spot = if same_size {
            None
        } else {
            let mut periodic = Array3::<f64>::zeros((channels, m, n));
            for c0 in (0..channels).step_by(2) {
                let second = (c0 + 1 < channels).then(|| sample.slice(s![c0 + 1, .., ..]));
                let (p0, p1) = periodic_pair(sample.slice(s![c0, .., ..]), second, &mut self.fft);
                periodic.slice_mut(s![c0, .., ..]).assign(&p0);
                if c0 + 1 < channels {
                    periodic.slice_mut(s![c0 + 1, .., ..]).assign(&p1);
                }
            }
            let variances: Vec<f64> = (0..channels)
                .map(|c| {
                    let ch = sample.slice(s![c, .., ..]);
                    ch.mapv(|v| (v - means[c]).powi(2)).mean().unwrap_or(0.0)
                })
                .collect();
            Some(extended_spot(
                periodic.view(),
                &variances,
                width,
                height,
                options.transition,
            ))
        };

        let mut out = Array3::<f64>::zeros((channels, height, width));
        let total = (width * height) as f64;
        for c0 in (0..channels).step_by(2) {
            let pair = c0 + 1 < channels;
            let mut z = match &spot {
                // At the sample's size the spot is the periodic component itself, whose DFT
                // the Poisson solver gives directly: one FFT per pair instead of three.
                None => periodic_spectrum_packed_times(
                    sample.slice(s![c0, .., ..]),
                    pair.then(|| sample.slice(s![c0 + 1, .., ..])),
                    Some(&factor),
                    &mut self.fft,
                ),
                Some(spot) => {
                    let first = spot.slice(s![c0, .., ..]);
                    let mut z = first.mapv(|v| Complex64::new(v, 0.0));
                    if pair {
                        Zip::from(&mut z)
                            .and(spot.slice(s![c0 + 1, .., ..]))
                            .for_each(|z, &v| z.im = v);
                    }
                    self.fft.forward(&mut z);
                    z.zip_mut_with(&factor, |z, f| *z *= f);
                    z
                }
            };
            // The mean is kept exactly: the zero frequency is the sample's mean times the area
            // (ADSN's factor there is random, and the extended spot's mean is only close to m).
            let m1 = if pair { means[c0 + 1] } else { 0.0 };
            z[[0, 0]] = Complex64::new(means[c0], m1) * total;
            self.fft.inverse(&mut z);
            let inv = 1.0 / total;
            Zip::from(out.slice_mut(s![c0, .., ..]))
                .and(&z)
                .for_each(|o, z| *o = z.re * inv);
            if pair {
                Zip::from(out.slice_mut(s![c0 + 1, .., ..]))
                    .and(&z)
                    .for_each(|o, z| *o = z.im * inv);
            }
        }
        Ok(out)
    }
}

/// Convenience wrapper: [`Rpn::synthesize`] with a fresh engine.
///
/// # Errors
/// As [`Rpn::synthesize`].
pub fn rpn(
    sample: ArrayView3<'_, f64>,
    options: &RpnOptions,
) -> Result<Array3<f64>, SpectrumError> {
    Rpn::new().synthesize(sample, options)
}

/// The DFT of one channel (complex result), used by tests and analyses that look at a single
/// channel's spectrum.
#[must_use]
pub fn dft(channel: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> Array2<Complex64> {
    let mut z = channel.mapv(|v| Complex64::new(v, 0.0));
    fft.forward(&mut z);
    z
}
