//! Periodic renders (`Evaluator::periodic`): for every `testdata/models/*.json` whose kind has a
//! periodic form, a window across the seams equals itself moved by one period in x, in y and in
//! both, bit for bit (at the origin, at a fractional offset and at `10⁷` periods), the two
//! evaluation paths agree, the seams are
//! seamless (the periodic function one period apart, positions not reduced, agrees up to
//! rounding, where the plain model does not unless periodic by construction), and the other
//! kinds are refused by name.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_cpu::{Evaluator, Window};
use spectex_model::{Model, PERIODIC_KINDS, Period};
use spectex_testkit::invariance::testdata_cases;

/// The periods tried, in order: a rectangular one (an axis mix-up shows), then one that every
/// classic octave of the shipped models divides, then the shipped wavelet tiles' 768 pixels,
/// then multiples of the shipped 4.8.8 Islamic pattern's 40-pixel cell.
const PERIODS: [(u32, u32); 4] = [(96, 64), (256, 128), (768, 768), (480, 320)];

/// The cases whose model accepts one of [`PERIODS`], with the first it accepts.
fn periodic_cases() -> Vec<(String, Model, Period)> {
    let mut out = Vec::new();
    for case in testdata_cases() {
        let accepted = PERIODS
            .iter()
            .map(|&(w, h)| Period::new(w, h).unwrap())
            .find(|&p| case.model.check_period(p).is_ok());
        if let Some(p) = accepted {
            out.push((case.name, case.model, p));
        }
    }
    out
}

fn render(eval: &Evaluator, window: &Window) -> Vec<f32> {
    eval.render(window).unwrap()
}

/// Asserts that a window across the seams near `offset` (at most 64² pixels, from `offset −
/// (29, 35)`: a seam in x and one in y inside it) equals, bit for bit, the same window moved by
/// one period in x, in y and in both, where the seams inside it are the next ones; and that a
/// 30×20 tile of it, across both seams too, has its bits.
///
/// Windows across the seams rather than a `2W × 2H` render against its `W × H` quarter: the
/// whole two periods (up to 1536² for a 768² period, at three offsets) took about 80% of this
/// binary's time and repeat the same exact reduction at more interior positions; that a kind's
/// rows are the same in any window and tiling is `spectex-testkit`'s invariance suite.
fn assert_repeats(name: &str, eval: &Evaluator, p: Period, offset: [f64; 2]) {
    let [w, h] = p.sides();
    let (a, b) = ((p.width as usize).min(64), (p.height as usize).min(64));
    let c = eval.output_channels();
    let at = [offset[0] - 29.0, offset[1] - 35.0];
    let window = Window::new(a, b).at(at, 1.0);
    let seams = render(eval, &window);
    assert_eq!(
        seams.len(),
        a * b * c,
        "{name}: one value per pixel and channel"
    );
    // A tile of the window, across both seams too, has the window's bits.
    let tile = render(eval, &window.tile(13, 17, 30, 20));
    assert_eq!(tile.len(), 30 * 20 * c, "{name}: the tile's values");
    for (n, x) in tile.iter().enumerate() {
        let (i, j, k) = (n / c % 30 + 13, n / c / 30 + 17, n % c);
        let y = seams[(j * a + i) * c + k];
        assert_eq!(
            x.to_bits(),
            y.to_bits(),
            "{name}, period {p}, offset {offset:?}: tile pixel ({i}, {j}) channel {k}"
        );
    }
    for (dx, dy) in [(w, 0.0), (0.0, h), (w, h)] {
        let moved = render(eval, &Window::new(a, b).at([at[0] + dx, at[1] + dy], 1.0));
        for (n, (x, y)) in seams.iter().zip(&moved).enumerate() {
            assert_eq!(
                x.to_bits(),
                y.to_bits(),
                "{name}, period {p}, offset {offset:?}: pixel ({}, {}) channel {} is {x}, moved \
                 by ({dx}, {dy}) {y}",
                n / c % a,
                n / c / a,
                n % c
            );
        }
    }
}

