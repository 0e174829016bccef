//! Domain warping on the device (`common.wgsl`'s displacement convention): constant
//! displacements render the base's shifted window, a warp by noise is the host reference at the
//! displaced positions, warps nest, tiles stay invisible, and a window beyond the warp's reach
//! is a typed error. Agreement with the CPU within derived bounds is the cross-check suite's.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::{first_bit_difference, lrp_f32};
use spectex_gpu::{GpuError, GpuEvaluator, GpuWindow};
use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric, Worley,
};
use spectex_model::fixtures::{gabor_isotropic, lrp_four_strata, phasor_pwm};
use spectex_model::{
    LrpNoise, MAX_POSITION, MAX_WARP, Model, PhasorOrientation, PhasorOutput, Stratum, Warp,
    WaveletNoise,
};

/// An LRP noise that is exactly `mean` everywhere (amplitude 0).
fn constant(mean: f32) -> Model {
    Model::Lrp(LrpNoise {
        seed: 0,
        mean,
        strata: vec![Stratum {
            window_width: 8.0,
            amplitude: 0.0,
            sub_strata: vec![vec![[0.1, 0.0]]],
        }],
    })
}

fn warp(base: Model, x: Model, y: Model, strength: f32) -> Model {
    Model::Warp(Warp {
        base: Box::new(base),
        x: Box::new(x),
        y: Box::new(y),
        strength,
    })
}

fn bases() -> Vec<(&'static str, Model)> {
    let mut phasor = phasor_pwm(
        2,
        PhasorOrientation::TwoLobes {
            angle_a: 0.4,
            angle_b: 1.2,
        },
    );
    phasor.output = PhasorOutput::Gabor;
    vec![
        ("lrp", Model::Lrp(lrp_four_strata(6))),
        ("gabor", Model::Gabor(gabor_isotropic())),
        ("phasor", Model::Phasor(phasor)),
        (
            "classic perlin fbm",
            classic(Basis::Gradient, 2, Some((FractalKind::Fbm, 3))),
        ),
        ("classic simplex", classic(Basis::Simplex, 2, None)),
        ("texture colour", testdata("texture-synthetic-colour")),
        ("texture grey", testdata("texture-synthetic-grey")),
        (
            "classic value ridged 3d",
            classic(
                Basis::Value,
                3,
                Some((
                    FractalKind::Ridged {
                        offset: 1.0,
                        weight_gain: 2.0,
                    },
                    2,
                )),
            ),
        ),
        (
            "classic worley f2 - f1",
            classic(
                Basis::Worley(Worley {
                    metric: Metric::Euclidean,
                    coefficients: [-1.0, 1.0, 0.0, 0.0],
                    points: FeaturePoints::Fixed(2),
                }),
                2,
                None,
            ),
        ),
        (
            "wavelet 3d",
            Model::Wavelet(WaveletNoise {
                seed: 2,
                dimensions: 3,
                tile_size: 32,
                cell_size: 5.0,
                bands: vec![1.0, 0.5],
                amplitude: 0.4,
                mean: 0.5,
            }),
        ),
    ]
}

/// A model of `testdata/models/`.
fn testdata(name: &str) -> Model {
    let path = format!(
        "{}/../../testdata/models/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    spectex_model::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn classic(basis: Basis, dimensions: u32, fractal: Option<(FractalKind, u32)>) -> Model {
    Model::Classic(ClassicNoise {
        seed: 4,
        dimensions,
        cell_size: 16.0,
        basis,
        fractal: fractal.map(|(kind, octaves)| Fractal {
            kind,
            octaves,
            lacunarity: 2.0,
            gain: 0.5,
        }),
        amplitude: 0.5,
        mean: 0.5,
    })
}

fn max_difference(a: &[f32], b: &[f32]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (f64::from(*x) - f64::from(*y)).abs())
        .fold(0.0, f64::max)
}

/// The relocation in the shader rounds a position by a few f32 ulps of the cell's size (the
/// CPU's is exact in f64); the values move by the noise's slope times that: far below 1e-4 for
/// these models, whose values change by ~0.1 over a pixel.
const RELOCATION_BOUND: f64 = 1e-4;

#[test]
fn constant_displacements_shift_the_window() {
    let Some(context) = common::gpu_or_skip("warp constant_displacements_shift_the_window") else {
        return;
    };
    for (offset, scale) in [([0.0, 0.0], 1.0), ([1.0e7, 1.0e7], 0.5)] {
        let window = GpuWindow::new(32, 24).at(offset, scale);
        let shifted = window.at([offset[0] + 5.0, offset[1] - 3.0], scale);
        for (name, base) in bases() {
            let warped = warp(base.clone(), constant(2.5), constant(-1.5), 2.0);
            let got = GpuEvaluator::new(&context, &warped)
                .unwrap()
                .render(&window)
                .unwrap();
            let gpu = GpuEvaluator::new(&context, &base).unwrap();
            let want = gpu.render(&shifted).unwrap();
            let unshifted = gpu.render(&window).unwrap();
            let e = max_difference(&got, &want);
            assert!(e <= RELOCATION_BOUND, "{name} at {offset:?}: {e}");
            // The comparison can fail: the shift does change the values.
            assert!(max_difference(&got, &unshifted) > 1e-2, "{name}: no shift");
        }
    }
}

