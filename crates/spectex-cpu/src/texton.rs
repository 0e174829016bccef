//! Texton placement / spot noise on the CPU ([`spectex_model::texton`]): per row, the textons of
//! the cells the row's pixels can reach are drawn once (a band of cell columns per cell row),
//! then each pixel sums (or takes the maximum of) the contributions in the model's order — cell
//! rows outer, cell columns inner, textons in draw order — so a pixel's bits do not depend on
//! the window, tiling or thread that evaluates it.

use spectex_model::period::wrap;
use spectex_model::texton::{Combine, MAX_TEXTONS_PER_CELL, Texton, TextonNoise};
use spectex_model::{Period, Window, grid::locate_cell};

use crate::{CpuError, CpuKind, RowKernel};

/// A texton model prepared for evaluation.
pub struct TextonEvaluator {
    model: TextonNoise,
    cdf: Option<[f32; MAX_TEXTONS_PER_CELL as usize]>,
    reach: i32,
    /// Cells per period along x and y of a periodic model: cell `(i, j)` draws the textons of
    /// `(i mod n_x, j mod n_y)`.
    cells: Option<[i64; 2]>,
}

impl TextonEvaluator {
    /// Prepares a validated model.
    #[must_use]
    pub fn new(model: &TextonNoise) -> Self {
        Self {
            model: model.clone(),
            cdf: model.poisson_cdf(),
            reach: model.reach(),
            cells: None,
        }
    }

    /// Prepares a validated model that accepts `period` (its cell divides it) made periodic.
    #[must_use]
    pub fn new_periodic(model: &TextonNoise, period: Period) -> Self {
        Self {
            cells: Some(period.cells(f64::from(model.cell_size))),
            ..Self::new(model)
        }
    }

    /// The value at `(x, y)` pixels (a one-pixel render gives the same bits).
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let mut out = [0.0f32];
        self.eval_rows(&Window::new(1, 1).at([x, y], 1.0), 0, &mut out);
        out[0]
    }

    /// The textons of cells `(first_i ..= last_i, j)`, one list per cell column.
    fn cell_row(&self, first_i: i32, last_i: i32, j: i32) -> Vec<Vec<Texton>> {
        (first_i..=last_i)
            .map(|i| {
                let mut list = Vec::new();
                let (hi, hj) = match self.cells {
                    None => (i, j),
                    Some([nx, ny]) => {
                        (wrap(i64::from(i), nx) as i32, wrap(i64::from(j), ny) as i32)
                    }
                };
                self.model
                    .cell_textons(hi, hj, self.cdf.as_ref(), |t| list.push(t));
                list
            })
            .collect()
    }
}

impl CpuKind for TextonNoise {
    /// The bench case: `testdata/models/texton-ellipsoids.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("texton-ellipsoids.json")
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        Ok(Box::new(TextonEvaluator::new(self)))
    }

    fn cpu_kernel_periodic(&self, _z: f64, period: Period) -> Result<Box<dyn RowKernel>, CpuError> {
        Ok(Box::new(TextonEvaluator::new_periodic(self, period)))
    }
}

