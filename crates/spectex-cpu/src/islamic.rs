//! Islamic star patterns on the CPU ([`spectex_model::islamic`]): each column's and row's
//! lattice fractions are split once per band in f64 ([`LatticeMap`]), then each pixel sums
//! them in f32 and runs the model's segment loop ([`IslamicGeometry::nearest`]) and output
//! formula, so a pixel's bits depend only on its position (and the window's footprint).

use spectex_model::Window;
use spectex_model::islamic::{
    IslamicGeometry, IslamicOutput, IslamicPattern, LatticeMap, footprint, output_value,
};

use crate::{CpuError, CpuKind, RowKernel};

/// An Islamic pattern prepared for evaluation.
pub struct IslamicEvaluator {
    geometry: IslamicGeometry,
    map: LatticeMap,
    output: IslamicOutput,
    cell: f32,
    width: f32,
}

impl IslamicEvaluator {
    /// Prepares a validated model.
    #[must_use]
    pub fn new(model: &IslamicPattern) -> Self {
        Self {
            geometry: model.geometry(),
            map: model.lattice_map(),
            output: model.output,
            cell: model.cell_size,
            width: model.line_width,
        }
    }
}

impl CpuKind for IslamicPattern {
    /// The bench case: `testdata/models/islamic-488-band.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("islamic-488-band.json")
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        Ok(Box::new(IslamicEvaluator::new(self)))
    }

    /// The pattern itself: it repeats with every period it accepts (a lattice period,
    /// `check_period`), and `Evaluator::periodic` reduces the positions.
    fn cpu_kernel_periodic(
        &self,
        z: f64,
        period: spectex_model::Period,
    ) -> Result<Box<dyn RowKernel>, CpuError> {
        spectex_model::ModelKind::check_period(self, period)?;
        self.cpu_kernel(z)
    }
}

