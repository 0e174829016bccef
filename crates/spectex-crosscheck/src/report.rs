//! Failure reports: `{case}-{adapter}-cpu.png`, `-gpu.png`, `-diff.png` and a Markdown and a JSON
//! report under [`REPORT_DIR`].

use std::path::{Path, PathBuf};

use crate::compare::{CaseWindow, Outcome};
use crate::error::CrosscheckError;

/// Where reports go, relative to the workspace root (`CARGO_TARGET_DIR` is honoured).
pub const REPORT_DIR: &str = "target/crosscheck";

/// The report directory: `$CARGO_TARGET_DIR/crosscheck` when set, else [`REPORT_DIR`] under the
/// workspace root.
fn report_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) => PathBuf::from(dir).join("crosscheck"),
        None => Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(REPORT_DIR),
    }
}

/// A file-name-safe form of an adapter name: `llvmpipe (LLVM 15.0.6, 256 bits)` → `llvmpipe`.
fn adapter_slug(adapter: &str) -> String {
    let first = adapter.split(['(', ' ']).next().unwrap_or("adapter");
    let slug: String = first
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    if slug.is_empty() {
        "adapter".into()
    } else {
        slug
    }
}

fn io_error(path: &Path, source: std::io::Error) -> CrosscheckError {
    CrosscheckError::Report {
        path: path.display().to_string(),
        source,
    }
}

/// Writes a grey PNG of `values` mapped linearly from `[lo, hi]` to `[0, 255]`.
fn write_png(
    path: &Path,
    width: usize,
    height: usize,
    values: &[f64],
    lo: f64,
    hi: f64,
) -> Result<(), CrosscheckError> {
    let span = if hi > lo { hi - lo } else { 1.0 };
    let bytes: Vec<u8> = values
        .iter()
        .map(|v| (((v - lo) / span).clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    image::save_buffer(
        path,
        &bytes,
        width as u32,
        height as u32,
        image::ExtendedColorType::L8,
    )
    .map_err(|e| io_error(path, std::io::Error::other(e)))
}

/// Writes the three images and the two reports of a window that did not pass; returns the
/// Markdown report's path.
///
/// # Errors
/// [`CrosscheckError::Report`] when a file cannot be written.
pub fn write_failure_report(
    case: &str,
    adapter: &str,
    window: &CaseWindow,
    outcome: &Outcome,
) -> Result<PathBuf, CrosscheckError> {
    write_failure_report_in(&report_dir(), case, adapter, window, outcome)
}

/// [`write_failure_report`] into `dir`.
///
/// # Errors
/// [`CrosscheckError::Report`] when a file cannot be written.
pub fn write_failure_report_in(
    dir: &Path,
    case: &str,
    adapter: &str,
    window: &CaseWindow,
    outcome: &Outcome,
) -> Result<PathBuf, CrosscheckError> {
    std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    let stem = format!("{case}-{}", adapter_slug(adapter));
    let c = &outcome.comparison;
    let cpu: Vec<f64> = c.cpu.iter().map(|&v| f64::from(v)).collect();
    let gpu: Vec<f64> = c.gpu.iter().map(|&v| f64::from(v)).collect();
    let finite = cpu.iter().chain(&gpu).filter(|v| v.is_finite());
    let lo = finite.clone().copied().fold(f64::INFINITY, f64::min);
    let hi = finite.copied().fold(f64::NEG_INFINITY, f64::max);
    write_png(
        &dir.join(format!("{stem}-cpu.png")),
        c.width,
        c.height,
        &cpu,
        lo,
        hi,
    )?;
    write_png(
        &dir.join(format!("{stem}-gpu.png")),
        c.width,
        c.height,
        &gpu,
        lo,
        hi,
    )?;
    let diff: Vec<f64> = cpu.iter().zip(&gpu).map(|(a, b)| (a - b).abs()).collect();
    // The difference image is scaled so that the tolerance is mid-grey: white is twice it.
    write_png(
        &dir.join(format!("{stem}-diff.png")),
        c.width,
        c.height,
        &diff,
        0.0,
        2.0 * outcome.tolerance.max_abs,
    )?;
    let json = serde_json::json!({
        "case": case,
        "adapter": adapter,
        "window": {
            "name": window.name, "width": window.width, "height": window.height,
            "offset": window.offset, "scale": window.scale,
        },
        "max_abs": c.max_abs, "mean_abs": c.mean_abs, "p999": c.p999, "spectral": c.spectral,
        "tolerance": {
            "max_abs": outcome.tolerance.max_abs, "mean_abs": outcome.tolerance.mean_abs,
            "spectral": outcome.spectral_tolerance,
        },
        "bit_identical": c.bit_identical, "pixels": c.cpu.len(),
        "verdict": format!("{:?}", outcome.verdict),
    });
    let json_path = dir.join(format!("{stem}.json"));
    std::fs::write(&json_path, format!("{json:#}\n")).map_err(|e| io_error(&json_path, e))?;
    let md = format!(
        "# Cross-check: {case} on {adapter}\n\nWindow: {window}\n\n\
         | measure | value | tolerance |\n|---|---|---|\n\
         | max abs error | {:.3e} | {:.3e} |\n| mean abs error | {:.3e} | {:.3e} |\n\
         | 99.9th percentile | {:.3e} | — |\n| spectral distance | {:.3e} | {:.3e} |\n\
         | bit-identical pixels | {} / {} | — |\n\nVerdict: {}\n\n\
         Images: `{stem}-cpu.png`, `{stem}-gpu.png`, `{stem}-diff.png` (mid-grey = tolerance).\n",
        c.max_abs,
        outcome.tolerance.max_abs,
        c.mean_abs,
        outcome.tolerance.mean_abs,
        c.p999,
        c.spectral,
        outcome.spectral_tolerance,
        c.bit_identical,
        c.cpu.len(),
        outcome.summary()
    );
    let md_path = dir.join(format!("{stem}.md"));
    std::fs::write(&md_path, md).map_err(|e| io_error(&md_path, e))?;
    Ok(md_path)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod tests {
    #![allow(clippy::unwrap_used, reason = "a test fails loudly")]

    use super::*;
    use crate::compare::{compare, judge, standard_windows};
    use crate::tolerance::Tolerance;

    pub fn a_failure_writes_three_images_and_two_reports() {
        let dir = tempfile::tempdir().unwrap();
        let a: Vec<f32> = (0..128 * 128).map(|i| (i as f32 * 0.01).sin()).collect();
        let mut b = a.clone();
        b[77] += 0.1;
        let t = Tolerance {
            max_abs: 1e-3,
            mean_abs: 1e-4,
        };
        let outcome = judge(compare(128, 128, a, b), t, None);
        assert!(!outcome.passed());
        let w = standard_windows()[0];
        let md = write_failure_report_in(
            dir.path(),
            "case-origin",
            "llvmpipe (LLVM 15)",
            &w,
            &outcome,
        )
        .unwrap();
        for suffix in ["-cpu.png", "-gpu.png", "-diff.png", ".json", ".md"] {
            let path = dir.path().join(format!("case-origin-llvmpipe{suffix}"));
            assert!(path.is_file(), "{} missing", path.display());
        }
        let text = std::fs::read_to_string(md).unwrap();
        assert!(text.contains("FAIL"), "{text}");
        let json = std::fs::read_to_string(dir.path().join("case-origin-llvmpipe.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert!((v["max_abs"].as_f64().unwrap() - 0.1).abs() < 1e-6);
    }
}
