//! Criterion bench of GPU evaluation in Mpix/s: LRP with a budget of J = 50 cosines over 4 strata
//! (periods 4.5, 9, 16, 28 pixels, tables of 40 random frequencies — the model of
//! `spectex-cpu`'s `eval` bench, so the numbers compare), one 1024² window, read back included;
//! phasor noise in 2D and on a 3D plane (256², the CPU bench's models); and the synthetic grey
//! and colour textures of `testdata/models` (128², frame time printed in ms); and three classic
//! noises of `testdata/models` (256²).
//!
//! `cargo bench -p spectex-gpu --bench gpu`; on lavapipe set `WGPU_ADAPTER_NAME=llvmpipe` (and
//! `VK_DRIVER_FILES`/`VK_ICD_FILENAMES` to its ICD file). Skips with a message when no adapter
//! exists.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spectex_gpu::{GpuContext, GpuEvaluator, GpuWindow};
use spectex_model::fixtures::{lrp_four_strata, phasor_pwm};
use spectex_model::{Field, Model, PhasorOrientation};

fn bench(c: &mut Criterion) {
    let context = match GpuContext::new() {
        Ok(context) => context,
        Err(e) => {
            eprintln!("skipping the GPU bench: {e}");
            return;
        }
    };
    let side = spectex_testkit::bench::side(1024);
    let window = GpuWindow::new(side, side).at([1000.0, 2000.0], 1.0);
    let pixels = (side * side) as f64;
    let mut group = c.benchmark_group("gpu_lrp_eval");
    group.throughput(Throughput::Elements(pixels as u64));
    group.sample_size(10);
    let budget = 50;
    let gpu =
        GpuEvaluator::new(&context, &Model::Lrp(lrp_four_strata(budget))).expect("valid model");
    // One timed render first, printed in the unit the project reports.
    let start = Instant::now();
    black_box(gpu.render(&window).expect("render"));
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "LRP J={budget}, 4 strata, {side}²: {:.3} Mpix/s on {} (one render, {seconds:.2} s)",
        pixels / seconds / 1e6,
        gpu.adapter_name()
    );
    group.bench_function(format!("J{budget}_{side}x{side}"), |b| {
        b.iter(|| gpu.render(black_box(&window)).expect("render"))
    });
    group.finish();

    // Phasor noise (the CPU bench's models), 256²: host kernel tables and read-back included.
    let side = spectex_testkit::bench::side(256);
    let window = GpuWindow::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("gpu_phasor_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    for (name, dimensions, orientation) in [
        (
            "2d_aligned",
            2,
            PhasorOrientation::Aligned {
                angle: Field::constant(0.5),
            },
        ),
        ("3d_isotropic", 3, PhasorOrientation::Isotropic),
    ] {
        let model = Model::Phasor(phasor_pwm(dimensions, orientation));
        let gpu = GpuEvaluator::new_at_z(&context, &model, 17.5).expect("valid model");
        group.bench_function(format!("{name}_{side}x{side}"), |b| {
            b.iter(|| gpu.render(black_box(&window)).expect("render"))
        });
    }
    group.finish();

    // Texture by example (the cross-check's synthetic cases), 128²: the LRP passes of the strata
    // and turbulence, the texture pass and every read-back included.
    let side = 128;
    let window = GpuWindow::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("gpu_texture_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    for (name, json) in [
        (
            "grey",
            include_str!("../../../testdata/models/texture-synthetic-grey.json"),
        ),
        (
            "colour",
            include_str!("../../../testdata/models/texture-synthetic-colour.json"),
        ),
    ] {
        let model = spectex_model::from_json(json).expect("valid model");
        let gpu = GpuEvaluator::new(&context, &model).expect("valid model");
        let start = Instant::now();
        black_box(gpu.render(&window).expect("render"));
        println!(
            "texture {name}, {side}²: {:.1} ms per frame on {} (one render)",
            start.elapsed().as_secs_f64() * 1e3,
            gpu.adapter_name()
        );
        group.bench_function(format!("{name}_{side}x{side}"), |b| {
            b.iter(|| gpu.render(black_box(&window)).expect("render"))
        });
    }
    group.finish();

    // Classic noises (the cross-check's cases), 256²: fBm of Perlin noise (5 octaves), 3D
    // simplex noise, and 3D Worley turbulence (3 octaves of 27 cells), read-back included.
    let side = spectex_testkit::bench::side(256);
    let window = GpuWindow::new(side, side).at([1000.0, 2000.0], 1.0);
    let mut group = c.benchmark_group("gpu_classic_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    for (name, json) in [
        (
            "perlin_fbm",
            include_str!("../../../testdata/models/classic-perlin-fbm.json"),
        ),
        (
            "simplex_3d",
            include_str!("../../../testdata/models/classic-simplex-3d.json"),
        ),
        (
            "worley_3d_turbulence",
            include_str!("../../../testdata/models/classic-worley-3d-turbulence.json"),
        ),
    ] {
        let model = spectex_model::from_json(json).expect("valid model");
        let gpu = GpuEvaluator::new_at_z(&context, &model, 37.3).expect("valid model");
        let start = Instant::now();
        black_box(gpu.render(&window).expect("render"));
        let seconds = start.elapsed().as_secs_f64();
        println!(
            "classic {name}, {side}²: {:.2} Mpix/s on {} (one render)",
            (side * side) as f64 / seconds / 1e6,
            gpu.adapter_name()
        );
        group.bench_function(format!("{name}_{side}x{side}"), |b| {
            b.iter(|| gpu.render(black_box(&window)).expect("render"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
