//! Measuring two renders of one window and judging the differences: the generic criterion
//! (each component's max, mean and spectral error within its [`Tolerance`]), the verdict of a
//! kind's own criterion, and the adapter-specific expected failures.

use ndarray::Array2;
use spectex_spectrum::{Fft2, welch_psd};

use crate::tolerance::Tolerance;

/// Adapter-specific expected failures: `(case prefix, adapter-name substring, reason)`. A case
/// listed here that passes on a matching adapter fails ("unexpected pass"), so the table cannot
/// go stale. Empty: every shipped case passes on lavapipe (Mesa 22.3.6), and every case but
/// the `classic-*` ones (not yet run there) on the NVIDIA drivers it was run on.
pub const EXPECTED_FAILURES: &[(&str, &str, &str)] = &[];

/// The expected-failure reason for `case` on `adapter`, if one is declared.
#[must_use]
pub fn expected_failure(case: &str, adapter: &str) -> Option<&'static str> {
    let adapter = adapter.to_lowercase();
    EXPECTED_FAILURES
        .iter()
        .find(|(prefix, name, _)| {
            case.starts_with(prefix) && adapter.contains(&name.to_lowercase())
        })
        .map(|(_, _, reason)| *reason)
}

/// A window rendered by both evaluators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaseWindow {
    /// Short name used in reports (`origin`, `far`, `scaled`).
    pub name: &'static str,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Model position of the top-left pixel.
    pub offset: [f64; 2],
    /// Model pixels per output pixel.
    pub scale: f64,
}

impl std::fmt::Display for CaseWindow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} {}×{} at ({}, {}) scale {}",
            self.name, self.width, self.height, self.offset[0], self.offset[1], self.scale
        )
    }
}

/// The four windows of every case: at the origin, at `(10⁷, 10⁷)` (invariant 2 of
/// `docs/ARCHITECTURE.md`), at a fractional scale and offset, and minified at scale 4, where
/// both evaluators filter (`spectex_model::filter`: the kinds that fade components do it on
/// both); 128² each, which keeps lavapipe fast and leaves Welch 9 blocks of 64².
#[must_use]
pub fn standard_windows() -> Vec<CaseWindow> {
    vec![
        CaseWindow {
            name: "origin",
            width: 128,
            height: 128,
            offset: [0.0, 0.0],
            scale: 1.0,
        },
        CaseWindow {
            name: "far",
            width: 128,
            height: 128,
            offset: [1.0e7, 1.0e7],
            scale: 1.0,
        },
        CaseWindow {
            name: "scaled",
            width: 128,
            height: 128,
            offset: [-37.25, 11.5],
            scale: 0.37,
        },
        CaseWindow {
            name: "minified",
            width: 128,
            height: 128,
            offset: [5.5, -13.25],
            scale: 4.0,
        },
    ]
}

/// The measured differences of one window.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Window width.
    pub width: usize,
    /// Window height.
    pub height: usize,
    /// The CPU render, row-major.
    pub cpu: Vec<f32>,
    /// The GPU render, row-major.
    pub gpu: Vec<f32>,
    /// `max |cpu − gpu|`.
    pub max_abs: f64,
    /// Mean of `|cpu − gpu|`.
    pub mean_abs: f64,
    /// 99.9th percentile of `|cpu − gpu|`.
    pub p999: f64,
    /// `Σ|P_cpu − P_gpu| / Σ P_cpu` of the two Welch spectra.
    pub spectral: f64,
    /// Standard deviation of the CPU render.
    pub sigma: f64,
    /// Pixels whose bits are identical.
    pub bit_identical: usize,
    /// The output component compared, for models with several values per pixel (a colour
    /// texture's R, G, B); `None` for single-valued models.
    pub channel: Option<usize>,
}

