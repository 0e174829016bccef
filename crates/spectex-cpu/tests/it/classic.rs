//! Classic noises against their definitions: gradient noise vanishes at lattice points, value
//! noise interpolates its lattice values, slow f64 references written from the papers (at the
//! origin and at 10⁷), Worley `F₁…F₄` against a brute-force search, range bounds derived from
//! the definitions, and bit-identity across tilings, thread counts and SIMD levels.

use spectex_cpu::classic::ClassicEvaluator;
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, Fractal, FractalKind, Metric, Worley, lattice_value,
};
use spectex_model::random::{Prng, cell_hash};

fn noise(basis: Basis, dimensions: u32, fractal: Option<Fractal>) -> ClassicNoise {
    let m = ClassicNoise {
        seed: 11,
        dimensions,
        cell_size: 16.0,
        basis,
        fractal,
        amplitude: 1.0,
        mean: 0.0,
    };
    m.validate().expect("test model is valid");
    m
}

fn fbm(kind: FractalKind) -> Option<Fractal> {
    Some(Fractal {
        kind,
        octaves: 4,
        lacunarity: 2.0,
        gain: 0.5,
    })
}

fn worley(metric: Metric, c: [f32; 4], points: FeaturePoints) -> Basis {
    Basis::Worley(Worley {
        metric,
        coefficients: c,
        points,
    })
}

/// Every kind the tests sweep, with a name for messages.
fn all_models() -> Vec<(&'static str, ClassicNoise)> {
    let ridged = FractalKind::Ridged {
        offset: 1.0,
        weight_gain: 2.0,
    };
    let f1 = [1.0, 0.0, 0.0, 0.0];
    let f2f1 = [-1.0, 1.0, 0.0, 0.0];
    vec![
        ("gradient2", noise(Basis::Gradient, 2, None)),
        ("gradient3", noise(Basis::Gradient, 3, None)),
        ("value2", noise(Basis::Value, 2, None)),
        ("value3", noise(Basis::Value, 3, None)),
        ("simplex2", noise(Basis::Simplex, 2, None)),
        ("simplex3", noise(Basis::Simplex, 3, None)),
        ("kensler2", noise(Basis::Kensler, 2, None)),
        ("kensler3", noise(Basis::Kensler, 3, None)),
        (
            "fbm_gradient2",
            noise(Basis::Gradient, 2, fbm(FractalKind::Fbm)),
        ),
        (
            "turbulence_simplex2",
            noise(Basis::Simplex, 2, fbm(FractalKind::Turbulence)),
        ),
        ("ridged_gradient3", noise(Basis::Gradient, 3, fbm(ridged))),
        (
            "worley2_f1",
            noise(
                worley(Metric::Euclidean, f1, FeaturePoints::Fixed(1)),
                2,
                None,
            ),
        ),
        (
            "worley2_f2f1_poisson",
            noise(
                worley(Metric::Manhattan, f2f1, FeaturePoints::Poisson(0.7)),
                2,
                None,
            ),
        ),
        (
            "worley3_f4",
            noise(
                worley(
                    Metric::Chebyshev,
                    [0.0, 0.0, 0.0, 1.0],
                    FeaturePoints::Poisson(1.5),
                ),
                3,
                fbm(FractalKind::Fbm),
            ),
        ),
    ]
}

// ---------------------------------------------------------------------------------------------
// Slow references in f64, written from the papers and the randomness contract.
// ---------------------------------------------------------------------------------------------

