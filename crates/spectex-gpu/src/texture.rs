//! Textures by example on the device (`shaders/texture.wgsl`): the structures packed into tables
//! once, the random-phase strata and turbulence strata as LRP evaluators on the same device, and
//! per tile the placement cells of every column and row (f64, `locate_cell`) and the planes of
//! the LRP passes' values: each channel's strata, then each turbulence stratum. An undisplaced
//! tile's passes run on the device in the tile's own submission, writing their planes into the
//! texture's table (nothing comes back to the host between them); a displaced one (a warp's
//! base) renders them on the host's request with its displacement. The shader sums the
//! turbulence strata and scales the sum in the CPU's f32 order.
//!
//! The texture by example's export (the glue of `shaders/texture.wgsl`): its own shader's parts
//! and the LRP models (strata and turbulence) whose values it reads; the placement cell is
//! the export's lattice 0.

use spectex_model::grid::locate_cell;
use spectex_model::texture::PLACEMENT_LAYER;
use spectex_model::{LrpNoise, Model, Period, TextureModel};

use crate::axis::{periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportNodeOf, ExportParts, TextureExport};
use crate::kernel::{
    GpuKernel, GpuKind, PreparedTile, ShaderKernel, Table, TileDisplacement, TileTables,
};
use crate::layout::wgsl_struct;
use crate::pipeline::{Gpu, Shaded, binding_limit};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuEvaluator, GpuWindow};

/// `shaders/texture.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/texture.wgsl"));

wgsl_struct! {
    /// `TextureParams` of `texture.wgsl`.
    pub(crate) struct TextureParams {
        width: u32,
        height: u32,
        /// 1 or 3.
        channels: u32,
        /// `T`, the structure period in pixels.
        period: u32,
        /// Seed of the placement shifts.
        seed: u32,
        /// 1 when placement cells draw random shifts.
        random_placement: u32,
        /// 1 when a colour basis maps the channels to RGB.
        colour: u32,
        /// [`PLACEMENT_LAYER`] (one definition, passed by the host).
        placement_layer: u32,
        /// 1: a minified render, the structure filtered over a footprint of `footprint` pixels
        /// (`Structure::eval_filtered`).
        filtered: u32,
        footprint: f32,
        /// `Turbulence::sigma` and `centre`: the displacement `σ·(Σ_S |n_S| − centre)`.
        turbulence_sigma: f32,
        turbulence_centre: f32,
        /// The colour basis' mean (a `vec4<f32>`, `w` unused).
        colour_mean: [f32; 4],
        /// Row `i` maps the channels to component `i` (`vec4<f32>` rows, `w` unused).
        basis: [[f32; 4]; 3],
        /// Placement cells per period along x and y of a periodic model (hashed modulo them,
        /// `wrap_cell`), 0 when not periodic.
        cells_x: i32,
        cells_y: i32,
        /// 1 when the model has turbulence (else the displacement is 0, as on the CPU).
        turbulence: u32,
        /// Turbulence strata per axis: planes of the values after the channels' (x's, then
        /// y's).
        turbulence_strata: u32,
    }
}

wgsl_struct! {
    /// `ChannelStructure` of `texture.wgsl`: one channel's fixed-phase structure.
    pub(crate) struct ChannelStructure {
        /// `b`, blocks per period side.
        blocks: u32,
        /// Index in the block table of this channel's block 0.
        first_block: u32,
        /// 0 when the channel has no structure (`n_R = 0`).
        present: u32,
        /// Index in the block-means table of this channel's mipmap level 0.
        first_mean: u32,
        /// `Δ_R = T/b`, `1/Δ_R` and `1/N` as the CPU rounds them (`1/(2T)` when `b = 1`).
        delta: f32,
        inv_delta: f32,
        inv_n: f32,
        _pad1: f32,
    }
}

wgsl_struct! {
    /// `PlacementAxis` of `texture.wgsl`: a position's placement cell and offset.
    pub(crate) struct PlacementAxis {
        cell: i32,
        offset: f32,
    }
}

/// A texture model ready to render tile by tile.
#[derive(Debug)]
pub(crate) struct TextureKernel {
    model: TextureModel,
    /// Each channel's strata with its mean, `None` where the channel has no strata.
    strata: Vec<Option<GpuEvaluator>>,
    /// Turbulence strata per axis, each a single-stratum LRP noise of mean 0.
    turbulence: [Vec<GpuEvaluator>; 2],
    /// The period of a periodic model: positions reduced modulo it, the strata and turbulence
    /// periodic LRP noises (the CPU's `TextureEvaluator::new_periodic`).
    period: Option<Period>,
    /// The device, for the planes of channels without strata (their mean, uploaded).
    gpu: Gpu,
}

