//! The wavelet noise's export (`shaders/export/wavelet.wgsl`): the compute shader's uniform
//! and band tables; band b's sample grid is the export's lattice b.

use spectex_model::WaveletNoise;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::wavelet::host;

impl ExportKind for WaveletNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/wavelet.wgsl");

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, tables) = host(self, z, None);
        // Band b's sample grid is the export's lattice b (export/wavelet.wgsl), its tile
        // offsets along x and y the constant `wavelet_export_offsets`.
        let lattices = kernel.bands.iter().map(|b| b.side).collect();
        let offsets: Vec<String> = kernel
            .bands
            .iter()
            .flat_map(|b| [b.offset[0], b.offset[1]])
            .map(|o| format!("{o}u"))
            .collect();
        let constants = format!(
            "/// Per band, the tile offsets o_b along x and y (spectex_model::wavelet::Band).\n\
             const wavelet_export_offsets: array<u32, {n}> = array<u32, {n}>({});\n",
            offsets.join(", "),
            n = offsets.len()
        );
        Ok(ExportParts::of(&kernel, &tables, lattices, "wavelet")?.with_constants(constants))
    }
}
