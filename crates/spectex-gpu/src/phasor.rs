//! Phasor noise on the device (`shaders/phasor.wgsl`): the model's profile flattened into
//! parameters and a data table, and per tile the box of kernel cells its pixels reach (drawn by
//! `spectex_model::phasor_kernels`, the code the CPU evaluator uses), the reach masks of its
//! pixel blocks (written on the device by `phasor_bin`, [`bin_layout`]) and, where the profile's
//! fields vary in space, their records per column and per row, from which the shader reads
//! each pixel's duty cycles and blend weight ([`device_fields`]; a displaced tile's come per
//! pixel, in f64, as the CPU computes them).
//!
//! Phasor noise's export (the glue of `shaders/phasor.wgsl`): the compute shader's uniform and
//! profile data, and the constants and field functions the glue draws kernels with in the
//! shader (the compute path's host draws them per tile instead).
//!
//! What the host derives from constant fields becomes a constant. A field that varies
//! (bandwidth, frequency, angle, duty cycle, blend weight; a `gradient` orientation's image;
//! a `coherent` orientation's direction process) is evaluated in the shader, in f32, where the
//! CPU evaluates it in f64: a constant, a linear ramp `value + g·n + g·r` from the integer
//! part `n` and a small offset `r`, or an image whose grey samples follow the profile data
//! and whose texel is located with the `(cell, offset)` split on the lattice of the image's
//! repeat (`export/split.wgsl`), so it is as precise at 10⁷ pixels as at the origin. Some uses
//! are discontinuous (thinning compares a uniform with `(b/b_max)²`) or ill-conditioned
//! (normalising an image's gradient or a sum of directions): the export test judges those
//! pixels as ambiguous where the CPU's value lies within the f32 evaluation's error of the
//! discontinuity, and the rest within a derived bound. A 3D model with a varying field is
//! refused ([`GpuError::Unsupported`] naming the feature): its fields' z and the 3D coherent
//! cap are not exported.

use std::fmt::Write as _;

use spectex_model::PhasorOrientation;
use spectex_model::grid::locate_cell;
use spectex_model::math::{cos_turns, sin_turns};
use spectex_model::phasor_kernels::DIRECTION_LAYER;
use spectex_model::phasor_kernels::{Impulse, PhasorKernels};
use spectex_model::{Field, FieldGrid, ModelKind, Period, PhasorNoise, PhasorOutput, Profile};

use crate::axis::{CellAxes, CellAxis, periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportParts, float};
use std::sync::Arc;

use crate::kernel::{
    DisplacementRead, GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables,
    halve_tile_to_fit,
};
use crate::layout::wgsl_struct;
use crate::pipeline::{Gpu, MAX_PASS_TABLE_BYTES, OwnPass, OwnPassLayout, Shaded, flat_grid};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/phasor.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/phasor.wgsl"));

wgsl_struct! {
    /// `PhasorParams` of `phasor.wgsl`; the tile size, cell box and plane are set per tile.
    pub(crate) struct PhasorParams {
        width: u32,
        height: u32,
        /// 1 for a 3D model (cells `k − 1, k, k + 1`), else 0.
        three_d: u32,
        /// 0 profiled, 1 phase, 2 intensity, 3 Gabor (`Im 𝒢`).
        output_kind: u32,
        /// The cell box: first column and row, columns, rows.
        box_i0: i32,
        box_j0: i32,
        box_cols: u32,
        box_rows: u32,
        /// The plane's cell layer and offset (3D), and whether it is in range.
        z_cell: i32,
        z_offset: f32,
        z_valid: u32,
        /// 1 when per-pixel profile parameters are bound (else the constants below are used).
        per_pixel: u32,
        mean: f32,
        amplitude: f32,
        /// Profile leaves A and B: kind (0 sine, 1 square, 2 triangle, 3 sawtooth, 4 samples,
        /// 5 harmonics), start and length in the profile data.
        a_kind: u32,
        a_start: u32,
        a_len: u32,
        b_kind: u32,
        b_start: u32,
        b_len: u32,
        /// 1 when the profile is a blend `(1 − s)·A + s·B`.
        blend: u32,
        duty_a: f32,
        duty_b: f32,
        weight: f32,
        /// `1/side` of the kernel cells, for warping.
        inv_side: f32,
        /// 1: a minified render, whose square profiles are filtered at the per-pixel `u` of
        /// the harmonic-scale table.
        filtered: u32,
        /// With `per_pixel`: 1 when the pixel-parameter table holds the fields' column and
        /// row records, read per pixel on the device ([`device_fields`]); 0 when it holds
        /// each pixel's values (displaced tiles, whose positions are the host's).
        pixel_fields: u32,
        _pad1: u32,
        _pad2: u32,
        /// Blocks of [`BLOCK`]² pixels across the tile.
        bin_blocks_x: u32,
        /// Cells per block along x and along y.
        bin_span: u32,
        /// Mask chunks per cell ([`CHUNK`] impulses each).
        bin_chunks: u32,
        /// `phasor_bin`'s invocations (0 where the bins table holds no masks,
        /// [`bin_layout`]) and invocations per row of its grid.
        bin_masks: u32,
        bin_stride: u32,
        _pad0: u32,
    }
}

/// Side of a bin block, pixels (`PHASOR_BLOCK`: `phasor_main`'s workgroup).
const BLOCK: usize = 8;
/// Impulses per mask chunk (`PHASOR_CHUNK`: an f32 holds an integer below 2¹⁶ exactly).
const CHUNK: u32 = 16;
/// `phasor_bin`: it reads the tile's cells (2), impulses (3), columns (7) and rows (8) and
/// writes the masks in `output`'s place (9), one invocation a mask, 64 a workgroup (its
/// `@workgroup_size`).
const BIN_PASS: OwnPassLayout = OwnPassLayout {
    label: "phasor bin",
    bindings: &[2, 3, 7, 8],
    target: 9,
    workgroup: 64,
    invocations: |uniform| bytemuck::pod_read_unaligned::<PhasorParams>(uniform).bin_masks,
};
/// The widest span of cells a block's masks cover along an axis: beyond it (a tile minified
/// far enough that 8 pixels cross several cells) the pixels visit every impulse.
const MAX_BIN_SPAN: u64 = 6;

