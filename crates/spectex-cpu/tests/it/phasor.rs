//! Phasor noise against a slow f64 reference of Eqs. (8)–(10) built from the randomness
//! contract, precision far away, profiles consistent with the phase, 3D slices continuous in z
//! (tilings and thread counts: the kit's invariance harness, over every testdata model).

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]
#![allow(
    clippy::disallowed_methods,
    reason = "the f64 reference uses libm on purpose"
)]

use spectex_cpu::{Evaluator, PhasorEvaluator, Window};
use spectex_model::random::{Prng, cell_hash};
use spectex_model::{Field, Model, PhasorNoise, PhasorOrientation, PhasorOutput, Profile};

fn model(orientation: PhasorOrientation, output: PhasorOutput) -> PhasorNoise {
    PhasorNoise {
        seed: 11,
        dimensions: 2,
        bandwidth: Field::constant(0.04),
        frequency: Field::constant(0.07),
        orientation,
        impulses_per_kernel: 20.0,
        profile: Profile::Sine,
        output,
        mean: 0.0,
        amplitude: 1.0,
    }
}

/// `(re, im)` of the complex Gabor noise at `(x, y)` from the definition, in f64: every impulse
/// of the 3×3 cells (drawn as the contract says) within the kernel radius, `a = exp(−π b²|d|²)`,
/// phase `2π(F u·d + ψ)` with `u` from the angle in f64.
fn reference(m: &PhasorNoise, x: f64, y: f64) -> (f64, f64) {
    let r = m.kernel_radius();
    let lambda = m.impulses_per_cell();
    let threshold = (-lambda).exp() as f32;
    let cap = (4.0 * lambda + 32.0).floor() as u32;
    let (b_min, b_max) = m.bandwidth_range();
    let (ci, cj) = ((x / r).floor() as i32, (y / r).floor() as i32);
    let (mut re, mut im) = (0.0, 0.0);
    for j in cj - 1..=cj + 1 {
        for i in ci - 1..=ci + 1 {
            let mut prng = Prng::new(cell_hash(i, j, 0, m.seed));
            let mut p = 1.0f32;
            let mut n = 0;
            while n < cap {
                p *= prng.next_f32();
                if p < threshold {
                    break;
                }
                n += 1;
            }
            for _ in 0..n {
                let ox = f64::from(prng.next_f32());
                let oy = f64::from(prng.next_f32());
                let (px, py) = ((f64::from(i) + ox) * r, (f64::from(j) + oy) * r);
                // A graded bandwidth: the kernel's own b, and thinning to keep the density of
                // impulses per footprint.
                let b = m.bandwidth.at(px, py, 0.0).clamp(b_min, b_max);
                if b_max > b_min && f64::from(prng.next_f32()) >= (b / b_max).powi(2) {
                    continue;
                }
                let angle = match &m.orientation {
                    PhasorOrientation::Aligned { angle } => angle.at(0.0, 0.0, 0.0),
                    PhasorOrientation::Isotropic => {
                        f64::from(prng.next_f32()) * std::f64::consts::TAU
                    }
                    other => panic!("reference does not cover {other:?}"),
                };
                let psi = f64::from(prng.next_f32());
                let (dx, dy) = (x - px, y - py);
                let d2 = dx * dx + dy * dy;
                // Truncated where the kernel falls below 5% of its peak: radius r·b_min/b.
                if d2 >= (r * b_min / b).powi(2) {
                    continue;
                }
                let a = (-std::f64::consts::PI * b * b * d2).exp();
                let f = m.frequency.at(0.0, 0.0, 0.0);
                let phase =
                    std::f64::consts::TAU * (f * (angle.cos() * dx + angle.sin() * dy) + psi);
                re += a * phase.cos();
                im += a * phase.sin();
            }
        }
    }
    (re, im)
}

/// f32 evaluation error: per impulse, the kernel (exp_poly, relative 1e-6), the cosine and sine
/// (2e-7 each) and the phase rounding (`F·r·|d|` ≤ 2 turns in cell units, a few ulps: 1e-6 turns,
/// times 2π); about `9λ·π/9 ≈ 6.4` impulses inside the radius on average, at most a few dozen:
/// 40 impulses × 1e-5 = 4e-4.
const TOLERANCE: f64 = 4e-4;

#[test]
fn matches_the_definition_near_and_far() {
    for orientation in [
        PhasorOrientation::Aligned {
            angle: Field::constant(0.7),
        },
        PhasorOrientation::Isotropic,
    ] {
        for graded in [false, true] {
            check_against_the_definition(orientation.clone(), graded);
        }
    }
}

