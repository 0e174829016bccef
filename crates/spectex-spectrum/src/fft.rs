//! Two-dimensional FFTs over `ndarray` with `rustfft`: row–column transforms whose plans are
//! cached by the planner and whose scratch and transpose buffers are reused between calls.

use ndarray::{Array2, ArrayView2};
use num_complex::Complex;
use rustfft::{FftDirection, FftNum, FftPlanner};

/// The sample types [`Fft2`] transforms: `f64` (sealed; another type would be one more
/// `fft_float!` line, and a minute more of this crate's compilation).
///
/// Why a trait and not `Fft2<T: FftNum>` alone: the transform's body plans with rustfft, whose
/// algorithms (every radix, SIMD level and size class) are generic over the sample type. A generic
/// `Fft2` method would be compiled again, with all of them, in every crate and test binary that
/// calls it (generics are not shared across crates in optimised builds): about a minute of
/// compilation each on a 2-core machine. Each type's transform is instead one non-generic
/// function compiled here once, that callers link to.
pub trait FftFloat: FftNum + sealed::Sealed {
    /// A new planner ([`Fft2::new`]): rustfft's constructor, generic too, is compiled here.
    #[doc(hidden)]
    fn planner() -> FftPlanner<Self>;

    /// Transforms a row-major `height × width` buffer in place ([`Fft2::process_slice`]).
    #[doc(hidden)]
    fn process_slice(
        engine: &mut Fft2<Self>,
        data: &mut [Complex<Self>],
        height: usize,
        width: usize,
        direction: FftDirection,
    );
}

mod sealed {
    pub trait Sealed {}
}

/// `FftFloat` for one sample type: the generic bodies instantiated here, once.
macro_rules! fft_float {
    ($t:ty) => {
        impl sealed::Sealed for $t {}

        impl FftFloat for $t {
            fn planner() -> FftPlanner<Self> {
                FftPlanner::new()
            }

            fn process_slice(
                engine: &mut Fft2<Self>,
                data: &mut [Complex<Self>],
                height: usize,
                width: usize,
                direction: FftDirection,
            ) {
                engine.process_slice_generic(data, height, width, direction);
            }
        }
    };
}

fft_float!(f64);

/// A reusable 2D FFT engine.
///
/// Holds a [`FftPlanner`] (which caches one plan per length and direction) and the scratch and
/// transpose buffers, so transforming many images of the same size allocates nothing after the
/// first. The transform is the unnormalised DFT
/// `X[k, l] = Σ_y Σ_x x[y, x] · exp(∓2πi (k·y/H + l·x/W))`, with `−` forward and `+` inverse;
/// [`Fft2::inverse_normalized`] divides by `H·W` so that it inverts [`Fft2::forward`].
///
/// ```
/// use ndarray::Array2;
/// use num_complex::Complex64;
/// use spectex_spectrum::Fft2;
///
/// let mut fft = Fft2::<f64>::new();
/// let original = Array2::from_shape_fn((6, 10), |(y, x)| Complex64::new((y * 10 + x) as f64, 0.0));
/// let mut a = original.clone();
/// fft.forward(&mut a);
/// assert!((a[[0, 0]].re - original.iter().map(|c| c.re).sum::<f64>()).abs() < 1e-9);
/// fft.inverse_normalized(&mut a);
/// assert!(a.iter().zip(&original).all(|(p, q)| (p - q).norm() < 1e-9));
/// ```
pub struct Fft2<T: FftFloat> {
    planner: FftPlanner<T>,
    scratch: Vec<Complex<T>>,
    transposed: Vec<Complex<T>>,
}

impl<T: FftFloat> Default for Fft2<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: FftFloat> std::fmt::Debug for Fft2<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fft2")
            .field("scratch_len", &self.scratch.len())
            .field("transposed_len", &self.transposed.len())
            .finish_non_exhaustive()
    }
}

impl<T: FftFloat> Fft2<T> {
    /// A new engine with an empty plan cache.
    #[must_use]
    pub fn new() -> Self {
        Self {
            planner: T::planner(),
            scratch: Vec::new(),
            transposed: Vec::new(),
        }
    }

    /// Forward DFT in place.
    pub fn forward(&mut self, data: &mut Array2<Complex<T>>) {
        self.process(data, FftDirection::Forward);
    }

    /// Unnormalised inverse DFT in place (`inverse(forward(x)) = H·W·x`).
    pub fn inverse(&mut self, data: &mut Array2<Complex<T>>) {
        self.process(data, FftDirection::Inverse);
    }

    /// Inverse DFT in place, divided by `H·W`, so that it undoes [`Fft2::forward`].
    pub fn inverse_normalized(&mut self, data: &mut Array2<Complex<T>>) {
        self.process(data, FftDirection::Inverse);
        let n = data.len();
        let scale = T::one() / T::from_usize(n).unwrap_or_else(T::one);
        data.mapv_inplace(|c| c * scale);
    }

