//! Wavelet noise on the device against a host transcription of the definition in f32 (the
//! model's tile, bands, `locate_sample` and `spline_weights`, summed in the documented order,
//! written here independently of spectex-cpu), near the origin, at 10⁷ and at a fractional scale,
//! in 2D and 3D; periodicity with the tile and tiling, both bit for bit.
//!
//! Run with `--nocapture` to see how many pixels are bit-identical to the transcription.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stderr,
    reason = "the measured agreement is the test's report"
)]

use crate::common;

use spectex_gpu::{GpuEvaluator, GpuWindow};
use spectex_model::Model;
use spectex_model::wavelet::{WaveletNoise, WaveletTile, locate_sample, spline_weights};

fn model(dimensions: u32, tile_size: u32, cell_size: f32, bands: Vec<f32>) -> WaveletNoise {
    let m = WaveletNoise {
        seed: 21,
        dimensions,
        tile_size,
        cell_size,
        bands,
        amplitude: 0.8,
        mean: 0.5,
    };
    m.validate().unwrap();
    m
}

/// The definition in f32: per band `Σ_i wx_i Σ_j wy_j Σ_k wz_k T`, then `mean + Σ_b a_b s_b`,
/// and the magnitude `|mean| + Σ_b |a_b| Σ |w T|` for the rounding bound.
fn transcription(m: &WaveletNoise, tile: &WaveletTile, x: f64, y: f64, z: f64) -> (f32, f64) {
    let n = tile.side;
    let t = |i: usize, j: usize, k: usize| tile.values[(k * n + j) * n + i];
    let mut acc = 0.0f32;
    let mut magnitude = f64::from(m.mean.abs());
    for band in m.bands() {
        let (i0, fx) = locate_sample(x, band.side, band.offset[0], n as u32);
        let (j0, fy) = locate_sample(y, band.side, band.offset[1], n as u32);
        let (wx, wy) = (spline_weights(fx), spline_weights(fy));
        let plane = |i: usize, j: usize| -> f32 {
            if m.dimensions == 2 {
                return t(i, j, 0);
            }
            let (k0, fz) = locate_sample(z, band.side, band.offset[2], n as u32);
            let wz = spline_weights(fz);
            let k = |s: usize| (k0 as usize + s) % n;
            (wz[0] * t(i, j, k(0)) + wz[1] * t(i, j, k(1))) + wz[2] * t(i, j, k(2))
        };
        let row = |i: usize| -> f32 {
            let j = |s: usize| (j0 as usize + s) % n;
            (wy[0] * plane(i, j(0)) + wy[1] * plane(i, j(1))) + wy[2] * plane(i, j(2))
        };
        let i = |s: usize| (i0 as usize + s) % n;
        let s = (wx[0] * row(i(0)) + wx[1] * row(i(1))) + wx[2] * row(i(2));
        acc += band.amplitude * s;
        let peak = tile.values.iter().fold(0.0f32, |a, v| a.max(v.abs()));
        magnitude += f64::from(band.amplitude.abs() * peak);
    }
    (m.mean + acc, magnitude)
}

fn cases() -> Vec<(&'static str, WaveletNoise, f64)> {
    vec![
        ("2d one band", model(2, 64, 8.0, vec![1.0]), 0.0),
        (
            "2d four bands",
            model(2, 128, 16.0, vec![1.0, 0.5, 0.25, 0.125]),
            0.0,
        ),
        ("3d two bands", model(3, 32, 9.5, vec![1.0, -0.7]), 123.25),
    ]
}

#[test]
fn matches_the_transcription_near_far_and_scaled() {
    let Some(context) = common::gpu_or_skip("wavelet transcription") else {
        return;
    };
    for (case, m, z) in cases() {
        let gpu = GpuEvaluator::new_at_z(&context, &Model::Wavelet(m.clone()), z).unwrap();
        let tile = m.tile();
        for window in [
            GpuWindow::new(96, 80),
            GpuWindow::new(96, 80).at([1.0e7, 1.0e7], 1.0),
            GpuWindow::new(96, 80).at([-37.25, 11.5], 0.37),
        ] {
            let got = gpu.render(&window).unwrap();
            let mut identical = 0;
            for j in 0..window.height {
                for i in 0..window.width {
                    let (want, magnitude) = transcription(&m, &tile, window.x(i), window.y(j), z);
                    let g = got[j * window.width + i];
                    identical += usize::from(g.to_bits() == want.to_bits());
                    // FMA contraction of any of the 13 (3D: 40) products and sums of a band
                    // changes one rounding each: 64 roundings of the magnitude bound them all.
                    let bound = 64.0 * f64::from(f32::EPSILON) * magnitude;
                    assert!(
                        f64::from((g - want).abs()) <= bound,
                        "{case} {window:?} ({i}, {j}): {g} vs {want} (bound {bound})"
                    );
                }
            }
            eprintln!(
                "wavelet {case} at {:?} scale {}: {identical}/{} pixels bit-identical to the transcription on {}",
                window.offset,
                window.scale,
                window.width * window.height,
                gpu.adapter_name()
            );
        }
    }
}

#[test]
fn periodic_and_tiles_are_invisible() {
    let Some(context) = common::gpu_or_skip("wavelet tiling") else {
        return;
    };
    for (case, m, z) in cases() {
        let mut gpu = GpuEvaluator::new_at_z(&context, &Model::Wavelet(m.clone()), z).unwrap();
        let window = GpuWindow::new(100, 70).at([1.0e7 + 0.5, -3.25], 1.0);
        let whole = gpu.render(&window).unwrap();
        // n·cell is a whole number of samples of every band; with a power-of-two cell every
        // division is exact in f64, so the shifted window reads the same indices and fractions.
        if m.cell_size.log2().fract() == 0.0 {
            let period = f64::from(m.tile_size) * f64::from(m.cell_size);
            let shifted = gpu
                .render(&GpuWindow::new(100, 70).at([1.0e7 + 0.5 + period, -3.25 - period], 1.0))
                .unwrap();
            assert_eq!(
                common::first_bit_difference(&whole, &shifted),
                None,
                "{case}: shifted by a period"
            );
        }
        gpu.set_max_tile(24, 16);
        let tiled = gpu.render(&window).unwrap();
        assert_eq!(
            common::first_bit_difference(&whole, &tiled),
            None,
            "{case}: tiles"
        );
    }
}