fn fade64(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Perlin's `grad` with branches ("Improving Noise", 2002), on the top four bits of the hash.
fn grad64(h: u32, x: f64, y: f64, z: f64) -> f64 {
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

fn hash3(i: i32, j: i32, k: i32, o: u32, seed: u32) -> u32 {
    cell_hash(i, j, o, cell_hash(k, 0, o, seed))
}

/// Improved Perlin noise (or value noise) at `(x, y[, z])` in cell units, octave `o`.
fn lattice_reference(gradient: bool, p: [f64; 3], three_d: bool, o: u32, seed: u32) -> f64 {
    let c = p.map(f64::floor);
    let u = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
    let nz = if three_d { 2 } else { 1 };
    let mut total = 0.0;
    for dz in 0..nz {
        for dy in 0..2 {
            for dx in 0..2 {
                let (i, j, k) = (c[0] as i32 + dx, c[1] as i32 + dy, c[2] as i32 + dz);
                let h = if three_d {
                    hash3(i, j, k, o, seed)
                } else {
                    cell_hash(i, j, o, seed)
                };
                let d = [
                    u[0] - f64::from(dx),
                    u[1] - f64::from(dy),
                    u[2] - f64::from(dz),
                ];
                let v = if gradient {
                    grad64(h, d[0], d[1], if three_d { d[2] } else { 0.0 })
                } else {
                    f64::from(lattice_value(h))
                };
                let wx = if dx == 1 {
                    fade64(u[0])
                } else {
                    1.0 - fade64(u[0])
                };
                let wy = if dy == 1 {
                    fade64(u[1])
                } else {
                    1.0 - fade64(u[1])
                };
                let wz = match (three_d, dz) {
                    (false, _) => 1.0,
                    (true, 1) => fade64(u[2]),
                    (true, _) => 1.0 - fade64(u[2]),
                };
                total += wx * wy * wz * v;
            }
        }
    }
    total
}

/// 2D simplex noise as in Gustavson's "Simplex noise demystified" (2005), with this
/// project's hash and Perlin's 16 gradients.
fn simplex2_reference(x: f64, y: f64, o: u32, seed: u32) -> f64 {
    let f2 = 0.5 * (3f64.sqrt() - 1.0);
    let g2 = (3.0 - 3f64.sqrt()) / 6.0;
    let s = (x + y) * f2;
    let (i, j) = ((x + s).floor(), (y + s).floor());
    let t = (i + j) * g2;
    let (x0, y0) = (x - (i - t), y - (j - t));
    let (i1, j1) = if x0 > y0 { (1.0, 0.0) } else { (0.0, 1.0) };
    let corners = [
        (0.0, 0.0, x0, y0),
        (i1, j1, x0 - i1 + g2, y0 - j1 + g2),
        (1.0, 1.0, x0 - 1.0 + 2.0 * g2, y0 - 1.0 + 2.0 * g2),
    ];
    let mut n = 0.0;
    for (di, dj, dx, dy) in corners {
        let t = 0.5 - dx * dx - dy * dy;
        if t > 0.0 {
            let h = cell_hash((i + di) as i32, (j + dj) as i32, o, seed);
            n += t.powi(4) * grad64(h, dx, dy, 0.0);
        }
    }
    70.0 * n
}

/// Feature points of a Worley cell, in cell units of the whole plane (contract order).
fn worley_points(w: &Worley, cell: [i32; 3], three_d: bool, o: u32, seed: u32) -> Vec<[f64; 3]> {
    let h = if three_d {
        hash3(cell[0], cell[1], cell[2], o, seed)
    } else {
        cell_hash(cell[0], cell[1], o, seed)
    };
    let mut prng = Prng::new(h);
    let count = match w.points {
        FeaturePoints::Fixed(n) => n,
        FeaturePoints::Poisson(_) => {
            let cdf = w.points.poisson_cdf().expect("poisson");
            let u = prng.next_f32();
            cdf.iter().filter(|&&p| u >= p).count() as u32
        }
    };
    (0..count)
        .map(|_| {
            let ox = f64::from(prng.next_f32());
            let oy = f64::from(prng.next_f32());
            let oz = if three_d {
                f64::from(prng.next_f32())
            } else {
                0.0
            };
            [
                f64::from(cell[0]) + ox,
                f64::from(cell[1]) + oy,
                f64::from(cell[2]) + oz,
            ]
        })
        .collect()
}

/// The four smallest distances from `p` (cell units) to every feature point of the cells within
/// `reach` of its cell: brute force.
fn worley_brute_force(w: &Worley, p: [f64; 3], three_d: bool, seed: u32, reach: i32) -> [f64; 4] {
    let c = p.map(|v| v.floor() as i32);
    let zr = if three_d { reach } else { 0 };
    let mut d = Vec::new();
    for dz in -zr..=zr {
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                for q in worley_points(w, [c[0] + dx, c[1] + dy, c[2] + dz], three_d, 0, seed) {
                    let e = [
                        p[0] - q[0],
                        p[1] - q[1],
                        if three_d { p[2] - q[2] } else { 0.0 },
                    ];
                    d.push(match w.metric {
                        Metric::Euclidean => (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt(),
                        Metric::Manhattan => e[0].abs() + e[1].abs() + e[2].abs(),
                        Metric::Chebyshev => e[0].abs().max(e[1].abs()).max(e[2].abs()),
                    });
                }
            }
        }
    }
    d.sort_by(f64::total_cmp);
    [d[0], d[1], d[2], d[3]]
}

fn render(m: &ClassicNoise, z: f64, window: &Window) -> Vec<f32> {
    Evaluator::new_at_z(&Model::Classic(m.clone()), z)
        .expect("valid")
        .render(window)
        .expect("window")
}

// ---------------------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------------------

#[test]
fn gradient_noise_is_zero_at_lattice_points() {
    for dims in [2, 3] {
        let m = noise(Basis::Gradient, dims, None);
        for z in [0.0, 48.0, -16.0] {
            let e = ClassicEvaluator::new(&m, z);
            for (i, j) in [(0, 0), (3, -2), (-7, 5), (625_000, 625_000)] {
                let (x, y) = (f64::from(i) * 16.0, f64::from(j) * 16.0);
                assert_eq!(
                    e.eval(x, y),
                    0.0,
                    "dims {dims}, z {z}, lattice point ({i}, {j})"
                );
            }
            // and not at cell centres (the gradients are never all zero there)
            let centre: f32 = (0..20)
                .map(|i| e.eval(f64::from(i) * 16.0 + 8.0, 8.0).abs())
                .sum();
            assert!(
                centre > 0.0,
                "dims {dims}: gradient noise is identically zero"
            );
        }
    }
}

#[test]
fn value_noise_equals_its_lattice_values() {
    for dims in [2u32, 3] {
        let m = noise(Basis::Value, dims, None);
        let z_cell = -3;
        let e = ClassicEvaluator::new(&m, f64::from(z_cell) * 16.0);
        for (i, j) in [(0, 0), (3, -2), (-7, 5), (625_000, -625_000)] {
            let h = if dims == 3 {
                hash3(i, j, z_cell, 0, m.seed)
            } else {
                cell_hash(i, j, 0, m.seed)
            };
            let got = e.eval(f64::from(i) * 16.0, f64::from(j) * 16.0);
            assert_eq!(
                got,
                lattice_value(h),
                "dims {dims}, lattice point ({i}, {j})"
            );
        }
    }
}

#[test]
fn lattice_noises_match_the_f64_reference_at_the_origin_and_far_away() {
    for (gradient, dims) in [(true, 2), (true, 3), (false, 2), (false, 3)] {
        let basis = if gradient {
            Basis::Gradient
        } else {
            Basis::Value
        };
        let m = noise(basis, dims, None);
        let z = 21.7;
        for offset in [0.0, 1.0e7] {
            let window = Window::new(40, 30).at([offset - 3.3, offset + 1.9], 0.77);
            let got = render(&m, z, &window);
            let mut worst = 0.0f64;
            for j in 0..window.height {
                for i in 0..window.width {
                    let p = [window.x(i) / 16.0, window.y(j) / 16.0, z / 16.0];
                    let r = lattice_reference(gradient, p, dims == 3, 0, m.seed);
                    worst = worst.max((f64::from(got[j * window.width + i]) - r).abs());
                }
            }
            // f32 arithmetic on offsets in [0, 1): a few ulps of values of order 1.
            assert!(
                worst < 2e-6,
                "gradient {gradient}, dims {dims}, offset {offset}: error {worst}"
            );
        }
    }
}

#[test]
fn simplex_matches_gustavson_at_the_origin_and_far_away() {
    let m = noise(Basis::Simplex, 2, None);
    // Simplex vertices (k, −k) in cell units vanish like any gradient noise's lattice points.
    let e = ClassicEvaluator::new(&m, 0.0);
    for k in [0, 1, -4, 9] {
        assert_eq!(
            e.eval(f64::from(k) * 16.0, -f64::from(k) * 16.0),
            0.0,
            "vertex {k}"
        );
    }
    for offset in [0.0, 1.0e7] {
        let window = Window::new(50, 40).at([offset + 0.5, offset - 7.25], 0.61);
        let got = render(&m, 0.0, &window);
        let mut worst = 0.0f64;
        for j in 0..window.height {
            for i in 0..window.width {
                let r = simplex2_reference(window.x(i) / 16.0, window.y(j) / 16.0, 0, m.seed);
                worst = worst.max((f64::from(got[j * window.width + i]) - r).abs());
            }
        }
        assert!(worst < 1e-5, "offset {offset}: error {worst}");
    }
}

#[test]
fn fractal_sums_follow_their_definitions() {
    let base = noise(Basis::Gradient, 2, None);
    let octave = |o: u32, x: f64, y: f64| {
        lattice_reference(
            true,
            [
                x / 16.0 * 2f64.powi(o as i32),
                y / 16.0 * 2f64.powi(o as i32),
                0.0,
            ],
            false,
            o,
            base.seed,
        )
    };
    let ridged = FractalKind::Ridged {
        offset: 1.0,
        weight_gain: 2.0,
    };
    for kind in [FractalKind::Fbm, FractalKind::Turbulence, ridged] {
        let m = noise(Basis::Gradient, 2, fbm(kind));
        let e = ClassicEvaluator::new(&m, 0.0);
        for (x, y) in [(3.3, 7.9), (1.0e7 + 0.4, -1.0e7 + 11.1), (-100.2, 55.5)] {
            let mut sum = 0.0;
            let mut previous = 0.0f64;
            for o in 0..4 {
                let n = octave(o, x, y);
                let w = 0.5f64.powi(o as i32);
                sum += w * match kind {
                    FractalKind::Fbm => n,
                    FractalKind::Turbulence => n.abs(),
                    FractalKind::Ridged { .. } => {
                        let mut s = (1.0 - n.abs()).powi(2);
                        if o > 0 {
                            s *= (previous * 2.0).clamp(0.0, 1.0);
                        }
                        previous = s;
                        s
                    }
                };
            }
            let got = f64::from(e.eval(x, y));
            assert!(
                (got - sum).abs() < 1e-5,
                "{kind:?} at ({x}, {y}): {got} vs {sum}"
            );
        }
    }
}

#[test]
fn ranges_follow_from_the_definitions() {
    // Value noise: a convex combination of lattice values in [−1, 1).
    // Gradient noise: a convex combination of g·d with two ±1 entries in g and |dᵢ| ≤ 1: |n| ≤ 2.
    // Simplex 2D: 70 · 3 · max_r (½ − r²)⁴·√2·r (|g·d| ≤ |g||d|), maximised on a fine grid of r.
    let simplex_bound = 70.0
        * 3.0
        * (0..=100_000)
            .map(|k| {
                let r = f64::from(k) / 100_000.0 * 0.5f64.sqrt();
                (0.5 - r * r).powi(4) * 2f64.sqrt() * r
            })
            .fold(0.0, f64::max);
    let window = Window::new(128, 128).at([-500.0, 300.0], 0.9);
    for (name, m, bound) in [
        ("value", noise(Basis::Value, 2, None), 1.0),
        ("value3", noise(Basis::Value, 3, None), 1.0),
        ("gradient", noise(Basis::Gradient, 2, None), 2.0),
        ("gradient3", noise(Basis::Gradient, 3, None), 2.0),
        ("simplex", noise(Basis::Simplex, 2, None), simplex_bound),
    ] {
        let v = render(&m, 5.5, &window);
        let worst = v.iter().fold(0.0f64, |a, &b| a.max(f64::from(b).abs()));
        assert!(worst <= bound, "{name}: |n| reaches {worst} > {bound}");
        let mean_abs = v.iter().map(|&b| f64::from(b).abs()).sum::<f64>() / v.len() as f64;
        assert!(
            mean_abs > 0.01 * bound,
            "{name}: almost constant ({mean_abs})"
        );
    }
}

#[test]
fn worley_distances_match_a_brute_force_search() {
    let cases = [
        (Metric::Euclidean, FeaturePoints::Fixed(1), false),
        (Metric::Manhattan, FeaturePoints::Fixed(2), false),
        (Metric::Chebyshev, FeaturePoints::Poisson(0.5), false),
        (Metric::Euclidean, FeaturePoints::Poisson(1.0), false),
        (Metric::Euclidean, FeaturePoints::Fixed(1), true),
        (Metric::Manhattan, FeaturePoints::Poisson(0.6), true),
    ];
    for (metric, points, three_d) in cases {
        let dims = if three_d { 3 } else { 2 };
        let z = 37.0;
        // Point samples: a minified render would fade the octave (`Filter::Pixel`).
        let window = Window::new(24, 24)
            .at([1.0e7 - 100.0, -250.3], 3.1)
            .filtered(spectex_cpu::Filter::Off);
        let mut f = Vec::new();
        for n in 0..4 {
            let mut c = [0.0f32; 4];
            c[n] = 1.0;
            let m = noise(worley(metric, c, points), dims, None);
            f.push(render(&m, z, &window));
        }
        let Basis::Worley(w) =
            noise(worley(metric, [1.0, 0.0, 0.0, 0.0], points), dims, None).basis
        else {
            unreachable!()
        };
        // Seven rings hold every point the evaluator may reach ([`WORLEY_MAX_RING`] = 6).
        let reach = if three_d { 4 } else { 7 };
        for p in (0..window.width * window.height).step_by(7) {
            let (i, j) = (p % window.width, p / window.width);
            let q = [window.x(i) / 16.0, window.y(j) / 16.0, z / 16.0];
            let reference = worley_brute_force(&w, q, three_d, 11, reach);
            let got = [f[0][p], f[1][p], f[2][p], f[3][p]];
            assert!(
                got[0] <= got[1] && got[1] <= got[2] && got[2] <= got[3],
                "{metric:?} {points:?} 3D {three_d}: not sorted at pixel {p}: {got:?}"
            );
            for n in 0..4 {
                assert!(
                    (f64::from(got[n]) - reference[n]).abs() < 1e-5,
                    "{metric:?} {points:?} 3D {three_d}: F{} at pixel {p}: {} vs {}",
                    n + 1,
                    got[n],
                    reference[n]
                );
            }
        }
    }
}

#[test]
fn tiles_threads_and_simd_levels_give_the_same_bits() {
    let window = Window::new(70, 37).at([1.0e7 + 0.3, -1.0e7 - 0.6], 0.83);
    for (name, m) in all_models() {
        let whole = render(&m, 19.0, &window);
        // Tiles of odd sizes, so lanes fall differently.
        let eval = Evaluator::new_at_z(&Model::Classic(m.clone()), 19.0).expect("valid");
        for (x, y, w, h) in [(0, 0, 13, 5), (13, 5, 57, 32), (3, 30, 1, 7), (69, 0, 1, 1)] {
            let tile = eval.render(&window.tile(x, y, w, h)).expect("tile");
            for r in 0..h {
                for c in 0..w {
                    assert_eq!(
                        tile[r * w + c].to_bits(),
                        whole[(y + r) * window.width + x + c].to_bits(),
                        "{name}: tile ({x}, {y}) pixel ({c}, {r})"
                    );
                }
            }
        }
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let again = pool.install(|| render(&m, 19.0, &window));
            assert!(
                again
                    .iter()
                    .zip(&whole)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{name}: {threads} threads"
            );
        }
        let mut e = ClassicEvaluator::new(&m, 19.0);
        let mut levels = Vec::new();
        e.set_simd(false);
        levels.push(("portable", e.clone()));
        if e.set_avx2() {
            levels.push(("avx2", e.clone()));
        }
        if e.set_simd(true) == 16 {
            levels.push(("avx512", e.clone()));
        }
        for (level, e) in levels {
            let mut out = vec![0.0f32; window.width * window.height];
            e.eval_rows(&window, 0, &mut out);
            assert!(
                out.iter()
                    .zip(&whole)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{name}: {level} differs"
            );
        }
    }
}

