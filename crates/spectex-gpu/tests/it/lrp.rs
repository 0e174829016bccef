//! LRP noise on the device against a slow f64 evaluation of the definition (Gilet et al. 2014,
//! Eqs. 1–2, with the draws of the randomness contract), near the origin, at `(10⁷, 10⁷)` and at
//! fractional scales; tiling; and, as a report, bit-identity with a host transcription of the
//! CPU's f32 arithmetic.
//!
//! Run with `--nocapture` to see the measured errors.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::{first_bit_difference, lrp_f32};
use spectex_gpu::{GpuEvaluator, GpuWindow};
use spectex_model::random::{Prng, cell_hash};
use spectex_model::{LrpNoise, Model, Stratum};
use spectex_testkit::fixtures::lrp_three_strata as model;
use spectex_testkit::reference;

/// Error bound of the device's f32 evaluation against [`reference::lrp`], per stratum, summed.
///
/// Per cosine term, with `ε = 2⁻²³` and `arg = f_max·1.5Δ + 1` turns bounding every intermediate
/// of `f_x·d_x + (f_y·d_y + φ)`:
/// - the argument: `d_x`, `d_y` are the f64 offsets rounded once (≤ ε/2 relative, independent of
///   the window's position — the point of the scheme), then two products and two sums, each
///   rounded to ≤ ε/2 of a value ≤ `arg`: at most `4ε·arg` turns, times `2π` for the cosine's
///   slope;
/// - `cos_turns`: 1e-6 (contract.rs, allowing fused multiply-adds);
/// - the window: 3.5e-6 (contract.rs), multiplying each term;
/// - summation: `J` terms of magnitude ≤ 1 accumulate ≤ `J·ε/2·J` per lattice point.
///
/// Times `A_S` and at most 9 lattice points inside the support (a disc of radius 1.5 cells).
fn tolerance(m: &LrpNoise) -> f64 {
    let eps = f64::from(f32::EPSILON);
    m.strata
        .iter()
        .map(|st| {
            let fmax = st
                .sub_strata
                .iter()
                .flatten()
                .map(|f| f64::from(f[0].hypot(f[1])))
                .fold(0.0, f64::max);
            let arg = fmax * 1.5 * f64::from(st.window_width) + 1.0;
            let j = st.sub_strata.len() as f64;
            let per_term = std::f64::consts::TAU * 4.0 * eps * arg + 1e-6 + 3.5e-6;
            f64::from(st.amplitude) * 9.0 * (j * per_term + j * j * eps / 2.0)
        })
        .sum()
}

/// Renders `window` and compares every pixel with the reference; returns the worst
/// error / tolerance ratio and the number of pixels bit-identical to the CPU transcription.
fn check(case: &str, gpu: &GpuEvaluator, m: &LrpNoise, window: &GpuWindow) -> (f64, usize) {
    let got = gpu.render(window).unwrap();
    let tol = tolerance(m);
    let (mut worst, mut worst_abs, mut same) = (0.0f64, 0.0f64, 0);
    for j in 0..window.height {
        for i in 0..window.width {
            let (x, y) = (window.x(i), window.y(j));
            let g = got[j * window.width + i];
            let want = reference::lrp(m, x, y);
            let err = (f64::from(g) - want).abs();
            assert!(
                err <= tol,
                "{case}, seed {}, {}×{} window: pixel ({i}, {j}) at ({x}, {y}): {g} on {} vs {want} \
                 (error {err:e} > tolerance {tol:e})",
                m.seed,
                window.width,
                window.height,
                gpu.adapter_name()
            );
            worst = worst.max(err / tol);
            worst_abs = worst_abs.max(err);
            same += usize::from(g.to_bits() == lrp_f32(m, x, y).to_bits());
        }
    }
    let n = window.width * window.height;
    eprintln!(
        "{case}: {n} pixels, max error {worst_abs:.2e}, worst error / tolerance {worst:.4} \
         (tolerance {tol:.2e}), {same}/{n} bit-identical to the CPU's f32 arithmetic"
    );
    (worst, same)
}