#[test]
fn a_window_across_the_seams_repeats_one_period_away_bit_for_bit() {
    let cases = periodic_cases();
    // Every kind with a periodic form is among the shipped cases.
    for kind in PERIODIC_KINDS.iter() {
        assert!(
            cases.iter().any(|(_, m, _)| m.kind() == *kind),
            "no testdata model of periodic kind {kind} accepts a period of {PERIODS:?}"
        );
    }
    // And a model that accepts a period is of a kind that declares a periodic form
    // (`ModelKind::PERIODIC`, what messages and registries list).
    for (name, model, _) in &cases {
        assert!(
            PERIODIC_KINDS.contains(&model.kind()),
            "{name} accepts a period but its kind {} does not declare PERIODIC",
            model.kind()
        );
    }
    for (name, model, p) in &cases {
        let eval = Evaluator::periodic(model, *p).unwrap();
        let [w, h] = p.sides();
        // Far: the largest multiple of the period (10⁷ periods, or fewer where 10⁷ would leave
        // the 2³⁰ range) that keeps the window in range.
        let far = |side: f64| ((spectex_cpu::MAX_POSITION / side).floor() - 2.0).min(1.0e7) * side;
        for offset in [[0.0, 0.0], [3.5, -17.25], [far(w), -far(h) + 5.0]] {
            assert_repeats(name, &eval, *p, offset);
        }
    }
}

#[test]
fn the_whole_window_and_point_paths_agree() {
    for (name, model, p) in periodic_cases() {
        let eval = Evaluator::periodic(&model, p).unwrap();
        let c = eval.output_channels();
        // An integer window (sub-windows moved by whole periods) against the same positions as
        // points, and a fractional-scale window (points) against its pixels one by one.
        for window in [
            Window::new(150, 3).at([-40.0, 1.0e6], 1.0),
            Window::new(40, 2).at([-7.3, 11.1], 0.77),
        ] {
            let rows = render(&eval, &window);
            let points: Vec<[f64; 2]> = (0..window.height)
                .flat_map(|j| (0..window.width).map(move |i| [window.x(i), window.y(j)]))
                .collect();
            let mut by_points = vec![0.0f32; points.len() * c];
            eval.eval_points(&points, &mut by_points);
            for (k, (a, b)) in rows.iter().zip(&by_points).enumerate() {
                assert_eq!(a.to_bits(), b.to_bits(), "{name} {window:?}: value {k}");
            }
        }
    }
}

#[test]
fn seams_are_seamless_where_the_plain_model_is_not() {
    for (name, model, p) in periodic_cases() {
        let function = Evaluator::periodic_unreduced(&model, p).unwrap();
        let plain = Evaluator::new(&model).unwrap();
        let [w, h] = p.sides();
        let window = Window::new(48, 24).at([-9.25, 4.5], 1.0);
        let base = render(&function, &window);
        let spread = {
            let mean = base.iter().map(|&v| f64::from(v)).sum::<f64>() / base.len() as f64;
            (base
                .iter()
                .map(|&v| (f64::from(v) - mean).powi(2))
                .sum::<f64>()
                / base.len() as f64)
                .sqrt()
        };
        assert!(spread > 0.0, "{name}: a constant window");
        for shift in [[w, 0.0], [0.0, -h], [3.0 * w, 2.0 * h]] {
            let moved = window.at(
                [window.offset[0] + shift[0], window.offset[1] + shift[1]],
                1.0,
            );
            let max = |eval: &Evaluator| {
                render(eval, &moved)
                    .iter()
                    .zip(&base)
                    .map(|(a, b)| (f64::from(*a) - f64::from(*b)).abs())
                    .fold(0.0f64, f64::max)
            };
            // Rounding only: lattice points placed at `n·(W/n)` rather than `W`, positions
            // a few periods away rounded in f64 — far below 10⁻³ of the field's spread.
            let periodic = max(&function);
            assert!(
                periodic <= 1e-3 * spread,
                "{name}, period {p}, shift {shift:?}: differs by {periodic} (spread {spread})"
            );
            // The plain model one period away is another part of the noise, except where it
            // is periodic by construction: a wavelet tile, a texture's structure alone, an
            // Islamic pattern's lattice, a matrix transformation's torus.
            let other = max(&plain);
            let plain_periodic =
                matches!(model.kind(), "wavelet" | "texture" | "islamic" | "matrix");
            assert!(
                plain_periodic || other > 0.1 * spread,
                "{name}, shift {shift:?}: the plain model is periodic too ({other}, {spread})"
            );
        }
    }
}

