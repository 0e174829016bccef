//! Domain warping on the device: a [`Warp`] has no model shader of its own. Per tile it renders
//! x and y, applies [`Warp::displacement`] in f32, and renders its base displaced by it through
//! the base's own shader (`common.wgsl`'s displacement convention, bind group 1 of every model
//! shader). How depends on what the base's host part reads of the displacement
//! ([`DisplacementRead`]):
//! - nothing (LRP, classic noise, a texture, whose LRP passes read it on the device too …): all
//!   of it is recorded in the tile's one submission: x's and y's dispatches, `compose.wgsl`'s
//!   `warp_displace`, and the base's dispatch reading the displacement from the device;
//! - its range (a phasor's cell box, a Voronoi search): a worker submits x, y and
//!   `warp_displace_range`, reads back the displacement's range (16 bytes), builds the base's
//!   tables for it, and the tile's submission records the base displaced by the displacement
//!   left on the device;
//! - every pixel's (a phasor's varying fields, a composite base), and for a warp displaced
//!   itself: the host composes: x and y rendered (displaced when the warp is), the
//!   displacement applied and added to the outer one, the base rendered.
//!
//! A warp's export: its three models, composed by the glue of `shaders/warp.wgsl` (the emitter
//! writes the composition, `Emitter::node`).

use spectex_model::{Model, Period, Warp};

use crate::cache::CachedPipeline;
use crate::export::{ExportKind, ExportNode, parts};
use crate::kernel::{
    DisplacementRange, DisplacementRead, GpuKernel, GpuKind, PreparedTile, TileTables, split_timer,
};
use crate::layout::wgsl_struct;
use crate::pipeline::{
    ErrorScopes, Gpu, compute_pipeline, encode_pass, flat_grid, submit_and_read,
};
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
    /// `compose.wgsl`'s `warp_displace`, or `warp_displace_range` where the base reads the
    /// displacement's range: where the base is displaced on the device.
    displace: Option<CachedPipeline>,
    /// One timestamp pair for a ranged tile's first submission, made on a worker.
    queries: Option<wgpu::QuerySet>,
}

/// Bytes of the displacement's range as `warp_displace_range` writes it: four `u32` maxima.
const RANGE_BYTES: u64 = 16;

/// The value of an order-preserving `u32` of `compose.wgsl`'s `ordered`.
fn unordered(u: u32) -> f32 {
    if u & 0x8000_0000 != 0 {
        f32::from_bits(u & 0x7fff_ffff)
    } else {
        f32::from_bits(!u)
    }
}

/// The range `warp_displace_range` wrote: the maxima of `ordered(dx)`, `!ordered(dx)`,
/// `ordered(dy)` and `!ordered(dy)`.
fn decode_range(bytes: &[u8]) -> Result<DisplacementRange, GpuError> {
    let words: [u32; 4] = bytemuck::pod_read_unaligned::<[u32; 4]>(
        bytes
            .get(..RANGE_BYTES as usize)
            .ok_or_else(|| GpuError::Validation("warp: a short range read back".to_owned()))?,
    );
    Ok(DisplacementRange {
        x: [unordered(!words[1]), unordered(words[0])],
        y: [unordered(!words[3]), unordered(words[2])],
    })
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
        let read = base.displacement_read();
        let entry = match read {
            DisplacementRead::Nothing => Some("warp_displace"),
            DisplacementRead::Range => Some("warp_displace_range"),
            DisplacementRead::Pixels => None,
        };
        let displace = entry
            .map(|entry| {
                let key = ("compose", entry, Vec::new());
                compute_pipeline(&gpu, key, 1, || wgsl_source("compose"))
            })
            .transpose()?;
        let queries = if read == DisplacementRead::Range {
            gpu.query_set(1)
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
            queries,
        }))
    }
}

impl WarpKernel {
    /// Whether the base's tables read the displacement's range (read back per tile).
    fn ranged(&self) -> bool {
        self.base.displacement_read() == DisplacementRead::Range
    }

