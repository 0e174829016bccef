//! Host side of `shaders/phasor.wgsl`: the model's profile flattened into parameters and a data
//! table, and per tile the box of kernel cells its pixels reach (drawn by
//! `spectex_model::phasor_kernels`, the code the CPU evaluator uses) and, where the profile's
//! fields vary in space, each pixel's duty cycles and blend weight (f64, as the CPU computes them).

use spectex_model::grid::locate_cell;
use spectex_model::phasor_kernels::{Impulse, PhasorKernels};
use spectex_model::{Field, PhasorNoise, PhasorOutput, Profile};

use crate::GpuError;
use crate::GpuWindow;
use crate::pack::{columns, gabor_axis, rows};

/// Words of `PhasorParams`.
pub(crate) const PARAM_WORDS: usize = 28;
/// Bytes of one impulse record (two `vec4<f32>`).
pub(crate) const IMPULSE_BYTES: u64 = 32;

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
pub(crate) struct PhasorPack {
    kernels: PhasorKernels,
    /// The plane of a 3D model.
    z: f64,
    params: [u32; PARAM_WORDS],
    /// Sampled-profile values and harmonic triples, f32 bits.
    pub profile_data: Vec<u32>,
    duty_a: Option<Field>,
    duty_b: Option<Field>,
    weight: Option<Field>,
    per_pixel: bool,
    /// Mean impulses per cell, for sizing tiles.
    pub lambda: f64,
}