#[test]
fn kinds_without_a_periodic_form_are_refused_by_name() {
    // Every shipped model that takes none of the test periods is refused by kind and period.
    for case in testdata_cases() {
        let accepted = PERIODS
            .iter()
            .any(|&(w, h)| case.model.check_period(Period::new(w, h).unwrap()).is_ok());
        if accepted {
            continue;
        }
        let p = Period::new(96, 64).unwrap();
        let err = Evaluator::periodic(&case.model, p).unwrap_err().to_string();
        assert!(
            err.contains("period 96x64") && err.contains(case.model.kind()),
            "{}: {err}",
            case.name
        );
    }
    // What each refusal names: (model, period, the words its message must hold).
    let cases: &[(&str, (u32, u32), &[&str])] = &[
        ("classic-simplex-2d", (256, 128), &["simplex", "skewed"]),
        (
            "islamic-hexagonal-star-distance",
            (480, 320),
            &["islamic.tiling", "\"square\" or \"4.8.8\""],
        ),
        (
            "islamic-488-band",
            (100, 80),
            &["islamic.cell_size = 40", "80, 120"],
        ),
        (
            "matrix-cat-rings",
            (96, 100),
            &["matrix.size = 96", "height 100", "192"],
        ),
        // Cells of 24 px divide 48, the Lloyd blocks of 4 × 24 = 96 px do not.
        (
            "voronoi-border-lloyd",
            (48, 48),
            &["voronoi.lloyd_block", "96"],
        ),
        ("voronoi-f1", (100, 56), &["voronoi.cell_size = 28", "56"]),
    ];
    for (name, (w, h), needles) in cases {
        let case = testdata_cases()
            .into_iter()
            .find(|c| c.name.contains(name))
            .unwrap();
        let p = Period::new(*w, *h).unwrap();
        let err = Evaluator::periodic(&case.model, p).unwrap_err().to_string();
        for needle in *needles {
            assert!(err.contains(needle), "{name} with {p}: {err}");
        }
    }
    // A rotated square lattice is periodic only when turned by a multiple of 90°.
    let case = testdata_cases()
        .into_iter()
        .find(|c| c.name.contains("islamic-488-band"))
        .unwrap();
    let Model::Islamic(mut m) = case.model else {
        panic!("not an Islamic model")
    };
    let p = Period::new(480, 320).unwrap();
    m.rotation = 90.0;
    assert!(Evaluator::periodic(&Model::Islamic(m.clone()), p).is_ok());
    m.rotation = 30.0;
    let err = Evaluator::periodic(&Model::Islamic(m), p)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("islamic.rotation") && err.contains("90°"),
        "{err}"
    );
}

/// Phasor noise is periodic when its fields repeat with the period; a ramp never does, and the
/// refusal names the field by its path (the shipped gradient-blend model's frequency is a ramp).
#[test]
fn phasor_fields_that_do_not_repeat_are_refused_by_path() {
    let p = Period::new(256, 256).unwrap();
    let case = testdata_cases()
        .into_iter()
        .find(|c| c.name.contains("phasor-gradient-blend"))
        .unwrap();
    let err = Evaluator::periodic(&case.model, p).unwrap_err().to_string();
    assert!(
        err.contains("period 256x256") && err.contains("phasor.frequency"),
        "{err}"
    );
    // So is the coherent PWM model's duty-cycle ramp.
    let coherent = testdata_cases()
        .into_iter()
        .find(|c| c.name.contains("phasor-pwm-coherent"))
        .unwrap();
    let err = Evaluator::periodic(&coherent.model, p)
        .unwrap_err()
        .to_string();
    assert!(err.contains("phasor.profile.square.duty"), "{err}");
    // With a constant duty cycle it is periodic: kernel cells 48.8 → 48 px and direction cells
    // (radius / bandwidth ratio 0.5) 97.7 → 96 px both divide 96.
    let Model::Phasor(mut m) = coherent.model else {
        panic!("not a phasor model")
    };
    m.profile = spectex_model::Profile::Square {
        duty: spectex_model::Field::constant(0.4),
    };
    let square = Period::new(96, 96).unwrap();
    let eval = Evaluator::periodic(&Model::Phasor(m), square).unwrap();
    for offset in [[0.0, 0.0], [-41.0, 1.0e7]] {
        assert_repeats("phasor-pwm-coherent, constant duty", &eval, square, offset);
    }
    // The constant-field shipped models have a periodic form (the repeat tests above run them).
    for name in ["phasor-two-lobes-phase", "phasor-3d-harmonics"] {
        let case = testdata_cases()
            .into_iter()
            .find(|c| c.name.contains(name))
            .unwrap();
        assert!(
            periodic_cases().iter().any(|(n, _, _)| *n == case.name),
            "{name} has no periodic form among the test periods"
        );
    }
}
