//! Gabor noise against a slow f64 reference written from the randomness contract, the closed-form
//! variance of Lagae et al. (Campbell's theorem), and the location of its spectral peak.

use spectex_cpu::gabor::GaborEvaluator;
use spectex_model::random::Prng;
use spectex_model::{GaborNoise, Orientation};
use spectex_testkit::fixtures::gabor as model;
use spectex_testkit::reference::{self, GaborReference};
use std::f64::consts::{PI, TAU};

// ---------------------------------------------------------------------------------------------
// The error bound against the slow f64 reference (`spectex_testkit::reference::gabor`, the
// contract transcribed from the module doc).
// ---------------------------------------------------------------------------------------------

/// Error bound of the f32 evaluation, per unit of `Σ|K·w|`, derived from the evaluator's steps
/// (cell units; `2⁻²⁴ ≈ 6e-8` is an f32 half-ulp near 1):
/// - offsets: `uₓ` rounded to f32 (≤ 2⁻²⁵), `(uₓ − s) − o_x` two more roundings (≤ 2⁻²⁴ each):
///   `|δd| ≤ 1.5e-7` per component;
/// - Gaussian `exp(−ln 20·d²)`: `δ(d²) ≤ 2|d|·δd·2 + 3 ulp ≈ 8e-7`, times `ln 20 ≈ 3`, plus
///   `exp_poly`'s 1e-6: relative `≤ 3.5e-6`;
/// - cosine: the phase error is `≤ F₀r·(2·δd + 4·2⁻²⁴)` turns (offsets, `f` rounding, two
///   products and a sum, all of magnitude ≤ 2F₀r) → `2π·F₀r·6e-7`, plus `cos_turns`' 2e-7;
/// - summation of ≤ a few hundred terms in 8 lanes plus a 3-level tree: ≤ `50·2⁻²⁴·Σ|K·w|`.
///
/// This is a worst-case bound, linear in the number of terms; the measured errors are below a
/// tenth of it (the tests print the worst ratio with `--nocapture`).
fn tolerance(m: &GaborNoise, r: &GaborReference) -> f64 {
    let f_cell = largest_frequency(m) * m.kernel_radius();
    let per_weight = 3.5e-6 + 2e-7 + TAU * f_cell * 6e-7 + 50.0 * 6e-8;
    per_weight * r.weight_sum + 2f64.powi(-23) * r.value.abs()
}

/// The largest `|f|` an impulse may have, cycles per pixel: `F₀`, or a spectrum's largest.
fn largest_frequency(m: &GaborNoise) -> f64 {
    match &m.orientation {
        Orientation::Spectrum { frequencies, .. } => frequencies
            .iter()
            .map(|f| f64::from(f[0]).hypot(f64::from(f[1])))
            .fold(0.0, f64::max),
        _ => f64::from(m.frequency),
    }
}

/// A Gabor noise by example: four components (one of weight 0, never drawn), one at the
/// largest frequency the model accepts.
fn spectrum_model(seed: u32, ipk: f32) -> GaborNoise {
    model(
        seed,
        ipk,
        0.06,
        0.0,
        Orientation::Spectrum {
            frequencies: vec![[0.1, 0.02], [-0.05, 0.2], [0.3, -0.3], [0.0, 0.5]],
            weights: vec![2.0, 1.0, 0.0, 0.5],
        },
    )
}

/// Compares `eval` with the reference at every point; at most 1% of the points may be skipped
/// for lying on a truncation edge.
fn check_against_reference(case: &str, m: &GaborNoise, points: &[(f64, f64)]) {
    let g = GaborEvaluator::new(m);
    let (mut skipped, mut worst_ratio) = (0, 0.0f64);
    for (idx, &(x, y)) in points.iter().enumerate() {
        let want = reference::gabor(m, x, y);
        if want.near_edge {
            skipped += 1;
            continue;
        }
        let got = f64::from(g.eval(x, y));
        let tol = tolerance(m, &want);
        let err = (got - want.value).abs();
        worst_ratio = worst_ratio.max(err / tol);
        assert!(
            err <= tol,
            "{case}, seed {}: point #{idx} ({x}, {y}): eval {got} vs reference {} (error {err:e} > {tol:e})",
            m.seed,
            want.value
        );
    }
    assert!(
        skipped * 100 <= points.len(),
        "{case}: {skipped} of {} points on a truncation edge",
        points.len()
    );
    println!(
        "{case}: {} points, {skipped} skipped, worst error / tolerance {worst_ratio:.3}",
        points.len()
    );
}

