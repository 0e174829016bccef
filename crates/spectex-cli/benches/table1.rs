//! The paper's Table 1 (Gilet et al. 2014, §6.2) for the shared exemplars: special-function
//! calls per pixel, ms per 128² frame and Mpix/s on the CPU (all threads) and on the GPU (the
//! adapter wgpu picks; lavapipe under `cargo xtask verify`'s variables), for random phases
//! (r = 0), fixed phases (r = 0.2) and fixed phases + random placement, with the memory of the
//! stored frequencies.
//!
//! `cargo bench -p spectex-cli --bench table1` (also run by `cargo xtask bench`). Timings are
//! the best of several repetitions after a warm-up; they are reported, never asserted. Skips the
//! shared exemplars with a printed reason when `../shared` is absent (the built-in exemplar is
//! always measured).

#![allow(clippy::print_stdout, reason = "the table is the point of this bench")]
#![allow(
    clippy::unwrap_used,
    reason = "a bench fails loudly on the first unexpected error"
)]

#[path = "../tests/it/common/mod.rs"]
mod common;

use std::time::Instant;

use ndarray::Array3;
use spectex_cpu::{Evaluator, Window};
use spectex_model::{Model, Stratum, TextureModel};
use spectex_sampling::{FitOptions, TextureOptions, fit_texture};

const EXEMPLARS: &[&str] = &[
    "skimage_gravel.png",
    "skimage_brick.png",
    "astex_ambientcg_paving_height_512.png",
    "astex_ambientcg_sand_height_512.png",
    "embark_ts_water_1.jpg",
];

fn load(path: &std::path::Path) -> Array3<f64> {
    common::planes(&image::open(path).unwrap())
}

/// Bytes of stored frequencies: strata tables (2 f32 per entry) and structure cosines (2 i32,
/// amplitude and phase).
fn memory(m: &TextureModel) -> (usize, usize) {
    let strata = |s: &[Stratum]| {
        s.iter()
            .map(|st| st.sub_strata.iter().map(|t| 8 * t.len()).sum::<usize>())
            .sum::<usize>()
    };
    let mut tables = 0;
    let mut fixed = 0;
    for ch in &m.channels {
        tables += strata(&ch.strata);
        fixed += ch.structure.as_ref().map_or(0, |s| 16 * s.total_cosines());
    }
    if let Some(t) = &m.turbulence {
        tables += strata(&t.strata);
    }
    (tables, fixed)
}

fn best_of(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let start = Instant::now();
        f();
        best = best.min(start.elapsed().as_secs_f64());
    }
    best
}

fn smoke() {
    let builtin = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/default_exemplar.png"
    );
    let img = load(std::path::Path::new(builtin));
    for (r, placement) in [(0.0, false), (0.2, false), (0.2, true)] {
        let options = TextureOptions {
            fit: FitOptions {
                budget: 12,
                ..FitOptions::default()
            },
            structure: r,
            random_placement: placement,
            ..TextureOptions::default()
        };
        let (model, _) = fit_texture(img.view(), &options).unwrap();
        let eval = Evaluator::new(&Model::Texture(model)).unwrap();
        let v = eval.render(&Window::new(16, 16)).unwrap();
        assert_eq!(v.len(), 16 * 16 * 3);
        assert!(v.iter().all(|x| x.is_finite()));
    }
    println!(
        "table1: smoke run (no timings); `cargo bench -p spectex-cli --bench table1` measures"
    );
}

fn kib(bytes: usize) -> String {
    format!("{:.1}K", bytes as f64 / 1024.0)
}

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --all-targets` runs this binary without it:
    // then it only checks that every setting fits, renders and agrees in size on one small
    // exemplar (the built-in), without timing anything.
    let full = std::env::args().any(|a| a == "--bench");
    if !full {
        smoke();
        return;
    }
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures"
    );
    let mut inputs: Vec<(String, Array3<f64>)> = Vec::new();
    let builtin = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/default_exemplar.png"
    );
    inputs.push(("builtin".into(), load(std::path::Path::new(builtin))));
    if std::path::Path::new(dir).is_dir() {
        for name in EXEMPLARS {
            inputs.push((
                (*name).to_owned(),
                load(&std::path::Path::new(dir).join(name)),
            ));
        }
    } else {
        println!("skipping the shared exemplars: ../shared/testdata/textures is absent");
    }
    let gpu = match spectex_gpu::GpuContext::new() {
        Ok(c) => Some(c),
        Err(e) => {
            println!("no GPU column: {e}");
            None
        }
    };
    let gpu_name = gpu
        .as_ref()
        .map_or_else(|| "none".to_owned(), |c| c.adapter_name().to_owned());
    let threads = rayon::current_num_threads();
    println!(
        "\nTable 1 style, J = 50, 4 strata, r = 0.2 for fixed phases; CPU {threads} threads, GPU {gpu_name}.\n"
    );
    println!(
        "| exemplar | setting | calls/px | CPU ms/128² | CPU Mpix/s (512²) | GPU ms/128² | GPU Mpix/s (512²) | strata tables | fixed cosines |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let frame = Window::new(128, 128).at([1.0e4, -2.0e4], 1.0);
    let big = Window::new(512, 512).at([1.0e4, -2.0e4], 1.0);
    for (name, img) in &inputs {
        for (setting, r, placement) in [
            ("random phases", 0.0, false),
            ("fixed phases", 0.2, false),
            ("fixed + placement", 0.2, true),
        ] {
            let options = TextureOptions {
                fit: FitOptions::default(),
                structure: r,
                random_placement: placement,
                ..TextureOptions::default()
            };
            let (model, _) = fit_texture(img.view(), &options).unwrap();
            let calls = model.special_calls_per_pixel();
            let (tables, fixed) = memory(&model);
            let model = Model::Texture(model);
            let eval = Evaluator::new(&model).unwrap();
            let ms = 1e3
                * best_of(20, || {
                    std::hint::black_box(eval.render(&frame).unwrap());
                });
            let cpu_rate = 512.0 * 512.0
                / best_of(3, || {
                    std::hint::black_box(eval.render(&big).unwrap());
                })
                / 1e6;
            let (gpu_ms, gpu_rate) = match &gpu {
                Some(ctx) => match spectex_gpu::GpuEvaluator::new(ctx, &model) {
                    Ok(g) if g.render(&frame).is_err() => (
                        format!("({})", g.render(&frame).unwrap_err()),
                        "—".to_owned(),
                    ),
                    Ok(g) => {
                        let ms = 1e3
                            * best_of(10, || {
                                std::hint::black_box(g.render(&frame).unwrap());
                            });
                        let rate = 512.0 * 512.0
                            / best_of(3, || {
                                std::hint::black_box(g.render(&big).unwrap());
                            })
                            / 1e6;
                        (format!("{ms:.2}"), format!("{rate:.2}"))
                    }
                    Err(e) => (format!("({e})"), "—".to_owned()),
                },
                None => ("—".to_owned(), "—".to_owned()),
            };
            println!(
                "| {name} | {setting} | {calls} | {ms:.2} | {cpu_rate:.2} | {gpu_ms} | {gpu_rate} | {} | {} |",
                kib(tables),
                kib(fixed)
            );
        }
    }
}
