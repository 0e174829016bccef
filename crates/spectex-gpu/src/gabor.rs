//! Gabor noise on the device (`shaders/gabor.wgsl`): the constants the CPU's Gabor evaluator
//! computes, by the same f64 expressions, in the uniform, and per tile each column's and row's
//! kernel-grid cell and offset, and the box of cells `gabor_draw` draws once on the device.
//!
//! The Gabor noise's export (the glue of `shaders/gabor.wgsl`): the compute shader's uniform; the
//! kernel grid (side: the kernel radius) is the export's only lattice.

use std::sync::Arc;

use spectex_model::{GaborNoise, Orientation, Period};

use crate::axis::{CellAxes, CellAxis};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::{OwnPass, OwnPassLayout, Shaded};
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/gabor.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/gabor.wgsl"));

/// The Poisson count's renormalisation chunk (the CPU's `POISSON_CHUNK`).
const POISSON_CHUNK: f64 = 64.0;

wgsl_struct! {
    /// `GaborParams` of `gabor.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct GaborParams {
        width: u32,
        height: u32,
        seed: u32,
        /// 0: one frequency vector `(dir_a, dir_b)`; 1: a random angle in turns
        /// `dir_a + u·dir_b`; 2: a component drawn from the `components` table.
        direction_kind: u32,
        mean: f32,
        amplitude: f32,
        /// `exp(−ρ)`, the Knuth threshold once the `exp(64)` chunks are used up.
        poisson_threshold: f32,
        /// `⌊λ / 64⌋`.
        poisson_chunks: u32,
        /// `exp(64)` and `exp(−64)` rounded to f32.
        chunk_up: f32,
        chunk_down: f32,
        /// `N_max = ⌊4λ + 32⌋`.
        max_impulses: u32,
        /// `F₀·r`, cycles per cell.
        frequency_cells: f32,
        dir_a: f32,
        dir_b: f32,
        /// `1/r` (f32 of the f64 value), for warping.
        inv_radius: f32,
        /// Entries of the `components` table (0 unless `direction_kind` is 2).
        components: u32,
        /// Cells per period along x and y of a periodic noise (cells hashed modulo them,
        /// `wrap_cell`), 0 when not periodic.
        cells_x: i32,
        cells_y: i32,
        _pad2: u32,
        /// The cell box: first column and row, columns, rows (0 where the draws table holds
        /// nothing); `gabor_draw`'s invocations per row of its dispatch grid.
        box_i0: i32,
        box_j0: i32,
        box_cols: u32,
        box_rows: u32,
        draw_stride: u32,
    }
}

/// `gabor_draw`: it reads the components (1) and writes the draws in `output`'s place (5), one
/// invocation a cell of the box, 64 a workgroup (its `@workgroup_size`).
const DRAW_PASS: OwnPassLayout = OwnPassLayout {
    label: "gabor draw",
    bindings: &[1],
    target: 5,
    workgroup: 64,
    invocations: |uniform| {
        let p = bytemuck::pod_read_unaligned::<GaborParams>(uniform);
        p.box_cols * p.box_rows
    },
};

wgsl_struct! {
    /// `GaborComponent` of `gabor.wgsl`: one entry of a spectrum's table.
    pub(crate) struct GaborComponent {
        /// `r·f_k`, cycles per cell unit (f64 products rounded to f32, as on the CPU).
        fx: f32,
        fy: f32,
        /// `C_k` of `spectex_model::cumulative_weights`.
        cumulative: f32,
        /// Where `pick_component` starts for a uniform in `[k/n, (k + 1)/n)` (`n` components):
        /// `spectex_model::pick_component` of `k/n` (a guide table, Chen and Asau 1974).
        guide: u32,
    }
}

/// A Gabor noise on the device: its uniform (tile size set per tile), its grid and its
/// components (empty unless it is a spectrum).
#[derive(Debug, Clone)]
pub(crate) struct GaborKernel {
    /// Kernel radius `r` = grid cell side, pixels.
    pub(crate) radius: f64,
    params: GaborParams,
    components: Vec<GaborComponent>,
    /// The period of a periodic noise: positions reduced modulo it.
    period: Option<Period>,
    /// `gabor_draw` on the device (none for the export, whose pixels draw for themselves).
    draw: Option<Arc<OwnPass>>,
}

