//! Helpers shared by the CLI's tests and benches: running the binary, scratch directories,
//! and images as channel planes.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `spectex` binary with `args`.
pub fn spectex(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spectex"))
        .args(args)
        .output()
        .expect("the spectex binary runs")
}

/// Runs the `spectex` binary with `args` and asserts that it succeeded (the message shows the
/// arguments and its stderr).
pub fn spectex_ok(args: &[&str]) -> Output {
    let out = spectex(args);
    assert!(
        out.status.success(),
        "spectex {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A fresh directory under the target dir for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The value after `--z` in `args`, or `"0"`.
pub fn z_of<'a>(args: &[&'a str]) -> &'a str {
    args.iter()
        .position(|a| *a == "--z")
        .map_or("0", |i| args[i + 1])
}

/// An image as `(channels, height, width)` values in `[0, 1]` (as `spectex` reads exemplars).
pub use spectex_reproduce::planes;
