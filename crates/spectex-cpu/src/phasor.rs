//! Phasor noise (Tricard, Efremov, Zanni, Neyret, Martínez & Lefebvre 2019) on the CPU, in 2D and
//! on slices of 3D.
//!
//! # The sum
//!
//! At a point `p`, `𝒢(p) = Σ_j a(p − x_j)·exp(i·2π(f_j·(p − x_j) + ψ_j))` over the impulses `x_j` within
//! the kernel radius `r` ([`PhasorNoise::kernel_radius`]), with `a(d) = exp(−π b²|d|²)` and the
//! frequency vector `f_j = F(x_j)·u_j` in cycles per pixel (Eqs. 10, 15). Space is cut into cells
//! of side `r` (squares, or cubes in 3D), so the impulses that reach `p` lie in the 3×3 (3×3×3)
//! cells around `p`'s cell. All arithmetic after locating `p` is f32 in cell units:
//! `d = (u − s) − o` for the point's offset `u ∈ [0, 1]` in its cell, the neighbour step
//! `s ∈ {−1, 0, 1}` and the impulse's offset `o` in its own cell, so precision does not depend
//! on how far from the origin the window is. An impulse contributes when `|d|² < 1`:
//! `g = exp_poly(−ln 20·|d|²)` (`π b² r² = ln 20`), `t = f·d + ψ` in turns (with `f` in turns
//! per cell), `re += g·cos_turns(t)`, `im += g·sin_turns(t)`, in the order: cell layers `s_z`,
//! rows `s_y`, columns `s_x` ascending, impulses in draw order.
//!
//! The phase offset `ψ_j`, uniform per impulse, is not in the paper's Eq. (5) but is standard in
//! Gabor noise: it makes every term's mean exactly 0, so `𝒢` is circularly symmetric and the
//! phase `φ` exactly uniform. Without it the mean of a term is the truncated kernel's Fourier
//! transform at `F`, whose side lobes (from the cut at 5% of the peak) are not negligible: a
//! PWM profile of duty 25% then came out 25.5% white at `F = 0.05`, `b = 0.02`, and 24.8% at
//! `b = 0.01` (measured), where the paper's Fig. 16 has 25.007%.
//!
//! Then `I = √(re² + im²)` (Eq. 8), `φ = atan2_turns(im, re)` in turns (Eq. 9), and the output is
//! `f(φ)` for the profile `f` (Eq. 4), `φ`, `I`, or `im = I·sin φ` (Gabor noise, Eq. 13).
//!
//! # Randomness contract (phasor: layers 0 and 1)
//!
//! Cell `(i, j)` of a 2D model draws from `Prng::new(cell_hash(i, j, layer, seed))`; cell
//! `(i, j, k)` of a 3D model from `Prng::new(cell_hash(i, j, layer, cell_hash(k, 0, layer,
//! seed)))`. Layer [`PHASOR_LAYER`] holds the kernels: a Poisson count (Knuth's product of
//! uniforms against `exp(−λ)` in f32, capped at `⌊4λ + 32⌋`), then per impulse its offsets
//! `u₁, u₂ (, u₃)` and, by orientation: none for `aligned` and `gradient` (the direction comes
//! from the field at the impulse), one uniform choosing the lobe for `two_lobes`, one (2D: the
//! angle in turns) or two (3D: `z = 2u − 1`, then the azimuth in turns) for `isotropic`, none
//! for `coherent`; last the phase offset `ψ` in turns. Layer [`DIRECTION_LAYER`] holds the coherent direction process (§3.2.2): its
//! own grid of side `r_f = r / bandwidth_ratio`, the same density, per impulse its offsets then
//! one uniform `v` (2D: angle `(2v − 1)·ω_f`) or two (3D: a direction in the cap of half-angle
//! `ω_f` around +x, `cos θ = 1 − v(1 − cos ω_f)`, azimuth `v'` turns).
//!
//! # Determinism
//!
//! Every pixel is a pure function of (model, position): any tiling and any thread count give the
//! same bits. Impulse draws are cached per band of rows, which changes nothing but speed.

use spectex_model::random::{Prng, cell_hash};
use spectex_model::{Field, PhasorNoise, PhasorOrientation, PhasorOutput, Profile, Window};