/// `n` points uniform in `[cx − h, cx + h] × [cy − h, cy + h]`, from a fixed stream.
fn points_around(cx: f64, cy: f64, h: f64, n: usize, seed: u32) -> Vec<(f64, f64)> {
    let mut prng = Prng::new(seed);
    (0..n)
        .map(|_| {
            (
                cx + h * (2.0 * prng.next_f64() - 1.0),
                cy + h * (2.0 * prng.next_f64() - 1.0),
            )
        })
        .collect()
}

fn reference_models() -> Vec<(&'static str, GaborNoise)> {
    let aniso = |angle| Orientation::Anisotropic { angle };
    vec![
        ("anisotropic ipk 8", model(1, 8.0, 0.05, 0.0625, aniso(0.7))),
        (
            "anisotropic ipk 1",
            model(2, 1.0, 0.05, 0.0625, aniso(-2.0)),
        ),
        ("anisotropic narrow", model(3, 32.0, 0.2, 0.25, aniso(0.0))),
        ("anisotropic wide", model(4, 16.0, 0.01, 0.45, aniso(1.3))),
        (
            "isotropic full",
            model(
                5,
                16.0,
                0.05,
                0.125,
                Orientation::Isotropic {
                    min: 0.0,
                    max: TAU as f32,
                },
            ),
        ),
        (
            "isotropic sector",
            model(
                6,
                64.0,
                0.08,
                0.1,
                Orientation::Isotropic { min: 0.3, max: 2.5 },
            ),
        ),
        (
            "isotropic far angles",
            model(
                7,
                4.0,
                0.05,
                0.05,
                Orientation::Isotropic {
                    min: -40.0,
                    max: -38.0,
                },
            ),
        ),
        (
            "renormalised count (λ ≈ 95)",
            model(8, 300.0, 0.1, 0.0625, aniso(0.2)),
        ),
        ("spectrum (by example)", spectrum_model(9, 24.0)),
    ]
}

#[test]
fn eval_matches_the_reference_near_the_origin_and_at_negative_coordinates() {
    for (case, m) in reference_models() {
        let r = m.kernel_radius();
        let mut points = points_around(0.0, 0.0, 4.0 * r, 300, 11);
        points.extend(points_around(-1234.5, -987.25, 3.0 * r, 200, 12));
        // Cell boundaries and exact multiples of r, where floor() matters.
        for k in -3..=3 {
            points.push((f64::from(k) * r, -f64::from(k) * r));
            points.push((f64::from(k) * r - 1e-9, 0.5 * r));
        }
        check_against_reference(case, &m, &points);
    }
}

/// Invariant 2 of docs/ARCHITECTURE.md: a window at `(10⁷, 10⁷)` (and farther) is as precise as one at the
/// origin, with the same tolerance.
#[test]
fn eval_is_as_precise_far_away() {
    for (case, m) in reference_models() {
        let r = m.kernel_radius();
        let mut points = points_around(1e7, 1e7, 3.0 * r, 250, 21);
        points.extend(points_around(-1e7, 3e6, 3.0 * r, 100, 22));
        points.extend(points_around(1e9, -1e9, 3.0 * r, 100, 23));
        check_against_reference(case, &m, &points);
    }
}

// ---------------------------------------------------------------------------------------------
// Bits: rows against points, purity, seeds.
// ---------------------------------------------------------------------------------------------

