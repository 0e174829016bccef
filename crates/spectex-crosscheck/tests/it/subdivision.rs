//! Stochastic subdivision on both evaluators: both stencils, 0 to 12 levels, rough and smooth,
//! at the origin, at 10⁷ pixels, magnified and minified, judged by the kind's derived f32-sum
//! tolerance (`spectex_crosscheck::tolerance::subdivision`); and warped, where the shader moves
//! its coarse-cell offsets by the displacement and the warp's regularity bound judges it.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_crosscheck::{CaseWindow, Verdict, check_model};
use spectex_gpu::GpuContext;
use spectex_model::subdivision::{Stencil, StochasticSubdivision};
use spectex_model::{ClassicNoise, Model, Warp};

fn gpu_or_skip() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(c) => Some(c),
        Err(e) if std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1") => {
            panic!("SPECTEX_REQUIRE_GPU=1 but no GPU: {e}")
        }
        Err(e) => {
            eprintln!("SKIPPED subdivision cross-check: {e}");
            None
        }
    }
}

fn windows() -> Vec<CaseWindow> {
    [
        ("origin", [0.0, 0.0], 1.0),
        ("far", [1.0e7, -1.0e7], 1.0),
        ("magnified", [-37.25, 11.5], 0.37),
        ("minified", [5.5, -13.25], 6.0),
    ]
    .into_iter()
    .map(|(name, offset, scale)| CaseWindow {
        name,
        width: 32,
        height: 32,
        offset,
        scale,
    })
    .collect()
}

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
    let Some(context) = gpu_or_skip() else {
        return;
    };
    let mut failed = Vec::new();
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        for (levels, hurst, cell) in [
            (0, 0.5, 8.0),
            (3, 0.2, 20.0),
            (8, 0.5, 64.0),
            (12, 0.9, 1000.0),
        ] {
            let model = Model::Subdivision(subdivision(stencil, levels, hurst, cell));
            let case = format!("{stencil:?} L={levels} H={hurst}");
            for (w, o) in check_model(&context, &case, &model, &windows()).unwrap() {
                println!("{case} {w}: max {:.2e}", o.comparison.max_abs);
                if !matches!(o.verdict, Verdict::Pass) {
                    failed.push(format!("{case} {w}: {}", o.summary()));
                }
            }
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn a_warped_subdivision_agrees_on_cpu_and_gpu() {
    let Some(context) = gpu_or_skip() else {
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
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        let model = Model::Warp(Warp {
            base: Box::new(Model::Subdivision(subdivision(stencil, 6, 0.5, 64.0))),
            x: Box::new(by(1)),
            y: Box::new(by(2)),
            strength: 6.0,
        });
        let case = format!("warped {stencil:?}");
        for (w, o) in check_model(&context, &case, &model, &windows()[..2]).unwrap() {
            println!("{case} {w}: max {:.2e}", o.comparison.max_abs);
            assert!(
                matches!(o.verdict, Verdict::Pass),
                "{case} {w}: {}",
                o.summary()
            );
        }
    }
}
