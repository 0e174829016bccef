//! Slow, obviously-correct f64 references shared by the CPU and GPU tests: each model's
//! definition summed directly with libm, drawing in the randomness contract's order (written
//! from the model docs, independently of either evaluator).

use std::f64::consts::{PI, TAU};

use spectex_model::random::{Prng, cell_hash};
use spectex_model::window::kaiser_bessel;
use spectex_model::{GaborNoise, LrpNoise, Orientation};

/// LRP noise (Gilet et al. 2014, Eqs. 1–2) at `(x, y)` pixels: every lattice point within two
/// cells of the point (one ring more than the support needs), its draws in the contract's
/// order, the arguments relative to the lattice point.
#[must_use]
pub fn lrp(m: &LrpNoise, x: f64, y: f64) -> f64 {
    let mut sum = f64::from(m.mean);
    for (s, st) in m.strata.iter().enumerate() {
        let d = f64::from(st.window_width);
        let (cx, cy) = ((x / d).round() as i64, (y / d).round() as i64);
        for ly in cy - 2..=cy + 2 {
            for lx in cx - 2..=cx + 2 {
                let (px, py) = (x - lx as f64 * d, y - ly as f64 * d);
                let w = kaiser_bessel((px * px + py * py).sqrt() / d);
                let mut prng = Prng::new(cell_hash(lx as i32, ly as i32, s as u32, m.seed));
                let mut c = 0.0;
                for table in &st.sub_strata {
                    let f = table[(prng.next_u32() % table.len() as u32) as usize];
                    let phase = f64::from(prng.next_f32());
                    let turns = f64::from(f[0]) * px + f64::from(f[1]) * py + phase;
                    c += (TAU * turns).cos();
                }
                sum += f64::from(st.amplitude) * w * c;
            }
        }
    }
    sum
}

/// The per-cell impulse count of Gabor noise: Knuth's product of f32 uniforms against `exp(−λ)`,
/// renormalised by `exp(64)` per 64 of λ, capped at `⌊4λ + 32⌋` (integer and exact f32 work:
/// every evaluator must agree exactly).
pub fn gabor_count(prng: &mut Prng, lambda: f64) -> u32 {
    let chunks0 = (lambda / 64.0).floor();
    let threshold = (-(lambda - 64.0 * chunks0)).exp() as f32;
    let (up, down) = (64f64.exp() as f32, (-64f64).exp() as f32);
    let cap = (4.0 * lambda + 32.0).floor() as u32;
    let mut chunks = chunks0 as u32;
    let mut p = 1.0f32;
    for k in 0..cap {
        p *= prng.next_f32();
        while chunks > 0 && p < down {
            p *= up;
            chunks -= 1;
        }
        if chunks == 0 && p < threshold {
            return k;
        }
    }
    cap
}

/// A Gabor noise value and what its error bound needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaborReference {
    /// The value.
    pub value: f64,
    /// `Σ|K·w|` over contributing impulses: the scale of an f32 evaluation's error.
    pub weight_sum: f64,
    /// Some impulse lies within 2e-6 (relative) of the truncation radius, where a rounding may
    /// legitimately switch a `0.05·K·w` step on or off (a point has such an impulse with
    /// probability ≈ `2·impulses_per_kernel·2e-6`).
    pub near_edge: bool,
}

/// Gabor noise (Lagae et al. 2009) at `(x, y)` pixels: a direct sum over the 5×5 cells around
/// the point (one ring more than an evaluator's 3×3, so a wrong neighbourhood shows up), each
/// cell's impulses drawn in the contract's order (count, offsets, weight, direction).
#[must_use]
pub fn gabor(m: &GaborNoise, x: f64, y: f64) -> GaborReference {
    let r = m.kernel_radius();
    let (ci, cj) = ((x / r).floor() as i32, (y / r).floor() as i32);
    let a = f64::from(m.bandwidth);
    let f0 = f64::from(m.frequency);
    let mut out = GaborReference {
        value: f64::from(m.mean),
        weight_sum: 0.0,
        near_edge: false,
    };
    for j in cj - 2..=cj + 2 {
        for i in ci - 2..=ci + 2 {
            let mut prng = Prng::new(cell_hash(i, j, 0, m.seed));
            let n = gabor_count(&mut prng, m.impulses_per_cell());
            for _ in 0..n {
                let ox = f64::from(prng.next_f32());
                let oy = f64::from(prng.next_f32());
                let kw = f64::from(m.amplitude) * (2.0 * f64::from(prng.next_f32()) - 1.0);
                // The frequency vector, cycles per pixel.
                let (fx, fy) = match &m.orientation {
                    &Orientation::Anisotropic { angle } => {
                        let theta = f64::from(angle);
                        (f0 * theta.cos(), f0 * theta.sin())
                    }
                    &Orientation::Isotropic { min, max } => {
                        let u = f64::from(prng.next_f32());
                        let theta = f64::from(min) + u * (f64::from(max) - f64::from(min));
                        (f0 * theta.cos(), f0 * theta.sin())
                    }
                    Orientation::Spectrum {
                        frequencies,
                        weights,
                    } => {
                        // The component whose cumulative interval holds u, by a linear scan
                        // (the evaluators search the table otherwise).
                        let u = prng.next_f32();
                        let cumulative = spectex_model::cumulative_weights(weights);
                        let k = cumulative
                            .iter()
                            .position(|&c| u < c)
                            .unwrap_or(cumulative.len() - 1);
                        (f64::from(frequencies[k][0]), f64::from(frequencies[k][1]))
                    }
                };
                let (dx, dy) = (x - (f64::from(i) + ox) * r, y - (f64::from(j) + oy) * r);
                let d2 = dx * dx + dy * dy;
                if (d2 / (r * r) - 1.0).abs() < 2e-6 {
                    out.near_edge = true;
                }
                if d2 < r * r {
                    let phase = TAU * (fx * dx + fy * dy);
                    out.value += kw * (-PI * a * a * d2).exp() * phase.cos();
                    out.weight_sum += kw.abs();
                }
            }
        }
    }
    out
}

