//! Kensler's better gradient noise (`Basis::Kensler`) against its definition: a slow f64 sum over
//! every corner within 3 cells (`spectex_testkit::reference::kensler`) near the origin and at
//! 10⁷, finite differences against that sum's analytic gradient (at lattice points and between
//! them), the kernel's support, and the variance and variogram (isotropy) against closed forms
//! integrated here from the kernel alone.

use spectex_cpu::classic::ClassicEvaluator;
use spectex_model::classic::{
    Basis, ClassicNoise, KENSLER_RADIUS2, KENSLER2_SCALE, KENSLER3_SCALE, kensler_weight,
};
use spectex_model::random::Prng;
use spectex_testkit::reference;

const SEED: u32 = 21;

fn model(dimensions: u32, cell: f32) -> ClassicNoise {
    let m = ClassicNoise {
        seed: SEED,
        dimensions,
        cell_size: cell,
        basis: Basis::Kensler,
        fractal: None,
        amplitude: 1.0,
        mean: 0.0,
    };
    m.validate().expect("test model is valid");
    m
}

fn scale(dimensions: u32) -> f64 {
    f64::from(if dimensions == 3 {
        KENSLER3_SCALE
    } else {
        KENSLER2_SCALE
    })
}

/// `∫₀² w(r)² r^power dr` by the midpoint rule (f64, 20 000 steps).
fn radial_integral(power: i32) -> f64 {
    let steps = 20_000;
    let h = 2.0 / f64::from(steps);
    (0..steps)
        .map(|i| {
            let r = (f64::from(i) + 0.5) * h;
            reference::kensler_kernel(r).0.powi(2) * r.powi(power)
        })
        .sum::<f64>()
        * h
}

#[test]
fn matches_the_f64_definition_near_and_far() {
    // f32 offsets (2⁻²⁴ of a cell) through slopes of about 1 per cell, and up to 64 f32 terms
    // of magnitude below 2 summed: a few 10⁻⁶; a wrong corner or gradient is ≥ 10⁻².
    const TOLERANCE: f64 = 2e-5;
    let z = 37.3;
    for dims in [2, 3] {
        let m = model(dims, 16.0);
        let eval = ClassicEvaluator::new(&m, z);
        let mut prng = Prng::new(5);
        for offset in [[-3.3, 5.1], [1.0e7, -3.0e6]] {
            let mut worst = 0.0f64;
            for k in 0..300 {
                let x = offset[0] + 160.0 * prng.next_f64();
                let y = offset[1] + 160.0 * prng.next_f64();
                let p = [x / 16.0, y / 16.0, z / 16.0];
                let want = scale(dims) * reference::kensler(p, dims == 3, 0, SEED).0;
                let got = f64::from(eval.eval(x, y));
                let e = (got - want).abs();
                assert!(
                    e <= TOLERANCE,
                    "{dims}D at ({x}, {y}) (point {k}): CPU {got} vs f64 {want}"
                );
                worst = worst.max(e);
            }
            eprintln!("kensler {dims}D at {offset:?}: max |CPU − f64| = {worst:.2e}");
        }
    }
}

/// Central differences of the CPU noise equal the analytic gradient of the definition: at a
/// lattice point it is the point's own hashed gradient plus its neighbours' kernel slopes
/// (the extended kernel does not vanish at the neighbours), between them the full sum.
#[test]
fn finite_differences_match_the_hashed_gradients() {
    let cell = 16.0;
    // Step 2⁻⁷ cell (0.125 px): truncation ~h²·|∂³n| ≈ 10⁻⁴, f32 rounding ≈ 10⁻⁷/h ≈ 10⁻⁵.
    let h = cell / 128.0;
    const TOLERANCE: f64 = 2e-3;
    for dims in [2, 3] {
        let m = model(dims, cell as f32);
        // Plane z on a lattice plane in 3D, so that (i, j) points are lattice points.
        let z = 3.0 * cell;
        let eval = ClassicEvaluator::new(&m, z);
        let mut prng = Prng::new(17);
        let mut points: Vec<[f64; 2]> = (0..12)
            .map(|k| [f64::from(k - 6) * cell, f64::from(2 * k - 9) * cell])
            .collect();
        points.extend((0..24).map(|_| [200.0 * prng.next_f64(), 200.0 * prng.next_f64()]));
        for (k, [x, y]) in points.into_iter().enumerate() {
            let p = [x / cell, y / cell, z / cell];
            let (_, g) = reference::kensler(p, dims == 3, 0, SEED);
            let dx = (f64::from(eval.eval(x + h, y)) - f64::from(eval.eval(x - h, y))) / (2.0 * h);
            let dy = (f64::from(eval.eval(x, y + h)) - f64::from(eval.eval(x, y - h))) / (2.0 * h);
            // The definition's gradient is per cell; the differences per pixel.
            let want = [g[0], g[1]].map(|c| scale(dims) * c / cell);
            for (axis, (got, want)) in [(dx, want[0]), (dy, want[1])].into_iter().enumerate() {
                assert!(
                    (got - want).abs() * cell <= TOLERANCE,
                    "{dims}D point {k} ({x}, {y}) axis {axis}: difference {got} vs gradient {want}"
                );
            }
        }
    }
}

