//! CPU (all threads) against the GPU adapter in one run: LRP with J = 50 cosines over 4 strata,
//! one 1024² window, read-back included. Prints the Mpix/s of each and their ratio.
//!
//! `cargo bench -p spectex-crosscheck --bench cpu_vs_gpu`; on lavapipe set
//! `WGPU_ADAPTER_NAME=llvmpipe`. Without an adapter only the CPU is measured.

#![allow(clippy::print_stdout, reason = "the ratio line is the bench's report")]
#![allow(clippy::unwrap_used, reason = "a bench fails loudly")]

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spectex_cpu::{Evaluator, Window};
use spectex_gpu::{GpuContext, GpuEvaluator, GpuWindow};
use spectex_model::Model;
use spectex_model::fixtures::lrp_four_strata;

/// The 4-stratum, J = 50 model of the spectex-cpu and spectex-gpu benches.
fn model() -> Model {
    Model::Lrp(lrp_four_strata(50))
}

/// The window side (benchmarking; 64 in a test pass).
fn side() -> usize {
    spectex_testkit::bench::side(1024)
}

fn bench(c: &mut Criterion) {
    let model = model();
    let cpu = Evaluator::new(&model).unwrap();
    let mut group = c.benchmark_group("lrp_j50_1024");
    group.sample_size(10);
    group.throughput(Throughput::Elements((side() * side()) as u64));
    let window = Window::new(side(), side());
    group.bench_function("cpu_all_threads", |b| {
        b.iter(|| black_box(cpu.render(&window).unwrap()));
    });
    // `cargo test --all-targets` runs benches once as a smoke test (no `--bench` argument): skip
    // the extra timed renders there, they take seconds on lavapipe.
    let measuring = std::env::args().any(|a| a == "--bench");
    let time = |f: &dyn Fn()| {
        f();
        let start = Instant::now();
        f();
        start.elapsed().as_secs_f64()
    };
    let cpu_s = if measuring {
        time(&|| {
            black_box(cpu.render(&window).unwrap());
        })
    } else {
        0.0
    };
    match GpuContext::new() {
        Ok(context) => {
            let gpu = GpuEvaluator::new(&context, &model).unwrap();
            let gwindow = GpuWindow::new(side(), side());
            group.bench_function("gpu", |b| {
                b.iter(|| black_box(gpu.render(&gwindow).unwrap()));
            });
            if !measuring {
                group.finish();
                return;
            }
            let gpu_s = time(&|| {
                black_box(gpu.render(&gwindow).unwrap());
            });
            let mpix = (side() * side()) as f64 / 1e6;
            println!(
                "lrp J=50 1024²: CPU {:.2} Mpix/s, {} {:.2} Mpix/s, GPU/CPU speed ratio {:.2}",
                mpix / cpu_s,
                gpu.adapter_name(),
                mpix / gpu_s,
                cpu_s / gpu_s
            );
        }
        Err(e) => println!("no GPU adapter, CPU only: {e}"),
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