// The kernel shape, truncation and cell location are Gabor noise's (same 5% cut, same cells).
use crate::gabor::{NEG_LN_20, libm_exp, locate};
use crate::math::{atan2_turns, cos_turns, exp_poly, sin_turns};

/// Randomness-contract layer of the kernels.
pub const PHASOR_LAYER: u32 = 0;
/// Randomness-contract layer of the coherent direction process.
pub const DIRECTION_LAYER: u32 = 1;

/// One kernel, as the evaluation loop needs it.
#[derive(Debug, Clone, Copy)]
struct Impulse {
    /// Offset in its cell, cell units.
    o: [f32; 3],
    /// Phase offset `ψ_j`, turns.
    psi: f32,
    /// Frequency vector, turns per cell unit (`F·r·u`).
    f: [f32; 3],
}

/// A Poisson process of impulses on a grid of cells.
#[derive(Debug, Clone, Copy)]
struct Grid {
    /// Cell side, pixels.
    side: f64,
    layer: u32,
    /// `exp(−λ)` in f32.
    threshold: f32,
    /// `⌊4λ + 32⌋`.
    cap: u32,
}

impl Grid {
    fn new(side: f64, lambda: f64, layer: u32) -> Self {
        Self {
            side,
            layer,
            // `λ < 64` for valid models, so `exp(−λ)` is a normal f32.
            threshold: libm_exp(-lambda) as f32,
            cap: (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32,
        }
    }

    /// The PRNG of a cell, seeded by the contract (module doc).
    fn prng(&self, cell: [i32; 3], three_d: bool, seed: u32) -> Prng {
        let seed = if three_d {
            cell_hash(cell[2], 0, self.layer, seed)
        } else {
            seed
        };
        Prng::new(cell_hash(cell[0], cell[1], self.layer, seed))
    }

    /// Knuth's Poisson draw: multiply uniforms until the product falls below `exp(−λ)`.
    fn count(&self, prng: &mut Prng) -> u32 {
        let mut p = 1.0f32;
        let mut n = 0;
        while n < self.cap {
            p *= prng.next_f32();
            if p < self.threshold {
                return n;
            }
            n += 1;
        }
        n
    }

    /// `(cell, offset in [0, 1])` of a coordinate, or `None` out of range (NaN included).
    fn locate(&self, coord: f64) -> Option<(i32, f32)> {
        locate(coord, self.side)
    }
}

/// How impulse directions are made, with the constants precomputed.
#[derive(Debug, Clone)]
enum Directions {
    Aligned(Field),
    Gradient {
        image: Field,
        offset: f64,
    },
    TwoLobes {
        a: [f32; 3],
        b: [f32; 3],
    },
    Isotropic,
    Coherent {
        grid: Grid,
        spread_turns: f32,
        cap_cos: f32,
    },
}

/// A phasor noise model prepared for evaluation at a fixed `z` (ignored by 2D models).
#[derive(Debug, Clone)]
pub struct PhasorEvaluator {
    model: PhasorNoise,
    kernels: Grid,
    directions: Directions,
    three_d: bool,
    z: f64,
}

/// The impulses of one row of cells `(j, k)`, per column from `i0`.
#[derive(Debug)]
struct CellRow {
    j: i32,
    k: i32,
    i0: i32,
    columns: Vec<Vec<Impulse>>,
}

impl PhasorEvaluator {
    /// Prepares `model` (assumed validated) for evaluation on the plane `z` (pixels).
    #[must_use]
    pub fn new(model: &PhasorNoise, z: f64) -> Self {
        let radius = model.kernel_radius();
        let lambda = model.impulses_per_cell();
        let three_d = model.dimensions == 3;
        let directions = match &model.orientation {
            PhasorOrientation::Aligned { angle } => Directions::Aligned(angle.clone()),
            PhasorOrientation::Gradient { image, offset } => Directions::Gradient {
                image: image.clone(),
                offset: f64::from(*offset),
            },
            PhasorOrientation::TwoLobes { angle_a, angle_b } => {
                let turn = |a: f32| (f64::from(a) / std::f64::consts::TAU) as f32;
                let (ta, tb) = (turn(*angle_a), turn(*angle_b));
                let a = [cos_turns(ta), sin_turns(ta), 0.0];
                let mut b = [cos_turns(tb), sin_turns(tb), 0.0];
                // §3.2.1: beyond π/2 apart, reverse one lobe (the dual formulation).
                if a[0] * b[0] + a[1] * b[1] < 0.0 {
                    b = [-b[0], -b[1], 0.0];
                }
                Directions::TwoLobes { a, b }
            }
            PhasorOrientation::Isotropic => Directions::Isotropic,
            PhasorOrientation::Coherent {
                spread,
                bandwidth_ratio,
            } => {
                let spread_turns = (f64::from(*spread) / std::f64::consts::TAU) as f32;
                Directions::Coherent {
                    grid: Grid::new(
                        radius / f64::from(*bandwidth_ratio),
                        lambda,
                        DIRECTION_LAYER,
                    ),
                    spread_turns,
                    cap_cos: cos_turns(spread_turns),
                }
            }
        };
        Self {
            model: model.clone(),
            kernels: Grid::new(radius, lambda, PHASOR_LAYER),
            directions,
            three_d,
            z: if three_d { z } else { 0.0 },
        }
    }