/// Kensler noise's corner gradient (unit vector) from the report's definition as
/// `spectex_model::classic` documents it: the xor `h = P_x[i] ⊕ P_y[j] (⊕ P_z[k])` of per-axis
/// entries `P_a[n] = cell_hash(n, a, o, seed)`, then `hash(h)`: in 2D the direction at
/// `(hash(h) >> 29)·45°` (by `cos`/`sin` in f64), in 3D the cube edge `hash(h) % 12` in
/// Perlin's order `(±1, ±1, 0)`, `(±1, 0, ±1)`, `(0, ±1, ±1)` (bit 0 the first sign, bit 1
/// the second) over `√2`.
#[must_use]
pub fn kensler_gradient(corner: [i64; 3], three_d: bool, o: u32, seed: u32) -> [f64; 3] {
    let axis = |n: i64, a: i32| cell_hash(n as i32, a, o, seed);
    let mut h = axis(corner[0], 0) ^ axis(corner[1], 1);
    if three_d {
        h ^= axis(corner[2], 2);
    }
    let g = spectex_model::random::hash(h);
    if three_d {
        let e = g % 12;
        let s0 = if e & 1 == 1 { -1.0 } else { 1.0 };
        let s1 = if e & 2 == 2 { -1.0 } else { 1.0 };
        let v = match e / 4 {
            0 => [s0, s1, 0.0],
            1 => [s0, 0.0, s1],
            _ => [0.0, s0, s1],
        };
        v.map(|c| c / 2f64.sqrt())
    } else {
        let angle = f64::from(g >> 29) * PI / 4.0;
        [angle.cos(), angle.sin(), 0.0]
    }
}

/// The radial kernel of Kensler noise in f64: `fade(1 − r²/4)` for `r < 2`, else 0, with
/// `fade(t) = 6t⁵ − 15t⁴ + 10t³`; and its derivative with respect to `r`.
#[must_use]
pub fn kensler_kernel(r: f64) -> (f64, f64) {
    if r >= 2.0 {
        return (0.0, 0.0);
    }
    let t = 1.0 - r * r / 4.0;
    let w = t.powi(3) * (6.0 * t * t - 15.0 * t + 10.0);
    let dw_dt = 30.0 * t * t * (t - 1.0) * (t - 1.0);
    (w, dw_dt * (-r / 2.0))
}

/// One octave of Kensler noise (unscaled: the plain sum over corners) at `p` in cell units and
/// its gradient: every corner within 3 cells of `p` (one ring more than the kernel's support
/// needs) adds `w(|δ|)·(g·δ)`, `δ = p − corner`.
#[must_use]
pub fn kensler(p: [f64; 3], three_d: bool, o: u32, seed: u32) -> (f64, [f64; 3]) {
    let base = p.map(|c| c.floor() as i64);
    let reach_z = if three_d { 3 } else { 0 };
    let (mut value, mut gradient) = (0.0, [0.0; 3]);
    for dz in -reach_z..=reach_z {
        for dy in -3..=3 {
            for dx in -3..=3 {
                let c = [base[0] + dx, base[1] + dy, base[2] + dz];
                let d = [
                    p[0] - c[0] as f64,
                    p[1] - c[1] as f64,
                    if three_d { p[2] - c[2] as f64 } else { 0.0 },
                ];
                let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let (w, dw) = kensler_kernel(r);
                if w == 0.0 {
                    continue;
                }
                let g = kensler_gradient(c, three_d, o, seed);
                let dot = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
                value += w * dot;
                for a in 0..3 {
                    let radial = if r > 0.0 { dw * d[a] / r * dot } else { 0.0 };
                    gradient[a] += radial + w * g[a];
                }
            }
        }
    }
    (value, gradient)
}
