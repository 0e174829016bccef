//! `cargo xtask fuzz`: the long fuzz campaigns and their summaries.

use std::ffi::OsString;
use std::process::Stdio;
use std::time::Instant;

use anyhow::{Context, Result, bail};

use crate::system::lavapipe_icd;
use crate::{Workspace, show};

/// Cases per campaign of `cargo xtask fuzz` unless `--cases` says otherwise.
const FUZZ_DEFAULT_CASES: u64 = 20_000;

/// `cargo xtask fuzz [--cases N] [--seed S]`: the fuzz tests of the kit (CPU), the CLI (images)
/// and the GPU crate, selected by the `fuzz_` in their names, with `SPECTEX_FUZZ_CASES` and
/// `SPECTEX_FUZZ_SEED` set, in the `fuzz` profile (release with overflow checks and debug
/// assertions, so arithmetic overflow is a finding, not a silent wrap). Prints each campaign's
/// summary (`fuzz <name>: …` and its indented lines), then the totals; fails if any campaign
/// did.
pub(crate) fn fuzz(ws: &Workspace, args: &[OsString]) -> Result<()> {
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

#[cfg(test)]
mod tests {
    use super::campaign_counts;

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
}
