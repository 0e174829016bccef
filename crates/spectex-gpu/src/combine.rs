//! Combinations on the device: a [`Combine`] has no model shader of its own. An undisplaced
//! tile records every operand's dispatch into a plane of its own and then a combination pass
//! written for the model ([`pass_wgsl`]: [`CombineOp::apply`](spectex_model::combine::CombineOp::apply),
//! the same operations in the same order, in `shaders/exact.wgsl`'s integer IEEE arithmetic) in
//! the tile's one submission. A shader's own float operations would not do: a compiler may
//! fuse a multiply and an add (a mix, a ramp, a smoothstep, a table lookup, a sine) into one
//! rounding, WGSL divides within 2.5 ulp and may flush subnormals; the exact arithmetic rounds
//! as the CPU does, so the cross-check holds the GPU's combination to `CombineOp::apply` of the
//! GPU's operands bit for bit. A displaced combination (a warp's base) renders its operands
//! and applies the operation on the host in f32.
//!
//! A combination's export (the glue of `shaders/combine.wgsl`): like a warp, a composition — each
//! operand is exported as its own prefixed model, and the glue's `combine_sample_cell`
//! (written by the emitter, per operation and channel) evaluates them at the position and applies
//! `CombineOp::apply`'s expression in the shader's own arithmetic, as cheap as WGSL makes it.

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

/// Workgroup size of the combination pass.
const PASS_WORKGROUP: u32 = 64;

