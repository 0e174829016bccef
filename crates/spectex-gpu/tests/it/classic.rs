//! Classic noises on the device (`shaders/classic.wgsl`) against independent references: exact
//! identities at lattice points (gradient noise and every fBm of it vanish there, value noise
//! equals its lattice value, a ridged sum of gradient noise there has a closed form), a slow f64
//! evaluation written from the definitions of `spectex_model::classic` (Perlin's branchy `grad`,
//! Gustavson's simplex in f64, Worley `F_n` by brute force over every cell within reach, the
//! fractal sums), near the origin, at (10⁷, −3·10⁶) and on 3D slices; and tiling, bit for bit.
//!
//! Run with `--nocapture` to see the measured errors.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use common::gpu_or_skip;
use spectex_gpu::{GpuContext, GpuError, GpuEvaluator, GpuWindow};
use spectex_model::Model;
use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, KENSLER2_SCALE, KENSLER3_SCALE,
    Metric, SIMPLEX_F2, SIMPLEX_F3, SIMPLEX_G2, SIMPLEX_G3, Worley,
};
use spectex_model::random::{Prng, cell_hash, unit_f32};
use spectex_testkit::reference;

fn noise(seed: u32, dimensions: u32, cell_size: f32, basis: Basis) -> ClassicNoise {
    ClassicNoise {
        seed,
        dimensions,
        cell_size,
        basis,
        fractal: None,
        amplitude: 1.0,
        mean: 0.0,
    }
}

fn with_fractal(mut m: ClassicNoise, kind: FractalKind, octaves: u32) -> ClassicNoise {
    m.fractal = Some(Fractal {
        kind,
        octaves,
        lacunarity: 2.0,
        gain: 0.5,
    });
    m.validate().unwrap();
    m
}

fn worley(metric: Metric, coefficients: [f32; 4], points: FeaturePoints) -> Basis {
    Basis::Worley(Worley {
        metric,
        coefficients,
        points,
    })
}

fn render(context: &GpuContext, m: &ClassicNoise, z: f64, window: &GpuWindow) -> Vec<f32> {
    let gpu = GpuEvaluator::new_at_z(context, &Model::Classic(m.clone()), z).unwrap();
    assert_eq!(gpu.output_channels(), 1);
    gpu.render(window).unwrap()
}

// ---------------------------------------------------------------------------------------------
// The f64 reference.

/// The hash of lattice corner `c` of octave `o` (the contract of `spectex_model::classic`).
fn corner(m: &ClassicNoise, c: [i64; 3], o: u32) -> u32 {
    let (i, j, k) = (c[0] as i32, c[1] as i32, c[2] as i32);
    if m.dimensions == 3 {
        cell_hash(i, j, o, cell_hash(k, 0, o, m.seed))
    } else {
        cell_hash(i, j, o, m.seed)
    }
}

