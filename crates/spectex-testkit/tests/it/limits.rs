//! Models at and one step past every limit: the valid ones render in bounded time, the others
//! are refused naming a field; nesting past the JSON reader's recursion limit is refused.

use std::time::Instant;

use spectex_cpu::Evaluator;
use spectex_model::{ModelError, Window};
use spectex_testkit::cpu::evaluate;
use spectex_testkit::limits::{limit_cases, nested_warp_text};

#[test]
fn models_at_each_limit_render_and_past_it_are_refused() {
    let mut slowest = (0.0, String::new());
    for case in limit_cases() {
        let verdict = case.model.validate();
        assert_eq!(
            verdict.is_ok(),
            case.valid,
            "{}: validation says {verdict:?}",
            case.name
        );
        if let Err(e) = verdict {
            assert!(
                matches!(e, ModelError::OutOfRange { .. } | ModelError::Length { .. }),
                "{}: {e}",
                case.name
            );
            assert!(Evaluator::new(&case.model).is_err(), "{}", case.name);
            continue;
        }
        let started = Instant::now();
        // A pixel, a far patch, and a minified row whose pixels lie 10⁶ pixels apart (rows
        // spanning many lattice columns once drew them all: hundreds of GB for these models).
        for window in [
            Window::new(1, 1),
            Window::new(2, 2).at([-1.0e7 + 0.5, 1.0e7 - 0.25], 0.37),
            Window::new(8, 2).at([-4.0e6, 3.0e6], 1e6),
        ] {
            let seen = evaluate(&case.model, &window, 37.3)
                .unwrap_or_else(|e| panic!("{}: {e}", case.name));
            let per_pixel = seen.render_seconds / seen.pixels as f64;
            if per_pixel > slowest.0 {
                slowest = (per_pixel, case.name.clone());
            }
        }
        println!(
            "limits: {:<50} build + 21 pixels in {:.3} s",
            case.name,
            started.elapsed().as_secs_f64()
        );
    }
    println!(
        "limits: slowest render {:.2} ms per pixel ({})",
        slowest.0 * 1e3,
        slowest.1
    );
}

#[test]
fn nesting_past_the_reader_limit_is_refused_without_overflowing() {
    for depth in [9, 60, 200, 2000] {
        let text = nested_warp_text(depth);
        let e = spectex_model::from_json(&text).expect_err("too deep");
        println!("limits: {depth} nested warps: {e}");
    }
}