/// Measures `cpu` against `gpu` (same window, row-major).
///
/// # Panics
/// If the two slices differ in length or do not hold `width × height` values.
#[must_use]
pub fn compare(width: usize, height: usize, cpu: Vec<f32>, gpu: Vec<f32>) -> Comparison {
    assert_eq!(cpu.len(), width * height, "CPU render size");
    assert_eq!(gpu.len(), width * height, "GPU render size");
    let mut errors: Vec<f64> = cpu
        .iter()
        .zip(&gpu)
        .map(|(a, b)| (f64::from(*a) - f64::from(*b)).abs())
        .collect();
    let bit_identical = cpu
        .iter()
        .zip(&gpu)
        .filter(|(a, b)| a.to_bits() == b.to_bits())
        .count();
    let n = errors.len().max(1) as f64;
    let mean_abs = errors.iter().sum::<f64>() / n;
    errors.sort_by(f64::total_cmp);
    let max_abs = errors.last().copied().unwrap_or(0.0);
    let p999 = errors
        .get(((errors.len() as f64 * 0.999).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0.0);
    let to_array =
        |v: &[f32]| Array2::from_shape_fn((height, width), |(y, x)| f64::from(v[y * width + x]));
    let (a, b) = (to_array(&cpu), to_array(&gpu));
    let mean = a.mean().unwrap_or(0.0);
    let sigma = (a.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
    let spectral = if width >= 3 && height >= 3 {
        let mut fft = Fft2::new();
        match (welch_psd(a.view(), &mut fft), welch_psd(b.view(), &mut fft)) {
            (Ok(pa), Ok(pb)) => {
                let total: f64 = pa.sum();
                let diff: f64 = pa.iter().zip(pb.iter()).map(|(x, y)| (x - y).abs()).sum();
                if total > 0.0 { diff / total } else { diff }
            }
            _ => 0.0,
        }
    } else {
        0.0
    };
    Comparison {
        width,
        height,
        cpu,
        gpu,
        max_abs,
        mean_abs,
        p999,
        spectral,
        sigma,
        bit_identical,
        channel: None,
    }
}

/// Component `channel` of an interleaved render with `channels` values per pixel.
pub(crate) fn plane(values: &[f32], channels: usize, channel: usize) -> Vec<f32> {
    values
        .iter()
        .skip(channel)
        .step_by(channels)
        .copied()
        .collect()
}

/// The verdict on one window.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Within every tolerance.
    Pass,
    /// Outside a tolerance; the reasons.
    Fail(Vec<String>),
    /// Outside a tolerance, as declared in [`EXPECTED_FAILURES`] (the reason).
    ExpectedFail(&'static str),
    /// Within tolerance although [`EXPECTED_FAILURES`] says it should fail (the reason).
    UnexpectedPass(&'static str),
}

impl Verdict {
    /// The verdict of a window that fails for the reasons `why` (none: it passes), given the
    /// expected failure `expected` declared for it.
    fn from_reasons(why: Vec<String>, expected: Option<&'static str>) -> Self {
        match (why.is_empty(), expected) {
            (true, None) => Self::Pass,
            (true, Some(reason)) => Self::UnexpectedPass(reason),
            (false, None) => Self::Fail(why),
            (false, Some(reason)) => Self::ExpectedFail(reason),
        }
    }
}

/// A comparison with its tolerance and verdict.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The measurements.
    pub comparison: Comparison,
    /// The model's tolerance.
    pub tolerance: Tolerance,
    /// The spectral tolerance for this render's contrast.
    pub spectral_tolerance: f64,
    /// The verdict.
    pub verdict: Verdict,
}

impl Outcome {
    /// Whether the suite should count this window as passing.
    #[must_use]
    pub fn passed(&self) -> bool {
        matches!(self.verdict, Verdict::Pass | Verdict::ExpectedFail(_))
    }

    /// One line: the errors against their tolerances and the verdict.
    #[must_use]
    pub fn summary(&self) -> String {
        let c = &self.comparison;
        let verdict = match &self.verdict {
            Verdict::Pass => "pass".to_owned(),
            Verdict::Fail(why) => format!("FAIL ({})", why.join("; ")),
            Verdict::ExpectedFail(why) => format!("expected failure ({why})"),
            Verdict::UnexpectedPass(why) => format!("FAIL: unexpected pass (declared: {why})"),
        };
        let channel = c
            .channel
            .map(|k| format!("channel {k}: "))
            .unwrap_or_default();
        format!(
            "{channel}max {:.2e} / {:.2e}, mean {:.2e} / {:.2e}, p99.9 {:.2e}, spectral {:.2e} / \
             {:.2e}, {}/{} bit-identical: {verdict}",
            c.max_abs,
            self.tolerance.max_abs,
            c.mean_abs,
            self.tolerance.mean_abs,
            c.p999,
            c.spectral,
            self.spectral_tolerance,
            c.bit_identical,
            c.cpu.len()
        )
    }
}

/// Judges `comparison` against `tolerance`, with the expected failure `expected` if declared.
#[must_use]
pub fn judge(
    comparison: Comparison,
    tolerance: Tolerance,
    expected: Option<&'static str>,
) -> Outcome {
    let spectral_tolerance = tolerance.spectral(comparison.sigma);
    let mut why = Vec::new();
    let c = &comparison;
    if c.max_abs.is_nan() || c.max_abs > tolerance.max_abs {
        why.push(format!("max {:.3e} > {:.3e}", c.max_abs, tolerance.max_abs));
    }
    if c.mean_abs.is_nan() || c.mean_abs > tolerance.mean_abs {
        why.push(format!(
            "mean {:.3e} > {:.3e}",
            c.mean_abs, tolerance.mean_abs
        ));
    }
    if c.spectral.is_nan() || c.spectral > spectral_tolerance {
        why.push(format!(
            "spectral {:.3e} > {:.3e}",
            c.spectral, spectral_tolerance
        ));
    }
    Outcome {
        comparison,
        tolerance,
        spectral_tolerance,
        verdict: Verdict::from_reasons(why, expected),
    }
}

/// Judges `comparison` by a kind's own criterion
/// ([`CheckKind::own_verdict`](crate::CheckKind::own_verdict)): `why` are the reasons it
/// fails (none when it passes). `tolerance` is what reports show; the spectra are not judged
/// (an infinite spectral tolerance), since the kind's criterion says which differences are
/// allowed where.
#[must_use]
pub fn judge_by_reasons(
    comparison: Comparison,
    tolerance: Tolerance,
    why: Vec<String>,
    expected: Option<&'static str>,
) -> Outcome {
    Outcome {
        comparison,
        tolerance,
        spectral_tolerance: f64::INFINITY,
        verdict: Verdict::from_reasons(why, expected),
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn planes_take_one_component_of_interleaved_values() {
        let v = [0.0, 1.0, 2.0, 10.0, 11.0, 12.0];
        assert_eq!(plane(&v, 3, 1), [1.0, 11.0]);
        assert_eq!(plane(&v, 1, 0), v);
    }

    pub fn identical_renders_measure_zero() {
        let v: Vec<f32> = (0..64).map(|i| (i as f32 * 0.37).sin()).collect();
        let c = compare(8, 8, v.clone(), v);
        assert_eq!(
            (c.max_abs, c.mean_abs, c.p999, c.spectral),
            (0.0, 0.0, 0.0, 0.0)
        );
        assert_eq!(c.bit_identical, 64);
    }

    pub fn one_outlier_sets_the_max_not_the_percentile() {
        let a: Vec<f32> = vec![0.5; 10_000];
        let mut b = a.clone();
        b[1234] = 0.75;
        let c = compare(100, 100, a, b);
        assert_eq!(c.max_abs, 0.25);
        assert_eq!(c.p999, 0.0);
        assert!((c.mean_abs - 0.25 / 10_000.0).abs() < 1e-12);
    }

    pub fn verdicts_follow_the_expected_failure_table() {
        let v: Vec<f32> = (0..64).map(|i| (i as f32 * 0.37).sin()).collect();
        let mut w = v.clone();
        w[3] += 0.5;
        let t = Tolerance {
            max_abs: 1e-3,
            mean_abs: 1e-4,
        };
        assert_eq!(
            judge(compare(8, 8, v.clone(), v.clone()), t, None).verdict,
            Verdict::Pass
        );
        assert!(matches!(
            judge(compare(8, 8, v.clone(), w.clone()), t, None).verdict,
            Verdict::Fail(_)
        ));
        let r = "known";
        assert!(!judge(compare(8, 8, v.clone(), v.clone()), t, Some(r)).passed());
        assert!(judge(compare(8, 8, v, w), t, Some(r)).passed());
    }
}
