//! Voronoi diagrams on the CPU ([`spectex_model::voronoi`]): per band of rows, the sites of
//! every lattice cell the band's pixels search are computed once (relaxed blocks once per
//! evaluator, [`BlockCache`]),
//! then each pixel runs the model's search ([`spectex_model::voronoi::search`]) over them, so a
//! pixel's bits do not depend on the window, tiling or thread that evaluates it.

use spectex_model::grid::locate_cell;
use spectex_model::voronoi::{BlockCache, Nearest, SiteTable, VoronoiNoise, VoronoiOutput, search};
use spectex_model::{ModelKind, Period, Window};

use crate::{CpuError, CpuKind, RowKernel};

/// A Voronoi model prepared for evaluation.
pub struct VoronoiEvaluator {
    model: VoronoiNoise,
    reach: i32,
    channels: usize,
    /// Relaxed Lloyd blocks, each computed once for every band and point that needs it.
    blocks: BlockCache,
    /// Cells per period along x and y of a periodic model (cells and Lloyd blocks wrapped,
    /// `VoronoiNoise::sites_periodic`).
    cells: Option<[i64; 2]>,
}

impl VoronoiEvaluator {
    /// Prepares a validated model.
    #[must_use]
    pub fn new(model: &VoronoiNoise) -> Self {
        Self {
            model: model.clone(),
            reach: model.output.reach(),
            channels: model.output_channels(),
            blocks: BlockCache::default(),
            cells: None,
        }
    }

    /// Prepares a validated model that accepts `period` made periodic: its cells (and Lloyd
    /// blocks) hashed and relaxed modulo the period.
    #[must_use]
    pub fn new_periodic(model: &VoronoiNoise, period: Period) -> Self {
        Self {
            cells: Some(period.cells(f64::from(model.cell_size))),
            ..Self::new(model)
        }
    }

    /// The pixel's value(s) from its search.
    fn write(&self, found: &Nearest, out: &mut [f32]) {
        match &self.model.output {
            VoronoiOutput::CellId => out[0] = found.site.id,
            VoronoiOutput::F1 => out[0] = found.f1,
            VoronoiOutput::Border => out[0] = found.border,
            VoronoiOutput::F2MinusF1 => out[0] = found.f2 - found.f1,
            VoronoiOutput::Palette { .. } | VoronoiOutput::Image { .. } => {
                out.copy_from_slice(&found.site.colour);
            }
        }
    }

    /// The rows `first..` of `window` into `out` with `table` covering their searches.
    fn eval_with_table(
        &self,
        window: &Window,
        first: usize,
        out: &mut [f32],
        columns: &[(i32, f32)],
        table: &SiteTable,
    ) {
        let side = f64::from(self.model.cell_size);
        let border = matches!(self.model.output, VoronoiOutput::Border);
        let channels = self.channels;
        for (r, line) in out.chunks_exact_mut(window.width * channels).enumerate() {
            let (cy, fy) = locate_cell(window.y(first + r), side).unwrap_or((0, 0.0));
            for (value, &(cx, fx)) in line.chunks_exact_mut(channels).zip(columns) {
                let found = search(
                    |di, dj| {
                        table.get(i64::from(cx) + i64::from(di), i64::from(cy) + i64::from(dj))
                    },
                    fx,
                    fy,
                    self.reach,
                    border,
                );
                self.write(&found, value);
            }
        }
    }
}

impl CpuKind for VoronoiNoise {
    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        Ok(Box::new(VoronoiEvaluator::new(self)))
    }

    fn cpu_kernel_periodic(&self, _z: f64, period: Period) -> Result<Box<dyn RowKernel>, CpuError> {
        self.check_period(period)?;
        Ok(Box::new(VoronoiEvaluator::new_periodic(self, period)))
    }
}

impl RowKernel for VoronoiEvaluator {
    fn output_channels(&self) -> usize {
        self.channels
    }