/// One plane of a tile's values: an LRP pass, or a channel's mean where it has no strata.
enum Plane<'a> {
    Lrp(&'a GpuEvaluator),
    Mean(f32),
}

/// The structure tables of a texture: a [`ChannelStructure`] per channel, the `(start, count)`
/// of every block of every structure, and `(k_x, k_y, A, φ)` of every fixed cosine.
pub(crate) struct Structures {
    /// Every channel's `Structure::mean_mipmap`, concatenated.
    pub(crate) means: Vec<f32>,
    pub(crate) channels: Vec<ChannelStructure>,
    pub(crate) blocks: Vec<[u32; 2]>,
    pub(crate) cosines: Vec<[f32; 4]>,
}

/// Packs the structures of a validated texture model.
pub(crate) fn pack_structures(model: &TextureModel) -> Structures {
    let mut channels = Vec::with_capacity(model.channels.len());
    let mut blocks: Vec<[u32; 2]> = Vec::new();
    let mut cosines: Vec<[f32; 4]> = Vec::new();
    let mut means: Vec<f32> = Vec::new();
    for ch in &model.channels {
        let first_block = blocks.len() as u32;
        let Some(s) = &ch.structure else {
            channels.push(ChannelStructure {
                blocks: 1,
                first_block,
                ..bytemuck::Zeroable::zeroed()
            });
            continue;
        };
        // The CPU's `Structure::eval` constants, rounded as it rounds them.
        let (delta, inv_delta, inv_n) = if s.blocks == 1 {
            (0.0f32, 0.0f32, 1.0 / (2 * model.period) as f32)
        } else {
            let delta = (model.period / s.blocks) as f32;
            let inv_delta = 1.0 / delta;
            (delta, inv_delta, 0.5 * inv_delta)
        };
        let first_mean = means.len() as u32;
        means.extend(s.mean_mipmap());
        channels.push(ChannelStructure {
            blocks: s.blocks,
            first_block,
            present: 1,
            first_mean,
            delta,
            inv_delta,
            inv_n,
            _pad1: 0.0,
        });
        for block in &s.cosines {
            blocks.push([cosines.len() as u32, block.len() as u32]);
            cosines.extend(block.iter().map(|c| {
                [
                    c.frequency[0] as f32,
                    c.frequency[1] as f32,
                    c.amplitude,
                    c.phase,
                ]
            }));
        }
    }
    // A texture without any structure still binds the block and cosine tables: `Table` gives
    // each one unused record.
    Structures {
        means,
        channels,
        blocks,
        cosines,
    }
}

impl GpuKind for TextureModel {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "texture",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["texture_main"],
    });

    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let strata = self
            .channels
            .iter()
            .map(|ch| {
                if ch.strata.is_empty() {
                    return Ok(None);
                }
                let lrp = LrpNoise {
                    seed: ch.seed,
                    mean: ch.mean,
                    strata: ch.strata.clone(),
                };
                lrp_evaluator(context, lrp, period).map(Some)
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        let mut turbulence: [Vec<GpuEvaluator>; 2] = [Vec::new(), Vec::new()];
        if let Some(t) = &self.turbulence {
            for (axis, evaluators) in turbulence.iter_mut().enumerate() {
                for (s, stratum) in t.strata.iter().enumerate() {
                    let lrp = LrpNoise {
                        seed: t.seed(axis, s),
                        mean: 0.0,
                        strata: vec![stratum.clone()],
                    };
                    evaluators.push(lrp_evaluator(context, lrp, period)?);
                }
            }
        }
        let structures = pack_structures(self);
        let limit = binding_limit(&context.limits());
        // What the cosine table occupies on the device (one unused record where there is none).
        let needed = size_of_val(structures.cosines.as_slice()).max(size_of::<[f32; 4]>()) as u64;
        if needed > limit {
            return Err(GpuError::LimitsExceeded {
                what: "texture structure cosines (bytes in one storage buffer)",
                value: needed,
                limit,
            });
        }
        let kernel = TextureKernel {
            model: self.clone(),
            strata,
            turbulence,
            period,
            gpu: Gpu::new(context),
        };
        Shaded::boxed(
            context,
            kernel,
            &[
                Table::new("texture structures", &structures.channels),
                Table::new("texture blocks", &structures.blocks),
                Table::new("texture cosines", &structures.cosines),
                Table::new("texture block means", &structures.means),
            ],
        )
    }
}

