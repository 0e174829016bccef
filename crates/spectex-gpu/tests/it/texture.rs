//! Texture by example on the device against a host transcription of the definition: the
//! per-pixel functions of `spectex_model::texture` (placement, structure, colour) evaluated on
//! the host, with each channel's strata and each turbulence stratum by the CPU's f32 LRP
//! arithmetic (`common::lrp_f32`), in the CPU evaluator's order. Grey with several blocks,
//! strata, turbulence and placement; one block; colour; far windows and fractional scales;
//! tiling; typed errors.
//!
//! Run with `--nocapture` to see the measured errors.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::{first_bit_difference, lrp_f32};
use spectex_gpu::{GpuError, GpuEvaluator, GpuWindow};
use spectex_model::grid::locate_cell;
use spectex_model::random::{Prng, cell_hash};
use spectex_model::{
    ColourBasis, FixedCosine, LrpNoise, Model, Stratum, Structure, TextureChannel, TextureModel,
    Turbulence,
};

/// A small random stratum (period `delta`, `j` cosines drawn from tables of 4 frequencies).
fn stratum(prng: &mut Prng, delta: f32, amplitude: f32, j: usize) -> Stratum {
    Stratum {
        window_width: delta,
        amplitude,
        sub_strata: (0..j)
            .map(|_| {
                (0..4)
                    .map(|_| [prng.next_f32() - 0.5, prng.next_f32() * 0.5])
                    .collect()
            })
            .collect(),
    }
}

/// A structure of `blocks²` blocks of 1 to `most` cosines with frequencies over the whole
/// allowed range `(−N/2, N/2]`.
fn structure(prng: &mut Prng, period: u32, blocks: u32, most: u32) -> Structure {
    let n = 2 * period / blocks;
    let k = |prng: &mut Prng| (prng.next_u32() % n) as i32 - (n / 2) as i32 + 1;
    Structure {
        blocks,
        cosines: (0..blocks * blocks)
            .map(|_| {
                let count = 1 + prng.next_u32() % most;
                (0..count)
                    .map(|_| FixedCosine {
                        frequency: [k(prng), k(prng)],
                        amplitude: 0.02 + 0.1 * prng.next_f32(),
                        phase: prng.next_f32(),
                    })
                    .collect()
            })
            .collect(),
    }
}

/// A grey texture: `blocks` per side, strata, turbulence and placement as asked.
fn grey(seed: u32, blocks: u32, turbulence: bool, placement: bool) -> TextureModel {
    let mut prng = Prng::new(cell_hash(0, 0, 91, seed));
    let period = 32;
    TextureModel {
        seed,
        period,
        channels: vec![TextureChannel {
            seed: seed + 1,
            mean: 0.5,
            strata: vec![
                stratum(&mut prng, 6.5, 0.08, 3),
                stratum(&mut prng, 14.0, 0.03, 2),
            ],
            structure: Some(structure(&mut prng, period, blocks, 5)),
        }],
        colour: None,
        turbulence: turbulence.then(|| Turbulence {
            sigma: 3.0,
            seeds: [seed + 10, seed + 20],
            strata: vec![
                stratum(&mut prng, 9.0, 0.3, 2),
                stratum(&mut prng, 20.0, 0.2, 2),
            ],
            centre: 0.4,
        }),
        random_placement: placement,
    }
}

/// A colour texture: three channels (structures of 4 and 1 blocks and none; the last channel
/// without strata) and a basis.
fn colour(seed: u32) -> TextureModel {
    let mut prng = Prng::new(cell_hash(0, 0, 92, seed));
    let period = 16;
    let channel = |prng: &mut Prng, c: u32, strata: bool, blocks: Option<u32>| TextureChannel {
        seed: seed + c,
        mean: 0.1 * c as f32,
        strata: if strata {
            vec![stratum(prng, 5.0, 0.05, 2)]
        } else {
            vec![]
        },
        structure: blocks.map(|b| structure(prng, period, b, 4)),
    };
    TextureModel {
        seed,
        period,
        channels: vec![
            channel(&mut prng, 0, true, Some(4)),
            channel(&mut prng, 1, true, Some(1)),
            channel(&mut prng, 2, false, None),
        ],
        colour: Some(ColourBasis {
            mean: [0.45, 0.4, 0.3],
            basis: [[0.58, 0.7, -0.4], [0.57, -0.1, 0.8], [0.58, -0.7, -0.4]],
        }),
        turbulence: Some(Turbulence {
            sigma: 1.5,
            seeds: [seed + 5, seed + 6],
            strata: vec![stratum(&mut prng, 7.0, 0.4, 3)],
            centre: 0.3,
        }),
        random_placement: true,
    }
}

