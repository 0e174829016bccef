//! `cargo xtask ci` and `verify`: rustfmt and clippy, the test runner and the test binaries.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result, bail};

use crate::json::compiler_artifacts;
use crate::system::ensure_lavapipe;
use crate::{Step, Workspace, run_command, run_steps, runs, show, target_dir};

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

/// `cargo xtask fmt`: `cargo fmt --all` and the source files it does not reach ([`fmt_args`]).
pub(crate) fn fmt(ws: &Workspace) -> Result<()> {
    ensure_rustfmt_and_clippy(ws)?;
    let args = fmt_args(ws, false)?;
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    run_command(&mut ws.cargo(&args))
}

/// `cargo fmt --all [-- --check]` plus every `.rs` file under `crates/*/src/`: rustfmt finds a
/// crate's modules by following its `mod` items, and the kinds' modules are declared by a macro
/// (`spectex_model::for_each_kind!(mod)`), which it does not expand.
fn fmt_args(ws: &Workspace, check: bool) -> Result<Vec<String>> {
    let mut args: Vec<String> = ["fmt", "--all", "--"].map(str::to_owned).to_vec();
    if check {
        args.push("--check".to_owned());
    }
    let mut files = Vec::new();
    for krate in fs::read_dir(ws.root.join("crates")).context("reading crates/")? {
        rust_files(&krate?.path().join("src"), &mut files)?;
    }
    files.sort();
    for file in files {
        let relative = file.strip_prefix(&ws.root).unwrap_or(&file);
        args.push(relative.to_string_lossy().into_owned());
    }
    Ok(args)
}

/// Every `.rs` file under `dir`, recursively (none if `dir` does not exist).
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    if !dir.is_dir() {
        return Ok(());
    }
    for entry in fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))? {
        let path = entry?.path();
        if path.is_dir() {
            rust_files(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    Ok(())
}

/// `cargo xtask ci`. The tests run once, on lavapipe with `SPECTEX_REQUIRE_GPU=1`, so the GPU
/// tests and the cross-check suite of `cargo xtask verify` run (and are built) in the test step,
/// and verify's report comes from that run. Every cargo command gets the same environment and
/// the test commands the same package selection (`--workspace`): a different selection unifies
/// dependency features differently and rebuilds the test binaries.
pub(crate) fn ci(ws: &Workspace) -> Result<()> {
    ensure_rustfmt_and_clippy(ws)?;
    let lavapipe = ensure_lavapipe(ws)?;
    let runner = TestRunner::from_env(ws)?;
    let summary = CrosscheckSummary::prepare(ws)?;
    eprintln!(
        "xtask: ci with {}, GPU tests on lavapipe (ICD {})",
        match runner {
            TestRunner::Nextest => "cargo nextest",
            TestRunner::Cargo => "cargo test",
        },
        lavapipe.icd.display()
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
    let ci_env = |command: &mut Command| {
        lavapipe.apply(command);
        summary.apply(command);
        command
            .env("RUSTC_WORKSPACE_WRAPPER", &driver)
            .env("RUSTFLAGS", &rustflags);
    };
    let step = |title: &str, args: &[&str]| {
        let mut command = ws.cargo(args);
        ci_env(&mut command);
        Step {
            title: title.to_owned(),
            command,
        }
    };
    let fmt_args = fmt_args(ws, true)?;
    let fmt_args: Vec<&str> = fmt_args.iter().map(String::as_str).collect();
    let mut steps = vec![step("cargo fmt --check (and every source file)", &fmt_args)];
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
        // `cargo xtask test`: the same build (`cargo test --tests --bench '*' --no-run`), then
        // the binaries two at a time on the 2-core machine (see `runner`).
        TestRunner::Cargo => {
            let mut command = Command::new(
                env::current_exe().context("finding the xtask executable to run `xtask test`")?,
            );
            command.arg("test").current_dir(&ws.root);
            ci_env(&mut command);
            steps.push(Step {
                title: "cargo xtask test: cargo test --tests --bench '*', the binaries in \
                        parallel (clippy -D warnings; GPU tests and cross-check on lavapipe)"
                    .to_owned(),
                command,
            });
        }
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
        ci_env(&mut command);
        steps.push(Step {
            title: format!("example {name} (as `cargo run --example {name}` runs it)"),
            command,
        });
    }
    steps.extend(crate::python::ci_steps(ws, &ci_env)?);
    run_steps("ci", steps)?;
    crate::browser::view_check(ws)?;
    summary.report()
}

/// The crates whose tests `cargo xtask verify` runs.
const VERIFIED_PACKAGES: &[&str] = &["spectex-gpu", "spectex-crosscheck"];

/// `cargo xtask verify`: the GPU tests and the cross-check suite on lavapipe, with a missing
/// adapter an error (`SPECTEX_REQUIRE_GPU=1`); prints the suite's line per model. The tests are
/// those `cargo xtask ci` builds (`--workspace`), picked by package after the build: selecting
/// the two crates with `-p` would resolve dependency features for them alone and build nearly
/// everything a second time.
pub(crate) fn verify(ws: &Workspace) -> Result<()> {
    let lavapipe = ensure_lavapipe(ws)?;
    eprintln!("xtask: verify on lavapipe, ICD {}", lavapipe.icd.display());
    let summary = CrosscheckSummary::prepare(ws)?;
    let gpu_env = |command: &mut Command| {
        lavapipe.apply(command);
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
        TestRunner::Cargo => test_executables(ws, &gpu_env, &["--tests"], Some(VERIFIED_PACKAGES))?
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
pub(crate) struct TestExecutable {
    pub(crate) executable: PathBuf,
    pub(crate) package_dir: PathBuf,
    /// The target's source file relative to the workspace root, to name it.
    pub(crate) source: String,
}

/// The test binaries of `packages` (every package: `None`) among those of
/// `cargo test --workspace TARGETS`, building them first when they are not up to date (with
/// `env`, the environment of the runs).
pub(crate) fn test_executables(
    ws: &Workspace,
    env: &dyn Fn(&mut Command),
    targets: &[&str],
    packages: Option<&[&str]>,
) -> Result<Vec<TestExecutable>> {
    let mut build = ws.cargo(&["test", "--workspace"]);
    build
        .args(targets)
        .args(["--no-run", "--message-format=json-render-diagnostics"]);
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
    for artifact in compiler_artifacts(&String::from_utf8_lossy(&output.stdout)) {
        let Some(executable) = artifact.executable.filter(|_| artifact.profile.test) else {
            continue; // a library, or a program (the `spectex` binary the CLI tests run)
        };
        let Some(package_dir) = artifact.manifest_path.parent() else {
            continue;
        };
        if packages.is_none_or(|packages| {
            packages
                .iter()
                .any(|p| package_dir.ends_with(Path::new("crates").join(p)))
        }) {
            let source = &artifact.target.src_path;
            found.push(TestExecutable {
                executable,
                package_dir: package_dir.to_path_buf(),
                source: source
                    .strip_prefix(&ws.root)
                    .unwrap_or(source)
                    .display()
                    .to_string(),
            });
        }
    }
    if found.is_empty() {
        bail!(
            "`{}` built no test of {}",
            show(&build),
            packages.map_or_else(|| "the workspace".to_owned(), |p| p.join(" or "))
        );
    }
    found.sort_by(|a, b| a.source.cmp(&b.source));
    Ok(found)
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