/// The evaluator of one of a texture's LRP passes, periodic with `period` when given (an LRP
/// noise takes any period: its lattices are fitted to it).
fn lrp_evaluator(
    context: &GpuContext,
    lrp: LrpNoise,
    period: Option<Period>,
) -> Result<GpuEvaluator, GpuError> {
    let model = Model::Lrp(lrp);
    match period {
        None => GpuEvaluator::new(context, &model),
        Some(p) => GpuEvaluator::periodic_at_z(context, &model, 0.0, p),
    }
}

impl TextureKernel {
    /// Values per pixel.
    fn channels(&self) -> usize {
        self.model.channels.len()
    }

    /// The LRP evaluators this texture runs per tile.
    fn evaluators(&self) -> impl Iterator<Item = &GpuEvaluator> {
        self.strata
            .iter()
            .flatten()
            .chain(self.turbulence.iter().flatten())
    }

    /// The planes of a tile's values, in order: each channel's strata (or mean), then the
    /// turbulence strata of x, then of y.
    fn planes(&self) -> impl Iterator<Item = Plane<'_>> {
        let channels = self
            .model
            .channels
            .iter()
            .zip(&self.strata)
            .map(|(ch, e)| e.as_ref().map_or(Plane::Mean(ch.mean), Plane::Lrp));
        channels.chain(self.turbulence.iter().flatten().map(Plane::Lrp))
    }
}

impl ShaderKernel for TextureKernel {
    const SHADER: &'static str = "texture";
    const ENTRY_POINT: &'static str = "texture_main";
    fn output_channels(&self) -> usize {
        self.channels()
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<PlacementAxis>() as u64
    }

    /// Megapixel tiles: each tile in flight holds its planes twice on the device (each pass's
    /// own buffer and the texture's table), 2·4·planes bytes a pixel.
    fn tile_pixels(&self) -> Option<usize> {
        Some(crate::kernel::CHAIN_TILE_PIXELS)
    }

    /// The largest per-pixel buffer holds the planes of every channel and every turbulence
    /// stratum.
    fn pixel_bytes(&self) -> u64 {
        4 * self.planes().count() as u64
    }

    /// Each LRP pass renders the same tile in one dispatch: it must fit them all.
    fn fit_tile(
        &self,
        window: &GpuWindow,
        [mut width, mut height]: [usize; 2],
        _limit: u64,
    ) -> Result<[usize; 2], GpuError> {
        for e in self.evaluators() {
            let [w, h] = e.tile_size(window)?;
            width = width.min(w);
            height = height.min(h);
        }
        Ok([width, height])
    }