/// The definition on the host, in the CPU evaluator's order (crates/spectex-cpu/src/texture.rs).
fn transcription(m: &TextureModel, window: &GpuWindow) -> Vec<f32> {
    let nc = m.output_channels();
    let side = m.placement_cell();
    let mut out = Vec::with_capacity(window.width * window.height * nc);
    for j in 0..window.height {
        let y = window.y(j);
        let (cy, sy) = locate_cell(y, side).unwrap_or((0, 0.0));
        for i in 0..window.width {
            let x = window.x(i);
            let (cx, sx) = locate_cell(x, side).unwrap_or((0, 0.0));
            let mut d = [0.0f32; 2];
            if let Some(t) = &m.turbulence {
                for (axis, d) in d.iter_mut().enumerate() {
                    let mut sum = 0.0f32;
                    for (s, st) in t.strata.iter().enumerate() {
                        let noise = LrpNoise {
                            seed: t.seed(axis, s),
                            mean: 0.0,
                            strata: vec![st.clone()],
                        };
                        sum += lrp_f32(&noise, x, y).abs();
                    }
                    *d = t.displacement(sum);
                }
            }
            let taps = m.placement(cx, sx, cy, sy, d);
            let mut v = [0.0f32; 3];
            for (c, ch) in m.channels.iter().enumerate() {
                let strata = if ch.strata.is_empty() {
                    ch.mean
                } else {
                    lrp_f32(
                        &LrpNoise {
                            seed: ch.seed,
                            mean: ch.mean,
                            strata: ch.strata.clone(),
                        },
                        x,
                        y,
                    )
                };
                v[c] = strata + m.structure_at(c, &taps);
            }
            for c in 0..nc {
                out.push(m.colour_component(c, &v[..nc]));
            }
        }
    }
    out
}

/// Single-precision unit roundoff.
const EPS: f64 = f32::EPSILON as f64 / 2.0;

/// A bound on `|gpu − transcription|` per output component (the cross-check's
/// `tolerance::texture` derives the same terms with named constants):
/// - strata: each LRP term's phase (4 roundings of `f_max·2.13Δ + 1` turns), cosine (1e-6) and
///   window (1.5e-6) errors, on each side, 9 lattice points × J per stratum, times A;
/// - structure, per channel with `S` = the largest block's `Σ A` and `K` = its `Σ A(|k|₁/2 + 1)`:
///   the phase `(k·u)/N + φ` (4 roundings of `|k|₁/2 + 1` turns) and `cos_turns` per cosine, on
///   each side, blended by weights summing to 1, then up to 4 taps with `Σ|ω| ≤ 2`, plus 1e-5·S
///   for every weight's rounding (`1/√Σω²` and the products, a few ulps each, 12 weights);
/// - turbulence: the displacement's error (σ times the strata bound) times the structure's
///   slope, `2π·max Σ A|k|₁/N + 2π·S/Δ_R`, on two axes, with `Σ|ω| ≤ 2`;
/// - summation: 64 roundings of the magnitude, and the colour basis' row sums.
fn tolerance(m: &TextureModel) -> Vec<f64> {
    let tau = std::f64::consts::TAU;
    let lrp = |strata: &[Stratum]| -> (f64, f64) {
        let (mut bound, mut magnitude) = (0.0, 0.0);
        for st in strata {
            let fmax = st
                .sub_strata
                .iter()
                .flatten()
                .map(|f| f64::from(f[0].hypot(f[1])))
                .fold(0.0, f64::max);
            let turns = fmax * 2.13 * f64::from(st.window_width) + 1.0;
            let per_term = 2.0 * (tau * 4.0 * EPS * turns + 1e-6 + 1.5e-6);
            let terms = 9.0 * st.sub_strata.len() as f64;
            bound += f64::from(st.amplitude) * terms * per_term;
            magnitude += f64::from(st.amplitude) * terms;
        }
        (bound + 64.0 * EPS * magnitude, magnitude)
    };
    let displacement = m.turbulence.as_ref().map_or(0.0, |t| {
        f64::from(t.sigma)
            * t.strata
                .iter()
                .map(|s| lrp(std::slice::from_ref(s)).0)
                .sum::<f64>()
    });
    let channels: Vec<(f64, f64)> = m
        .channels
        .iter()
        .map(|ch| {
            let (strata, mut magnitude) = lrp(&ch.strata);
            magnitude += f64::from(ch.mean).abs();
            let Some(s) = &ch.structure else {
                return (strata + 64.0 * EPS * magnitude, magnitude);
            };
            let n = f64::from(2 * m.period / s.blocks);
            let delta = f64::from(m.period / s.blocks);
            let (mut big_s, mut big_k, mut slope) = (0.0f64, 0.0f64, 0.0f64);
            for block in &s.cosines {
                let a: f64 = block.iter().map(|c| f64::from(c.amplitude)).sum();
                let k1 = |c: &FixedCosine| f64::from(c.frequency[0].abs() + c.frequency[1].abs());
                let k: f64 = block
                    .iter()
                    .map(|c| f64::from(c.amplitude) * (k1(c) / 2.0 + 1.0))
                    .sum();
                let g: f64 = block.iter().map(|c| f64::from(c.amplitude) * k1(c)).sum();
                big_s = big_s.max(a);
                big_k = big_k.max(k);
                slope = slope.max(tau * g / n + tau * a / delta);
            }
            let per_side = tau * 4.0 * EPS * big_k + 1e-6 * big_s;
            let structure = 2.0 * 2.0 * per_side + 1e-5 * big_s;
            magnitude += 2.0 * big_s;
            (
                strata + structure + 2.0 * 2.0 * slope * displacement + 64.0 * EPS * magnitude,
                magnitude,
            )
        })
        .collect();
    match &m.colour {
        None => vec![channels[0].0],
        Some(c) => (0..3)
            .map(|i| {
                let row = c.basis[i];
                let (mut bound, mut magnitude) = (0.0, f64::from(c.mean[i]).abs());
                for (k, &(e, v)) in channels.iter().enumerate() {
                    bound += f64::from(row[k]).abs() * e;
                    magnitude += f64::from(row[k]).abs() * v;
                }
                bound + 64.0 * EPS * magnitude
            })
            .collect(),
    }
}

