//! The stochastic subdivision's export (`shaders/export/subdivision.wgsl`): the compute
//! shader's uniform and scales; the coarse lattice is the export's only lattice.

use spectex_model::subdivision::StochasticSubdivision;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::kernel::Table;
use crate::subdivision::host;

impl ExportKind for StochasticSubdivision {
    const GLUE: &'static str = include_str!("../../../../shaders/export/subdivision.wgsl");

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, scales) = host(self);
        // The coarse lattice is the export's lattice 0 (export/subdivision.wgsl).
        let lattices = vec![kernel.side];
        ExportParts::of(
            &kernel,
            &[Table::new("subdivision scales", &scales)],
            lattices,
            "subdivision",
        )
    }
}
