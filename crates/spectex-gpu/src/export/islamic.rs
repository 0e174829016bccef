//! The Islamic pattern's export (`shaders/export/islamic.wgsl`): the compute shader's uniform
//! and segment table, and the fixed-point tables with which the glue forms the lattice
//! fractions `frac(A·p + c)` of a position (the compute path's host splits them in f64).

use spectex_model::IslamicPattern;

use super::{ExportKind, ExportNode, ExportParts};
use crate::GpuError;
use crate::kernel::Table;

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
    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, segments) = crate::islamic::pack(self);
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
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("islamic segments", &segments)],
            Vec::new(),
            "islamic",
        )?
        .with_constants(constants))
    }
}
