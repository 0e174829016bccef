//! A phasor profile's varying fields as the device reads them per pixel (spectex_gpu's
//! `device_fields`, from records per column and per row), against their definition
//! (`Field::at` in f64, clamped to `[0, 1]`, rounded to f32), within
//! `tolerance::phasor::device_field_error`: linear ramps steep enough to cross `[0, 1]` in the
//! window and an image field, at the origin, at 10⁶ pixels and scaled, 2D and on a 3D plane.
//!
//! The probe model blends a square profile of duty 0 (always 0) with one of duty 1 (always 1,
//! `phase01` < 1) by the field: its output, at zero mean and unit amplitude, is the weight
//! itself, `(1 − s)·0 + s·1 = s` exactly in f32, on either evaluator.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_crosscheck::tolerance::phasor::device_field_error;
use spectex_gpu::GpuEvaluator;
use spectex_model::{Field, Model, PhasorNoise, PhasorOrientation, PhasorOutput, Profile, Window};

use crate::common::gpu_or_skip;

/// The probe: output = `weight` at every pixel.
fn probe(weight: Field, dimensions: u8) -> PhasorNoise {
    PhasorNoise {
        seed: 3,
        dimensions,
        bandwidth: Field::constant(0.03),
        frequency: Field::constant(0.05),
        orientation: PhasorOrientation::Isotropic,
        impulses_per_kernel: 4.0,
        profile: Profile::Blend {
            a: Box::new(Profile::Square {
                duty: Field::constant(0.0),
            }),
            b: Box::new(Profile::Square {
                duty: Field::constant(1.0),
            }),
            weight,
        },
        output: PhasorOutput::Profiled,
        mean: 0.0,
        amplitude: 1.0,
    }
}

#[test]
fn fields_read_on_the_device_are_their_definition_within_the_bound() {
    let Some(context) = gpu_or_skip("phasor fields on the device") else {
        return;
    };
    let grey: Vec<f32> = (0..35).map(|k| ((k * 17) % 35) as f32 / 34.0).collect();
    let near = [
        ("origin", [0.0, 0.0], 1.0),
        ("scaled", [-20.25, 11.5], 0.73),
    ];
    let far = [
        ("far", [1.0e6, 1.0e6 - 0.5], 1.0),
        ("far, scaled", [1.0e6 + 3.0e3, 1.0e6], 7.3),
    ];
    // Each field with windows where it lies inside (0, 1) (a clamped value would hide the
    // sum's error): a steep ramp near the origin, a gentle one whose terms are ~30 at 10⁶
    // pixels (a sum of the two terms in f32 would be off by ~1e-6 there), an image anywhere.
    let fields: [(&str, Field, Vec<_>); 3] = [
        (
            "linear",
            Field::Linear {
                value: 0.3,
                gradient: [3.1e-3, -2.3e-3, 1.0e-3],
            },
            near.to_vec(),
        ),
        (
            "linear far out",
            Field::Linear {
                value: -7.5,
                gradient: [3.1e-5, -2.3e-5, 1.0e-5],
            },
            far.to_vec(),
        ),
        (
            "image",
            Field::Image {
                width: 7,
                height: 5,
                grey,
                pixel_size: 9.5,
                min: 0.15,
                max: 0.95,
            },
            near.into_iter().chain(far).collect(),
        ),
    ];
    let mut worst = Vec::new();
    for (name, field, windows) in &fields {
        let bound = device_field_error(field);
        for dims in [2, 3] {
            let z = if dims == 3 { 17.25 } else { 0.0 };
            let model = Model::Phasor(probe(field.clone(), dims));
            let gpu = GpuEvaluator::new_at_z(&context, &model, z).unwrap();
            for &(place, offset, scale) in windows {
                let window = Window::new(48, 40).at(offset, scale);
                let got = gpu.render(&window).unwrap();
                let mut largest = 0.0f64;
                let mut varied = (f32::INFINITY, f32::NEG_INFINITY);
                let mut inside = 0;
                for j in 0..window.height {
                    for i in 0..window.width {
                        let want = field.at(window.x(i), window.y(j), z).clamp(0.0, 1.0) as f32;
                        let v = got[j * window.width + i];
                        let d = (f64::from(v) - f64::from(want)).abs();
                        assert!(
                            d <= bound,
                            "{name} {dims}D {place} ({i}, {j}): device {v}, definition {want}, \
                             |Δ| {d:e} over the bound {bound:e}"
                        );
                        largest = largest.max(d);
                        inside += usize::from(want > 0.0 && want < 1.0);
                        varied = (varied.0.min(want), varied.1.max(want));
                    }
                }
                // The window exercises the sum, not the clamp.
                assert_eq!(
                    inside,
                    window.width * window.height,
                    "{name} {dims}D {place}"
                );
                worst.push(format!(
                    "{name} {dims}D {place}: max |Δ| {largest:.2e} (bound {bound:.2e}), \
                     values {:.3}..{:.3}",
                    varied.0, varied.1
                ));
            }
        }
    }
    println!("{}", worst.join("\n"));
}
