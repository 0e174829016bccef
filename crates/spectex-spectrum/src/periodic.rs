//! Periodic + smooth decomposition of an image (Moisan, "Periodic plus smooth image
//! decomposition", 2011), as used by Random Phase Noise to remove the cross artefact of a
//! non-periodic sample.
//!
//! The periodic component `p` of `h` is the unique solution of `Δp = Δᵢh`, `mean(p) = mean(h)`,
//! where `Δ` is the periodic 4-neighbour Laplacian and `Δᵢ` the Laplacian restricted to the
//! image's interior (a border pixel has only its 3 or 2 neighbours inside). It is solved by the
//! FFT Poisson solver of the RPN paper: `p̂(ξ) = Δᵢĥ(ξ) / (2cos(2πk/H) + 2cos(2πl/W) − 4)` for
//! `ξ = (k, l) ≠ 0`, and `p̂(0) = ĥ(0) = Σh`. The smooth component is `s = h − p`.

use ndarray::{Array2, ArrayView2, CowArray, Ix2};
use num_complex::Complex64;

use crate::Fft2;

/// The Laplacian of `h` in the interior of its domain: `Σ_{n ∈ N(x) ∩ Ω} (h(n) − h(x))`.
#[must_use]
pub fn interior_laplacian(h: ArrayView2<'_, f64>) -> Array2<f64> {
    let (rows, cols) = h.dim();
    Array2::from_shape_fn((rows, cols), |(y, x)| {
        let c = h[[y, x]];
        let mut sum = 0.0;
        if y > 0 {
            sum += h[[y - 1, x]] - c;
        }
        if y + 1 < rows {
            sum += h[[y + 1, x]] - c;
        }
        if x > 0 {
            sum += h[[y, x - 1]] - c;
        }
        if x + 1 < cols {
            sum += h[[y, x + 1]] - c;
        }
        sum
    })
}

/// The periodic 4-neighbour Laplacian: `Σ_{n ∈ N(x)} p(n) − 4p(x)` with indices taken mod size.
#[must_use]
pub fn periodic_laplacian(p: ArrayView2<'_, f64>) -> Array2<f64> {
    let (rows, cols) = p.dim();
    Array2::from_shape_fn((rows, cols), |(y, x)| {
        p[[(y + rows - 1) % rows, x]]
            + p[[(y + 1) % rows, x]]
            + p[[y, (x + cols - 1) % cols]]
            + p[[y, (x + 1) % cols]]
            - 4.0 * p[[y, x]]
    })
}

/// `2cos(2πk/n) − 2` for `k` in `0..n`: one axis of the periodic Laplacian's DFT multiplier.
fn laplacian_axis(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            // Reduce k/n in turns exactly before the trigonometric call.
            let turns = k as f64 / n as f64;
            2.0 * (2.0 * std::f64::consts::PI * turns).cos() - 2.0
        })
        .collect()
}

/// The DFT of the periodic component of one or two real channels, packed as one complex image:
/// `P̂₀ + i·P̂₁`, where `P̂ᵢ` is the DFT of the periodic component of `channels[i]`.
///
/// Packing two real channels into the real and imaginary parts halves the number of FFTs; by
/// linearity the result is exactly `P̂₀ + i·P̂₁` (with `P̂₁ = 0` when only one channel is given).
/// This costs one FFT of the image's size.
///
/// # Panics
/// If the two channels differ in shape (a caller bug).
#[must_use]
pub fn periodic_spectrum_packed(
    first: ArrayView2<'_, f64>,
    second: Option<ArrayView2<'_, f64>>,
    fft: &mut Fft2<f64>,
) -> Array2<Complex64> {
    periodic_spectrum_packed_times(first, second, None, fft)
}

/// [`periodic_spectrum_packed`] multiplied by `factor` at every frequency but the zero one, in
/// the same pass as the Poisson division (memory passes, not arithmetic, bound this step).
pub(crate) fn periodic_spectrum_packed_times(
    first: ArrayView2<'_, f64>,
    second: Option<ArrayView2<'_, f64>>,
    factor: Option<&Array2<Complex64>>,
    fft: &mut Fft2<f64>,
) -> Array2<Complex64> {
    let (rows, cols) = first.dim();
    let first = standard(first);
    let second = second.map(|s| {
        assert_eq!(s.dim(), (rows, cols), "packed channels differ in shape");
        standard(s)
    });
    let mut z = Array2::<Complex64>::zeros((rows, cols));
    let (sum0, sum1) = interior_laplacian_packed(
        first.as_slice().expect("standard layout"),
        second
            .as_ref()
            .map(|s| s.as_slice().expect("standard layout")),
        rows,
        cols,
        z.as_slice_mut().expect("fresh arrays are contiguous"),
    );
    fft.forward(&mut z);
    let ax_y = laplacian_axis(rows);
    let ax_x = laplacian_axis(cols);
    let zs = z.as_slice_mut().expect("fresh arrays are contiguous");
    // The multiplier is < 0 everywhere but at the zero frequency, where these loops divide by
    // zero; that entry is overwritten below. No branch keeps the loops vectorised.
    match factor {
        None => {
            for (row, ay) in zs.chunks_exact_mut(cols).zip(&ax_y) {
                for (v, ax) in row.iter_mut().zip(&ax_x) {
                    *v *= 1.0 / (ay + ax);
                }
            }
        }
        Some(f) => {
            let fs = f.as_slice().expect("phase fields are contiguous");
            for ((row, frow), ay) in zs
                .chunks_exact_mut(cols)
                .zip(fs.chunks_exact(cols))
                .zip(&ax_y)
            {
                for ((v, f), ax) in row.iter_mut().zip(frow).zip(&ax_x) {
                    *v *= f * (1.0 / (ay + ax));
                }
            }
        }
    }
    z[[0, 0]] = Complex64::new(sum0, sum1);
    z
}

