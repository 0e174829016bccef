//! Project automation for spectex (`cargo xtask <command>`): orchestration only, it shells out to cargo.
//!
//! Each command is a list of [`Step`]s run in order by [`run_steps`], which prints a numbered header
//! per step, stops at the first failure naming the step, and ends with one summary line. A new
//! command is a new function building its steps (and checking the tools it needs first).
//!
//! This file holds the dispatch, the help, the [`Workspace`] and the step runner; the commands
//! are in `ci` (ci, verify, fmt), `runner` (test), `bench` (with `fastnoise`, FastNoiseSIMD's
//! harness), `gpu`, `fuzz`, `checks` (export-check, bevy-check, reproduce) and `browser` (CI's
//! browser test of `spectex view`, view-bench); `system` installs and finds lavapipe,
//! `json` reads cargo's and criterion's JSON.

use anyhow::{Context, Result, bail};
use std::env;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

mod bench;
mod browser;
mod checks;
mod ci;
mod fastnoise;
mod fuzz;
mod gpu;
mod json;
mod python;
mod runner;
mod system;

use bench::bench;
use checks::{bevy_check, export_check, reproduce};
use ci::{ci, verify};
use fuzz::fuzz;

/// Every command with the one line `cargo xtask help` prints for it.
const COMMANDS: &[(&str, &str)] = &[
    (
        "ci",
        "what CI runs: installs rustfmt, clippy and lavapipe if missing; fmt --check, clippy \
         -D warnings, every test once with the GPU on lavapipe, doc tests, one line per \
         cross-checked model (XTASK_TEST_RUNNER=nextest: tests by cargo-nextest)",
    ),
    (
        "test",
        "`cargo test --workspace --tests --bench '*'` with the test binaries run in parallel, \
         as many at a time as there are cores (XTASK_TEST_JOBS), each one's output whole when \
         it ends; `cargo xtask test -- ARGS` passes ARGS to every binary",
    ),
    (
        "fmt",
        "cargo fmt --all, and the kinds' modules it does not reach (declared by a macro); \
         what `ci` checks",
    ),
    (
        "python",
        "the Python bindings' pytest suite as CI runs it (venv and module under target/); \
         `cargo xtask python wheel [--no-default-features]`: the release wheel by maturin, its size, \
         the import time and the render overhead against Rust",
    ),
    (
        "verify",
        "GPU verification on lavapipe: GPU tests and the CPU-vs-GPU cross-check of \
         testdata/models, one line per model",
    ),
    (
        "bench",
        "criterion benches of RPN vs one FFT, then a table of medians; every model kind's \
         Mpix/s on 1 thread and all threads (target/bench/summary.md and summary.svg; \
         `cargo xtask bench kinds` for that summary alone); extra args go to criterion \
         (`cargo xtask bench -- --quick`); then the texture-by-example Table 1 (CPU and GPU). \
         `cargo xtask bench classic`: the classic noises on one thread against FastNoiseSIMD \
         (pyfastnoisesimd, installed in target/bench/fastnoisesimd-venv; skipped with a \
         message where it cannot be) on the same grid, ratios in target/bench/classic.md. \
         `cargo xtask bench gpu [--size N]`: every testdata model on the GPU (kernel-only by \
         timestamps, end to end) against the CPU on all threads, and the LRP Table 1 texture \
         frame, into target/bench/gpu.md and gpu.svg (lavapipe unless WGPU_ADAPTER_NAME is set)",
    ),
    (
        "gpu-report",
        "builds what a GPU machine without Rust needs to test and measure spectex there into \
         target/gpu-report/ (release CLI, models and export benches, spectex-gpu's and the \
         cross-check's tests and xtask stripped and compressed, the Vulkan loader's .deb files, \
         run.sh): `bash target/gpu-report/run.sh [SIDE]` there runs the tests on that GPU and \
         prints every testdata model's GPU kernel-only, GPU end-to-end (bench and CLI) and CPU \
         Mpix/s, and each exported module's cost in calibration cosines",
    ),
    (
        "gpu-table",
        "`gpu-table FILE… [--size N]`: the models bench's and run.sh's figures as one Markdown \
         table (what run.sh calls on the GPU machine)",
    ),
    (
        "fuzz",
        "long fuzz campaigns (optimised, overflow checks on): generated and mutated models \
         through the CPU (and the GPU on lavapipe when installed), images through the CLI; \
         `--cases N` per campaign (default 20000), `--seed S`; prints cases and findings",
    ),
    (
        "reproduce",
        "the papers' figures and claims regenerated and judged into target/reproduce/ \
         (index.html, report.md, claims.json): `cargo xtask reproduce [PAPER…] [--quick] \
         [--no-gpu]`, papers lrp, rpn, phasor, survey, gabor-example, tiling (all by default); exits 1 when a claim \
         recorded as reproduced no longer holds",
    ),
    (
        "bevy-check",
        "the WGSL export in Bevy: exports testdata/models/lrp-ring.json, builds \
         examples/bevy-material (its own project, never built by CI; target dir \
         target/bevy unless BEVY_TARGET_DIR), renders one frame headlessly on lavapipe and \
         compares it with the CPU render within the derived tolerance",
    ),
    (
        "export-check",
        "the WGSL export render test on lavapipe over every exportable model in \
         testdata/models, the textures and warps CI leaves out included (lavapipe compiles \
         each of those for 20-200 s): `cargo test --workspace --test it \
         export::exported_modules` with SPECTEX_EXPORT_ALL=1",
    ),
    (
        "view-bench",
        "`spectex view`'s redraw after \"new seed\" in headless Chromium, measured: the release \
         binary, 2 workers, a 1024x1024 view of MODEL (default testdata/models/lrp-gravel.json), \
         coarse and full times, the server's time per step, the CPU of browser and server; \
         `cargo xtask view-bench [MODEL.json] [--redraws N] [--pan X,Y] [--zoom K]`",
    ),
    ("help", "print this list"),
];

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<()> {
    let mut args = env::args_os().skip(1);
    let command = args.next().map(|a| a.to_string_lossy().into_owned());
    let rest: Vec<OsString> = args.collect();
    match command.as_deref() {
        None | Some("help" | "--help" | "-h") => {
            print_help();
            Ok(())
        }
        Some("ci") => {
            if !rest.is_empty() {
                bail!("`cargo xtask ci` takes no arguments (got {rest:?})");
            }
            ci(&Workspace::locate()?)
        }
        Some("verify") => {
            if !rest.is_empty() {
                bail!("`cargo xtask verify` takes no arguments (got {rest:?})");
            }
            verify(&Workspace::locate()?)
        }
        Some("fmt") => {
            if !rest.is_empty() {
                bail!("`cargo xtask fmt` takes no arguments (got {rest:?})");
            }
            ci::fmt(&Workspace::locate()?)
        }
        Some("test") => runner::test(&Workspace::locate()?, &rest),
        Some("python") => python::python(&Workspace::locate()?, &rest),
        Some("bench") => bench(&Workspace::locate()?, rest),
        Some("fuzz") => fuzz(&Workspace::locate()?, &rest),
        Some("gpu-report") => {
            if !rest.is_empty() {
                bail!("`cargo xtask gpu-report` takes no arguments (got {rest:?})");
            }
            gpu::gpu_report(&Workspace::locate()?)
        }
        Some("gpu-table") => gpu::gpu_table(&rest),
        Some("view-bench") => browser::view_bench(&Workspace::locate()?, &rest),
        Some("reproduce") => reproduce(&Workspace::locate()?, &rest),
        Some("export-check") => {
            if !rest.is_empty() {
                bail!("`cargo xtask export-check` takes no arguments (got {rest:?})");
            }
            export_check(&Workspace::locate()?)
        }
        Some("bevy-check") => {
            if !rest.is_empty() {
                bail!("`cargo xtask bevy-check` takes no arguments (got {rest:?})");
            }
            bevy_check(&Workspace::locate()?)
        }
        Some(other) => bail!(
            "unknown command `{other}`; valid commands: {}",
            COMMANDS
                .iter()
                .map(|(name, _)| *name)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

fn print_help() {
    println!("usage: cargo xtask <command>\n\ncommands:");
    for (name, about) in COMMANDS {
        println!("  {name:<9} {about}");
    }
}

/// The workspace root and the cargo to run there.
struct Workspace {
    root: PathBuf,
    cargo: OsString,
}

impl Workspace {
    fn locate() -> Result<Self> {
        let manifest_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        let root = manifest_dir
            .parent()
            .with_context(|| format!("{} has no parent directory", manifest_dir.display()))?
            .to_path_buf();
        // Cargo sets CARGO for the programs it runs, so nested calls use the same toolchain.
        let cargo = env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        Ok(Self { root, cargo })
    }

    /// `cargo <args>` to run in the workspace root.
    fn cargo(&self, args: &[&str]) -> Command {
        let mut command = Command::new(&self.cargo);
        command.args(args).current_dir(&self.root);
        command
    }
}

/// One numbered step of a command.
struct Step {
    title: String,
    command: Command,
}

/// Runs `steps` in order, stopping at the first failure; prints a header per step and a summary.
fn run_steps(name: &str, steps: Vec<Step>) -> Result<()> {
    let started = Instant::now();
    let count = steps.len();
    for (i, mut step) in steps.into_iter().enumerate() {
        eprintln!("xtask: [{}/{count}] {}", i + 1, step.title);
        let step_started = Instant::now();
        run_command(&mut step.command).with_context(|| {
            format!(
                "`cargo xtask {name}` failed at step {}/{count} ({})",
                i + 1,
                step.title
            )
        })?;
        eprintln!(
            "xtask: [{}/{count}] done in {:.1} s",
            i + 1,
            step_started.elapsed().as_secs_f64()
        );
    }
    eprintln!(
        "xtask: {name} passed: {count} step(s) in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn run_command(command: &mut Command) -> Result<()> {
    let shown = show(command);
    let status = command
        .status()
        .with_context(|| format!("could not start `{shown}`"))?;
    if !status.success() {
        bail!("`{shown}` failed ({status})");
    }
    Ok(())
}

/// The command line as a user would type it, for messages.
fn show(command: &Command) -> String {
    std::iter::once(command.get_program())
        .chain(command.get_args())
        .map(|part| part.to_string_lossy())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Whether `command` starts and exits successfully (its output discarded).
fn runs(command: &mut Command) -> bool {
    command
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|status| status.success())
}

/// The cargo target directory (`CARGO_TARGET_DIR`, relative to the workspace root, else
/// `target/`).
fn target_dir(ws: &Workspace) -> PathBuf {
    match env::var_os("CARGO_TARGET_DIR") {
        Some(target) => ws.root.join(target),
        None => ws.root.join("target"),
    }
}
