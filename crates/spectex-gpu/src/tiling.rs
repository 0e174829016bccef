//! Tiling and blending on the device (`shaders/tiling.wgsl`): the host builds the exemplar's
//! pyramid and prefiltered tables once (`TilingTexture::tables`, the CPU's bytes) and, per tile,
//! each column's and row's whole pixel and fraction (the CPU's split)
//! and the tile's mip levels (`spectex_model::tiling::mip_level` of its footprint).
//!
//! The export (the glue of `shaders/tiling.wgsl`): the uniform, the texels and the tables; the
//! pixel grid is the export's lattice 0. The texels and tables
//! exceed the constants' limit for any real exemplar, so an exported tiling texture reads them
//! from the storage buffer (`spectex export --wgsl --tables buffer`): `texels` (one `vec4<f32>`
//! per texel of every mip level: the Gaussianised channels, then zeros) and `luts` (per level and
//! channel 1024 `f32`), at the offsets the module's header lists.

use spectex_model::Period;
use spectex_model::tiling::{
    Blend, LUT_ENTRIES, LUT_RANGE, Level, TILING_BLOCK_LAYER, TILING_LAYER, TilingTables,
    TilingTexture, mip_level,
};

use crate::axis::{CellAxis, cell_axis, periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/tiling.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/tiling.wgsl"));

wgsl_struct! {
    /// `TilingParams` of `tiling.wgsl`; `width`, `height` and the levels are the tile's.
    pub(crate) struct TilingParams {
        width: u32,
        height: u32,
        seed: u32,
        channels: u32,
        lo: u32,
        span_x: u32,
        span_y: u32,
        /// 0: variance-preserving, 1: hex.
        blend: u32,
        sharpness: u32,
        rotation: f32,
        /// Whole pixels (the side even).
        side: i32,
        row: i32,
        /// A periodic lattice's vertices per row and rows, 0 when not periodic.
        wrap_c: i32,
        wrap_rows: i32,
        /// 1 when `level1` is mixed into `level0` with weight `mix`.
        two_levels: u32,
        mix: f32,
        lut_scale: f32,
        lut_range: f32,
        layer: u32,
        block_layer: u32,
        /// (first texel, width, height, level index).
        level0: [u32; 4],
        level1: [u32; 4],
        /// The colour mean (`w` unused), then the basis by rows.
        mean: [f32; 4],
        basis0: [f32; 4],
        basis1: [f32; 4],
        basis2: [f32; 4],
        inv_side: f32,
        inv_row: f32,
        /// The exemplar's sides (level 0).
        ex_width: u32,
        ex_height: u32,
    }
}

/// A tiling texture on the device: its uniform (tile size and levels set per tile), lattice
/// and levels.
#[derive(Debug, Clone)]
pub(crate) struct TilingKernel {
    params: TilingParams,
    levels: Vec<Level>,
    period: Option<Period>,
}

/// A level as the shader reads it.
fn level_record(levels: &[Level], l: usize) -> [u32; 4] {
    let lv = levels[l.min(levels.len() - 1)];
    [
        lv.offset,
        lv.width,
        lv.height,
        l.min(levels.len() - 1) as u32,
    ]
}

/// The kernel of a validated model, its lattice fitted to `period` when given, and its tables.
pub(crate) fn pack(
    model: &TilingTexture,
    period: Option<Period>,
) -> Result<(TilingKernel, TilingTables), GpuError> {
    let refused = || {
        GpuError::Model(model.validate().err().unwrap_or_else(|| {
            spectex_model::ModelError::OutOfRange {
                field: "tiling.tile".into(),
                value: f64::from(model.tile),
                range: "a tile the exemplar holds",
            }
        }))
    };
    let lattice = model.lattice(period).ok_or_else(refused)?;
    let (lo, spans) = lattice
        .spans(model.width, model.height)
        .ok_or_else(refused)?;
    // vec4<f32> rows, w unused.
    let (mean3, basis3) = model.colour();
    let pad = |v: [f32; 3]| [v[0], v[1], v[2], 0.0];
    let (mean, basis) = (pad(mean3), basis3.map(pad));
    let (blend, sharpness, rotation) = match model.blend {
        Blend::Variance => (0, 1, 0.0),
        Blend::Hex {
            sharpness,
            rotation,
        } => (1, sharpness, rotation),
    };
    let tables = model.tables();
    let (wrap_c, wrap_rows) = lattice.wrap.unwrap_or((0, 0));
    let params = TilingParams {
        width: 0,
        height: 0,
        seed: model.seed,
        channels: model.channels,
        lo,
        span_x: spans[0],
        span_y: spans[1],
        blend,
        sharpness,
        rotation,
        side: lattice.side as i32,
        row: lattice.row as i32,
        wrap_c,
        wrap_rows,
        two_levels: 0,
        mix: 0.0,
        lut_scale: (LUT_ENTRIES - 1) as f32 / (2.0 * LUT_RANGE),
        lut_range: LUT_RANGE,
        layer: TILING_LAYER,
        block_layer: TILING_BLOCK_LAYER,
        level0: level_record(&tables.levels, 0),
        level1: level_record(&tables.levels, 0),
        mean,
        basis0: basis[0],
        basis1: basis[1],
        basis2: basis[2],
        inv_side: (1.0 / lattice.side) as f32,
        inv_row: (1.0 / lattice.row) as f32,
        ex_width: model.width,
        ex_height: model.height,
    };
    let kernel = TilingKernel {
        params,
        levels: tables.levels.clone(),
        period,
    };
    Ok((kernel, tables))
}

/// The resident tables: the texels, then the look-up tables.
fn resident(tables: &TilingTables) -> [Table; 2] {
    [
        Table::new("tiling texels", &tables.texels),
        Table::new("tiling luts", &tables.luts),
    ]
}

impl GpuKind for TilingTexture {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "tiling",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["tiling_main"],
    });

    /// Periodic: the lattice fitted to the period and its vertices keyed modulo it, positions
    /// reduced by the host, as the CPU's periodic kernel.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (kernel, tables) = pack(self, period)?;
        Shaded::boxed(context, kernel, &resident(&tables))
    }
}

