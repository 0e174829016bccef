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
    const GLUE: &'static str = include_str!("../../../../shaders/export/islamic.wgsl");

    fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, segments) = crate::islamic::pack(self, None);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The glue's sum of the set bits' table entries, modulo 2³² (`islamic_export_fixed_sum`),
    /// is `frac(a·n)·2³²` within its roundings: at most half a unit per entry (32) and for the
    /// reference (1), whatever `n` — the identity `a·n = Σ_k bit_k(n)·a·w_k`.
    #[test]
    fn fixed_point_sums_are_the_fraction_of_a_times_n() {
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
