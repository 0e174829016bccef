//! Matrix transformation on the device (`shaders/matrix.wgsl`): the host computes
//! `A = (M⁻¹)^k mod N` once and, per tile, each column's and row's cell on the pixel grid (the
//! CPU's split); the shader reduces the cell modulo `N` and reads the source at `A·q mod N`.
//!
//! The matrix transformation's export (the glue of `shaders/matrix.wgsl`): the compute shader's
//! uniform and texels; the glue takes the pixel cell from the position's integer part, so
//! the export needs no lattice.

use spectex_model::Period;
use spectex_model::matrix::{MatrixSource, MatrixTransform};

use crate::axis::{CellAxes, CellAxis};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/matrix.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/matrix.wgsl"));

wgsl_struct! {
    /// `MatrixParams` of `matrix.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct MatrixParams {
        width: u32,
        height: u32,
        size: u32,
        /// 0: rings, 1: image.
        image: u32,
        a00: u32,
        a01: u32,
        a10: u32,
        a11: u32,
        rings: u32,
        amplitude: f32,
        mean: f32,
        _pad0: u32,
    }
}

/// A matrix transformation on the device.
#[derive(Debug, Clone)]
pub(crate) struct MatrixKernel {
    params: MatrixParams,
    /// The period of a periodic transformation (a multiple of `N`): positions reduced modulo
    /// it, the texture itself unchanged.
    period: Option<Period>,
}

impl GpuKind for MatrixTransform {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "matrix",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["matrix_main"],
    });

    /// Periodic: the texture is periodic with its torus side `N`
    /// (`ModelKind::check_period`): only the positions are reduced, as the CPU's
    /// `PeriodicKernel` reduces them.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (kernel, texels) = pack(self, period)?;
        Shaded::boxed(context, kernel, &[Table::new("matrix texels", &texels)])
    }
}

/// The kernel of a matrix transformation, its positions reduced modulo `period` when given, and
/// its source's texels (one unused texel for the rings).
pub(crate) fn pack(
    model: &MatrixTransform,
    period: Option<Period>,
) -> Result<(MatrixKernel, Vec<f32>), GpuError> {
    let a = model
        .inverse_power()
        .ok_or_else(|| GpuError::Model(model.validate().err().unwrap_or_else(not_invertible)))?;
    let (image, rings, texels) = match &model.source {
        MatrixSource::Rings { rings } => (0, *rings, vec![0.0f32]),
        MatrixSource::Image { texels } => (1, 0, texels.clone()),
    };
    let kernel = MatrixKernel {
        params: MatrixParams {
            width: 0,
            height: 0,
            size: model.size,
            image,
            a00: a[0][0],
            a01: a[0][1],
            a10: a[1][0],
            a11: a[1][1],
            rings,
            amplitude: model.amplitude,
            mean: model.mean,
            _pad0: 0,
        },
        period,
    };
    Ok((kernel, texels))
}

fn not_invertible() -> spectex_model::ModelError {
    spectex_model::ModelError::OutOfRange {
        field: "matrix.matrix".into(),
        value: 0.0,
        range: "an invertible matrix modulo size",
    }
}

impl ShaderKernel for MatrixKernel {
    const SHADER: &'static str = "matrix";
    const ENTRY_POINT: &'static str = "matrix_main";

    const SHAPE: &'static [&'static str] = &["MATRIX_IMAGE"];

    /// The model's image (the shader's shape overrides).
    fn shape(&self) -> Vec<u32> {
        vec![self.params.image]
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
        let params = MatrixParams {
            width: width as u32,
            height: height as u32,
            ..self.params
        };
        Ok(TileTables::new(
            &params,
            CellAxes::new(1.0, tile, self.period).tables(["matrix columns", "matrix rows"]),
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for MatrixTransform {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, texels) = pack(self, None)?;
        ExportParts::of(
            &kernel,
            &[Table::new("matrix texels", &texels)],
            Vec::new(),
            "matrix",
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
        assert_matches_wgsl::<MatrixParams>("matrix", "MatrixParams");
    }
}