/// Perlin's `grad(hash, x, y, z)` of "Improving Noise", with branches, on the top four bits.
fn grad(h: u32, x: f64, y: f64, z: f64) -> f64 {
    let h = h >> 28;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Gradient or value noise at `p` (cell units), by the tensor-product definition.
fn lattice(m: &ClassicNoise, p: [f64; 3], o: u32, gradient: bool) -> f64 {
    let d = m.dimensions as usize;
    let cell = p.map(f64::floor);
    let t = [p[0] - cell[0], p[1] - cell[1], p[2] - cell[2]];
    let mut sum = 0.0;
    for bits in 0..(1 << d) {
        let mut c = [0i64; 3];
        let mut w = 1.0;
        let mut delta = [0.0; 3];
        for a in 0..d {
            let b = (bits >> a) & 1;
            c[a] = cell[a] as i64 + b as i64;
            delta[a] = t[a] - b as f64;
            w *= if b == 1 { fade(t[a]) } else { 1.0 - fade(t[a]) };
        }
        let h = corner(m, c, o);
        let v = if gradient {
            grad(h, delta[0], delta[1], delta[2])
        } else {
            2.0 * f64::from(unit_f32(h)) - 1.0
        };
        sum += w * v;
    }
    sum
}

/// Simplex noise at `p` (Gustavson 2005) in f64; also whether `p` lies within `1e-5` of a
/// boundary between simplices (where 3D simplex noise, with `r² = 0.6`, is discontinuous).
fn simplex(m: &ClassicNoise, p: [f64; 3], o: u32) -> (f64, bool) {
    let three_d = m.dimensions == 3;
    let d = if three_d { 3 } else { 2 };
    let (f, g, r2, scale) = if three_d {
        (SIMPLEX_F3, SIMPLEX_G3, 0.6, 32.0)
    } else {
        (SIMPLEX_F2, SIMPLEX_G2, 0.5, 70.0)
    };
    let s: f64 = p[..d].iter().sum::<f64>() * f;
    let skewed: Vec<f64> = p[..d].iter().map(|x| x + s).collect();
    let cell: Vec<f64> = skewed.iter().map(|x| x.floor()).collect();
    let frac: Vec<f64> = skewed.iter().zip(&cell).map(|(x, c)| x - c).collect();
    let t: f64 = cell.iter().sum::<f64>() * g;
    let x0: Vec<f64> = (0..d).map(|a| p[a] - (cell[a] - t)).collect();
    // Corners in order of decreasing x0 component: traverse the simplex by unit steps.
    let mut order: Vec<usize> = (0..d).collect();
    order.sort_by(|&a, &b| x0[b].total_cmp(&x0[a]));
    let mut near = frac.iter().any(|&v| !(1e-5..=1.0 - 1e-5).contains(&v));
    for a in 0..d {
        for b in a + 1..d {
            near |= (x0[a] - x0[b]).abs() < 1e-5;
        }
    }
    let mut step = [0i64; 3];
    let mut sum = 0.0;
    for k in 0..=d {
        if k > 0 {
            step[order[k - 1]] += 1;
        }
        let mut delta = [0.0; 3];
        let mut c = [0i64; 3];
        for a in 0..d {
            delta[a] = x0[a] - step[a] as f64 + k as f64 * g;
            c[a] = cell[a] as i64 + step[a];
        }
        let r = r2 - delta.iter().map(|v| v * v).sum::<f64>();
        if r > 0.0 {
            sum += r.powi(4) * grad(corner(m, c, o), delta[0], delta[1], delta[2]);
        }
    }
    (scale * sum, near)
}

/// Worley `C₁F₁ + … + C₄F₄` at `p` by brute force over every cell within `reach` cells.
fn worley_brute(m: &ClassicNoise, w: &Worley, p: [f64; 3], o: u32) -> f64 {
    let three_d = m.dimensions == 3;
    let reach: i64 = if three_d { 2 } else { 4 };
    let cell = p.map(|v| v.floor() as i64);
    let cdf = w.points.poisson_cdf();
    let mut distances = Vec::new();
    let zr = if three_d { reach } else { 0 };
    for dz in -zr..=zr {
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let c = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                let mut prng = Prng::new(corner(m, c, o));
                let count = match (w.points, &cdf) {
                    (FeaturePoints::Fixed(n), _) => n,
                    (_, Some(cdf)) => {
                        let u = prng.next_f32();
                        cdf.iter().filter(|&&q| u >= q).count() as u32
                    }
                    (_, None) => unreachable!("a Poisson count has a CDF"),
                };
                for _ in 0..count {
                    let mut q = [0.0; 3];
                    let axes = if three_d { 3 } else { 2 };
                    for (a, v) in q.iter_mut().enumerate().take(axes) {
                        *v = c[a] as f64 + f64::from(prng.next_f32());
                    }
                    let delta: Vec<f64> = (0..axes).map(|a| (p[a] - q[a]).abs()).collect();
                    distances.push(match w.metric {
                        Metric::Euclidean => delta.iter().map(|v| v * v).sum::<f64>().sqrt(),
                        Metric::Manhattan => delta.iter().sum(),
                        Metric::Chebyshev => delta.iter().copied().fold(0.0, f64::max),
                    });
                }
            }
        }
    }
    distances.sort_by(f64::total_cmp);
    (0..4)
        .map(|k| f64::from(w.coefficients[k]) * distances.get(k).copied().unwrap_or(7.0).min(7.0))
        .sum()
}