/// `graded`: the bandwidth varies across a 4×4 image field from 0.025 to 0.05 (kernels of two
/// sizes, thinned to keep the density per footprint).
fn check_against_the_definition(orientation: PhasorOrientation, graded: bool) {
    let with = |output| {
        let mut m = model(orientation.clone(), output);
        if graded {
            m.bandwidth = Field::Image {
                width: 4,
                height: 4,
                grey: (0..16).map(|k| (k * 7 % 16) as f32 / 15.0).collect(),
                pixel_size: 60.0,
                min: 0.025,
                max: 0.05,
            };
            m.impulses_per_kernel = 8.0;
        }
        m
    };
    let gabor = with(PhasorOutput::Gabor);
    let intensity = with(PhasorOutput::Intensity);
    let phase = with(PhasorOutput::Phase);
    let (g, i, p) = (
        PhasorEvaluator::new(&gabor, 0.0),
        PhasorEvaluator::new(&intensity, 0.0),
        PhasorEvaluator::new(&phase, 0.0),
    );
    let mut prng = Prng::new(5);
    for base in [0.0, -777.25, 3.0e6, -1.0e7] {
        for _ in 0..150 {
            let (x, y) = (
                base + prng.next_f64() * 300.0,
                -base + prng.next_f64() * 300.0,
            );
            let (re, im) = reference(&gabor, x, y);
            let got_im = f64::from(g.eval(x, y));
            assert!(
                (got_im - im).abs() < TOLERANCE,
                "Im at ({x}, {y}): {got_im} vs {im}"
            );
            let got_i = f64::from(i.eval(x, y));
            let want_i = re.hypot(im);
            assert!(
                (got_i - want_i).abs() < TOLERANCE,
                "I at ({x}, {y}): {got_i} vs {want_i}"
            );
            // The phase is compared on the circle, where the intensity is not tiny (near a
            // singularity the angle of a small vector is ill-conditioned).
            if want_i > 0.05 {
                let want_p = im.atan2(re) / std::f64::consts::TAU;
                let mut e = (f64::from(p.eval(x, y)) - want_p).rem_euclid(1.0);
                e = e.min(1.0 - e);
                assert!(
                    e < TOLERANCE / want_i,
                    "phase at ({x}, {y}): error {e} turns"
                );
            }
        }
    }
}

/// The profiles read the same phase: the square profile is 1 exactly where the phase (in
/// `[0, 1)` turns) is below the duty cycle; the sine profile is `sin(2π·phase)`; triangle and
/// sawtooth are the stated functions of the phase.
#[test]
fn profiles_are_functions_of_the_phase() {
    let base = model(
        PhasorOrientation::Aligned {
            angle: Field::constant(0.3),
        },
        PhasorOutput::Phase,
    );
    let window = Window::new(64, 64).at([100.0, 50.0], 1.0);
    let render = |profile: Profile, output: PhasorOutput| {
        let mut m = base.clone();
        m.profile = profile;
        m.output = output;
        Evaluator::new(&Model::Phasor(m))
            .unwrap()
            .render(&window)
            .unwrap()
    };
    let phase = render(Profile::Sine, PhasorOutput::Phase);
    let duty = 0.3;
    let square = render(
        Profile::Square {
            duty: Field::constant(duty),
        },
        PhasorOutput::Profiled,
    );
    let sine = render(Profile::Sine, PhasorOutput::Profiled);
    let tri = render(Profile::Triangle, PhasorOutput::Profiled);
    let saw = render(Profile::Sawtooth, PhasorOutput::Profiled);
    for k in 0..phase.len() {
        let t = f64::from(phase[k]).rem_euclid(1.0);
        assert_eq!(
            square[k],
            if t < f64::from(duty) { 1.0 } else { 0.0 },
            "pixel {k}"
        );
        let s = (std::f64::consts::TAU * t).sin();
        assert!((f64::from(sine[k]) - s).abs() < 1e-5, "sine at {k}");
        let u = (t + 0.25).rem_euclid(1.0);
        assert!((f64::from(tri[k]) - (1.0 - 4.0 * (u - 0.5).abs())).abs() < 1e-5);
        assert!((f64::from(saw[k]) - (2.0 * t - 1.0)).abs() < 1e-5);
    }
}

/// A 3D model's slices: continuous in z (neighbouring planes differ by the kernel's smoothness)
/// and not constant in z (the planes far apart are unrelated).
#[test]
fn three_d_slices_are_continuous_in_z() {
    let mut m = model(PhasorOrientation::Isotropic, PhasorOutput::Gabor);
    m.dimensions = 3;
    let window = Window::new(48, 48).at([0.0, 0.0], 1.0);
    let at = |z: f64| {
        Evaluator::new_at_z(&Model::Phasor(m.clone()), z)
            .unwrap()
            .render(&window)
            .unwrap()
    };
    let (a, b, far) = (at(10.0), at(10.01), at(500.0));
    let mean_diff = |u: &[f32], v: &[f32]| {
        u.iter()
            .zip(v)
            .map(|(x, y)| f64::from((x - y).abs()))
            .sum::<f64>()
            / u.len() as f64
    };
    let level = a.iter().map(|v| f64::from(v.abs())).sum::<f64>() / a.len() as f64;
    // d/dz of a sum of kernels of frequency F is at most 2πF per unit of kernel weight, so 0.01
    // px moves a pixel by under 2π·0.07·0.01 ≈ 0.0044 of its kernels' total weight; kernels
    // entering or leaving the truncation sphere jump by ≤ 0.05 but only at a few pixels. On
    // average the planes differ by well under 1% of the noise's level.
    let near = mean_diff(&a, &b);
    assert!(
        near < 0.01 * level,
        "planes 0.01 apart differ by {near} (level {level})"
    );
    let apart = mean_diff(&a, &far);
    assert!(
        apart > 0.5 * level,
        "planes 490 apart differ by only {apart}"
    );
}
