//! Criterion bench of the CPU steppers: Gray–Scott at 1024² (the reported size, all
//! threads) and 256², and Life at 1024². `cargo bench -p spectex-simulate`.

use criterion::{Criterion, criterion_group, criterion_main};
use spectex_model::simulation::{GrayScott, GrayScottPreset, LifeLike, Simulation, SimulationSpec};
use spectex_simulate::Simulator;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("simulate_step");
    group.sample_size(10);
    for side in [256u32, 1024] {
        let spec = SimulationSpec::new(
            side,
            side,
            0,
            1,
            Simulation::GrayScott(GrayScott::preset(GrayScottPreset::Mazes)),
        );
        let Ok(mut sim) = Simulator::new(&spec) else {
            return;
        };
        group.bench_function(format!("gray_scott_{side}"), |b| b.iter(|| sim.step()));
    }
    let spec = SimulationSpec::new(1024, 1024, 0, 1, Simulation::Life(LifeLike::conway()));
    if let Ok(mut sim) = Simulator::new(&spec) {
        group.bench_function("life_1024", |b| b.iter(|| sim.step()));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