/// Packs a validated Gabor model, periodic with `period` when given (a period it accepts): the
/// CPU's `GaborEvaluator::new_periodic`, square cells of the fitted radius hashed modulo the
/// period.
pub(crate) fn pack(model: &GaborNoise, period: Option<Period>) -> GaborKernel {
    let radius = period
        .and_then(|p| model.periodic_radius(p))
        .unwrap_or_else(|| model.kernel_radius());
    let cells = period.map_or([0, 0], |p| p.cells(radius).map(|n| n as i32));
    let lambda = model.impulses_per_cell();
    let chunks = (lambda / POISSON_CHUNK).floor();
    let rest = lambda - chunks * POISSON_CHUNK;
    let frequency_cells = f64::from(model.frequency) * radius;
    let mut components = Vec::new();
    let (direction_kind, dir_a, dir_b) = match &model.orientation {
        &Orientation::Anisotropic { angle } => {
            let (sin, cos) = f64::from(angle).sin_cos();
            (
                0u32,
                (frequency_cells * cos) as f32,
                (frequency_cells * sin) as f32,
            )
        }
        &Orientation::Isotropic { min, max } => {
            let turn = std::f64::consts::TAU;
            (
                1u32,
                (f64::from(min) / turn).rem_euclid(1.0) as f32,
                ((f64::from(max) - f64::from(min)) / turn) as f32,
            )
        }
        Orientation::Spectrum {
            frequencies,
            weights,
        } => {
            let cumulative = spectex_model::cumulative_weights(weights);
            // The CPU's pick at each bucket's lower edge (any start gives the shader the same
            // pick; this one is a step or two from it).
            let n = cumulative.len() as f32;
            let guide = |k: usize| spectex_model::pick_component(&cumulative, k as f32 / n) as u32;
            components = frequencies
                .iter()
                .zip(&cumulative)
                .enumerate()
                .map(|(k, (f, &cumulative))| GaborComponent {
                    fx: (f64::from(f[0]) * radius) as f32,
                    fy: (f64::from(f[1]) * radius) as f32,
                    cumulative,
                    guide: guide(k),
                })
                .collect();
            (2u32, 0.0, 0.0)
        }
    };
    let params = GaborParams {
        width: 0,
        height: 0,
        seed: model.seed,
        direction_kind,
        mean: model.mean,
        amplitude: model.amplitude,
        poisson_threshold: (-rest).exp() as f32,
        poisson_chunks: chunks as u32,
        chunk_up: POISSON_CHUNK.exp() as f32,
        chunk_down: (-POISSON_CHUNK).exp() as f32,
        max_impulses: (4.0 * lambda + 32.0).floor().max(1.0) as u32,
        frequency_cells: frequency_cells as f32,
        dir_a,
        dir_b,
        inv_radius: (1.0 / radius) as f32,
        components: components.len() as u32,
        cells_x: cells[0],
        cells_y: cells[1],
        ..bytemuck::Zeroable::zeroed()
    };
    GaborKernel {
        radius,
        params,
        components,
        period,
        draw: None,
    }
}

impl GaborKernel {
    /// The resident table (binding 1): the components, one zeroed filler when there are none.
    fn tables(&self) -> [Table; 1] {
        [Table::new("gabor components", &self.components)]
    }
}

impl GpuKind for GaborNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "gabor",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["gabor_draw", "gabor_main"],
    });

    fn kernel_with_period(
        &self,
        context: &GpuContext,
        _z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let mut kernel = pack(self, period);
        kernel.draw = Some(OwnPass::new(context, "gabor", "gabor_draw")?);
        let tables = kernel.tables();
        Shaded::boxed(context, kernel, &tables)
    }
}

impl ShaderKernel for GaborKernel {
    const SHADER: &'static str = "gabor";
    const ENTRY_POINT: &'static str = "gabor_main";