#[test]
fn matches_the_definition_near_far_and_at_fractional_scales() {
    let Some(context) = common::gpu_or_skip("lrp matches_the_definition") else {
        return;
    };
    for seed in [1, 2] {
        let m = model(seed);
        let gpu = GpuEvaluator::new(&context, &Model::Lrp(m.clone())).unwrap();
        let cases = [
            ("origin", [0.0, 0.0], 1.0),
            ("far (1e7, 1e7)", [1.0e7, 1.0e7], 1.0),
            ("fractional scale 0.37", [-1234.5, 77.25], 0.37),
            ("far, scale 2.9", [-3.0e6 + 0.3, 1.0e7], 2.9),
        ];
        let mut ratios = Vec::new();
        for (case, offset, scale) in cases {
            // Point samples: the definition, not a minified render's gains (scale 2.9).
            let window = GpuWindow::new(48, 40)
                .at(offset, scale)
                .filtered(spectex_gpu::Filter::Off);
            ratios.push(check(case, &gpu, &m, &window).0);
        }
        // Invariant 2: far away is as precise as the origin (same bound, and in practice the
        // same order of error).
        assert!(ratios[1] <= 1.0 && ratios[0] <= 1.0);
    }
}

#[test]
fn tiles_are_invisible() {
    let Some(context) = common::gpu_or_skip("lrp tiles_are_invisible") else {
        return;
    };
    let m = Model::Lrp(model(6));
    let mut gpu = GpuEvaluator::new(&context, &m).unwrap();
    let window = GpuWindow::new(83, 45).at([1.0e7 + 0.3, -2.0e5], 1.3);
    let whole = gpu.render(&window).unwrap();
    assert_eq!(gpu.tile_size(&window).unwrap(), [83, 45], "one tile");
    // One-pixel tiles (a dispatch each, about 12 ms on lavapipe) on the 9×7 sub-window below
    // only: over the whole window they cost 45 s of CI.
    for (tw, th) in [(7, 5), (16, 16), (83, 1), (13, 45)] {
        gpu.set_max_tile(tw, th);
        assert_eq!(gpu.tile_size(&window).unwrap(), [tw, th]);
        let tiled = gpu.render(&window).unwrap();
        let first = first_bit_difference(&whole, &tiled);
        assert_eq!(
            first, None,
            "tiles {tw}×{th}: first differing index {first:?}"
        );
    }
    // A sub-window evaluates exactly the pixels of the window it is cut from, in one-pixel
    // tiles too.
    gpu.set_max_tile(1, 1);
    assert_eq!(gpu.tile_size(&window).unwrap(), [1, 1]);
    let tile = gpu.render(&window.tile(30, 20, 9, 7)).unwrap();
    for r in 0..7 {
        let row = &whole[(20 + r) * 83 + 30..(20 + r) * 83 + 39];
        assert_eq!(
            first_bit_difference(&tile[r * 9..(r + 1) * 9], row),
            None,
            "row {r}"
        );
    }
}

#[test]
fn one_stratum_many_cosines_large_tables() {
    // The bench's shape at a small size: 40-entry tables, J = 13, Δ = 4.5 px.
    let Some(context) = common::gpu_or_skip("lrp one_stratum_many_cosines") else {
        return;
    };
    let mut prng = Prng::new(cell_hash(1, 2, 3, 4));
    let m = LrpNoise {
        seed: 9,
        mean: 0.5,
        strata: vec![Stratum {
            window_width: 4.5,
            amplitude: 0.05,
            sub_strata: (0..13)
                .map(|_| {
                    (0..40)
                        .map(|_| [prng.next_f32() - 0.5, prng.next_f32() * 0.5])
                        .collect()
                })
                .collect(),
        }],
    };
    let gpu = GpuEvaluator::new(&context, &Model::Lrp(m.clone())).unwrap();
    check(
        "J = 13, tables of 40",
        &gpu,
        &m,
        &GpuWindow::new(32, 32).at([-77.0, 1.0e6], 0.8),
    );
}
