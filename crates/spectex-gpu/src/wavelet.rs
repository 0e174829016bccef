//! Wavelet noise on the device (`shaders/wavelet.wgsl`): the planes its bands read (built on
//! the host by the model's one function, [`WaveletTile::plane`]: the tile in 2D, a 3D tile
//! summed over the evaluator's `z` per band, as the CPU does) and its bands uploaded once, and
//! per tile and band each column's and row's tile index and fraction, located in f64 by
//! [`locate_sample`] (the CPU's call).
//!
//! The wavelet noise's export (the glue of `shaders/wavelet.wgsl`): the compute shader's uniform
//! and band tables; band b's sample grid is the export's lattice b.

use spectex_model::wavelet::{Band, WaveletTile, locate_sample};
use spectex_model::{Period, WaveletNoise};

use crate::axis::{periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/wavelet.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/wavelet.wgsl"));

wgsl_struct! {
    /// `WaveletParams` of `wavelet.wgsl`.
    pub(crate) struct WaveletParams {
        width: u32,
        height: u32,
        bands: u32,
        /// Tile side `n`.
        n: u32,
        /// 2 or 3.
        dimensions: u32,
        mean: f32,
        // Padding to a whole 16-byte uniform row, as the WGSL struct has it.
        _pad0: u32,
        _pad1: u32,
    }
}

wgsl_struct! {
    /// `WaveletBand` of `wavelet.wgsl`: a band's amplitude, where its plane starts in the
    /// planes table, and `1/c_b` (for warping).
    pub(crate) struct WaveletBand {
        amplitude: f32,
        first: u32,
        inv_side: f32,
        _pad: u32,
    }
}

wgsl_struct! {
    /// `WaveletAxis` of `wavelet.wgsl`: a position's first tile index and fraction in one band.
    pub(crate) struct WaveletAxis {
        index: u32,
        fraction: f32,
    }
}

/// A wavelet noise on the device: what the host needs per tile.
#[derive(Debug, Clone)]
pub(crate) struct WaveletKernel {
    n: u32,
    dimensions: u32,
    mean: f32,
    pub(crate) bands: Vec<Band>,
    /// The period of a periodic model: positions reduced modulo it (the tile repeats within
    /// it, so nothing else changes).
    period: Option<Period>,
}

impl WaveletKernel {
    /// [`WaveletAxis`] records for `count` positions along `axis` (0 = x, 1 = y), band-major.
    fn axis(&self, axis: usize, count: usize, position: impl Fn(usize) -> f64) -> Vec<WaveletAxis> {
        let mut records = Vec::with_capacity(count * self.bands.len());
        for b in &self.bands {
            for i in 0..count {
                let (index, fraction) = locate_sample(position(i), b.side, b.offset[axis], self.n);
                records.push(WaveletAxis { index, fraction });
            }
        }
        records
    }
}

/// The planes `bands` read at the plane `z` (one, the tile, in 2D; one per band in 3D,
/// concatenated) and the band records pointing into them.
fn planes(tile: &WaveletTile, bands: &[Band], z: f64) -> (Vec<f32>, Vec<WaveletBand>) {
    let mut planes = Vec::new();
    let mut records = Vec::with_capacity(bands.len());
    for b in bands {
        if tile.dimensions == 3 || planes.is_empty() {
            planes.extend(tile.plane(b, z));
        }
        records.push(WaveletBand {
            amplitude: b.amplitude,
            first: (planes.len() - tile.side * tile.side) as u32,
            inv_side: (1.0 / b.side) as f32,
            _pad: 0,
        });
    }
    (planes, records)
}

impl GpuKind for WaveletNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "wavelet",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["wavelet_main"],
    });

    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (kernel, tables) = host(self, z, period);
        Shaded::boxed(context, kernel, &tables)
    }
}

/// The kernel of a validated wavelet noise on the plane `z`, periodic with `period` when
/// given, and its resident tables (the planes, the bands): what the device evaluator uploads
/// and what the WGSL export writes.
pub(crate) fn host(
    model: &WaveletNoise,
    z: f64,
    period: Option<Period>,
) -> (WaveletKernel, Vec<Table>) {
    let bands = model.bands();
    let (planes, band_records) = planes(&model.tile(), &bands, z);
    let kernel = WaveletKernel {
        n: model.tile_size,
        dimensions: model.dimensions,
        mean: model.mean,
        bands,
        period,
    };
    let tables = vec![
        Table::new("wavelet planes", &planes),
        Table::new("wavelet bands", &band_records),
    ];
    (kernel, tables)
}

impl ShaderKernel for WaveletKernel {
    const SHADER: &'static str = "wavelet";
    const ENTRY_POINT: &'static str = "wavelet_main";

    const SHAPE: &'static [&'static str] = &["WAVELET_DIMENSIONS", "WAVELET_TILE"];

    /// The model's dimension and tile side.
    fn shape(&self) -> Vec<u32> {
        vec![self.dimensions, self.n]
    }

    fn axis_bytes(&self) -> u64 {
        (size_of::<WaveletAxis>() * self.bands.len()) as u64
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: TileDisplacement<'_>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        let params = WaveletParams {
            width: tile.width as u32,
            height: tile.height as u32,
            bands: self.bands.len() as u32,
            n: self.n,
            dimensions: self.dimensions,
            mean: self.mean,
            ..bytemuck::Zeroable::zeroed()
        };
        Ok(TileTables::new(
            &params,
            vec![
                Table::new(
                    "wavelet columns",
                    &self.axis(0, tile.width, periodic_columns(tile, self.period)),
                ),
                Table::new(
                    "wavelet rows",
                    &self.axis(1, tile.height, periodic_rows(tile, self.period)),
                ),
            ],
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for WaveletNoise {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, tables) = host(self, z, None);
        // Band b's sample grid is the export's lattice b (the glue of wavelet.wgsl), its tile
        // offsets along x and y the constant `wavelet_export_offsets`.
        let lattices = kernel.bands.iter().map(|b| b.side).collect();
        let offsets: Vec<String> = kernel
            .bands
            .iter()
            .flat_map(|b| [b.offset[0], b.offset[1]])
            .map(|o| format!("{o}u"))
            .collect();
        let constants = format!(
            "/// Per band, the tile offsets o_b along x and y (spectex_model::wavelet::Band).\n\
             const wavelet_export_offsets: array<u32, {n}> = array<u32, {n}>({});\n",
            offsets.join(", "),
            n = offsets.len()
        );
        // The bands written out (`WAVELET_EXPORT_BANDS`, wavelet.wgsl's glue), their records
        // constants even when the tile goes to a buffer: wavelet-3d-multiband's export (4
        // bands) ran in 0.58 of the time on lavapipe (5.7 → 3.3 calibration cosines an
        // evaluation, `cargo bench -p spectex-crosscheck --bench export`).
        Ok(ExportParts::of(&kernel, &tables, lattices, "wavelet")?
            .with_constants(constants)
            .with_unrolled("WAVELET_EXPORT_BANDS", kernel.bands.len(), |b| {
                format!("acc = acc + wavelet_export_band(at, {b}u);")
            })
            .with_constant_tables(&["bands", "columns", "rows"]))
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    pub fn records_match_the_wgsl() {
        assert_matches_wgsl::<WaveletParams>("wavelet", "WaveletParams");
        assert_matches_wgsl::<WaveletBand>("wavelet", "WaveletBand");
        assert_matches_wgsl::<WaveletAxis>("wavelet", "WaveletAxis");
    }
}
