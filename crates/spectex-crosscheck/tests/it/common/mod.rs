//! Helpers shared by the cross-check tests: one place that decides whether a test without an
//! adapter skips (loudly) or fails (`SPECTEX_REQUIRE_GPU=1`), the small windows of the per-kind
//! suites (lavapipe is slow) and their loop over cases.

use spectex_crosscheck::{CaseWindow, Verdict, check_model};
use spectex_gpu::GpuContext;
use spectex_model::Model;

/// Environment variable that turns a missing adapter from a skip into a failure.
pub const REQUIRE_GPU_ENV: &str = "SPECTEX_REQUIRE_GPU";

/// A device for `test`, or `None` (after printing why) when there is no adapter and
/// `SPECTEX_REQUIRE_GPU` is not `1`.
///
/// # Panics
/// When no adapter exists and `SPECTEX_REQUIRE_GPU=1`.
pub fn gpu_or_skip(test: &str) -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(c) => Some(c),
        Err(e) if std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| v == "1") => {
            panic!("{test}: {REQUIRE_GPU_ENV}=1 but no GPU: {e}")
        }
        Err(e) => {
            println!("SKIPPED {test}: {e}");
            None
        }
    }
}

/// 32×32 windows at the origin, at 10⁷ pixels, magnified (scale 0.37) and minified at
/// `minified_scale`.
pub fn small_windows(minified_scale: f64) -> Vec<CaseWindow> {
    [
        ("origin", [0.0, 0.0], 1.0),
        ("far", [1.0e7, -1.0e7], 1.0),
        ("magnified", [-37.25, 11.5], 0.37),
        ("minified", [5.5, -13.25], minified_scale),
    ]
    .into_iter()
    .map(|(name, offset, scale)| CaseWindow {
        name,
        width: 32,
        height: 32,
        offset,
        scale,
    })
    .collect()
}

/// Checks every `(case, model)` on both evaluators in `windows`, printing each window's
/// largest error, and fails listing every window whose verdict is not a pass.
///
/// # Panics
/// When a model cannot be checked or a window does not pass.
pub fn check_cases(
    context: &GpuContext,
    cases: impl IntoIterator<Item = (String, Model)>,
    windows: &[CaseWindow],
) {
    let mut failed = Vec::new();
    for (case, model) in cases {
        let outcomes =
            check_model(context, &case, &model, windows).unwrap_or_else(|e| panic!("{case}: {e}"));
        for (w, o) in outcomes {
            println!("{case} {w}: max {:.2e}", o.comparison.max_abs);
            if !matches!(o.verdict, Verdict::Pass) {
                failed.push(format!("{case} {w}: {}", o.summary()));
            }
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