    /// Transforms `data` in place in the given direction.
    pub fn process(&mut self, data: &mut Array2<Complex<T>>, direction: FftDirection) {
        if !data.is_standard_layout() {
            *data = data.as_standard_layout().into_owned();
        }
        let (height, width) = data.dim();
        if let Some(slice) = data.as_slice_mut() {
            self.process_slice(slice, height, width, direction);
        }
    }

    /// Transforms a row-major `height × width` buffer in place.
    ///
    /// # Panics
    /// If `data.len() != height * width`: that is a caller bug, not an input error.
    pub fn process_slice(
        &mut self,
        data: &mut [Complex<T>],
        height: usize,
        width: usize,
        direction: FftDirection,
    ) {
        T::process_slice(self, data, height, width, direction);
    }

    /// The body of [`Fft2::process_slice`], instantiated only by [`FftFloat`]'s impls.
    fn process_slice_generic(
        &mut self,
        data: &mut [Complex<T>],
        height: usize,
        width: usize,
        direction: FftDirection,
    ) {
        assert_eq!(data.len(), height * width, "buffer is not height × width");
        if data.is_empty() {
            return;
        }
        let row_fft = self.planner.plan_fft(width, direction);
        let col_fft = self.planner.plan_fft(height, direction);
        let scratch_len = row_fft
            .get_inplace_scratch_len()
            .max(col_fft.get_inplace_scratch_len());
        if self.scratch.len() < scratch_len {
            self.scratch
                .resize(scratch_len, Complex::new(T::zero(), T::zero()));
        }
        if self.transposed.len() < data.len() {
            self.transposed
                .resize(data.len(), Complex::new(T::zero(), T::zero()));
        }
        let transposed = &mut self.transposed[..data.len()];

        // All rows in one call: rustfft processes consecutive chunks of the plan's length.
        if width > 1 {
            row_fft.process_with_scratch(data, &mut self.scratch[..scratch_len]);
        }
        if height > 1 {
            // Columns become rows of the transpose, so every 1D transform runs on contiguous
            // memory; `transpose` is cache-blocked, which matters once an image exceeds L2.
            transpose::transpose(data, transposed, width, height);
            col_fft.process_with_scratch(transposed, &mut self.scratch[..scratch_len]);
            transpose::transpose(transposed, data, height, width);
        }
    }
}

/// Moves the zero frequency to the centre, at `(H/2, W/2)` (rounded down), like NumPy's
/// `fftshift`: `out[(k + H/2) mod H, (l + W/2) mod W] = a[k, l]`.
#[must_use]
pub fn centered<T: Clone>(a: ArrayView2<'_, T>) -> Array2<T> {
    let (h, w) = a.dim();
    Array2::from_shape_fn((h, w), |(y, x)| {
        a[[(y + h - h / 2) % h, (x + w - w / 2) % w]].clone()
    })
}

