//! LRP evaluation against the slow f64 reference of `spectex_testkit::reference`, precision far
//! away, exact support edges at any zoom, and the same bits on every SIMD level (tilings and
//! thread counts: the kit's invariance harness, over every testdata model).

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::disallowed_methods,
    reason = "the f64 reference uses libm on purpose"
)]

use spectex_cpu::{Evaluator, LrpEvaluator, Window};
use spectex_model::random::Prng;
use spectex_model::{LrpNoise, Model};
use spectex_testkit::fixtures::lrp_three_strata as model;
use spectex_testkit::reference;

/// Error bound of the f32 evaluation: per cosine term, the f32 rounding of an argument of at
/// most |f|·1.5Δ + 1 turns (relative 2⁻²³ · a few operations, times 2π), the polynomial cosine
/// (2e-7) and the f32 window (2e-6); times A_S, summed over the ≤ 9·J_S terms of each stratum.
fn tolerance(m: &LrpNoise) -> f64 {
    m.strata
        .iter()
        .map(|st| {
            let fmax = st
                .sub_strata
                .iter()
                .flatten()
                .map(|f| f64::from(f[0].hypot(f[1])))
                .fold(0.0, f64::max);
            let arg = fmax * 1.5 * f64::from(st.window_width) + 1.0;
            let per_term =
                2.0 * std::f64::consts::PI * arg * 4.0 * f64::from(f32::EPSILON) + 2e-7 + 2e-6;
            f64::from(st.amplitude) * 9.0 * st.sub_strata.len() as f64 * per_term
        })
        .sum()
}

#[test]
fn matches_the_definition_near_and_far() {
    for seed in [1, 2, 3] {
        let m = model(seed);
        let eval = LrpEvaluator::new(&m);
        let tol = tolerance(&m);
        let mut prng = Prng::new(seed);
        for base in [0.0, -1234.5, 1.0e7, -3.0e6] {
            for _ in 0..200 {
                let (x, y) = (
                    base + prng.next_f64() * 100.0,
                    base * 0.5 + prng.next_f64() * 100.0,
                );
                let (got, want) = (f64::from(eval.eval(x, y)), reference::lrp(&m, x, y));
                assert!(
                    (got - want).abs() <= tol,
                    "seed {seed} at ({x}, {y}): {got} vs {want}, tolerance {tol:e}"
                );
            }
        }
    }
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// A row evaluates each lattice point only over the pixels of its support's chord; a pixel just
/// inside the support's edge, at any zoom, must still get its (tiny) term. Each pixel of a row
/// straddling the edge of the first stratum's support (`1.5·Δ = 14.25` from the point at the
/// origin, along `y = 0`) is compared with the same position evaluated alone (a 1×1 window,
/// where every lattice point is tried on that pixel).
#[test]
fn support_edges_are_exact_at_any_zoom() {
    let eval = LrpEvaluator::new(&model(4));
    for scale in [1.0e-6, 1.0e-3, 0.37, 1.0, 41.0] {
        let width = 97;
        let edge = 14.25 - 48.5 * scale;
        // Point samples: the support's edges, not a minified render's gains (scale 41).
        let window = Window::new(width, 1)
            .at([edge, 0.0], scale)
            .filtered(spectex_cpu::Filter::Off);
        let mut row = vec![0.0; width];
        eval.eval_row(&window, 0, &mut row);
        for (i, v) in row.iter().enumerate() {
            let alone = eval.eval(window.x(i), 0.0);
            assert_eq!(
                v.to_bits(),
                alone.to_bits(),
                "scale {scale}, pixel {i} at x = {}",
                window.x(i)
            );
        }
    }
}

#[test]
fn same_bits_on_every_simd_level() {
    let m = model(7);
    let mut portable = LrpEvaluator::new(&m);
    portable.set_avx2(false);
    let mut wide = LrpEvaluator::new(&m);
    wide.set_avx2(true);
    let mut widest = LrpEvaluator::new(&m);
    let has_avx512 = widest.set_avx512(true);
    eprintln!(
        "AVX-512 path {}",
        if has_avx512 {
            "compared"
        } else {
            "absent on this CPU"
        }
    );
    let window = Window::new(131, 9).at([12.5, -7.0], 0.9);
    for row in 0..9 {
        let (mut a, mut b, mut c) = (vec![0.0; 131], vec![0.0; 131], vec![0.0; 131]);
        portable.eval_row(&window, row, &mut a);
        wide.eval_row(&window, row, &mut b);
        widest.eval_row(&window, row, &mut c);
        assert_eq!(bits(&a), bits(&b), "row {row}: AVX2 against portable");
        assert_eq!(bits(&a), bits(&c), "row {row}: widest against portable");
    }
}

/// The spatial statistics follow from the model: mean `m.mean`; variance `Σ_S π·J_S·A_S²·c`
/// with `c = ∫ r w² dr` (each cosine has variance A²/2; the lattice average of Σ w² is 2πc).
#[test]
fn mean_and_variance_follow_from_the_model() {
    let m = model(8);
    let eval = Evaluator::new(&Model::Lrp(m.clone())).unwrap();
    let values = eval
        // Point samples at 1.7 pixels apart: the model's own moments, unfiltered.
        .render(
            &Window::new(1024, 1024)
                .at([0.0, 0.0], 1.7)
                .filtered(spectex_cpu::Filter::Off),
        )
        .unwrap();
    let n = values.len() as f64;
    let mean = values.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    let var = values
        .iter()
        .map(|&v| (f64::from(v) - mean).powi(2))
        .sum::<f64>()
        / n;
    let c = spectex_model::window::window_radial_energy();
    let want: f64 = m
        .strata
        .iter()
        .map(|s| {
            std::f64::consts::PI * s.sub_strata.len() as f64 * f64::from(s.amplitude).powi(2) * c
        })
        .sum();
    // 1024² samples spanning ~75 lattice periods of the widest stratum per side: thousands of
    // independent lattice points, so a few percent.
    assert!((mean - 0.25).abs() < 0.02 * want.sqrt(), "mean {mean}");
    assert!((var / want - 1.0).abs() < 0.05, "variance {var} vs {want}");
}

#[test]
fn bad_windows_are_typed_errors() {
    let eval = Evaluator::new(&Model::Lrp(model(9))).unwrap();
    for (w, msg) in [
        (Window::new(0, 5), "width"),
        (Window::new(5, 5).at([f64::NAN, 0.0], 1.0), "offset x"),
        (Window::new(5, 5).at([0.0, 0.0], 0.0), "scale"),
        (Window::new(5, 5).at([0.0, 2.0e9], 1.0), "position"),
    ] {
        let e = eval.render(&w).unwrap_err().to_string();
        assert!(e.contains(msg), "{e}");
    }
    let mut bad = model(9);
    bad.strata[0].window_width = f32::NAN;
    assert!(Evaluator::new(&Model::Lrp(bad)).is_err());
}
