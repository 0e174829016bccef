//! Gabor noise on the device against a slow f64 evaluation written from the randomness contract
//! of `crates/spectex-cpu/src/gabor.rs` (Poisson count by Knuth's method with renormalisation and
//! a cap, then per impulse x, y, weight and, for isotropic noise, direction), near the origin and
//! far away; tiling; and, as a report, bit-identity with a host transcription of the CPU's f32
//! arithmetic.
//!
//! Run with `--nocapture` to see the measured errors.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::{cpu_cos_turns, cpu_exp_poly, first_bit_difference};
use spectex_gpu::{GpuEvaluator, GpuWindow};
use spectex_model::random::{Prng, cell_hash_in_row, layer_key, row_key};
use spectex_model::{GaborNoise, Model, Orientation};
use spectex_testkit::fixtures::gabor as model;
use spectex_testkit::reference::{self, GaborReference};
use std::f64::consts::TAU;

fn models() -> Vec<(&'static str, GaborNoise)> {
    let aniso = |angle| Orientation::Anisotropic { angle };
    vec![
        ("anisotropic ipk 8", model(1, 8.0, 0.05, 0.0625, aniso(0.7))),
        ("anisotropic narrow", model(3, 32.0, 0.2, 0.25, aniso(0.0))),
        (
            "isotropic full",
            model(
                5,
                16.0,
                0.05,
                0.125,
                Orientation::Isotropic {
                    min: 0.0,
                    max: TAU as f32,
                },
            ),
        ),
        (
            "isotropic far angles",
            model(
                7,
                4.0,
                0.05,
                0.05,
                Orientation::Isotropic {
                    min: -40.0,
                    max: -38.0,
                },
            ),
        ),
        (
            "renormalised count (λ ≈ 95)",
            model(8, 300.0, 0.1, 0.0625, aniso(0.2)),
        ),
        (
            "spectrum (by example)",
            model(
                9,
                24.0,
                0.06,
                0.0,
                Orientation::Spectrum {
                    frequencies: vec![[0.1, 0.02], [-0.05, 0.2], [0.3, -0.3], [0.0, 0.5]],
                    weights: vec![2.0, 1.0, 0.0, 0.5],
                },
            ),
        ),
        (
            // `pick_component` from its guide table: uneven weights over 61 components, with
            // runs of zero weights (equal cumulative entries) and a heavy last one.
            "spectrum, 61 components",
            model(
                10,
                24.0,
                0.06,
                0.0,
                Orientation::Spectrum {
                    frequencies: (0..61)
                        .map(|k| {
                            let a = k as f32 * 0.37;
                            [0.2 * a.cos(), 0.2 * a.sin()]
                        })
                        .collect(),
                    weights: (0..61)
                        .map(|k| match k % 7 {
                            0..=2 => 0.0,
                            _ if k == 60 => 9.0,
                            r => r as f32 * 0.3,
                        })
                        .collect(),
                },
            ),
        ),
    ]
}

/// The largest `|f|` an impulse may have, cycles per pixel: `F₀`, or a spectrum's largest.
fn largest_frequency(m: &GaborNoise) -> f64 {
    match &m.orientation {
        Orientation::Spectrum { frequencies, .. } => frequencies
            .iter()
            .map(|f| f64::from(f[0]).hypot(f64::from(f[1])))
            .fold(0.0, f64::max),
        _ => f64::from(m.frequency),
    }
}

// ---------------------------------------------------------------------------------------------
// The error bound against the slow f64 reference (`spectex_testkit::reference::gabor`).