#[test]
fn eval_row_is_eval_bit_for_bit() {
    let rows: [(f64, f64, f64, usize); 8] = [
        (0.0, 0.0, 1.0, 200),
        (-37.25, -100.5, 1.0, 300),
        (1e7 + 0.5, 1e7 - 64.0, 1.0, 257),
        (12.0, 5.0, 0.37, 400),
        (-3.0, 50.0, -0.5, 200),
        (7.0, -500.0, 25.0, 64), // steps wider than a cell: columns are skipped
        (7.0, 3.0, 0.0, 16),
        (-9e6, 4e6, 0.25, 100),
    ];
    for (case, m) in reference_models() {
        let g = GaborEvaluator::new(&m);
        for &(y, x0, dx, n) in &rows {
            let mut out = vec![f32::NAN; n];
            g.eval_row(y, x0, dx, &mut out);
            for (i, v) in out.iter().enumerate() {
                let x = x0 + i as f64 * dx;
                let want = g.eval(x, y);
                assert_eq!(
                    v.to_bits(),
                    want.to_bits(),
                    "{case}, seed {}: row y={y} x0={x0} dx={dx}, first differing index {i}: {v} vs {want}",
                    m.seed
                );
            }
        }
    }
}

#[test]
fn values_are_pure_and_seeds_differ() {
    let (_, m) = &reference_models()[0];
    let a = GaborEvaluator::new(m);
    let b = GaborEvaluator::new(m);
    let mut other = m.clone();
    other.seed += 1;
    let c = GaborEvaluator::new(&other);
    let (mut row_a, mut row_b, mut row_c) =
        (vec![0.0f32; 512], vec![0.0f32; 512], vec![0.0f32; 512]);
    let mut differing = 0;
    for y in -8..8 {
        let y = f64::from(y) * 3.5;
        a.eval_row(y, -100.0, 0.75, &mut row_a);
        b.eval_row(y, -100.0, 0.75, &mut row_b);
        c.eval_row(y, -100.0, 0.75, &mut row_c);
        for i in 0..row_a.len() {
            assert_eq!(row_a[i].to_bits(), row_b[i].to_bits(), "y={y}, index {i}");
            assert_eq!(
                row_a[i].to_bits(),
                a.eval(-100.0 + i as f64 * 0.75, y).to_bits(),
                "y={y}, index {i}"
            );
            differing += usize::from(row_a[i] != row_c[i]);
        }
    }
    assert!(
        differing > 16 * 512 * 9 / 10,
        "only {differing} pixels differ between seeds"
    );
}

// ---------------------------------------------------------------------------------------------
// Statistics: mean and variance against Campbell's theorem.
// ---------------------------------------------------------------------------------------------

/// `∫ g(d)^p dd` over the truncated disk, for the anisotropic kernel along x (the integral does
/// not depend on the direction), by the midpoint rule on a 1000×1000 grid over `[−r, r]²`.
fn kernel_power_integral(m: &GaborNoise, p: i32) -> f64 {
    let r = m.kernel_radius();
    let (a, f0, k) = (
        f64::from(m.bandwidth),
        f64::from(m.frequency),
        f64::from(m.amplitude),
    );
    let n = 1000;
    let h = 2.0 * r / f64::from(n);
    let mut sum = 0.0;
    for iy in 0..n {
        let y = -r + (f64::from(iy) + 0.5) * h;
        for ix in 0..n {
            let x = -r + (f64::from(ix) + 0.5) * h;
            let d2 = x * x + y * y;
            if d2 < r * r {
                sum += (k * (-PI * a * a * d2).exp() * (TAU * f0 * x).cos()).powi(p);
            }
        }
    }
    sum * h * h
}

