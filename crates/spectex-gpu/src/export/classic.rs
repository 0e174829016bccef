//! The classic noise's export (`shaders/export/classic.wgsl`): the compute shader's uniform
//! and octave table; per octave three lattices (the cell and, for simplex noise, the two
//! parts of the skew).

use spectex_model::ClassicNoise;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::classic::pack;
use crate::kernel::Table;

impl ExportKind for ClassicNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/classic.wgsl");

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, octaves) = pack(self, z);
        // Octave o: lattices 3o (c_o), 3o + 1 (c_o/(1 + F)) and 3o + 2 (c_o/F) of
        // export/classic.wgsl; the skew lattices only matter to simplex noise (F > 0).
        let lattices: Vec<f64> = kernel
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
        let halving = u32::from(halving(&lattices));
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("classic octaves", &octaves)],
            lattices,
            "classic",
        )?
        .with_constants(format!(
            "/// 1: every octave's lattices are the previous octave's halved exactly (split once).\n\
             const classic_export_halving: u32 = {halving}u;\n"
        )))
    }
}

/// Whether each octave's three lattices are exactly half the previous octave's, in f64 and as
/// the f32 sides the glue reads (lacunarity 2): then `export_halve` derives octave o + 1's
/// splits from octave o's, exactly where the sides are f32.
fn halving(lattices: &[f64]) -> bool {
    lattices
        .chunks_exact(3)
        .zip(lattices.chunks_exact(3).skip(1))
        .all(|(coarse, fine)| {
            coarse.iter().zip(fine).all(|(&c, &f)| {
                c == 2.0 * f && f > 0.0 && (c as f32) == 2.0 * (f as f32) && (f as f32) > 0.0
            })
        })
}

#[cfg(test)]
mod tests {
    use super::halving;

    #[test]
    fn halving_needs_every_lattice_halved_exactly() {
        assert!(halving(&[
            32.0, 20.0, 80.0, 16.0, 10.0, 40.0, 8.0, 5.0, 20.0
        ]));
        assert!(halving(&[32.0, 32.0, 32.0]));
        // Lacunarity 1.9, or one skew lattice off by an ulp.
        assert!(!halving(&[32.0, 32.0, 32.0, 16.842, 16.842, 16.842]));
        let off = 10.0f64.next_up();
        assert!(!halving(&[32.0, 20.0, 80.0, 16.0, off, 40.0]));
    }
}