/// Error bound of the device's f32 evaluation, per unit of `Σ|K·w|` (cell units; `2⁻²⁴ ≈ 6e-8`
/// is an f32 half-ulp near 1). The CPU's derivation (crates/spectex-cpu/tests/it/gabor.rs) with the
/// device's function tolerances of contract.rs:
/// - offsets `d` good to 1.5e-7 per component → Gaussian `exp(−ln 20·d²)`: `δ(d²) ≈ 8e-7` times
///   `ln 20 ≈ 3`, plus `exp_poly`'s 2e-6: relative ≤ 4.5e-6;
/// - cosine: phase error ≤ `F₀r·6e-7` turns (offsets, products, sum) plus, for isotropic noise,
///   the direction `(cos_turns, cos_turns)` good to 1e-6 each → `F₀r·1.5e-6`; times 2π; plus
///   `cos_turns`' 1e-6;
/// - summation in 8 lanes and a 3-level tree: ≤ `50·2⁻²⁴·Σ|K·w|`.
fn tolerance(m: &GaborNoise, r: &GaborReference) -> f64 {
    let f_cell = largest_frequency(m) * m.kernel_radius();
    let per_weight = 4.5e-6 + 1e-6 + TAU * f_cell * (6e-7 + 1.5e-6) + 50.0 * 6e-8;
    per_weight * r.weight_sum + 2f64.powi(-23) * r.value.abs()
}

// ---------------------------------------------------------------------------------------------
// The CPU's f32 evaluation (GaborEvaluator::eval), transcribed for the bit-identity report.

fn cpu_transcription(m: &GaborNoise, x: f64, y: f64) -> f32 {
    let radius = m.kernel_radius();
    let lambda = m.impulses_per_cell();
    let locate = |c: f64| {
        let p = c / radius;
        (p.abs() < 2_147_483_646.0).then(|| (p.floor() as i32, (p - p.floor()) as f32))
    };
    let (Some((ci, ux)), Some((cj, uy))) = (locate(x), locate(y)) else {
        return m.mean;
    };
    let f_cell = f64::from(m.frequency) * radius;
    let key = layer_key(0, m.seed);
    let mut cols = [0.0f32; 3];
    for (s, col) in (-1i32..=1).zip(cols.iter_mut()) {
        let uxs = ux - s as f32;
        let mut acc = [0.0f32; 8];
        let mut k = 0;
        for t in -1i32..=1 {
            let uyt = uy - t as f32;
            let mut prng = Prng::new(cell_hash_in_row(ci + s, row_key(cj + t, key)));
            for _ in 0..reference::gabor_count(&mut prng, lambda) {
                let ox = prng.next_f32();
                let oy = prng.next_f32();
                let w = 2.0 * prng.next_f32() - 1.0;
                let (fx, fy) = match &m.orientation {
                    &Orientation::Anisotropic { angle } => {
                        let (sin, cos) = f64::from(angle).sin_cos();
                        ((f_cell * cos) as f32, (f_cell * sin) as f32)
                    }
                    Orientation::Spectrum {
                        frequencies,
                        weights,
                    } => {
                        let c = spectex_model::cumulative_weights(weights);
                        let u = prng.next_f32();
                        let k = c.iter().position(|&c| u < c).unwrap_or(c.len() - 1);
                        let f = frequencies[k];
                        (
                            (f64::from(f[0]) * radius) as f32,
                            (f64::from(f[1]) * radius) as f32,
                        )
                    }
                    &Orientation::Isotropic { min, max } => {
                        let t_min = (f64::from(min) / TAU).rem_euclid(1.0) as f32;
                        let span = ((f64::from(max) - f64::from(min)) / TAU) as f32;
                        let turns = t_min + prng.next_f32() * span;
                        let f = f_cell as f32;
                        (f * cpu_cos_turns(turns), f * cpu_cos_turns(turns - 0.25))
                    }
                };
                let dy = uyt - oy;
                let dy2 = dy * dy;
                if dy2 < 1.0 {
                    let dx = uxs - ox;
                    let d2 = dx * dx + dy2;
                    let gauss = cpu_exp_poly(-2.995_732_3 * d2);
                    let wave = cpu_cos_turns(fx * dx + fy * dy);
                    let v = m.amplitude * w * gauss * wave;
                    acc[k % 8] += if d2 < 1.0 { v } else { 0.0 };
                    k += 1;
                }
            }
        }
        *col = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
    }
    m.mean + ((cols[0] + cols[1]) + cols[2])
}

