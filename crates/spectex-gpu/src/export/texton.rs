//! The texton noise's export (`shaders/export/texton.wgsl`): the compute shader's uniform
//! and model data; the texton grid is the export's only lattice.

use spectex_model::TextonNoise;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::kernel::Table;
use crate::texton::host;

impl ExportKind for TextonNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/texton.wgsl");

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, data) = host(self);
        // The texton grid is the export's lattice 0 (export/texton.wgsl).
        let lattices = vec![kernel.cell_size];
        ExportParts::of(
            &kernel,
            &[Table::new("texton model data", &data)],
            lattices,
            "texton",
        )
    }
}
