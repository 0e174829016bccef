//! Image inputs through the `spectex` binary's loader (`io.rs`, the path every exemplar and
//! control image takes): every valid PNG colour type and bit depth is read; broken, truncated,
//! huge-header and zero-size files, and random or mutated PNGs and JPEGs, make it print one
//! `error: …` line and exit 1 — never a panic, an abort, a hang, or memory beyond a bound (each
//! run is under `ulimit -v` and `timeout`). Generators come from `spectex-testkit`;
//! `cargo xtask fuzz` runs the campaign long.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::print_stdout,
    reason = "the campaign summary is the test's report"
)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use image::{ExtendedColorType, ImageEncoder};
use spectex_testkit::fuzz::{Observation, Settings, Target, run};
use spectex_testkit::images::{
    ByteMutation, byte_mutation, malformed_pngs, mutate_bytes, patch_jpeg_dimensions, random_png,
    valid_pngs,
};
use spectex_testkit::proptest::prelude::*;
use spectex_testkit::proptest::sample::select;

/// Virtual memory a run may reserve, KiB (6 GiB): the decoder's own limit is 4 GiB and a
/// truncated file claiming 16384 × 16384 × 16-bit RGBA reserves 2 GiB of it (never touched); a
/// loader that believed a header claiming 100000 × 100000 would reserve 30 GB or more and abort.
const MEMORY_LIMIT_KIB: u64 = 6 << 20;
/// Seconds a run may take.
const TIME_LIMIT_S: u32 = 60;
/// Cases CI runs.
const CI_CASES: u32 = 150;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("fuzz-images-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// How one run ended.
struct Run {
    code: Option<i32>,
    stderr: String,
    wrote: bool,
}

/// Writes `bytes` to a file and runs `spectex rpn` on it under the memory and time limits.
fn run_on(dir: &Path, bytes: &[u8]) -> Run {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let case = dir.join(NEXT.fetch_add(1, Ordering::Relaxed).to_string());
    std::fs::create_dir_all(&case).unwrap();
    let (input, output) = (case.join("input.png"), case.join("out.png"));
    std::fs::write(&input, bytes).unwrap();
    let out = Command::new("sh")
        .args([
            "-c",
            &format!("ulimit -v {MEMORY_LIMIT_KIB} && exec timeout {TIME_LIMIT_S} \"$0\" \"$@\""),
            env!("CARGO_BIN_EXE_spectex"),
            "rpn",
            input.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ])
        .output()
        .expect("sh runs");
    let run = Run {
        code: out.status.code(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        wrote: output.exists(),
    };
    let _ = std::fs::remove_dir_all(&case);
    run
}

/// `Ok(true)` when the file was read (exit 0, output written), `Ok(false)` when it was refused
/// the way the CLI promises (exit 1, one `error: …` line, no output), else what went wrong.
fn judge(run: &Run) -> Result<bool, String> {
    if run.stderr.contains("panicked") {
        return Err(format!("panicked: {}", run.stderr.trim()));
    }
    match run.code {
        Some(0) if run.wrote => Ok(true),
        Some(0) => Err("exit 0 without an output file".into()),
        Some(1) => {
            let errors = run
                .stderr
                .lines()
                .filter(|l| l.starts_with("error: "))
                .count();
            if errors != 1 {
                return Err(format!(
                    "exit 1 with {errors} `error: ` lines: {}",
                    run.stderr.trim()
                ));
            }
            if run.wrote {
                return Err("exit 1 but an output file was left".into());
            }
            Ok(false)
        }
        Some(124) => Err(format!("no result within {TIME_LIMIT_S} s")),
        other => Err(format!(
            "exit status {other:?} (an abort, a signal, or memory past {} GiB?): {}",
            MEMORY_LIMIT_KIB >> 20,
            run.stderr.trim()
        )),
    }
}

#[test]
fn fuzz_valid_pngs_of_every_type_are_read() {
    let dir = scratch("valid");
    for (what, bytes) in valid_pngs() {
        let run = run_on(&dir, &bytes);
        assert_eq!(judge(&run), Ok(true), "{what}: {}", run.stderr);
    }
}

#[test]
fn fuzz_malformed_pngs_are_refused() {
    let dir = scratch("malformed");
    for (what, bytes) in malformed_pngs() {
        let run = run_on(&dir, &bytes);
        assert_eq!(judge(&run), Ok(false), "{what}: {}", run.stderr);
    }
}

/// Small valid JPEGs, grey and colour.
fn jpegs() -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for (w, h, colour) in [(8u32, 8u32, false), (17, 5, true), (3, 9, true)] {
        let channels = if colour { 3 } else { 1 };
        let pixels: Vec<u8> = (0..w * h * channels)
            .map(|i| (i * 37 % 251) as u8)
            .collect();
        let mut bytes = Vec::new();
        let kind = if colour {
            ExtendedColorType::Rgb8
        } else {
            ExtendedColorType::L8
        };
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 90)
            .write_image(&pixels, w, h, kind)
            .unwrap();
        out.push((
            format!("{w}×{h} {} JPEG", if colour { "RGB" } else { "grey" }),
            bytes,
        ));
    }
    out
}

