//! Combinations on the device: a [`Combine`] has no model shader of its own. Where WGSL
//! computes its operation exactly as the CPU does ([`exact_in_wgsl`]: sums, products, minima,
//! maxima, folds), an undisplaced tile records every operand's dispatch into a plane of its own
//! and then a combination pass written for the model (the export's WGSL of
//! [`CombineOp::apply`](spectex_model::combine::CombineOp::apply), the same operations in the
//! same order) in the tile's one submission. Otherwise, and for a displaced combination (a
//! warp's base), it renders its operands and applies the operation on the host in f32, the
//! CPU's expression: the cross-check holds the GPU's combination to `CombineOp::apply` of the
//! GPU's operands bit for bit, and a shader compiler may fuse a multiply and an add (a mix, a
//! ramp, a smoothstep, a table lookup, a sine) into one rounding.
//!
//! A combination's export (the glue of `shaders/combine.wgsl`): like a warp, a composition — each
//! operand is exported as its own prefixed model, and the glue's `combine_sample_cell`
//! (written by the emitter, per operation and channel) evaluates them at the position and applies
//! `CombineOp::apply`'s expression in WGSL (the compute path applies it on the host in f32).

use spectex_model::{Combine, Model, ModelKind, Period};

use std::fmt::Write as _;

use crate::cache::CachedPipeline;
use crate::export::emitter::{combine_constants, combine_expression};
use crate::export::{ExportKind, ExportNode, parts};
use crate::kernel::{GpuKernel, GpuKind, PreparedTile, TileTables, split_timer};
use crate::layout::wgsl_struct;
use crate::pipeline::{Gpu, build_pipeline, encode_pass, flat_grid, leading};
use crate::shaders::{ShaderFile, kernel_and_glue, wgsl_source};
use crate::{GpuContext, GpuError, GpuEvaluator, GpuWindow};

wgsl_struct! {
    /// `CombinePass` of the combination pass ([`pass_wgsl`]).
    pub(crate) struct CombinePass {
        count: u32,
        per_row: u32,
        _pad0: u32,
        _pad1: u32,
    }
}

/// Whether the combination pass computes `op` bit for bit as `CombineOp::apply` does on any
/// device: only additions, multiplications, subtractions, absolute values, minima and maxima,
/// none of which a compiler may contract with another (for finite operands; WGSL leaves `min`
/// and `max` of NaN to the device).
pub(crate) fn exact_in_wgsl(op: &spectex_model::combine::CombineOp) -> bool {
    use spectex_model::combine::CombineOp as Op;
    matches!(
        op,
        Op::Add | Op::Multiply | Op::Min | Op::Max | Op::AbsFold { .. }
    )
}

/// Workgroup size of the combination pass.
const PASS_WORKGROUP: u32 = 64;

