//! Domain warping on the device: a [`Warp`] has no shader of its own. Per tile it renders x and y
//! (displaced themselves when the warp is), applies [`Warp::displacement`] on the host in f32,
//! and renders its base displaced by the sum through the base's own shader (`common.wgsl`'s
//! displacement convention, bind group 1 of every model shader).
//!
//! A warp's export: its three models, composed by the glue of `shaders/warp.wgsl` (the emitter
//! writes the composition, `Emitter::node`).

use spectex_model::{Model, Period, Warp};

use crate::export::{ExportKind, ExportNode, parts};
use crate::kernel::{GpuKernel, GpuKind};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuEvaluator, GpuWindow};

/// A warp's three sub-evaluators.
#[derive(Debug)]
pub(crate) struct WarpKernel {
    model: Warp,
    /// The whole model, for [`spectex_model::warp::check_window`].
    whole: Model,
    base: GpuEvaluator,
    x: GpuEvaluator,
    y: GpuEvaluator,
    /// The period of a periodic warp: its three models are periodic (each reduces its own
    /// positions), so its window is never out of range.
    period: Option<Period>,
}

impl GpuKind for Warp {
    /// No shader of its own: its kernel runs its operands' kernels.
    const SHADER: Option<ShaderFile> = None;

    /// Periodic: the CPU's periodic warp: base, x and y each periodic with `period` (then `d`
    /// is, and the base at positions one period apart is too).
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let sub = |m: &Model| GpuEvaluator::prepared_with_period(context, m, z, period);
        Ok(Box::new(WarpKernel {
            model: self.clone(),
            whole: Model::Warp(self.clone()),
            base: sub(&self.base)?,
            x: sub(&self.x)?,
            y: sub(&self.y)?,
            period,
        }))
    }
}

impl GpuKernel for WarpKernel {
    fn output_channels(&self) -> usize {
        self.base.output_channels()
    }

    /// Every sub-evaluator renders the same tile: the smallest of theirs.
    fn tile_size(&self, window: &GpuWindow, cap: [usize; 2]) -> Result<[usize; 2], GpuError> {
        let mut size = [window.width.min(cap[0]), window.height.min(cap[1])];
        for e in [&self.base, &self.x, &self.y] {
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

    /// A periodic warp's positions are reduced into the period (the CPU's `PeriodicKernel`
    /// checks nothing either).
    fn check_window(&self, window: &GpuWindow) -> Result<(), GpuError> {
        if self.period.is_some() {
            return Ok(());
        }
        Ok(spectex_model::warp::check_window(&self.whole, window)?)
    }

    /// x and y at the (displaced) positions, their clamped displacement added in f32 to the
    /// outer one, and the base displaced by the sum.
    fn render_tile(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<Vec<f32>, GpuError> {
        let vx = self.x.render_tile_displaced(tile, displacement)?;
        let vy = self.y.render_tile_displaced(tile, displacement)?;
        let mut total = Vec::with_capacity(2 * vx.len());
        for (k, (a, b)) in vx.iter().zip(&vy).enumerate() {
            let d = [self.model.displacement(*a), self.model.displacement(*b)];
            match displacement {
                Some(outer) => total.extend([outer[2 * k] + d[0], outer[2 * k + 1] + d[1]]),
                None => total.extend(d),
            }
        }
        // The base is point-sampled at the displaced positions, as the CPU's `eval_point` does:
        // a warp filters only its displacement fields (they are rendered on the window).
        let base_tile = tile.filtered(spectex_model::Filter::Off);
        self.base.render_tile_displaced(&base_tile, Some(&total))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for Warp {
    const GLUE: &'static str = kernel_and_glue(include_str!("../shaders/warp.wgsl")).1;

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        Ok(ExportNode::Warp {
            base: Box::new(parts(&self.base, z)?),
            x: Box::new(parts(&self.x, z)?),
            y: Box::new(parts(&self.y, z)?),
            strength: self.strength,
        })
    }
}
