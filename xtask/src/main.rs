//! Project automation for spectex (`cargo xtask <command>`): orchestration only, it shells out to cargo.
//!
//! Each command is a list of [`Step`]s run in order by [`run_steps`], which prints a numbered header
//! per step, stops at the first failure naming the step, and ends with one summary line. A new
//! command is a new function building its steps (and checking the tools it needs first).

use anyhow::{Context, Result, bail};
use std::env;
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Instant, SystemTime};

mod gpu;
mod python;

/// Every command with the one line `cargo xtask help` prints for it.
const COMMANDS: &[(&str, &str)] = &[
    (
        "ci",
        "what CI runs: installs rustfmt, clippy and lavapipe if missing; fmt --check, clippy \
         -D warnings, every test once with the GPU on lavapipe, doc tests, one line per \
         cross-checked model (XTASK_TEST_RUNNER=nextest: tests by cargo-nextest)",
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
        "builds what a GPU machine without Rust needs to measure spectex there into \
         target/gpu-report/ (release CLI, models bench and xtask stripped and compressed, the \
         Vulkan loader's .deb files, run.sh): `bash target/gpu-report/run.sh [SIDE]` there prints \
         every testdata model's GPU kernel-only, GPU end-to-end (bench and CLI) and CPU Mpix/s",
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
         [--no-gpu]`, papers lrp, rpn, phasor, survey (all by default); exits 1 when a claim \
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
    ("help", "print this list"),
];

/// Benchmark pairs reported as "RPN time in units of one FFT of the output size".
const FFT_EQUIVALENTS: &[(&str, &str)] = &[
    ("rpn_rgb_512_same_size", "fft2_c64_512x512"),
    ("rpn_rgb_512_to_2048", "fft2_c64_2048x2048"),
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

/// Installs rustfmt and clippy with rustup when either is missing; fails, saying how to install
/// them, when that is not possible.
fn ensure_rustfmt_and_clippy(ws: &Workspace) -> Result<()> {
    let missing = || -> Vec<&'static str> {
        [("rustfmt", "fmt"), ("clippy", "clippy")]
            .into_iter()
            .filter(|(_, subcommand)| !runs(&mut ws.cargo(&[subcommand, "--version"])))
            .map(|(tool, _)| tool)
            .collect()
    };
    let first = missing();
    if first.is_empty() {
        return Ok(());
    }
    // rustup installs components for the user who owns the toolchain: no root needed. Under
    // `cargo`, RUSTUP_TOOLCHAIN names the toolchain running us, so that one gets them.
    if runs(Command::new("rustup").arg("--version")) {
        let mut add = Command::new("rustup");
        add.args(["component", "add"]).args(&first);
        eprintln!("xtask: {} missing: {}", first.join(" and "), show(&add));
        run_command(&mut add)?;
    }
    let still = missing();
    if !still.is_empty() {
        bail!(
            "{} not installed; install with: rustup component add rustfmt clippy",
            still.join(" and ")
        );
    }
    Ok(())
}

/// The `clippy-driver` of the toolchain running us (beside its `rustc`, in the sysroot's `bin`).
fn clippy_driver() -> Result<PathBuf> {
    let rustc = env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let output = Command::new(&rustc)
        .args(["--print", "sysroot"])
        .output()
        .context("could not run `rustc --print sysroot`")?;
    let sysroot = PathBuf::from(String::from_utf8_lossy(&output.stdout).trim());
    let driver = sysroot
        .join("bin")
        .join(format!("clippy-driver{}", env::consts::EXE_SUFFIX));
    if !driver.is_file() {
        bail!(
            "clippy-driver not found at {}; install it with: rustup component add clippy",
            driver.display()
        );
    }
    Ok(driver)
}

/// Whether this process runs as root (effective uid 0, from `/proc/self/status`).
fn is_root() -> bool {
    fs::read_to_string("/proc/self/status").is_ok_and(|status| {
        status
            .lines()
            .find_map(|line| line.strip_prefix("Uid:"))
            .and_then(|ids| ids.split_whitespace().nth(1))
            == Some("0")
    })
}

/// The Debian packages of lavapipe (software Vulkan) and the Vulkan loader wgpu opens.
const LAVAPIPE_PACKAGES: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];

/// The packages of `packages` that dpkg does not list as installed; none where there is no dpkg
/// (not Debian or Ubuntu: there [`lavapipe_icd`] says what is missing).
fn missing_debian_packages<'a>(packages: &[&'a str]) -> Vec<&'a str> {
    packages
        .iter()
        .copied()
        .filter(|package| {
            Command::new("dpkg-query")
                .args(["--show", "--showformat=${Status}", package])
                .stderr(Stdio::null())
                .output()
                .is_ok_and(|out| String::from_utf8_lossy(&out.stdout) != "install ok installed")
        })
        .collect()
}

/// `apt-get update` and `apt-get install` of `packages` when running as root with apt-get;
/// otherwise an error saying what to install.
fn apt_install(packages: &[&str], what: &str) -> Result<()> {
    let install = ["install", "-y", "--no-install-recommends"];
    if !is_root() || !runs(Command::new("apt-get").arg("--version")) {
        bail!(
            "{what} is not installed; install it as root with `apt-get update && apt-get {} {}`",
            install.join(" "),
            packages.join(" ")
        );
    }
    eprintln!("xtask: installing {what}: {}", packages.join(" "));
    let apt_get = |args: &[&str]| {
        run_command(
            Command::new("apt-get")
                .args(args)
                .env("DEBIAN_FRONTEND", "noninteractive"),
        )
    };
    apt_get(&["update"])?;
    apt_get(&[&install[..], packages].concat())
}

/// The lavapipe ICD, after installing lavapipe and the Vulkan loader (as root, on Debian or
/// Ubuntu) when they are missing. An ICD named by `VK_DRIVER_FILES`/`VK_ICD_FILENAMES` is the
/// user's choice and installs nothing.
fn ensure_lavapipe() -> Result<PathBuf> {
    if ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"]
        .iter()
        .all(|var| env::var_os(var).is_none())
    {
        let missing = missing_debian_packages(LAVAPIPE_PACKAGES);
        if !missing.is_empty() {
            apt_install(&missing, "lavapipe (software Vulkan, for the GPU tests)")?;
        }
    }
    lavapipe_icd()
}

/// Where Debian's `mesa-vulkan-drivers` puts the lavapipe ICD file.
const LAVAPIPE_ICD_DIR: &str = "/usr/share/vulkan/icd.d";

/// The lavapipe ICD: `VK_DRIVER_FILES` or `VK_ICD_FILENAMES` when set (first existing file of
/// the list), else `lvp_icd.<arch>.json` from `mesa-vulkan-drivers`.
fn lavapipe_icd() -> Result<PathBuf> {
    for var in ["VK_DRIVER_FILES", "VK_ICD_FILENAMES"] {
        if let Some(value) = env::var_os(var) {
            let found = env::split_paths(&value).find(|p| p.is_file());
            match found {
                Some(path) => return Ok(path),
                None => bail!(
                    "{var} is set to {value:?} but names no existing ICD file; unset it to use \
                     lavapipe from mesa-vulkan-drivers"
                ),
            }
        }
    }
    let preferred = Path::new(LAVAPIPE_ICD_DIR).join(format!("lvp_icd.{}.json", env::consts::ARCH));
    if preferred.is_file() {
        return Ok(preferred);
    }
    let any = fs::read_dir(LAVAPIPE_ICD_DIR).ok().and_then(|dir| {
        dir.filter_map(|e| e.ok().map(|e| e.path())).find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("lvp_icd."))
        })
    });
    any.with_context(|| {
        format!(
            "lavapipe (software Vulkan) is not installed: no {} ; install it with \
             `apt-get install mesa-vulkan-drivers libvulkan1` (Debian/Ubuntu), or point \
             VK_DRIVER_FILES at a Vulkan ICD file",
            preferred.display()
        )
    })
}

/// Sets the environment that runs the GPU tests on lavapipe and makes a missing adapter a
/// failure (`SPECTEX_REQUIRE_GPU=1`) instead of a skip.
fn lavapipe_env(command: &mut Command, icd: &Path) {
    command
        .env("VK_DRIVER_FILES", icd)
        .env("VK_ICD_FILENAMES", icd)
        .env("WGPU_ADAPTER_NAME", "llvmpipe")
        .env("SPECTEX_REQUIRE_GPU", "1");
}

/// What runs the tests: `cargo test`, or cargo-nextest with `XTASK_TEST_RUNNER=nextest`. On the
/// 2-core CI machine nextest was no faster (one 90 s fidelity test bounds both; nextest starts a
/// process per test and cannot run the table1 bench, so the benches need a second command), so
/// it is a choice, not the default.
#[derive(Clone, Copy, PartialEq, Eq)]
enum TestRunner {
    Nextest,
    Cargo,
}

impl TestRunner {
    fn from_env(ws: &Workspace) -> Result<Self> {
        match env::var("XTASK_TEST_RUNNER").as_deref() {
            Err(_) | Ok("" | "cargo") => Ok(Self::Cargo),
            Ok("nextest") if runs(&mut ws.cargo(&["nextest", "--version"])) => Ok(Self::Nextest),
            Ok("nextest") => bail!(
                "XTASK_TEST_RUNNER=nextest but cargo-nextest is not installed; install it with \
                 `cargo install cargo-nextest --locked`, or unset XTASK_TEST_RUNNER"
            ),
            Ok(other) => bail!("XTASK_TEST_RUNNER must be `cargo` or `nextest`, not `{other}`"),
        }
    }
}

/// The cargo target directory (`CARGO_TARGET_DIR`, relative to the workspace root, else
/// `target/`).
fn target_dir(ws: &Workspace) -> PathBuf {
    match env::var_os("CARGO_TARGET_DIR") {
        Some(target) => ws.root.join(target),
        None => ws.root.join("target"),
    }
}

/// The file the cross-check suite (`crates/spectex-crosscheck/tests/it/models.rs`) writes its
/// `crosscheck:` lines to, one per model, when `SPECTEX_CROSSCHECK_SUMMARY` names it: the test
/// run that checks the models is the one that reports them, so nothing is built or run twice.
struct CrosscheckSummary {
    path: PathBuf,
}

impl CrosscheckSummary {
    const ENV: &str = "SPECTEX_CROSSCHECK_SUMMARY";

    /// `target/crosscheck/summary.txt`, with an earlier run's summary removed so that only this
    /// run's lines can be reported.
    fn prepare(ws: &Workspace) -> Result<Self> {
        let dir = target_dir(ws).join("crosscheck");
        fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join("summary.txt");
        match fs::remove_file(&path) {
            Err(err) if err.kind() != std::io::ErrorKind::NotFound => {
                return Err(err).with_context(|| format!("removing {}", path.display()));
            }
            _ => {}
        }
        Ok(Self { path })
    }

    fn apply(&self, command: &mut Command) {
        command.env(Self::ENV, &self.path);
    }

    /// Prints the suite's lines; fails when it wrote none (it skipped, or did not run).
    fn report(&self) -> Result<()> {
        let text = match fs::read_to_string(&self.path) {
            Ok(text) => text,
            Err(err) if err.kind() == std::io::ErrorKind::NotFound => String::new(),
            Err(err) => {
                return Err(err).with_context(|| format!("reading {}", self.path.display()));
            }
        };
        let lines: Vec<&str> = text
            .lines()
            .filter(|l| l.starts_with("crosscheck:"))
            .collect();
        if lines.is_empty() {
            bail!(
                "the cross-check suite wrote no model line to {}: did it skip, or not run?",
                self.path.display()
            );
        }
        for line in &lines {
            println!("{line}");
        }
        eprintln!(
            "xtask: verify passed: {} model(s) agree on CPU and lavapipe",
            lines.len()
        );
        Ok(())
    }
}

/// `cargo xtask ci`. The tests run once, on lavapipe with `SPECTEX_REQUIRE_GPU=1`, so the GPU
/// tests and the cross-check suite of `cargo xtask verify` run (and are built) in the test step,
/// and verify's report comes from that run. Every cargo command gets the same environment and
/// the test commands the same package selection (`--workspace`): a different selection unifies
/// dependency features differently and rebuilds the test binaries.
fn ci(ws: &Workspace) -> Result<()> {
    ensure_rustfmt_and_clippy(ws)?;
    let icd = ensure_lavapipe()?;
    let runner = TestRunner::from_env(ws)?;
    let summary = CrosscheckSummary::prepare(ws)?;
    eprintln!(
        "xtask: ci with {}, GPU tests on lavapipe (ICD {})",
        match runner {
            TestRunner::Nextest => "cargo nextest",
            TestRunner::Cargo => "cargo test",
        },
        icd.display()
    );
    // Clippy runs inside the test build instead of as a check build of its own (which compiled
    // every dependency a second time, in check mode: about 2 minutes of a 2-core machine).
    // `clippy-driver` as cargo's workspace wrapper is what `cargo clippy` itself sets up; it
    // lints the workspace's crates (every target the steps build: libraries, binaries, tests,
    // benches, examples) while compiling them, and is plain rustc for dependencies. With
    // `-D warnings` any lint or compiler warning fails the build. Every cargo step gets the same
    // environment, so no step rebuilds what another built.
    let driver = clippy_driver()?;
    let rustflags = match env::var("RUSTFLAGS") {
        Ok(flags) if !flags.trim().is_empty() => format!("{flags} -D warnings"),
        _ => "-D warnings".to_owned(),
    };
    let step = |title: &str, args: &[&str]| {
        let mut command = ws.cargo(args);
        lavapipe_env(&mut command, &icd);
        summary.apply(&mut command);
        command
            .env("RUSTC_WORKSPACE_WRAPPER", &driver)
            .env("RUSTFLAGS", &rustflags);
        Step {
            title: title.to_owned(),
            command,
        }
    };
    let mut steps = vec![step(
        "cargo fmt --check",
        &["fmt", "--all", "--", "--check"],
    )];
    match runner {
        TestRunner::Nextest => {
            steps.push(step(
                "cargo nextest run --workspace --tests (clippy -D warnings; GPU tests and cross-check on lavapipe)",
                &["nextest", "run", "--workspace", "--tests"],
            ));
            // The benches in test mode (one quick pass each): nextest cannot list the table1
            // bench, which has its own `main`. `--benches` would run the libraries' unit tests
            // again (a library is a bench target too); `--bench '*'` is the [[bench]]es only.
            steps.push(step(
                "cargo test --bench '*' (each bench once, as a test)",
                &["test", "--workspace", "--bench", "*"],
            ));
        }
        // Every target but the examples, which are built once as programs below: with
        // `--all-targets` they would also be linked a second time as test harnesses.
        // `--tests` is every target with `test = true`: the libraries' and binaries' unit tests
        // and the integration tests; `--lib --bins` would also build a harness for the targets
        // that say `test = false` (spectex-cli's, whose unit tests are in its `it` binary).
        // `--bench '*'` is the [[bench]]es only (`--benches` adds the libraries again).
        TestRunner::Cargo => steps.push(step(
            "cargo test --tests --bench '*' (clippy -D warnings; GPU tests and cross-check on lavapipe)",
            &["test", "--workspace", "--tests", "--bench", "*"],
        )),
    }
    steps.push(step("cargo test --doc", &["test", "--workspace", "--doc"]));
    // The numbered examples, built in the test profile with the workspace's feature set (the
    // dependencies the test step built, so only the examples are compiled) and run as
    // `cargo run --example NAME` would run them. `cargo run -p spectex-cli` would resolve features
    // for that package alone and rebuild much of the workspace.
    steps.push(step(
        "cargo build --examples (test profile, clippy -D warnings)",
        &["build", "--workspace", "--examples", "--profile", "test"],
    ));
    let examples_out = target_dir(ws).join("examples-out");
    fs::create_dir_all(&examples_out)
        .with_context(|| format!("creating {}", examples_out.display()))?;
    let examples_bin = target_dir(ws).join("debug").join("examples");
    for name in example_names(ws)? {
        let mut command =
            Command::new(examples_bin.join(format!("{name}{}", env::consts::EXE_SUFFIX)));
        command.arg(&examples_out).current_dir(&ws.root);
        lavapipe_env(&mut command, &icd);
        steps.push(Step {
            title: format!("example {name} (as `cargo run --example {name}` runs it)"),
            command,
        });
    }
    steps.extend(python::ci_steps(ws, &|command: &mut Command| {
        lavapipe_env(command, &icd);
        summary.apply(command);
        command
            .env("RUSTC_WORKSPACE_WRAPPER", &driver)
            .env("RUSTFLAGS", &rustflags);
    })?);
    run_steps("ci", steps)?;
    summary.report()
}

/// The crates whose tests `cargo xtask verify` runs.
const VERIFIED_PACKAGES: &[&str] = &["spectex-gpu", "spectex-crosscheck"];

/// `cargo xtask verify`: the GPU tests and the cross-check suite on lavapipe, with a missing
/// adapter an error (`SPECTEX_REQUIRE_GPU=1`); prints the suite's line per model. The tests are
/// those `cargo xtask ci` builds (`--workspace`), picked by package after the build: selecting
/// the two crates with `-p` would resolve dependency features for them alone and build nearly
/// everything a second time.
fn verify(ws: &Workspace) -> Result<()> {
    let icd = ensure_lavapipe()?;
    eprintln!("xtask: verify on lavapipe, ICD {}", icd.display());
    let summary = CrosscheckSummary::prepare(ws)?;
    let gpu_env = |command: &mut Command| {
        lavapipe_env(command, &icd);
        summary.apply(command);
    };
    let steps = match TestRunner::from_env(ws)? {
        TestRunner::Nextest => {
            let filter = VERIFIED_PACKAGES
                .iter()
                .map(|p| format!("package({p})"))
                .collect::<Vec<_>>()
                .join(" | ");
            let mut command = ws.cargo(&["nextest", "run", "--workspace", "--tests", "-E"]);
            command.arg(&filter);
            gpu_env(&mut command);
            vec![Step {
                title: format!("cargo nextest run -E '{filter}' (lavapipe, SPECTEX_REQUIRE_GPU=1)"),
                command,
            }]
        }
        TestRunner::Cargo => test_executables(ws, &gpu_env, VERIFIED_PACKAGES)?
            .into_iter()
            .map(|test| {
                let mut command = Command::new(&test.executable);
                // What `cargo test` gives a test binary.
                command
                    .current_dir(&test.package_dir)
                    .env("CARGO_MANIFEST_DIR", &test.package_dir);
                gpu_env(&mut command);
                Step {
                    title: format!("{} (lavapipe, SPECTEX_REQUIRE_GPU=1)", test.source),
                    command,
                }
            })
            .collect(),
    };
    run_steps("verify", steps)?;
    summary.report()
}

/// A test binary cargo built.
struct TestExecutable {
    executable: PathBuf,
    package_dir: PathBuf,
    /// The target's source file relative to the workspace root, to name it.
    source: String,
}

/// The test binaries of `packages` among those of `cargo test --workspace --tests`, building
/// them first when they are not up to date (with `env`, the environment of the runs).
fn test_executables(
    ws: &Workspace,
    env: &dyn Fn(&mut Command),
    packages: &[&str],
) -> Result<Vec<TestExecutable>> {
    let mut build = ws.cargo(&[
        "test",
        "--workspace",
        "--tests",
        "--no-run",
        "--message-format=json-render-diagnostics",
    ]);
    env(&mut build);
    eprintln!("xtask: building the tests: {}", show(&build));
    let output = build
        .stderr(Stdio::inherit())
        .output()
        .with_context(|| format!("could not start `{}`", show(&build)))?;
    if !output.status.success() {
        bail!("`{}` failed ({})", show(&build), output.status);
    }
    let mut found = Vec::new();
    for line in String::from_utf8_lossy(&output.stdout).lines() {
        if !line.contains(r#""reason":"compiler-artifact""#) {
            continue;
        }
        let (Some(executable), Some(manifest), Some(source)) = (
            json_string_field(line, "executable"),
            json_string_field(line, "manifest_path"),
            json_string_field(line, "src_path"),
        ) else {
            continue; // a library, or a test without an executable
        };
        let Some(package_dir) = Path::new(&manifest).parent() else {
            continue;
        };
        if packages
            .iter()
            .any(|p| package_dir.ends_with(Path::new("crates").join(p)))
        {
            found.push(TestExecutable {
                executable: executable.into(),
                package_dir: package_dir.to_path_buf(),
                source: Path::new(&source)
                    .strip_prefix(&ws.root)
                    .unwrap_or(Path::new(&source))
                    .display()
                    .to_string(),
            });
        }
    }
    if found.is_empty() {
        bail!(
            "`{}` built no test of {}",
            show(&build),
            packages.join(" or ")
        );
    }
    found.sort_by(|a, b| a.source.cmp(&b.source));
    Ok(found)
}

/// The string value of the first `"key":"…"` in a line of cargo's JSON messages (which have no
/// spaces between tokens); `None` when the key is absent or not a string (`"executable":null`).
/// Found by string search, so that xtask needs no JSON library.
fn json_string_field(line: &str, key: &str) -> Option<String> {
    let start = line.find(&format!("\"{key}\":\""))? + key.len() + 4;
    let mut value = String::new();
    let mut chars = line[start..].chars();
    loop {
        match chars.next()? {
            '"' => return Some(value),
            '\\' => match chars.next()? {
                'n' => value.push('\n'),
                't' => value.push('\t'),
                'u' => {
                    let hex: String = chars.by_ref().take(4).collect();
                    value.push(char::from_u32(u32::from_str_radix(&hex, 16).ok()?)?);
                }
                escaped => value.push(escaped), // \" \\ \/
            },
            c => value.push(c),
        }
    }
}

/// Cases per campaign of `cargo xtask fuzz` unless `--cases` says otherwise.
const FUZZ_DEFAULT_CASES: u64 = 20_000;

/// `cargo xtask fuzz [--cases N] [--seed S]`: the fuzz tests of the kit (CPU), the CLI (images)
/// and the GPU crate, selected by the `fuzz_` in their names, with `SPECTEX_FUZZ_CASES` and
/// `SPECTEX_FUZZ_SEED` set, in the `fuzz` profile (release with overflow checks and debug
/// assertions, so arithmetic overflow is a finding, not a silent wrap). Prints each campaign's
/// summary (`fuzz <name>: …` and its indented lines), then the totals; fails if any campaign
/// did.
fn fuzz(ws: &Workspace, args: &[OsString]) -> Result<()> {
    let mut cases = FUZZ_DEFAULT_CASES;
    let mut seed: Option<u64> = None;
    let mut args = args.iter().map(|a| a.to_string_lossy().into_owned());
    while let Some(arg) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .with_context(|| format!("`{name}` needs a value"))?
                .parse::<u64>()
                .with_context(|| format!("`{name}` takes a non-negative integer"))
        };
        match arg.as_str() {
            "--cases" => cases = value("--cases")?,
            "--seed" => seed = Some(value("--seed")?),
            other => bail!("`cargo xtask fuzz` takes `--cases N` and `--seed S` (got `{other}`)"),
        }
    }
    let icd = lavapipe_icd().ok();
    let campaigns: [(&str, &[&str]); 3] = [
        (
            "CPU: generated and mutated models",
            &["-p", "spectex-testkit", "--test", "it"],
        ),
        ("CLI: image files", &["-p", "spectex-cli", "--tests"]),
        ("GPU: generated models", &["-p", "spectex-gpu", "--tests"]),
    ];
    let started = Instant::now();
    let (mut total_cases, mut total_findings, mut failed) = (0u64, 0u64, Vec::new());
    for (title, target) in campaigns {
        let mut command = ws.cargo(&["test", "--profile", "fuzz"]);
        command
            .args(target)
            .args(["--", "fuzz_", "--nocapture", "--test-threads", "1"])
            .env("SPECTEX_FUZZ_CASES", cases.to_string());
        if let Some(seed) = seed {
            command.env("SPECTEX_FUZZ_SEED", seed.to_string());
        }
        if let Some(icd) = &icd {
            command
                .env("VK_DRIVER_FILES", icd)
                .env("VK_ICD_FILENAMES", icd)
                .env("WGPU_ADAPTER_NAME", "llvmpipe");
        }
        eprintln!("xtask: fuzz {title}: {}", show(&command));
        let output = command
            .stderr(Stdio::inherit())
            .output()
            .with_context(|| format!("could not start `{}`", show(&command)))?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        let mut in_summary = false;
        for line in stdout.lines() {
            // A summary is its `fuzz <name>: N cases …` line and the indented lines after it;
            // with --nocapture the harness's `test <name> ... ` may stand before it on the line.
            let line = line.find("fuzz ").map_or(line, |i| &line[i..]);
            if let Some((cases, findings)) = campaign_counts(line) {
                in_summary = true;
                total_cases += cases;
                total_findings += findings;
            } else if !line.starts_with("  ") {
                in_summary = false;
            }
            if in_summary {
                println!("{line}");
            }
        }
        if !output.status.success() {
            failed.push(format!("{title} ({})", output.status));
        }
    }
    eprintln!(
        "xtask: fuzz: {total_cases} cases, {total_findings} finding(s) in {:.0} s",
        started.elapsed().as_secs_f64()
    );
    if !failed.is_empty() {
        bail!(
            "fuzz campaigns failed: {}; the findings above show each input (shrunk where possible)",
            failed.join(", ")
        );
    }
    Ok(())
}

/// The cases and findings of a campaign summary line, `fuzz <name>: N cases in …, K finding(s)`.
fn campaign_counts(line: &str) -> Option<(u64, u64)> {
    let (_, rest) = line.strip_prefix("fuzz ")?.split_once(": ")?;
    let cases = rest.split(' ').next()?.parse().ok()?;
    let findings = rest
        .rsplit(", ")
        .next()?
        .strip_suffix(" finding(s)")?
        .parse()
        .ok()?;
    Some((cases, findings))
}

/// The papers `cargo xtask reproduce` knows (spectex-reproduce's `Paper::ALL`).
const PAPERS: &[&str] = &["lrp", "rpn", "phasor", "survey"];

/// `cargo xtask reproduce [PAPER…] [--quick] [--no-gpu]`: builds spectex-reproduce in release
/// and runs it into `target/reproduce/`. The arguments are checked here first, so a typo costs
/// no build.
/// `cargo xtask export-check`: the export render test over every exportable model on lavapipe.
fn export_check(ws: &Workspace) -> Result<()> {
    let icd = ensure_lavapipe()?;
    let mut command = ws.cargo(&[
        "test",
        "--workspace",
        "--test",
        "it",
        "export::exported_modules",
        "--",
        "--nocapture",
    ]);
    lavapipe_env(&mut command, &icd);
    command.env("SPECTEX_EXPORT_ALL", "1");
    run_steps(
        "export-check",
        vec![Step {
            title: "the export render test over every exportable model (lavapipe)".to_owned(),
            command,
        }],
    )
}

/// The model, window and frame of `cargo xtask bevy-check`; the window is the one
/// `crates/spectex-crosscheck/tests/it/export.rs` compares the frame on (`BEVY_WINDOW`).
const BEVY_MODEL: &str = "testdata/models/lrp-ring.json";
const BEVY_WINDOW: [&str; 5] = ["128", "96", "-37.25", "81.5", "0.75"];

/// `cargo xtask bevy-check`: export a model, run the Bevy example headlessly on lavapipe (one
/// frame into a file), and compare the frame with the CPU in the cross-check test binary.
fn bevy_check(ws: &Workspace) -> Result<()> {
    let icd = ensure_lavapipe()?;
    let out = target_dir(ws).join("bevy-check");
    fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let module = out.join("model.wgsl");
    let frame = out.join("frame.f32");
    let _ = fs::remove_file(&frame);
    // The test profile, as the comparison's `cargo test` builds: one build of the workspace.
    let mut export = ws.cargo(&[
        "run",
        "--profile",
        "test",
        "-p",
        "spectex-cli",
        "--",
        "export",
        BEVY_MODEL,
        "--wgsl",
    ]);
    export.arg(&module);
    let example = ws.root.join("examples/bevy-material");
    let mut bevy = Command::new(&ws.cargo);
    bevy.current_dir(&example).args(["run", "--"]);
    bevy.arg(&module).arg(&frame).args(BEVY_WINDOW);
    bevy.env(
        "CARGO_TARGET_DIR",
        env::var_os("BEVY_TARGET_DIR").map_or_else(|| target_dir(ws).join("bevy"), PathBuf::from),
    );
    lavapipe_env(&mut bevy, &icd);
    private_runtime_dir(ws, &mut bevy)?;
    let mut compare = ws.cargo(&[
        "test",
        "-p",
        "spectex-crosscheck",
        "--test",
        "it",
        "export::bevy_frame",
        "--",
        "--nocapture",
    ]);
    compare.env("SPECTEX_BEVY_FRAME", &frame);
    run_steps(
        "bevy-check",
        vec![
            Step {
                title: format!("export {BEVY_MODEL}"),
                command: export,
            },
            Step {
                title: "build and run examples/bevy-material (one headless frame)".to_owned(),
                command: bevy,
            },
            Step {
                title: "compare the frame with the CPU render".to_owned(),
                command: compare,
            },
        ],
    )
}

/// Mesa's Vulkan loader prints "error: XDG_RUNTIME_DIR is invalid or not set" once per
/// adapter query when the variable is unset (as in CI and containers); the GPU works either
/// way. A private runtime directory under the target dir keeps the output to real errors.
fn private_runtime_dir(ws: &Workspace, command: &mut Command) -> Result<()> {
    #[cfg(unix)]
    if env::var_os("XDG_RUNTIME_DIR").is_none() {
        use std::os::unix::fs::PermissionsExt;
        let runtime = target_dir(ws).join("xtask-runtime");
        fs::create_dir_all(&runtime)
            .and_then(|()| fs::set_permissions(&runtime, fs::Permissions::from_mode(0o700)))
            .with_context(|| format!("creating {}", runtime.display()))?;
        command.env("XDG_RUNTIME_DIR", &runtime);
    }
    Ok(())
}

fn reproduce(ws: &Workspace, args: &[OsString]) -> Result<()> {
    for arg in args {
        let arg = arg.to_string_lossy();
        if arg.starts_with('-') {
            if !["--quick", "--no-gpu"].contains(&arg.as_ref()) {
                bail!(
                    "unknown option `{arg}` of `cargo xtask reproduce`; options: --quick, --no-gpu"
                );
            }
        } else if !PAPERS.contains(&arg.to_ascii_lowercase().as_str()) {
            bail!("unknown paper `{arg}`; valid papers: {}", PAPERS.join(", "));
        }
    }
    let out = target_dir(ws).join("reproduce");
    let mut command = ws.cargo(&["run", "--release", "-p", "spectex-reproduce", "--"]);
    command.arg("--out").arg(&out).args(args);
    private_runtime_dir(ws, &mut command)?;
    run_steps(
        "reproduce",
        vec![Step {
            title: format!(
                "spectex-reproduce{} into {}",
                args.iter()
                    .map(|a| format!(" {}", a.to_string_lossy()))
                    .collect::<String>(),
                out.display()
            ),
            command,
        }],
    )
}

fn bench(ws: &Workspace, mut extra: Vec<OsString>) -> Result<()> {
    // `cargo xtask bench classic`: the classic noises against FastNoiseSIMD.
    if extra.first().is_some_and(|a| a == "gpu") {
        return gpu::bench_gpu(ws, &extra[1..]);
    }
    if extra.first().is_some_and(|a| a == "classic") {
        extra.remove(0);
        if extra.first().is_some_and(|a| a == "--") {
            extra.remove(0);
        }
        return bench_classic(ws, &extra);
    }
    // `cargo xtask bench kinds`: the kinds summary alone.
    let kinds_only = extra.first().is_some_and(|a| a == "kinds");
    if kinds_only {
        extra.remove(0);
    }
    // `cargo xtask bench -- --quick` delivers the `--` too; accept it with or without.
    if extra.first().is_some_and(|a| a == "--") {
        extra.remove(0);
    }
    if kinds_only {
        return bench_kinds(ws, &extra);
    }
    let mut command = ws.cargo(&["bench", "-p", "spectex-spectrum", "--bench", "rpn"]);
    if !extra.is_empty() {
        command.arg("--").args(&extra);
    }
    let started = SystemTime::now();
    run_steps(
        "bench",
        vec![Step {
            title: "cargo bench -p spectex-spectrum --bench rpn".into(),
            command,
        }],
    )?;
    print_bench_table(&criterion_dir(ws).join("rpn"), started)?;
    bench_kinds(ws, &extra)?;
    // The paper's Table 1 for texture by example (prints its own markdown table).
    run_steps(
        "bench",
        vec![Step {
            title: "cargo bench -p spectex-reproduce --bench table1".into(),
            command: ws.cargo(&["bench", "-p", "spectex-reproduce", "--bench", "table1"]),
        }],
    )
}

/// One model kind in the summary of `cargo xtask bench`.
#[derive(Debug, Clone, PartialEq)]
struct KindSpeed {
    /// The kind (or a kind's reference path, `*_reference`).
    kind: String,
    /// Kernel, cosine or lattice evaluations per pixel (the evaluator's `cost_per_pixel`).
    evaluations_per_pixel: f64,
    /// Mpix/s on 1 thread.
    single: f64,
    /// Mpix/s on all threads.
    all: f64,
}

/// Every kind's speed (`spectex-cpu`'s `kinds` bench group), summarised in `target/bench/` as
/// a Markdown table and an SVG bar chart (`summary` with either extension).
fn bench_kinds(ws: &Workspace, extra: &[OsString]) -> Result<()> {
    let out = target_dir(ws).join("bench");
    let mut command = ws.cargo(&[
        "bench",
        "-p",
        "spectex-cpu",
        "--bench",
        "eval",
        "--",
        "kinds/",
    ]);
    command.args(extra).env("SPECTEX_BENCH_DIR", &out);
    let started = SystemTime::now();
    run_steps(
        "bench",
        vec![Step {
            title: "cargo bench -p spectex-cpu --bench eval -- kinds/".into(),
            command,
        }],
    )?;
    let costs = out.join("kinds.tsv");
    let tsv = fs::read_to_string(&costs)
        .with_context(|| format!("reading {} (the kinds bench writes it)", costs.display()))?;
    let group = criterion_dir(ws).join("kinds");
    let median_ns = |id: &str| -> Result<f64> {
        let estimates = group.join(id).join("new").join("estimates.json");
        let stale = fs::metadata(&estimates)
            .and_then(|m| m.modified())
            .map_or(true, |modified| modified < started);
        if stale {
            bail!("{} was not written by this run", estimates.display());
        }
        let json = fs::read_to_string(&estimates)
            .with_context(|| format!("reading {}", estimates.display()))?;
        parse_median_ns(&json)
            .with_context(|| format!("no median point_estimate in {}", estimates.display()))
    };
    let mut kinds = Vec::new();
    for line in tsv.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let (kind, evaluations_per_pixel, pixels) = parse_kind_line(line)
            .with_context(|| format!("{}: bad line {line:?}", costs.display()))?;
        let mpix = |ns: f64| pixels / ns * 1e3;
        kinds.push(KindSpeed {
            single: mpix(median_ns(&format!("{kind}_1_thread"))?),
            all: mpix(median_ns(&format!("{kind}_all_threads"))?),
            kind,
            evaluations_per_pixel,
        });
    }
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let markdown = summary_markdown(&kinds, threads);
    let md = out.join("summary.md");
    fs::write(&md, &markdown).with_context(|| format!("writing {}", md.display()))?;
    let svg = out.join("summary.svg");
    summary_chart(&svg, &kinds, threads).with_context(|| format!("drawing {}", svg.display()))?;
    println!("{markdown}");
    println!("written: {} and {}", md.display(), svg.display());
    Ok(())
}

/// The cases of `spectex-cpu`'s `grid` bench group and of `benches/fastnoisesimd.py`, in
/// table order, with whether spectex has a `*_reference` path for them.
const CLASSIC_CASES: &[(&str, bool)] = &[
    ("perlin", true),
    ("value", true),
    ("simplex", false),
    ("cellular", false),
    ("fbm6", true),
];

/// `cargo xtask bench classic`: the `grid` group of `spectex-cpu`'s classic bench, then
/// FastNoiseSIMD on the same grid in the same invocation (installed in a virtual environment
/// under `target/bench` when missing; skipped with a message where that fails), then the ratio
/// table, printed and written to `target/bench/classic.md`.
fn bench_classic(ws: &Workspace, extra: &[OsString]) -> Result<()> {
    let out = target_dir(ws).join("bench");
    fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let mut command = ws.cargo(&[
        "bench",
        "-p",
        "spectex-cpu",
        "--bench",
        "classic",
        "--",
        "grid/",
    ]);
    command.args(extra);
    let started = SystemTime::now();
    run_steps(
        "bench",
        vec![Step {
            title: "cargo bench -p spectex-cpu --bench classic -- grid/".into(),
            command,
        }],
    )?;
    let fastnoise = match fastnoisesimd_python(ws, &out) {
        Ok(python) => {
            let tsv = out.join("fastnoisesimd.tsv");
            let script = ws.root.join("crates/spectex-cpu/benches/fastnoisesimd.py");
            let mut command = Command::new(&python);
            command.arg(&script).arg("--out").arg(&tsv);
            run_steps(
                "bench",
                vec![Step {
                    title: "FastNoiseSIMD on the same grid (benches/fastnoisesimd.py)".into(),
                    command,
                }],
            )?;
            let text = fs::read_to_string(&tsv)
                .with_context(|| format!("reading {} (the script writes it)", tsv.display()))?;
            Some(parse_fastnoise_tsv(&text).with_context(|| format!("parsing {}", tsv.display()))?)
        }
        Err(why) => {
            println!("skipping FastNoiseSIMD: {why:#}");
            None
        }
    };
    let group = criterion_dir(ws).join("grid");
    let pixels = 2048.0 * 2048.0;
    // The best sample: the bench times by the render thread's CPU time, and on a shared
    // machine the fastest sample is the one least disturbed (caches, frequency).
    let mpix = |id: &str| -> Result<f64> {
        let sample = group.join(id).join("new").join("sample.json");
        let stale = fs::metadata(&sample)
            .and_then(|m| m.modified())
            .map_or(true, |modified| modified < started);
        if stale {
            bail!("{} was not written by this run", sample.display());
        }
        let json =
            fs::read_to_string(&sample).with_context(|| format!("reading {}", sample.display()))?;
        let ns = parse_best_ns(&json)
            .with_context(|| format!("no iters and times in {}", sample.display()))?;
        Ok(pixels / ns * 1e3)
    };
    let mut rows = Vec::new();
    for &(case, has_reference) in CLASSIC_CASES {
        let reference = |d: &str| -> Result<Option<f64>> {
            if has_reference {
                mpix(&format!("{case}_{d}_reference")).map(Some)
            } else {
                Ok(None)
            }
        };
        // Absent where the CPU has no AVX2 and FMA (the bench skips them).
        let guarantees = ["3d", "2d"].map(|d| {
            mpix(&format!("{case}_{d}_exact"))
                .and_then(|exact| Ok((exact, mpix(&format!("{case}_{d}_relaxed"))?)))
                .ok()
        });
        rows.push(ClassicRow {
            guarantees,
            case: case.to_string(),
            three_d: mpix(&format!("{case}_3d"))?,
            three_d_reference: reference("3d")?,
            two_d: mpix(&format!("{case}_2d"))?,
            two_d_reference: reference("2d")?,
            fastnoise: fastnoise
                .as_ref()
                .and_then(|f| f.iter().find(|(c, _, _)| c == case))
                .map(|(_, m, level)| (*m, level.clone())),
        });
    }
    let markdown = classic_markdown(&rows);
    let md = out.join("classic.md");
    fs::write(&md, &markdown).with_context(|| format!("writing {}", md.display()))?;
    println!("{markdown}");
    println!("written: {}", md.display());
    Ok(())
}

/// A Python with `pyfastnoisesimd`: the virtual environment `out/fastnoisesimd-venv`, created
/// and filled on first use (the package's C++ builds against numpy's headers, without build
/// isolation).
fn fastnoisesimd_python(ws: &Workspace, out: &Path) -> Result<PathBuf> {
    let venv = out.join("fastnoisesimd-venv");
    let python = venv.join("bin").join("python3");
    let has_package = |python: &Path| {
        Command::new(python)
            .args([
                "-c",
                "import numpy; numpy.product = numpy.prod; import pyfastnoisesimd",
            ])
            .current_dir(&ws.root)
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if python.exists() && has_package(&python) {
        return Ok(python);
    }
    let quiet = |mut c: Command, what: &str| -> Result<()> {
        eprintln!("xtask: {what}");
        let output = c
            .output()
            .with_context(|| format!("{what}: could not start"))?;
        if !output.status.success() {
            let stderr = String::from_utf8_lossy(&output.stderr);
            let tail: Vec<&str> = stderr.lines().rev().take(5).collect();
            bail!(
                "{what} failed: {}",
                tail.into_iter().rev().collect::<Vec<_>>().join(" / ")
            );
        }
        Ok(())
    };
    let mut create = Command::new("python3");
    create.args(["-m", "venv"]).arg(&venv);
    quiet(create, "python3 -m venv target/bench/fastnoisesimd-venv")?;
    let mut base = Command::new(&python);
    base.args(["-m", "pip", "install", "-q", "wheel", "setuptools", "numpy"]);
    quiet(base, "pip install wheel setuptools numpy")?;
    let include = Command::new(&python)
        .args(["-c", "import numpy; print(numpy.get_include())"])
        .output()
        .context("asking numpy for its include directory")?;
    let include = String::from_utf8_lossy(&include.stdout).trim().to_string();
    let mut package = Command::new(&python);
    package
        .args([
            "-m",
            "pip",
            "install",
            "-q",
            "--no-build-isolation",
            "pyfastnoisesimd",
        ])
        .env("CFLAGS", format!("-I{include}"));
    quiet(
        package,
        "pip install pyfastnoisesimd (builds FastNoiseSIMD's C++, a minute or two)",
    )?;
    if !has_package(&python) {
        bail!("pyfastnoisesimd installed but does not import");
    }
    Ok(python)
}

/// `case<TAB>Mpix/s<TAB>SIMD level` lines of `fastnoisesimd.py`, after its header.
fn parse_fastnoise_tsv(text: &str) -> Result<Vec<(String, f64, String)>> {
    let mut rows = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let fields: Vec<&str> = line.split('\t').map(str::trim).collect();
        let [case, mpix, level] = fields[..] else {
            bail!("bad line {line:?}");
        };
        let mpix: f64 = mpix
            .parse()
            .with_context(|| format!("bad Mpix/s in {line:?}"))?;
        rows.push((case.to_string(), mpix, level.to_string()));
    }
    Ok(rows)
}

/// One case of `cargo xtask bench classic`, Mpix/s on one thread.
#[derive(Debug, Clone, PartialEq)]
struct ClassicRow {
    case: String,
    three_d: f64,
    three_d_reference: Option<f64>,
    two_d: f64,
    two_d_reference: Option<f64>,
    /// FastNoiseSIMD's (3D slice) and its SIMD level, when it ran.
    fastnoise: Option<(f64, String)>,
    /// The cost of the guarantees, 3D and 2D: spectex's evaluator exact and with the
    /// bench-only f32 cell split and FMA (`*_exact`, `*_relaxed`), where the CPU ran them.
    guarantees: [Option<(f64, f64)>; 2],
}

/// The classic table: spectex 3D and 2D (and their reference paths), FastNoiseSIMD, and the
/// ratios spectex / FastNoiseSIMD (above 1: spectex is faster).
fn classic_markdown(rows: &[ClassicRow]) -> String {
    let level = rows
        .iter()
        .find_map(|r| r.fastnoise.as_ref().map(|(_, l)| l.clone()))
        .unwrap_or_else(|| "not run".to_string());
    let mut md = format!(
        "Classic noises, one thread, 2048² window, cell 32 px (3D: the slice z = 7 px), \
         Mpix/s by the render thread's CPU time, the best of criterion's samples (FastNoiseSIMD: \
         the best of 15 grids, SIMD level {level}).\n\n\
         | noise | spectex 3D | 3D reference path | FastNoiseSIMD 3D | spectex 3D / FNS | \
         spectex 2D | 2D reference path | spectex 2D / FNS |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
    );
    let number = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.1}"));
    let ratio = |ours: f64, theirs: Option<f64>| {
        theirs.map_or("–".to_string(), |t| format!("{:.2}", ours / t))
    };
    for r in rows {
        let theirs = r.fastnoise.as_ref().map(|(m, _)| *m);
        md.push_str(&format!(
            "| {} | {:.1} | {} | {} | {} | {:.1} | {} | {} |\n",
            r.case,
            r.three_d,
            number(r.three_d_reference),
            number(theirs),
            ratio(r.three_d, theirs),
            r.two_d,
            number(r.two_d_reference),
            ratio(r.two_d, theirs),
        ));
    }
    md.push_str(
        "\nWhat the guarantees (f64 cell split, no FMA) cost: the same evaluator exact and with \
         the bench-only f32 split and FMA, Mpix/s, same run.\n\n\
         | noise | 3D exact | 3D relaxed | 3D relaxed / exact | 2D exact | 2D relaxed | \
         2D relaxed / exact |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for r in rows {
        let cells = r.guarantees.map(|g| match g {
            Some((exact, relaxed)) => format!("{exact:.1} | {relaxed:.1} | {:.2}", relaxed / exact),
            None => "– | – | –".to_string(),
        });
        md.push_str(&format!("| {} | {} | {} |\n", r.case, cells[0], cells[1]));
    }
    md
}

/// `kind<TAB>evaluations per pixel<TAB>pixels` of the kinds bench's `kinds.tsv`.
fn parse_kind_line(line: &str) -> Option<(String, f64, f64)> {
    let mut fields = line.split('\t');
    let kind = fields.next()?.trim().to_string();
    let evaluations: f64 = fields.next()?.trim().parse().ok()?;
    let pixels: f64 = fields.next()?.trim().parse().ok()?;
    (!kind.is_empty() && fields.next().is_none()).then_some((kind, evaluations, pixels))
}

/// The summary table, then each fast path's ratio to the reference path measured beside it.
fn summary_markdown(kinds: &[KindSpeed], threads: usize) -> String {
    let mut md = format!(
        "| kind | evaluations per pixel | 1 thread (Mpix/s) | {threads} threads (Mpix/s) |\n\
         | --- | ---: | ---: | ---: |\n"
    );
    for k in kinds {
        md.push_str(&format!(
            "| {} | {:.1} | {:.2} | {:.2} |\n",
            k.kind, k.evaluations_per_pixel, k.single, k.all
        ));
    }
    for k in kinds {
        let Some(base) = k.kind.strip_suffix("_reference") else {
            continue;
        };
        if let Some(fast) = kinds.iter().find(|f| f.kind == base) {
            md.push_str(&format!(
                "\n{base}: {:.2}× the reference path on 1 thread, {:.2}× on {threads} threads.",
                fast.single / k.single,
                fast.all / k.all
            ));
        }
    }
    md.push('\n');
    md
}

/// A horizontal bar chart of the summary (log scale: the kinds span three decades).
fn summary_chart(path: &Path, kinds: &[KindSpeed], threads: usize) -> Result<()> {
    use plotters::prelude::*;
    use plotters::style::text_anchor::{HPos, Pos, VPos};

    let n = kinds.len();
    let height = 110 + 44 * u32::try_from(n).context("too many kinds")?;
    let root = SVGBackend::new(path, (900, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let speeds = kinds.iter().flat_map(|k| [k.single, k.all]);
    let max = speeds.clone().fold(1.0f64, f64::max) * 3.0;
    let min = speeds.fold(f64::INFINITY, f64::min).min(1.0) / 2.0;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "spectex CPU evaluation, 256² (Mpix/s, log scale)",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(150)
        .build_cartesian_2d((min..max).log_scale(), 0f64..n as f64)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_label_formatter(&|_| String::new())
        .x_desc("Mpix/s")
        .draw()?;
    let single_colour = RGBColor(230, 126, 34);
    let all_colour = RGBColor(41, 128, 185);
    let value_style =
        TextStyle::from(("sans-serif", 12).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (bar, colour, label) in [
        (0, single_colour, "1 thread".to_string()),
        (1, all_colour, format!("{threads} threads")),
    ] {
        let bars = kinds.iter().enumerate().map(|(i, k)| {
            let top = (n - 1 - i) as f64;
            let speed = if bar == 0 { k.single } else { k.all };
            let (y0, y1) = if bar == 0 {
                (top + 0.52, top + 0.9)
            } else {
                (top + 0.1, top + 0.48)
            };
            Rectangle::new([(min, y0), (speed, y1)], colour.filled())
        });
        chart
            .draw_series(bars)?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
        chart.draw_series(kinds.iter().enumerate().map(|(i, k)| {
            let top = (n - 1 - i) as f64;
            let (speed, y) = if bar == 0 {
                (k.single, top + 0.71)
            } else {
                (k.all, top + 0.29)
            };
            Text::new(format!(" {speed:.1}"), (speed, y), value_style.clone())
        }))?;
    }
    let name_style =
        TextStyle::from(("sans-serif", 14).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
    for (i, k) in kinds.iter().enumerate() {
        let (x, y) = chart.backend_coord(&(min, (n - 1 - i) as f64 + 0.5));
        let name = format!("{} ({:.0}/px)", k.kind, k.evaluations_per_pixel);
        root.draw(&Text::new(name, (x - 8, y), name_style.clone()))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// Where criterion writes its results, following its own order of preference.
fn criterion_dir(ws: &Workspace) -> PathBuf {
    if let Some(home) = env::var_os("CRITERION_HOME") {
        return PathBuf::from(home);
    }
    target_dir(ws).join("criterion")
}

/// Prints the median of every benchmark in `group_dir`, then the FFT-equivalents whose ids exist.
/// Results older than `started` (benchmarks this run filtered out) are marked as such.
fn print_bench_table(group_dir: &Path, started: SystemTime) -> Result<()> {
    let entries = fs::read_dir(group_dir)
        .with_context(|| format!("no criterion results in {}", group_dir.display()))?;
    let mut medians: Vec<(String, f64, bool)> = Vec::new();
    for entry in entries {
        let entry = entry.with_context(|| format!("reading {}", group_dir.display()))?;
        let estimates = entry.path().join("new").join("estimates.json");
        if !estimates.is_file() {
            continue; // criterion's own report folders
        }
        let json = fs::read_to_string(&estimates)
            .with_context(|| format!("reading {}", estimates.display()))?;
        let median_ns = parse_median_ns(&json)
            .with_context(|| format!("no median point_estimate in {}", estimates.display()))?;
        let stale = fs::metadata(&estimates)
            .and_then(|m| m.modified())
            .is_ok_and(|modified| modified < started);
        medians.push((
            entry.file_name().to_string_lossy().into_owned(),
            median_ns,
            stale,
        ));
    }
    if medians.is_empty() {
        bail!("no criterion results in {}", group_dir.display());
    }
    medians.sort_by(|a, b| a.0.cmp(&b.0));

    let width = medians.iter().map(|m| m.0.len()).max().unwrap_or(0);
    println!("{:<width$}  {:>12}", "benchmark", "median (ms)");
    for (name, median_ns, stale) in &medians {
        let note = if *stale { "  (earlier run)" } else { "" };
        println!("{name:<width$}  {:>12.3}{note}", median_ns / 1e6);
    }
    let median_of = |id: &str| medians.iter().find(|m| m.0 == id).map(|m| m.1);
    for (rpn, fft) in FFT_EQUIVALENTS {
        if let (Some(rpn_ns), Some(fft_ns)) = (median_of(rpn), median_of(fft)) {
            println!("{rpn} / {fft} = {:.2} FFT-equivalents", rpn_ns / fft_ns);
        }
    }
    Ok(())
}

/// The `"median": { "point_estimate": <ns>, ... }` of a criterion `estimates.json`, found by string
/// search so that xtask needs no JSON library.
fn parse_median_ns(json: &str) -> Option<f64> {
    let median = &json[json.find("\"median\"")?..];
    let key = "\"point_estimate\"";
    let value = median[median.find(key)? + key.len()..]
        .trim_start()
        .strip_prefix(':')?
        .trim_start();
    let end = value
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E')))
        .unwrap_or(value.len());
    value[..end].parse().ok()
}

/// The number array after `"key":` in `json` (criterion's `sample.json`), by string search.
fn json_numbers(json: &str, key: &str) -> Option<Vec<f64>> {
    let quoted = format!("\"{key}\"");
    let rest = json[json.find(&quoted)? + quoted.len()..]
        .trim_start()
        .strip_prefix(':')?
        .trim_start()
        .strip_prefix('[')?;
    let list = &rest[..rest.find(']')?];
    list.split(',')
        .filter(|v| !v.trim().is_empty())
        .map(|v| v.trim().parse().ok())
        .collect()
}

/// The fastest time per iteration (ns) over the samples of a criterion `sample.json`
/// (`"iters"` and `"times"`, one entry per sample), or `None` when the arrays are missing,
/// empty or of different lengths.
fn parse_best_ns(json: &str) -> Option<f64> {
    let iters = json_numbers(json, "iters")?;
    let times = json_numbers(json, "times")?;
    if iters.len() != times.len() {
        return None;
    }
    iters
        .iter()
        .zip(&times)
        .filter(|(i, _)| **i > 0.0)
        .map(|(i, t)| t / i)
        .min_by(f64::total_cmp)
}

/// The numbered examples of `crates/spectex-cli/examples/` (file stems, sorted).
fn example_names(ws: &Workspace) -> Result<Vec<String>> {
    let dir = ws.root.join("crates/spectex-cli/examples");
    let mut names: Vec<String> = fs::read_dir(&dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|ext| ext == "rs"))
        .filter_map(|path| path.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    names.sort();
    Ok(names)
}

#[cfg(test)]
mod tests {
    use super::{
        ClassicRow, KindSpeed, campaign_counts, classic_markdown, json_string_field, parse_best_ns,
        parse_fastnoise_tsv, parse_kind_line, parse_median_ns, summary_markdown,
    };

    #[test]
    fn fastnoise_lines_and_the_classic_table() {
        let rows = parse_fastnoise_tsv("case\tmpix_per_s\tsimd_level\nperlin\t300.5\tAVX2\n\n")
            .expect("parses");
        assert_eq!(
            rows,
            vec![("perlin".to_string(), 300.5, "AVX2".to_string())]
        );
        assert!(parse_fastnoise_tsv("h\nperlin\tfast\tAVX2").is_err());
        assert!(parse_fastnoise_tsv("h\nperlin\t1").is_err());
        let md = classic_markdown(&[
            ClassicRow {
                case: "perlin".into(),
                three_d: 150.0,
                three_d_reference: Some(100.0),
                two_d: 450.0,
                two_d_reference: None,
                fastnoise: Some((300.0, "AVX2".into())),
                guarantees: [Some((150.0, 300.0)), None],
            },
            ClassicRow {
                case: "simplex".into(),
                three_d: 50.0,
                three_d_reference: None,
                two_d: 60.0,
                two_d_reference: None,
                fastnoise: None,
                guarantees: [None, None],
            },
        ]);
        assert!(md.contains("SIMD level AVX2"), "{md}");
        assert!(
            md.contains("| perlin | 150.0 | 100.0 | 300.0 | 0.50 | 450.0 | – | 1.50 |"),
            "{md}"
        );
        assert!(
            md.contains("| simplex | 50.0 | – | – | – | 60.0 | – | – |"),
            "{md}"
        );
        // Relaxed at twice the exact speed: the ratio 2.00; the 2D side was not run.
        assert!(
            md.contains("| perlin | 150.0 | 300.0 | 2.00 | – | – | – |"),
            "{md}"
        );
    }

    #[test]
    fn kind_lines_and_the_summary_table() {
        assert_eq!(
            parse_kind_line("phasor\t91.5\t65536"),
            Some(("phasor".to_string(), 91.5, 65536.0))
        );
        assert_eq!(parse_kind_line("phasor\t91.5"), None);
        assert_eq!(parse_kind_line("phasor\tx\t1"), None);
        let kind = |kind: &str, single, all| KindSpeed {
            kind: kind.into(),
            evaluations_per_pixel: 92.0,
            single,
            all,
        };
        let md = summary_markdown(
            &[
                kind("phasor", 10.0, 18.0),
                kind("phasor_reference", 2.0, 3.0),
            ],
            2,
        );
        assert!(md.contains("| phasor | 92.0 | 10.00 | 18.00 |"), "{md}");
        assert!(md.contains("2 threads (Mpix/s)"), "{md}");
        assert!(
            md.contains("phasor: 5.00× the reference path on 1 thread, 6.00× on 2 threads."),
            "{md}"
        );
    }

    #[test]
    fn string_fields_are_read_from_cargo_messages() {
        let line = r#"{"reason":"compiler-artifact","manifest_path":"/w/a \"b\"\\c/Cargo.toml","target":{"name":"it","src_path":"/w/tests/it/main.rs"},"executable":null,"fresh":true,"x":"\u00e9\n"}"#;
        assert_eq!(
            json_string_field(line, "manifest_path").as_deref(),
            Some(r#"/w/a "b"\c/Cargo.toml"#)
        );
        assert_eq!(json_string_field(line, "name").as_deref(), Some("it"));
        assert_eq!(json_string_field(line, "executable"), None);
        assert_eq!(json_string_field(line, "missing"), None);
        assert_eq!(json_string_field(line, "x").as_deref(), Some("é\n"));
        assert_eq!(json_string_field(r#"{"a":"unterminated"#, "a"), None);
    }

    #[test]
    fn campaign_summaries_give_cases_and_findings() {
        assert_eq!(
            campaign_counts(
                "fuzz models-cpu: 600 cases in 4.7 s, 262 accepted, 338 rejected, 2 finding(s)"
            ),
            Some((600, 2))
        );
        assert_eq!(campaign_counts("fuzz: nothing"), None);
        assert_eq!(campaign_counts("  slowest render: 1 µs"), None);
    }

    #[test]
    fn median_is_read_from_criterion_estimates() {
        let json = r#"{"mean":{"confidence_interval":{"confidence_level":0.95,"lower_bound":1.0,"upper_bound":2.0},"point_estimate":1.5,"standard_error":0.1},"median":{"confidence_interval":{"confidence_level":0.95,"lower_bound":3.0,"upper_bound":4.0},"point_estimate":3456789.25,"standard_error":0.2},"median_abs_dev":{"point_estimate":7.0}}"#;
        assert_eq!(parse_median_ns(json), Some(3_456_789.25));
        assert_eq!(
            parse_median_ns(r#"{"median": {"point_estimate" : 1.5e6}}"#),
            Some(1.5e6)
        );
        assert_eq!(parse_median_ns(r#"{"mean":{"point_estimate":1.0}}"#), None);
    }

    #[test]
    fn best_sample_is_read_from_criterion_samples() {
        // Per iteration: 100, 75, 90 ns; the best is 75.
        let json =
            r#"{"sampling_mode":"Linear","iters":[1.0,2.0,3.0],"times":[100.0,150.0,270.0]}"#;
        assert_eq!(parse_best_ns(json), Some(75.0));
        assert_eq!(
            parse_best_ns(r#"{"iters": [ 4.0 ], "times" : [ 1e3 ]}"#),
            Some(250.0)
        );
        assert_eq!(parse_best_ns(r#"{"iters":[1.0,2.0],"times":[1.0]}"#), None);
        assert_eq!(parse_best_ns(r#"{"iters":[],"times":[]}"#), None);
        assert_eq!(parse_best_ns(r#"{"times":[1.0]}"#), None);
    }
}
