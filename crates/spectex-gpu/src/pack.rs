//! Packing on the host: a model into the words of its storage buffers, and a tile's columns and
//! rows into the per-axis tables through which the shaders receive positions (f64 work done here,
//! so the device needs only f32 and integers; see the precision notes in `shaders/lrp.wgsl`).

use spectex_model::wavelet::{Band, locate_sample};
use spectex_model::{GaborNoise, LrpNoise, Orientation, WaveletNoise};

use crate::GpuWindow;

/// Bytes of one `LatticeAxis` entry of `lrp.wgsl` (cell + 4 offsets).
pub(crate) const LRP_AXIS_BYTES: u64 = 20;
/// Bytes of one `GaborAxis` entry of `gabor.wgsl` (cell, offset, valid).
pub(crate) const GABOR_AXIS_BYTES: u64 = 12;

/// An LRP model as buffer words, plus what the host needs per tile.
#[derive(Debug, Clone)]
pub(crate) struct LrpPack {
    pub seed: u32,
    pub mean: f32,
    /// `Δ_s` in f64 (from the model's f32), per stratum.
    pub deltas: Vec<f64>,
    /// `LrpStratum` records: inv_delta2, amplitude, table_first, cosines, delta.
    pub strata: Vec<u32>,
    /// `(f_x, f_y)` bits of every table, concatenated.
    pub frequencies: Vec<u32>,
    /// `(start, len)` of every sub-stratum's table, strata in order.
    pub tables: Vec<u32>,
}

/// Packs a validated LRP model.
pub(crate) fn pack_lrp(model: &LrpNoise) -> LrpPack {
    let mut pack = LrpPack {
        seed: model.seed,
        mean: model.mean,
        deltas: Vec::with_capacity(model.strata.len()),
        strata: Vec::with_capacity(5 * model.strata.len()),
        frequencies: Vec::new(),
        tables: Vec::new(),
    };
    for stratum in &model.strata {
        let delta = f64::from(stratum.window_width);
        pack.deltas.push(delta);
        // The CPU's `(1.0 / (delta * delta)) as f32`.
        pack.strata.push(((1.0 / (delta * delta)) as f32).to_bits());
        pack.strata.push(stratum.amplitude.to_bits());
        pack.strata.push((pack.tables.len() / 2) as u32);
        pack.strata.push(stratum.sub_strata.len() as u32);
        pack.strata.push(stratum.window_width.to_bits());
        for table in &stratum.sub_strata {
            pack.tables.push((pack.frequencies.len() / 2) as u32);
            pack.tables.push(table.len() as u32);
            for f in table {
                pack.frequencies.push(f[0].to_bits());
                pack.frequencies.push(f[1].to_bits());
            }
        }
    }
    pack
}

/// `LatticeAxis` records for `count` positions `position(i)`, stratum-major: for stratum `s` and
/// position `i`, the lattice cell `c = ⌊x/Δ⌋` (wrapped to i32 as the CPU does) and
/// `f32(x − (c + k − 1)·Δ)` for `k = 0..3`.
pub(crate) fn lrp_axis(deltas: &[f64], count: usize, position: impl Fn(usize) -> f64) -> Vec<u32> {
    let mut words = Vec::with_capacity(deltas.len() * count * 5);
    for &delta in deltas {
        for i in 0..count {
            let x = position(i);
            let cell = (x / delta).floor() as i64;
            words.push(cell as i32 as u32);
            for k in -1..=2 {
                words.push(((x - (cell + k) as f64 * delta) as f32).to_bits());
            }
        }
    }
    words
}

/// The Poisson count's renormalisation chunk (the CPU's `POISSON_CHUNK`).
const POISSON_CHUNK: f64 = 64.0;

