//! Golden images: a small fixed-seed run of every preset, compared with the PNG stored under
//! `testdata/simulations/`. The CPU gives the same bytes on every machine (plain `*` and `+`,
//! no fused operations, no thread-dependent order), so the only tolerance is the PNG's 8-bit
//! quantisation: a value within half a level of the stored one (plus 10⁻³ of a level for the
//! f32 → level arithmetic) passes. Regenerate deliberately with
//! `SPECTEX_UPDATE_GOLDEN=1 cargo test --workspace --test it golden::`, and say in the commit
//! why the images changed.

use std::path::PathBuf;

use spectex_model::simulation::{
    Cyclic, Elementary, GrayScott, GrayScottPreset, LifeLike, Simulation, SimulationSpec,
    SwiftHohenberg,
};
use spectex_simulate::Simulator;

/// The golden runs: name, spec. Kept small (128², a few thousand cell-steps per pixel at most)
/// so the whole test stays around a second.
fn golden_specs() -> Vec<(&'static str, SimulationSpec)> {
    let gs = |preset| Simulation::GrayScott(GrayScott::preset(preset));
    let mut specs: Vec<(&'static str, SimulationSpec)> = [
        ("gray-scott-spots", GrayScottPreset::Spots),
        ("gray-scott-stripes", GrayScottPreset::Stripes),
        ("gray-scott-mazes", GrayScottPreset::Mazes),
        ("gray-scott-holes", GrayScottPreset::Holes),
    ]
    .into_iter()
    .map(|(name, preset)| (name, SimulationSpec::new(128, 128, 3000, 1, gs(preset))))
    .collect();
    specs.extend([
        (
            "swift-hohenberg",
            SimulationSpec::new(
                128,
                128,
                200,
                1,
                Simulation::SwiftHohenberg(SwiftHohenberg::STRIPES),
            ),
        ),
        (
            "life",
            SimulationSpec::new(128, 128, 100, 1, Simulation::Life(LifeLike::conway())),
        ),
        (
            "elementary",
            SimulationSpec::new(128, 128, 0, 1, Simulation::Elementary(Elementary::RULE_30)),
        ),
        (
            "cyclic",
            SimulationSpec::new(128, 128, 150, 1, Simulation::Cyclic(Cyclic::SPIRALS)),
        ),
    ]);
    specs
}

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/simulations")
}

fn level(g: f32) -> f64 {
    f64::from(g.clamp(0.0, 1.0)) * 255.0
}

#[test]
fn presets_match_their_golden_images() {
    let update = std::env::var_os("SPECTEX_UPDATE_GOLDEN").is_some();
    let mut failures = Vec::new();
    for (name, spec) in golden_specs() {
        let mut sim = Simulator::new(&spec).unwrap_or_else(|e| panic!("{name}: {e}"));
        sim.run(Simulator::total_steps(&spec), &mut |_| {});
        let grey = sim.grey();
        let path = golden_dir().join(format!("{name}.png"));
        if update {
            let bytes = grey.iter().map(|&g| level(g).round() as u8).collect();
            let img = image::GrayImage::from_raw(spec.width, spec.height, bytes)
                .unwrap_or_else(|| panic!("{name}: image size"));
            std::fs::create_dir_all(golden_dir()).unwrap_or_else(|e| panic!("{e}"));
            spectex_testkit::image_files::save(&image::DynamicImage::ImageLuma8(img), &path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            continue;
        }
        let stored = spectex_testkit::image_files::open(&path)
            .unwrap_or_else(|e| {
                panic!(
                    "{}: {e}; create it with SPECTEX_UPDATE_GOLDEN=1",
                    path.display()
                )
            })
            .to_luma8();
        assert_eq!(stored.dimensions(), (spec.width, spec.height), "{name}");
        let worst = grey
            .iter()
            .zip(stored.as_raw())
            .enumerate()
            .map(|(i, (&g, &s))| (i, (level(g) - f64::from(s)).abs()))
            .fold((0, 0.0f64), |a, b| if b.1 > a.1 { b } else { a });
        if worst.1 > 0.501 {
            let (x, y) = (worst.0 % spec.width as usize, worst.0 / spec.width as usize);
            failures.push(format!(
                "{name}: pixel ({x}, {y}) differs by {:.2} levels from {}",
                worst.1,
                path.display()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{}\nIf the change is intended, regenerate with `SPECTEX_UPDATE_GOLDEN=1 cargo test \
         --workspace --test it golden::` and explain in the commit message why the images changed.",
        failures.join("\n")
    );
}