/// The model at `(x, y, z)` pixels; and whether it lies near a 3D simplex seam.
fn reference(m: &ClassicNoise, x: f64, y: f64, z: f64) -> (f64, bool) {
    let mut acc = 0.0;
    let mut previous = 0.0;
    let mut near = false;
    for o in 0..m.octaves() {
        let side = m.octave_cell(o);
        let p = [
            x / side,
            y / side,
            if m.dimensions == 3 { z / side } else { 0.0 },
        ];
        let n = match &m.basis {
            Basis::Gradient => lattice(m, p, o, true),
            Basis::Value => lattice(m, p, o, false),
            Basis::Simplex => {
                let (n, seam) = simplex(m, p, o);
                near |= seam && m.dimensions == 3;
                n
            }
            Basis::Kensler => {
                let scale = if m.dimensions == 3 {
                    KENSLER3_SCALE
                } else {
                    KENSLER2_SCALE
                };
                f64::from(scale) * reference::kensler(p, m.dimensions == 3, o, m.seed).0
            }
            Basis::Worley(w) => worley_brute(m, w, p, o),
        };
        let weight = f64::from(m.fractal.as_ref().map_or(1.0, |f| f.gain)).powi(o as i32);
        acc += weight
            * match m.fractal.as_ref().map(|f| f.kind) {
                None | Some(FractalKind::Fbm) => n,
                Some(FractalKind::Turbulence) => n.abs(),
                Some(FractalKind::Ridged {
                    offset,
                    weight_gain,
                }) => {
                    let r = f64::from(offset) - n.abs();
                    let mut s = r * r;
                    if o > 0 {
                        s *= (previous * f64::from(weight_gain)).clamp(0.0, 1.0);
                    }
                    previous = s;
                    s
                }
            };
    }
    (f64::from(m.mean) + f64::from(m.amplitude) * acc, near)
}

// ---------------------------------------------------------------------------------------------

