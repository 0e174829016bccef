//! Voronoi diagrams on the device (`shaders/voronoi.wgsl`): per tile, the host computes the
//! sites of the box of lattice cells the tile's pixels search (`spectex_model::voronoi`, Lloyd
//! relaxation included, so the device reads the CPU's f32 seeds, IDs and colours), and each
//! column's and row's cell and offset (the CPU's split); the shader runs the search. A 3D
//! diagram's box spans the planes of cells its search reaches around the plane `z`.
//!
//! A Voronoi diagram's export (the glue of `shaders/voronoi.wgsl`): the compute shader's uniform
//! and the constants with which the glue draws each searched cell's site in the shader (the
//! compute path's host draws a box of sites per tile).
//!
//! Lloyd relaxation is refused ([`GpuError::Unsupported`] naming it): the host relaxes each
//! block in f64 (exact centroids of clipped Voronoi cells, Jacobi sweeps over the block and
//! its ring), which a shader could only approximate in f32 — a relaxed seed's error there has
//! no derived bound, and a seed on the other side of a bisector changes a cell's ID and
//! colour. So is the image colour output: its texel is `⌊(i + o)·C⌋ mod W` in f64, which f32
//! cannot locate far from the origin. The default (jittered seeds, the cell ID) and the ID,
//! distance, border and palette outputs export.

use std::sync::Arc;

use spectex_model::ModelKind;
use spectex_model::Period;
use spectex_model::grid::locate_cell;

use spectex_model::voronoi::{BlockCache, VoronoiNoise, VoronoiOutput};

use crate::axis::{CellAxes, CellAxis};
use crate::export::{ExportKind, ExportNode, ExportParts, float};
use crate::kernel::{
    DisplacementRead, GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables,
    halve_tile_to_fit,
};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/voronoi.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/voronoi.wgsl"));

wgsl_struct! {
    /// `VoronoiParams` of `voronoi.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct VoronoiParams {
        width: u32,
        height: u32,
        reach: i32,
        /// 0: cell ID, 1: F1, 2: border, 3: F2 − F1, 4: colour.
        output: u32,
        box_i0: i32,
        box_j0: i32,
        box_cols: u32,
        box_rows: u32,
        /// `1/C` (f32 of the f64 value), for warping.
        inv_cell: f32,
        /// 0 in 2D; in 3D the box's planes, `2·reach + 1` from `z_cell − reach`.
        box_depth: u32,
        /// A 3D model's plane `z`: its cell and offset (`locate_cell`), 0 in 2D.
        z_cell: i32,
        z_offset: f32,
    }
}

/// Floats per site in the table: offset x, y, ID, colour r, g, b.
const SITE_FLOATS: usize = 6;
/// Floats per site of a 3D table: those of [`SITE_FLOATS`], then offset z.
const SITE3_FLOATS: usize = 7;

/// A Voronoi model on the device.
#[derive(Debug, Clone)]
pub(crate) struct VoronoiKernel {
    model: VoronoiNoise,
    params: VoronoiParams,
    /// The period of a periodic model and its cells per period: positions reduced modulo it,
    /// sites drawn by `VoronoiNoise::sites_periodic` (cells and Lloyd blocks wrapped).
    period: Option<(Period, [i64; 2])>,
    /// Relaxed Lloyd blocks, kept for the kernel's life and shared by the workers preparing
    /// its tiles, as the CPU evaluator keeps its own: a block under the margins of several
    /// tiles' boxes is relaxed once, not once per tile (a 512² tile of 16-pixel cells and
    /// 5-cell blocks reached about 1.75 times the blocks it covers). Relaxation is a function
    /// of the block alone, so the sites are the same bits.
    blocks: Arc<BlockCache>,
}

impl VoronoiKernel {
    fn side(&self) -> f64 {
        f64::from(self.model.cell_size)
    }

    /// Cells of a tile's box at `scale` (its span plus the search reach each side, and one
    /// more for rounding).
    fn box_cells(&self, width: usize, height: usize, scale: f64) -> f64 {
        let margin = 2.0 * f64::from(self.params.reach) + 3.0;
        let along = |n: usize| n as f64 * scale / self.side() + margin;
        along(width) * along(height) * f64::from(self.params.box_depth.max(1))
    }

    /// Floats per site of the table.
    fn site_floats(&self) -> usize {
        if self.params.box_depth > 0 {
            SITE3_FLOATS
        } else {
            SITE_FLOATS
        }
    }
}