impl ShaderKernel for TilingKernel {
    const SHADER: &'static str = "tiling";
    const ENTRY_POINT: &'static str = "tiling_main";

    const SHAPE: &'static [&'static str] = &["TILING_BLEND", "TILING_CHANNELS"];

    /// The model's blend and channel count (the shader's shape overrides; two_levels is the
    /// tile's footprint's).
    fn shape(&self) -> Vec<u32> {
        vec![self.params.blend, self.params.channels]
    }

    fn output_channels(&self) -> usize {
        self.params.channels as usize
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<CellAxis>() as u64
    }

    /// The output (up to 3 values) or the displacement (2 values).
    fn pixel_bytes(&self) -> u64 {
        4 * u64::from(self.params.channels).max(2)
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: TileDisplacement<'_>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        let (level, mix) = mip_level(tile.footprint(), self.levels.len());
        let params = TilingParams {
            width: tile.width as u32,
            height: tile.height as u32,
            two_levels: u32::from(mix > 0.0),
            mix,
            level0: level_record(&self.levels, level),
            level1: level_record(&self.levels, level + 1),
            ..self.params
        };
        // Whole pixels and fractions (the CPU's `locate_cell(x, 1.0)`), valid below 2³⁰.
        let usable = |mut axis: Vec<CellAxis>| {
            for a in &mut axis {
                if a.cell.unsigned_abs() >= 1 << 30 {
                    *a = bytemuck::Zeroable::zeroed();
                }
            }
            axis
        };
        let columns = usable(cell_axis(
            1.0,
            tile.width,
            periodic_columns(tile, self.period),
        ));
        let rows = usable(cell_axis(
            1.0,
            tile.height,
            periodic_rows(tile, self.period),
        ));
        Ok(TileTables::new(
            &params,
            vec![
                Table::new("tiling columns", &columns),
                Table::new("tiling rows", &rows),
            ],
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for TilingTexture {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, tables) = pack(self, None)?;
        // The pixel grid: the glue splits on the triangle lattice in integers.
        let lattices = vec![1.0];
        let (value, result) = if self.channels == 3 {
            ("vec3<f32>", "v")
        } else {
            ("f32", "v.x")
        };
        Ok(
            ExportParts::of(&kernel, &resident(&tables), lattices, "tiling")?.with_substitutions(
                vec![
                    ("TILING_VALUE", value.to_string()),
                    ("TILING_RESULT", result.to_string()),
                ],
            ),
        )
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    pub fn params_match_the_wgsl() {
        assert_matches_wgsl::<TilingParams>("tiling", "TilingParams");
    }
}
