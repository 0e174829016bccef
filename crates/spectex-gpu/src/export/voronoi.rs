//! A Voronoi diagram's export (`shaders/export/voronoi.wgsl`): the compute shader's uniform
//! and the constants with which the glue draws each searched cell's site in the shader (the
//! compute path's host draws a box of sites per tile).
//!
//! Lloyd relaxation is refused ([`GpuError::Unsupported`] naming it): the host relaxes each
//! block in f64 (exact centroids of clipped Voronoi cells, Jacobi sweeps over the block and
//! its ring), which a shader could only approximate in f32 — a relaxed seed's error there has
//! no derived bound, and a seed on the other side of a bisector changes a cell's ID and
//! colour. So is the image colour output: its texel is `⌊(i + o)·C⌋ mod W` in f64, which f32
//! cannot locate far from the origin. The default (jittered seeds, the cell ID) and the ID,
//! distance, border and palette outputs export.

use spectex_model::ModelKind;
use spectex_model::voronoi::{VoronoiNoise, VoronoiOutput};

use super::{ExportKind, ExportNode, ExportParts, float};
use crate::GpuError;

impl ExportKind for VoronoiNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/voronoi.wgsl");

    /// A 3D diagram exports its plane `z`.
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let refuse = |feature: &str| GpuError::Unsupported {
            kind: VoronoiNoise::NAME,
            feature: format!("WGSL export of {feature}"),
        };
        if self.lloyd_iterations > 0 {
            return Err(refuse(
                "Lloyd-relaxed seeds (lloyd_iterations > 0: the host relaxes them in f64)",
            ));
        }
        let palette = match &self.output {
            VoronoiOutput::Image { .. } => {
                return Err(refuse(
                    "the image colour output (its texel under a seed is located in f64)",
                ));
            }
            VoronoiOutput::Palette { colours } => colours.clone(),
            _ => vec![[0.0; 3]],
        };
        let kernel = crate::voronoi::pack(self, None).at_z(z);
        let colours = palette
            .iter()
            .map(|c| {
                format!(
                    "vec3<f32>({}, {}, {})",
                    float(c[0]),
                    float(c[1]),
                    float(c[2])
                )
            })
            .collect::<Vec<_>>()
            .join(", ");
        let n = palette.len();
        let constants = format!(
            "const voronoi_export_seed: u32 = {}u;\n\
             const voronoi_export_jitter: f32 = {};\n\
             const voronoi_export_colours: u32 = {n}u;\n\
             var<private> voronoi_export_palette: array<vec3<f32>, {n}> = \
             array<vec3<f32>, {n}>({colours});\n\
             /// The output binding `write_value` of voronoi.wgsl writes to (unused here).\n\
             var<private> output: array<f32, 3>;\n",
            self.seed,
            float(self.jitter),
        );
        // The seed lattice is the export's lattice 0 (export/voronoi.wgsl).
        let mut node = ExportParts::of(&kernel, &[], vec![f64::from(self.cell_size)], "voronoi")?
            .with_constants(constants);
        if let ExportNode::Leaf(parts) = &mut node {
            let (value, result) = if self.output.channels() == 1 {
                ("f32", "v.x")
            } else {
                ("vec3<f32>", "v")
            };
            parts.substitutions = vec![
                ("VORONOI_VALUE", value.to_owned()),
                ("VORONOI_RESULT", result.to_owned()),
            ];
        }
        Ok(node)
    }
}