/// The reach masks of an undisplaced tile (`phasor_bin` in `phasor.wgsl`): per block of
/// [`BLOCK`]² pixels, layer and cell of the block's span (its first column's cell − 1 to its
/// last column's + 1, and the same for rows), one bit per impulse of the cell that may reach a
/// pixel of the block. Returns the uniform's fields set and the table's size in bytes, or
/// `None` where the masks would not fit `limit` or `MAX_PASS_TABLE_BYTES`, or a block spans
/// too many cells.
fn bin_layout(
    params: &mut PhasorParams,
    gpu: &Gpu,
    scale: f64,
    side: f64,
    most_impulses: u32,
    limit: u64,
) -> Option<u64> {
    // Columns `BLOCK − 1` steps apart cross at most ⌊(BLOCK − 1)·scale/side⌋ + 1 cell
    // boundaries; the span adds a neighbour on each side.
    let span = ((BLOCK - 1) as f64 * scale / side).floor() + 4.0;
    if span.is_nan() || span > MAX_BIN_SPAN as f64 {
        return None;
    }
    let span = span as u64;
    let (width, height) = (u64::from(params.width), u64::from(params.height));
    let blocks_x = width.div_ceil(BLOCK as u64);
    let blocks = blocks_x * height.div_ceil(BLOCK as u64);
    let layers = if params.three_d == 1 { 3 } else { 1 };
    let masks = blocks * layers * span * span;
    let chunks = u64::from(most_impulses.div_ceil(CHUNK).max(1));
    let bytes = masks * chunks * 4;
    let masks = u32::try_from(masks).ok()?;
    if bytes > limit.min(MAX_PASS_TABLE_BYTES) {
        return None;
    }
    let (stride, _) = flat_grid(gpu, masks, BIN_PASS.workgroup);
    params.bin_blocks_x = blocks_x as u32;
    params.bin_span = span as u32;
    params.bin_chunks = chunks as u32;
    params.bin_masks = masks;
    params.bin_stride = stride;
    Some(bytes)
}

wgsl_struct! {
    /// `PhasorImpulse` of `phasor.wgsl`: `(o, ψ)` and `(f, sharp)` of [`Impulse`].
    pub(crate) struct PhasorImpulse {
        o_psi: [f32; 4],
        f: [f32; 4],
    }
}

/// One leaf of a profile as the shader reads it.
#[derive(Debug, Clone)]
struct Leaf {
    kind: u32,
    start: u32,
    len: u32,
    /// The square profile's duty field.
    duty: Option<Field>,
}

/// A phasor model ready to render tile by tile.
#[derive(Debug, Clone)]
pub(crate) struct PhasorKernel {
    kernels: PhasorKernels,
    /// The plane of a 3D model.
    z: f64,
    /// The uniform's model part (the tile's fields are set per tile).
    params: PhasorParams,
    duty_a: Option<Field>,
    duty_b: Option<Field>,
    weight: Option<Field>,
    /// Where each of those fields' grey samples start in the profile data (an image field).
    grey_starts: [u32; 3],
    pub(crate) per_pixel: bool,
    /// `F`, for the harmonic scale `u = F(p)·s` of a minified render.
    frequency: Field,
    /// Mean impulses per cell, for sizing tiles.
    lambda: f64,
    /// The period of a periodic model: positions reduced modulo it (the kernels' cells are
    /// fitted to it and hashed modulo it, `PhasorKernels::new_periodic`).
    period: Option<Period>,
    /// `phasor_bin` on the device (none for the export, which draws its own kernels).
    bin: Option<Arc<OwnPass>>,
}

fn leaf(profile: &Profile, data: &mut Vec<f32>) -> Result<Leaf, GpuError> {
    let start = data.len() as u32;
    let (kind, len, duty) = match profile {
        Profile::Sine => (0, 0, None),
        Profile::Square { duty } => (1, 0, Some(duty.clone())),
        Profile::Triangle => (2, 0, None),
        Profile::Sawtooth => (3, 0, None),
        Profile::Samples { values } => {
            // The values, then the Fourier series a minified render reads (the CPU's).
            data.extend(values);
            data.extend(spectex_model::filter::samples_series(values));
            (4, values.len() as u32, None)
        }
        Profile::Harmonics { terms } => {
            for h in terms {
                // The CPU's `h.k as f32` and `(phase / 2π) as f32`.
                let shift = (f64::from(h.phase) / std::f64::consts::TAU) as f32;
                data.extend([h.k as f32, h.weight, shift]);
            }
            (5, terms.len() as u32, None)
        }
        Profile::Blend { .. } => {
            return Err(GpuError::Unsupported {
                kind: PhasorNoise::NAME,
                feature: "profiles with nested blends (one blend of two profiles is supported)"
                    .into(),
            });
        }
    };
    Ok(Leaf {
        kind,
        start,
        len,
        duty,
    })
}

/// A field's value at `p` as the CPU's profile reads it: clamped to `[0, 1]`, then f32.
fn unit_at(field: Option<&Field>, p: [f64; 3]) -> f32 {
    field.map_or(0.0, |f| f.at(p[0], p[1], p[2]).clamp(0.0, 1.0) as f32)
}

