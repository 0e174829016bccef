//! Stochastic subdivision on both evaluators: both stencils, 0 to 12 levels, rough and smooth,
//! at the origin, at 10⁷ pixels, magnified and minified, judged by the kind's derived f32-sum
//! tolerance (`spectex_crosscheck::tolerance::subdivision`); and warped, where the shader moves
//! its coarse-cell offsets by the displacement and the warp's regularity bound judges it.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_model::subdivision::{Stencil, StochasticSubdivision};
use spectex_model::{ClassicNoise, Model, Warp};

use crate::common::{check_cases, gpu_or_skip, small_windows};

fn subdivision(stencil: Stencil, levels: u32, hurst: f32, cell_size: f32) -> StochasticSubdivision {
    StochasticSubdivision {
        seed: levels * 7 + 1,
        cell_size,
        levels,
        hurst,
        amplitude: 0.2,
        mean: 0.5,
        stencil,
    }
}

#[test]
fn both_stencils_agree_on_cpu_and_gpu() {
    let Some(context) = gpu_or_skip("subdivision cross-check") else {
        return;
    };
    let mut cases = Vec::new();
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        for (levels, hurst, cell) in [
            (0, 0.5, 8.0),
            (3, 0.2, 20.0),
            (8, 0.5, 64.0),
            (12, 0.9, 1000.0),
        ] {
            let model = Model::Subdivision(subdivision(stencil, levels, hurst, cell));
            cases.push((format!("{stencil:?} L={levels} H={hurst}"), model));
        }
    }
    check_cases(&context, cases, &small_windows(6.0));
}

#[test]
fn a_warped_subdivision_agrees_on_cpu_and_gpu() {
    let Some(context) = gpu_or_skip("subdivision cross-check") else {
        return;
    };
    let by = |seed: u32| {
        Model::Classic(
            ClassicNoise::fbm()
                .seed(seed)
                .cell_size(48.0)
                .build()
                .unwrap(),
        )
    };
    let cases = [Stencil::Midpoint, Stencil::Cubic].map(|stencil| {
        let model = Model::Warp(Warp {
            base: Box::new(Model::Subdivision(subdivision(stencil, 6, 0.5, 64.0))),
            x: Box::new(by(1)),
            y: Box::new(by(2)),
            strength: 6.0,
        });
        (format!("warped {stencil:?}"), model)
    });
    check_cases(&context, cases, &small_windows(6.0)[..2]);
}
