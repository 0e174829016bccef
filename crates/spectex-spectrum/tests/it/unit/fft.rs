//! The cached 2D FFT against the definition of the DFT (`src/fft.rs`).

use ndarray::Array2;
use ndarray::ShapeBuilder;
use num_complex::Complex;
use num_complex::Complex64;
use spectex_model::random::{Prng, cell_hash};
use spectex_spectrum::fft::*;

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
    let (s, t) = fft.buffer_addresses();
    let mut b = random_image(32, 48, 2);
    fft.forward(&mut b);
    fft.inverse(&mut b);
    assert_eq!(s, fft.buffer_addresses().0, "scratch was reallocated");
    assert_eq!(
        t,
        fft.buffer_addresses().1,
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