/// A Gabor model as the words of `GaborParams` (width and height left 0) and its grid size.
#[derive(Debug, Clone)]
pub(crate) struct GaborPack {
    /// Kernel radius `r` = grid cell side, pixels.
    pub radius: f64,
    /// The 16 words of `GaborParams`; words 0 and 1 are set per tile.
    pub params: [u32; 16],
}

/// Packs a validated Gabor model: the constants the CPU's `GaborEvaluator::new` computes, by the
/// same f64 expressions.
pub(crate) fn pack_gabor(model: &GaborNoise) -> GaborPack {
    let radius = model.kernel_radius();
    let lambda = model.impulses_per_cell();
    let chunks = (lambda / POISSON_CHUNK).floor();
    let rest = lambda - chunks * POISSON_CHUNK;
    let frequency_cells = f64::from(model.frequency) * radius;
    let (kind, dir_a, dir_b) = match model.orientation {
        Orientation::Anisotropic { angle } => {
            let (sin, cos) = f64::from(angle).sin_cos();
            (
                0u32,
                (frequency_cells * cos) as f32,
                (frequency_cells * sin) as f32,
            )
        }
        Orientation::Isotropic { min, max } => {
            let turn = std::f64::consts::TAU;
            (
                1u32,
                (f64::from(min) / turn).rem_euclid(1.0) as f32,
                ((f64::from(max) - f64::from(min)) / turn) as f32,
            )
        }
    };
    let params = [
        0,
        0,
        model.seed,
        kind,
        model.mean.to_bits(),
        model.amplitude.to_bits(),
        ((-rest).exp() as f32).to_bits(),
        chunks as u32,
        (POISSON_CHUNK.exp() as f32).to_bits(),
        ((-POISSON_CHUNK).exp() as f32).to_bits(),
        (4.0 * lambda + 32.0).floor().max(1.0) as u32,
        (frequency_cells as f32).to_bits(),
        dir_a.to_bits(),
        dir_b.to_bits(),
        ((1.0 / radius) as f32).to_bits(),
        0,
    ];
    GaborPack { radius, params }
}

/// `GaborAxis` records for `count` positions: `p = x / r`, the cell `⌊p⌋`, the offset
/// `f32(p − ⌊p⌋)` and 1, or `(0, 0, 0)` where `|p|` is out of range (the pixel is `mean`).
pub(crate) fn gabor_axis(radius: f64, count: usize, position: impl Fn(usize) -> f64) -> Vec<u32> {
    let mut words = Vec::with_capacity(3 * count);
    for i in 0..count {
        match spectex_model::grid::locate_cell(position(i), radius) {
            Some((cell, offset)) => words.extend([cell as u32, offset.to_bits(), 1]),
            None => words.extend([0, 0, 0]),
        }
    }
    words
}

/// Bytes of one `WaveletAxis` entry of `wavelet.wgsl` (index, fraction), per band.
pub(crate) const WAVELET_AXIS_BYTES: u64 = 8;

/// A wavelet noise as buffer words: its tile (built on the host by the model's one function),
/// its `WaveletBand` records, and what the host needs per tile.
#[derive(Debug, Clone)]
pub(crate) struct WaveletPack {
    pub n: u32,
    pub dimensions: u32,
    pub mean: f32,
    pub bands: Vec<Band>,
    /// f32 bits of the tile, `x` fastest.
    pub tile: Vec<u32>,
    /// `WaveletBand` records: amplitude, first z layer, z fraction, `1/c_b` (for warping).
    pub band_words: Vec<u32>,
}

/// Packs a validated wavelet noise for the plane `z`.
pub(crate) fn pack_wavelet(model: &WaveletNoise, z: f64) -> WaveletPack {
    let tile = model.tile();
    let n = model.tile_size;
    let bands = model.bands();
    let mut band_words = Vec::with_capacity(4 * bands.len());
    for b in &bands {
        let (k0, f) = if model.dimensions == 3 {
            locate_sample(z, b.side, b.offset[2], n)
        } else {
            (0, 0.0)
        };
        band_words.extend([
            b.amplitude.to_bits(),
            k0,
            f.to_bits(),
            ((1.0 / b.side) as f32).to_bits(),
        ]);
    }
    WaveletPack {
        n,
        dimensions: model.dimensions,
        mean: model.mean,
        bands,
        tile: tile.values.iter().map(|v| v.to_bits()).collect(),
        band_words,
    }
}

