//! Islamic star patterns on the device (`shaders/islamic.wgsl`): the model's f32 segment table
//! is uploaded once, and per tile each column's and row's lattice fractions (the CPU's f64
//! split, `spectex_model::islamic::LatticeMap`); the shader sums them and runs the CPU's
//! segment loop and output formula.
//!
//! The Islamic pattern's export (the glue of `shaders/islamic.wgsl`): the compute shader's uniform,
//! the segment loop written out with each segment's values as literals (a loop over the table
//! cost about 5 calibration cosines a segment on lavapipe, written out 0.5–2), and the
//! fixed-point tables with which the glue forms the lattice fractions `frac(A·p + c)` of a
//! position (the compute path's host splits them in f64).

use spectex_model::Period;
use spectex_model::islamic::{
    IslamicOutput, IslamicPattern, LatticeMap, SEGMENT_FLOATS, footprint,
};

use crate::axis::{periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportParts, float};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/islamic.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/islamic.wgsl"));

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
        source: WGSL.0,
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
        Shaded::boxed(context, kernel, &[uniform_segments(&segments)?])
    }
}

/// The segments `islamic.wgsl`'s uniform table holds (two vec4 each, 64 KiB: a uniform
/// binding's guaranteed size); a pattern has a few hundred (3.12.12: 432).
const UNIFORM_SEGMENTS: usize = 2048;