impl GpuKind for VoronoiNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "voronoi",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["voronoi_main"],
    });

    /// Periodic: the CPU's periodic Voronoi diagram: the host draws the sites with the cells
    /// and Lloyd blocks wrapped, at positions reduced modulo the period. A 3D model is cut at
    /// the plane `z`.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        Shaded::boxed(context, pack(self, period).at_z(z), &[])
    }
}

impl VoronoiKernel {
    /// The kernel on the plane `z` (pixels; 2D models ignore it).
    pub(crate) fn at_z(mut self, z: f64) -> Self {
        if self.model.dimensions == 3 {
            let (cell, offset) = locate_cell(z, self.side()).unwrap_or((0, 0.0));
            self.params.z_cell = cell;
            self.params.z_offset = offset;
        }
        self
    }
}

/// The kernel of a Voronoi model, periodic with `period` when given (a 3D one on the plane
/// `z = 0`: [`VoronoiKernel::at_z`]).
pub(crate) fn pack(model: &VoronoiNoise, period: Option<Period>) -> VoronoiKernel {
    let reach = model.reach();
    let box_depth = if model.dimensions == 3 {
        (2 * reach + 1) as u32
    } else {
        0
    };
    let output = match model.output {
        VoronoiOutput::CellId => 0,
        VoronoiOutput::F1 => 1,
        VoronoiOutput::Border => 2,
        VoronoiOutput::F2MinusF1 => 3,
        VoronoiOutput::Palette { .. } | VoronoiOutput::Image { .. } => 4,
    };
    VoronoiKernel {
        model: model.clone(),
        params: VoronoiParams {
            width: 0,
            height: 0,
            reach,
            output,
            box_i0: 0,
            box_j0: 0,
            box_cols: 0,
            box_rows: 0,
            inv_cell: (1.0 / f64::from(model.cell_size)) as f32,
            box_depth,
            z_cell: 0,
            z_offset: 0.0,
        },
        period: period.map(|p| (p, p.cells(f64::from(model.cell_size)))),
        blocks: Arc::default(),
    }
}

