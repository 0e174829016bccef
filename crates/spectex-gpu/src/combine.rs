//! Combinations on the device: a [`Combine`] has no shader of its own. Per tile it renders
//! every operand through its own kernel (displaced when the combination is) and applies
//! [`CombineOp::apply`](spectex_model::combine::CombineOp::apply) on the host in f32, the
//! CPU's expression, as a warp applies its displacement.
//!
//! A combination's export (the glue of `shaders/combine.wgsl`): like a warp, a composition — each
//! operand is exported as its own prefixed model, and the glue's `combine_sample_cell`
//! (written by the emitter, per operation and channel) evaluates them at the position and applies
//! `CombineOp::apply`'s expression in WGSL (the compute path applies it on the host in f32).

use spectex_model::{Combine, Model, ModelKind, Period};

use crate::export::{ExportKind, ExportNode, parts};
use crate::kernel::{GpuKernel, GpuKind};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuEvaluator, GpuWindow};

/// A combination's operand evaluators.
#[derive(Debug)]
pub(crate) struct CombineKernel {
    model: Combine,
    /// The whole model, for [`spectex_model::warp::check_window`].
    whole: Model,
    operands: Vec<GpuEvaluator>,
    /// The period of a periodic combination: every operand is periodic (each reduces its own
    /// positions), so its window is never out of range.
    period: Option<Period>,
}

impl GpuKind for Combine {
    /// No shader of its own: its kernel runs its operands' kernels.
    const SHADER: Option<ShaderFile> = None;

    /// Periodic: every operand periodic with `period` (the CPU's periodic combination).
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let operands = self
            .operands
            .iter()
            .map(|m| GpuEvaluator::prepared_with_period(context, m, z, period))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Box::new(CombineKernel {
            model: self.clone(),
            whole: Model::Combine(self.clone()),
            operands,
            period,
        }))
    }
}

impl GpuKernel for CombineKernel {
    fn output_channels(&self) -> usize {
        self.model.output_channels()
    }

    /// Every operand renders the same tile: the smallest of theirs.
    fn tile_size(&self, window: &GpuWindow, cap: [usize; 2]) -> Result<[usize; 2], GpuError> {
        let mut size = [window.width.min(cap[0]), window.height.min(cap[1])];
        for e in &self.operands {
            let [w, h] = e.tile_size(window)?;
            size = [size[0].min(w), size[1].min(h)];
        }
        Ok(size)
    }

    /// Quarter-megapixel tiles: the host composes every tile, so a render spreads them over
    /// the cores.
    fn tile_pixels(&self) -> Option<usize> {
        Some(1 << 18)
    }

    /// A periodic combination's positions are reduced into the period.
    fn check_window(&self, window: &GpuWindow) -> Result<(), GpuError> {
        if self.period.is_some() {
            return Ok(());
        }
        Ok(spectex_model::warp::check_window(&self.whole, window)?)
    }

    fn render_tile(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError> {
        let values = self
            .operands
            .iter()
            .map(|e| e.render_tile_displaced(tile, displacement))
            .collect::<Result<Vec<_>, _>>()?;
        let widths: Vec<usize> = self
            .operands
            .iter()
            .map(GpuEvaluator::output_channels)
            .collect();
        let channels = self.output_channels();
        let pixels = tile.width * tile.height;
        let mut out = vec![0.0f32; pixels * channels];
        let mut pixel: Vec<&[f32]> = Vec::with_capacity(values.len());
        for (p, o) in out.chunks_exact_mut(channels).enumerate() {
            pixel.clear();
            pixel.extend(
                values
                    .iter()
                    .zip(&widths)
                    .map(|(v, &w)| &v[p * w..p * w + w]),
            );
            for (c, value) in o.iter_mut().enumerate() {
                *value = self.model.op.apply(&pixel, c);
            }
        }
        Ok(out)
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for Combine {
    const GLUE: &'static str = kernel_and_glue(include_str!("../shaders/combine.wgsl")).1;

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        Ok(ExportNode::Combine {
            op: self.op.clone(),
            operands: self
                .operands
                .iter()
                .map(|m| parts(m, z))
                .collect::<Result<_, _>>()?,
            channels: self.output_channels(),
        })
    }
}
