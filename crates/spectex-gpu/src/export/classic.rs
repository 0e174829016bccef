//! The classic noise's export (`shaders/export/classic.wgsl`): the compute shader's uniform
//! and octave table; per octave three lattices (the cell and, for simplex noise, the two
//! parts of the skew).

use spectex_model::ClassicNoise;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::classic::pack;
use crate::kernel::Table;

impl ExportKind for ClassicNoise {
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, octaves) = pack(self, z);
        // Octave o: lattices 3o (c_o), 3o + 1 (c_o/(1 + F)) and 3o + 2 (c_o/F) of
        // export/classic.wgsl; the skew lattices only matter to simplex noise (F > 0).
        let lattices = kernel
            .sides
            .iter()
            .flat_map(|&c| {
                let f = kernel.skew;
                if f > 0.0 {
                    [c, c / (1.0 + f), c / f]
                } else {
                    [c, c, c]
                }
            })
            .collect();
        ExportParts::of(
            &kernel,
            &[Table::new("classic octaves", &octaves)],
            lattices,
            "classic",
        )
    }
}