/// Packs a validated phasor model for the plane `z`, periodic with `period` when given: the
/// kernel and the profile data.
pub(crate) fn pack(
    model: &PhasorNoise,
    z: f64,
    period: Option<Period>,
) -> Result<(PhasorKernel, Vec<f32>), GpuError> {
    let mut data = Vec::new();
    let (a, b, weight) = match &model.profile {
        Profile::Blend { a, b, weight } => (
            leaf(a, &mut data)?,
            Some(leaf(b, &mut data)?),
            Some(weight.clone()),
        ),
        other => (leaf(other, &mut data)?, None, None),
    };
    let constant = |f: &Option<Field>| {
        f.as_ref()
            .is_none_or(|f| matches!(f, Field::Constant { .. }))
    };
    let duty_b = b.as_ref().and_then(|b| b.duty.clone());
    let per_pixel = !(constant(&a.duty) && constant(&duty_b) && constant(&weight));
    // The grey samples of image fields, after the profiles: the device interpolates them.
    let grey_starts = [&a.duty, &duty_b, &weight].map(|f| match f {
        Some(Field::Image { grey, .. }) if per_pixel => {
            let start = data.len() as u32;
            data.extend(grey);
            start
        }
        _ => 0,
    });
    let origin = [0.0; 3];
    let kernels = match period {
        None => PhasorKernels::new(model),
        Some(p) => PhasorKernels::new_periodic(model, p)?,
    };
    let mut params = PhasorParams {
        three_d: u32::from(kernels.three_d()),
        output_kind: match model.output {
            PhasorOutput::Profiled => 0,
            PhasorOutput::Phase => 1,
            PhasorOutput::Intensity => 2,
            PhasorOutput::Gabor => 3,
        },
        per_pixel: u32::from(per_pixel),
        mean: model.mean,
        amplitude: model.amplitude,
        a_kind: a.kind,
        a_start: a.start,
        a_len: a.len,
        duty_a: unit_at(a.duty.as_ref(), origin),
        duty_b: unit_at(duty_b.as_ref(), origin),
        weight: unit_at(weight.as_ref(), origin),
        inv_side: (1.0 / kernels.side()) as f32,
        ..bytemuck::Zeroable::zeroed()
    };
    if let Some(b) = &b {
        (params.b_kind, params.b_start, params.b_len) = (b.kind, b.start, b.len);
        params.blend = 1;
    }
    let kernel = PhasorKernel {
        z: if kernels.three_d() { z } else { 0.0 },
        kernels,
        params,
        duty_a: a.duty,
        duty_b,
        weight,
        grey_starts,
        per_pixel,
        frequency: model.frequency.clone(),
        lambda: model.impulses_per_cell(),
        period,
        bin: None,
    };
    Ok((kernel, data))
}

impl GpuKind for PhasorNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "phasor",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["phasor_bin", "phasor_main"],
    });

    /// Periodic: the cells drawn on the host by `PhasorKernels::new_periodic` (fitted to the
    /// period and hashed modulo it, the CPU's), at positions reduced modulo the period.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (mut kernel, profile_data) = pack(self, z, period)?;
        kernel.bin = Some(OwnPass::new(context, "phasor", "phasor_bin")?);
        Shaded::boxed(
            context,
            kernel,
            &[Table::new("phasor profile", &profile_data)],
        )
    }
}

impl PhasorKernel {
    /// Cell side of the kernel grid, pixels.
    fn side(&self) -> f64 {
        self.kernels.side()
    }

    /// Cells in the box of a `width × height` tile at `scale` (for sizing tiles).
    fn box_cells(&self, width: usize, height: usize, scale: f64) -> f64 {
        let along = |n: usize| n as f64 * scale / self.side() + 4.0;
        along(width) * along(height) * if self.kernels.three_d() { 3.0 } else { 1.0 }
    }
}

impl ShaderKernel for PhasorKernel {
    const SHADER: &'static str = "phasor";
    const ENTRY_POINT: &'static str = "phasor_main";