/// A row-major view of `a`, copying only when it is not already one.
fn standard(a: ArrayView2<'_, f64>) -> CowArray<'_, f64, Ix2> {
    if a.is_standard_layout() {
        CowArray::from(a)
    } else {
        CowArray::from(Array2::from_shape_fn(a.dim(), |i| a[i]))
    }
}

/// One row of `Δᵢh` into `lap` (same values as [`interior_laplacian`], written as straight
/// passes over slices, which the compiler vectorises).
fn laplacian_row(h: &[f64], rows: usize, cols: usize, y: usize, lap: &mut [f64]) {
    let row = &h[y * cols..(y + 1) * cols];
    if cols > 1 {
        lap[0] = row[1] - row[0];
        lap[cols - 1] = row[cols - 2] - row[cols - 1];
        for (l, w) in lap[1..cols - 1].iter_mut().zip(row.windows(3)) {
            *l = (w[0] - w[1]) + (w[2] - w[1]);
        }
    } else {
        lap[0] = 0.0;
    }
    if y > 0 {
        let up = &h[(y - 1) * cols..y * cols];
        for ((l, u), c) in lap.iter_mut().zip(up).zip(row) {
            *l += u - c;
        }
    }
    if y + 1 < rows {
        let down = &h[(y + 1) * cols..(y + 2) * cols];
        for ((l, d), c) in lap.iter_mut().zip(down).zip(row) {
            *l += d - c;
        }
    }
}

/// Writes `Δᵢh₀ + i·Δᵢh₁` of two row-major images into `out` in one pass and returns
/// `(Σh₀, Σh₁)`.
fn interior_laplacian_packed(
    h0: &[f64],
    h1: Option<&[f64]>,
    rows: usize,
    cols: usize,
    out: &mut [Complex64],
) -> (f64, f64) {
    let (mut sum0, mut sum1) = (0.0, 0.0);
    let (mut lap0, mut lap1) = (vec![0.0; cols], vec![0.0; cols]);
    for y in 0..rows {
        laplacian_row(h0, rows, cols, y, &mut lap0);
        sum0 += h0[y * cols..(y + 1) * cols].iter().sum::<f64>();
        if let Some(h1) = h1 {
            laplacian_row(h1, rows, cols, y, &mut lap1);
            sum1 += h1[y * cols..(y + 1) * cols].iter().sum::<f64>();
        }
        for ((o, &a), &b) in out[y * cols..(y + 1) * cols]
            .iter_mut()
            .zip(&lap0)
            .zip(&lap1)
        {
            *o = Complex64::new(a, b);
        }
    }
    (sum0, sum1)
}

/// The periodic and smooth components of an image, `h = periodic + smooth`.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicSmooth {
    /// `p`: periodic, with the same mean as the image.
    pub periodic: Array2<f64>,
    /// `s = h − p`: smooth, zero mean.
    pub smooth: Array2<f64>,
}

/// Decomposes `h` into its periodic and smooth components (two FFTs of the image's size).
///
/// ```
/// use ndarray::Array2;
/// use spectex_spectrum::{Fft2, periodic_smooth};
///
/// // A ramp is as non-periodic as an image gets; its periodic component has the same mean.
/// let h = Array2::from_shape_fn((16, 24), |(y, x)| (x + 2 * y) as f64);
/// let d = periodic_smooth(h.view(), &mut Fft2::new());
/// assert!((d.periodic.mean().unwrap() - h.mean().unwrap()).abs() < 1e-9);
/// assert!(d.smooth.mean().unwrap().abs() < 1e-9);
/// ```
#[must_use]
pub fn periodic_smooth(h: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> PeriodicSmooth {
    let pair = periodic_pair(h, None, fft);
    let periodic = pair.0;
    let smooth = &h - &periodic;
    PeriodicSmooth { periodic, smooth }
}

/// The periodic components of one or two channels with two FFTs in all (one forward, one
/// inverse, on the packed pair). The second result is all zeros when `second` is `None`.
#[must_use]
pub fn periodic_pair(
    first: ArrayView2<'_, f64>,
    second: Option<ArrayView2<'_, f64>>,
    fft: &mut Fft2<f64>,
) -> (Array2<f64>, Array2<f64>) {
    let mut z = periodic_spectrum_packed(first, second, fft);
    fft.inverse_normalized(&mut z);
    (z.mapv(|c| c.re), z.mapv(|c| c.im))
}