/// The combination pass of `op` over operands of `widths` channels into `channels`:
/// `common.wgsl`, the glue's functions and constants (`shaders/combine.wgsl`), and an entry
/// point that reads operand `k`'s value at a pixel from its plane of `operands` and writes the
/// operation's channels.
pub(crate) fn pass_wgsl(
    op: &spectex_model::combine::CombineOp,
    widths: &[usize],
    channels: usize,
) -> Option<String> {
    let mut code = wgsl_source("common")?;
    code.push_str(<Combine as ExportKind>::GLUE);
    code.push_str(&combine_constants(op));
    code.push_str(
        "\nstruct CombinePass {\n    count: u32,\n    per_row: u32,\n    _pad0: u32,\n    \
         _pad1: u32,\n}\n\n\
         @group(0) @binding(0) var<uniform> combine_pass: CombinePass;\n\
         /// Operand k's values, channels interleaved, one plane after another.\n\
         @group(0) @binding(1) var<storage, read> operands: array<f32>;\n\
         @group(0) @binding(2) var<storage, read_write> combined: array<f32>;\n\n\
         @compute @workgroup_size(64, 1, 1)\n\
         fn combine_main(@builtin(global_invocation_id) gid: vec3<u32>) {\n    \
         let p = gid.y * combine_pass.per_row + gid.x;\n    \
         let n = combine_pass.count;\n    \
         if (p >= n) {\n        return;\n    }\n",
    );
    let mut plane = 0;
    for (k, &w) in widths.iter().enumerate() {
        if w == 1 {
            let _ = writeln!(code, "    let v{k} = operands[{plane}u * n + p];");
        } else {
            let _ = writeln!(
                code,
                "    let v{k} = vec3<f32>(operands[{plane}u * n + 3u * p], \
                 operands[{plane}u * n + 3u * p + 1u], operands[{plane}u * n + 3u * p + 2u]);"
            );
        }
        plane += w;
    }
    for c in 0..channels {
        let _ = writeln!(
            code,
            "    combined[{channels}u * p + {c}u] = {};",
            combine_expression(op, widths, c)
        );
    }
    code.push_str("}\n");
    Some(code)
}

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
    gpu: Gpu,
    /// The combination pass, built for this model ([`pass_wgsl`]) where its operation is
    /// [`exact_in_wgsl`].
    pass: Option<CachedPipeline>,
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
        let widths: Vec<usize> = operands.iter().map(GpuEvaluator::output_channels).collect();
        let gpu = Gpu::new(context);
        let pass = if exact_in_wgsl(&self.op) {
            let source = pass_wgsl(&self.op, &widths, self.output_channels()).ok_or_else(|| {
                GpuError::Validation("common.wgsl missing from the registry".to_owned())
            })?;
            Some(build_pipeline(
                &gpu,
                "spectex combine",
                source,
                "combine_main",
                1,
            )?)
        } else {
            None
        };
        Ok(Box::new(CombineKernel {
            model: self.clone(),
            whole: Model::Combine(self.clone()),
            operands,
            period,
            gpu,
            pass,
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

    /// Megapixel tiles where the device combines (a tile in flight holds every operand's plane
    /// twice, its own buffer and the combination's input, beside its output); quarter-megapixel
    /// ones where the host does, so a render spreads them over the cores.
    fn tile_pixels(&self) -> Option<usize> {
        crate::kernel::composite_tile_pixels(self.pass.is_some())
    }

    /// Every operand's host part, for [`encode_chain`](Self::encode_chain), where the device
    /// combines; else the host's combination.
    fn prepare_tile(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
        if self.pass.is_none() {
            return self.render_tile(tile, None).map(PreparedTile::Values);
        }
        Ok(PreparedTile::Chain {
            operands: self
                .operands
                .iter()
                .map(|e| e.prepare_pass(tile))
                .collect::<Result<_, _>>()?,
            base: None,
        })
    }

    /// Each operand into its own buffer, copied into its plane of the combination's input,
    /// then the combination pass into `output`: one submission, nothing read back.
    fn encode_chain(
        &self,
        tile: &GpuWindow,
        operands: Vec<PreparedTile>,
        _base: Option<TileTables>,
        encoder: &mut wgpu::CommandEncoder,
        output: &wgpu::Buffer,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let Some(pipeline) = self.pass.as_ref() else {
            return Err(GpuError::Validation(
                "combine: a chain for an operation the host applies".to_owned(),
            ));
        };
        if operands.len() != self.operands.len() {
            return Err(GpuError::Validation(
                "combine: a chain of another shape".to_owned(),
            ));
        }
        let gpu = &self.gpu;
        use wgpu::BufferUsages as U;
        let n = tile.width * tile.height;
        let planes: usize = self
            .operands
            .iter()
            .map(GpuEvaluator::output_channels)
            .sum();
        let input = gpu.empty(
            "combine operands",
            4 * (planes * n).max(1) as u64,
            U::STORAGE | U::COPY_DST,
        );
        // The timer starts with the first operand's dispatch where it has one (else with the
        // combination) and ends with the combination.
        let (mut first_timer, pass_timer) = match operands.first() {
            Some(PreparedTile::Values(_)) | None => (None, timer),
            Some(_) => split_timer(timer),
        };
        let mut at = 0u64;
        for (e, prepared) in self.operands.iter().zip(operands) {
            let bytes = 4 * (e.output_channels() * n) as u64;
            let own = gpu.empty(
                "combine operand",
                bytes.max(4),
                U::STORAGE | U::COPY_SRC | U::COPY_DST,
            );
            e.encode_pass(tile, prepared, encoder, &own, first_timer.take())?;
            encoder.copy_buffer_to_buffer(&own, 0, &input, at, bytes);
            at += bytes;
        }
        let (per_row, grid) = flat_grid(gpu, n as u32, PASS_WORKGROUP);
        let params = CombinePass {
            count: n as u32,
            per_row,
            ..bytemuck::Zeroable::zeroed()
        };
        let values = 4 * (self.output_channels() * n).max(1) as u64;
        let bindings = vec![input.as_entire_binding(), leading(output, values)];
        let pass = ("spectex combine", pipeline);
        encode_pass(gpu, encoder, pass, &params, bindings, grid, pass_timer)
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

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use spectex_model::combine::{CombineOp, RampStop};

    use crate::layout::check::assert_source_matches_wgsl;

    /// The combination pass of every operation (grey and colour operands, a colour ramp)
    /// parses and validates with naga, and its uniform has the Rust record's fields and size.
    pub fn passes_of_every_operation_validate() {
        let stop = |at, c| RampStop {
            at,
            colour: [c, 0.5, 1.0 - c],
        };
        let cases: Vec<(CombineOp, Vec<usize>, usize)> = vec![
            (CombineOp::Add, vec![1, 1, 1], 1),
            (CombineOp::Multiply, vec![3, 3], 3),
            (CombineOp::Min, vec![1, 1], 1),
            (CombineOp::Max, vec![3, 3], 3),
            (CombineOp::Mix, vec![3, 3, 1], 3),
            (
                CombineOp::Smoothstep {
                    edges: [0.25, 0.75],
                },
                vec![1],
                1,
            ),
            (
                CombineOp::AbsFold {
                    offset: -0.8,
                    step: 0.4,
                    folds: 3,
                },
                vec![1],
                1,
            ),
            (CombineOp::SinFold { gain: 3.0 }, vec![3], 3),
            (
                CombineOp::Histogram {
                    domain: [-1.0, 1.0],
                    table: vec![0.0, 0.1, 0.5, 1.0],
                },
                vec![1],
                1,
            ),
            (
                CombineOp::Ramp {
                    stops: vec![stop(0.0, 0.0), stop(0.5, 0.7)],
                },
                vec![1],
                3,
            ),
        ];
        for (op, widths, channels) in cases {
            let source = super::pass_wgsl(&op, &widths, channels).unwrap();
            let name = format!("combine pass of {op:?}");
            assert_source_matches_wgsl::<super::CombinePass>(&name, &source, "CombinePass");
            assert!(
                source.contains(&format!("combined[{channels}u * p + {}u]", channels - 1)),
                "{op:?}: every channel written"
            );
        }
    }
}
