//! Host side of `shaders/texture.wgsl`: a texture model's structures packed into tables once,
//! its random-phase strata and turbulence strata as LRP evaluators on the same device, and per
//! tile the strata values, the turbulence displacement (summed and scaled here in the CPU's f32
//! order) and the placement cells of every column and row (f64, `locate_cell`).

use spectex_model::grid::locate_cell;
use spectex_model::texture::PLACEMENT_LAYER;
use spectex_model::{LrpNoise, Model, TextureModel};

use crate::{GpuContext, GpuError, GpuEvaluator, GpuWindow};

/// Words of `TextureParams`.
const PARAM_WORDS: usize = 24;
/// Words of one `ChannelStructure`.
const CHANNEL_WORDS: usize = 8;
/// Bytes of one `PlacementAxis` entry (cell, offset).
pub(crate) const PLACEMENT_AXIS_BYTES: u64 = 8;

/// A texture model ready to render tile by tile.
#[derive(Debug)]
pub(crate) struct TexturePack {
    pub model: TextureModel,
    /// Each channel's strata with its mean, `None` where the channel has no strata.
    strata: Vec<Option<GpuEvaluator>>,
    /// Turbulence strata per axis, each a single-stratum LRP noise of mean 0.
    turbulence: [Vec<GpuEvaluator>; 2],
    /// `ChannelStructure` records, one per channel.
    pub structures: Vec<u32>,
    /// `(start, count)` of every block of every structure.
    pub blocks: Vec<u32>,
    /// `(k_x, k_y, A, φ)` f32 bits of every fixed cosine.
    pub cosines: Vec<u32>,
}

/// The buffers of one tile.
pub(crate) struct TextureTile {
    pub params: Vec<u32>,
    /// `channels + 2` planes: strata per channel, then the x and y displacements.
    pub values: Vec<u32>,
    pub columns: Vec<u32>,
    pub rows: Vec<u32>,
}

/// Packs a validated texture model; `limit` bounds one storage buffer.
pub(crate) fn pack_texture(
    context: &GpuContext,
    model: &TextureModel,
    limit: u64,
) -> Result<TexturePack, GpuError> {
    let strata = model
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
            GpuEvaluator::new(context, &Model::Lrp(lrp)).map(Some)
        })
        .collect::<Result<Vec<_>, GpuError>>()?;
    let mut turbulence: [Vec<GpuEvaluator>; 2] = [Vec::new(), Vec::new()];
    if let Some(t) = &model.turbulence {
        for (axis, evaluators) in turbulence.iter_mut().enumerate() {
            for (s, stratum) in t.strata.iter().enumerate() {
                let lrp = LrpNoise {
                    seed: t.seed(axis, s),
                    mean: 0.0,
                    strata: vec![stratum.clone()],
                };
                evaluators.push(GpuEvaluator::new(context, &Model::Lrp(lrp))?);
            }
        }
    }
    let mut structures = Vec::with_capacity(CHANNEL_WORDS * model.channels.len());
    let mut blocks = Vec::new();
    let mut cosines = Vec::new();
    for ch in &model.channels {
        let first_block = (blocks.len() / 2) as u32;
        let Some(s) = &ch.structure else {
            structures.extend([1, first_block, 0, 0, 0, 0, 0, 0]);
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
        structures.extend([
            s.blocks,
            first_block,
            1,
            0,
            delta.to_bits(),
            inv_delta.to_bits(),
            inv_n.to_bits(),
            0,
        ]);
        for block in &s.cosines {
            blocks.extend([(cosines.len() / 4) as u32, block.len() as u32]);
            for c in block {
                cosines.extend([
                    (c.frequency[0] as f32).to_bits(),
                    (c.frequency[1] as f32).to_bits(),
                    c.amplitude.to_bits(),
                    c.phase.to_bits(),
                ]);
            }
        }
    }
    // A binding's buffer must hold at least one element of its array (a texture without any
    // structure still binds the tables): one unused block and one unused cosine.
    if blocks.is_empty() {
        blocks.extend([0, 0]);
    }
    if cosines.is_empty() {
        cosines.extend([0; 4]);
    }
    let needed = 4 * cosines.len() as u64;
    if needed > limit {
        return Err(GpuError::LimitsExceeded {
            what: "texture structure cosines (bytes in one storage buffer)",
            value: needed,
            limit,
        });
    }
    Ok(TexturePack {
        model: model.clone(),
        strata,
        turbulence,
        structures,
        blocks,
        cosines,
    })
}

impl TexturePack {
    /// Values per pixel.
    pub fn channels(&self) -> usize {
        self.model.channels.len()
    }

    /// The LRP evaluators this texture runs per tile (for sizing tiles).
    pub fn evaluators(&self) -> impl Iterator<Item = &GpuEvaluator> {
        self.strata
            .iter()
            .flatten()
            .chain(self.turbulence.iter().flatten())
    }

    /// Renders the tile's strata and turbulence on the device (at positions displaced by a
    /// warp's `displacement`, if any) and builds the texture pass's tables.
    pub fn tile(
        &self,
        tile: &GpuWindow,
        displacement: Option<&[f32]>,
    ) -> Result<TextureTile, GpuError> {
        let n = tile.width * tile.height;
        let nc = self.channels();
        let mut values: Vec<f32> = Vec::with_capacity((nc + 2) * n);
        for (ch, evaluator) in self.model.channels.iter().zip(&self.strata) {
            match evaluator {
                Some(e) => values.extend(e.render_tile_displaced(tile, displacement)?),
                None => values.resize(values.len() + n, ch.mean),
            }
        }
        // Σ_S |n_S| per axis in stratum order, then σ(Σ − centre): the CPU's f32 operations.
        for evaluators in &self.turbulence {
            let mut sum = vec![0.0f32; n];
            for e in evaluators {
                for (s, v) in sum
                    .iter_mut()
                    .zip(e.render_tile_displaced(tile, displacement)?)
                {
                    *s += v.abs();
                }
            }
            if let Some(t) = &self.model.turbulence {
                for s in &mut sum {
                    *s = t.displacement(*s);
                }
            }
            values.extend(sum);
        }
        let side = self.model.placement_cell();
        let axis = |count: usize, position: &dyn Fn(usize) -> f64| -> Vec<u32> {
            (0..count)
                .flat_map(|i| {
                    let (cell, offset) = locate_cell(position(i), side).unwrap_or((0, 0.0));
                    [cell as u32, offset.to_bits()]
                })
                .collect()
        };
        let columns = axis(tile.width, &|i| tile.x(i));
        let rows = axis(tile.height, &|j| tile.y(j));
        let mut params = vec![0u32; PARAM_WORDS];
        params[..8].copy_from_slice(&[
            tile.width as u32,
            tile.height as u32,
            nc as u32,
            self.model.period,
            self.model.seed,
            u32::from(self.model.random_placement),
            u32::from(self.model.colour.is_some()),
            PLACEMENT_LAYER,
        ]);
        if let Some(c) = &self.model.colour {
            for i in 0..3 {
                params[8 + i] = c.mean[i].to_bits();
                for j in 0..3 {
                    params[12 + 4 * i + j] = c.basis[i][j].to_bits();
                }
            }
        }
        Ok(TextureTile {
            params,
            values: values.iter().map(|v| v.to_bits()).collect(),
            columns,
            rows,
        })
    }
}
