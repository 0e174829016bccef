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
    /// The addresses of the scratch and transpose buffers, for the test that they are reused
    /// between calls (`tests/it/unit/fft.rs`); not an API.
    #[doc(hidden)]
    #[must_use]
    pub fn buffer_addresses(&self) -> (usize, usize) {
        (
            self.scratch.as_ptr() as usize,
            self.transposed.as_ptr() as usize,
        )
    }

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
