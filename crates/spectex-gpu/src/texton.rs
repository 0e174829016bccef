//! Texton placement / spot noise on the device (`shaders/texton.wgsl`): the model's constants
//! in the uniform, its Poisson CDF and image texels packed once, and per tile each column's and
//! row's texton-grid cell and offset (the CPU's split).
//!
//! The texton noise's export (the glue of `shaders/texton.wgsl`): the compute shader's uniform
//! and model data; the texton grid is the export's only lattice.

use spectex_model::texton::{Combine, MAX_TEXTONS_PER_CELL, Placement, Spot};
use spectex_model::{Period, TextonNoise};

use crate::axis::{CellAxes, CellAxis};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
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
        _pad1: u32,
        _pad2: u32,
        /// Cells per period along x and y of a periodic model (cells hashed modulo them,
        /// `wrap_cell`), 0 when not periodic.
        cells_x: i32,
        cells_y: i32,
        _pad3: u32,
        _pad4: u32,
    }
}

/// A texton model on the device.
#[derive(Debug, Clone)]
pub(crate) struct TextonKernel {
    pub(crate) cell_size: f64,
    params: TextonParams,
    /// The period of a periodic model: positions reduced modulo it.
    period: Option<Period>,
}

impl GpuKind for TextonNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "texton",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["texton_main"],
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

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: TileDisplacement<'_>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        let params = TextonParams {
            width: tile.width as u32,
            height: tile.height as u32,
            ..self.params
        };
        Ok(TileTables::new(
            &params,
            CellAxes::new(self.cell_size, tile, self.period)
                .tables(["texton columns", "texton rows"]),
        ))
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
}