/// Campbell's theorem for the compound Poisson process `n = mean + Σ w_k g(x − x_k)` with
/// impulse density `λ_d = impulses_per_kernel / (π r²)` and weights uniform in `[−1, 1]`:
/// `E n = mean`, `Var n = λ_d·E[w²]·∫g²` with `E[w²] = 1/3`, and the fourth cumulant
/// `κ₄ = λ_d·E[w⁴]·∫g⁴` with `E[w⁴] = 1/5`. (Lagae et al. §3.3 give `Var ≈ λ_d K²/(4a²)·E[w²]`
/// for the untruncated kernel with `F₀ ≫ a`; here the truncated integral is computed exactly.)
///
/// Samples lie on a grid of pitch `2r + 1` px, so their disks of influence are disjoint and the
/// values are independent. With `N = 256²` samples, the sample mean has standard error `σ/√N` and
/// the sample variance `√((κ₄ + 2σ⁴)/N)`; the tolerance is 5 standard errors (about 3.5% of the
/// variance for ipk = 8, 2% for ipk = 32).
#[test]
fn mean_and_variance_match_campbells_theorem() {
    let cases = [
        (
            "anisotropic ipk 8",
            model(
                31,
                8.0,
                0.05,
                0.0625,
                Orientation::Anisotropic { angle: 0.4 },
            ),
        ),
        (
            "isotropic ipk 32",
            model(
                32,
                32.0,
                0.05,
                0.1,
                Orientation::Isotropic {
                    min: 0.0,
                    max: TAU as f32,
                },
            ),
        ),
        (
            "anisotropic low frequency",
            model(33, 16.0, 0.1, 0.02, Orientation::Anisotropic { angle: 2.0 }),
        ),
    ];
    for (case, m) in cases {
        let g = GaborEvaluator::new(&m);
        let r = m.kernel_radius();
        let density = f64::from(m.impulses_per_kernel) / (PI * r * r);
        let var = density / 3.0 * kernel_power_integral(&m, 2);
        let kappa4 = density / 5.0 * kernel_power_integral(&m, 4);
        let side = 256;
        let pitch = 2.0 * r + 1.0;
        let mut row = vec![0.0f32; side];
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for iy in 0..side {
            g.eval_row(-5000.0 + iy as f64 * pitch, 1234.5, pitch, &mut row);
            for &v in &row {
                let v = f64::from(v) - f64::from(m.mean);
                s1 += v;
                s2 += v * v;
            }
        }
        let n = (side * side) as f64;
        let mean_dev = s1 / n;
        let sample_var = s2 / n - mean_dev * mean_dev;
        let se_mean = (var / n).sqrt();
        let se_var = ((kappa4 + 2.0 * var * var) / n).sqrt();
        println!(
            "{case}: variance {sample_var:.5} vs {var:.5} ({:+.2}%, tolerance {:.2}%), mean offset {mean_dev:.2e}",
            100.0 * (sample_var / var - 1.0),
            500.0 * se_var / var
        );
        assert!(
            mean_dev.abs() < 5.0 * se_mean,
            "{case}, seed {}: mean offset {mean_dev} vs standard error {se_mean}",
            m.seed
        );
        assert!(
            (sample_var - var).abs() < 5.0 * se_var,
            "{case}, seed {}: variance {sample_var} vs Campbell {var} (standard error {se_var})",
            m.seed
        );
    }
}

/// Gabor noise by example: the sample variance of many independent samples against Campbell's
/// theorem over the component marks, `Var = λ_d/3 · Σ_k p_k ∫g_k²` with `p_k = w_k/Σw` and
/// `∫g_k²` the anisotropic kernel's integral at `F₀ = |f_k|` (this file's 1000² grid), and
/// that against the model's own `amplitude · unit_std_dev()` (the model crate's 400² grid).
/// Tolerance: 5 standard errors, as above.
#[test]
fn spectrum_variance_matches_campbell_and_unit_std_dev() {
    let m = spectrum_model(51, 24.0);
    let Orientation::Spectrum {
        frequencies,
        weights,
    } = &m.orientation
    else {
        unreachable!("a spectrum model")
    };
    let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
    let r = m.kernel_radius();
    let density = f64::from(m.impulses_per_kernel) / (PI * r * r);
    let (mut var, mut kappa4) = (0.0, 0.0);
    for (f, &w) in frequencies.iter().zip(weights) {
        let mut one = m.clone();
        one.frequency = f64::from(f[0]).hypot(f64::from(f[1])) as f32;
        one.orientation = Orientation::Anisotropic { angle: 0.0 };
        let p = f64::from(w) / total;
        var += p * density / 3.0 * kernel_power_integral(&one, 2);
        kappa4 += p * density / 5.0 * kernel_power_integral(&one, 4);
    }
    let model_var = (f64::from(m.amplitude) * m.unit_std_dev()).powi(2);
    assert!(
        (model_var / var - 1.0).abs() < 1e-3,
        "unit_std_dev gives variance {model_var}, Campbell's integral {var}"
    );
    let g = GaborEvaluator::new(&m);
    let side = 256;
    let pitch = 2.0 * r + 1.0;
    let mut row = vec![0.0f32; side];
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for iy in 0..side {
        g.eval_row(-7000.0 + iy as f64 * pitch, 321.5, pitch, &mut row);
        for &v in &row {
            let v = f64::from(v) - f64::from(m.mean);
            s1 += v;
            s2 += v * v;
        }
    }
    let n = (side * side) as f64;
    let mean_dev = s1 / n;
    let sample_var = s2 / n - mean_dev * mean_dev;
    let se_var = ((kappa4 + 2.0 * var * var) / n).sqrt();
    println!(
        "spectrum: variance {sample_var:.5} vs {var:.5} ({:+.2}%, tolerance {:.2}%)",
        100.0 * (sample_var / var - 1.0),
        500.0 * se_var / var
    );
    assert!(
        (sample_var - var).abs() < 5.0 * se_var,
        "seed {}: variance {sample_var} vs Campbell {var} (standard error {se_var})",
        m.seed
    );
}