    /// Kernel evaluations per pixel (every impulse of the neighbouring cells is visited), for
    /// reports: `9λ` in 2D, `27λ` in 3D.
    #[must_use]
    pub fn kernels_per_pixel(&self) -> f64 {
        let cells = if self.three_d { 27.0 } else { 9.0 };
        cells * self.model.impulses_per_cell()
    }

    /// The unit direction of the coherent field at `x` pixels (§3.2.2), f32.
    fn coherent_direction(
        &self,
        grid: &Grid,
        spread_turns: f32,
        cap_cos: f32,
        x: [f64; 3],
    ) -> [f32; 3] {
        let dims = if self.three_d { 3 } else { 2 };
        let mut cell = [0i32; 3];
        let mut u = [0.0f32; 3];
        for a in 0..dims {
            let Some((c, o)) = grid.locate(x[a]) else {
                return [1.0, 0.0, 0.0];
            };
            cell[a] = c;
            u[a] = o;
        }
        let mut sum = [0.0f32; 3];
        let zs: &[i32] = if self.three_d { &[-1, 0, 1] } else { &[0] };
        for &sz in zs {
            for sy in -1..=1 {
                for sx in -1..=1 {
                    let c = [cell[0] + sx, cell[1] + sy, cell[2] + sz];
                    let mut prng = grid.prng(c, self.three_d, self.model.seed);
                    for _ in 0..grid.count(&mut prng) {
                        let o = [
                            prng.next_f32(),
                            prng.next_f32(),
                            if self.three_d { prng.next_f32() } else { 0.0 },
                        ];
                        let dir = if self.three_d {
                            let v = prng.next_f32();
                            let w = prng.next_f32();
                            let c = 1.0 - v * (1.0 - cap_cos);
                            let s = (1.0 - c * c).max(0.0).sqrt();
                            [c, s * cos_turns(w), s * sin_turns(w)]
                        } else {
                            let t = (2.0 * prng.next_f32() - 1.0) * spread_turns;
                            [cos_turns(t), sin_turns(t), 0.0]
                        };
                        let d = [
                            (u[0] - sx as f32) - o[0],
                            (u[1] - sy as f32) - o[1],
                            if self.three_d {
                                (u[2] - sz as f32) - o[2]
                            } else {
                                0.0
                            },
                        ];
                        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        if d2 < 1.0 {
                            let g = exp_poly(NEG_LN_20 * d2);
                            for a in 0..3 {
                                sum[a] += g * dir[a];
                            }
                        }
                    }
                }
            }
        }
        let norm = (sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]).sqrt();
        if norm > 0.0 {
            [sum[0] / norm, sum[1] / norm, sum[2] / norm]
        } else {
            [1.0, 0.0, 0.0]
        }
    }