    const SHAPE: &'static [&'static str] = &[
        "PHASOR_THREE_D",
        "PHASOR_OUTPUT_KIND",
        "PHASOR_PER_PIXEL",
        "PHASOR_A_KIND",
        "PHASOR_B_KIND",
        "PHASOR_BLEND",
    ];

    /// The cell box reads a displacement's range; varying profile fields and a minified
    /// tile's harmonic scale are read per displaced pixel on the host.
    fn displacement_read(&self) -> DisplacementRead {
        if self.per_pixel {
            DisplacementRead::Pixels
        } else {
            DisplacementRead::Range
        }
    }

    /// Dimension, output, per-pixel parameters, profiles and blend.
    fn shape(&self) -> Vec<u32> {
        let p = &self.params;
        vec![
            p.three_d,
            p.output_kind,
            p.per_pixel,
            p.a_kind,
            p.b_kind,
            p.blend,
        ]
    }

    /// Quarter-megapixel tiles: its kernel cells are drawn on the host per tile, so a render
    /// prepares many tiles in parallel.
    fn tile_pixels(&self) -> Option<usize> {
        Some(crate::kernel::HOST_TILE_PIXELS)
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<CellAxis>() as u64
    }

    /// The output or the displacement (2 values) and the per-pixel profile parameters
    /// (3 values, where the profile's fields vary).
    fn pixel_bytes(&self) -> u64 {
        16
    }

    /// The tile's box of kernel cells must fit one buffer, with room for a Poisson count well
    /// above its mean (`1.5λ + 4` impulses per cell).
    fn fit_tile(
        &self,
        window: &GpuWindow,
        tile: [usize; 2],
        limit: u64,
    ) -> Result<[usize; 2], GpuError> {
        let per_cell = (1.5 * self.lambda + 4.0) * size_of::<PhasorImpulse>() as f64;
        Ok(halve_tile_to_fit(tile, per_cell, limit, |w, h| {
            self.box_cells(w, h, window.scale)
        }))
    }

    /// Draws the tile's cell box and builds its tables. Displaced, the box covers every
    /// displaced pixel's cells (one more cell on each side than the f64 cells, for the shader's
    /// f32 relocation), from each pixel's displacement or from their range; with each pixel's,
    /// the profile parameters are read at the displaced positions, as the CPU reads them.
    ///
    /// # Errors
    /// Besides the tables' limits, [`GpuError::Validation`] for a displacement's range alone
    /// where the tables need each pixel's ([`ShaderKernel::displacement_read`], a minified
    /// tile's harmonic scale).
    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        limit: u64,
    ) -> Result<TileTables, GpuError> {
        let per_pixel_needed = self.per_pixel || tile.footprint().is_some();
        if per_pixel_needed && matches!(displacement, TileDisplacement::Within(_)) {
            return Err(GpuError::Validation(
                "phasor: varying fields or a minified tile need each pixel's displacement, \
                 not its range"
                    .to_owned(),
            ));
        }
        let pixels = displacement.pixels();
        let side = self.side();
        let (width, height) = (tile.width, tile.height);
        // The pixels' positions, reduced modulo the period of a periodic model.
        let column_x = periodic_columns(tile, self.period);
        let row_y = periodic_rows(tile, self.period);
        let axes = CellAxes::new(side, tile, self.period);
        let displaced = |i: usize, j: usize| -> [f64; 2] {
            match pixels {
                Some(d) => {
                    let k = 2 * (j * width + i);
                    [
                        column_x(i) + f64::from(d[k]),
                        row_y(j) + f64::from(d[k + 1]),
                    ]
                }
                None => [column_x(i), row_y(j)],
            }
        };
        // The cell range of the pixels; of displaced ones widened by one cell (f32 relocation).
        let [x_range, y_range] = axes.cell_range(tile, displacement)?.map(|r| {
            let widen = i32::from(displacement.is_some());
            r.map(|(lo, hi)| (lo.saturating_sub(widen), hi.saturating_add(widen)))
        });
        let (z_cell, z_offset, z_valid) = if self.kernels.three_d() {
            match locate_cell(self.z, side) {
                Some((k, u)) => (k, u, 1),
                None => (0, 0.0, 0),
            }
        } else {
            (0, 0.0, 1)
        };
        let mut params = PhasorParams {
            width: width as u32,
            height: height as u32,
            z_cell,
            z_offset,
            z_valid,
            filtered: u32::from(tile.footprint().is_some()),
            ..self.params
        };
        let mut cells: Vec<[u32; 2]> = Vec::new();
        let mut impulses: Vec<PhasorImpulse> = Vec::new();
        if let (Some((i_lo, i_hi)), Some((j_lo, j_hi))) = (x_range, y_range) {
            let (i0, j0) = (i_lo - 1, j_lo - 1);
            let (cols, rows_n) = ((i_hi + 1 - i0 + 1) as u32, (j_hi + 1 - j0 + 1) as u32);
            (params.box_i0, params.box_j0) = (i0, j0);
            (params.box_cols, params.box_rows) = (cols, rows_n);
            let layers: &[i32] = if self.kernels.three_d() {
                &[-1, 0, 1]
            } else {
                &[0]
            };
            // A strongly warped tile may reach far more cells than its own box: refuse before
            // drawing them rather than after.
            let box_bytes = size_of::<[u32; 2]>() as u64
                * u64::from(cols)
                * u64::from(rows_n)
                * layers.len() as u64;
            if box_bytes > limit {
                return Err(GpuError::LimitsExceeded {
                    what: "bytes of a tile's phasor cell table (a smaller tile, scale or warp \
                           strength)",
                    value: box_bytes,
                    limit,
                });
            }
            let mut drawn: Vec<Impulse> = Vec::new();
            for &sz in layers {
                for j in j0..j0 + rows_n as i32 {
                    for i in i0..i0 + cols as i32 {
                        self.kernels.draw_cell([i, j, z_cell + sz], &mut drawn);
                        cells.push([impulses.len() as u32, drawn.len() as u32]);
                        impulses.extend(drawn.iter().map(|imp| PhasorImpulse {
                            o_psi: [imp.o[0], imp.o[1], imp.o[2], imp.psi],
                            f: [imp.f[0], imp.f[1], imp.f[2], imp.sharp],
                        }));
                    }
                }
                let bytes = size_of_val(impulses.as_slice()) as u64;
                if bytes > limit {
                    return Err(GpuError::LimitsExceeded {
                        what: "bytes of a tile's phasor impulses (use a smaller tile or scale)",
                        value: bytes,
                        limit,
                    });
                }
            }
        }
        let mut pixel_params: Vec<f32> = Vec::new();
        let fields = [&self.duty_a, &self.duty_b, &self.weight];
        if self.per_pixel && pixels.is_none() {
            // Undisplaced pixels lie on a grid: the fields are read per pixel on the device
            // from records per column and per row, O(width + height) here.
            let xs: Vec<f64> = (0..width).map(&column_x).collect();
            let ys: Vec<f64> = (0..height).map(&row_y).collect();
            pixel_params = device_fields(fields, self.grey_starts, &xs, &ys, self.z);
            params.pixel_fields = 1;
        } else if self.per_pixel {
            pixel_params.reserve(3 * width * height);
            for j in 0..height {
                for i in 0..width {
                    let [x, y] = displaced(i, j);
                    let p = [x, y, self.z];
                    pixel_params.extend(fields.map(|f| unit_at(f.as_ref(), p)));
                }
            }
        }
        // A minified render's harmonic scale per pixel, `u = F(p)·s` rounded to f32 as the CPU
        // rounds it; an unused 0 when unfiltered.
        let harmonic_scale: Vec<f32> = match (tile.footprint(), pixels) {
            (Some(s), None) => {
                let grid =
                    FieldGrid::new(&self.frequency, (0..width).map(&column_x).collect(), self.z);
                let mut scale = vec![0.0; width * height];
                for (j, row) in scale.chunks_exact_mut(width).enumerate() {
                    grid.row(row_y(j), |i, f| row[i] = (f * s) as f32);
                }
                scale
            }
            (Some(s), Some(_)) => (0..height)
                .flat_map(|j| (0..width).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let [x, y] = displaced(i, j);
                    (self.frequency.at(x, y, self.z) * s) as f32
                })
                .collect(),
            (None, _) => vec![0.0],
        };
        // The reach masks, written on the device by `phasor_bin` before the tile's dispatch:
        // for an undisplaced tile (a displaced one's pixels move between blocks).
        let most = cells.iter().map(|c| c[1]).max().unwrap_or(0);
        let binned = match &self.bin {
            Some(bin) if !displacement.is_some() && !cells.is_empty() => {
                bin_layout(&mut params, &bin.gpu, tile.scale, side, most, limit)
            }
            _ => None,
        };
        let bins = Table::left_to_pass("phasor bins", binned);
        Ok(TileTables::new(
            &params,
            vec![
                Table::new("phasor cells", &cells),
                Table::new("phasor impulses", &impulses),
                Table::new("phasor pixel params", &pixel_params),
                Table::new("phasor harmonic scale", &harmonic_scale),
            ]
            .into_iter()
            .chain(std::iter::once(bins))
            .chain(axes.tables(["phasor columns", "phasor rows"]))
            .collect(),
        )
        .with_pass(binned.map(|_| &params)))
    }

    fn own_pass(&self) -> Option<(&OwnPass, &'static OwnPassLayout)> {
        self.bin.as_deref().map(|pass| (pass, &BIN_PASS))
    }
}