    fn cost_per_pixel(&self) -> f64 {
        self.model.cells_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let rows = out.len() / (width * self.channels);
        let side = f64::from(self.model.cell_size);
        let columns: Vec<(i32, f32)> = (0..width)
            .map(|i| locate_cell(window.x(i), side).unwrap_or((0, 0.0)))
            .collect();
        let row_cells: Vec<i32> = (0..rows)
            .map(|r| locate_cell(window.y(first + r), side).map_or(0, |c| c.0))
            .collect();
        let reach = i64::from(self.reach);
        let lo = i64::from(columns.iter().map(|c| c.0).min().unwrap_or(0)) - reach;
        let hi = i64::from(columns.iter().map(|c| c.0).max().unwrap_or(0)) + reach;
        let top = i64::from(row_cells.iter().copied().min().unwrap_or(0)) - reach;
        let bottom = i64::from(row_cells.iter().copied().max().unwrap_or(0)) + reach;
        let span = (hi - lo + 1).unsigned_abs();
        let tall = (bottom - top + 1).unsigned_abs();
        // A minified band (its cells far more than its pixels): each pixel alone, with only
        // its own cells' sites computed. A one-pixel window always takes the table path.
        let sparse = crate::is_minified(span, reach.unsigned_abs(), width)
            || crate::is_minified(tall, reach.unsigned_abs(), rows);
        if sparse && width * rows > 1 {
            for r in 0..rows {
                for i in 0..width {
                    let start = (r * width + i) * self.channels;
                    self.eval_rows(
                        &window.tile(i, first + r, 1, 1),
                        0,
                        &mut out[start..start + self.channels],
                    );
                }
            }
            return;
        }
        let (w, h) = (span as usize, tall as usize);
        let table = match self.cells {
            None => self.model.sites_cached(lo, top, w, h, &self.blocks),
            Some(cells) => self
                .model
                .sites_periodic(lo, top, w, h, &self.blocks, cells),
        };
        self.eval_with_table(window, first, out, &columns, &table);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every seed of the 11 × 11 cells around the pixel's, in f64 absolute cell units.
    fn seeds(m: &VoronoiNoise, cx: i64, cy: i64) -> Vec<([f64; 2], [f32; 3], f32)> {
        let t = m.sites(cx - 5, cy - 5, 11, 11);
        let mut out = Vec::new();
        for j in cy - 5..=cy + 5 {
            for i in cx - 5..=cx + 5 {
                let s = t.get(i, j);
                out.push((
                    [
                        i as f64 + f64::from(s.offset[0]),
                        j as f64 + f64::from(s.offset[1]),
                    ],
                    s.colour,
                    s.id,
                ));
            }
        }
        out
    }

    /// Brute force in f64 over 121 seeds: F1, F2, the ID and colour of the nearest, and the
    /// border distance as the minimum over all other seeds of the distance to their bisector,
    /// `(|q − p|² − |n − p|²) / (2|q − n|)`.
    fn brute(m: &VoronoiNoise, x: f64, y: f64) -> (f64, f64, f32, [f32; 3], f64) {
        let c = f64::from(m.cell_size);
        let (px, py) = (x / c, y / c);
        let all = seeds(m, px.floor() as i64, py.floor() as i64);
        let d = |q: &[f64; 2]| ((q[0] - px).powi(2) + (q[1] - py).powi(2)).sqrt();
        let mut order: Vec<usize> = (0..all.len()).collect();
        order.sort_by(|&a, &b| d(&all[a].0).total_cmp(&d(&all[b].0)));
        let n = &all[order[0]];
        let (f1, f2) = (d(&n.0), d(&all[order[1]].0));
        let border = all
            .iter()
            .filter(|q| q.0 != n.0)
            .map(|q| {
                let qn = ((q.0[0] - n.0[0]).powi(2) + (q.0[1] - n.0[1]).powi(2)).sqrt();
                (d(&q.0).powi(2) - f1 * f1) / (2.0 * qn)
            })
            .fold(f64::INFINITY, f64::min);
        (f1, f2, n.2, n.1, border)
    }

    fn render(m: &VoronoiNoise, w: &Window) -> Vec<f32> {
        let e = VoronoiEvaluator::new(m);
        let mut out = vec![0.0f32; w.width * w.height * e.channels];
        e.eval_rows(w, 0, &mut out);
        out
    }

    #[test]
    fn outputs_match_brute_force_over_all_nearby_seeds() {
        let palette = VoronoiOutput::Palette {
            colours: vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        };
        for (k, lloyd) in [(0u32, 4u32), (2, 3)].into_iter().enumerate() {
            for origin in [[0.0, 0.0], [-77.3, 12.9], [1.0e7, -1.0e7]] {
                let w = Window::new(24, 5).at(origin, 3.1);
                let base = VoronoiNoise {
                    cell_size: 16.0,
                    seed: 5,
                    lloyd_iterations: lloyd.0,
                    lloyd_block: lloyd.1,
                    ..VoronoiNoise::default()
                };
                let with = |output: VoronoiOutput| VoronoiNoise {
                    output,
                    ..base.clone()
                };
                let ids = render(&with(VoronoiOutput::CellId), &w);
                let f1 = render(&with(VoronoiOutput::F1), &w);
                let f21 = render(&with(VoronoiOutput::F2MinusF1), &w);
                let border = render(&with(VoronoiOutput::Border), &w);
                let colours = render(&with(palette.clone()), &w);
                for j in 0..w.height {
                    for i in 0..w.width {
                        let at = j * w.width + i;
                        let (bf1, bf2, id, _, bb) = brute(&base, w.x(i), w.y(j));
                        let here = format!("case {k}, origin {origin:?}, pixel ({i}, {j})");
                        // Distances in cell units: f32 rounding of offsets near 1 cell.
                        assert!((f64::from(f1[at]) - bf1).abs() < 1e-5, "{here}: F1");
                        assert!(
                            (f64::from(f21[at]) - (bf2 - bf1)).abs() < 1e-5,
                            "{here}: F2-F1"
                        );
                        assert!((f64::from(border[at]) - bb).abs() < 1e-5, "{here}: border");
                        // The nearest seed is unambiguous away from the bisectors.
                        if bf2 - bf1 > 1e-4 {
                            assert_eq!(ids[at], id, "{here}: id");
                            let n = (id * 3.0) as usize;
                            let want = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]][n];
                            assert_eq!(colours[at * 3..at * 3 + 3], want, "{here}: colour");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn image_colours_are_the_texel_under_the_seed() {
        // A 1-pixel cell with no jitter puts the seed of cell (i, j) at (i + ½, j + ½) pixels,
        // in texel (i mod W, j mod H): the render at pixel centres reproduces the image tiled.
        let texels: Vec<[f32; 3]> = (0..6).map(|k| [k as f32, 0.5, -(k as f32)]).collect();
        let m = VoronoiNoise {
            cell_size: 1.0,
            jitter: 0.0,
            output: VoronoiOutput::Image {
                width: 3,
                height: 2,
                texels: texels.clone(),
            },
            ..VoronoiNoise::default()
        };
        let w = Window::new(7, 5).at([-2.5, 0.5], 1.0);
        let out = render(&m, &w);
        for j in 0..5 {
            for i in 0..7 {
                let (x, y) = (w.x(i).floor() as i64, w.y(j).floor() as i64);
                let t = texels[(y.rem_euclid(2) * 3 + x.rem_euclid(3)) as usize];
                let at = (j * 7 + i) * 3;
                assert_eq!(out[at..at + 3], t, "pixel ({i}, {j})");
            }
        }
    }

    #[test]
    fn a_regular_grid_has_known_distances() {
        // Jitter 0: seeds at cell centres. At a cell's corner F1 = √½ and the border is 0; at
        // the centre F1 = 0 and the border is ½ (cell units).
        let m = VoronoiNoise {
            jitter: 0.0,
            output: VoronoiOutput::Border,
            ..VoronoiNoise::default()
        };
        let e = VoronoiEvaluator::new(&m);
        let mut v = [0.0f32];
        e.eval_rows(&Window::new(1, 1).at([16.0, 16.0], 1.0), 0, &mut v);
        assert!((v[0] - 0.5).abs() < 1e-6, "{}", v[0]);
        e.eval_rows(&Window::new(1, 1).at([24.0, 16.0], 1.0), 0, &mut v);
        assert!((v[0] - 0.25).abs() < 1e-6, "{}", v[0]);
    }
}