    const SHAPE: &'static [&'static str] = &["GABOR_DIRECTION_KIND"];

    /// How impulses draw their direction.
    fn shape(&self) -> Vec<u32> {
        vec![self.params.direction_kind]
    }

    fn axis_bytes(&self) -> u64 {
        size_of::<CellAxis>() as u64
    }

    /// The tile's axes and, with `gabor_draw`, the draws of its box of cells (the cells of its
    /// pixels and their neighbours), left to the device; where they would not fit `limit` or
    /// `MAX_PASS_TABLE_BYTES`, the pixels draw for themselves, as a displaced tile's do (its
    /// pixels leave the box).
    fn tile_tables(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
        limit: u64,
    ) -> Result<TileTables, GpuError> {
        let mut params = GaborParams {
            width: tile.width as u32,
            height: tile.height as u32,
            ..self.params
        };
        let axes = CellAxes::new(self.radius, tile, self.period);
        let cell_bytes = (1 + 2 * u64::from(params.max_impulses)) * 16;
        let drawn = match &self.draw {
            Some(draw) if !displacement.is_some() => draw.draw_box(
                axes.cell_range(tile, displacement)?,
                (1, cell_bytes),
                (DRAW_PASS.workgroup, limit),
            ),
            _ => None,
        };
        if let Some(b) = drawn {
            (params.box_i0, params.box_j0) = (b.i0, b.j0);
            (params.box_cols, params.box_rows, params.draw_stride) = (b.cols, b.rows, b.stride);
        }
        let draws = Table::left_to_pass("gabor draws", drawn.map(|b| b.bytes));
        Ok(TileTables::new(
            &params,
            std::iter::once(draws)
                .chain(axes.tables(["gabor columns", "gabor rows"]))
                .collect(),
        )
        .with_pass(drawn.map(|_| &params)))
    }

    fn own_pass(&self) -> Option<(&OwnPass, &'static OwnPassLayout)> {
        self.draw.as_deref().map(|pass| (pass, &DRAW_PASS))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for GaborNoise {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let kernel = pack(self, None);
        // The kernel grid is the export's lattice 0 (the glue of gabor.wgsl).
        let lattices = vec![kernel.radius];
        // The components are a storage buffer of the export, as the compute shader's.
        ExportParts::of(&kernel, &kernel.tables(), lattices, "gabor")
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    /// A tile whose cells `gabor_draw` drew once renders the bits of the same tile whose pixels
    /// draw for themselves: one direction, a range of angles and a spectrum (each impulse's
    /// own frequency), near the origin, far from it, magnified and minified, on tiles whose
    /// sides are not multiples of the workgroup, and a periodic noise's tile across its
    /// period. Each tile must really be drawn (its one pass prepared).
    pub fn drawn_cells_render_the_per_pixel_bits() {
        use crate::layout::check::context_or_skip;
        use crate::pipeline::assert_own_pass_keeps_bits;
        let Some(context) = context_or_skip("drawn_cells_render_the_per_pixel_bits") else {
            return;
        };
        let isotropic = spectex_model::fixtures::gabor_isotropic();
        let mut anisotropic = isotropic.clone();
        anisotropic.orientation = Orientation::Anisotropic { angle: 0.4 };
        let mut spectrum = isotropic.clone();
        spectrum.orientation = Orientation::Spectrum {
            frequencies: vec![[0.05, 0.0], [0.0, 0.1], [-0.03, 0.04], [0.2, 0.2]],
            weights: vec![3.0, 0.0, 1.0, 0.25],
        };
        let period = Period::new(256, 128).unwrap();
        let cases = [
            (
                &anisotropic,
                None,
                GpuWindow::new(37, 21).at([1.0e6, -3.0e5], 1.0),
            ),
            (
                &isotropic,
                None,
                GpuWindow::new(19, 13).at([-40.5, 7.25], 3.5),
            ),
            (&spectrum, None, GpuWindow::new(40, 24).at([3.0, 5.0], 0.37)),
            (
                &spectrum,
                Some(period),
                GpuWindow::new(48, 40).at([230.0, 100.0], 1.0),
            ),
        ];
        for (model, period, tile) in cases {
            let kernel = pack(model, period);
            let mut drawn = kernel.clone();
            drawn.draw = Some(OwnPass::new(&context, "gabor", "gabor_draw").unwrap());
            let tables = kernel.tables();
            assert_own_pass_keeps_bits(&context, (drawn, kernel), &tables, &tile);
        }
    }

    pub fn params_match_the_wgsl() {
        assert_matches_wgsl::<GaborParams>("gabor", "GaborParams");
        assert_matches_wgsl::<GaborComponent>("gabor", "GaborComponent");
    }
}