/// Renders `window` and compares every value with the transcription; returns the largest
/// absolute error.
fn check(case: &str, gpu: &GpuEvaluator, m: &TextureModel, window: &GpuWindow) -> f64 {
    let got = gpu.render(window).unwrap();
    let want = transcription(m, window);
    let nc = m.output_channels();
    assert_eq!(gpu.output_channels(), nc, "{case}: output channels");
    assert_eq!(got.len(), window.width * window.height * nc, "{case}");
    let tol = tolerance(m);
    let mut worst = vec![0.0f64; nc];
    let mut same = 0;
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        let (pixel, c) = (k / nc, k % nc);
        let (i, j) = (pixel % window.width, pixel / window.width);
        let err = (f64::from(*g) - f64::from(*w)).abs();
        assert!(
            err <= tol[c],
            "{case}, seed {}, {}×{} window: pixel ({i}, {j}) at ({}, {}), channel {c}: {g} on {} \
             vs {w} (error {err:e} > tolerance {:e})",
            m.seed,
            window.width,
            window.height,
            window.x(i),
            window.y(j),
            gpu.adapter_name(),
            tol[c]
        );
        worst[c] = worst[c].max(err);
        same += usize::from(g.to_bits() == w.to_bits());
    }
    let report: Vec<String> = worst
        .iter()
        .zip(&tol)
        .map(|(e, t)| format!("{e:.2e} (tolerance {t:.2e})"))
        .collect();
    eprintln!(
        "{case}: {} values, max error per channel {}, {same}/{} bit-identical to the host's f32 \
         arithmetic",
        got.len(),
        report.join(", "),
        got.len()
    );
    worst.iter().copied().fold(0.0, f64::max)
}

