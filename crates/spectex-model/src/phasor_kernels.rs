//! The kernel process of phasor noise: which impulses a cell holds and each one's position,
//! frequency vector and phase offset. This is part of the randomness contract (DESIGN invariant
//! 1): the CPU evaluator sums these kernels per pixel and the GPU evaluator's host builds its
//! impulse tables from them, so both see the same kernels bit for bit.
//!
//! # Randomness contract (phasor: layers 0 and 1)
//!
//! Cell `(i, j)` of a 2D model draws from `Prng::new(cell_hash(i, j, layer, seed))`; cell
//! `(i, j, k)` of a 3D model from `Prng::new(cell_hash(i, j, layer, cell_hash(k, 0, layer,
//! seed)))`; a periodic model ([`PhasorKernels::new_periodic`]) hashes `i` and `j` modulo its
//! cells per period. Layer [`PHASOR_LAYER`] holds the kernels: a Poisson count (Knuth's product of
//! uniforms against `exp(−λ)` in f32, capped at `⌊4λ + 32⌋`), then per impulse its offsets
//! `u₁, u₂ (, u₃)`; where the bandwidth varies, one uniform `v` that keeps the impulse when
//! `v < (b/b_max)^dims` for the bandwidth `b` at its position (a discarded impulse draws nothing
//! more); then by orientation: none for `aligned` and `gradient` (the direction comes
//! from the field at the impulse), one uniform choosing the lobe for `two_lobes`, one (2D: the
//! angle in turns) or two (3D: `z = 2u − 1`, then the azimuth in turns) for `isotropic`, none
//! for `coherent`; last the phase offset `ψ` in turns. Layer [`DIRECTION_LAYER`] holds the
//! coherent direction process (§3.2.2): its own grid of side `r_f = r / bandwidth_ratio` (`r` the
//! widest kernel's radius), the
//! same density, per impulse its offsets then one uniform `v` (2D: angle `(2v − 1)·ω_f`) or two
//! (3D: a direction in the cap of half-angle `ω_f` around +x, `cos θ = 1 − v(1 − cos ω_f)`,
//! azimuth `v'` turns).
//!
//! Fields are read at the impulse's position `((i, j, k) + o)·r` in f64; directions and the
//! coherent sum use the f32 functions of [`crate::math`].

use crate::grid::locate_cell;
use crate::math::{cos_turns, exp_poly, sin_turns};
use crate::random::{Prng, cell_hash};
use crate::{Field, NEG_LN_20, PhasorNoise, PhasorOrientation};

/// Randomness-contract layer of the kernels.
pub const PHASOR_LAYER: u32 = 0;
/// Randomness-contract layer of the coherent direction process.
pub const DIRECTION_LAYER: u32 = 1;

/// One kernel in cell units of its cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impulse {
    /// Offset in its cell, cell units (`o[2] = 0` in 2D).
    pub o: [f32; 3],
    /// Phase offset `ψ_j`, turns.
    pub psi: f32,
    /// `(b_j / b_min)²`: the kernel is `exp(NEG_LN_20·sharp·|d|²)` for `sharp·|d|² < 1`, `d` in
    /// cell units (exactly 1 for a constant bandwidth).
    pub sharp: f32,
    /// Frequency vector `F(x_j)·r·u_j`, turns per cell unit.
    pub f: [f32; 3],
}

/// A Poisson process of impulses on a grid of cells.
#[derive(Debug, Clone, Copy)]
struct Grid {
    /// Cell side, pixels.
    side: f64,
    layer: u32,
    /// `exp(−λ)` in f32 (`λ < 64` for valid models, so a normal f32).
    threshold: f32,
    /// `⌊4λ + 32⌋`.
    cap: u32,
    /// Cells per period along x and y when periodic (cells hashed modulo them), else 0.
    wrap: [i32; 2],
}