/// The signed frequency of DFT index `k` of a length-`n` transform, in cycles per sample:
/// `k/n` for `k ≤ n/2`, `(k − n)/n` above.
#[must_use]
pub fn signed_frequency(k: usize, n: usize) -> f64 {
    let k = if 2 * k <= n {
        k as f64
    } else {
        k as f64 - n as f64
    };
    k / n as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::ShapeBuilder;
    use num_complex::Complex64;
    use spectex_model::random::{Prng, cell_hash};

    /// The definition: `X[k, l] = Σ_y Σ_x x[y, x] e^{−2πi(ky/H + lx/W)}` evaluated in f64, with the
    /// angle reduced exactly in integers before the trigonometric call.
    fn naive_dft_at(x: &Array2<Complex64>, k: usize, l: usize, sign: f64) -> Complex64 {
        let (h, w) = x.dim();
        let mut sum = Complex64::new(0.0, 0.0);
        for y in 0..h {
            for xx in 0..w {
                // (k·y/H + l·x/W) mod 1, as an exact integer fraction over H·W.
                let num = ((k * y) % h) * w + ((l * xx) % w) * h;
                let turns = (num % (h * w)) as f64 / (h * w) as f64;
                let angle = sign * 2.0 * std::f64::consts::PI * turns;
                sum += x[[y, xx]] * Complex64::new(angle.cos(), angle.sin());
            }
        }
        sum
    }

    fn random_image(h: usize, w: usize, seed: u32) -> Array2<Complex64> {
        let mut prng = Prng::new(cell_hash(h as i32, w as i32, 0, seed));
        Array2::from_shape_fn((h, w), |_| {
            Complex64::new(prng.next_f64() - 0.5, prng.next_f64() - 0.5)
        })
    }

    /// Frequencies to check: all of them for small sizes, a fixed pseudo-random subset of 300
    /// (plus the corners) for large ones, where the O((HW)²) definition would take minutes.
    fn frequencies(h: usize, w: usize, seed: u32) -> Vec<(usize, usize)> {
        if h * w <= 64 * 64 {
            return (0..h).flat_map(|k| (0..w).map(move |l| (k, l))).collect();
        }
        let mut prng = Prng::new(seed);
        let mut f = vec![
            (0, 0),
            (h - 1, w - 1),
            (h / 2, w / 2),
            (0, w / 2),
            (h / 2, 0),
        ];
        f.extend((0..300).map(|_| (prng.next_u32() as usize % h, prng.next_u32() as usize % w)));
        f
    }

    fn sizes() -> Vec<(usize, usize)> {
        let mut s: Vec<(usize, usize)> = (1..=17).map(|n| (n, n)).collect();
        s.extend([(1, 7), (9, 1), (30, 45), (45, 30), (64, 64), (300, 300)]);
        s
    }

    fn check<T: FftFloat + Into<f64>>(tolerance: f64, to_t: impl Fn(f64) -> T) {
        let mut fft = Fft2::<T>::new();
        for (seed, (h, w)) in sizes().into_iter().enumerate() {
            let x = random_image(h, w, seed as u32);
            let mut a: Array2<Complex<T>> = x.mapv(|c| Complex::new(to_t(c.re), to_t(c.im)));
            // Compare against the definition applied to the values actually transformed.
            let x64 = a.mapv(|c| Complex64::new(c.re.into(), c.im.into()));
            let norm = x64.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
            fft.forward(&mut a);
            for &(k, l) in &frequencies(h, w, seed as u32) {
                let want = naive_dft_at(&x64, k, l, -1.0);
                let got = Complex64::new(a[[k, l]].re.into(), a[[k, l]].im.into());
                let err = (got - want).norm() / norm.max(1e-300);
                assert!(
                    err <= tolerance,
                    "forward {h}×{w} seed {seed}: first bad frequency ({k}, {l}): got {got}, \
                     want {want}, relative error {err:e} > {tolerance:e}"
                );
            }
            // Inverse: the definition with + sign, on the forward output.
            let spectrum = a.mapv(|c| Complex64::new(c.re.into(), c.im.into()));
            let snorm = spectrum.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
            fft.inverse(&mut a);
            for &(k, l) in &frequencies(h, w, seed as u32 + 1000) {
                let want = naive_dft_at(&spectrum, k, l, 1.0);
                let got = Complex64::new(a[[k, l]].re.into(), a[[k, l]].im.into());
                let err = (got - want).norm() / snorm.max(1e-300);
                assert!(
                    err <= tolerance,
                    "inverse {h}×{w} seed {seed}: first bad index ({k}, {l}): got {got}, \
                     want {want}, relative error {err:e} > {tolerance:e}"
                );
            }
        }
    }

    /// Relative to the input's L2 norm, a single output coefficient's error is bounded by the
    /// accumulated rounding of O(log n) butterfly stages: ~1e-15 in f64.
    #[test]
    fn forward_and_inverse_match_the_definition_f64() {
        check::<f64>(1e-13, |v| v);
    }

    #[test]
    fn plans_and_buffers_are_reused() {
        let mut fft = Fft2::<f64>::new();
        let mut a = random_image(32, 48, 1);
        fft.forward(&mut a);
        let (s, t) = (fft.scratch.as_ptr(), fft.transposed.as_ptr());
        let mut b = random_image(32, 48, 2);
        fft.forward(&mut b);
        fft.inverse(&mut b);
        assert_eq!(s, fft.scratch.as_ptr(), "scratch was reallocated");
        assert_eq!(
            t,
            fft.transposed.as_ptr(),
            "transpose buffer was reallocated"
        );
    }

    #[test]
    fn non_standard_layout_is_handled() {
        let x = random_image(8, 12, 3);
        let mut fft = Fft2::<f64>::new();
        let mut a = x.clone();
        fft.forward(&mut a);
        let mut t = Array2::zeros((8, 12).f()); // same values, Fortran layout
        t.assign(&x);
        assert!(!t.is_standard_layout());
        fft.forward(&mut t);
        assert!(a.iter().zip(t.iter()).all(|(p, q)| (p - q).norm() < 1e-12));
    }

    #[test]
    fn centered_puts_dc_in_the_middle() {
        for (h, w) in [(4, 4), (5, 7), (1, 3)] {
            let a = Array2::from_shape_fn((h, w), |(y, x)| (y, x));
            let c = centered(a.view());
            assert_eq!(c[[h / 2, w / 2]], (0, 0), "{h}×{w}");
        }
    }

    #[test]
    fn signed_frequencies() {
        assert_eq!(signed_frequency(0, 8), 0.0);
        assert_eq!(signed_frequency(4, 8), 0.5);
        assert_eq!(signed_frequency(5, 8), -3.0 / 8.0);
        assert_eq!(signed_frequency(3, 7), 3.0 / 7.0);
        assert_eq!(signed_frequency(4, 7), -3.0 / 7.0);
    }
}