#[test]
fn lattice_points_give_the_exact_identities() {
    let Some(context) = gpu_or_skip("classic lattice identities") else {
        return;
    };
    let cell = 16.0f32;
    let side = 12;
    for (offset, z_cells) in [([0.0, 0.0], 0i64), ([1.0e7, -3.0e6], -3)] {
        // One output pixel per lattice point: scale = the cell side, point-sampled (a minified
        // render would fade the octave).
        let window = GpuWindow::new(side, side)
            .at(offset, f64::from(cell))
            .filtered(spectex_gpu::Filter::Off);
        let z = z_cells as f64 * f64::from(cell);
        let (i0, j0) = (
            (offset[0] / f64::from(cell)) as i64,
            (offset[1] / f64::from(cell)) as i64,
        );
        for dims in [2, 3] {
            let g = render(&context, &noise(3, dims, cell, Basis::Gradient), z, &window);
            assert!(
                g.iter().all(|&v| v == 0.0),
                "gradient noise {dims}D at lattice points {offset:?}: {:?}",
                g.iter().find(|v| **v != 0.0)
            );
            let m = noise(3, dims, cell, Basis::Value);
            let v = render(&context, &m, z, &window);
            for j in 0..side {
                for i in 0..side {
                    let c = [i0 + i as i64, j0 + j as i64, z_cells];
                    let want = 2.0 * unit_f32(corner(&m, c, 0)) - 1.0;
                    assert_eq!(
                        v[j * side + i].to_bits(),
                        want.to_bits(),
                        "value noise {dims}D at lattice point {c:?}"
                    );
                }
            }
            // Lattice points of octave 0 are lattice points of every finer octave (λ = 2).
            let fbm = with_fractal(noise(3, dims, cell, Basis::Gradient), FractalKind::Fbm, 3);
            let f = render(&context, &fbm, z, &window);
            assert!(f.iter().all(|&v| v == 0.0), "fBm {dims}D at lattice points");
            // Ridged with n = 0: s₀ = 1, s₁ = 1·clamp(½·1) = ½, s₂ = clamp(½·½) = ¼, weighted by
            // 1, ½, ¼: 1 + ¼ + 1/16, then mean + amplitude·sum.
            let mut ridged = with_fractal(
                noise(3, dims, cell, Basis::Gradient),
                FractalKind::Ridged {
                    offset: 1.0,
                    weight_gain: 0.5,
                },
                3,
            );
            ridged.amplitude = 2.0;
            ridged.mean = -1.0;
            let r = render(&context, &ridged, z, &window);
            assert!(
                r.iter().all(|&v| v == -1.0 + 2.0 * 1.3125),
                "ridged {dims}D at lattice points: {}",
                r[0]
            );
            // Turbulence of value noise: Σ ½ᵒ·|lattice value of layer o|.
            let turbulence = with_fractal(
                noise(3, dims, cell, Basis::Value),
                FractalKind::Turbulence,
                2,
            );
            let t = render(&context, &turbulence, z, &window);
            for j in 0..side {
                for i in 0..side {
                    let want: f64 = (0..2u32)
                        .map(|o| {
                            let s = 1i64 << o;
                            let c = [s * (i0 + i as i64), s * (j0 + j as i64), s * z_cells];
                            let v = 2.0 * f64::from(unit_f32(corner(&turbulence, c, o))) - 1.0;
                            0.5f64.powi(o as i32) * v.abs()
                        })
                        .sum();
                    let got = f64::from(t[j * side + i]);
                    assert!(
                        (got - want).abs() < 1e-6,
                        "turbulence {dims}D at ({i}, {j}): {got} vs {want}"
                    );
                }
            }
        }
    }
}

/// The cases compared with the f64 reference: (name, model, z).
fn cases() -> Vec<(&'static str, ClassicNoise, f64)> {
    let fixed1 = FeaturePoints::Fixed(1);
    vec![
        (
            "gradient 2D fBm",
            with_fractal(noise(1, 2, 24.0, Basis::Gradient), FractalKind::Fbm, 3),
            0.0,
        ),
        ("gradient 3D", noise(2, 3, 20.0, Basis::Gradient), 37.3),
        (
            "value 3D ridged",
            with_fractal(
                noise(3, 3, 18.0, Basis::Value),
                FractalKind::Ridged {
                    offset: 1.0,
                    weight_gain: 2.0,
                },
                2,
            ),
            -11.7,
        ),
        ("simplex 2D", noise(4, 2, 14.0, Basis::Simplex), 0.0),
        ("kensler 2D", noise(12, 2, 13.0, Basis::Kensler), 0.0),
        (
            "kensler 3D fBm",
            with_fractal(noise(13, 3, 17.0, Basis::Kensler), FractalKind::Fbm, 2),
            29.1,
        ),
        (
            "simplex 3D turbulence",
            with_fractal(
                noise(5, 3, 22.0, Basis::Simplex),
                FractalKind::Turbulence,
                2,
            ),
            51.9,
        ),
        (
            "Worley F1 euclidean",
            noise(
                6,
                2,
                12.0,
                worley(Metric::Euclidean, [1.0, 0.0, 0.0, 0.0], fixed1),
            ),
            0.0,
        ),
        (
            "Worley F2 − F1 manhattan, Poisson",
            noise(
                7,
                2,
                12.0,
                worley(
                    Metric::Manhattan,
                    [-1.0, 1.0, 0.0, 0.0],
                    FeaturePoints::Poisson(1.5),
                ),
            ),
            0.0,
        ),
        (
            "Worley F4 chebyshev, 3 points",
            noise(
                8,
                2,
                16.0,
                worley(
                    Metric::Chebyshev,
                    [0.5, 0.0, 0.25, 1.0],
                    FeaturePoints::Fixed(3),
                ),
            ),
            0.0,
        ),
        (
            "Worley 3D F1 euclidean",
            noise(
                9,
                3,
                10.0,
                worley(Metric::Euclidean, [1.0, 0.0, 0.0, 0.0], fixed1),
            ),
            23.4,
        ),
    ]
}

