//! Domain warping against identities: strength 0 is the base bit for bit; constant displacement
//! models shift the base's window exactly; a warp is its definition pixel by pixel (the base
//! evaluated alone at `p + D(x(p))`); tiles and thread counts give the same bits; bad models and
//! windows are typed errors.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_cpu::{CpuError, Evaluator, Window};
use spectex_model::classic::{Basis, ClassicNoise, Fractal, FractalKind};
use spectex_model::fixtures::{constant, gabor_isotropic, lrp_four_strata, phasor_pwm};
use spectex_model::{
    ColourBasis, MAX_POSITION, MAX_WARP, Model, ModelError, PhasorOrientation, Stratum,
    TextureChannel, TextureModel, Warp,
};

fn fbm(seed: u32) -> Model {
    Model::Classic(ClassicNoise {
        seed,
        dimensions: 2,
        cell_size: 24.0,
        basis: Basis::Gradient,
        fractal: Some(Fractal {
            kind: FractalKind::Fbm,
            octaves: 3,
            lacunarity: 2.0,
            gain: 0.5,
        }),
        amplitude: 1.0,
        mean: 0.0,
    })
}

fn colour_texture() -> Model {
    let channel = |seed| TextureChannel {
        seed,
        mean: 0.1,
        strata: vec![Stratum {
            window_width: 12.0,
            amplitude: 0.05,
            sub_strata: vec![vec![[0.08, 0.02], [-0.03, 0.09]]; 3],
        }],
        structure: None,
    };
    Model::Texture(TextureModel {
        seed: 4,
        period: 16,
        channels: vec![channel(1), channel(2), channel(3)],
        colour: Some(ColourBasis {
            mean: [0.5; 3],
            basis: [[1.0, 0.2, 0.0], [0.0, 1.0, 0.3], [0.1, 0.0, 1.0]],
        }),
        turbulence: None,
        random_placement: true,
    })
}

/// One base of every kind.
fn bases() -> Vec<(&'static str, Model)> {
    vec![
        ("lrp", Model::Lrp(lrp_four_strata(8))),
        ("gabor", Model::Gabor(gabor_isotropic())),
        (
            "phasor",
            Model::Phasor(phasor_pwm(
                2,
                PhasorOrientation::TwoLobes {
                    angle_a: 0.4,
                    angle_b: 1.2,
                },
            )),
        ),
        ("classic", fbm(9)),
        ("texture", colour_texture()),
    ]
}

fn warp(base: Model, x: Model, y: Model, strength: f32) -> Model {
    Model::Warp(Warp {
        base: Box::new(base),
        x: Box::new(x),
        y: Box::new(y),
        strength,
    })
}

fn render(model: &Model, window: &Window) -> Vec<f32> {
    Evaluator::new(model).unwrap().render(window).unwrap()
}

fn assert_bits(a: &[f32], b: &[f32], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    if let Some(i) = a
        .iter()
        .zip(b)
        .position(|(x, y)| x.to_bits() != y.to_bits())
    {
        panic!("{what}: value {i} differs: {} vs {}", a[i], b[i]);
    }
}

#[test]
fn strength_zero_is_the_base_bit_for_bit() {
    let window = Window::new(37, 21).at([1.0e7 + 0.3, -2.5e6], 0.71);
    for (name, base) in bases() {
        let warped = warp(base.clone(), fbm(1), fbm(2), 0.0);
        assert_bits(
            &render(&warped, &window),
            &render(&base, &window),
            &format!("{name} at strength 0"),
        );
    }
}

/// Constant displacement models `x = 2.5`, `y = −1.5` at strength 2 shift the window by
/// `(5, −3)`; offsets, scale and shift are chosen so that both position sums are exact in f64.
#[test]
fn constant_displacement_is_a_shifted_window() {
    for (offset, scale) in [
        ([0.0, 0.0], 1.0),
        ([1.0e7, 1.0e7], 0.5),
        ([-64.0, 32.0], 0.25),
    ] {
        let window = Window::new(33, 17).at(offset, scale);
        let shifted = Window::new(33, 17).at([offset[0] + 5.0, offset[1] - 3.0], scale);
        for (name, base) in bases() {
            let warped = warp(base.clone(), constant(2.5), constant(-1.5), 2.0);
            assert_bits(
                &render(&warped, &window),
                &render(&base, &shifted),
                &format!("{name} at {offset:?}"),
            );
        }
    }
}

/// A warp of a warp adds the displacements (here exactly: small dyadic numbers).
#[test]
fn nested_constant_warps_add_their_shifts() {
    let window = Window::new(24, 24).at([100.0, -50.0], 1.0);
    let base = Model::Lrp(lrp_four_strata(6));
    let inner = warp(base.clone(), constant(1.0), constant(0.5), 4.0);
    let outer = warp(inner, constant(-0.25), constant(3.0), 2.0);
    let shifted = window.at([100.0 + 4.0 - 0.5, -50.0 + 2.0 + 6.0], 1.0);
    assert_bits(&render(&outer, &window), &render(&base, &shifted), "nested");
}