    /// Records x's and y's dispatches into planes of their own and the composition into
    /// `displacement` (and, given `range`, `warp_displace_range`'s maxima into it, zero
    /// before); `timer` writes its start at the first pass and its end at the composition.
    fn encode_displacement(
        &self,
        tile: &GpuWindow,
        [x, y]: [PreparedTile; 2],
        encoder: &mut wgpu::CommandEncoder,
        displacement: &wgpu::Buffer,
        range: Option<&wgpu::Buffer>,
        timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let Some(pipeline) = &self.displace else {
            return Err(GpuError::Validation(
                "warp: its base is not displaced on the device".to_owned(),
            ));
        };
        let gpu = &self.gpu;
        let n = tile.width * tile.height;
        use wgpu::BufferUsages as U;
        let plane = |label| gpu.empty(label, 4 * n.max(1) as u64, U::STORAGE | U::COPY_DST);
        let (vx, vy) = (plane("warp x"), plane("warp y"));
        // The start is written by x's dispatch where it has one, else by the composition;
        // the end (where `timer` has one) by the composition.
        let (x_timer, compose_timer) =
            if matches!(x, PreparedTile::Values(_) | PreparedTile::OnDevice(_)) {
                (None, timer)
            } else {
                split_timer(timer)
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
        let mut bindings = vec![
            vx.as_entire_binding(),
            vy.as_entire_binding(),
            displacement.as_entire_binding(),
        ];
        bindings.extend(range.map(wgpu::Buffer::as_entire_binding));
        let pass = ("spectex warp compose", pipeline);
        encode_pass(gpu, encoder, pass, &params, bindings, grid, compose_timer)
    }

    /// x, y and the displacement of `tile` rendered in a submission of this (worker) thread,
    /// timed into the context's clock where the device has timestamps: the displacement, left
    /// on the device, and its range, read back.
    fn displace_with_range(
        &self,
        tile: &GpuWindow,
        operands: Vec<PreparedTile>,
    ) -> Result<(wgpu::Buffer, DisplacementRange), GpuError> {
        let invalid = || GpuError::Validation("warp: x and y expected".to_owned());
        let [x, y] = <[PreparedTile; 2]>::try_from(operands).map_err(|_| invalid())?;
        let gpu = &self.gpu;
        use wgpu::BufferUsages as U;
        let n = tile.width * tile.height;
        // Error scopes are per thread: this worker's calls need their own.
        let scope = ErrorScopes::push(&gpu.device);
        let displacement = gpu.empty(
            "warp displacement",
            8 * n.max(1) as u64,
            U::STORAGE | U::COPY_SRC,
        );
        let range = gpu.empty("warp range", RANGE_BYTES, U::STORAGE | U::COPY_SRC);
        let read = submit_and_read(
            gpu,
            self.queries.as_ref(),
            (&range, RANGE_BYTES),
            |encoder, timer| {
                self.encode_displacement(tile, [x, y], encoder, &displacement, Some(&range), timer)
            },
        );
        scope.pop()?;
        let bytes = read?;
        Ok((displacement, decode_range(&bytes)?))
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
    /// base's tables (point-sampled, as [`render_tile`](Self::render_tile)), where the base
    /// reads the displacement's range after x, y and the displacement ran on the device (this
    /// worker waits for their 16 bytes of range); else the host's composition.
    fn prepare_tile(&self, tile: &GpuWindow) -> Result<PreparedTile, GpuError> {
        if self.displace.is_none() {
            return self.render_tile(tile, None).map(PreparedTile::Values);
        }
        let base_tile = tile.filtered(spectex_model::Filter::Off);
        let operands = vec![self.x.prepare_pass(tile)?, self.y.prepare_pass(tile)?];
        if !self.ranged() {
            return Ok(PreparedTile::Chain {
                operands,
                base: Some(self.base.prepare_device_displaced(&base_tile, None)?),
            });
        }
        let (displacement, range) = self.displace_with_range(tile, operands)?;
        Ok(PreparedTile::Chain {
            operands: vec![PreparedTile::OnDevice(displacement)],
            base: Some(
                self.base
                    .prepare_device_displaced(&base_tile, Some(range))?,
            ),
        })
    }

    /// x and y into planes of their own and `warp_displace` into the displacement, then the
    /// base displaced by it into `output` (or, given the displacement already on the device,
    /// the base alone): one submission, nothing read back.
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
        let Some(base) = base else {
            return Err(invalid());
        };
        let base_tile = tile.filtered(spectex_model::Filter::Off);
        let mut operands = operands.into_iter();
        match (operands.next(), operands.next(), operands.next()) {
            (Some(PreparedTile::OnDevice(displacement)), None, None) if self.ranged() => self
                .base
                .encode_device_displaced(&base_tile, base, encoder, output, &displacement, timer),
            (Some(x), Some(y), None) if !self.ranged() => {
                let n = tile.width * tile.height;
                let displacement = self.gpu.empty(
                    "warp displacement",
                    8 * n.max(1) as u64,
                    wgpu::BufferUsages::STORAGE,
                );
                let (start, end) = split_timer(timer);
                self.encode_displacement(tile, [x, y], encoder, &displacement, None, start)?;
                self.base.encode_device_displaced(
                    &base_tile,
                    base,
                    encoder,
                    output,
                    &displacement,
                    end,
                )
            }
            _ => Err(invalid()),
        }
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
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use spectex_model::fixtures::constant;
    use spectex_model::random::Prng;

    use super::*;
    use crate::layout::check::{assert_matches_wgsl, context_or_skip};
    use crate::pipeline::read_buffer;

    pub fn compose_params_match_the_wgsl() {
        assert_matches_wgsl::<ComposeParams>("compose", "ComposeParams");
    }

    /// The order-preserving map of `compose.wgsl` undone: `ordered` written again here from
    /// its definition, then decoded, over values across the range (signs, zeros, subnormals,
    /// infinities).
    pub fn ordered_words_decode_to_their_values() {
        let ordered = |v: f32| {
            let b = v.to_bits();
            if b & 0x8000_0000 != 0 {
                !b
            } else {
                b | 0x8000_0000
            }
        };
        let values = [
            f32::NEG_INFINITY,
            -MAX_WARP_F32,
            -1.5,
            -f32::MIN_POSITIVE / 4.0,
            -0.0,
            0.0,
            f32::MIN_POSITIVE / 4.0,
            2.25,
            f32::INFINITY,
        ];
        for pair in values.windows(2) {
            assert!(ordered(pair[0]) < ordered(pair[1]), "{pair:?}");
        }
        for v in values {
            assert_eq!(unordered(ordered(v)).to_bits(), v.to_bits());
        }
    }

    const MAX_WARP_F32: f32 = spectex_model::MAX_WARP;

    /// A warp keeps its displacement on the device where its base's host part reads nothing
    /// of it (LRP), only its range (a phasor's cell box, a Voronoi search: 16 bytes read back)
    /// or reads it through passes of its own (a texture's LRP planes). Each gives the bits of
    /// the host's composition of the same tile ([`WarpKernel::render_tile`]: x and y read
    /// back, the displacement applied there and uploaded), near the origin and far from it.
    /// The testdata warps are made 20 times stronger, so their displacements reach cells
    /// beyond the margins of an undisplaced box (the test fails when the range is ignored).
    pub fn a_displacement_kept_on_the_device_is_the_host_composition() {
        let test = "a_displacement_kept_on_the_device_is_the_host_composition";
        let Some(context) = context_or_skip(test) else {
            return;
        };
        for name in [
            "warp-phasor-by-lrp",
            "combine-cracks",
            "warp-texture-colour",
            "warp-lrp-by-gabor",
        ] {
            let path = format!(
                "{}/../../testdata/models/{name}.json",
                env!("CARGO_MANIFEST_DIR")
            );
            let mut model =
                spectex_model::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
            fn stronger(model: &mut Model) {
                if let Model::Warp(w) = model {
                    w.strength *= 20.0;
                }
                if let Model::Combine(c) = model {
                    c.operands.iter_mut().for_each(stronger);
                }
            }
            stronger(&mut model);
            let evaluator = GpuEvaluator::new(&context, &model).unwrap();
            for offset in [[-3.3, 20.0], [1.0e6, -3.0e5]] {
                let window = GpuWindow::new(40, 28).at(offset, 0.8);
                let device = evaluator.render(&window).unwrap();
                let host = evaluator.render_tile_displaced(&window, None).unwrap();
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert!(bits(&device) == bits(&host), "{name} at {offset:?}");
            }
        }
    }

    /// `warp_displace_range` over more pixels than one workgroup (with values that clamp, a
    /// NaN, both zeros): each displacement is `Warp::displacement` of its value bit for bit,
    /// and the range read back is the host's minimum and maximum of those, in IEEE total
    /// order (so −0 below +0).
    pub fn displacement_range_is_the_exact_extremes() {
        let Some(context) = context_or_skip("displacement_range_is_the_exact_extremes") else {
            return;
        };
        let gpu = Gpu::new(&context);
        let key = ("compose", "warp_displace_range", Vec::new());
        let pipeline = compute_pipeline(&gpu, key, 1, || wgsl_source("compose")).unwrap();
        let warp = Warp {
            base: Box::new(constant(0.0)),
            x: Box::new(constant(0.0)),
            y: Box::new(constant(0.0)),
            strength: 37.5,
        };
        let n = 1000;
        let mut prng = Prng::new(0x5eed);
        let mut draw = |k: usize| match k {
            3 => f32::NAN,
            17 => -0.0,
            400 => 1e6,
            999 => -1e6,
            _ => 4.0 * prng.next_f32() - 2.5,
        };
        let xs: Vec<f32> = (0..n).map(&mut draw).collect();
        let ys: Vec<f32> = (0..n)
            .map(|k| if k == 17 { 0.0 } else { draw(k + 1) })
            .collect();
        use wgpu::BufferUsages as U;
        let input = |label, v: &[f32]| gpu.buffer(label, bytemuck::cast_slice(v), U::STORAGE);
        let (vx, vy) = (input("x", &xs), input("y", &ys));
        let displacement = gpu.empty("d", 8 * n as u64, U::STORAGE | U::COPY_SRC);
        let range = gpu.empty("range", RANGE_BYTES, U::STORAGE | U::COPY_SRC);
        let readback = gpu.empty(
            "readback",
            8 * n as u64 + RANGE_BYTES,
            U::MAP_READ | U::COPY_DST,
        );
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let (per_row, grid) = flat_grid(&gpu, n as u32, COMPOSE_WORKGROUP);
        let params = ComposeParams {
            count: n as u32,
            per_row,
            strength: warp.strength,
            max_warp: spectex_model::MAX_WARP,
        };
        let bindings = vec![
            vx.as_entire_binding(),
            vy.as_entire_binding(),
            displacement.as_entire_binding(),
            range.as_entire_binding(),
        ];
        encode_pass(
            &gpu,
            &mut encoder,
            ("test", &pipeline),
            &params,
            bindings,
            grid,
            None,
        )
        .unwrap();
        encoder.copy_buffer_to_buffer(&displacement, 0, &readback, 0, 8 * n as u64);
        encoder.copy_buffer_to_buffer(&range, 0, &readback, 8 * n as u64, RANGE_BYTES);
        let index = gpu.queue.submit([encoder.finish()]);
        let bytes = read_buffer(&gpu.device, &readback, &gpu.lost, Some(index)).unwrap();
        let (field, words) = bytes.split_at(8 * n);
        let field: Vec<f32> = bytemuck::pod_collect_to_vec(field);
        let want: Vec<[f32; 2]> = xs
            .iter()
            .zip(&ys)
            .map(|(&x, &y)| [warp.displacement(x), warp.displacement(y)])
            .collect();
        for (k, (got, want)) in field.chunks_exact(2).zip(&want).enumerate() {
            assert_eq!(
                [got[0].to_bits(), got[1].to_bits()],
                want.map(f32::to_bits),
                "pixel {k}"
            );
        }
        let extremes = |axis: usize| {
            let mut v: Vec<f32> = want.iter().map(|d| d[axis]).collect();
            v.sort_by(f32::total_cmp);
            [v[0], v[n - 1]]
        };
        let got = decode_range(words).unwrap();
        assert_eq!(got.x.map(f32::to_bits), extremes(0).map(f32::to_bits));
        assert_eq!(got.y.map(f32::to_bits), extremes(1).map(f32::to_bits));
        assert_eq!(got.x, [-spectex_model::MAX_WARP, spectex_model::MAX_WARP]);
    }
}
