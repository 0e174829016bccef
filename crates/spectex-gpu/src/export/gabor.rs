//! The Gabor noise's export (`shaders/export/gabor.wgsl`): the compute shader's uniform; the
//! kernel grid (side: the kernel radius) is the export's only lattice.

use spectex_model::GaborNoise;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::gabor::pack;

impl ExportKind for GaborNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/gabor.wgsl");

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let kernel = pack(self, None);
        // The kernel grid is the export's lattice 0 (export/gabor.wgsl).
        let lattices = vec![kernel.radius];
        ExportParts::of(&kernel, &[], lattices, "gabor")
    }
}
