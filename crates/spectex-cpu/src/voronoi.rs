//! Voronoi diagrams on the CPU ([`spectex_model::voronoi`]): per band of rows, the sites of
//! every lattice cell the band's pixels search are computed once (relaxed blocks once per
//! evaluator, [`BlockCache`]),
//! then each pixel runs the model's search ([`spectex_model::voronoi::search`]) over them, so a
//! pixel's bits do not depend on the window, tiling or thread that evaluates it. A 3D
//! diagram's band table is the box of cells its pixels search on the plane `z`
//! ([`spectex_model::voronoi::search3`], which skips the cells that cannot matter).

use spectex_model::grid::locate_cell;
use spectex_model::voronoi::{
    BlockCache, Nearest, Nearest3, SiteTable, SiteTable3, VoronoiNoise, VoronoiOutput, search,
    search3, search3_full,
};
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
    /// A 3D model's plane `z`: its cell and offset (`locate_cell`); `None` in 2D.
    plane: Option<(i32, f32)>,
}

impl VoronoiEvaluator {
    /// Prepares a validated model.
    #[must_use]
    pub fn new(model: &VoronoiNoise) -> Self {
        Self::new_at_z(model, 0.0)
    }

    /// Prepares a validated model on the plane `z` (pixels; 2D models ignore it).
    #[must_use]
    pub fn new_at_z(model: &VoronoiNoise, z: f64) -> Self {
        Self {
            model: model.clone(),
            reach: model.reach(),
            channels: model.output_channels(),
            blocks: BlockCache::default(),
            cells: None,
            plane: (model.dimensions == 3)
                .then(|| locate_cell(z, f64::from(model.cell_size)).unwrap_or((0, 0.0))),
        }
    }

    /// Prepares a validated model that accepts `period` made periodic: its cells (and Lloyd
    /// blocks) hashed and relaxed modulo the period.
    #[must_use]
    pub fn new_periodic(model: &VoronoiNoise, period: Period) -> Self {
        Self::new_periodic_at_z(model, 0.0, period)
    }

    /// [`new_periodic`](Self::new_periodic) on the plane `z` (pixels; 2D models ignore it): a
    /// 3D model wraps its cells along x and y only.
    #[must_use]
    pub fn new_periodic_at_z(model: &VoronoiNoise, z: f64, period: Period) -> Self {
        Self {
            cells: Some(period.cells(f64::from(model.cell_size))),
            ..Self::new_at_z(model, z)
        }
    }

    /// A 3D pixel's value(s) from its search.
    fn write3(&self, found: &Nearest3, out: &mut [f32]) {
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

    /// The rows `first..` of `window` into `out` with `table` covering their 3D searches on
    /// the plane (cell `cz`, offset `fz`); `full` takes [`search3_full`].
    #[allow(clippy::too_many_arguments)]
    fn eval_with_table3(
        &self,
        window: &Window,
        first: usize,
        out: &mut [f32],
        columns: &[(i32, f32)],
        table: &SiteTable3,
        (cz, fz): (i32, f32),
        full: bool,
    ) {
        let side = f64::from(self.model.cell_size);
        let border = matches!(self.model.output, VoronoiOutput::Border);
        let second = matches!(self.model.output, VoronoiOutput::F2MinusF1);
        let channels = self.channels;
        for (r, line) in out.chunks_exact_mut(window.width * channels).enumerate() {
            let (cy, fy) = locate_cell(window.y(first + r), side).unwrap_or((0, 0.0));
            for (value, &(cx, fx)) in line.chunks_exact_mut(channels).zip(columns) {
                let site = |di: i32, dj: i32, dk: i32| {
                    table.get(
                        i64::from(cx) + i64::from(di),
                        i64::from(cy) + i64::from(dj),
                        i64::from(cz) + i64::from(dk),
                    )
                };
                let found = if full {
                    search3_full(site, [fx, fy, fz], self.reach, second, border)
                } else {
                    search3(site, [fx, fy, fz], self.reach, second, border)
                };
                self.write3(&found, value);
            }
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
    /// The bench case: `testdata/models/voronoi-f1.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("voronoi-f1.json")
    }

    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        Ok(Box::new(VoronoiEvaluator::new_at_z(self, z)))
    }

    fn cpu_kernel_periodic(&self, z: f64, period: Period) -> Result<Box<dyn RowKernel>, CpuError> {
        self.check_period(period)?;
        Ok(Box::new(VoronoiEvaluator::new_periodic_at_z(
            self, z, period,
        )))
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
        self.eval(window, first, out, false);
    }

    /// A 3D model's rows by [`search3_full`] (every cell within the reach); 2D has one path.
    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval(window, first, out, true);
    }
}