/// A linear field's term as a column's or row's record: `(·, ·, lo, hi)` with `hi = f32(v)`
/// and `lo = f32(v − hi)`, so that the shader's sum of two terms (a two-float addition) is
/// `v_column + v_row` to far below an f32 ulp, whatever their size far from the origin.
fn split(v: f64) -> [f32; 4] {
    let hi = v as f32;
    [0.0, 0.0, (v - f64::from(hi)) as f32, hi]
}

/// Field `field`'s record of a column (`axis` 0, at `x = c`) or a row (1, at `y = c`) on
/// the plane `z`, for [`device_fields`].
fn field_record(field: &Field, c: f64, axis: usize, z: f64) -> [f32; 4] {
    match field {
        Field::Constant { value } if axis == 0 => [0.0, 0.0, 0.0, *value],
        Field::Constant { .. } => [0.0; 4],
        Field::Linear { value, gradient } => {
            let [gx, gy, gz] = gradient.map(f64::from);
            split(if axis == 0 {
                (f64::from(*value) + gx * c) + gz * z
            } else {
                gy * c
            })
        }
        Field::Image { width, .. } => {
            let (i0, i1, t) = field.image_tap(c, axis).unwrap_or((0, 0, 0.0));
            let stride = if axis == 0 { 1 } else { *width };
            [(i0 * stride) as f32, (i1 * stride) as f32, t as f32, 0.0]
        }
    }
}

/// Words of one field's header in the pixel-parameter table of [`device_fields`].
const FIELD_HEADER: usize = 4;
/// Words of one column's or row's record in it.
const FIELD_RECORD: usize = 4;