/// The three windows: origin, far, fractional scale.
fn windows() -> [(&'static str, GpuWindow); 3] {
    [
        ("origin", GpuWindow::new(40, 32)),
        (
            "far (1e7, 1e7)",
            GpuWindow::new(40, 32).at([1.0e7, 1.0e7], 1.0),
        ),
        (
            "fractional scale 0.37",
            GpuWindow::new(40, 32).at([-1234.5, 77.25], 0.37),
        ),
    ]
}

#[test]
fn grey_with_blocks_strata_turbulence_and_placement() {
    let Some(context) = common::gpu_or_skip("texture grey") else {
        return;
    };
    for (blocks, turbulence, placement) in [(4, true, true), (2, false, true), (8, true, false)] {
        let m = grey(3 + blocks, blocks, turbulence, placement);
        let gpu = GpuEvaluator::new(&context, &Model::Texture(m.clone())).unwrap();
        assert_eq!(gpu.output_channels(), 1);
        for (name, window) in windows() {
            let case =
                format!("grey b={blocks} turbulence={turbulence} placement={placement}, {name}");
            check(&case, &gpu, &m, &window);
        }
    }
}

#[test]
fn one_block_structure() {
    let Some(context) = common::gpu_or_skip("texture one block") else {
        return;
    };
    for placement in [false, true] {
        let mut m = grey(11, 1, false, placement);
        m.channels[0].strata.clear();
        let gpu = GpuEvaluator::new(&context, &Model::Texture(m.clone())).unwrap();
        for (name, window) in windows() {
            check(
                &format!("one block, placement={placement}, {name}"),
                &gpu,
                &m,
                &window,
            );
        }
    }
}

/// r = 0: no channel has a structure (the tables bind one unused entry each), with and
/// without placement and turbulence, which then change nothing.
#[test]
fn no_structure_at_all() {
    let Some(context) = common::gpu_or_skip("texture without structure") else {
        return;
    };
    for (turbulence, placement) in [(false, false), (true, true)] {
        let mut m = grey(13, 2, turbulence, placement);
        m.channels[0].structure = None;
        let gpu = GpuEvaluator::new(&context, &Model::Texture(m.clone())).unwrap();
        for (name, window) in windows() {
            check(
                &format!("no structure, turbulence={turbulence}, placement={placement}, {name}"),
                &gpu,
                &m,
                &window,
            );
        }
    }
}

#[test]
fn colour_with_a_basis() {
    let Some(context) = common::gpu_or_skip("texture colour") else {
        return;
    };
    let m = colour(21);
    let gpu = GpuEvaluator::new(&context, &Model::Texture(m.clone())).unwrap();
    assert_eq!(gpu.output_channels(), 3);
    for (name, window) in windows() {
        check(&format!("colour, {name}"), &gpu, &m, &window);
    }
}

#[test]
fn tiles_are_invisible() {
    let Some(context) = common::gpu_or_skip("texture tiles_are_invisible") else {
        return;
    };
    let m = Model::Texture(colour(5));
    let mut gpu = GpuEvaluator::new(&context, &m).unwrap();
    let window = GpuWindow::new(21, 13).at([1.0e7 + 0.3, -2.0e5], 1.3);
    let whole = gpu.render(&window).unwrap();
    assert_eq!(gpu.tile_size(&window).unwrap(), [21, 13], "one tile");
    for (tw, th) in [(1, 1), (7, 5), (16, 8), (21, 1), (4, 13)] {
        gpu.set_max_tile(tw, th);
        assert_eq!(gpu.tile_size(&window).unwrap(), [tw, th]);
        let tiled = gpu.render(&window).unwrap();
        let first = first_bit_difference(&whole, &tiled);
        assert_eq!(
            first, None,
            "tiles {tw}×{th}: first differing index {first:?}"
        );
    }
    // A sub-window evaluates exactly the values of the window it is cut from.
    let tile = gpu.render(&window.tile(5, 4, 9, 7)).unwrap();
    for r in 0..7 {
        let row = &whole[((4 + r) * 21 + 5) * 3..((4 + r) * 21 + 14) * 3];
        assert_eq!(
            first_bit_difference(&tile[r * 27..(r + 1) * 27], row),
            None,
            "row {r}"
        );
    }
}

#[test]
fn bad_models_are_typed_errors() {
    let Some(context) = common::gpu_or_skip("texture bad models") else {
        return;
    };
    let mut two_channels = grey(1, 2, false, false);
    two_channels.channels.push(two_channels.channels[0].clone());
    let mut bad_period = grey(1, 2, false, false);
    bad_period.period = 48;
    let mut bad_frequency = grey(1, 2, false, false);
    if let Some(s) = &mut bad_frequency.channels[0].structure {
        s.cosines[0][0].frequency = [33, 0];
    }
    let mut nan_sigma = grey(1, 2, true, false);
    if let Some(t) = &mut nan_sigma.turbulence {
        t.sigma = f32::NAN;
    }
    for (name, m) in [
        ("two channels without a basis", two_channels),
        ("period 48", bad_period),
        ("frequency 33 with N = 32", bad_frequency),
        ("NaN sigma", nan_sigma),
    ] {
        match GpuEvaluator::new(&context, &Model::Texture(m)) {
            Err(GpuError::Model(e)) => eprintln!("{name}: {e}"),
            other => panic!("{name}: expected a model error, got {other:?}"),
        }
    }
    // A bad window is a typed error too.
    let gpu = GpuEvaluator::new(&context, &Model::Texture(grey(1, 2, false, true))).unwrap();
    let far = GpuWindow::new(4, 4).at([f64::NAN, 0.0], 1.0);
    assert!(matches!(gpu.render(&far), Err(GpuError::Window { .. })));
}