impl VoronoiEvaluator {
    /// [`RowKernel::eval_rows`], by the full 3D search when `full`.
    fn eval(&self, window: &Window, first: usize, out: &mut [f32], full: bool) {
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
                    self.eval(
                        &window.tile(i, first + r, 1, 1),
                        0,
                        &mut out[start..start + self.channels],
                        full,
                    );
                }
            }
            return;
        }
        let (w, h) = (span as usize, tall as usize);
        if let Some((cz, fz)) = self.plane {
            let depth = 2 * self.reach + 1;
            let table = self.model.sites3(
                [lo, top, i64::from(cz) - reach],
                [w, h, depth as usize],
                self.cells,
            );
            self.eval_with_table3(window, first, out, &columns, &table, (cz, fz), full);
            return;
        }
        let table = match self.cells {
            None => self.model.sites_cached(lo, top, w, h, &self.blocks),
            Some(cells) => self
                .model
                .sites_periodic(lo, top, w, h, &self.blocks, cells),
        };
        self.eval_with_table(window, first, out, &columns, &table);
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
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

    pub fn outputs_match_brute_force_over_all_nearby_seeds() {
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

    /// Brute force in f64 over the 11 × 11 × 11 cells around the pixel's on the plane `z`
    /// (more than the 9 × 9 × 9 the exact border needs): F1, F2, the nearest's ID and the
    /// border as the least distance to a bisector plane, `(|q − p|² − F1²) / (2|q − n|)`.
    /// Positions relative to the pixel's cell, so far windows lose nothing in f64.
    fn brute3(m: &VoronoiNoise, x: f64, y: f64, z: f64) -> (f64, f64, f32, f64) {
        let c = f64::from(m.cell_size);
        let p = [x / c, y / c, z / c];
        let cell = p.map(f64::floor);
        let f = [p[0] - cell[0], p[1] - cell[1], p[2] - cell[2]];
        let (ci, cj, ck) = (cell[0] as i64, cell[1] as i64, cell[2] as i64);
        let mut seeds = Vec::new();
        for dk in -5..=5i64 {
            for dj in -5..=5i64 {
                for di in -5..=5i64 {
                    let (o, id) = m.jittered3(ci + di, cj + dj, ck + dk);
                    let q = [
                        di as f64 + f64::from(o[0]),
                        dj as f64 + f64::from(o[1]),
                        dk as f64 + f64::from(o[2]),
                    ];
                    seeds.push((q, id));
                }
            }
        }
        let dist = |a: &[f64; 3], b: &[f64; 3]| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        seeds.sort_by(|a, b| dist(&a.0, &f).total_cmp(&dist(&b.0, &f)));
        let (n, id) = seeds[0];
        let (f1, f2) = (dist(&n, &f), dist(&seeds[1].0, &f));
        let border = seeds[1..]
            .iter()
            .map(|(q, _)| (dist(q, &f).powi(2) - f1 * f1) / (2.0 * dist(q, &n)))
            .fold(f64::INFINITY, f64::min);
        (f1, f2, id, border)
    }

    fn render3(m: &VoronoiNoise, w: &Window, z: f64) -> Vec<f32> {
        let e = VoronoiEvaluator::new_at_z(m, z);
        let mut out = vec![0.0f32; w.width * w.height * e.channels];
        e.eval_rows(w, 0, &mut out);
        out
    }

    pub fn outputs_3d_match_brute_force_near_and_far() {
        let palette = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        for (origin, z) in [
            ([0.0, 0.0], 0.0),
            ([-77.3, 12.9], 37.3),
            ([1.0e7, -1.0e7], 1.0e5 + 0.7),
        ] {
            for jitter in [1.0f32, 0.8] {
                let w = Window::new(20, 4).at(origin, 3.1);
                let base = VoronoiNoise {
                    dimensions: 3,
                    cell_size: 16.0,
                    jitter,
                    seed: 5,
                    ..VoronoiNoise::default()
                };
                let with = |output: VoronoiOutput| VoronoiNoise {
                    output,
                    ..base.clone()
                };
                let ids = render3(&with(VoronoiOutput::CellId), &w, z);
                let f1 = render3(&with(VoronoiOutput::F1), &w, z);
                let f21 = render3(&with(VoronoiOutput::F2MinusF1), &w, z);
                let border = render3(&with(VoronoiOutput::Border), &w, z);
                let colours = render3(
                    &with(VoronoiOutput::Palette {
                        colours: palette.to_vec(),
                    }),
                    &w,
                    z,
                );
                for j in 0..w.height {
                    for i in 0..w.width {
                        let at = j * w.width + i;
                        let (bf1, bf2, id, bb) = brute3(&base, w.x(i), w.y(j), z);
                        let here = format!("origin {origin:?}, z {z}, jitter {jitter}, ({i}, {j})");
                        // Cell units: the f32 rounding of the pixel's offsets and of a few
                        // operations on values below 10 cells, ≈ 10⁻⁶.
                        assert!((f64::from(f1[at]) - bf1).abs() < 1e-5, "{here}: F1");
                        assert!(
                            (f64::from(f21[at]) - (bf2 - bf1)).abs() < 1e-5,
                            "{here}: F2-F1"
                        );
                        assert!((f64::from(border[at]) - bb).abs() < 1e-5, "{here}: border");
                        if bf2 - bf1 > 1e-4 {
                            assert_eq!(ids[at], id, "{here}: id");
                            let want = palette[((id * 3.0) as usize).min(2)];
                            assert_eq!(colours[at * 3..at * 3 + 3], want, "{here}: colour");
                        }
                    }
                }
            }
        }
    }

    pub fn the_3d_fast_path_is_the_full_search() {
        for output in [
            VoronoiOutput::CellId,
            VoronoiOutput::F2MinusF1,
            VoronoiOutput::Border,
        ] {
            let m = VoronoiNoise {
                dimensions: 3,
                cell_size: 8.0,
                jitter: 0.9,
                output,
                ..VoronoiNoise::default()
            };
            let e = VoronoiEvaluator::new_at_z(&m, -3.3);
            let w = Window::new(64, 16).at([-100.0, 31.0], 0.7);
            let mut fast = vec![0.0f32; 64 * 16];
            let mut full = fast.clone();
            e.eval_rows(&w, 0, &mut fast);
            e.eval_rows_reference(&w, 0, &mut full);
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&full), "{:?}", m.output);
        }
    }

    pub fn a_regular_3d_lattice_slice_at_cell_centres_is_the_2d_diagram() {
        // Jitter 0 puts every seed at its cell's centre. On the plane through the centres of
        // the layer k (z = (k + ½)·C) the nearest seed lies in that layer (d_z = 0, so the
        // same f32 d² as in 2D), and the layers above and below add bisector planes ½ away,
        // no nearer than a square cell's own border (at most ½): F1 and the border equal the
        // 2D diagram's bit for bit.
        for output in [VoronoiOutput::F1, VoronoiOutput::Border] {
            let two = VoronoiNoise {
                jitter: 0.0,
                cell_size: 12.0,
                output,
                ..VoronoiNoise::default()
            };
            let three = VoronoiNoise {
                dimensions: 3,
                ..two.clone()
            };
            let w = Window::new(40, 9).at([-30.2, 7.7], 0.9);
            for k in [0i64, -3, 4000] {
                let z = (k as f64 + 0.5) * 12.0;
                let bits = |v: Vec<f32>| v.into_iter().map(f32::to_bits).collect::<Vec<_>>();
                assert_eq!(
                    bits(render3(&three, &w, z)),
                    bits(render(&two, &w)),
                    "{:?}, layer {k}",
                    two.output
                );
            }
        }
    }

    pub fn a_periodic_3d_diagram_repeats_in_x_and_y_only() {
        let m = VoronoiNoise {
            dimensions: 3,
            cell_size: 8.0,
            output: VoronoiOutput::Border,
            ..VoronoiNoise::default()
        };
        let period = Period::new(32, 24).expect("valid period");
        let e =
            crate::Evaluator::periodic_at_z(&spectex_model::Model::Voronoi(m.clone()), 5.5, period)
                .expect("periodic");
        // A 64 × 48 render is the 32 × 24 period repeated 2 × 2, bit for bit.
        let out = e
            .render(&Window::new(64, 48).at([-7.5, 3.25], 1.0))
            .expect("renders");
        for j in 0..24 {
            for i in 0..32 {
                let v = out[j * 64 + i].to_bits();
                for (a, b) in [(32, 0), (0, 24), (32, 24)] {
                    assert_eq!(
                        v,
                        out[(j + b) * 64 + i + a].to_bits(),
                        "({i}, {j}) + ({a}, {b})"
                    );
                }
            }
        }
        // The cells of one period: the wrapped box equals the unwrapped one shifted.
        let a = m.sites3([0, 0, 0], [4, 3, 2], Some([4, 3]));
        let b = m.sites3([4, -3, 0], [4, 3, 2], Some([4, 3]));
        assert_eq!(
            a,
            SiteTable3 {
                origin: [0, 0, 0],
                ..b.clone()
            }
        );
        // z is not wrapped: another plane of cells holds other seeds.
        let c = m.sites3([0, 0, 2], [4, 3, 2], Some([4, 3]));
        assert_ne!(a.sites, c.sites);
    }

    pub fn image_colours_are_the_texel_under_the_seed() {
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

    pub fn a_regular_grid_has_known_distances() {
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