/// The pixel-parameter table of an undisplaced tile whose profile fields vary, for
/// `phasor.wgsl`'s `pixel_field` (a grid of columns `xs` and rows `ys` on the plane `z`):
///
/// - per field (duty A, duty B, blend weight) a header `(kind, grey start, min, max − min)`,
///   kind 0 absent (the uniform's constant), 1 a sum of a column's and a row's term, 2 an image;
/// - per field and column `(i0, i1, t, ·)` (an image) or `(·, ·, lo, hi)` (a linear field),
///   then per field and row `(j0·w, j1·w, t, ·)` or `(·, ·, lo, hi)`.
///
/// An image field's value is the bilinear interpolation of its grey samples (at its start
/// in the profile data) between the taps the CPU interpolates (`Field::image_tap`), mapped to
/// `min + g·(max − min)`, in f32 where the CPU computes in f64. A linear field's is the sum
/// of a column's term `value + g_x·x + g_z·z` and a row's `g_y·y`, each two f32 ([`split`])
/// added as two-float numbers, so within an ulp of the CPU's f64 value rounded (a constant's
/// column term is its value, its row term 0). Either is then clamped to `[0, 1]`. The
/// cross-check bounds the difference (`spectex_crosscheck::tolerance::phasor`).
fn device_fields(
    fields: [&Option<Field>; 3],
    grey_starts: [u32; 3],
    xs: &[f64],
    ys: &[f64],
    z: f64,
) -> Vec<f32> {
    let (w, h) = (xs.len(), ys.len());
    let mut table = vec![0.0f32; 3 * (FIELD_HEADER + FIELD_RECORD * (w + h))];
    let (columns, rows) = (3 * FIELD_HEADER, 3 * (FIELD_HEADER + FIELD_RECORD * w));
    for (f, field) in fields.into_iter().enumerate() {
        let Some(field) = field else { continue };
        let header = &mut table[FIELD_HEADER * f..FIELD_HEADER * (f + 1)];
        header[0] = 1.0;
        if let Field::Image { min, max, .. } = field {
            let span = (f64::from(*max) - f64::from(*min)) as f32;
            header.copy_from_slice(&[2.0, grey_starts[f] as f32, *min, span]);
        }
        for (i, &x) in xs.iter().enumerate() {
            let at = columns + FIELD_RECORD * (f * w + i);
            table[at..at + FIELD_RECORD].copy_from_slice(&field_record(field, x, 0, z));
        }
        for (j, &y) in ys.iter().enumerate() {
            let at = rows + FIELD_RECORD * (f * h + j);
            table[at..at + FIELD_RECORD].copy_from_slice(&field_record(field, y, 1, z));
        }
    }
    table
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

/// The unit direction at `angle` radians as `PhasorKernels` rounds it (`planar`).
fn planar(angle: f64) -> [f32; 3] {
    let t = (angle / std::f64::consts::TAU).rem_euclid(1.0) as f32;
    [cos_turns(t), sin_turns(t), 0.0]
}

/// Whether a field varies over the plane (its range is more than one value).
fn varies(field: &Field) -> bool {
    let (lo, hi) = field.range();
    lo != hi
}

/// The WGSL function `phasor_export_<name>(n, r)`: `field` at the pixel position `n + r`
/// (header of the glue of `phasor.wgsl`), an image's grey samples appended to `data` and its
/// repeat's lattices to `lattices` ([`image_samples`]).
fn field_function(
    name: &str,
    field: &Field,
    data: &mut Vec<f32>,
    lattices: &mut Vec<f64>,
) -> String {
    let signature = format!("fn phasor_export_{name}(n: vec2<i32>, r: vec2<f32>) -> f32");
    let body = match field {
        Field::Constant { value } => format!("return {};", float(*value)),
        Field::Linear { value, gradient } => {
            let (gx, gy) = (float(gradient[0]), float(gradient[1]));
            format!(
                "return (({} + {gx} * f32(n.x)) + {gx} * r.x) + ({gy} * f32(n.y) + {gy} * r.y);",
                float(*value)
            )
        }
        Field::Image {
            width,
            height,
            grey,
            pixel_size,
            min,
            max,
        } => {
            let (sample, args) =
                image_samples([*width, *height], grey, *pixel_size, data, lattices);
            let span = (f64::from(*max) - f64::from(*min)) as f32;
            format!(
                "{sample}\n    let g = phasor_export_bilinear({args});\n    return {} + g * {};",
                float(*min),
                float(span)
            )
        }
    };
    format!("{signature} {{\n    {body}\n}}\n")
}

/// The WGSL function `phasor_export_steer(n, r)`: a gradient orientation's central differences
/// of `image`'s grey level at `n + r` (`phasor_export_differences`, which interpolates the
/// samples' own differences, [`sample_differences`]), or 0 where `image` is not an image (the
/// CPU's `gradient_angle` is then none: the offset alone).
fn steer_function(image: &Field, data: &mut Vec<f32>, lattices: &mut Vec<f64>) -> String {
    let body = if let Field::Image {
        width,
        height,
        grey,
        pixel_size,
        ..
    } = image
    {
        let pairs = sample_differences(grey, *width, *height);
        let (sample, args) = image_samples([*width, *height], &pairs, *pixel_size, data, lattices);
        format!("{sample}\n    return phasor_export_differences({args});")
    } else {
        "return vec2<f32>(0.0f);".to_owned()
    };
    format!("fn phasor_export_steer(n: vec2<i32>, r: vec2<f32>) -> vec2<f32> {{\n    {body}\n}}\n")
}

/// The central differences of `grey` (`w × h` samples, row-major, periodic) at each sample,
/// `(s[i+1, j] − s[i−1, j], s[i, j+1] − s[i, j−1])`, in f64 rounded once: `w × h` pairs,
/// row-major.
fn sample_differences(grey: &[f32], w: usize, h: usize) -> Vec<f32> {
    let s = |i: usize, j: usize| f64::from(grey[j * w + i]);
    let mut pairs = Vec::with_capacity(2 * w * h);
    for j in 0..h {
        let (up, down) = ((j + 1) % h, (j + h - 1) % h);
        for i in 0..w {
            let (right, left) = ((i + 1) % w, (i + w - 1) % w);
            pairs.push((s(right, j) - s(left, j)) as f32);
            pairs.push((s(i, up) - s(i, down)) as f32);
        }
    }
    pairs
}

/// An image field's `samples` (`size` = width, height: its grey levels, or their
/// [`sample_differences`]) appended to `data` and its repeat's lattices to `lattices`: the WGSL lines that form the position `(x, y)` = `n + r`
/// from `n`'s remainders on those lattices (the private `phasor_export_rem<l>_at` that
/// [`locate_fields`] declares and sets once per pixel: every caller passes the pixel's `n`),
/// and the arguments `start, w, h, u, v` of a sampler at sample coordinates `x/pixel_size − ½`
/// (the CPU's).
fn image_samples(
    size: [usize; 2],
    samples: &[f32],
    pixel_size: f32,
    data: &mut Vec<f32>,
    lattices: &mut Vec<f64>,
) -> (String, String) {
    let [width, height] = size;
    let start = data.len();
    data.extend(samples);
    let side = f64::from(pixel_size);
    let lx = lattices.len();
    lattices.push(width as f64 * side);
    lattices.push(height as f64 * side);
    let inv = float((1.0 / side) as f32);
    (
        format!(
            "let x = phasor_export_rem{lx}_at + r.x;\n    \
             let y = phasor_export_rem{}_at + r.y;",
            lx + 1
        ),
        format!("{start}u, {width}i, {height}i, x * {inv} - 0.5f, y * {inv} - 0.5f"),
    )
}

/// The declarations of `phasor_export_rem<l>_at` for the image fields' repeat lattices (from
/// lattice 2 on: every lattice after the kernel and direction grids), and
/// `phasor_export_locate_fields(n)`, which `phasor_sample_cell` calls first: it splits the
/// pixel's integer position on each of them once, where the fields, read per impulse and per
/// steering sample, would otherwise split the same `n` every time (a 32-step table loop each).
fn locate_fields(lattices: usize) -> String {
    let mut out = String::new();
    let mut body = String::new();
    for l in 2..lattices {
        let axis = if l % 2 == 0 { "x" } else { "y" };
        let _ = writeln!(
            out,
            "/// The pixel's `n.{axis}` split on lattice {l}: its remainder (set per pixel).\n\
             var<private> phasor_export_rem{l}_at: f32;"
        );
        let _ = write!(
            body,
            "\n    phasor_export_rem{l}_at = export_split(n.{axis}, {l}u).rem;"
        );
    }
    let _ = writeln!(
        out,
        "/// Splits the pixel's integer position `n` on the image fields' lattices, once per pixel.\n\
         fn phasor_export_locate_fields(n: vec2<i32>) {{{body}\n}}"
    );
    out
}

impl ExportKind for PhasorNoise {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, mut profile) = pack(self, z, None)?;
        let side = self.kernel_radius();
        let lambda = self.impulses_per_cell();
        let three_d = self.dimensions == 3;
        let graded = varies(&self.bandwidth);
        let varying_f = varies(&self.frequency);
        let duty = |p: &Profile| match p {
            Profile::Square { duty } => Some(duty.clone()),
            _ => None,
        };
        let (duty_a, duty_b, weight) = match &self.profile {
            Profile::Blend { a, b, weight } => (duty(a), duty(b), Some(weight.clone())),
            other => (duty(other), None, None),
        };
        let varying_angle =
            matches!(&self.orientation, PhasorOrientation::Aligned { angle } if varies(angle));
        let steered = matches!(
            self.orientation,
            PhasorOrientation::Gradient { .. } | PhasorOrientation::Coherent { .. }
        );
        if three_d && (graded || varying_f || varying_angle || steered || kernel.per_pixel) {
            return Err(GpuError::Unsupported {
                kind: PhasorNoise::NAME,
                feature: "WGSL export of a 3D model with a varying field or a gradient or \
                          coherent orientation (spectex export evaluates 2D fields)"
                    .into(),
            });
        }
        // Lattice 0: the kernel grid; 1: the coherent direction grid (or a copy of 0); then
        // the image fields' repeats.
        let mut lattices = vec![side];
        // The directions as `PhasorKernels::new` and `direction` make them.
        let mut coherent = (1.0f32, 1u32, 0.0f32, 1.0f32, side);
        // A gradient orientation's offset, as the cosine and sine it turns directions by.
        let mut rotation = (1.0f32, 0.0f32);
        let (mode, a, b) = match &self.orientation {
            PhasorOrientation::Aligned { angle } if !varies(angle) => {
                let a = planar(angle.range().0);
                (0u32, a, a)
            }
            PhasorOrientation::Aligned { .. } => (3, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            PhasorOrientation::TwoLobes { angle_a, angle_b } => {
                let turn = |a: f32| (f64::from(a) / std::f64::consts::TAU) as f32;
                let (ta, tb) = (turn(*angle_a), turn(*angle_b));
                let a = [cos_turns(ta), sin_turns(ta), 0.0];
                let mut b = [cos_turns(tb), sin_turns(tb), 0.0];
                if a[0] * b[0] + a[1] * b[1] < 0.0 {
                    b = [-b[0], -b[1], 0.0];
                }
                (1, a, b)
            }
            PhasorOrientation::Isotropic => (2, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            PhasorOrientation::Gradient { offset, .. } => {
                let o = f64::from(*offset);
                rotation = (o.cos() as f32, o.sin() as f32);
                (4, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            }
            PhasorOrientation::Coherent {
                spread,
                bandwidth_ratio,
            } => {
                // `PhasorKernels::new`'s direction grid: side r/ratio, the same density.
                let spread_turns = (f64::from(*spread) / std::f64::consts::TAU) as f32;
                coherent = (
                    (-lambda).exp() as f32,
                    (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32,
                    spread_turns,
                    cos_turns(spread_turns),
                    side / f64::from(*bandwidth_ratio),
                );
                (5, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            }
        };
        lattices.push(coherent.4);
        let mut functions = String::new();
        let constant = Field::constant(0.0);
        for (name, field) in [
            ("bandwidth", &self.bandwidth),
            ("frequency_field", &self.frequency),
            (
                "angle",
                match &self.orientation {
                    PhasorOrientation::Aligned { angle } => angle,
                    _ => &constant,
                },
            ),
            ("duty_a", duty_a.as_ref().unwrap_or(&constant)),
            ("duty_b", duty_b.as_ref().unwrap_or(&constant)),
            ("weight", weight.as_ref().unwrap_or(&constant)),
        ] {
            // A constant field's function is never called (the glue reads the constants
            // then): it returns the value all the same.
            functions.push_str(&field_function(name, field, &mut profile, &mut lattices));
        }
        let steer = match &self.orientation {
            PhasorOrientation::Gradient { image, .. } => image,
            _ => &constant,
        };
        functions.push_str(&steer_function(steer, &mut profile, &mut lattices));
        let (b_min, b_max) = self.bandwidth_range();
        // `PhasorKernels`' grid and frequency magnitude (`F.clamp(0, ½)·r` rounded once).
        let threshold = (-lambda).exp() as f32;
        let cap = (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32;
        let frequency = self.frequency.range().0;
        let fr = (frequency.clamp(0.0, 0.5) * side) as f32;
        let vec3 = |d: [f32; 3]| {
            format!(
                "vec3<f32>({}, {}, {})",
                float(fr * d[0]),
                float(fr * d[1]),
                float(fr * d[2])
            )
        };
        let unit = |d: [f32; 3]| {
            format!(
                "vec3<f32>({}, {}, {})",
                float(d[0]),
                float(d[1]),
                float(d[2])
            )
        };
        functions.push_str(&locate_fields(lattices.len()));
        let constants = format!(
            "const phasor_export_seed: u32 = {}u;\n\
             const phasor_export_threshold: f32 = {};\n\
             const phasor_export_cap: u32 = {cap}u;\n\
             const phasor_export_mode: u32 = {mode}u;\n\
             const phasor_export_fr: f32 = {};\n\
             const phasor_export_f_a: vec3<f32> = {};\n\
             const phasor_export_f_b: vec3<f32> = {};\n\
             const phasor_export_u_a: vec3<f32> = {};\n\
             const phasor_export_u_b: vec3<f32> = {};\n\
             const phasor_export_graded: u32 = {}u;\n\
             const phasor_export_b_min: f32 = {};\n\
             const phasor_export_b_max: f32 = {};\n\
             const phasor_export_varying_f: u32 = {}u;\n\
             const phasor_export_side: f32 = {};\n\
             const phasor_export_offset_cos: f32 = {};\n\
             const phasor_export_offset_sin: f32 = {};\n\
             const phasor_export_dir_threshold: f32 = {};\n\
             const phasor_export_dir_cap: u32 = {}u;\n\
             const phasor_export_spread_turns: f32 = {};\n\
             const phasor_export_cap_cos: f32 = {};\n\
             const phasor_export_per_pixel: u32 = {}u;\n\
             {functions}",
            self.seed,
            float(threshold),
            float(fr),
            vec3(a),
            vec3(b),
            unit(a),
            unit(b),
            u32::from(graded),
            float(b_min as f32),
            float(b_max as f32),
            u32::from(varying_f),
            float(side as f32),
            float(rotation.0),
            float(rotation.1),
            float(coherent.0),
            coherent.1,
            float(coherent.2),
            float(coherent.3),
            u32::from(kernel.per_pixel),
        );
        debug_assert_eq!(DIRECTION_LAYER, 1, "the glue of phasor.wgsl hashes layer 1");
        // The kernel grid is the export's lattice 0 (the glue of phasor.wgsl).
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("phasor profile", &profile)],
            lattices,
            "phasor",
        )?
        .with_constants(constants))
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    pub fn records_match_the_wgsl() {
        assert_matches_wgsl::<PhasorParams>("phasor", "PhasorParams");
        assert_matches_wgsl::<PhasorImpulse>("phasor", "PhasorImpulse");
    }

    /// The masks `phasor_bin` writes drop only impulses that add nothing: a binned tile
    /// renders the bits of the same tile visited in full, for a graded bandwidth (whose
    /// sharper kernels the masks cull most), a 3D model, a magnified, a minified and a far
    /// window, tiles whose sides are not multiples of the block, and a periodic model's tile
    /// across its period (whose wrapped blocks fall back to full visits). Each tile must
    /// really be binned (its one pass prepared). A bound of 0.9 in place of
    /// `PHASOR_CELL_REACH2`, or no fallback for wrapped blocks, fails it.
    pub fn binned_masks_render_the_unbinned_bits() {
        use crate::layout::check::context_or_skip;
        use crate::pipeline::assert_own_pass_keeps_bits;
        let Some(context) = context_or_skip("binned_masks_render_the_unbinned_bits") else {
            return;
        };
        let mut graded = spectex_model::fixtures::phasor_pwm(2, PhasorOrientation::Isotropic);
        graded.bandwidth = Field::Image {
            width: 2,
            height: 2,
            grey: vec![0.0, 1.0, 0.5, 0.25],
            pixel_size: 40.0,
            min: 0.02,
            max: 0.04,
        };
        let three_d = spectex_model::fixtures::phasor_pwm(3, PhasorOrientation::Isotropic);
        let period = Period::new(160, 160).unwrap();
        let cases = [
            (
                &graded,
                None,
                GpuWindow::new(37, 21).at([1.0e6, -3.0e5], 1.0),
            ),
            (
                &graded,
                None,
                GpuWindow::new(64, 48).at([-40.5, 7.25], 0.37),
            ),
            (&graded, None, GpuWindow::new(19, 13).at([3.0, 5.0], 3.5)),
            (
                &three_d,
                None,
                GpuWindow::new(40, 24).at([-2.0e3, 55.5], 1.0),
            ),
            (
                &graded,
                Some(period),
                GpuWindow::new(48, 40).at([130.0, 150.0], 1.0),
            ),
        ];
        for (model, period, tile) in cases {
            let (kernel, data) = pack(model, 12.5, period).unwrap();
            let mut binned = kernel.clone();
            binned.bin = Some(OwnPass::new(&context, "phasor", "phasor_bin").unwrap());
            let tables = [Table::new("phasor profile", &data)];
            assert_own_pass_keeps_bits(&context, (binned, kernel), &tables, &tile);
        }
    }

    /// A nested blend is refused before any device work, naming the kind as model files do.
    pub fn nested_blends_are_unsupported_in_phasor_models() {
        let mut model = spectex_model::fixtures::phasor_pwm(2, PhasorOrientation::Isotropic);
        let blend = |a: Profile| Profile::Blend {
            a: Box::new(a),
            b: Box::new(Profile::Sine),
            weight: Field::constant(0.5),
        };
        model.profile = blend(blend(Profile::Sine));
        match pack(&model, 0.0, None) {
            Err(e @ GpuError::Unsupported { kind: "phasor", .. }) => assert_eq!(
                e.to_string(),
                "the GPU evaluator does not support profiles with nested blends (one blend of \
                 two profiles is supported) in phasor models"
            ),
            other => panic!("expected Unsupported for a phasor model, got {other:?}"),
        }
    }
}
