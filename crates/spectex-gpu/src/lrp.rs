//! LRP noise on the device (`shaders/lrp.wgsl`): the model's strata, frequency tables and
//! sub-strata packed once, and per tile the lattice cell of every column and row with its f32
//! offsets to the nearby lattice points (f64 on the host, so a window at `(10⁷, 10⁷)` is as
//! precise as one at the origin), and the box of lattice points whose draws `lrp_draw` makes
//! once on the device before `lrp_main` reads them ([`draw_boxes`]).
//!
//! The LRP noise's export (the glue of `shaders/lrp.wgsl`): the compute shader's uniform and
//! tables; stratum s's lattice is the export's lattice s.

use std::sync::Arc;

use spectex_model::{LrpNoise, Period};

use crate::axis::{periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::{OwnPass, OwnPassLayout, Shaded, binding_limit, flat_grid};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/lrp.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/lrp.wgsl"));

wgsl_struct! {
    /// `LrpParams` of `lrp.wgsl`.
    pub(crate) struct LrpParams {
        width: u32,
        height: u32,
        strata: u32,
        seed: u32,
        mean: f32,
        /// 1: a minified render, each cosine multiplied by its entry's gain.
        filtered: u32,
        /// `lrp_draw`: the lattice points of every box.
        draw_points: u32,
        /// `lrp_draw`: invocations per row of its dispatch grid.
        draw_stride: u32,
    }
}

wgsl_struct! {
    /// `LrpBox` of `lrp.wgsl`: a stratum's lattice points drawn once for a tile.
    pub(crate) struct LrpBox {
        x0: i32,
        y0: i32,
        /// 0: the stratum's pixels draw for themselves.
        width: u32,
        height: u32,
        first_record: u32,
        first_point: u32,
    }
}

wgsl_struct! {
    /// `LrpStratum` of `lrp.wgsl`: one stratum's constants.
    pub(crate) struct LrpStratum {
        /// `1/Δ²` rounded to f32 from f64 (the CPU's `(1.0 / (delta * delta)) as f32`).
        inv_delta2: f32,
        amplitude: f32,
        /// Index in the sub-strata table of the stratum's cosine 0.
        table_first: u32,
        /// `J_s`, the cosines per lattice point.
        cosines: u32,
        /// `Δ_s` (the model's f32; along x, fitted to a period), for warping.
        delta: f32,
        /// The lattice period along y.
        delta_y: f32,
        /// `(Δ_x/Δ_y)²` (1 for a square lattice).
        aspect2: f32,
        /// Lattice points per period along x and y (0: not periodic).
        cells_x: i32,
        cells_y: i32,
    }
}

wgsl_struct! {
    /// `LatticeAxis` of `lrp.wgsl`: a position's lattice cell `c = ⌊x/Δ⌋` (wrapped to i32 as
    /// the CPU does) and `f32(x − (c + k − 1)·Δ)` for `k = 0..3`.
    pub(crate) struct LatticeAxis {
        cell: i32,
        offset: [f32; 4],
    }
}

/// What an LRP noise needs per tile once its tables are on the device.
#[derive(Debug, Clone)]
pub(crate) struct LrpKernel {
    /// The model, for the gains of a footprint.
    model: LrpNoise,
    seed: u32,
    mean: f32,
    /// `Δ_s` in f64 (from the model's f32, or fitted to the period along x), per stratum.
    pub(crate) deltas: Vec<f64>,
    /// The lattice periods along y, per stratum (`deltas` unless periodic).
    deltas_y: Vec<f64>,
    /// The period of a periodic model: positions reduced modulo it.
    period: Option<Period>,
    /// The packed strata, for the boxes' record counts.
    strata: Vec<LrpStratum>,
    /// `lrp_draw` on the device (none for the export, whose pixels draw for themselves).
    draw: Option<Arc<OwnPass>>,
}

/// Records (`vec4<f32>`, 16 bytes) of drawn cosines a tile may hold per pixel: LRP's
/// lattices have `J_s/Δ_s²` records per pixel, which stays below 2 for every testdata model
/// (1.9 for lrp-gravel's Δ = 1.25 stratum with J = 3) and for the bench model (0.86 at J = 50);
/// a stratum beyond what is left draws per pixel.
const DRAWS_PER_PIXEL: u64 = 2;

/// The boxes of lattice points a tile's strata draw once, their record and point counts: stratum s's
/// box spans the lattice columns `c − 1 … c + 2` of every column's cell `c` (`columns`,
/// stratum-major, `width` per stratum; rows likewise), as long as the records so far stay
/// within `budget`; a stratum whose box does not fit, or whose box is wider than the i32
/// lattice (cells wrapped around), keeps width 0.
pub(crate) fn draw_boxes(
    strata: &[LrpStratum],
    (columns, width): (&[LatticeAxis], usize),
    (rows, height): (&[LatticeAxis], usize),
    budget: u64,
) -> (Vec<LrpBox>, u64, u32) {
    let span = |axes: &[LatticeAxis]| {
        let lo = axes.iter().map(|a| i64::from(a.cell)).min().unwrap_or(0) - 1;
        let hi = axes.iter().map(|a| i64::from(a.cell)).max().unwrap_or(0) + 2;
        (lo, (hi - lo + 1) as u64)
    };
    let mut boxes = Vec::with_capacity(strata.len());
    let (mut records, mut points) = (0u64, 0u64);
    for (s, stratum) in strata.iter().enumerate() {
        let (x0, w) = span(&columns[s * width..(s + 1) * width]);
        let (y0, h) = span(&rows[s * height..(s + 1) * height]);
        let count = w * h * u64::from(stratum.cosines);
        let mut b = LrpBox {
            x0: x0 as i32,
            y0: y0 as i32,
            first_record: records as u32,
            first_point: points as u32,
            ..bytemuck::Zeroable::zeroed()
        };
        if records + count <= budget && w * h <= u64::from(u32::MAX) {
            b.width = w as u32;
            b.height = h as u32;
            records += count;
            points += w * h;
        }
        boxes.push(b);
    }
    (boxes, records, points as u32)
}

/// An LRP model's tables: its strata, every sub-stratum's `(f_x, f_y)` concatenated, and the
/// `(start, len)` of every sub-stratum's table, strata in order.
#[derive(Debug, Clone)]
struct LrpTables {
    strata: Vec<LrpStratum>,
    frequencies: Vec<[f32; 2]>,
    tables: Vec<[u32; 2]>,
}

/// Packs a validated LRP model, its lattices fitted to `period` when periodic.
fn pack(model: &LrpNoise, period: Option<Period>) -> LrpTables {
    let mut packed = LrpTables {
        strata: Vec::with_capacity(model.strata.len()),
        frequencies: Vec::new(),
        tables: Vec::new(),
    };
    for stratum in &model.strata {
        let [delta, delta_y] = lattice_sides(stratum.window_width, period);
        let cells = period.map_or([0, 0], |p| {
            p.fit_lattice(f64::from(stratum.window_width))
                .cells
                .map(|n| n as i32)
        });
        packed.strata.push(LrpStratum {
            inv_delta2: (1.0 / (delta * delta)) as f32,
            amplitude: stratum.amplitude,
            table_first: packed.tables.len() as u32,
            cosines: stratum.sub_strata.len() as u32,
            delta: delta as f32,
            delta_y: delta_y as f32,
            aspect2: ((delta / delta_y) * (delta / delta_y)) as f32,
            cells_x: cells[0],
            cells_y: cells[1],
        });
        for table in &stratum.sub_strata {
            packed
                .tables
                .push([packed.frequencies.len() as u32, table.len() as u32]);
            packed.frequencies.extend(table);
        }
    }
    packed
}

/// The lattice periods `[Δ_x, Δ_y]` of a stratum of window width `width`: `Δ_S` twice, or
/// the sides of the lattice fitted to `period` (the CPU's).
fn lattice_sides(width: f32, period: Option<Period>) -> [f64; 2] {
    let nominal = f64::from(width);
    period.map_or([nominal, nominal], |p| p.fit_lattice(nominal).side)
}

/// `lrp_draw`: it reads the strata, frequencies and sub-strata (1–3), the gains (6) and the
/// boxes (7) and writes the draws in `output`'s place (9), one invocation a lattice point, 64
/// a workgroup (its `@workgroup_size`).
const DRAW_PASS: OwnPassLayout = OwnPassLayout {
    label: "lrp draw",
    bindings: &[1, 2, 3, 6, 7],
    target: 9,
    workgroup: 64,
    invocations: |uniform| bytemuck::pod_read_unaligned::<LrpParams>(uniform).draw_points,
};

/// [`LatticeAxis`] records for `count` positions `position(i)`, stratum-major.
pub(crate) fn lattice_axis(
    deltas: &[f64],
    count: usize,
    position: impl Fn(usize) -> f64,
) -> Vec<LatticeAxis> {
    let mut records = Vec::with_capacity(deltas.len() * count);
    for &delta in deltas {
        for i in 0..count {
            let x = position(i);
            let cell = (x / delta).floor() as i64;
            let offset = [-1, 0, 1, 2].map(|k| (x - (cell + k) as f64 * delta) as f32);
            records.push(LatticeAxis {
                cell: cell as i32,
                offset,
            });
        }
    }
    records
}

/// The kernel of a validated model (periodic with `period` when given) and the tables it keeps
/// on the device, in binding order, with the frequency tables' size in bytes: what the device
/// evaluator uploads and what the WGSL export writes as constants.
pub(crate) fn host(model: &LrpNoise, period: Option<Period>) -> (LrpKernel, Vec<Table>, u64) {
    let packed = pack(model, period);
    let frequency_bytes = size_of_val(packed.frequencies.as_slice()) as u64;
    let sides: Vec<[f64; 2]> = model
        .strata
        .iter()
        .map(|s| lattice_sides(s.window_width, period))
        .collect();
    let kernel = LrpKernel {
        model: model.clone(),
        seed: model.seed,
        mean: model.mean,
        deltas: sides.iter().map(|s| s[0]).collect(),
        deltas_y: sides.iter().map(|s| s[1]).collect(),
        period,
        strata: packed.strata.clone(),
        draw: None,
    };
    let tables = vec![
        Table::new("lrp strata", &packed.strata),
        Table::new("lrp frequencies", &packed.frequencies),
        Table::new("lrp tables", &packed.tables),
    ];
    (kernel, tables, frequency_bytes)
}

impl GpuKind for LrpNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "lrp",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["lrp_draw", "lrp_main"],
    });

    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (mut kernel, tables, needed) = host(self, period);
        let limit = binding_limit(&context.limits());
        if needed > limit {
            return Err(GpuError::LimitsExceeded {
                what: "frequency tables (bytes in one storage buffer)",
                value: needed,
                limit,
            });
        }
        kernel.draw = Some(OwnPass::new(context, "lrp", "lrp_draw")?);
        Shaded::boxed(context, kernel, &tables)
    }
}