impl RowKernel for TextonEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.model.textons_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let side = f64::from(self.model.cell_size);
        // Column splits once per band; positions out of range were rejected by the window check.
        let columns: Vec<(i32, f32)> = (0..width)
            .map(|i| locate_cell(window.x(i), side).unwrap_or((0, 0.0)))
            .collect();
        let lo = columns.iter().map(|c| c.0).min().unwrap_or(0) - self.reach;
        let hi = columns.iter().map(|c| c.0).max().unwrap_or(0) + self.reach;
        let reach = self.reach;
        // A minified row: each pixel alone (`crate::eval_if_minified`).
        let span = (i64::from(hi) - i64::from(lo) + 1).unsigned_abs();
        if crate::eval_if_minified(
            window,
            first,
            out,
            (span, reach.unsigned_abs().into()),
            |w, f, o| self.eval_rows(w, f, o),
        ) {
            return;
        }
        // The textons of the cell rows around the current row's cell, redrawn when it changes.
        let mut cached: Option<(i32, Vec<Vec<Vec<Texton>>>)> = None;
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let (cy, fy) = locate_cell(window.y(first + r), side).unwrap_or((0, 0.0));
            if cached.as_ref().is_none_or(|(row, _)| *row != cy) {
                let rows = (-reach..=reach)
                    .map(|dj| self.cell_row(lo, hi, cy + dj))
                    .collect();
                cached = Some((cy, rows));
            }
            let Some((_, rows)) = &cached else {
                continue;
            };
            for (value, &(cx, fx)) in line.iter_mut().zip(&columns) {
                let mut acc = 0.0f32;
                for (row, dj) in rows.iter().zip(-reach..=reach) {
                    for di in -reach..=reach {
                        for t in &row[(cx + di - lo) as usize] {
                            let tx = fx - (di as f32 + t.offset[0]);
                            let ty = fy - (dj as f32 + t.offset[1]);
                            let contribution = t.weight * self.model.spot_at(t, tx, ty);
                            match self.model.combine {
                                Combine::Sum => acc += contribution,
                                // Over a canvas of 0; `>` keeps +0 against −0 (w < 0 outside
                                // the support), as the WGSL twin does.
                                Combine::Max => {
                                    if contribution > acc {
                                        acc = contribution;
                                    }
                                }
                            }
                        }
                    }
                }
                *value = self.model.mean + acc;
            }
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::texton::{Placement, Spot};

    /// The definition written out per pixel in f64 positions: every cell within reach, every
    /// texton, the spot by its formula (an independent transcription of the module docs).
    fn reference(m: &TextonNoise, x: f64, y: f64) -> f32 {
        let c = f64::from(m.cell_size);
        let (cx, cy) = ((x / c).floor(), (y / c).floor());
        let (fx, fy) = ((x / c - cx) as f32, (y / c - cy) as f32);
        let cdf = m.poisson_cdf();
        let reach = m.reach();
        let mut acc = 0.0f32;
        for dj in -reach..=reach {
            for di in -reach..=reach {
                m.cell_textons(cx as i32 + di, cy as i32 + dj, cdf.as_ref(), |t| {
                    let tx = fx - (di as f32 + t.offset[0]);
                    let ty = fy - (dj as f32 + t.offset[1]);
                    let v = t.weight * m.spot_at(&t, tx, ty);
                    match m.combine {
                        Combine::Sum => acc += v,
                        Combine::Max => {
                            if v > acc {
                                acc = v;
                            }
                        }
                    }
                });
            }
        }
        m.mean + acc
    }

    fn models() -> Vec<TextonNoise> {
        vec![
            TextonNoise::default(),
            TextonNoise {
                placement: Placement::Poisson { density: 2.5 },
                spot: Spot::Gaussian,
                combine: Combine::Max,
                radii: [30.0, 30.0],
                seed: 7,
                ..TextonNoise::default()
            },
            TextonNoise {
                spot: Spot::Image {
                    width: 3,
                    height: 2,
                    values: vec![0.0, 1.0, 0.5, -1.0, 2.0, 0.25],
                },
                rotation: [0.1, 0.1],
                ..TextonNoise::default()
            },
        ]
    }

    pub fn rows_match_the_per_pixel_definition() {
        for (k, m) in models().iter().enumerate() {
            let e = TextonEvaluator::new(m);
            for origin in [[0.0, 0.0], [-77.3, 12.9], [1.0e7, -1.0e7]] {
                let w = Window::new(40, 6).at(origin, 0.83);
                let mut out = vec![0.0f32; 40 * 6];
                e.eval_rows(&w, 0, &mut out);
                for j in 0..6 {
                    for i in 0..40 {
                        // The reference splits in f64 from the same f64 position: the same
                        // (cell, offset) as locate_cell, so the same bits.
                        let want = reference(m, w.x(i), w.y(j));
                        let got = out[j * 40 + i];
                        assert_eq!(
                            got.to_bits(),
                            want.to_bits(),
                            "model {k}, origin {origin:?}, pixel ({i}, {j}): {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    pub fn an_isolated_ellipsoid_has_its_radii() {
        // One texton per cell at the centre, no rotation, unit scale and weight: along the
        // texton's x axis the value is √(1 − (d/a)²) and vanishes at d = a (Eq. (6), height 1).
        let m = TextonNoise {
            placement: Placement::Grid { jitter: 0.0 },
            rotation: [0.0, 0.0],
            scale: [1.0, 1.0],
            intensity: [1.0, 1.0],
            radii: [12.0, 6.0],
            ..TextonNoise::default()
        };
        let e = TextonEvaluator::new(&m);
        let centre = 16.0; // the centre of cell 0
        for d in [0.0, 3.0, 6.0, 9.0, 11.9] {
            let want = (1.0 - (d / 12.0f64).powi(2)).sqrt();
            let got = f64::from(e.eval(centre + d, centre));
            assert!((got - want).abs() < 1e-5, "d = {d}: {got} vs {want}");
        }
        assert_eq!(e.eval(centre + 12.5, centre), 0.0);
        assert_eq!(e.eval(centre, centre + 6.5), 0.0);
    }
}