    /// The impulses of cell `(i, j, k)`, in draw order.
    fn draw_cell(&self, cell: [i32; 3], out: &mut Vec<Impulse>) {
        out.clear();
        let g = &self.kernels;
        let mut prng = g.prng(cell, self.three_d, self.model.seed);
        let n = g.count(&mut prng);
        let turn = std::f64::consts::TAU;
        for _ in 0..n {
            let o = [
                prng.next_f32(),
                prng.next_f32(),
                if self.three_d { prng.next_f32() } else { 0.0 },
            ];
            // The impulse's position in pixels, for the fields (f64).
            let x = [
                (f64::from(cell[0]) + f64::from(o[0])) * g.side,
                (f64::from(cell[1]) + f64::from(o[1])) * g.side,
                if self.three_d {
                    (f64::from(cell[2]) + f64::from(o[2])) * g.side
                } else {
                    0.0
                },
            ];
            let planar = |angle: f64| {
                let t = (angle / turn).rem_euclid(1.0) as f32;
                [cos_turns(t), sin_turns(t), 0.0]
            };
            let u = match &self.directions {
                Directions::Aligned(angle) => planar(angle.at(x[0], x[1], x[2])),
                Directions::Gradient { image, offset } => {
                    planar(image.gradient_angle(x[0], x[1]).unwrap_or(0.0) + offset)
                }
                Directions::TwoLobes { a, b } => {
                    if prng.next_f32() < 0.5 {
                        *a
                    } else {
                        *b
                    }
                }
                Directions::Isotropic => {
                    if self.three_d {
                        let z = 2.0 * prng.next_f32() - 1.0;
                        let s = (1.0 - z * z).max(0.0).sqrt();
                        let t = prng.next_f32();
                        [s * cos_turns(t), s * sin_turns(t), z]
                    } else {
                        let t = prng.next_f32();
                        [cos_turns(t), sin_turns(t), 0.0]
                    }
                }
                Directions::Coherent {
                    grid,
                    spread_turns,
                    cap_cos,
                } => self.coherent_direction(grid, *spread_turns, *cap_cos, x),
            };
            let psi = prng.next_f32();
            let fr = (self.model.frequency.at(x[0], x[1], x[2]).clamp(0.0, 0.5) * g.side) as f32;
            out.push(Impulse {
                o,
                psi,
                f: [fr * u[0], fr * u[1], fr * u[2]],
            });
        }
    }

    /// Holds the cell rows `(j + s_y, k + s_z)` for a row of pixels, columns `i0..=i1`.
    fn update_rows(&self, rows: &mut Vec<CellRow>, j: i32, k: i32, i0: i32, i1: i32) {
        let zs: &[i32] = if self.three_d { &[-1, 0, 1] } else { &[0] };
        let wanted: Vec<(i32, i32)> = zs
            .iter()
            .flat_map(|&sz| (-1..=1).map(move |sy| (j + sy, k + sz)))
            .collect();
        rows.retain(|r| {
            r.i0 == i0 && r.columns.len() == (i1 - i0 + 1) as usize && wanted.contains(&(r.j, r.k))
        });
        for &(cj, ck) in &wanted {
            if rows.iter().any(|r| r.j == cj && r.k == ck) {
                continue;
            }
            let columns = (i0..=i1)
                .map(|ci| {
                    let mut v = Vec::new();
                    self.draw_cell([ci, cj, ck], &mut v);
                    v
                })
                .collect();
            rows.push(CellRow {
                j: cj,
                k: ck,
                i0,
                columns,
            });
        }
        // Layers then rows ascending: the contract's summation order.
        rows.sort_unstable_by_key(|r| (r.k, r.j));
    }

