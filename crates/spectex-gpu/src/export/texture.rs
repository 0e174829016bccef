//! The texture by example's export (`shaders/export/texture.wgsl`): its own shader's parts
//! and the LRP models (strata and turbulence) whose values it reads; the placement cell is
//! the export's lattice 0.

use spectex_model::texture::PLACEMENT_LAYER;
use spectex_model::{LrpNoise, Model, TextureModel};

use super::{ExportKind, ExportNode, ExportNodeOf, ExportParts, TextureExport};
use crate::GpuError;
use crate::kernel::Table;
use crate::texture::{PlacementAxis, TextureParams, pack_structures};

impl ExportKind for TextureModel {
    const GLUE: &'static str = include_str!("../../../../shaders/export/texture.wgsl");

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let lrp = |seed, mean, strata| Model::Lrp(LrpNoise { seed, mean, strata });
        let strata = self
            .channels
            .iter()
            .map(|ch| {
                if ch.strata.is_empty() {
                    Ok(Err(ch.mean))
                } else {
                    lrp(ch.seed, ch.mean, ch.strata.clone())
                        .export_node(z)
                        .map(Ok)
                }
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        let turbulence = match &self.turbulence {
            Some(t) => {
                let mut axes: [Vec<ExportNode>; 2] = [Vec::new(), Vec::new()];
                for (axis, nodes) in axes.iter_mut().enumerate() {
                    for (s, stratum) in t.strata.iter().enumerate() {
                        nodes
                            .push(lrp(t.seed(axis, s), 0.0, vec![stratum.clone()]).export_node(z)?);
                    }
                }
                Some((t.sigma, t.centre, axes))
            }
            None => None,
        };
        let structures = pack_structures(self);
        let nc = self.channels.len();
        let mut params = TextureParams {
            width: 1,
            height: 1,
            channels: nc as u32,
            period: self.period,
            seed: self.seed,
            random_placement: u32::from(self.random_placement),
            colour: u32::from(self.colour.is_some()),
            placement_layer: PLACEMENT_LAYER,
            ..bytemuck::Zeroable::zeroed()
        };
        if let Some(c) = &self.colour {
            for i in 0..3 {
                params.colour_mean[i] = c.mean[i];
                params.basis[i][..3].copy_from_slice(&c.basis[i]);
            }
        }
        // The uniform, the resident tables, then the per-tile tables of a one-pixel tile
        // (unused by the glue, which computes their values itself).
        let bindings = vec![
            bytemuck::bytes_of(&params).to_vec(),
            Table::new("texture structures", &structures.channels).bytes,
            Table::new("texture blocks", &structures.blocks).bytes,
            Table::new("texture cosines", &structures.cosines).bytes,
            Table::new("texture block means", &structures.means).bytes,
            Table::new("texture values", &vec![0.0f32; nc + 2]).bytes,
            Table::new(
                "texture columns",
                &[PlacementAxis {
                    cell: 0,
                    offset: 0.0,
                }],
            )
            .bytes,
            Table::new(
                "texture rows",
                &[PlacementAxis {
                    cell: 0,
                    offset: 0.0,
                }],
            )
            .bytes,
        ];
        // The placement cell P = T/2 is the export's lattice 0 (export/texture.wgsl).
        let leaf = ExportParts::new(
            "texture",
            "texture",
            nc,
            bindings,
            vec![self.placement_cell()],
        );
        Ok(ExportNode::Texture(Box::new(TextureExport {
            leaf,
            strata,
            turbulence,
        })))
    }
}
