//! Phasor noise on the device: tiles (each with its own box of host-drawn kernel cells) are
//! invisible, a 3D model's planes follow `z`, per-pixel profile parameters reach the right
//! pixels, and what the shader cannot express is a typed error. Agreement with the CPU within
//! derived bounds is the cross-check suite's (`spectex-crosscheck`, `phasor.rs`).

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::first_bit_difference;
use spectex_gpu::{GpuError, GpuEvaluator, GpuWindow};
use spectex_model::{Field, Model, PhasorNoise, PhasorOrientation, PhasorOutput, Profile};

fn model(dimensions: u8, profile: Profile, output: PhasorOutput) -> PhasorNoise {
    PhasorNoise {
        seed: 4,
        dimensions,
        bandwidth: Field::constant(0.03),
        frequency: Field::constant(0.07),
        orientation: PhasorOrientation::Coherent {
            spread: 2.4,
            bandwidth_ratio: 0.5,
        },
        impulses_per_kernel: 16.0,
        profile,
        output,
        mean: 0.0,
        amplitude: 1.0,
    }
}

#[test]
fn tiles_are_invisible() {
    let Some(context) = common::gpu_or_skip("phasor tiles_are_invisible") else {
        return;
    };
    let duty = Field::Linear {
        value: 0.5,
        gradient: [1e-5, -2e-5, 0.0],
    };
    let m = model(2, Profile::Square { duty }, PhasorOutput::Profiled);
    let mut gpu = GpuEvaluator::new(&context, &Model::Phasor(m)).unwrap();
    // Point-sampled (binary), then minified at scale 1.3 (the square's filtered series).
    for filter in [spectex_gpu::Filter::Off, spectex_gpu::Filter::Pixel] {
        let window = GpuWindow::new(53, 29)
            .at([1.0e7 + 0.3, -2.0e5], 1.3)
            .filtered(filter);
        gpu.set_max_tile(2048, 2048);
        let whole = gpu.render(&window).unwrap();
        if filter == spectex_gpu::Filter::Off {
            assert!(whole.iter().all(|&v| v == 0.0 || v == 1.0), "PWM is binary");
        } else {
            assert!(
                whole.iter().any(|&v| v != 0.0 && v != 1.0),
                "filtered PWM is smooth"
            );
        }
        for (tw, th) in [(8, 8), (53, 3), (7, 29)] {
            gpu.set_max_tile(tw, th);
            let tiled = gpu.render(&window).unwrap();
            let first = first_bit_difference(&whole, &tiled);
            assert_eq!(
                first, None,
                "{filter:?}, tiles {tw}×{th}: first differing index {first:?}"
            );
        }
        // One-pixel tiles (a dispatch each) on a 9×7 sub-window: over the whole window they
        // cost 20 s of CI.
        gpu.set_max_tile(1, 1);
        let tile = gpu.render(&window.tile(30, 20, 9, 7)).unwrap();
        for r in 0..7 {
            let row = &whole[(20 + r) * 53 + 30..(20 + r) * 53 + 39];
            assert_eq!(
                first_bit_difference(&tile[r * 9..(r + 1) * 9], row),
                None,
                "{filter:?}, one-pixel tiles, row {r}"
            );
        }
    }
}

/// The same 3D model on two planes 0.01 px apart is nearly the same image; 400 px apart it is
/// another one (the GPU receives z through the host's cell/offset split).
#[test]
fn three_d_planes_follow_z() {
    let Some(context) = common::gpu_or_skip("phasor three_d_planes_follow_z") else {
        return;
    };
    let m = Model::Phasor(model(3, Profile::Sine, PhasorOutput::Gabor));
    let window = GpuWindow::new(32, 32).at([5.0, 7.0], 1.0);
    let at = |z: f64| {
        GpuEvaluator::new_at_z(&context, &m, z)
            .unwrap()
            .render(&window)
            .unwrap()
    };
    let (a, b, far) = (at(20.0), at(20.01), at(420.0));
    let mean_diff = |u: &[f32], v: &[f32]| {
        u.iter()
            .zip(v)
            .map(|(x, y)| f64::from((x - y).abs()))
            .sum::<f64>()
            / u.len() as f64
    };
    let level = a.iter().map(|v| f64::from(v.abs())).sum::<f64>() / a.len() as f64;
    assert!(
        mean_diff(&a, &b) < 0.01 * level,
        "{} vs {level}",
        mean_diff(&a, &b)
    );
    assert!(mean_diff(&a, &far) > 0.5 * level);
}

/// A blend of sine (weight 0) and a constant-1 sampled profile (weight 1) driven by a ramp: each
/// pixel must read its own weight, so the value climbs from the sine to 1 across the window.
#[test]
fn per_pixel_parameters_reach_their_pixels() {
    let Some(context) = common::gpu_or_skip("phasor per_pixel_parameters") else {
        return;
    };
    // Weight 0 at x ≤ 0, 1 at x ≥ 100 (clamped), along x only.
    let weight = Field::Linear {
        value: 0.0,
        gradient: [0.01, 0.0, 0.0],
    };
    let profile = Profile::Blend {
        a: Box::new(Profile::Sine),
        b: Box::new(Profile::Samples {
            values: vec![1.0, 1.0],
        }),
        weight,
    };
    let m = Model::Phasor(model(2, profile, PhasorOutput::Profiled));
    let gpu = GpuEvaluator::new(&context, &m).unwrap();
    let row = gpu
        .render(&GpuWindow::new(30, 1).at([110.0, 3.0], 1.0))
        .unwrap();
    assert!(
        row.iter().all(|&v| v == 1.0),
        "weight 1 right of x = 100: {row:?}"
    );
    let left = gpu
        .render(&GpuWindow::new(30, 1).at([-60.0, 3.0], 1.0))
        .unwrap();
    assert!(left.iter().all(|&v| (-1.0..=1.0).contains(&v)));
    assert!(
        left.iter().any(|&v| v < 0.9),
        "weight 0 left of x = 0 is the sine"
    );
}

#[test]
fn nested_blends_and_bad_planes_are_typed_errors() {
    let Some(context) = common::gpu_or_skip("phasor typed errors") else {
        return;
    };
    let blend = |a: Profile| Profile::Blend {
        a: Box::new(a),
        b: Box::new(Profile::Sine),
        weight: Field::constant(0.5),
    };
    let nested = Model::Phasor(model(
        2,
        blend(blend(Profile::Sine)),
        PhasorOutput::Profiled,
    ));
    let e = GpuEvaluator::new(&context, &nested).unwrap_err();
    assert!(matches!(e, GpuError::Unsupported { .. }), "{e}");
    assert!(e.to_string().contains("nested blends"), "{e}");
    let flat = Model::Phasor(model(3, Profile::Sine, PhasorOutput::Profiled));
    let e = GpuEvaluator::new_at_z(&context, &flat, f64::NAN).unwrap_err();
    assert!(e.to_string().contains('z'), "{e}");
}
