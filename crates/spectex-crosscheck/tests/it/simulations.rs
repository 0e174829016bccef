//! The simulations on the CPU and on the GPU (lavapipe in CI): cellular automata equal cell
//! for cell, Gray–Scott pixel by pixel for its first steps within the derived bound and
//! statistically after many (`spectex_crosscheck::simulation`). Small grids: lavapipe is slow.
//! Skips with a printed reason when no GPU adapter exists, unless `SPECTEX_REQUIRE_GPU=1`.

use spectex_crosscheck::simulation::check_simulation;
use spectex_gpu::GpuContext;
use spectex_model::simulation::{
    Cyclic, Elementary, GrayScott, GrayScottPreset, LifeLike, Neighbourhood, Simulation,
    SimulationSpec, SwiftHohenberg,
};

use crate::common::gpu_or_skip;

fn check(context: &GpuContext, name: &str, spec: &SimulationSpec, criteria: &[&str]) {
    let checks = check_simulation(context, spec).unwrap_or_else(|e| panic!("{name}: {e}"));
    let used: Vec<&str> = checks.iter().map(|c| c.criterion).collect();
    assert_eq!(used, criteria, "{name}");
    for c in &checks {
        eprintln!(
            "{name}: {} {}: {}",
            c.criterion,
            if c.passed { "ok" } else { "FAILED" },
            c.detail
        );
        assert!(
            c.passed,
            "{name}: {} check failed: {}",
            c.criterion, c.detail
        );
    }
}

#[test]
fn automata_are_equal_cell_for_cell() {
    let Some(context) = gpu_or_skip("simulation cross-check") else {
        return;
    };
    let cases = [
        ("life", Simulation::Life(LifeLike::conway()), 60),
        (
            "highlife",
            Simulation::Life(LifeLike {
                rule: "B36/S23".to_owned(),
                density: 0.3,
            }),
            40,
        ),
        ("cyclic-313", Simulation::Cyclic(Cyclic::SPIRALS), 60),
        (
            "cyclic-vn",
            Simulation::Cyclic(Cyclic {
                states: 14,
                threshold: 1,
                neighbourhood: Neighbourhood::VonNeumann,
            }),
            60,
        ),
        ("rule-30", Simulation::Elementary(Elementary::RULE_30), 5),
        (
            "rule-110-single",
            Simulation::Elementary(Elementary {
                rule: 110,
                single: true,
                density: 0.5,
            }),
            0,
        ),
    ];
    // 67 × 45: sizes that are not multiples of the workgroup's side.
    for (name, simulation, steps) in cases {
        check(
            &context,
            name,
            &SimulationSpec::new(67, 45, steps, 3, simulation),
            &["exact"],
        );
    }
}

#[test]
fn gray_scott_agrees_pixelwise_then_statistically() {
    let Some(context) = gpu_or_skip("simulation cross-check") else {
        return;
    };
    let gs = Simulation::GrayScott(GrayScott::preset(GrayScottPreset::Mazes));
    check(
        &context,
        "gray-scott mazes",
        &SimulationSpec::new(96, 96, 2500, 2, gs),
        &["pixelwise", "statistical"],
    );
}

#[test]
fn swift_hohenberg_is_refused_on_the_gpu_with_a_reason() {
    let Some(context) = gpu_or_skip("simulation cross-check") else {
        return;
    };
    let spec = SimulationSpec::new(
        16,
        16,
        1,
        0,
        Simulation::SwiftHohenberg(SwiftHohenberg::STRIPES),
    );
    let e = check_simulation(&context, &spec)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("swift-hohenberg") && e.contains("CPU"), "{e}");
}