impl RowKernel for IslamicEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.geometry.len() as f64
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let (f, inv_f) = footprint(window.footprint());
        let columns: Vec<[f32; 2]> = (0..width).map(|i| self.map.column(window.x(i))).collect();
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let row = self.map.row(window.y(first + r));
            for (value, &column) in line.iter_mut().zip(&columns) {
                let (s, t) = LatticeMap::fractions(column, row);
                let (d2, odd) = self.geometry.nearest(s, t);
                *value = output_value(self.output, d2, odd, self.cell, self.width, f, inv_f);
            }
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use std::f64::consts::PI;

    use spectex_model::Filter;
    use spectex_model::islamic::{Motif, Tiling};

    use super::*;

    /// An f64 reference built from the definition independently of the model's tables: per
    /// regular polygon (centre, `n`, inradius `r`, first normal `φ₀`), the contact point of
    /// corner `k` lies on the corner's bisector (angle `φ_k + π/n`) at distance `|m − λ·u|`
    /// with `λ = r·sin(π/n)/cos(θ − π/n)` (law of sines in the triangle centre, midpoint,
    /// contact point); a star's chords join midpoints `k` and `k + d`.
    fn reference_segments(
        tiling: Tiling,
        motif: Motif,
        around: [i64; 2],
    ) -> Vec<([f64; 2], [f64; 2])> {
        let [e1, e2] = tiling.basis();
        let mut out = Vec::new();
        for j in around[1] - 4..=around[1] + 4 {
            for i in around[0] - 4..=around[0] + 4 {
                for t in tiling.tiles() {
                    let c = [
                        t.centre[0] + i as f64 * e1[0] + j as f64 * e2[0],
                        t.centre[1] + i as f64 * e1[1] + j as f64 * e2[1],
                    ];
                    let n = f64::from(t.sides);
                    let r = t.inradius;
                    let at =
                        |rho: f64, angle: f64| [c[0] + rho * angle.cos(), c[1] + rho * angle.sin()];
                    let phi = |k: u32| t.normal0 + 2.0 * PI * f64::from(k) / n;
                    match motif {
                        Motif::Contact { angle } => {
                            let th = f64::from(angle).to_radians();
                            let lambda = r * (PI / n).sin() / (th - PI / n).cos();
                            // In the midpoint's frame: (r − λ sin θ, λ cos θ).
                            let (x, y) = (r - lambda * th.sin(), lambda * th.cos());
                            let rho = x.hypot(y);
                            for k in 0..t.sides {
                                let m0 = at(r, phi(k));
                                let xk = at(rho, phi(k) + PI / n);
                                let m1 = at(r, phi(k + 1));
                                out.push((m0, xk));
                                out.push((xk, m1));
                            }
                        }
                        Motif::Star { step } => {
                            let d = step.min((t.sides - 1) / 2);
                            for k in 0..t.sides {
                                out.push((at(r, phi(k)), at(r, phi(k + d))));
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The signed distance (pixels) at `p` by brute force in f64: the pattern point
    /// `u = R(−α)(p − o)/C` less the phase, in cell units, against every segment near it;
    /// the sign by the even–odd rule over those closed polygons.
    fn pattern_point(m: &IslamicPattern, p: [f64; 2]) -> [f64; 2] {
        let c = f64::from(m.cell_size);
        let al = f64::from(m.rotation).to_radians();
        let v = [p[0] - f64::from(m.offset[0]), p[1] - f64::from(m.offset[1])];
        let u = [
            (al.cos() * v[0] + al.sin() * v[1]) / c,
            (-al.sin() * v[0] + al.cos() * v[1]) / c,
        ];
        let [e1, e2] = m.tiling.basis();
        let ph = m.phase();
        [
            u[0] - ph[0] * e1[0] - ph[1] * e2[0],
            u[1] - ph[0] * e1[1] - ph[1] * e2[1],
        ]
    }

    fn reference(m: &IslamicPattern, p: [f64; 2]) -> f64 {
        let c = f64::from(m.cell_size);
        let q = pattern_point(m, p);
        let [_, e2] = m.tiling.basis();
        // The lattice cell of q: t = q_y / e2_y, s = q_x − t·e2_x.
        let t = q[1] / e2[1];
        let s = q[0] - t * e2[0];
        let segs = reference_segments(m.tiling, m.motif, [s.floor() as i64, t.floor() as i64]);
        let mut best = f64::INFINITY;
        let mut odd = false;
        for (a, b) in segs {
            let d = [b[0] - a[0], b[1] - a[1]];
            let pa = [q[0] - a[0], q[1] - a[1]];
            let h = ((pa[0] * d[0] + pa[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
            best = best.min((pa[0] - d[0] * h).hypot(pa[1] - d[1] * h));
            if (a[1] <= q[1]) != (b[1] <= q[1]) {
                let x = a[0] + (q[1] - a[1]) / d[1] * d[0];
                if q[0] < x {
                    odd = !odd;
                }
            }
        }
        if odd { -best * c } else { best * c }
    }

    fn render(m: &IslamicPattern, w: &Window) -> Vec<f32> {
        let e = IslamicEvaluator::new(m);
        let mut out = vec![0.0f32; w.width * w.height];
        e.eval_rows(w, 0, &mut out);
        out
    }

    /// The f32 evaluation's distance error, pixels: the lattice fractions are rounded to f32
    /// (2⁻²⁴ each, summed: ≈ 2.4e-7 cell units), the segment endpoints too (≈ 2.4e-7 of
    /// coordinates below 4), and the loop's products and sums round a few times values below
    /// 8: well under 1e-5 cell units, which this bound allows (times the cell size).
    const DISTANCE_TOLERANCE_CELLS: f64 = 1e-5;

    fn patterns() -> Vec<IslamicPattern> {
        let mut out = Vec::new();
        for (k, tiling) in [
            Tiling::Square,
            Tiling::Hexagonal,
            Tiling::OctagonSquare,
            Tiling::DodecagonTriangle,
        ]
        .into_iter()
        .enumerate()
        {
            for motif in [
                Motif::Contact { angle: 67.5 },
                Motif::Contact { angle: 30.0 },
                Motif::Star { step: 3 },
            ] {
                out.push(IslamicPattern {
                    seed: k as u32,
                    tiling,
                    motif,
                    cell_size: 40.0,
                    output: IslamicOutput::Distance,
                    rotation: 17.0 * k as f32,
                    offset: [3.5, -11.25],
                    ..IslamicPattern::default()
                });
            }
        }
        out
    }

    pub fn the_signed_distance_matches_brute_force_in_f64() {
        for m in patterns() {
            for origin in [[0.0, 0.0], [-77.3, 12.9], [1.0e7, -1.0e7]] {
                let w = Window::new(23, 19).at(origin, 3.7);
                let got = render(&m, &w);
                let tol = DISTANCE_TOLERANCE_CELLS * f64::from(m.cell_size);
                for j in 0..w.height {
                    for i in 0..w.width {
                        let want = reference(&m, [w.x(i), w.y(j)]);
                        let v = f64::from(got[j * w.width + i]);
                        let here = format!("{:?} {:?} at {origin:?} ({i}, {j})", m.tiling, m.motif);
                        if want.abs() > tol {
                            assert!((v - want).abs() <= tol, "{here}: {v} vs {want}");
                        } else {
                            assert!(v.abs() <= 2.0 * tol, "{here}: {v} vs {want}");
                        }
                    }
                }
            }
        }
    }

    /// The pattern is invariant under its tiling's translations, rotations (a quarter turn
    /// about a square or an octagon, a sixth about a hexagon or a dodecagon) and mirrors (along
    /// the first tile's first normal, through its centre: with the rotations D4 or D6): the
    /// value at
    /// `p` and at `p` moved by the symmetry, within the f32 evaluation's error twice.
    pub fn the_pattern_has_its_tilings_symmetries() {
        for m in patterns() {
            let e = IslamicEvaluator::new(&m);
            let c = f64::from(m.cell_size);
            let al = f64::from(m.rotation).to_radians();
            let ph = m.phase();
            let [e1, e2] = m.tiling.basis();
            let tiles = m.tiling.tiles();
            // The first tile's centre in pixels (its largest polygon).
            let t = tiles[0];
            let u = [
                t.centre[0] + ph[0] * e1[0] + ph[1] * e2[0],
                t.centre[1] + ph[0] * e1[1] + ph[1] * e2[1],
            ];
            let to_px = |v: [f64; 2]| {
                [
                    c * (al.cos() * v[0] - al.sin() * v[1]),
                    c * (al.sin() * v[0] + al.cos() * v[1]),
                ]
            };
            let cu = to_px(u);
            let centre = [
                cu[0] + f64::from(m.offset[0]),
                cu[1] + f64::from(m.offset[1]),
            ];
            // The lattice's rotation order about the first tile's centre: 4 on the square
            // lattices (the octagon's D8 is not the 4.8.8 pattern's: its squares break it),
            // 6 on the hexagonal ones (likewise the dodecagon's D12).
            let order = match m.tiling {
                Tiling::Square | Tiling::OctagonSquare => 4.0,
                Tiling::Hexagonal | Tiling::DodecagonTriangle => 6.0,
            };
            let turn = 2.0 * PI / order;
            let tol = 2.0 * DISTANCE_TOLERANCE_CELLS * c;
            let value = |p: [f64; 2]| {
                let mut v = [0.0f32];
                e.eval_rows(&Window::new(1, 1).at(p, 1.0), 0, &mut v);
                f64::from(v[0])
            };
            let shift = to_px(e1);
            for k in 0..40 {
                let k = f64::from(k);
                let p = [
                    centre[0] + 0.9 * c * (0.37 * k).sin(),
                    centre[1] + 0.8 * c * (0.91 * k).cos(),
                ];
                let v = [p[0] - centre[0], p[1] - centre[1]];
                let rotated = [
                    centre[0] + turn.cos() * v[0] - turn.sin() * v[1],
                    centre[1] + turn.sin() * v[0] + turn.cos() * v[1],
                ];
                let moved = [p[0] + 3.0 * shift[0], p[1] + 3.0 * shift[1]];
                // The mirror through the centre along e₁ (the first tile's first normal).
                let axis = [al.cos(), al.sin()];
                let along = v[0] * axis[0] + v[1] * axis[1];
                let mirrored = [
                    centre[0] + 2.0 * along * axis[0] - v[0],
                    centre[1] + 2.0 * along * axis[1] - v[1],
                ];
                let here = format!("{:?} {:?} point {k}", m.tiling, m.motif);
                let a = value(p);
                // Near a line the sign may flip with the rounding: compare magnitudes there.
                for (what, b) in [
                    ("rotation", value(rotated)),
                    ("translation", value(moved)),
                    ("mirror", value(mirrored)),
                ] {
                    let diff = if a.abs() <= tol {
                        a.abs() - b.abs()
                    } else {
                        a - b
                    };
                    assert!(diff.abs() <= tol, "{here}: {what} {a} vs {b}");
                }
            }
        }
    }

    /// A star `{4/1}` on squares joins the edge midpoints of every square: together the
    /// lines `q_x + q_y ∈ ℤ + ½` and `q_x − q_y ∈ ℤ + ½` (cell units, pattern frame). Rotated
    /// by 45° they are axis-aligned, so across a single line a pixel's square box covers
    /// exactly the 1D box-filtered band: the band's value equals a 64 × 64 supersampling of the
    /// band of those analytic lines over the pixel's footprint, wherever the box meets one
    /// family of lines only.
    pub fn the_band_is_the_box_filtered_coverage() {
        let m = IslamicPattern {
            tiling: Tiling::Square,
            motif: Motif::Star { step: 1 },
            cell_size: 48.0,
            line_width: 3.0,
            rotation: 45.0,
            output: IslamicOutput::Band,
            ..IslamicPattern::default()
        };
        let f = 4.0;
        let w = Window::new(24, 24)
            .at([5.25, -9.5], 1.3)
            .filtered(Filter::Footprint(f));
        let got = render(&m, &w);
        let c = f64::from(m.cell_size);
        // Distances in pixels to the nearest line of each family.
        let families = |p: [f64; 2]| {
            let q = pattern_point(&m, p);
            let line = |v: f64| (v - 0.5 - (v - 0.5).round()).abs() * c / 2f64.sqrt();
            (line(q[0] + q[1]), line(q[0] - q[1]))
        };
        let mut compared = 0;
        for j in 0..w.height {
            for i in 0..w.width {
                let p = [w.x(i), w.y(j)];
                let (da, db) = families(p);
                if da.max(db) <= f + f64::from(m.line_width) {
                    continue;
                }
                let n = 64;
                let mut inside = 0usize;
                for b in 0..n {
                    for a in 0..n {
                        let x = p[0] - f / 2.0 + f * (f64::from(a) + 0.5) / f64::from(n);
                        let y = p[1] - f / 2.0 + f * (f64::from(b) + 0.5) / f64::from(n);
                        let (da, db) = families([x, y]);
                        if da.min(db) <= 0.5 * f64::from(m.line_width) {
                            inside += 1;
                        }
                    }
                }
                let sampled = inside as f64 / f64::from(n * n);
                compared += usize::from(sampled > 0.0);
                // 64 samples across the box: the sampled coverage is within one row of
                // samples (1/64) of the exact one.
                let v = f64::from(got[j * w.width + i]);
                assert!(
                    (v - sampled).abs() <= 1.0 / 64.0 + 1e-6,
                    "({i}, {j}): {v} vs {sampled}"
                );
            }
        }
        assert!(compared > 20, "{compared} pixels on a line compared");
    }
}