#[test]
fn fuzz_jpegs_with_huge_zero_or_cut_frames_are_refused() {
    let dir = scratch("jpeg");
    for (what, bytes) in jpegs() {
        assert_eq!(judge(&run_on(&dir, &bytes)), Ok(true), "{what}");
        for (w, h) in [(65_535, 65_535), (16_385, 2), (0, 0), (0, 8)] {
            let patched = patch_jpeg_dimensions(&bytes, w, h).expect("a frame header");
            let run = run_on(&dir, &patched);
            assert_eq!(
                judge(&run),
                Ok(false),
                "{what} claiming {w}×{h}: {}",
                run.stderr
            );
        }
        for cut in [2, 20, bytes.len() / 2] {
            let run = run_on(&dir, &bytes[..cut]);
            assert_eq!(
                judge(&run),
                Ok(false),
                "{what} cut to {cut} bytes: {}",
                run.stderr
            );
        }
    }
}

/// A file to load: its description, its bytes, and whether it must be read (`Some(true)`), must
/// be refused (`Some(false)`), or either.
type ImageCase = (String, Vec<u8>, Option<bool>);

fn image_cases() -> BoxedStrategy<ImageCase> {
    let mutated = |sources: Vec<(String, Vec<u8>)>| {
        (select(sources), byte_mutation()).prop_map(
            |((what, bytes), m): ((String, Vec<u8>), ByteMutation)| {
                (format!("{what}, {m:?}"), mutate_bytes(&bytes, &m), None)
            },
        )
    };
    let headers = random_png().prop_map(|(what, bytes)| (what, bytes, None));
    prop_oneof![mutated(valid_pngs()), mutated(jpegs()), headers].boxed()
}

#[test]
fn fuzz_random_and_mutated_images_are_read_or_refused_cleanly() {
    let dir = scratch("campaign");
    let target: Target<ImageCase> = Arc::new(move |(_, bytes, expect): &ImageCase| {
        let read = judge(&run_on(&dir, bytes))?;
        if expect.is_some_and(|e| e != read) {
            return Err(format!("read = {read}, expected {expect:?}"));
        }
        Ok(Observation {
            kind: Some(if bytes.starts_with(&[0xFF, 0xD8]) {
                "jpeg"
            } else {
                "png"
            }),
            accepted: read,
            ..Observation::default()
        })
    });
    let report = run(
        "images-cli",
        &Settings::from_env(CI_CASES),
        &image_cases(),
        |(what, bytes, _)| format!("{what} ({} bytes)", bytes.len()),
        &target,
    );
    println!("{}", report.summary());
    assert!(report.findings.is_empty(), "{}", report.summary());
}