impl Grid {
    fn new(side: f64, lambda: f64, layer: u32) -> Self {
        Self {
            side,
            layer,
            threshold: (-lambda).exp() as f32,
            cap: (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32,
            wrap: [0, 0],
        }
    }

    /// The same process on cells of side `side` hashed modulo the period `[w, h]` (pixels, each
    /// a whole number of cells, [`crate::PhasorNoise::periodic_sides`]): a cell one period away
    /// draws the same impulses, at its own position.
    fn periodic(self, side: f64, period: [f64; 2]) -> Self {
        let cells = |p: f64| (p / side).round().clamp(1.0, f64::from(i32::MAX)) as i32;
        Self {
            side,
            wrap: [cells(period[0]), cells(period[1])],
            ..self
        }
    }

    /// The PRNG of a cell, seeded by the contract.
    fn prng(&self, cell: [i32; 3], three_d: bool, seed: u32) -> Prng {
        let [x, y] = [0, 1].map(|a| {
            if self.wrap[a] > 0 {
                cell[a].rem_euclid(self.wrap[a])
            } else {
                cell[a]
            }
        });
        let seed = if three_d {
            cell_hash(cell[2], 0, self.layer, seed)
        } else {
            seed
        };
        Prng::new(cell_hash(x, y, self.layer, seed))
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

/// The kernels of a phasor noise model (assumed validated).
#[derive(Debug, Clone)]
pub struct PhasorKernels {
    seed: u32,
    three_d: bool,
    frequency: Field,
    /// A varying bandwidth: the field and its range `(b_min, b_max)`.
    graded: Option<(Field, f64, f64)>,
    grid: Grid,
    directions: Directions,
}

impl PhasorKernels {
    /// The kernel process of `model`.
    #[must_use]
    pub fn new(model: &PhasorNoise) -> Self {
        let radius = model.kernel_radius();
        let lambda = model.impulses_per_cell();
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
        let (b_min, b_max) = model.bandwidth_range();
        Self {
            seed: model.seed,
            three_d: model.dimensions == 3,
            frequency: model.frequency.clone(),
            graded: (b_max > b_min).then(|| (model.bandwidth.clone(), b_min, b_max)),
            grid: Grid::new(radius, lambda, PHASOR_LAYER),
            directions,
        }
    }

    /// The kernel process of `model` made periodic with `period` (along x and y; a 3D model's z
    /// is not wrapped): cells of the sides [`PhasorNoise::periodic_sides`] fits, hashed modulo
    /// the period, the kernels scaled with their cells (a kernel is truncated at one cell, and
    /// its frequency vector is `F·side·u` turns per cell, so frequencies stay `F` per pixel while
    /// the bandwidth moves with the side), or why the model has no periodic form
    /// ([`crate::ModelKind::check_period`] says why).
    ///
    /// # Errors
    /// [`crate::ModelError::Period`] when the model has no periodic form with `period`.
    pub fn new_periodic(
        model: &PhasorNoise,
        period: crate::Period,
    ) -> Result<Self, crate::ModelError> {
        crate::ModelKind::check_period(model, period)?;
        // `check_period` accepted the sides, so they fit.
        let (side, direction_side) =
            model
                .periodic_sides(period)
                .ok_or_else(|| crate::ModelError::Period {
                    period: period.to_string(),
                    kind: "phasor",
                    requirement: "its cells could not be fitted to the period".into(),
                })?;
        let sides = period.sides();
        let mut kernels = Self::new(model);
        kernels.grid = kernels.grid.periodic(side, sides);
        if let (Directions::Coherent { grid, .. }, Some(d)) =
            (&mut kernels.directions, direction_side)
        {
            *grid = grid.periodic(d, sides);
        }
        Ok(kernels)
    }

    /// Cell side (the kernel radius), pixels.
    #[must_use]
    pub fn side(&self) -> f64 {
        self.grid.side
    }

    /// Whether cells are cubes (a 3D model).
    #[must_use]
    pub fn three_d(&self) -> bool {
        self.three_d
    }

    /// `(cell, offset in [0, 1])` of a coordinate on the kernel grid ([`locate_cell`]).
    #[must_use]
    pub fn locate(&self, coord: f64) -> Option<(i32, f32)> {
        locate_cell(coord, self.grid.side)
    }

    /// The impulses of cell `(i, j, k)` (`k` ignored in 2D), in draw order, into `out`.
    pub fn draw_cell(&self, cell: [i32; 3], out: &mut Vec<Impulse>) {
        out.clear();
        let g = &self.grid;
        let mut prng = g.prng(cell, self.three_d, self.seed);
        let n = g.count(&mut prng);
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
            let mut sharp = 1.0f32;
            if let Some((field, b_min, b_max)) = &self.graded {
                // Thinning: the process has the density of the narrowest kernels; one at
                // bandwidth b is kept with probability (b / b_max)^dimensions.
                let b = field.at(x[0], x[1], x[2]).clamp(*b_min, *b_max);
                let keep = (b / b_max).powi(if self.three_d { 3 } else { 2 });
                if f64::from(prng.next_f32()) >= keep {
                    continue;
                }
                sharp = ((b / b_min) * (b / b_min)) as f32;
            }
            let u = self.direction(&mut prng, x);
            let psi = prng.next_f32();
            let fr = (self.frequency.at(x[0], x[1], x[2]).clamp(0.0, 0.5) * g.side) as f32;
            out.push(Impulse {
                o,
                psi,
                sharp,
                f: [fr * u[0], fr * u[1], fr * u[2]],
            });
        }
    }

    /// The unit direction of an impulse at `x` pixels, drawing what its mode draws.
    fn direction(&self, prng: &mut Prng, x: [f64; 3]) -> [f32; 3] {
        let planar = |angle: f64| {
            let t = (angle / std::f64::consts::TAU).rem_euclid(1.0) as f32;
            [cos_turns(t), sin_turns(t), 0.0]
        };
        match &self.directions {
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
        }
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
            let Some((c, o)) = locate_cell(x[a], grid.side) else {
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
                    let mut prng = grid.prng(c, self.three_d, self.seed);
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
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::{PhasorOutput, Profile};

    fn model(orientation: PhasorOrientation) -> PhasorNoise {
        PhasorNoise {
            seed: 2,
            dimensions: 2,
            bandwidth: Field::constant(0.05),
            frequency: Field::constant(0.1),
            orientation,
            impulses_per_kernel: 20.0,
            profile: Profile::Sine,
            output: PhasorOutput::Profiled,
            mean: 0.0,
            amplitude: 1.0,
        }
    }

    /// Every impulse of a 6×6 block of cells, as unit directions.
    fn directions(m: &PhasorNoise) -> Vec<[f64; 2]> {
        let kernels = PhasorKernels::new(m);
        let mut all = Vec::new();
        let mut cell = Vec::new();
        for j in -3..3 {
            for i in -3..3 {
                kernels.draw_cell([i, j, 0], &mut cell);
                all.extend(cell.iter().map(|imp| {
                    let n = f64::from(imp.f[0]).hypot(f64::from(imp.f[1]));
                    [f64::from(imp.f[0]) / n, f64::from(imp.f[1]) / n]
                }));
            }
        }
        assert!(all.len() > 100, "{} impulses", all.len());
        all
    }

    /// §3.2.1: two bi-lobes more than π/2 apart use the dual formulation (the second direction
    /// reversed, so every pair is less than π/2 apart); closer ones keep both directions.
    pub fn two_lobes_switch_sign_beyond_a_right_angle() {
        for (b, reversed) in [(2.1f64, true), (1.0, false)] {
            let m = model(PhasorOrientation::TwoLobes {
                angle_a: 0.0,
                angle_b: b as f32,
            });
            let want_b = if reversed {
                [-b.cos(), -b.sin()]
            } else {
                [b.cos(), b.sin()]
            };
            let (mut on_a, mut on_b) = (0, 0);
            for d in directions(&m) {
                if (d[0] - 1.0).abs() < 1e-6 && d[1].abs() < 1e-6 {
                    on_a += 1;
                } else {
                    assert!(
                        (d[0] - want_b[0]).abs() < 1e-6 && (d[1] - want_b[1]).abs() < 1e-6,
                        "b = {b}: direction {d:?}"
                    );
                    on_b += 1;
                }
            }
            // Each lobe gets about half of the kernels.
            let share = f64::from(on_a) / f64::from(on_a + on_b);
            assert!((share - 0.5).abs() < 0.1, "b = {b}: share {share}");
        }
    }

    /// Kernels steered by an image follow its gradient plus the offset: a grey ramp along x
    /// with offset π/2 gives kernels along ±y.
    pub fn gradient_orientation_follows_the_image() {
        let image = Field::Image {
            width: 64,
            height: 1,
            grey: (0..64).map(|i| (i as f32 / 63.0).min(1.0)).collect(),
            pixel_size: 4.0,
            min: 0.0,
            max: 1.0,
        };
        let m = model(PhasorOrientation::Gradient {
            image,
            offset: std::f32::consts::FRAC_PI_2,
        });
        let kernels = PhasorKernels::new(&m);
        let mut cell = Vec::new();
        // Cells inside the rising part of the ramp (x from 20 to 200 px; r ≈ 19.5 px).
        let mut seen = 0;
        for i in 2..9 {
            kernels.draw_cell([i, 0, 0], &mut cell);
            for imp in &cell {
                let x = (f64::from(i) + f64::from(imp.o[0])) * kernels.side();
                if (12.0..240.0).contains(&x) {
                    assert!(
                        imp.f[0].abs() < 1e-5 * imp.f[1].abs().max(1.0),
                        "{:?}",
                        imp.f
                    );
                    seen += 1;
                }
            }
        }
        assert!(seen > 10, "{seen}");
    }

    /// The process of a 2D model ignores k; a 3D model's layers differ.
    pub fn layers_are_independent_in_3d_only() {
        let mut m = model(PhasorOrientation::Isotropic);
        let draw = |m: &PhasorNoise, k: i32| {
            let mut v = Vec::new();
            PhasorKernels::new(m).draw_cell([1, 2, k], &mut v);
            v
        };
        assert_eq!(draw(&m, 0), draw(&m, 5));
        m.dimensions = 3;
        assert_ne!(draw(&m, 0), draw(&m, 5));
    }
}
