//! Texton placement / spot noise on the device (`shaders/texton.wgsl`): the model's constants
//! in the uniform, its Poisson CDF and image texels packed once, and per tile each column's and
//! row's texton-grid cell and offset (the CPU's split), and the box of cells `texton_draw`
//! draws once on the device.
//!
//! The texton noise's export (the glue of `shaders/texton.wgsl`): the compute shader's uniform
//! and model data; the texton grid is the export's only lattice.

use std::sync::Arc;

use spectex_model::texton::{Combine, MAX_TEXTONS_PER_CELL, Placement, Spot};
use spectex_model::{Period, TextonNoise};

use crate::axis::{CellAxes, CellAxis};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::{OwnPass, OwnPassLayout, Shaded};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/texton.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/texton.wgsl"));

wgsl_struct! {
    /// `TextonParams` of `texton.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct TextonParams {
        width: u32,
        height: u32,
        seed: u32,
        reach: i32,
        /// 0: grid, 1: Poisson.
        placement: u32,
        /// 0: ellipsoid, 1: Gaussian, 2: image.
        spot: u32,
        /// 0: sum, 1: maximum.
        combine: u32,
        image_width: u32,
        image_height: u32,
        jitter: f32,
        cell_size: f32,
        /// `1/C` (f32 of the f64 value), for warping.
        inv_cell: f32,
        radius_a: f32,
        radius_b: f32,
        rotation_lo: f32,
        rotation_hi: f32,
        scale_lo: f32,
        scale_hi: f32,
        intensity_lo: f32,
        intensity_hi: f32,
        mean: f32,
        // Padding to a whole 16-byte uniform row, as the WGSL struct has it.
        _pad0: u32,
        /// The cell box's first column and row.
        box_i0: i32,
        box_j0: i32,
        /// Cells per period along x and y of a periodic model (cells hashed modulo them,
        /// `wrap_cell`), 0 when not periodic.
        cells_x: i32,
        cells_y: i32,
        /// The cell box's columns and rows (0 columns where the draws table holds nothing);
        /// `texton_draw`'s invocations per row of its grid.
        box_cols: u32,
        box_rows: u32,
        draw_stride: u32,
        _pad1: u32,
        _pad2: u32,
        _pad3: u32,
    }
}

/// `texton_draw`: it reads the model data (1: the Poisson CDF) and writes the draws in
/// `output`'s place (5), one invocation a cell of the box, 64 a workgroup (its
/// `@workgroup_size`).
const DRAW_PASS: OwnPassLayout = OwnPassLayout {
    label: "texton draw",
    bindings: &[1],
    target: 5,
    workgroup: 64,
    invocations: |uniform| {
        let p = bytemuck::pod_read_unaligned::<TextonParams>(uniform);
        p.box_cols * p.box_rows
    },
};

/// A texton model on the device.
#[derive(Debug, Clone)]
pub(crate) struct TextonKernel {
    pub(crate) cell_size: f64,
    params: TextonParams,
    /// The period of a periodic model: positions reduced modulo it.
    period: Option<Period>,
    /// `texton_draw` on the device (none for the export, whose pixels draw for themselves).
    draw: Option<Arc<OwnPass>>,
}

impl GpuKind for TextonNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "texton",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["texton_main", "texton_draw"],
    });

    /// Periodic: the CPU's `TextonEvaluator::new_periodic`: the cell divides the period, cells
    /// hashed modulo the cells per period.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (mut kernel, data) = host(self);
        if let Some(period) = period {
            let cells = period.cells(kernel.cell_size);
            kernel.params.cells_x = cells[0] as i32;
            kernel.params.cells_y = cells[1] as i32;
            kernel.period = Some(period);
        }
        kernel.draw = Some(OwnPass::new(context, "texton", "texton_draw")?);
        Shaded::boxed(context, kernel, &[Table::new("texton model data", &data)])
    }
}