    /// Evaluates consecutive rows of `window` from row `first` into `out` (whole rows).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let g = self.kernels;
        let (x_first, x_last) = (window.x(0), window.x(width - 1));
        let columns = g.locate(x_first).zip(g.locate(x_last));
        let z = if self.three_d {
            g.locate(self.z)
        } else {
            Some((0, 0.0))
        };
        let mut rows = Vec::new();
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let y = window.y(first + r);
            let (Some(((c0, _), (c1, _))), Some((cj, uy)), Some((ck, uz))) =
                (columns, g.locate(y), z)
            else {
                line.fill(0.0);
                continue;
            };
            self.update_rows(&mut rows, cj, ck, c0 - 1, c1 + 1);
            for (i, v) in line.iter_mut().enumerate() {
                let x = window.x(i);
                let Some((ci, ux)) = g.locate(x) else {
                    *v = 0.0;
                    continue;
                };
                let (re, im) = sum_at(&rows, ci, cj, ck, [ux, uy, uz]);
                *v = self.output(re, im, [x, y, self.z]);
            }
        }
    }

    /// The noise at `(x, y)` (and this evaluator's `z`): the same bits as any render.
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let w = Window::new(1, 1).at([x, y], 1.0);
        let mut out = [0.0f32];
        self.eval_rows(&w, 0, &mut out);
        out[0]
    }

    fn output(&self, re: f32, im: f32, p: [f64; 3]) -> f32 {
        let v = match self.model.output {
            PhasorOutput::Intensity => (re * re + im * im).sqrt(),
            PhasorOutput::Gabor => im,
            PhasorOutput::Phase => atan2_turns(im, re),
            PhasorOutput::Profiled => profile(&self.model.profile, re, im, p),
        };
        self.model.mean + self.model.amplitude * v
    }
}

/// `Σ` of the module doc at the point of cell `(ci, cj, ck)`, offset `u`.
fn sum_at(rows: &[CellRow], ci: i32, cj: i32, ck: i32, u: [f32; 3]) -> (f32, f32) {
    let (mut re, mut im) = (0.0f32, 0.0f32);
    for row in rows {
        let sy = row.j - cj;
        let sz = row.k - ck;
        let dy = u[1] - sy as f32;
        let dz = u[2] - sz as f32;
        for sx in -1..=1 {
            let Some(column) = usize::try_from(ci + sx - row.i0)
                .ok()
                .and_then(|c| row.columns.get(c))
            else {
                continue;
            };
            let dxs = u[0] - sx as f32;
            for imp in column {
                let d = [dxs - imp.o[0], dy - imp.o[1], dz - imp.o[2]];
                let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if d2 < 1.0 {
                    let g = exp_poly(NEG_LN_20 * d2);
                    let t = imp.f[0] * d[0] + imp.f[1] * d[1] + imp.f[2] * d[2] + imp.psi;
                    re += g * cos_turns(t);
                    im += g * sin_turns(t);
                }
            }
        }
    }
    (re, im)
}

/// The phase `atan2(im, re)` in turns, in `[0, 1)`.
fn phase01(re: f32, im: f32) -> f32 {
    let phase = atan2_turns(im, re);
    let t = if phase < 0.0 { phase + 1.0 } else { phase };
    if t >= 1.0 { 0.0 } else { t }
}

/// The profile of the phase at position `p`. The phase is only computed by the profiles that
/// read it (the sine is `im / I` directly).
fn profile(shape: &Profile, re: f32, im: f32, p: [f64; 3]) -> f32 {
    match shape {
        Profile::Sine => {
            let i = (re * re + im * im).sqrt();
            if i > 0.0 { im / i } else { 0.0 }
        }
        Profile::Square { duty } => {
            let d = duty.at(p[0], p[1], p[2]).clamp(0.0, 1.0) as f32;
            if phase01(re, im) < d { 1.0 } else { 0.0 }
        }
        Profile::Triangle => {
            let mut s = phase01(re, im) + 0.25;
            if s >= 1.0 {
                s -= 1.0;
            }
            1.0 - 4.0 * (s - 0.5).abs()
        }
        Profile::Sawtooth => 2.0 * phase01(re, im) - 1.0,
        Profile::Samples { values } => {
            let n = values.len();
            let pos = phase01(re, im) * n as f32;
            let i = (pos as usize).min(n - 1);
            let frac = pos - i as f32;
            values[i] * (1.0 - frac) + values[(i + 1) % n] * frac
        }
        Profile::Harmonics { terms } => {
            let t = phase01(re, im);
            terms
                .iter()
                .map(|h| {
                    let shift = (f64::from(h.phase) / std::f64::consts::TAU) as f32;
                    h.weight * sin_turns(h.k as f32 * t + shift)
                })
                .sum()
        }
        Profile::Blend { a, b, weight } => {
            let s = weight.at(p[0], p[1], p[2]).clamp(0.0, 1.0) as f32;
            (1.0 - s) * profile(a, re, im, p) + s * profile(b, re, im, p)
        }
    }
}
