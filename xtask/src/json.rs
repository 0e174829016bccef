//! The JSON xtask reads, by serde_json: cargo's messages and criterion's estimates and samples.

use std::path::PathBuf;

use serde::Deserialize;

/// A `compiler-artifact` message of cargo's `--message-format=json` (the fields xtask reads).
#[derive(Debug, Deserialize)]
pub(crate) struct Artifact {
    /// The package's `Cargo.toml`.
    pub manifest_path: PathBuf,
    pub target: ArtifactTarget,
    /// The built binary; `None` for a library (`"executable":null`).
    pub executable: Option<PathBuf>,
    pub profile: ArtifactProfile,
}

/// How an [`Artifact`] was compiled (the fields xtask reads).
#[derive(Debug, Deserialize)]
pub(crate) struct ArtifactProfile {
    /// A test harness (a test, or a bench built by `cargo test`), not a program such as the
    /// `spectex` binary the CLI's tests run.
    pub test: bool,
}

/// The target an [`Artifact`] was built for.
#[derive(Debug, Deserialize)]
pub(crate) struct ArtifactTarget {
    pub name: String,
    /// The target's root source file.
    pub src_path: PathBuf,
}

/// One line of cargo's JSON messages: a compiler artifact, or any other message.
#[derive(Deserialize)]
#[serde(tag = "reason")]
enum Message {
    #[serde(rename = "compiler-artifact")]
    CompilerArtifact(Artifact),
    #[serde(other)]
    Other,
}

/// The compiler artifacts among cargo's JSON messages, one per line of `stdout`; other
/// messages and lines that are not a message are skipped.
pub(crate) fn compiler_artifacts(stdout: &str) -> impl Iterator<Item = Artifact> + '_ {
    stdout
        .lines()
        .filter_map(|line| match serde_json::from_str(line) {
            Ok(Message::CompilerArtifact(artifact)) => Some(artifact),
            Ok(Message::Other) | Err(_) => None,
        })
}

/// The fields of a criterion `estimates.json` xtask reads.
#[derive(Deserialize)]
struct Estimates {
    median: Estimate,
}

/// One statistic of [`Estimates`].
#[derive(Deserialize)]
struct Estimate {
    point_estimate: f64,
}

/// The median (ns) of a criterion `estimates.json`: its `"median": { "point_estimate": … }`.
pub(crate) fn criterion_median_ns(json: &str) -> Option<f64> {
    serde_json::from_str::<Estimates>(json)
        .ok()
        .map(|e| e.median.point_estimate)
}

/// The fields of a criterion `sample.json` xtask reads: one entry per sample.
#[derive(Deserialize)]
struct Sample {
    iters: Vec<f64>,
    times: Vec<f64>,
}

/// The fastest time per iteration (ns) over the samples of a criterion `sample.json`
/// (`"iters"` and `"times"`, one entry per sample), or `None` when the arrays are missing,
/// empty or of different lengths.
pub(crate) fn criterion_best_ns(json: &str) -> Option<f64> {
    let Sample { iters, times } = serde_json::from_str(json).ok()?;
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::{compiler_artifacts, criterion_best_ns, criterion_median_ns};

    #[test]
    fn artifacts_are_read_from_cargo_messages() {
        let line = r#"{"reason":"compiler-artifact","manifest_path":"/w/a \"b\"\\c/Cargo.toml","target":{"name":"it","src_path":"/w/tests/it/main.rs"},"executable":null,"profile":{"opt_level":"2","test":true},"fresh":true,"x":"\u00e9\n"}"#;
        let with_executable = line.replace(r#""executable":null"#, r#""executable":"/w/t/it-1""#);
        let stdout = [
            line,
            r#"{"reason":"build-finished","success":true}"#,
            r#"{"a":"unterminated"#,
            &with_executable,
        ]
        .join("\n");
        let artifacts: Vec<_> = compiler_artifacts(&stdout).collect();
        assert_eq!(artifacts.len(), 2);
        assert_eq!(
            artifacts[0].manifest_path,
            Path::new(r#"/w/a "b"\c/Cargo.toml"#)
        );
        assert_eq!(artifacts[0].target.name, "it");
        assert_eq!(
            artifacts[0].target.src_path,
            Path::new("/w/tests/it/main.rs")
        );
        assert_eq!(artifacts[0].executable, None);
        assert!(artifacts[0].profile.test);
        assert_eq!(
            artifacts[1].executable.as_deref(),
            Some(Path::new("/w/t/it-1"))
        );
    }

    #[test]
    fn median_is_read_from_criterion_estimates() {
        let json = r#"{"mean":{"confidence_interval":{"confidence_level":0.95,"lower_bound":1.0,"upper_bound":2.0},"point_estimate":1.5,"standard_error":0.1},"median":{"confidence_interval":{"confidence_level":0.95,"lower_bound":3.0,"upper_bound":4.0},"point_estimate":3456789.25,"standard_error":0.2},"median_abs_dev":{"point_estimate":7.0}}"#;
        assert_eq!(criterion_median_ns(json), Some(3_456_789.25));
        assert_eq!(
            criterion_median_ns(r#"{"median": {"point_estimate" : 1.5e6}}"#),
            Some(1.5e6)
        );
        assert_eq!(
            criterion_median_ns(r#"{"mean":{"point_estimate":1.0}}"#),
            None
        );
    }

    #[test]
    fn best_sample_is_read_from_criterion_samples() {
        // Per iteration: 100, 75, 90 ns; the best is 75.
        let json =
            r#"{"sampling_mode":"Linear","iters":[1.0,2.0,3.0],"times":[100.0,150.0,270.0]}"#;
        assert_eq!(criterion_best_ns(json), Some(75.0));
        assert_eq!(
            criterion_best_ns(r#"{"iters": [ 4.0 ], "times" : [ 1e3 ]}"#),
            Some(250.0)
        );
        assert_eq!(
            criterion_best_ns(r#"{"iters":[1.0,2.0],"times":[1.0]}"#),
            None
        );
        assert_eq!(criterion_best_ns(r#"{"iters":[],"times":[]}"#), None);
        assert_eq!(criterion_best_ns(r#"{"times":[1.0]}"#), None);
    }
}