impl ShaderKernel for LrpKernel {
    const SHADER: &'static str = "lrp";
    const ENTRY_POINT: &'static str = "lrp_main";

    fn axis_bytes(&self) -> u64 {
        (size_of::<LatticeAxis>() * self.deltas.len()) as u64
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        limit: u64,
    ) -> Result<TileTables, GpuError> {
        let params = LrpParams {
            width: tile.width as u32,
            height: tile.height as u32,
            strata: self.deltas.len() as u32,
            seed: self.seed,
            mean: self.mean,
            filtered: u32::from(tile.footprint().is_some()),
            ..bytemuck::Zeroable::zeroed()
        };
        // Every table entry's gain, in the order of the frequencies (the CPU's, from the same
        // function); an unused 1 when unfiltered (a binding holds at least one element).
        let gains: Vec<f32> = match tile.footprint() {
            Some(side) => spectex_model::filter::lrp_gains(&self.model, side)
                .into_iter()
                .flatten()
                .collect(),
            None => vec![1.0],
        };
        let columns = lattice_axis(
            &self.deltas,
            tile.width,
            periodic_columns(tile, self.period),
        );
        let rows = lattice_axis(
            &self.deltas_y,
            tile.height,
            periodic_rows(tile, self.period),
        );
        // A displaced tile's pixels move to other cells: they draw for themselves.
        let draw = self.draw.as_ref().filter(|_| !displacement.is_some());
        let (boxes, records, points) = match draw {
            Some(_) => {
                let pixels = (tile.width * tile.height) as u64;
                let budget = (DRAWS_PER_PIXEL * pixels).min(limit / 16);
                draw_boxes(
                    &self.strata,
                    (&columns, tile.width),
                    (&rows, tile.height),
                    budget,
                )
            }
            None => (vec![bytemuck::Zeroable::zeroed(); self.deltas.len()], 0, 0),
        };
        // The pass's uniform: the tile's, with its point count and grid row.
        let pass = match draw {
            Some(draw) if records > 0 => Some(LrpParams {
                draw_points: points,
                draw_stride: flat_grid(&draw.gpu, points, DRAW_PASS.workgroup).0,
                ..params
            }),
            _ => None,
        };
        let draws = Table::left_to_pass("lrp draws", pass.map(|_| 16 * records));
        Ok(TileTables::new(
            &params,
            vec![
                Table::new("lrp columns", &columns),
                Table::new("lrp rows", &rows),
                Table::new("lrp gains", &gains),
                Table::new("lrp boxes", &boxes),
                draws,
            ],
        )
        .with_pass(pass.as_ref()))
    }