/// 3D simplex noise as in Gustavson (2005), with his nested ranking of the offsets.
fn simplex3_reference(p: [f64; 3], seed: u32) -> f64 {
    let (f3, g3) = (1.0 / 3.0, 1.0 / 6.0);
    let s = (p[0] + p[1] + p[2]) * f3;
    let c = p.map(|v| (v + s).floor());
    let t = (c[0] + c[1] + c[2]) * g3;
    let d0 = [p[0] - (c[0] - t), p[1] - (c[1] - t), p[2] - (c[2] - t)];
    let (x0, y0, z0) = (d0[0], d0[1], d0[2]);
    let (o1, o2) = if x0 >= y0 {
        if y0 >= z0 {
            ([1.0, 0.0, 0.0], [1.0, 1.0, 0.0])
        } else if x0 >= z0 {
            ([1.0, 0.0, 0.0], [1.0, 0.0, 1.0])
        } else {
            ([0.0, 0.0, 1.0], [1.0, 0.0, 1.0])
        }
    } else if y0 < z0 {
        ([0.0, 0.0, 1.0], [0.0, 1.0, 1.0])
    } else if x0 < z0 {
        ([0.0, 1.0, 0.0], [0.0, 1.0, 1.0])
    } else {
        ([0.0, 1.0, 0.0], [1.0, 1.0, 0.0])
    };
    let mut n = 0.0;
    for (k, o) in [[0.0; 3], o1, o2, [1.0; 3]].into_iter().enumerate() {
        let d: Vec<f64> = (0..3).map(|a| d0[a] - o[a] + k as f64 * g3).collect();
        let t = 0.6 - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if t > 0.0 {
            let h = hash3(
                (c[0] + o[0]) as i32,
                (c[1] + o[1]) as i32,
                (c[2] + o[2]) as i32,
                0,
                seed,
            );
            n += t.powi(4) * grad64(h, d[0], d[1], d[2]);
        }
    }
    32.0 * n
}