#[test]
fn the_kernel_has_radius_two_cells() {
    assert_eq!(KENSLER_RADIUS2, 4.0);
    assert_eq!(kensler_weight(0.0), 1.0);
    for r2 in [4.0f32, 4.000_001, 4.5, 9.0, 1e6] {
        assert_eq!(kensler_weight(r2), 0.0, "w at r² = {r2}");
    }
    for r2 in [0.5f32, 1.0, 2.0, 3.9] {
        assert!(kensler_weight(r2) > 0.0, "w at r² = {r2}");
    }
    // C² at the rim: w ~ 10·(1 − r²/4)³ as r → 2, so a step 10⁻² inside is below 10⁻⁴.
    let inside = 2.0f32 - 1e-2;
    assert!(kensler_weight(inside * inside) < 1e-4);
    // The f32 kernel against the f64 one.
    for k in 0..200 {
        let r = f64::from(k) / 100.0;
        let got = f64::from(kensler_weight((r * r) as f32));
        assert!(
            (got - reference::kensler_kernel(r).0).abs() < 1e-6,
            "r = {r}"
        );
    }
}

/// Mean 0 and variance `scale²·σ²` with `σ² = (1/d)∫ w(|δ|)²|δ|² dδ` (independent corners
/// with `E[g gᵀ] = I/d`), the integral computed here from the kernel: 2D over a 512² render of
/// cells of 4.37 pixels (13 700 cells, offsets spread over the cell), 3D over 8 planes.
#[test]
fn variance_matches_the_closed_form() {
    let pi = std::f64::consts::PI;
    let closed = [
        (2, 0.5 * 2.0 * pi * radial_integral(3)),
        (3, (1.0 / 3.0) * 4.0 * pi * radial_integral(4)),
    ];
    for (dims, sigma2) in closed {
        let m = model(dims, 4.37);
        let planes: Vec<f64> = if dims == 3 {
            (0..8)
                .map(|k| 4.37 * (f64::from(k) + 0.5) / 8.0 + 100.0)
                .collect()
        } else {
            vec![0.0]
        };
        let side = if dims == 3 { 192 } else { 512 };
        let (mut sum, mut sum2, mut count) = (0.0, 0.0, 0.0);
        for z in planes {
            let eval = ClassicEvaluator::new(&m, z);
            let window = spectex_model::Window::new(side, side);
            let mut out = vec![0.0f32; side * side];
            eval.eval_rows(&window, 0, &mut out);
            for v in out {
                let v = f64::from(v);
                sum += v;
                sum2 += v * v;
                count += 1.0;
            }
        }
        let mean = sum / count;
        let variance = sum2 / count - mean * mean;
        let want = scale(dims).powi(2) * sigma2;
        eprintln!(
            "kensler {dims}D: variance {variance:.5} vs closed form {want:.5}, mean {mean:.4}"
        );
        // Relative standard error of a variance over ~3000 correlation areas: ~2.5%.
        assert!(
            (variance / want - 1.0).abs() < 0.1,
            "{dims}D: variance {variance} vs closed form {want}"
        );
        assert!(mean.abs() < 0.02, "{dims}D: mean {mean}");
    }
}

/// The variogram `γ(L·e_θ) = E[(n(x + L e_θ) − n(x))²]` at `L = ½` cell is the same in every
/// direction and equals `2·scale²·(σ² − C(L))`, `C(L) = ½∫ ψ(δ)·ψ(δ + L e_x) dδ` with
/// `ψ(δ) = w(|δ|)δ`, integrated here on a 600² grid: the spectrum is isotropic (Perlin's
/// tensor-product kernel is not). 20 000 pairs at random positions per direction: a relative
/// standard error of 1%.
#[test]
fn the_variogram_is_isotropic_and_matches_the_closed_form() {
    let lag = 0.5;
    let n = 600;
    let h = 4.0 / f64::from(n);
    let psi = |x: f64, y: f64| {
        let w = reference::kensler_kernel((x * x + y * y).sqrt()).0;
        [w * x, w * y]
    };
    let (mut c0, mut cl) = (0.0, 0.0);
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (
                -2.0 + (f64::from(i) + 0.5) * h,
                -2.0 + (f64::from(j) + 0.5) * h,
            );
            let a = psi(x, y);
            let b = psi(x + lag, y);
            c0 += a[0] * a[0] + a[1] * a[1];
            cl += a[0] * b[0] + a[1] * b[1];
        }
    }
    let (c0, cl) = (0.5 * c0 * h * h, 0.5 * cl * h * h);
    let want = 2.0 * scale(2).powi(2) * (c0 - cl);
    let cell = 16.0;
    let eval = ClassicEvaluator::new(&model(2, cell as f32), 0.0);
    let mut prng = Prng::new(99);
    let base: Vec<[f64; 2]> = (0..20_000)
        .map(|_| [1.0e5 * prng.next_f64(), 1.0e5 * prng.next_f64()])
        .collect();
    let mut at_base = vec![0.0f32; base.len()];
    eval.eval_points(&base, &mut at_base);
    for degrees in [0.0f64, 30.0, 45.0, 60.0, 90.0, 135.0] {
        let (s, c) = degrees.to_radians().sin_cos();
        let moved: Vec<[f64; 2]> = base
            .iter()
            .map(|p| [p[0] + lag * cell * c, p[1] + lag * cell * s])
            .collect();
        let mut at_moved = vec![0.0f32; moved.len()];
        eval.eval_points(&moved, &mut at_moved);
        let gamma = at_base
            .iter()
            .zip(&at_moved)
            .map(|(a, b)| (f64::from(*b) - f64::from(*a)).powi(2))
            .sum::<f64>()
            / base.len() as f64;
        eprintln!("kensler variogram at {degrees}°: {gamma:.5} vs closed form {want:.5}");
        assert!(
            (gamma / want - 1.0).abs() < 0.05,
            "direction {degrees}°: γ = {gamma} vs closed form {want}"
        );
    }
}
