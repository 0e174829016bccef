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
                let theta = match m.orientation {
                    Orientation::Anisotropic { angle } => f64::from(angle),
                    Orientation::Isotropic { min, max } => {
                        let u = f64::from(prng.next_f32());
                        f64::from(min) + u * (f64::from(max) - f64::from(min))
                    }
                };
                let (dx, dy) = (x - (f64::from(i) + ox) * r, y - (f64::from(j) + oy) * r);
                let d2 = dx * dx + dy * dy;
                if (d2 / (r * r) - 1.0).abs() < 2e-6 {
                    out.near_edge = true;
                }
                if d2 < r * r {
                    let phase = TAU * f0 * (theta.cos() * dx + theta.sin() * dy);
                    out.value += kw * (-PI * a * a * d2).exp() * phase.cos();
                    out.weight_sum += kw.abs();
                }
            }
        }
    }
    out
}
