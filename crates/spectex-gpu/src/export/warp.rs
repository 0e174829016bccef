//! A warp's export: its three models, composed by `shaders/export/warp.wgsl` (the emitter
//! writes the composition, `Emitter::node`).

use super::{ExportKind, ExportNode, parts};
use crate::GpuError;

impl ExportKind for spectex_model::Warp {
    const GLUE: &'static str = include_str!("../../../../shaders/export/warp.wgsl");

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        Ok(ExportNode::Warp {
            base: Box::new(parts(&self.base, z)?),
            x: Box::new(parts(&self.x, z)?),
            y: Box::new(parts(&self.y, z)?),
            strength: self.strength,
        })
    }
}