impl ShaderKernel for VoronoiKernel {
    const SHADER: &'static str = "voronoi";
    const ENTRY_POINT: &'static str = "voronoi_main";
    const SHAPE: &'static [&'static str] = &["VORONOI_OUTPUT", "VORONOI_REACH", "VORONOI_THREE_D"];

    /// The box of sites covers the displaced pixels' cells: their range is enough.
    fn displacement_read(&self) -> DisplacementRead {
        DisplacementRead::Range
    }

    /// The model's output, search reach and dimension (the shader's shape overrides).
    fn shape(&self) -> Vec<u32> {
        let p = &self.params;
        vec![p.output, p.reach as u32, u32::from(p.box_depth > 0)]
    }

    fn output_channels(&self) -> usize {
        self.model.output.channels()
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<CellAxis>() as u64
    }

    /// The output (3 values for colour) or the displacement (2 values).
    fn pixel_bytes(&self) -> u64 {
        4 * self.model.output.channels().max(2) as u64
    }

    /// The tile's box of sites must fit one buffer.
    fn fit_tile(
        &self,
        window: &GpuWindow,
        tile: [usize; 2],
        limit: u64,
    ) -> Result<[usize; 2], GpuError> {
        let per_cell = (self.site_floats() * 4) as f64;
        Ok(halve_tile_to_fit(tile, per_cell, limit, |w, h| {
            self.box_cells(w, h, window.scale)
        }))
    }

    /// The box covers every (displaced) pixel's search: the cells of its pixels, widened by one
    /// cell for the shader's f32 relocation of a displaced pixel, and by the reach.
    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        limit: u64,
    ) -> Result<TileTables, GpuError> {
        let side = self.side();
        let (width, height) = (tile.width, tile.height);
        let period = self.period.map(|(p, _)| p);
        let axes = CellAxes::new(side, tile, period);
        let range = axes
            .cell_range(tile, displacement)?
            .map(|r| r.map(|(lo, hi)| (i64::from(lo), i64::from(hi))));
        let margin = i64::from(self.params.reach) + i64::from(displacement.is_some());
        let mut params = VoronoiParams {
            width: width as u32,
            height: height as u32,
            ..self.params
        };
        let mut data: Vec<f32> = Vec::new();
        if let [Some((i_lo, i_hi)), Some((j_lo, j_hi))] = range {
            let (i0, j0) = (i_lo - margin, j_lo - margin);
            let cols = (i_hi + margin - i0 + 1) as usize;
            let rows_n = (j_hi + margin - j0 + 1) as usize;
            let depth = (self.params.box_depth as usize).max(1);
            let bytes = (cols * rows_n * depth * self.site_floats() * 4) as u64;
            if bytes > limit {
                return Err(GpuError::LimitsExceeded {
                    what: "bytes of a tile's Voronoi site table (a smaller tile, scale or warp \
                           strength)",
                    value: bytes,
                    limit,
                });
            }
            if self.params.box_depth > 0 {
                let cells = self.period.map(|(_, c)| c);
                let k0 = i64::from(self.params.z_cell) - i64::from(self.params.reach);
                let table = self
                    .model
                    .sites3([i0, j0, k0], [cols, rows_n, depth], cells);
                data.reserve(cols * rows_n * depth * SITE3_FLOATS);
                for s in &table.sites {
                    data.extend([
                        s.offset[0],
                        s.offset[1],
                        s.id,
                        s.colour[0],
                        s.colour[1],
                        s.colour[2],
                        s.offset[2],
                    ]);
                }
            }
            let table = match self.period {
                _ if self.params.box_depth > 0 => None,
                None => Some(self.model.sites_cached(i0, j0, cols, rows_n, &self.blocks)),
                Some((_, cells)) => {
                    Some(
                        self.model
                            .sites_periodic(i0, j0, cols, rows_n, &self.blocks, cells),
                    )
                }
            };
            data.reserve(cols * rows_n * SITE_FLOATS);
            for s in table.iter().flat_map(|t| &t.sites) {
                data.extend([
                    s.offset[0],
                    s.offset[1],
                    s.id,
                    s.colour[0],
                    s.colour[1],
                    s.colour[2],
                ]);
            }
            // Cells are i32 on the device; a box beyond that range is only at |p| near the
            // limits, where the axis records are invalid anyway.
            params.box_i0 = i0 as i32;
            params.box_j0 = j0 as i32;
            params.box_cols = cols as u32;
            params.box_rows = rows_n as u32;
        }
        Ok(TileTables::new(
            &params,
            vec![Table::new("voronoi sites", &data)]
                .into_iter()
                .chain(axes.tables(["voronoi columns", "voronoi rows"]))
                .collect(),
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for VoronoiNoise {
    const GLUE: &'static str = WGSL.1;

    /// A 3D diagram exports its plane `z`.
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let refuse = |feature: &str| GpuError::Unsupported {
            kind: VoronoiNoise::NAME,
            feature: format!("WGSL export of {feature}"),
        };
        if self.lloyd_iterations > 0 {
            return Err(refuse(
                "Lloyd-relaxed seeds (lloyd_iterations > 0: the host relaxes them in f64)",
            ));
        }
        let palette = match &self.output {
            VoronoiOutput::Image { .. } => {
                return Err(refuse(
                    "the image colour output (its texel under a seed is located in f64)",
                ));
            }
            VoronoiOutput::Palette { colours } => colours.clone(),
            _ => vec![[0.0; 3]],
        };
        let kernel = pack(self, None).at_z(z);
        let colours = palette
            .iter()
            .map(|c| {
                format!(
                    "vec3<f32>({}, {}, {})",
                    float(c[0]),
                    float(c[1]),
                    float(c[2])
                )
            })
            .collect::<Vec<_>>()
            .join(", ");
        let n = palette.len();
        let constants = format!(
            "const voronoi_export_seed: u32 = {}u;\n\
             const voronoi_export_jitter: f32 = {};\n\
             const voronoi_export_colours: u32 = {n}u;\n\
             var<private> voronoi_export_palette: array<vec3<f32>, {n}> = \
             array<vec3<f32>, {n}>({colours});\n\
             /// The output binding `write_value` of voronoi.wgsl writes to (unused here).\n\
             var<private> output: array<f32, 3>;\n",
            self.seed,
            float(self.jitter),
        );
        // The seed lattice is the export's lattice 0 (the glue of voronoi.wgsl).
        let (value, result) = if self.output.channels() == 1 {
            ("f32", "v.x")
        } else {
            ("vec3<f32>", "v")
        };
        Ok(
            ExportParts::of(&kernel, &[], vec![f64::from(self.cell_size)], "voronoi")?
                .with_constants(constants)
                .with_substitutions(vec![
                    ("VORONOI_VALUE", value.to_owned()),
                    ("VORONOI_RESULT", result.to_owned()),
                ]),
        )
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    pub fn params_match_the_wgsl() {
        assert_matches_wgsl::<VoronoiParams>("voronoi", "VoronoiParams");
    }
}