/// The combination pass of `op` over operands of `widths` channels into `channels`:
/// `common.wgsl` and `exact.wgsl` (whose `arith_*` the glue computes in), the glue's functions
/// and constants (`shaders/combine.wgsl`), and an entry point that reads operand `k`'s value
/// at a pixel from its plane of `operands` and writes the operation's channels.
pub(crate) fn pass_wgsl(
    op: &spectex_model::combine::CombineOp,
    widths: &[usize],
    channels: usize,
) -> Option<String> {
    let mut code = wgsl_source("exact")?;
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
    /// The combination pass, built for this model ([`pass_wgsl`]).
    pass: CachedPipeline,
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
        let source = pass_wgsl(&self.op, &widths, self.output_channels()).ok_or_else(|| {
            GpuError::Validation("exact.wgsl missing from the registry".to_owned())
        })?;
        let pass = build_pipeline(&gpu, "spectex combine", source, ("combine_main", &[]), 1)?;
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

    /// Megapixel tiles: a tile in flight holds every operand's plane twice, its own buffer and
    /// the combination's input, beside its output.
    fn tile_pixels(&self) -> Option<usize> {
        crate::kernel::composite_tile_pixels(true)
    }

    /// Every operand's host part, for [`encode_chain`](Self::encode_chain).
    fn prepare_tile(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
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
        let pipeline = &self.pass;
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
            Some(PreparedTile::Values(_) | PreparedTile::OnDevice(_)) | None => (None, timer),
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
    use spectex_model::random::Prng;

    use crate::layout::check::assert_source_matches_wgsl;
    use crate::pipeline::{Gpu, build_pipeline, encode_pass, flat_grid, read_buffer};

    /// The device of the tests below, or `None` (skipped with a message) without one.
    fn device(test: &str) -> Option<Gpu> {
        crate::layout::check::context_or_skip(test).map(|c| Gpu::new(&c))
    }

    /// Runs `combine_main` of `source` (the combination pass's bindings) over `count` pixels
    /// whose operand planes are `planes`, and returns `outputs` values.
    fn run_pass(
        gpu: &Gpu,
        source: String,
        count: usize,
        planes: &[f32],
        outputs: usize,
    ) -> Vec<f32> {
        use wgpu::BufferUsages as U;
        let pipeline =
            build_pipeline(gpu, "combine test", source, ("combine_main", &[]), 1).unwrap();
        let input = gpu.buffer("operands", bytemuck::cast_slice(planes), U::STORAGE);
        let bytes = 4 * outputs as u64;
        let output = gpu.empty("combined", bytes, U::STORAGE | U::COPY_SRC);
        let readback = gpu.empty("readback", bytes, U::MAP_READ | U::COPY_DST);
        let (per_row, grid) = flat_grid(gpu, count as u32, super::PASS_WORKGROUP);
        let params = super::CombinePass {
            count: count as u32,
            per_row,
            ..bytemuck::Zeroable::zeroed()
        };
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        let bindings = vec![input.as_entire_binding(), output.as_entire_binding()];
        encode_pass(
            gpu,
            &mut encoder,
            ("combine test", &pipeline),
            &params,
            bindings,
            grid,
            None,
        )
        .unwrap();
        encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
        let raw = read_buffer(&gpu.device, &readback, &gpu.lost, None).unwrap();
        bytemuck::cast_slice(&raw).to_vec()
    }

    /// Bit-for-bit equality, any NaN for a NaN.
    fn same(got: f32, want: f32) -> bool {
        got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan())
    }

    /// `exact.wgsl`'s `a + b`, `a − b`, `a · b` and `a / b` are the CPU's f32 operations bit for
    /// bit: random bit patterns (every class: zeros, subnormals, normals, infinities, NaNs),
    /// near-equal pairs (cancellation), products and quotients that overflow or fall into and
    /// below the subnormals, and the halfway cases of each rounding. Skips without a GPU.
    pub fn exact_arithmetic_rounds_as_the_cpu() {
        let Some(gpu) = device("exact_arithmetic_rounds_as_the_cpu") else {
            return;
        };
        let mut prng = Prng::new(0x05ee_df32);
        let mut pairs: Vec<(f32, f32)> = Vec::new();
        let specials = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            0.5,
            3.0,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x007f_ffff),
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            12_582_912.0,
            1.0 + f32::EPSILON,
            1.0 - f32::EPSILON / 2.0,
        ];
        for &a in &specials {
            for &b in &specials {
                pairs.push((a, b));
            }
        }
        for _ in 0..60_000 {
            // Any bits.
            let a = f32::from_bits(prng.next_u32());
            let b = f32::from_bits(prng.next_u32());
            pairs.push((a, b));
            // Exponents within a few of each other and of the ends of the range.
            let e = |prng: &mut Prng, lo: u32, span: u32| {
                let exp = lo + prng.next_u32() % span;
                f32::from_bits((prng.next_u32() & 0x807f_ffff) | (exp.min(254) << 23))
            };
            let x = e(&mut prng, 100, 50);
            pairs.push((x, e(&mut prng, 100, 50)));
            // Near-equal: a few ulps apart, either sign.
            let ulps = prng.next_u32() % 64;
            let y =
                f32::from_bits(x.to_bits().wrapping_add(ulps) ^ (prng.next_u32() & 0x8000_0000));
            pairs.push((x, y));
            // Tiny and huge: subnormal and overflowing results.
            pairs.push((e(&mut prng, 0, 40), e(&mut prng, 90, 40)));
            pairs.push((e(&mut prng, 200, 55), e(&mut prng, 100, 50)));
            pairs.push((e(&mut prng, 0, 30), e(&mut prng, 0, 30)));
        }
        let count = pairs.len();
        let mut planes = Vec::with_capacity(2 * count);
        planes.extend(pairs.iter().map(|p| p.0));
        planes.extend(pairs.iter().map(|p| p.1));
        let source = format!(
            "{}\n{}",
            crate::wgsl_source("exact").unwrap(),
            "struct CombinePass { count: u32, per_row: u32, _pad0: u32, _pad1: u32, }
@group(0) @binding(0) var<uniform> combine_pass: CombinePass;
@group(0) @binding(1) var<storage, read> operands: array<f32>;
@group(0) @binding(2) var<storage, read_write> combined: array<f32>;
@compute @workgroup_size(64, 1, 1)
fn combine_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = gid.y * combine_pass.per_row + gid.x;
    let n = combine_pass.count;
    if (p >= n) {
        return;
    }
    let a = operands[p];
    let b = operands[n + p];
    combined[4u * p] = exact_add(a, b);
    combined[4u * p + 1u] = exact_sub(a, b);
    combined[4u * p + 2u] = exact_mul(a, b);
    combined[4u * p + 3u] = exact_div(a, b);
}
"
        );
        let got = run_pass(&gpu, source, count, &planes, 4 * count);
        let mut wrong = Vec::new();
        for (i, &(a, b)) in pairs.iter().enumerate() {
            for (k, (name, want)) in [("+", a + b), ("-", a - b), ("*", a * b), ("/", a / b)]
                .into_iter()
                .enumerate()
            {
                if !same(got[4 * i + k], want) {
                    wrong.push(format!(
                        "{a:e} {name} {b:e} ({:08x} {name} {:08x}): {:08x}, the CPU {:08x}",
                        a.to_bits(),
                        b.to_bits(),
                        got[4 * i + k].to_bits(),
                        want.to_bits()
                    ));
                }
            }
        }
        assert!(
            wrong.is_empty(),
            "{} of {} differ, first: {:#?}",
            wrong.len(),
            4 * count,
            &wrong[..wrong.len().min(8)]
        );
    }

    /// The combination pass of every operation computes `CombineOp::apply` bit for bit on
    /// operand values across and beyond each operation's range: its edges, knots and stops,
    /// their neighbours, and random values. Skips without a GPU.
    pub fn combination_passes_are_apply_bit_for_bit() {
        let Some(gpu) = device("combination_passes_are_apply_bit_for_bit") else {
            return;
        };
        let mut prng = Prng::new(0xc0_4b1e);
        for (op, widths, channels) in cases() {
            let mut anchors: Vec<f32> = vec![0.0, -0.0, 1.0, -1.0, 0.25, 0.75, 0.5, -0.8, 0.4];
            match &op {
                CombineOp::Smoothstep { edges } => anchors.extend(edges),
                CombineOp::Histogram { domain, .. } => anchors.extend(domain),
                CombineOp::Ramp { stops } => anchors.extend(stops.iter().map(|s| s.at)),
                _ => {}
            }
            let mut values: Vec<f32> = Vec::new();
            for &v in &anchors {
                values.push(v);
                values.push(f32::from_bits(v.to_bits().wrapping_add(1)));
                values.push(f32::from_bits(v.to_bits().wrapping_sub(1)));
            }
            while values.len() < 4096 {
                values.push(4.0 * prng.next_f32() - 2.0);
            }
            let count = values.len();
            let planes_per_pixel: usize = widths.iter().sum();
            // Operand planes of the pass: each channel a rotation of the values.
            let mut planes = vec![0.0f32; planes_per_pixel * count];
            let mut at = 0;
            for (k, &w) in widths.iter().enumerate() {
                for p in 0..count {
                    for c in 0..w {
                        planes[at + p * w + c] = values[(p + 17 * k + 5 * c) % count];
                    }
                }
                at += w * count;
            }
            let source = super::pass_wgsl(&op, &widths, channels).unwrap();
            let got = run_pass(&gpu, source, count, &planes, channels * count);
            let mut at;
            for p in 0..count {
                at = 0;
                let pixel: Vec<&[f32]> = widths
                    .iter()
                    .map(|&w| {
                        let v = &planes[at + p * w..at + p * w + w];
                        at += w * count;
                        v
                    })
                    .collect();
                for c in 0..channels {
                    let want = op.apply(&pixel, c);
                    let g = got[p * channels + c];
                    assert!(
                        same(g, want),
                        "{op:?} at {pixel:?}, channel {c}: {g:e}, the CPU {want:e}"
                    );
                }
            }
        }
    }

    /// One of each operation: grey and colour operands, a colour ramp.
    fn cases() -> Vec<(CombineOp, Vec<usize>, usize)> {
        let stop = |at, c| RampStop {
            at,
            colour: [c, 0.5, 1.0 - c],
        };
        vec![
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
            (CombineOp::Smoothstep { edges: [0.3, 0.3] }, vec![1], 1),
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
            (CombineOp::SinFold { gain: -1234.5 }, vec![1], 1),
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
                    stops: vec![stop(0.0, 0.0), stop(0.5, 0.7), stop(0.9, 0.2)],
                },
                vec![1],
                3,
            ),
        ]
    }

    /// The combination pass of every operation (grey and colour operands, a colour ramp)
    /// parses and validates with naga, and its uniform has the Rust record's fields and size.
    pub fn passes_of_every_operation_validate() {
        for (op, widths, channels) in cases() {
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
