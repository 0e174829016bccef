//! Swift–Hohenberg, semi-implicit in Fourier space (f64, rustfft through `spectex_spectrum`).

use num_complex::Complex;
use rayon::prelude::*;
use rustfft::FftDirection;
use spectex_model::simulation::{SwiftHohenberg, swift_hohenberg_grey};
use spectex_spectrum::{Fft2, signed_frequency};

/// The field, the spectral buffer and `1 / (1 + dt (1 − |q|²)²)` per frequency.
#[derive(Debug)]
pub(crate) struct SwiftHohenbergState {
    p: SwiftHohenberg,
    width: usize,
    height: usize,
    pub(crate) u: Vec<f64>,
    buffer: Vec<Complex<f64>>,
    implicit: Vec<f64>,
    fft: Fft2<f64>,
}

impl Clone for SwiftHohenbergState {
    fn clone(&self) -> Self {
        SwiftHohenbergState {
            p: self.p,
            width: self.width,
            height: self.height,
            u: self.u.clone(),
            buffer: self.buffer.clone(),
            implicit: self.implicit.clone(),
            fft: Fft2::new(),
        }
    }
}

impl SwiftHohenbergState {
    pub(crate) fn new(p: SwiftHohenberg, width: usize, height: usize, u: &[f32]) -> Self {
        let dt = f64::from(p.dt);
        let lambda = f64::from(p.wavelength);
        // The dimensionless wavenumber of DFT index (kx, ky): lengths are scaled so that the
        // critical wavelength 2π is `wavelength` pixels, so |q| = |f| · wavelength with f in
        // cycles per pixel.
        let implicit = (0..height)
            .flat_map(|ky| (0..width).map(move |kx| (kx, ky)))
            .map(|(kx, ky)| {
                let fx = signed_frequency(kx, width);
                let fy = signed_frequency(ky, height);
                let q2 = (fx * fx + fy * fy) * lambda * lambda;
                1.0 / (1.0 + dt * (1.0 - q2) * (1.0 - q2))
            })
            .collect();
        SwiftHohenbergState {
            p,
            width,
            height,
            u: u.iter().map(|&x| f64::from(x)).collect(),
            buffer: vec![Complex::new(0.0, 0.0); width * height],
            implicit,
            fft: Fft2::new(),
        }
    }

    pub(crate) fn step(&mut self) {
        let (r, g, dt) = (
            f64::from(self.p.r),
            f64::from(self.p.g),
            f64::from(self.p.dt),
        );
        let w = self.width;
        self.buffer
            .par_chunks_mut(w)
            .zip(self.u.par_chunks(w))
            .for_each(|(out, u)| {
                for (o, &u) in out.iter_mut().zip(u) {
                    let nonlinear = r * u + g * u * u - u * u * u;
                    *o = Complex::new(u + dt * nonlinear, 0.0);
                }
            });
        let (h, w) = (self.height, self.width);
        self.fft
            .process_slice(&mut self.buffer, h, w, FftDirection::Forward);
        self.buffer
            .par_chunks_mut(w)
            .zip(self.implicit.par_chunks(w))
            .for_each(|(b, m)| b.iter_mut().zip(m).for_each(|(b, m)| *b *= *m));
        self.fft
            .process_slice(&mut self.buffer, h, w, FftDirection::Inverse);
        let scale = 1.0 / (w * h) as f64;
        self.u
            .par_chunks_mut(w)
            .zip(self.buffer.par_chunks(w))
            .for_each(|(u, b)| u.iter_mut().zip(b).for_each(|(u, b)| *u = b.re * scale));
    }

    pub(crate) fn grey(&self) -> Vec<f32> {
        self.u
            .iter()
            .map(|&u| swift_hohenberg_grey(&self.p, u as f32))
            .collect()
    }
}
