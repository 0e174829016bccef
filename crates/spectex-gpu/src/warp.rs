//! Domain warping on the device: a [`Warp`] has no model shader of its own. Per tile it renders
//! x and y, applies [`Warp::displacement`] in f32, and renders its base displaced by it through
//! the base's own shader (`common.wgsl`'s displacement convention, bind group 1 of every model
//! shader). Where the base's host part does not read the displacement, all of it is recorded in
//! the tile's one submission: x's and y's dispatches, `compose.wgsl`'s `warp_displace`, and the
//! base's dispatch reading the displacement from the device. Otherwise (a phasor, Voronoi or
//! texture base), and for a warp displaced itself, the host composes: x and y rendered (displaced
//! when the warp is), the displacement applied and added to the outer one, the base rendered.
//!
//! A warp's export: its three models, composed by the glue of `shaders/warp.wgsl` (the emitter
//! writes the composition, `Emitter::node`).

use spectex_model::{Model, Period, Warp};

use crate::cache::CachedPipeline;
use crate::export::{ExportKind, ExportNode, parts};
use crate::kernel::{GpuKernel, GpuKind, PreparedTile, TileTables, split_timer};
use crate::layout::wgsl_struct;
use crate::pipeline::{Gpu, compute_pipeline, encode_pass, flat_grid};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuEvaluator, GpuWindow, wgsl_source};

wgsl_struct! {
    /// `ComposeParams` of `compose.wgsl`.
    pub(crate) struct ComposeParams {
        count: u32,
        per_row: u32,
        strength: f32,
        max_warp: f32,
    }
}

/// Workgroup size of `compose.wgsl`'s entry points.
const COMPOSE_WORKGROUP: u32 = 64;

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
    gpu: Gpu,
    /// `compose.wgsl`'s `warp_displace`, where the base is displaced on the device.
    displace: Option<CachedPipeline>,
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
        let gpu = Gpu::new(context);
        let base = sub(&self.base)?;
        let displace = if base.displaced_on_device() {
            let key = ("compose", "warp_displace", Vec::new());
            Some(compute_pipeline(&gpu, key, 1, || wgsl_source("compose"))?)
        } else {
            None
        };
        Ok(Box::new(WarpKernel {
            model: self.clone(),
            whole: Model::Warp(self.clone()),
            base,
            x: sub(&self.x)?,
            y: sub(&self.y)?,
            period,
            gpu,
            displace,
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

    /// Quarter-megapixel tiles where the host composes every tile, so a render spreads them
    /// over the cores; megapixel ones where the device does (a tile in flight holds x, y and the
    /// displacement, 16 bytes a pixel, beside its output).
    fn tile_pixels(&self) -> Option<usize> {
        crate::kernel::composite_tile_pixels(self.displace.is_some())
    }

    /// On the device where the base is displaced there: x's and y's host parts and the
    /// base's tables (point-sampled, as [`render_tile`](Self::render_tile)); else the host's
    /// composition.
    fn prepare_tile(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
        if self.displace.is_none() {
            return self.render_tile(tile, None).map(PreparedTile::Values);
        }
        let base_tile = tile.filtered(spectex_model::Filter::Off);
        Ok(PreparedTile::Chain {
            operands: vec![self.x.prepare_pass(tile)?, self.y.prepare_pass(tile)?],
            base: Some(self.base.prepare_device_displaced(&base_tile)?),
        })
    }

    /// x and y into planes of their own, `warp_displace` into the displacement, then the
    /// base displaced by it into `output`: one submission, nothing read back.
    fn encode_chain(
        &self,
        tile: &GpuWindow,
        operands: Vec<PreparedTile>,
        base: Option<TileTables>,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let invalid = || GpuError::Validation("warp: a chain of another shape".to_owned());
        let (Some(pipeline), Some(base), Ok([x, y])) = (
            &self.displace,
            base,
            <[PreparedTile; 2]>::try_from(operands),
        ) else {
            return Err(invalid());
        };
        let gpu = &self.gpu;
        let n = tile.width * tile.height;
        use wgpu::BufferUsages as U;
        let plane = |label| gpu.empty(label, 4 * n.max(1) as u64, U::STORAGE | U::COPY_DST);
        let (vx, vy) = (plane("warp x"), plane("warp y"));
        let displacement = gpu.empty("warp displacement", 8 * n.max(1) as u64, U::STORAGE);
        // The start is written by x's dispatch where it has one, else by the composition.
        let (start, end) = split_timer(timer);
        let (x_timer, compose_timer) = if matches!(x, PreparedTile::Values(_)) {
            (None, start)
        } else {
            (start, None)
        };
        self.x.encode_pass(tile, x, encoder, &vx, x_timer)?;
        self.y.encode_pass(tile, y, encoder, &vy, None)?;
        let (per_row, grid) = flat_grid(gpu, n as u32, COMPOSE_WORKGROUP);
        let params = ComposeParams {
            count: n as u32,
            per_row,
            strength: self.model.strength,
            max_warp: spectex_model::MAX_WARP,
        };
        let bindings = vec![
            vx.as_entire_binding(),
            vy.as_entire_binding(),
            displacement.as_entire_binding(),
        ];
        let pass = ("spectex warp compose", pipeline);
        encode_pass(gpu, encoder, pass, &params, bindings, grid, compose_timer)?;
        let base_tile = tile.filtered(spectex_model::Filter::Off);
        self.base
            .encode_device_displaced(&base_tile, base, encoder, output, &displacement, end)
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

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod tests {
    use crate::layout::check::assert_matches_wgsl;

    pub fn compose_params_match_the_wgsl() {
        assert_matches_wgsl::<super::ComposeParams>("compose", "ComposeParams");
    }
}