    fn own_pass(&self) -> Option<(&OwnPass, &'static OwnPassLayout)> {
        self.draw.as_deref().map(|pass| (pass, &DRAW_PASS))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for LrpNoise {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, tables, _) = host(self, None);
        // Stratum s's lattice is the export's lattice s (the glue of lrp.wgsl).
        let lattices = kernel.deltas.clone();
        // The strata written out (`LRP_EXPORT_STRATA`, lrp.wgsl's glue), their records and
        // table bounds constants even when the frequencies go to a buffer: lrp-gravel's export
        // (4 strata, J = 3) ran in half the time on lavapipe (27 → 13 calibration cosines an
        // evaluation, `cargo bench -p spectex-crosscheck --bench export`).
        Ok(ExportParts::of(&kernel, &tables, lattices, "lrp")?
            .with_unrolled("LRP_EXPORT_STRATA", kernel.deltas.len(), |s| {
                format!("total += lrp_export_stratum(at.n, at.u, {s}u);")
            })
            .with_constant_tables(&["strata", "tables"]))
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    /// A binding kept constant that the shader does not declare is an error, not a silent
    /// no-op (`ExportParts::with_constant_tables`).
    pub fn an_unknown_constant_table_is_refused() {
        use crate::export::{ExportOptions, TableStorage, emit};
        use spectex_model::Stratum;
        let m = LrpNoise {
            seed: 3,
            mean: 0.5,
            strata: vec![Stratum {
                window_width: 4.0,
                amplitude: 1.0,
                sub_strata: vec![vec![[0.1, 0.2], [0.3, 0.0]]],
            }],
        };
        let model = spectex_model::Model::Lrp(m.clone());
        let options = ExportOptions {
            tables: TableStorage::Buffer {
                group: 3,
                binding: 100,
            },
            ..ExportOptions::default()
        };
        let node = m.export_parts(0.0).unwrap();
        assert!(emit(&model, &node, &options).is_ok());
        let wrong = node.with_constant_tables(&["strata", "no_such_table"]);
        match emit(&model, &wrong, &options) {
            Err(GpuError::Validation(why)) => assert!(why.contains("no_such_table"), "{why}"),
            other => panic!("{other:?}"),
        }
    }

    pub fn records_match_the_wgsl() {
        assert_matches_wgsl::<LrpParams>("lrp", "LrpParams");
        assert_matches_wgsl::<LrpStratum>("lrp", "LrpStratum");
        assert_matches_wgsl::<LatticeAxis>("lrp", "LatticeAxis");
        assert_matches_wgsl::<LrpBox>("lrp", "LrpBox");
    }

    /// Boxes worked by hand: Δ = 10, columns at x = 5, 15, 25 (cells 0, 1, 2) reach lattice
    /// columns −1 … 4; a stratum over the budget keeps width 0 and the next one starts where
    /// the drawn ones end.
    pub fn boxes_hold_every_reached_point_within_the_budget() {
        let stratum = |cosines| LrpStratum {
            cosines,
            ..bytemuck::Zeroable::zeroed()
        };
        let strata = [stratum(3), stratum(100), stratum(2)];
        let deltas = [10.0, 10.0, 10.0];
        let columns = lattice_axis(&deltas, 3, |i| 5.0 + 10.0 * i as f64);
        let rows = lattice_axis(&deltas, 2, |j| -12.0 + 3.0 * j as f64);
        // Rows at −12 and −9: cells −2 and −1, lattice rows −3 … 1.
        let (boxes, records, points) = draw_boxes(&strata, (&columns, 3), (&rows, 2), 200);
        let want = |x0, y0, width, height, first_record, first_point| LrpBox {
            x0,
            y0,
            width,
            height,
            first_record,
            first_point,
        };
        assert_eq!(boxes[0], want(-1, -3, 6, 5, 0, 0));
        // 30 points × 100 cosines do not fit the 110 records left of 200.
        assert_eq!(boxes[1], want(-1, -3, 0, 0, 90, 30));
        assert_eq!(boxes[2], want(-1, -3, 6, 5, 90, 30));
        assert_eq!(records, 90 + 60);
        assert_eq!(points, 30 + 30);
        // Every lattice point a pixel's loop reaches lies in a drawn box.
        for (s, b) in boxes.iter().enumerate().filter(|(_, b)| b.width > 0) {
            for c in &columns[3 * s..3 * s + 3] {
                for r in &rows[2 * s..2 * s + 2] {
                    for k in 0..4 {
                        let (i, j) = (c.cell + k - 1 - b.x0, r.cell + k - 1 - b.y0);
                        assert!((0..b.width as i32).contains(&i), "{s} {c:?}");
                        assert!((0..b.height as i32).contains(&j), "{s} {r:?}");
                    }
                }
            }
        }
    }

    /// `lrp_main` reading the points `lrp_draw` drew gives the bits of the pixels drawing for
    /// themselves (the export's and a displaced tile's way): a stratum too dense for the
    /// budget (Δ = 1, J = 4: 4 records a pixel) beside drawn ones, at 10⁶ and minified.
    pub fn drawn_points_render_the_per_pixel_bits() {
        use crate::layout::check::context_or_skip;
        use crate::pipeline::assert_own_pass_keeps_bits;
        use spectex_model::Stratum;
        let Some(context) = context_or_skip("drawn_points_render_the_per_pixel_bits") else {
            return;
        };
        let mut m = spectex_model::fixtures::lrp_four_strata(10);
        m.strata.insert(
            1,
            Stratum {
                window_width: 1.0,
                amplitude: 0.05,
                sub_strata: m.strata[0].sub_strata.iter().take(4).cloned().collect(),
            },
        );
        let tiles = [
            GpuWindow::new(37, 21).at([1.0e6, -3.0e5], 1.0),
            GpuWindow::new(19, 13).at([-40.5, 7.25], 3.5),
        ];
        for tile in &tiles {
            let (kernel, tables, _) = host(&m, None);
            let mut drawn = kernel.clone();
            drawn.draw = Some(OwnPass::new(&context, "lrp", "lrp_draw").unwrap());
            let prepared = drawn
                .tile_tables(tile, TileDisplacement::None, u64::MAX)
                .unwrap();
            let boxes: &[LrpBox] = bytemuck::cast_slice(&prepared.tables[3].bytes);
            assert_eq!(boxes[1].width, 0, "the dense stratum draws per pixel");
            assert!(boxes.iter().filter(|b| b.width > 0).count() >= 3);
            assert_own_pass_keeps_bits(&context, (drawn, kernel), &tables, tile);
        }
    }

    pub fn lattice_offsets_are_the_rounded_f64_differences() {
        let records = lattice_axis(&[9.5], 3, |i| 1.0e7 + i as f64 * 0.25);
        for (i, r) in records.iter().enumerate() {
            let x = 1.0e7 + i as f64 * 0.25;
            let cell = (x / 9.5).floor() as i64;
            assert_eq!(i64::from(r.cell), cell);
            for k in 0..4 {
                let want = (x - (cell + k as i64 - 1) as f64 * 9.5) as f32;
                assert_eq!(r.offset[k], want);
            }
            // The pixel lies in [cell, cell + 1) lattice steps: offset k = 1 is in [0, Δ).
            assert!((0.0..=9.5).contains(&r.offset[1]), "{}", r.offset[1]);
        }
    }

    pub fn pack_concatenates_tables_in_order() {
        use spectex_model::Stratum;
        let m = LrpNoise {
            seed: 3,
            mean: 0.5,
            strata: vec![
                Stratum {
                    window_width: 4.0,
                    amplitude: 1.0,
                    sub_strata: vec![vec![[0.1, 0.2]], vec![[0.3, 0.4], [0.0, 0.1]]],
                },
                Stratum {
                    window_width: 8.0,
                    amplitude: 2.0,
                    sub_strata: vec![vec![[0.25, 0.0]]],
                },
            ],
        };
        let p = pack(&m, None);
        assert_eq!(p.tables, [[0, 1], [1, 2], [3, 1]]);
        assert_eq!(
            (
                p.strata[0].table_first,
                p.strata[0].cosines,
                p.strata[0].delta
            ),
            (0, 2, 4.0)
        );
        assert_eq!(
            (
                p.strata[1].table_first,
                p.strata[1].cosines,
                p.strata[1].delta
            ),
            (2, 1, 8.0)
        );
        assert_eq!(p.strata[0].inv_delta2, 1.0 / 16.0);
        assert_eq!(p.frequencies[3], [0.25, 0.0]);
        // The bytes the device receives: a stratum is nine words, in the WGSL's order.
        let words: &[u32] = bytemuck::cast_slice(&p.strata);
        assert_eq!(
            words[11..18],
            [
                2,
                1,
                8.0f32.to_bits(),
                8.0f32.to_bits(),
                1.0f32.to_bits(),
                0,
                0
            ]
        );
        // Fitted to a 96×64 period: Δ = 4 divides both (24 × 16 cells), Δ = 8 too (12 × 8).
        let periodic = pack(&m, Some(Period::new(96, 64).unwrap()));
        let cells: Vec<[i32; 2]> = periodic
            .strata
            .iter()
            .map(|s| [s.cells_x, s.cells_y])
            .collect();
        assert_eq!(cells, [[24, 16], [12, 8]]);
    }
}
