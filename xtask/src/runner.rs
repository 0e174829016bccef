//! `cargo xtask test`: every test binary of the workspace (the integration tests, the unit tests
//! they carry, and each bench once as a test) built by one `cargo test --no-run` and run several
//! at a time.
//!
//! `cargo test` runs its binaries one after another, each with a thread per core; a binary
//! whose tests end unevenly (one long fidelity test, a bench pass on one thread) leaves cores
//! idle until it ends. On the 2-core CI machine the binaries took 274 s one by one for 482 s of
//! CPU time; run two at a time they fill both cores. Each binary's output is printed whole when it
//! ends, so the log reads as `cargo test`'s does, a block per binary.

use std::ffi::OsString;
use std::fs;
use std::num::NonZero;
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::thread;
use std::time::Instant;

use anyhow::{Context, Result, bail};

use crate::ci::{TestExecutable, test_executables};
use crate::{Workspace, target_dir};

/// `cargo xtask test [-- ARGS]`: builds the test binaries, then runs them as many at a time as
/// the machine has cores (`XTASK_TEST_JOBS` to choose), the largest first (the size of a test
/// binary is a fair guess of how long it runs); `ARGS` go to every binary (a filter, `--ignored`).
/// The environment is the binaries' too (CI's lavapipe variables).
pub(crate) fn test(ws: &Workspace, rest: &[OsString]) -> Result<()> {
    let args: &[OsString] = match rest.split_first() {
        None => &[],
        Some((dashes, args)) if dashes == "--" => args,
        Some((first, _)) => bail!(
            "`cargo xtask test` takes its test binaries' arguments after `--` (got {first:?})"
        ),
    };
    let jobs = match std::env::var("XTASK_TEST_JOBS") {
        Ok(text) => text
            .parse::<NonZero<usize>>()
            .map_err(|_| {
                anyhow::anyhow!("XTASK_TEST_JOBS must be a whole number from 1, not `{text}`")
            })?
            .get(),
        Err(_) => thread::available_parallelism().map_or(1, NonZero::get),
    };
    let mut tests = test_executables(ws, &|_| {}, &["--tests", "--bench", "*"], None)?;
    tests.sort_by_cached_key(|test| {
        std::cmp::Reverse(fs::metadata(&test.executable).map_or(0, |m| m.len()))
    });
    let logs = target_dir(ws).join("xtask-test");
    fs::create_dir_all(&logs).with_context(|| format!("creating {}", logs.display()))?;
    let count = tests.len();
    eprintln!("xtask: running {count} test binaries, {jobs} at a time, the largest first");
    let started = Instant::now();
    let failures = run_all(tests, args, jobs, &logs);
    let seconds = started.elapsed().as_secs_f64();
    if !failures.is_empty() {
        bail!(
            "{} of {count} test binaries failed ({seconds:.1} s): {}",
            failures.len(),
            failures.join(", ")
        );
    }
    eprintln!("xtask: {count} test binaries passed in {seconds:.1} s");
    Ok(())
}

/// Runs `tests` in order, `jobs` at a time, each one's output into `logs/{index}.log`; returns
/// the sources of those that failed (or could not start), in the order they ended.
fn run_all(
    tests: Vec<TestExecutable>,
    args: &[OsString],
    jobs: usize,
    logs: &std::path::Path,
) -> Vec<String> {
    let count = tests.len();
    let queue = Mutex::new(tests.into_iter().enumerate());
    let failures = Mutex::new(Vec::new());
    thread::scope(|scope| {
        for _ in 0..jobs.clamp(1, count.max(1)) {
            scope.spawn(|| {
                loop {
                    // The guard is dropped at the end of this statement, before the run.
                    let next = queue.lock().map(|mut queue| queue.next());
                    let Ok(Some((index, test))) = next else { break };
                    let log = logs.join(format!("{index}.log"));
                    if let Err(err) = run_one(&test, args, &log) {
                        eprintln!("xtask: {}: {err:#}", test.source);
                        if let Ok(mut failures) = failures.lock() {
                            failures.push(test.source.clone());
                        }
                    }
                }
            });
        }
    });
    failures.into_inner().unwrap_or_default()
}

/// Runs one test binary as `cargo test` would (in its package's directory, with
/// `CARGO_MANIFEST_DIR`), its output into `log`, then prints the log whole.
fn run_one(test: &TestExecutable, args: &[OsString], log: &std::path::Path) -> Result<()> {
    let file = fs::File::create(log).with_context(|| format!("creating {}", log.display()))?;
    let mut command = Command::new(&test.executable);
    command
        .args(args)
        .current_dir(&test.package_dir)
        .env("CARGO_MANIFEST_DIR", &test.package_dir)
        .stdin(Stdio::null())
        .stdout(file.try_clone().context("duplicating a log file handle")?)
        .stderr(file);
    let started = Instant::now();
    let status = command
        .status()
        .with_context(|| format!("could not start {}", test.executable.display()))?;
    let seconds = started.elapsed().as_secs_f64();
    let output =
        fs::read_to_string(log).unwrap_or_else(|err| format!("(reading the log: {err})\n"));
    let verdict = if status.success() { "passed" } else { "FAILED" };
    // One write, so that two binaries ending together do not interleave.
    eprint!(
        "xtask: test {} {verdict} in {seconds:.1} s ({})\n{output}",
        test.source,
        test.executable.display()
    );
    if !status.success() {
        bail!("{status}");
    }
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use std::ffi::OsString;
    use std::fs;
    use std::os::unix::fs::PermissionsExt;
    use std::path::Path;

    use super::run_all;
    use crate::ci::TestExecutable;

    /// An executable shell script `name` in `dir` with `body`.
    fn script(dir: &Path, name: &str, body: &str) -> TestExecutable {
        let path = dir.join(name);
        fs::write(&path, format!("#!/bin/sh\n{body}\n")).expect("writing a test script");
        fs::set_permissions(&path, fs::Permissions::from_mode(0o755))
            .expect("making it executable");
        TestExecutable {
            executable: path,
            package_dir: dir.to_path_buf(),
            source: name.to_owned(),
        }
    }

    #[test]
    fn every_binary_runs_once_with_the_arguments_and_failures_are_named() {
        let dir = std::env::temp_dir().join(format!("xtask-runner-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        // Each binary appends its name, its arguments and its CARGO_MANIFEST_DIR to a record.
        let record = dir.join("record");
        let line = format!(
            r#"echo "$0 $* $CARGO_MANIFEST_DIR" >> '{}'"#,
            record.display()
        );
        let tests = vec![
            script(&dir, "a", &format!("{line}\nsleep 0.2")),
            script(&dir, "b", &format!("{line}\necho b failed\nexit 3")),
            script(&dir, "c", &line),
            script(&dir, "d", &format!("{line}\nexit 1")),
        ];
        let args = [OsString::from("--exact"), OsString::from("x")];
        let mut failures = run_all(tests, &args, 2, &dir);
        failures.sort();
        assert_eq!(failures, ["b", "d"]);
        let mut lines: Vec<String> = fs::read_to_string(&record)
            .unwrap()
            .lines()
            .map(str::to_owned)
            .collect();
        lines.sort();
        let expected: Vec<String> = ["a", "b", "c", "d"]
            .iter()
            .map(|name| format!("{} --exact x {}", dir.join(name).display(), dir.display()))
            .collect();
        assert_eq!(lines, expected);
        // The second binary's output is in its log, by its index.
        assert_eq!(fs::read_to_string(dir.join("1.log")).unwrap(), "b failed\n");
        fs::remove_dir_all(&dir).unwrap();
    }
}