/// The kernel of a validated model and its model data (the Poisson CDF, then the image's
/// texels): what the device evaluator uploads and what the WGSL export writes.
pub(crate) fn host(model: &TextonNoise) -> (TextonKernel, Vec<f32>) {
    let this = model;
    {
        let (jitter, placement) = match this.placement {
            Placement::Grid { jitter } => (jitter, 0),
            Placement::Poisson { .. } => (0.0, 1),
        };
        // The CDF (zeros for a grid, which never reads it), then the image's texels.
        let mut data: Vec<f32> = this
            .poisson_cdf()
            .unwrap_or([0.0; MAX_TEXTONS_PER_CELL as usize])
            .to_vec();
        let (spot, image_width, image_height) = match &this.spot {
            Spot::Ellipsoid => (0, 0, 0),
            Spot::Gaussian => (1, 0, 0),
            Spot::Image {
                width,
                height,
                values,
            } => {
                data.extend_from_slice(values);
                (2, *width, *height)
            }
        };
        let kernel = TextonKernel {
            cell_size: f64::from(this.cell_size),
            params: TextonParams {
                width: 0,
                height: 0,
                seed: this.seed,
                reach: this.reach(),
                placement,
                spot,
                combine: match this.combine {
                    Combine::Sum => 0,
                    Combine::Max => 1,
                },
                image_width,
                image_height,
                jitter,
                cell_size: this.cell_size,
                inv_cell: (1.0 / f64::from(this.cell_size)) as f32,
                radius_a: this.radii[0],
                radius_b: this.radii[1],
                rotation_lo: this.rotation[0],
                rotation_hi: this.rotation[1],
                scale_lo: this.scale[0],
                scale_hi: this.scale[1],
                intensity_lo: this.intensity[0],
                intensity_hi: this.intensity[1],
                mean: this.mean,
                ..bytemuck::Zeroable::zeroed()
            },
            period: None,
            draw: None,
        };
        (kernel, data)
    }
}

impl ShaderKernel for TextonKernel {
    const SHADER: &'static str = "texton";
    const ENTRY_POINT: &'static str = "texton_main";