#[test]
fn nested_warps_add_their_displacements() {
    let Some(context) = common::gpu_or_skip("warp nested_warps_add_their_displacements") else {
        return;
    };
    let window = GpuWindow::new(24, 24).at([100.0, -50.0], 1.0);
    let base = Model::Lrp(lrp_four_strata(6));
    let inner = warp(base.clone(), constant(1.0), constant(0.5), 4.0);
    let outer = warp(inner, constant(-0.25), constant(3.0), 2.0);
    let got = GpuEvaluator::new(&context, &outer)
        .unwrap()
        .render(&window)
        .unwrap();
    let want = GpuEvaluator::new(&context, &base)
        .unwrap()
        .render(&window.at([103.5, -42.0], 1.0))
        .unwrap();
    let e = max_difference(&got, &want);
    assert!(e <= RELOCATION_BOUND, "{e}");
}

/// A warped LRP noise against the host's transcription of the CPU's f32 evaluation
/// (`common::lrp_f32`) at `p + D(x(p), y(p))`, with x and y rendered alone on the device.
#[test]
fn a_warp_by_noise_is_the_reference_at_displaced_positions() {
    let Some(context) =
        common::gpu_or_skip("warp a_warp_by_noise_is_the_reference_at_displaced_positions")
    else {
        return;
    };
    let base = lrp_four_strata(6);
    let (mut x, mut y) = (lrp_four_strata(3), lrp_four_strata(3));
    x.seed = 11;
    y.seed = 12;
    let model = Warp {
        base: Box::new(Model::Lrp(base.clone())),
        x: Box::new(Model::Lrp(x.clone())),
        y: Box::new(Model::Lrp(y.clone())),
        strength: 40.0,
    };
    for offset in [[0.0, 0.0], [1.0e7, -1.0e7]] {
        let window = GpuWindow::new(24, 16).at(offset, 0.75);
        let got = GpuEvaluator::new(&context, &Model::Warp(model.clone()))
            .unwrap()
            .render(&window)
            .unwrap();
        let vx = GpuEvaluator::new(&context, &Model::Lrp(x.clone()))
            .unwrap()
            .render(&window)
            .unwrap();
        let vy = GpuEvaluator::new(&context, &Model::Lrp(y.clone()))
            .unwrap()
            .render(&window)
            .unwrap();
        let mut moved = 0;
        for j in 0..window.height {
            for i in 0..window.width {
                let k = j * window.width + i;
                let d = [model.displacement(vx[k]), model.displacement(vy[k])];
                moved += usize::from(d[0].abs() > 1.0);
                let want = lrp_f32(
                    &base,
                    window.x(i) + f64::from(d[0]),
                    window.y(j) + f64::from(d[1]),
                );
                let e = (f64::from(got[k]) - f64::from(want)).abs();
                assert!(e <= RELOCATION_BOUND, "pixel ({i}, {j}) at {offset:?}: {e}");
            }
        }
        assert!(moved > 50, "the warp hardly moves anything: {moved}");
    }
}

#[test]
fn tiles_are_invisible() {
    let Some(context) = common::gpu_or_skip("warp tiles_are_invisible") else {
        return;
    };
    let window = GpuWindow::new(40, 28).at([-3.3, 1.0e7], 0.8);
    // Voronoi reads only its displacement's range, per tile (as a phasor with constant
    // fields does, among the bases).
    let voronoi = ("voronoi lloyd border", testdata("voronoi-border-lloyd"));
    for (name, base) in bases().into_iter().chain([voronoi]) {
        let model = warp(
            base,
            Model::Lrp(lrp_four_strata(3)),
            Model::Lrp(lrp_four_strata(4)),
            25.0,
        );
        let mut gpu = GpuEvaluator::new(&context, &model).unwrap();
        let whole = gpu.render(&window).unwrap();
        gpu.set_max_tile(16, 8);
        let tiled = gpu.render(&window).unwrap();
        assert_eq!(first_bit_difference(&whole, &tiled), None, "{name}");
    }
}

#[test]
fn a_window_beyond_the_warp_reach_is_a_typed_error() {
    let Some(context) = common::gpu_or_skip("warp a_window_beyond_the_warp_reach_is_a_typed_error")
    else {
        return;
    };
    let lrp = Model::Lrp(lrp_four_strata(3));
    let gpu = GpuEvaluator::new(&context, &warp(lrp.clone(), lrp.clone(), lrp, 4.0)).unwrap();
    let edge = MAX_POSITION - f64::from(MAX_WARP);
    match gpu.render(&GpuWindow::new(4, 4).at([edge, 0.0], 1.0)) {
        Err(GpuError::Window { parameter, .. }) => assert_eq!(parameter, "window position"),
        other => panic!("{:?}", other.err()),
    }
}