    /// The placement tables and the LRP passes' planes: undisplaced, the passes' host parts,
    /// recorded on the device before the texture's dispatch ([`Self::encode_passes`], displaced
    /// there by a displacement on the device, so a warp keeps it there); displaced by each
    /// pixel's displacement from the host, the planes rendered now.
    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        let n = tile.width * tile.height;
        let nc = self.channels();
        let planes = self.planes().count();
        let mut passes = Vec::new();
        let values = match displacement {
            TileDisplacement::Within(_) => {
                return Err(GpuError::Validation(
                    "texture: its passes need each pixel's displacement, not its range".to_owned(),
                ));
            }
            // Displaced on the device, its passes read the displacement themselves (their
            // host parts prepared for that, `encode_device_displaced`'s contract).
            TileDisplacement::None | TileDisplacement::OnDevice => {
                for plane in self.planes() {
                    if let Plane::Lrp(e) = plane {
                        passes.push(match displacement {
                            TileDisplacement::OnDevice => {
                                PreparedTile::Tables(e.prepare_device_displaced(tile, None)?)
                            }
                            _ => e.prepare_pass(tile)?,
                        });
                    }
                }
                Table::filled_on_device("texture values", 4 * (planes * n) as u64)
            }
            TileDisplacement::Pixels(d) => {
                let mut values: Vec<f32> = Vec::with_capacity(planes * n);
                for plane in self.planes() {
                    match plane {
                        Plane::Lrp(e) => values.extend(e.render_tile_displaced(tile, Some(d))?),
                        Plane::Mean(mean) => values.resize(values.len() + n, mean),
                    }
                }
                Table::new("texture values", &values)
            }
        };
        let side = self.model.placement_cell();
        let axis = |count: usize, position: &dyn Fn(usize) -> f64| -> Vec<PlacementAxis> {
            (0..count)
                .map(|i| {
                    let (cell, offset) = locate_cell(position(i), side).unwrap_or((0, 0.0));
                    PlacementAxis { cell, offset }
                })
                .collect()
        };
        let columns = axis(tile.width, &periodic_columns(tile, self.period));
        let rows = axis(tile.height, &periodic_rows(tile, self.period));
        let cells = self
            .period
            .map_or([0, 0], |p| p.cells(side).map(|n| n as i32));
        let mut params = TextureParams {
            width: tile.width as u32,
            height: tile.height as u32,
            channels: nc as u32,
            period: self.model.period,
            seed: self.model.seed,
            random_placement: u32::from(self.model.random_placement),
            colour: u32::from(self.model.colour.is_some()),
            placement_layer: PLACEMENT_LAYER,
            filtered: u32::from(tile.footprint().is_some()),
            footprint: tile.footprint().map_or(0.0, |f| f as f32),
            cells_x: cells[0],
            cells_y: cells[1],
            turbulence_strata: self.turbulence[0].len() as u32,
            ..bytemuck::Zeroable::zeroed()
        };
        if let Some(t) = &self.model.turbulence {
            params.turbulence = 1;
            params.turbulence_sigma = t.sigma;
            params.turbulence_centre = t.centre;
        }
        if let Some(c) = &self.model.colour {
            for i in 0..3 {
                params.colour_mean[i] = c.mean[i];
                params.basis[i][..3].copy_from_slice(&c.basis[i]);
            }
        }
        let mut tables = TileTables::new(
            &params,
            vec![
                values,
                Table::new("texture columns", &columns),
                Table::new("texture rows", &rows),
            ],
        );
        tables.passes = passes;
        Ok(tables)
    }

    /// Each LRP pass into a plane of `target` (through a buffer of its own, copied into
    /// place), a channel's mean uploaded into its plane: all before the texture's dispatch in
    /// the same submission.
    fn encode_passes(
        &self,
        tile: &GpuWindow,
        passes: Vec<PreparedTile>,
        encoder: &mut wgpu::CommandEncoder,
        (target, _, displacement): (&wgpu::Buffer, &[&wgpu::Buffer], Option<&wgpu::Buffer>),
        mut timer: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), GpuError> {
        let n = tile.width * tile.height;
        let plane_bytes = 4 * n as u64;
        let mut passes = passes.into_iter();
        for (k, plane) in self.planes().enumerate() {
            let at = k as u64 * plane_bytes;
            match plane {
                Plane::Mean(mean) => {
                    self.gpu
                        .queue
                        .write_buffer(target, at, bytemuck::cast_slice(&vec![mean; n]));
                }
                Plane::Lrp(e) => {
                    let prepared = passes.next().ok_or_else(|| {
                        GpuError::Validation("texture: fewer passes than LRP planes".to_owned())
                    })?;
                    let plane = self.gpu.empty(
                        "texture pass",
                        plane_bytes,
                        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    );
                    let timer = timer.take();
                    match (displacement, prepared) {
                        (None, prepared) => e.encode_pass(tile, prepared, encoder, &plane, timer),
                        (Some(d), PreparedTile::Tables(tables)) => {
                            e.encode_device_displaced(tile, tables, encoder, &plane, d, timer)
                        }
                        (Some(_), _) => Err(GpuError::Validation(
                            "texture: a displaced pass of another shape".to_owned(),
                        )),
                    }?;
                    encoder.copy_buffer_to_buffer(&plane, 0, target, at, plane_bytes);
                }
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for TextureModel {
    const GLUE: &'static str = WGSL.1;

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
        // The placement cell P = T/2 is the export's lattice 0 (the glue of texture.wgsl).
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

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    pub fn records_match_the_wgsl() {
        assert_matches_wgsl::<TextureParams>("texture", "TextureParams");
        assert_matches_wgsl::<ChannelStructure>("texture", "ChannelStructure");
        assert_matches_wgsl::<PlacementAxis>("texture", "PlacementAxis");
    }
}