// ---------------------------------------------------------------------------------------------
// Spectrum: the power peaks at ±F₀ω.
// ---------------------------------------------------------------------------------------------

/// Periodogram `|DFT|²` of an `n×n` image (row-major, `[y][x]`) by the separable naive DFT.
fn periodogram(img: &[f64], n: usize) -> Vec<f64> {
    let tw: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let t = -TAU * k as f64 / n as f64;
            (t.cos(), t.sin())
        })
        .collect();
    // Rows: over x.
    let mut rows = vec![(0.0, 0.0); n * n];
    for y in 0..n {
        for kx in 0..n {
            let (mut re, mut im) = (0.0, 0.0);
            for x in 0..n {
                let (c, s) = tw[(kx * x) % n];
                re += img[y * n + x] * c;
                im += img[y * n + x] * s;
            }
            rows[y * n + kx] = (re, im);
        }
    }
    // Columns: over y.
    let mut power = vec![0.0; n * n];
    for kx in 0..n {
        for ky in 0..n {
            let (mut re, mut im) = (0.0, 0.0);
            for y in 0..n {
                let (c, s) = tw[(ky * y) % n];
                let (a, b) = rows[y * n + kx];
                re += a * c - b * s;
                im += a * s + b * c;
            }
            power[ky * n + kx] = re * re + im * im;
        }
    }
    power
}

/// An anisotropic model with `F₀ = 1/8` cycles/px along x: the averaged periodogram of 128×128
/// renders peaks at `(±16, 0)` bins within one bin. `a = 0.02` makes the spectral Gaussian
/// `exp(−2π|f − F₀ω|²/a²)` 0.72 bins wide (std), so bins two away have 2% of the peak's expected
/// power; averaging 8 disjoint windows keeps the periodogram's exponential scatter from moving
/// the maximum there.
#[test]
fn power_spectrum_peaks_at_the_kernel_frequency() {
    let m = model(
        41,
        16.0,
        0.02,
        0.125,
        Orientation::Anisotropic { angle: 0.0 },
    );
    let g = GaborEvaluator::new(&m);
    let n = 128;
    let mut avg = vec![0.0; n * n];
    let mut row = vec![0.0f32; n];
    for w in 0..8 {
        let (ox, oy) = (w as f64 * 1000.0 - 3000.0, -(w as f64) * 700.0);
        let mut img = vec![0.0; n * n];
        for y in 0..n {
            g.eval_row(oy + y as f64, ox, 1.0, &mut row);
            for x in 0..n {
                img[y * n + x] = f64::from(row[x]);
            }
        }
        let mean = img.iter().sum::<f64>() / (n * n) as f64;
        img.iter_mut().for_each(|v| *v -= mean);
        for (a, p) in avg.iter_mut().zip(periodogram(&img, n)) {
            *a += p;
        }
    }
    let signed = |k: usize| {
        if k < n / 2 {
            k as i64
        } else {
            k as i64 - n as i64
        }
    };
    let (best, _) = avg
        .iter()
        .enumerate()
        .skip(1)
        .fold((0, f64::MIN), |b, (i, &p)| if p > b.1 { (i, p) } else { b });
    let (ky, kx) = (signed(best / n), signed(best % n));
    let expected = (f64::from(m.frequency) * n as f64) as i64;
    assert!(
        (kx.abs() - expected).abs() <= 1 && ky.abs() <= 1,
        "seed {}: peak at bin (kx {kx}, ky {ky}), expected (±{expected}, 0)",
        m.seed
    );
}