/// `WaveletAxis` records for `count` positions along `axis` (0 = x, 1 = y), band-major: the
/// first tile index and the fraction of [`locate_sample`], the CPU's call.
pub(crate) fn wavelet_axis(
    pack: &WaveletPack,
    axis: usize,
    count: usize,
    position: impl Fn(usize) -> f64,
) -> Vec<u32> {
    let mut words = Vec::with_capacity(2 * count * pack.bands.len());
    for b in &pack.bands {
        for i in 0..count {
            let (index, f) = locate_sample(position(i), b.side, b.offset[axis], pack.n);
            words.extend([index, f.to_bits()]);
        }
    }
    words
}

/// Column positions of a window, for the axis tables.
pub(crate) fn columns(window: &GpuWindow) -> impl Fn(usize) -> f64 + '_ {
    move |i| window.x(i)
}

/// Row positions of a window.
pub(crate) fn rows(window: &GpuWindow) -> impl Fn(usize) -> f64 + '_ {
    move |j| window.y(j)
}

/// Little-endian bytes of buffer words (the layout every wgpu backend uses).
pub(crate) fn bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lrp_axis_offsets_are_the_rounded_f64_differences() {
        let words = lrp_axis(&[9.5], 3, |i| 1.0e7 + i as f64 * 0.25);
        for i in 0..3 {
            let x = 1.0e7 + i as f64 * 0.25;
            let cell = (x / 9.5).floor() as i64;
            assert_eq!(words[5 * i] as i32 as i64, cell);
            for k in 0..4 {
                let want = (x - (cell + k as i64 - 1) as f64 * 9.5) as f32;
                assert_eq!(f32::from_bits(words[5 * i + 1 + k]), want);
            }
            // The pixel lies in [cell, cell + 1) lattice steps: offset k = 1 is in [0, Δ).
            let d = f32::from_bits(words[5 * i + 2]);
            assert!((0.0..=9.5).contains(&d), "{d}");
        }
    }

    #[test]
    fn lrp_pack_concatenates_tables_in_order() {
        use spectex_model::Stratum;
        let m = LrpNoise {
            seed: 3,
            mean: 0.5,
            strata: vec![
                Stratum {
                    window_width: 4.0,
                    amplitude: 1.0,
                    sub_strata: vec![vec![[0.1, 0.2]], vec![[0.3, 0.4], [0.0, 0.1]]],
                },
                Stratum {
                    window_width: 8.0,
                    amplitude: 2.0,
                    sub_strata: vec![vec![[0.25, 0.0]]],
                },
            ],
        };
        let p = pack_lrp(&m);
        assert_eq!(p.tables, [0, 1, 1, 2, 3, 1]);
        assert_eq!(p.strata[2..5], [0, 2, 4.0f32.to_bits()]);
        assert_eq!(p.strata[7..10], [2, 1, 8.0f32.to_bits()]);
        assert_eq!(f32::from_bits(p.strata[0]), 1.0 / 16.0);
        assert_eq!(f32::from_bits(p.frequencies[6]), 0.25);
    }

    #[test]
    fn gabor_axis_splits_cells_and_rejects_out_of_range() {
        let w = gabor_axis(2.0, 3, |i| [-0.5, 4.0, 1e300][i]);
        assert_eq!(w[0..3], [(-1i32) as u32, 0.75f32.to_bits(), 1]);
        assert_eq!(w[3..6], [2, 0, 1]);
        assert_eq!(w[6..9], [0, 0, 0]);
    }
}
