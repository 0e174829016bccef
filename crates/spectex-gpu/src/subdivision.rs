//! Stochastic subdivision on the device (`shaders/subdivision.wgsl`): the host computes the
//! level scales `σ_ℓ/√21845` once (f64, rounded to f32) and, per tile, each column's and row's
//! coarse cell and f32 offset (the CPU's split); the shader computes every level's block per
//! pixel in f32. The WGSL export locates the coarse cell itself (the glue of `subdivision.wgsl`).
//!
//! The stochastic subdivision's export (the glue of `shaders/subdivision.wgsl`): the compute
//! shader's uniform and scales; the coarse lattice is the export's only lattice.

use spectex_model::subdivision::{Stencil, StochasticSubdivision};
use spectex_model::{ModelKind, Period};

use crate::axis::{CellAxes, CellAxis};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/subdivision.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/subdivision.wgsl"));

wgsl_struct! {
    /// `SubdivisionParams` of `subdivision.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct SubdivisionParams {
        width: u32,
        height: u32,
        seed: u32,
        levels: u32,
        /// 0: midpoint, 1: cubic.
        cubic: u32,
        mean: f32,
        inv_cell: f32,
        _pad0: u32,
    }
}

/// A stochastic subdivision on the device.
#[derive(Debug, Clone)]
pub(crate) struct SubdivisionKernel {
    params: SubdivisionParams,
    pub(crate) side: f64,
}

/// The kernel of a validated model and its level scales (f32 of the f64 values): what the
/// device evaluator uploads and what the WGSL export writes.
pub(crate) fn host(model: &StochasticSubdivision) -> (SubdivisionKernel, Vec<f32>) {
    let side = f64::from(model.cell_size);
    let scales: Vec<f32> = model.level_scales().iter().map(|&s| s as f32).collect();
    let kernel = SubdivisionKernel {
        params: SubdivisionParams {
            width: 0,
            height: 0,
            seed: model.seed,
            levels: model.levels,
            cubic: u32::from(model.stencil == Stencil::Cubic),
            mean: model.mean,
            inv_cell: (1.0 / side) as f32,
            _pad0: 0,
        },
        side,
    };
    (kernel, scales)
}

impl GpuKind for StochasticSubdivision {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "subdivision",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["subdivision_main"],
    });

    /// No periodic form (the model layer refuses every period first).
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        if let Some(period) = period {
            return Err(GpuError::Unsupported {
                kind: Self::NAME,
                feature: format!(
                    "a period ({period}): the device path has no periodic form for it"
                ),
            });
        }
        let (kernel, scales) = host(self);
        Shaded::boxed(
            context,
            kernel,
            &[Table::new("subdivision scales", &scales)],
        )
    }
}

impl ShaderKernel for SubdivisionKernel {
    const SHADER: &'static str = "subdivision";
    const ENTRY_POINT: &'static str = "subdivision_main";

    const SHAPE: &'static [&'static str] = &["SUBDIVISION_CUBIC"];

    /// The model's cubic (the shader's shape overrides).
    fn shape(&self) -> Vec<u32> {
        vec![self.params.cubic]
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<CellAxis>() as u64
    }

    /// The output or the displacement (2 values).
    fn pixel_bytes(&self) -> u64 {
        8
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: TileDisplacement<'_>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        let (width, height) = (tile.width, tile.height);
        let params = SubdivisionParams {
            width: width as u32,
            height: height as u32,
            ..self.params
        };
        Ok(TileTables::new(
            &params,
            CellAxes::new(self.side, tile, None)
                .tables(["subdivision columns", "subdivision rows"]),
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for StochasticSubdivision {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, scales) = host(self);
        // The coarse lattice is the export's lattice 0 (the glue of subdivision.wgsl).
        let lattices = vec![kernel.side];
        ExportParts::of(
            &kernel,
            &[Table::new("subdivision scales", &scales)],
            lattices,
            "subdivision",
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
        assert_matches_wgsl::<SubdivisionParams>("subdivision", "SubdivisionParams");
    }
}
