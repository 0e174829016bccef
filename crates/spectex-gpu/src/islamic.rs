//! Islamic star patterns on the device (`shaders/islamic.wgsl`): the model's f32 segment table
//! is uploaded once, and per tile each column's and row's lattice fractions (the CPU's f64
//! split, `spectex_model::islamic::LatticeMap`); the shader sums them and runs the CPU's
//! segment loop and output formula.

use spectex_model::Period;
use spectex_model::islamic::{IslamicOutput, IslamicPattern, LatticeMap, footprint};

use crate::axis::{periodic_columns, periodic_rows};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::ShaderFile;
use crate::{GpuContext, GpuError, GpuWindow};

wgsl_struct! {
    /// `IslamicParams` of `islamic.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct IslamicParams {
        width: u32,
        height: u32,
        /// Segments in the table.
        segments: u32,
        /// 0: band, 1: distance, 2: filled.
        output: u32,
        /// `C`, pixels.
        cell: f32,
        /// `w`, pixels.
        line_width: f32,
        /// `f`, pixels.
        footprint: f32,
        /// `f32(1/f)`.
        inv_footprint: f32,
        /// `e₁`, `e₂` (f32).
        e1x: f32,
        e1y: f32,
        e2x: f32,
        e2y: f32,
        /// `A` (f32), for a warp's displacement: `Δs = a00·dx + a01·dy`.
        a00: f32,
        a01: f32,
        a10: f32,
        a11: f32,
    }
}

/// An Islamic pattern on the device.
#[derive(Debug, Clone)]
pub(crate) struct IslamicKernel {
    map: LatticeMap,
    params: IslamicParams,
    /// The period of a periodic pattern (a lattice period of the tiling): positions reduced
    /// modulo it, the pattern itself unchanged.
    period: Option<Period>,
}

impl GpuKind for IslamicPattern {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "islamic",
        source: include_str!("../../../shaders/islamic.wgsl"),
        needs_common: true,
        entry_points: &["islamic_main"],
    });

    /// Periodic: the pattern is periodic with every lattice period
    /// (`ModelKind::check_period`): only the positions are reduced, as the CPU's
    /// `PeriodicKernel` reduces them.
    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (kernel, segments) = pack(self, period);
        Shaded::boxed(
            context,
            kernel,
            &[Table::new("islamic segments", &segments)],
        )
    }
}

/// The kernel of an Islamic pattern, its positions reduced modulo `period` when given, and its
/// segment table (seven f32 per segment).
pub(crate) fn pack(model: &IslamicPattern, period: Option<Period>) -> (IslamicKernel, Vec<f32>) {
    let geometry = model.geometry();
    let map = model.lattice_map();
    let [e1, e2] = geometry.basis;
    let kernel = IslamicKernel {
        map,
        params: IslamicParams {
            width: 0,
            height: 0,
            segments: geometry.len() as u32,
            output: match model.output {
                IslamicOutput::Band => 0,
                IslamicOutput::Distance => 1,
                IslamicOutput::Filled => 2,
            },
            cell: model.cell_size,
            line_width: model.line_width,
            footprint: 1.0,
            inv_footprint: 1.0,
            e1x: e1[0],
            e1y: e1[1],
            e2x: e2[0],
            e2y: e2[1],
            a00: map.a[0][0] as f32,
            a01: map.a[0][1] as f32,
            a10: map.a[1][0] as f32,
            a11: map.a[1][1] as f32,
        },
        period,
    };
    (kernel, geometry.segments)
}

impl ShaderKernel for IslamicKernel {
    const SHADER: &'static str = "islamic";
    const ENTRY_POINT: &'static str = "islamic_main";

    fn axis_bytes(&self) -> u64 {
        8
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: Option<&[f32]>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        let (f, inv_f) = footprint(tile.footprint());
        let params = IslamicParams {
            width: tile.width as u32,
            height: tile.height as u32,
            footprint: f,
            inv_footprint: inv_f,
            ..self.params
        };
        let (x, y) = (
            periodic_columns(tile, self.period),
            periodic_rows(tile, self.period),
        );
        let columns: Vec<[f32; 2]> = (0..tile.width).map(|i| self.map.column(x(i))).collect();
        let rows: Vec<[f32; 2]> = (0..tile.height).map(|j| self.map.row(y(j))).collect();
        Ok(TileTables::new(
            &params,
            vec![
                Table::new("islamic columns", &columns),
                Table::new("islamic rows", &rows),
            ],
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    #[test]
    fn params_match_the_wgsl() {
        assert_matches_wgsl::<IslamicParams>("islamic", "IslamicParams");
    }
}
