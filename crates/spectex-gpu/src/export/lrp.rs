//! The LRP noise's export (`shaders/export/lrp.wgsl`): the compute shader's uniform and
//! tables; stratum s's lattice is the export's lattice s.

use spectex_model::LrpNoise;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::lrp::host;

impl ExportKind for LrpNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/lrp.wgsl");

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, tables, _) = host(self, None);
        // Stratum s's lattice is the export's lattice s (export/lrp.wgsl).
        let lattices = kernel.deltas.clone();
        ExportParts::of(&kernel, &tables, lattices, "lrp")
    }
}
