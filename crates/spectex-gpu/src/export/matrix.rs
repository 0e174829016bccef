//! The matrix transformation's export (`shaders/export/matrix.wgsl`): the compute shader's
//! uniform and texels; the glue takes the pixel cell from the position's integer part, so
//! the export needs no lattice.

use spectex_model::matrix::MatrixTransform;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::kernel::Table;

impl ExportKind for MatrixTransform {
    const GLUE: &'static str = include_str!("../../../../shaders/export/matrix.wgsl");

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, texels) = crate::matrix::pack(self, None)?;
        ExportParts::of(
            &kernel,
            &[Table::new("matrix texels", &texels)],
            Vec::new(),
            "matrix",
        )
    }
}