fn leaf(profile: &Profile, data: &mut Vec<u32>) -> Result<Leaf, GpuError> {
    let start = data.len() as u32;
    let (kind, len, duty) = match profile {
        Profile::Sine => (0, 0, None),
        Profile::Square { duty } => (1, 0, Some(duty.clone())),
        Profile::Triangle => (2, 0, None),
        Profile::Sawtooth => (3, 0, None),
        Profile::Samples { values } => {
            data.extend(values.iter().map(|v| v.to_bits()));
            (4, values.len() as u32, None)
        }
        Profile::Harmonics { terms } => {
            for h in terms {
                // The CPU's `h.k as f32` and `(phase / 2π) as f32`.
                let shift = (f64::from(h.phase) / std::f64::consts::TAU) as f32;
                data.extend([(h.k as f32).to_bits(), h.weight.to_bits(), shift.to_bits()]);
            }
            (5, terms.len() as u32, None)
        }
        Profile::Blend { .. } => {
            return Err(GpuError::Unsupported {
                kind: "phasor profiles with nested blends (one blend of two profiles is supported)"
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

/// Packs a validated phasor model for the plane `z`.
pub(crate) fn pack_phasor(model: &PhasorNoise, z: f64) -> Result<PhasorPack, GpuError> {
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
    let origin = [0.0; 3];
    let kernels = PhasorKernels::new(model);
    let mut params = [0u32; PARAM_WORDS];
    params[2] = u32::from(kernels.three_d());
    params[3] = match model.output {
        PhasorOutput::Profiled => 0,
        PhasorOutput::Phase => 1,
        PhasorOutput::Intensity => 2,
        PhasorOutput::Gabor => 3,
    };
    params[11] = u32::from(per_pixel);
    params[12] = model.mean.to_bits();
    params[13] = model.amplitude.to_bits();
    params[14..17].copy_from_slice(&[a.kind, a.start, a.len]);
    if let Some(b) = &b {
        params[17..20].copy_from_slice(&[b.kind, b.start, b.len]);
        params[20] = 1;
    }
    params[21] = unit_at(a.duty.as_ref(), origin).to_bits();
    params[22] = unit_at(duty_b.as_ref(), origin).to_bits();
    params[23] = unit_at(weight.as_ref(), origin).to_bits();
    params[24] = ((1.0 / kernels.side()) as f32).to_bits();
    if data.is_empty() {
        data.push(0);
    }
    Ok(PhasorPack {
        z: if kernels.three_d() { z } else { 0.0 },
        kernels,
        params,
        profile_data: data,
        duty_a: a.duty,
        duty_b,
        weight,
        per_pixel,
        lambda: model.impulses_per_cell(),
    })
}

/// The buffers of one tile.
pub(crate) struct PhasorTile {
    pub params: Vec<u32>,
    pub cells: Vec<u32>,
    pub impulses: Vec<u32>,
    pub pixel_params: Vec<u32>,
    pub columns: Vec<u32>,
    pub rows: Vec<u32>,
}

impl PhasorPack {
    /// Cell side of the kernel grid, pixels.
    pub fn side(&self) -> f64 {
        self.kernels.side()
    }

    /// Cells in the box of a `width × height` tile at `scale` (for sizing tiles).
    pub fn box_cells(&self, width: usize, height: usize, scale: f64) -> f64 {
        let along = |n: usize| n as f64 * scale / self.side() + 4.0;
        along(width) * along(height) * if self.kernels.three_d() { 3.0 } else { 1.0 }
    }

    /// Draws the tile's cell box and builds its tables; `limit` bounds one storage buffer.
    /// With a per-pixel `displacement` (pixels, `(dx, dy)` interleaved, row-major), the box
    /// covers every displaced pixel's cells (one more cell on each side than the f64 cells, for
    /// the shader's f32 relocation) and the profile parameters are read at the displaced
    /// positions, as the CPU reads them.
    pub fn tile(
        &self,
        tile: &GpuWindow,
        limit: u64,
        displacement: Option<&[f32]>,
    ) -> Result<PhasorTile, GpuError> {
        let side = self.side();
        let (width, height) = (tile.width, tile.height);
        let columns = gabor_axis(side, width, columns(tile));
        let rows = gabor_axis(side, height, rows(tile));
        let range = |words: &[u32]| {
            words
                .chunks_exact(3)
                .filter(|w| w[2] == 1)
                .map(|w| w[0] as i32)
                .fold(None, |acc: Option<(i32, i32)>, c| {
                    Some(acc.map_or((c, c), |(lo, hi)| (lo.min(c), hi.max(c))))
                })
        };
        let displaced = |i: usize, j: usize| -> [f64; 2] {
            match displacement {
                Some(d) => {
                    let k = 2 * (j * width + i);
                    [tile.x(i) + f64::from(d[k]), tile.y(j) + f64::from(d[k + 1])]
                }
                None => [tile.x(i), tile.y(j)],
            }
        };
        // The cell range of the displaced pixels, widened by one cell (f32 relocation).
        let displaced_range = || {
            let mut range: [Option<(i32, i32)>; 2] = [None, None];
            for j in 0..height {
                for i in 0..width {
                    for (axis, &p) in displaced(i, j).iter().enumerate() {
                        if let Some((c, _)) = locate_cell(p, side) {
                            let (lo, hi) = range[axis].unwrap_or((c, c));
                            range[axis] = Some((lo.min(c), hi.max(c)));
                        }
                    }
                }
            }
            range.map(|r| r.map(|(lo, hi)| (lo.saturating_sub(1), hi.saturating_add(1))))
        };
        let [x_range, y_range] = match displacement {
            Some(_) => displaced_range(),
            None => [range(&columns), range(&rows)],
        };
        let (z_cell, z_offset, z_valid) = if self.kernels.three_d() {
            match locate_cell(self.z, side) {
                Some((k, u)) => (k, u, 1),
                None => (0, 0.0, 0),
            }
        } else {
            (0, 0.0, 1)
        };
        let mut params = self.params;
        params[0] = width as u32;
        params[1] = height as u32;
        params[8] = z_cell as u32;
        params[9] = z_offset.to_bits();
        params[10] = z_valid;
        let mut cells = Vec::new();
        let mut impulses = Vec::new();
        if let (Some((i_lo, i_hi)), Some((j_lo, j_hi))) = (x_range, y_range) {
            let (i0, j0) = (i_lo - 1, j_lo - 1);
            let (cols, rows_n) = ((i_hi + 1 - i0 + 1) as u32, (j_hi + 1 - j0 + 1) as u32);
            params[4] = i0 as u32;
            params[5] = j0 as u32;
            params[6] = cols;
            params[7] = rows_n;
            let layers: &[i32] = if self.kernels.three_d() {
                &[-1, 0, 1]
            } else {
                &[0]
            };
            // A strongly warped tile may reach far more cells than its own box: refuse before
            // drawing them rather than after.
            let box_bytes = 8 * u64::from(cols) * u64::from(rows_n) * layers.len() as u64;
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
                        cells.extend([(impulses.len() / 8) as u32, drawn.len() as u32]);
                        for imp in &drawn {
                            impulses.extend(
                                [imp.o[0], imp.o[1], imp.o[2], imp.psi]
                                    .iter()
                                    .chain(&[imp.f[0], imp.f[1], imp.f[2], imp.sharp])
                                    .map(|v| v.to_bits()),
                            );
                        }
                    }
                }
                if 4 * impulses.len() as u64 > limit {
                    return Err(GpuError::LimitsExceeded {
                        what: "bytes of a tile's phasor impulses (use a smaller tile or scale)",
                        value: 4 * impulses.len() as u64,
                        limit,
                    });
                }
            }
        }
        let mut pixel_params = Vec::new();
        if self.per_pixel {
            pixel_params.reserve(3 * width * height);
            for j in 0..height {
                for i in 0..width {
                    let [x, y] = displaced(i, j);
                    let p = [x, y, self.z];
                    pixel_params.extend([
                        unit_at(self.duty_a.as_ref(), p).to_bits(),
                        unit_at(self.duty_b.as_ref(), p).to_bits(),
                        unit_at(self.weight.as_ref(), p).to_bits(),
                    ]);
                }
            }
        }
        Ok(PhasorTile {
            params: params.to_vec(),
            cells,
            impulses,
            pixel_params,
            columns,
            rows,
        })
    }
}