    const SHAPE: &'static [&'static str] = &[
        "TEXTON_COMBINE",
        "TEXTON_PLACEMENT",
        "TEXTON_SPOT",
        "TEXTON_REACH",
    ];

    /// The model's combine, placement, spot and search reach (the shader's shape overrides).
    fn shape(&self) -> Vec<u32> {
        let p = &self.params;
        vec![p.combine, p.placement, p.spot, p.reach as u32]
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<CellAxis>() as u64
    }

    /// The tile's axes and, with `texton_draw`, the draws of its box of cells (the cells of
    /// its pixels and those within `reach`), left to the device; where they would not fit
    /// `limit` or `MAX_PASS_TABLE_BYTES`, the pixels draw for themselves, as a displaced
    /// tile's do (its pixels leave the box).
    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        limit: u64,
    ) -> Result<TileTables, GpuError> {
        let mut params = TextonParams {
            width: tile.width as u32,
            height: tile.height as u32,
            ..self.params
        };
        let axes = CellAxes::new(self.cell_size, tile, self.period);
        let per_cell = if params.placement == 1 {
            MAX_TEXTONS_PER_CELL as u64
        } else {
            1
        };
        let drawn = match &self.draw {
            Some(draw) if !displacement.is_some() => draw.draw_box(
                axes.cell_range(tile, displacement)?,
                (params.reach.unsigned_abs(), (1 + 2 * per_cell) * 16),
                (DRAW_PASS.workgroup, limit),
            ),
            _ => None,
        };
        if let Some(b) = drawn {
            (params.box_i0, params.box_j0) = (b.i0, b.j0);
            (params.box_cols, params.box_rows, params.draw_stride) = (b.cols, b.rows, b.stride);
        }
        let draws = Table::left_to_pass("texton draws", drawn.map(|b| b.bytes));
        Ok(TileTables::new(
            &params,
            std::iter::once(draws)
                .chain(axes.tables(["texton columns", "texton rows"]))
                .collect(),
        )
        .with_pass(drawn.map(|_| &params)))
    }

    fn own_pass(&self) -> Option<(&OwnPass, &'static OwnPassLayout)> {
        self.draw.as_deref().map(|pass| (pass, &DRAW_PASS))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for TextonNoise {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, data) = host(self);
        // The texton grid is the export's lattice 0 (the glue of texton.wgsl).
        let lattices = vec![kernel.cell_size];
        ExportParts::of(
            &kernel,
            &[Table::new("texton model data", &data)],
            lattices,
            "texton",
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
        assert_matches_wgsl::<TextonParams>("texton", "TextonParams");
    }

    /// A tile whose cells `texton_draw` drew once renders the bits of the same tile whose
    /// pixels draw for themselves: Poisson placement with Gaussian spots kept by their
    /// maximum, and a jittered grid of image spots reaching two cells, summed; far from the
    /// origin, magnified, minified, on tiles whose sides are not multiples of the workgroup,
    /// and periodic across the period. Each tile must really be drawn (its one pass
    /// prepared). Not the ellipsoid: lavapipe folds the per-pixel path's `q·(1/(a·s))` into a
    /// division, where the drawn path keeps the CPU's product (its texton-ellipsoids render
    /// is the CPU's bit for bit, the per-pixel one differs in 321 bytes of 128,690).
    pub fn drawn_cells_render_the_per_pixel_bits() {
        use crate::layout::check::context_or_skip;
        use crate::pipeline::assert_own_pass_keeps_bits;
        let Some(context) = context_or_skip("texton drawn_cells_render_the_per_pixel_bits") else {
            return;
        };
        let poisson = TextonNoise {
            seed: 4,
            cell_size: 12.0,
            placement: Placement::Poisson { density: 3.0 },
            spot: Spot::Gaussian,
            radii: [9.0, 5.0],
            rotation: [0.0, 1.0],
            scale: [0.7, 1.3],
            intensity: [0.2, 1.0],
            combine: Combine::Max,
            mean: 0.1,
        };
        let image = TextonNoise {
            seed: 9,
            cell_size: 10.0,
            placement: Placement::Grid { jitter: 0.8 },
            spot: Spot::Image {
                width: 3,
                height: 2,
                values: vec![0.0, 1.0, 0.5, 0.25, 0.75, 0.1],
            },
            radii: [16.0, 7.0],
            rotation: [-0.2, 0.2],
            scale: [0.9, 1.2],
            intensity: [-0.5, 0.5],
            combine: Combine::Sum,
            mean: 0.5,
        };
        assert!(image.reach() >= 2, "the image spots reach two cells");
        let period = Period::new(120, 60).unwrap();
        let cases = [
            (
                &poisson,
                None,
                GpuWindow::new(37, 21).at([1.0e6, -3.0e5], 1.0),
            ),
            (
                &poisson,
                None,
                GpuWindow::new(19, 13).at([-40.5, 7.25], 3.5),
            ),
            (&image, None, GpuWindow::new(40, 24).at([3.0, 5.0], 0.37)),
            (
                &image,
                Some(period),
                GpuWindow::new(48, 40).at([100.0, 30.0], 1.0),
            ),
        ];
        for (model, period, tile) in cases {
            let (mut kernel, data) = host(model);
            if let Some(period) = period {
                let cells = period.cells(kernel.cell_size);
                (kernel.params.cells_x, kernel.params.cells_y) = (cells[0] as i32, cells[1] as i32);
                kernel.period = Some(period);
            }
            let mut drawn = kernel.clone();
            drawn.draw = Some(OwnPass::new(&context, "texton", "texton_draw").unwrap());
            let tables = [Table::new("texton model data", &data)];
            assert_own_pass_keeps_bits(&context, (drawn, kernel), &tables, &tile);
        }
    }
}