#[test]
fn simplex3_matches_gustavson_at_the_origin_and_far_away() {
    let m = noise(Basis::Simplex, 3, None);
    for (offset, z) in [(0.0, 0.0), (0.0, 29.3), (1.0e7, -1.0e7 + 3.1)] {
        let window = Window::new(50, 40).at([offset + 0.5, offset - 7.25], 0.61);
        let got = render(&m, z, &window);
        let mut worst = 0.0f64;
        for j in 0..window.height {
            for i in 0..window.width {
                let p = [window.x(i) / 16.0, window.y(j) / 16.0, z / 16.0];
                let r = simplex3_reference(p, m.seed);
                worst = worst.max((f64::from(got[j * window.width + i]) - r).abs());
            }
        }
        assert!(worst < 1e-5, "offset {offset}, z {z}: error {worst}");
    }
}

/// The bench-only relaxed evaluator (`set_relaxed`: f32 cell split, FMA) computes the same
/// noises, near the origin where an f32 position keeps its fraction: against the f64
/// references, within the exact path's bounds plus the f32 position's rounding (at most
/// 2⁻²⁴·|p| ≤ 2⁻²⁴·4 cells here, times a slope of at most 4 per cell: under 1e-6).
#[test]
fn relaxed_bench_variant_computes_the_same_noises_near_the_origin() {
    let window = Window::new(40, 30).at([-3.3, 1.9], 0.77);
    let z = 21.7;
    let cases: [(Basis, u32, f64); 6] = [
        (Basis::Gradient, 2, 2e-6 + 1e-6),
        (Basis::Gradient, 3, 2e-6 + 1e-6),
        (Basis::Value, 2, 2e-6 + 1e-6),
        (Basis::Value, 3, 2e-6 + 1e-6),
        (Basis::Simplex, 2, 1e-5 + 1e-6),
        (Basis::Simplex, 3, 1e-5 + 1e-6),
    ];
    for (basis, dims, bound) in cases {
        let m = noise(basis.clone(), dims, None);
        let mut e = ClassicEvaluator::new(&m, z);
        if !e.set_relaxed(true) {
            println!("no AVX2 and FMA: the relaxed variant is not available, nothing to check");
            return;
        }
        let mut got = vec![0.0f32; window.width * window.height];
        e.eval_rows(&window, 0, &mut got);
        let mut worst = 0.0f64;
        for j in 0..window.height {
            for i in 0..window.width {
                let p = [window.x(i) / 16.0, window.y(j) / 16.0, z / 16.0];
                let r = match (&basis, dims) {
                    (Basis::Simplex, 2) => simplex2_reference(p[0], p[1], 0, m.seed),
                    (Basis::Simplex, _) => simplex3_reference(p, m.seed),
                    (b, _) => lattice_reference(*b == Basis::Gradient, p, dims == 3, 0, m.seed),
                };
                worst = worst.max((f64::from(got[j * window.width + i]) - r).abs());
            }
        }
        assert!(worst < bound, "{basis:?} {dims}D relaxed: error {worst}");
    }
}
