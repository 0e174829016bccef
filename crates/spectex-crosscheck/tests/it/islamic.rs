//! Islamic star patterns on both evaluators: every tiling, both motifs and every output on
//! small windows (lavapipe is slow), at the origin, at 10⁷ pixels, magnified and minified,
//! judged by the kind's derived tolerance; and a warp of one, whose displacement the shader
//! applies to its lattice fractions.

use spectex_gpu::GpuEvaluator;
use spectex_model::islamic::{IslamicOutput, IslamicPattern, Motif, Tiling};
use spectex_model::{LrpNoise, Model, Stratum, Warp, Window};

use crate::common::{check_cases, gpu_or_skip, small_windows};

#[test]
fn every_tiling_motif_and_output_agrees_on_cpu_and_gpu() {
    let Some(context) = gpu_or_skip("islamic cross-check") else {
        return;
    };
    let mut cases = Vec::new();
    for (k, tiling) in [
        Tiling::Square,
        Tiling::Hexagonal,
        Tiling::OctagonSquare,
        Tiling::DodecagonTriangle,
    ]
    .into_iter()
    .enumerate()
    {
        for (motif, output) in [
            (Motif::Contact { angle: 62.0 }, IslamicOutput::Band),
            (Motif::Star { step: 3 }, IslamicOutput::Distance),
            (Motif::Contact { angle: 35.0 }, IslamicOutput::Filled),
        ] {
            let model = Model::Islamic(IslamicPattern {
                seed: k as u32,
                tiling,
                motif,
                cell_size: 24.0,
                line_width: 2.0,
                output,
                rotation: 11.0 * k as f32,
                offset: [1.5, -2.0],
            });
            cases.push((format!("{tiling:?} {motif:?} {output:?}"), model));
        }
    }
    check_cases(&context, cases, &small_windows(4.0));
}

/// A constant warp shifts the window: the shader moves the lattice fractions by `A·d` in f32,
/// the CPU evaluates at the displaced positions in f64; they agree within the distance's
/// rounding bound grown by the f32 product (a few ulps of a cell: 1e-3 pixels here).
#[test]
fn a_constant_warp_shifts_the_pattern_on_the_gpu() {
    let Some(context) = gpu_or_skip("islamic cross-check") else {
        return;
    };
    let base = Model::Islamic(IslamicPattern {
        tiling: Tiling::Hexagonal,
        output: IslamicOutput::Distance,
        cell_size: 24.0,
        ..IslamicPattern::default()
    });
    // An LRP noise that is exactly `mean` everywhere (amplitude 0).
    let constant = |mean: f32| {
        Model::Lrp(LrpNoise {
            seed: 0,
            mean,
            strata: vec![Stratum {
                window_width: 8.0,
                amplitude: 0.0,
                sub_strata: vec![vec![[0.1, 0.0]]],
            }],
        })
    };
    let warped = Model::Warp(Warp {
        base: Box::new(base.clone()),
        x: Box::new(constant(2.5)),
        y: Box::new(constant(-1.5)),
        strength: 2.0,
    });
    for offset in [[0.0, 0.0], [1.0e7, 1.0e7]] {
        let window = Window::new(24, 16).at(offset, 1.0);
        let shifted = window.at([offset[0] + 5.0, offset[1] - 3.0], 1.0);
        let got = GpuEvaluator::new(&context, &warped)
            .unwrap()
            .render(&window)
            .unwrap();
        let want = spectex_cpu::Evaluator::new(&base)
            .unwrap()
            .render(&shifted)
            .unwrap();
        let e = got
            .iter()
            .zip(&want)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(e <= 1e-3, "at {offset:?}: {e}");
        assert!(
            want.iter().any(|&v| (v - want[0]).abs() > 1.0),
            "constant render"
        );
    }
}
