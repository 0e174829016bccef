//! The paper's Table 1 (Gilet et al. 2014, §6.2) for the built-in and shared exemplars, as
//! `spectex_reproduce::table1` measures it: special-function calls per pixel, ms per 128² frame
//! and Mpix/s on the CPU and on the GPU (the adapter wgpu picks; lavapipe under
//! `cargo xtask verify`'s variables), with the memory of the stored frequencies.
//!
//! `cargo bench -p spectex-reproduce --bench table1` (also run by `cargo xtask bench`). Timings
//! are reported, never asserted. Without `--bench` (as `cargo test --bench '*'` runs it) it
//! measures nothing: the crate's test runs the same measurement on tiny sizes.

#![allow(clippy::print_stdout, reason = "the table is the point of this bench")]

use std::process::ExitCode;

use spectex_reproduce::{Config, Effort, table1};

fn main() -> ExitCode {
    if !std::env::args().any(|a| a == "--bench") {
        println!("table1: measured by `cargo bench -p spectex-reproduce --bench table1`");
        return ExitCode::SUCCESS;
    }
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> spectex_reproduce::Result<()> {
    let config = Config::new(Vec::new(), Effort::Full, std::env::temp_dir());
    let mut inputs = vec![("built-in".to_owned(), table1::builtin_exemplar()?)];
    match &config.shared_textures {
        Some(dir) => {
            for name in table1::EXEMPLARS {
                inputs.push(((*name).to_owned(), table1::load_exemplar(&dir.join(name))?));
            }
        }
        None => println!("skipping the shared exemplars: ../shared/testdata/textures is absent"),
    }
    let gpu = match spectex_gpu::GpuContext::new() {
        Ok(c) => Some(c),
        Err(e) => {
            println!("no GPU column: {e}");
            None
        }
    };
    let mut tables = Vec::new();
    for (name, img) in inputs {
        tables.push((name, table1::measure(&img, 50, 20, gpu.as_ref(), true)?));
    }
    println!(
        "\nTable 1 style, J = 50, 4 strata, r = 0.2 for fixed phases; CPU {} threads, GPU {}.\n",
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
        gpu.as_ref()
            .map_or_else(|| "none".to_owned(), spectex_gpu::GpuContext::adapter_name)
    );
    print!("{}", table1::markdown(&tables));
    Ok(())
}