#[test]
fn renders_match_the_f64_reference_near_and_far() {
    let Some(context) = gpu_or_skip("classic f64 reference") else {
        return;
    };
    // f32 offsets (≤ 2⁻²⁴ of a cell) through slopes of at most ~30 per cell (simplex), the f32
    // sums of 3 octaves and Worley's squared distances: well below 1e-4; a bug is ≥ 1e-2.
    const TOLERANCE: f64 = 1e-4;
    // Across a 3D simplex seam the noise jumps by up to 32·2·0.1⁴ (Gustavson's r² = 0.6).
    const SEAM: f64 = 6.4e-3;
    let side = 24;
    for (name, m, z) in cases() {
        m.validate().unwrap();
        for (offset, scale) in [([-5.5, 3.25], 0.85), ([1.0e7, -3.0e6], 1.0)] {
            let window = GpuWindow::new(side, side).at(offset, scale);
            let got = render(&context, &m, z, &window);
            let mut worst = 0.0f64;
            for j in 0..side {
                for i in 0..side {
                    let (want, near) = reference(&m, window.x(i), window.y(j), z);
                    let e = (f64::from(got[j * side + i]) - want).abs();
                    let bound = if near { SEAM } else { TOLERANCE };
                    assert!(
                        e <= bound,
                        "{name} at {offset:?}, pixel ({i}, {j}): GPU {} vs f64 {want}",
                        got[j * side + i]
                    );
                    if !near {
                        worst = worst.max(e);
                    }
                }
            }
            let spread = got.iter().copied().fold(f32::NEG_INFINITY, f32::max)
                - got.iter().copied().fold(f32::INFINITY, f32::min);
            assert!(spread > 0.05, "{name} at {offset:?}: nearly constant");
            eprintln!("{name} at {offset:?}: max |GPU − f64| = {worst:.2e}");
        }
    }
}

#[test]
fn tiles_give_the_same_bits() {
    let Some(context) = gpu_or_skip("classic tiling") else {
        return;
    };
    let window = GpuWindow::new(40, 36).at([1.0e7 + 0.5, -3.0e6], 0.75);
    for (name, m, z) in cases() {
        let model = Model::Classic(m);
        let mut gpu = GpuEvaluator::new_at_z(&context, &model, z).unwrap();
        let whole = gpu.render(&window).unwrap();
        gpu.set_max_tile(16, 7);
        assert_eq!(gpu.tile_size(&window).unwrap(), [16, 7]);
        let tiled = gpu.render(&window).unwrap();
        assert_eq!(
            common::first_bit_difference(&whole, &tiled),
            None,
            "{name}: tiles differ"
        );
    }
}

#[test]
fn a_bad_plane_is_a_typed_error() {
    let Some(context) = gpu_or_skip("classic bad z") else {
        return;
    };
    let model = Model::Classic(noise(1, 3, 16.0, Basis::Gradient));
    for z in [f64::NAN, 2.0e9] {
        assert!(matches!(
            GpuEvaluator::new_at_z(&context, &model, z),
            Err(GpuError::Window { parameter: "z", .. })
        ));
    }
}
