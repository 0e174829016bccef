//! SIGTERM and SIGINT sent to a streamed render (a batch scheduler's time limit, a user's
//! Ctrl-C): the command stops at the next band, removes its temporary file, writes no output
//! and exits with 128 + the signal's number and a message naming the signal.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{s, scratch};

/// The temporary files `spectex` writes into `dir` (`.spectex-XXXX.tmp`).
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with(".spectex-") && n.ends_with(".tmp"))
        .collect()
}

/// Starts a streamed render far larger than the test waits for, sends `signal` once its
/// temporary file exists, and checks how the command ended.
fn stopped_by(signal: &str, number: i32, output: &str) {
    let dir = scratch(&format!("signal-{signal}"));
    let out = dir.join(output);
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models/lrp-gravel.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_spectex"))
        .args(["render", s(&model), "-o", s(&out), "--size", "16384x16384"])
        .args(["--stream", "--band-rows", "64"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while temporaries(&dir).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no temporary file appeared in {}",
            dir.display()
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the render ended early"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    // Let it write a band or two first.
    std::thread::sleep(Duration::from_millis(300));
    let sent = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success(), "kill -{signal} failed");
    let stopped = Instant::now();
    let ended = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&ended.stderr);
    println!(
        "{signal}: exit status {:?} after {:.2} s, stderr: {}",
        ended.status.code(),
        stopped.elapsed().as_secs_f64(),
        stderr.trim()
    );
    assert_eq!(ended.status.code(), Some(128 + number), "stderr: {stderr}");
    assert!(
        stderr.starts_with("error: stopped by ") && stderr.contains(signal),
        "stderr: {stderr}"
    );
    assert_eq!(
        temporaries(&dir),
        Vec::<String>::new(),
        "temporary file left"
    );
    assert!(
        !out.exists(),
        "an unfinished {} was published",
        out.display()
    );
}

#[test]
fn sigterm_stops_a_streamed_exr_render_and_removes_its_temporary_file() {
    stopped_by("TERM", 15, "big.exr");
}

#[test]
fn sigint_stops_a_streamed_png_render_and_removes_its_temporary_file() {
    stopped_by("INT", 2, "big.png");
}