/// The definition, pixel by pixel: each sub-model evaluated alone, the displacement clamped,
/// the base at the f64 sum.
#[test]
fn a_warp_is_its_definition() {
    let window = Window::new(29, 13).at([1.0e7 - 3.3, 4.0e6], 0.9);
    for (name, base) in bases() {
        let strength = 20.0;
        let model = Warp {
            base: Box::new(base.clone()),
            x: Box::new(fbm(5)),
            y: Box::new(Model::Lrp(lrp_four_strata(4))),
            strength,
        };
        let got = render(&Model::Warp(model.clone()), &window);
        let (b, x, y) = (
            Evaluator::new(&base).unwrap(),
            Evaluator::new(&model.x).unwrap(),
            Evaluator::new(&model.y).unwrap(),
        );
        let nc = b.output_channels();
        let mut moved = 0;
        for j in 0..window.height {
            for i in 0..window.width {
                let p = [window.x(i), window.y(j)];
                let (mut vx, mut vy) = ([0.0f32], [0.0f32]);
                x.eval_point(p, &mut vx);
                y.eval_point(p, &mut vy);
                let d = [model.displacement(vx[0]), model.displacement(vy[0])];
                moved += usize::from(d[0].abs() > 1.0);
                let mut want = vec![0.0f32; nc];
                b.eval_point([p[0] + f64::from(d[0]), p[1] + f64::from(d[1])], &mut want);
                let k = (j * window.width + i) * nc;
                assert_bits(&got[k..k + nc], &want, &format!("{name} pixel ({i}, {j})"));
            }
        }
        assert!(
            moved > 50,
            "{name}: the warp hardly moves anything ({moved} pixels)"
        );
    }
}

#[test]
fn displacements_are_clamped_to_max_warp() {
    let window = Window::new(8, 4).at([3.0, 5.0], 1.0);
    let base = Model::Lrp(lrp_four_strata(4));
    let warped = warp(base.clone(), constant(1e9), constant(-1e9), 1000.0);
    let max = f64::from(MAX_WARP);
    let shifted = window.at([3.0 + max, 5.0 - max], 1.0);
    assert_bits(
        &render(&warped, &window),
        &render(&base, &shifted),
        "clamped",
    );
}

#[test]
fn tiles_and_threads_give_the_same_bits() {
    let window = Window::new(45, 38).at([-1.0e7 + 0.25, 1.0e7 - 0.6], 0.83);
    for (name, base) in bases() {
        let model = warp(base, fbm(7), fbm(8), 12.0);
        let eval = Evaluator::new(&model).unwrap();
        let nc = eval.output_channels();
        let whole = eval.render(&window).unwrap();
        for (x, y, w, h) in [(0, 0, 13, 5), (13, 5, 32, 33), (3, 30, 1, 7), (44, 0, 1, 1)] {
            let tile = eval.render(&window.tile(x, y, w, h)).unwrap();
            for r in 0..h {
                let start = ((y + r) * window.width + x) * nc;
                assert_bits(
                    &tile[r * w * nc..(r + 1) * w * nc],
                    &whole[start..start + w * nc],
                    &format!("{name}: tile ({x}, {y}) row {r}"),
                );
            }
        }
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let again = pool.install(|| eval.render(&window).unwrap());
            assert_bits(&again, &whole, &format!("{name}: {threads} threads"));
        }
    }
}

#[test]
fn bad_models_and_windows_are_typed_errors() {
    let base = Model::Lrp(lrp_four_strata(4));
    let nan = warp(base.clone(), fbm(1), fbm(2), f32::NAN);
    match Evaluator::new(&nan) {
        Err(CpuError::Model(ModelError::OutOfRange { field, .. })) => {
            assert_eq!(field, "warp.strength");
        }
        other => panic!("{:?}", other.err()),
    }
    let colour_y = warp(base.clone(), fbm(1), colour_texture(), 1.0);
    assert!(matches!(
        Evaluator::new(&colour_y),
        Err(CpuError::Model(ModelError::Length { .. }))
    ));
    let eval = Evaluator::new(&warp(base, fbm(1), fbm(2), 1.0)).unwrap();
    let edge = MAX_POSITION - f64::from(MAX_WARP);
    match eval.render(&Window::new(4, 4).at([0.0, edge], 1.0)) {
        Err(CpuError::Window { parameter, .. }) => assert_eq!(parameter, "window position"),
        other => panic!("{:?}", other.err()),
    }
    assert!(
        eval.render(&Window::new(4, 4).at([0.0, edge - 4.0], 1.0))
            .is_ok()
    );
}