/// Renders `window` and compares each pixel with the reference (at most 1% of pixels may be
/// skipped for lying on a truncation edge).
fn check(case: &str, gpu: &GpuEvaluator, m: &GaborNoise, window: &GpuWindow) {
    let got = gpu.render(window).unwrap();
    let (mut worst, mut worst_abs, mut skipped, mut same) = (0.0f64, 0.0f64, 0, 0);
    for j in 0..window.height {
        for i in 0..window.width {
            let (x, y) = (window.x(i), window.y(j));
            let g = got[j * window.width + i];
            same += usize::from(g.to_bits() == cpu_transcription(m, x, y).to_bits());
            let want = reference::gabor(m, x, y);
            if want.near_edge {
                skipped += 1;
                continue;
            }
            let tol = tolerance(m, &want);
            let err = (f64::from(g) - want.value).abs();
            assert!(
                err <= tol,
                "{case}, seed {}: pixel ({i}, {j}) at ({x}, {y}): {g} on {} vs reference {} \
                 (error {err:e} > tolerance {tol:e})",
                m.seed,
                gpu.adapter_name(),
                want.value
            );
            worst = worst.max(err / tol);
            worst_abs = worst_abs.max(err);
        }
    }
    let n = window.width * window.height;
    assert!(
        skipped * 100 <= n,
        "{case}: {skipped} of {n} pixels on an edge"
    );
    eprintln!(
        "{case}: {n} pixels, {skipped} skipped, max error {worst_abs:.2e}, worst error / tolerance \
         {worst:.3}, {same}/{n} bit-identical to the CPU's f32 arithmetic"
    );
}

#[test]
fn matches_the_reference_near_and_far() {
    let Some(context) = common::gpu_or_skip("gabor matches_the_reference") else {
        return;
    };
    for (case, m) in models() {
        let gpu = GpuEvaluator::new(&context, &Model::Gabor(m.clone())).unwrap();
        let r = m.kernel_radius();
        for (place, offset, scale) in [
            ("origin", [-20.0, -15.0], 1.0),
            ("far (1e7, 1e7)", [1.0e7, 1.0e7], 1.0),
            ("negative, scale 0.37", [-1234.5, -987.25], 0.37),
            ("far, cell-sized steps", [-9.0e6, 4.0e6], 0.45 * r),
        ] {
            let window = GpuWindow::new(40, 32).at(offset, scale);
            check(&format!("{case} at {place}"), &gpu, &m, &window);
        }
    }
}

#[test]
fn out_of_range_positions_give_the_mean() {
    let Some(context) = common::gpu_or_skip("gabor out_of_range_positions") else {
        return;
    };
    let (_, mut m) = models().remove(0);
    m.bandwidth = 10.0; // r ≈ 0.097 px: |x / r| exceeds the i32 cell range near 2^30 px.
    let gpu = GpuEvaluator::new(&context, &Model::Gabor(m.clone())).unwrap();
    let got = gpu
        .render(&GpuWindow::new(4, 2).at([1.07e9, 0.0], 1.0))
        .unwrap();
    assert!(got.iter().all(|&v| v == m.mean), "{got:?}");
}

#[test]
fn tiles_are_invisible() {
    let Some(context) = common::gpu_or_skip("gabor tiles_are_invisible") else {
        return;
    };
    let (_, m) = models().remove(2);
    let mut gpu = GpuEvaluator::new(&context, &Model::Gabor(m)).unwrap();
    let window = GpuWindow::new(61, 37).at([1.0e7 + 0.3, -2.0e5], 0.9);
    let whole = gpu.render(&window).unwrap();
    for (tw, th) in [(1, 1), (8, 8), (13, 37), (61, 5)] {
        gpu.set_max_tile(tw, th);
        let tiled = gpu.render(&window).unwrap();
        let first = first_bit_difference(&whole, &tiled);
        assert_eq!(
            first, None,
            "tiles {tw}×{th}: first differing index {first:?}"
        );
    }
}
