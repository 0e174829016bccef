//! Periodic renders on the device (`GpuEvaluator::periodic_at_z`) for every shipped model of a
//! kind with a periodic form: tiles stay invisible and a window moved by whole periods gives the
//! same bits. The CPU comparison is the cross-check's (`spectex-crosscheck`,
//! `periodic_models_agree_on_cpu_and_gpu`).

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_gpu::{GpuEvaluator, GpuWindow};
use spectex_model::{PERIODIC_KINDS, Period};
use spectex_testkit::invariance::testdata_cases;

use crate::common;

/// The periods tried, in order (the CPU's periodic tests' list).
const PERIODS: [(u32, u32); 4] = [(96, 64), (256, 128), (768, 768), (480, 320)];

#[test]
fn periodic_tiles_and_whole_periods_are_invisible() {
    let Some(context) = common::gpu_or_skip("periodic renders") else {
        return;
    };
    let mut kinds = Vec::new();
    for case in testdata_cases() {
        let Some(p) = PERIODS
            .iter()
            .map(|&(w, h)| Period::new(w, h).unwrap())
            .find(|&p| case.model.check_period(p).is_ok())
        else {
            continue;
        };
        let mut gpu = GpuEvaluator::periodic_at_z(&context, &case.model, 0.0, p).unwrap();
        let [w, h] = p.sides();
        // Across the period's corner, at a fractional offset.
        let at = [w - 20.25, -13.5];
        let window = GpuWindow::new(48, 40).at(at, 1.0);
        let whole = gpu.render(&window).unwrap();
        let moved = gpu
            .render(&GpuWindow::new(48, 40).at([at[0] - 3.0 * w, at[1] + 2.0e4 * h], 1.0))
            .unwrap();
        assert_eq!(
            common::first_bit_difference(&whole, &moved),
            None,
            "{}: moved by whole periods ({p})",
            case.name
        );
        gpu.set_max_tile(13, 9);
        let tiled = gpu.render(&window).unwrap();
        assert_eq!(
            common::first_bit_difference(&whole, &tiled),
            None,
            "{}: tiles ({p})",
            case.name
        );
        kinds.push(case.model.kind());
    }
    for kind in PERIODIC_KINDS.iter() {
        assert!(
            kinds.contains(kind),
            "no shipped {kind} model takes a period of {PERIODS:?}"
        );
    }
}