/// The segment table (seven f32 per segment) as `islamic.wgsl`'s uniform reads it:
/// `(a_x, a_y, b_x, b_y)`, `(d_x, d_y, ι, 0)` per segment.
///
/// # Errors
/// [`GpuError::LimitsExceeded`] for more than [`UNIFORM_SEGMENTS`] segments.
fn uniform_segments(segments: &[f32]) -> Result<Table, GpuError> {
    let records: Vec<[f32; 4]> = segments
        .chunks_exact(SEGMENT_FLOATS)
        .flat_map(|s| [[s[0], s[1], s[2], s[3]], [s[4], s[5], s[6], 0.0]])
        .collect();
    Table::uniform(
        "islamic segments",
        "records of an Islamic pattern's segment table (two a segment)",
        &records,
        2 * UNIFORM_SEGMENTS,
    )
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

    const SHAPE: &'static [&'static str] = &["ISLAMIC_OUTPUT"];

    /// The model's output (the shader's shape overrides).
    fn shape(&self) -> Vec<u32> {
        vec![self.params.output]
    }

    fn axis_bytes(&self) -> u64 {
        8
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: TileDisplacement<'_>,
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

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

/// `frac(v)·2³²` rounded to an integer, modulo 2³² (exact in f64 for `|v| < 2⁵²`: the
/// fraction is exact and the scaling by a power of two too).
fn fixed(v: f64) -> u32 {
    let f = v - v.floor();
    (((f * 4_294_967_296.0).round() as u64) % (1 << 32)) as u32
}

/// Per coefficient `a` and bit `k`, `frac(a·w_k)` in fixed point (`w_k = 2^k`, `w_31 = −2³¹`).
fn bit_table(a: f64) -> impl Iterator<Item = u32> {
    (0..32).map(move |k| {
        let w = if k == 31 {
            -2_147_483_648.0
        } else {
            f64::from(1u32 << k)
        };
        fixed(a * w)
    })
}

impl ExportKind for IslamicPattern {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, segments) = pack(self, None);
        let map = self.lattice_map();
        // Tables 0–3: A₀₀ (s from x), A₀₁ (s from y), A₁₀ (t from x), A₁₁ (t from y).
        let table: Vec<String> = [map.a[0][0], map.a[0][1], map.a[1][0], map.a[1][1]]
            .into_iter()
            .flat_map(bit_table)
            .map(|v| format!("{v}u"))
            .collect();
        let constants = format!(
            "var<private> islamic_export_fixed: array<u32, 128> = array<u32, 128>({});\n\
             const islamic_export_c: vec2<u32> = vec2<u32>({}u, {}u);\n",
            table.join(", "),
            fixed(map.c[0]),
            fixed(map.c[1]),
        );
        // The segment loop written out, each segment's values as literals (the glue's
        // `islamic_export_at`).
        let segment = |k: usize| {
            let [ax, ay, _bx, by, dx, dy, inv] =
                std::array::from_fn(|i| float(segments[SEGMENT_FLOATS * k + i]));
            format!(
                "islamic_segment(q, vec2<f32>({ax}, {ay}), {by}, vec2<f32>({dx}, {dy}), {inv}, \
                 &best, &odd);"
            )
        };
        let count = segments.len() / SEGMENT_FLOATS;
        // The table the compute path's loop reads is one unused zero record here.
        let unread: &[[f32; 4]] = &[];
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("islamic segments", unread)],
            Vec::new(),
            "islamic",
        )?
        .with_constants(constants)
        .with_unrolled("ISLAMIC_EXPORT_SEGMENTS", count, segment)
        // Only the compute path, unused here, reads the tables (the segments written out, a
        // position's fractions summed from the fixed-point tables): a buffer export binds none.
        // The segments, a uniform table, are constants in any export.
        .with_constant_tables(&["columns", "rows"]))
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::{assert_fills_uniform_array, assert_matches_wgsl};

    pub fn params_match_the_wgsl() {
        assert_matches_wgsl::<IslamicParams>("islamic", "IslamicParams");
    }

    /// The uniform table holds each segment's seven values where the shader reads them, pads
    /// to the binding's 64 KiB, and refuses one segment more than it holds, naming the limit.
    pub fn uniform_segments_hold_the_table_or_name_the_limit() {
        let segments: Vec<f32> = (0..2 * SEGMENT_FLOATS).map(|i| i as f32).collect();
        let table = uniform_segments(&segments).unwrap();
        assert_eq!(table.bytes.len(), 65536);
        assert_fills_uniform_array("islamic", "segments", &table.bytes);
        let records: &[[f32; 4]] = bytemuck::cast_slice(&table.bytes);
        assert_eq!(records[2], [7.0, 8.0, 9.0, 10.0]);
        assert_eq!(records[3], [11.0, 12.0, 13.0, 0.0]);
        assert!(records[4..].iter().all(|r| *r == [0.0; 4]));
        let over = vec![0.0f32; (UNIFORM_SEGMENTS + 1) * SEGMENT_FLOATS];
        match uniform_segments(&over) {
            Err(GpuError::LimitsExceeded { value, limit, .. }) => {
                assert_eq!((value, limit), (4098, 4096));
            }
            other => panic!("{other:?}"),
        }
    }

    /// The glue's sum of the set bits' table entries, modulo 2³² (`islamic_export_fixed_sum`),
    /// is `frac(a·n)·2³²` within its roundings: at most half a unit per entry (32) and for the
    /// reference (1), whatever `n` — the identity `a·n = Σ_k bit_k(n)·a·w_k`.
    pub fn fixed_point_sums_are_the_fraction_of_a_times_n() {
        for a in [1.0 / 48.0, -0.017_320_508_075_688_77, 0.123_456_789, 3.5] {
            let table: Vec<u32> = bit_table(a).collect();
            for n in [
                0i32,
                1,
                -1,
                7,
                -48,
                1_000_003,
                10_000_000,
                i32::MAX,
                i32::MIN,
            ] {
                let bits = n as u32;
                let sum = (0..32)
                    .filter(|k| ((bits >> k) & 1) == 1)
                    .fold(0u32, |acc, k| acc.wrapping_add(table[k]));
                // The reference: a·n = p + e exactly (p the rounded product, e = fma(a, n, −p)
                // its exact error), so frac(a·n) = frac(frac(p) + e), one rounding of 2⁻⁵³.
                let p = a * f64::from(n);
                let e = a.mul_add(f64::from(n), -p);
                let want = fixed((p - p.floor()) + e);
                let diff = sum.wrapping_sub(want) as i32;
                assert!(diff.abs() <= 17, "a = {a}, n = {n}: {sum} vs {want}");
            }
        }
    }
}
