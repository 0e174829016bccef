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

/// Every command with the one line `cargo xtask help` prints for it.
const COMMANDS: &[(&str, &str)] = &[
    (
        "ci",
        "what CI runs: cargo fmt --check, clippy -D warnings, all tests, doc tests",
    ),
    (
        "verify",
        "GPU verification on lavapipe: GPU tests and the CPU-vs-GPU cross-check of \
         testdata/models, one line per model",
    ),
    (
        "bench",
        "criterion benches of RPN vs one FFT, then a table of medians; \
         extra args go to criterion (`cargo xtask bench -- --quick`); then the \
         texture-by-example Table 1 (CPU and GPU)",
    ),
    (
        "fuzz",
        "long fuzz campaigns (optimised, overflow checks on): generated and mutated models \
         through the CPU (and the GPU on lavapipe when installed), images through the CLI; \
         `--cases N` per campaign (default 20000), `--seed S`; prints cases and findings",
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
        Some("bench") => bench(&Workspace::locate()?, rest),
        Some("fuzz") => fuzz(&Workspace::locate()?, &rest),
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
        println!("  {name:<7} {about}");
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
    title: &'static str,
    command: Command,
}

/// Runs `steps` in order, stopping at the first failure; prints a header per step and a summary.
fn run_steps(name: &str, steps: Vec<Step>) -> Result<()> {
    let started = Instant::now();
    let count = steps.len();
    for (i, mut step) in steps.into_iter().enumerate() {
        eprintln!("xtask: [{}/{count}] {}", i + 1, step.title);
        run_command(&mut step.command).with_context(|| {
            format!(
                "`cargo xtask {name}` failed at step {}/{count} ({})",
                i + 1,
                step.title
            )
        })?;
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

/// Fails, saying how to install them, unless `cargo fmt` and `cargo clippy` both run.
fn require_rustfmt_and_clippy(ws: &Workspace) -> Result<()> {
    let missing: Vec<&str> = [("rustfmt", "fmt"), ("clippy", "clippy")]
        .into_iter()
        .filter(|(_, subcommand)| {
            !ws.cargo(&[subcommand, "--version"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|status| status.success())
        })
        .map(|(tool, _)| tool)
        .collect();
    if !missing.is_empty() {
        bail!(
            "{} not installed; install with: rustup component add rustfmt clippy",
            missing.join(" and ")
        );
    }
    Ok(())
}

fn ci(ws: &Workspace) -> Result<()> {
    require_rustfmt_and_clippy(ws)?;
    let step = |title, args: &[&str]| Step {
        title,
        command: ws.cargo(args),
    };
    run_steps(
        "ci",
        vec![
            step("cargo fmt --check", &["fmt", "--all", "--", "--check"]),
            step(
                "cargo clippy -D warnings",
                &[
                    "clippy",
                    "--workspace",
                    "--all-targets",
                    "--",
                    "-D",
                    "warnings",
                ],
            ),
            step(
                "cargo test --all-targets",
                &["test", "--workspace", "--all-targets"],
            ),
            step("cargo test --doc", &["test", "--workspace", "--doc"]),
        ],
    )?;
    verify(ws)
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

/// `cargo xtask verify`: the GPU tests and the cross-check suite on lavapipe, with a missing
/// adapter an error (`SPECTEX_REQUIRE_GPU=1`); prints the suite's line per model.
fn verify(ws: &Workspace) -> Result<()> {
    let icd = lavapipe_icd()?;
    eprintln!("xtask: verify on lavapipe, ICD {}", icd.display());
    let gpu_env = |command: &mut Command| {
        command
            .env("VK_DRIVER_FILES", &icd)
            .env("VK_ICD_FILENAMES", &icd)
            .env("WGPU_ADAPTER_NAME", "llvmpipe")
            .env("SPECTEX_REQUIRE_GPU", "1");
    };
    let mut gpu_tests = ws.cargo(&["test", "-p", "spectex-gpu", "--tests"]);
    gpu_env(&mut gpu_tests);
    run_steps(
        "verify",
        vec![Step {
            title: "cargo test -p spectex-gpu (lavapipe, SPECTEX_REQUIRE_GPU=1)",
            command: gpu_tests,
        }],
    )?;
    let mut suite = ws.cargo(&[
        "test",
        "-p",
        "spectex-crosscheck",
        "--tests",
        "--",
        "--nocapture",
    ]);
    gpu_env(&mut suite);
    eprintln!("xtask: cross-check suite: {}", show(&suite));
    let output = suite
        .stderr(Stdio::inherit())
        .output()
        .with_context(|| format!("could not start `{}`", show(&suite)))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let lines: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("crosscheck:"))
        .collect();
    if !output.status.success() {
        print!("{stdout}");
        bail!(
            "the cross-check suite failed ({}); images and reports are in target/crosscheck/",
            output.status
        );
    }
    if lines.is_empty() {
        print!("{stdout}");
        bail!("the cross-check suite printed no model line: did it skip?");
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

fn bench(ws: &Workspace, mut extra: Vec<OsString>) -> Result<()> {
    // `cargo xtask bench -- --quick` delivers the `--` too; accept it with or without.
    if extra.first().is_some_and(|a| a == "--") {
        extra.remove(0);
    }
    let mut command = ws.cargo(&["bench", "-p", "spectex-spectrum", "--bench", "rpn"]);
    if !extra.is_empty() {
        command.arg("--").args(&extra);
    }
    let started = SystemTime::now();
    run_steps(
        "bench",
        vec![Step {
            title: "cargo bench -p spectex-spectrum --bench rpn",
            command,
        }],
    )?;
    print_bench_table(&criterion_dir(ws).join("rpn"), started)?;
    // The paper's Table 1 for texture by example (prints its own markdown table).
    run_steps(
        "bench",
        vec![Step {
            title: "cargo bench -p spectex-cli --bench table1",
            command: ws.cargo(&["bench", "-p", "spectex-cli", "--bench", "table1"]),
        }],
    )
}

/// Where criterion writes its results, following its own order of preference.
fn criterion_dir(ws: &Workspace) -> PathBuf {
    if let Some(home) = env::var_os("CRITERION_HOME") {
        return PathBuf::from(home);
    }
    match env::var_os("CARGO_TARGET_DIR") {
        Some(target) => ws.root.join(target).join("criterion"),
        None => ws.root.join("target").join("criterion"),
    }
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

#[cfg(test)]
mod tests {
    use super::{campaign_counts, parse_median_ns};

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
}
