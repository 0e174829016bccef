//! Matrix transformation (`spectex_model::matrix`): both evaluators read the texel from the same
//! integer cell by the same integer map, so the texel is identical; the value `mean +
//! amplitude·S` rounds once on the CPU and at most twice (a product and a sum, or one contracted
//! product-add) on the GPU.

use spectex_model::matrix::{MatrixSource, MatrixTransform};

use super::{CheckKind, F32_UNIT_ROUNDOFF, Regularity, Tolerance};

/// `max |S|`: 1 for the rings (0 or 1), the largest texel for an image.
fn source_bound(m: &MatrixTransform) -> f64 {
    match &m.source {
        MatrixSource::Rings { .. } => 1.0,
        MatrixSource::Image { texels } => texels
            .iter()
            .map(|v| f64::from(v.abs()))
            .fold(0.0, f64::max),
    }
}

/// `|mean| + |amplitude|·max|S|`, the largest value.
fn magnitude(m: &MatrixTransform) -> f64 {
    f64::from(m.mean).abs() + f64::from(m.amplitude).abs() * source_bound(m)
}

/// The index computation is exact (integers below 2²⁵ on both sides), so the tolerance is the
/// value's roundings alone: the CPU's `mean + amplitude·S` rounds the product and the sum
/// (values ≤ the magnitude), the GPU the same two or one contracted: `3` unit roundoffs of the
/// magnitude between them, rounded up to 4.
#[must_use]
pub fn matrix(m: &MatrixTransform) -> Tolerance {
    Tolerance::from_max(4.0 * F32_UNIT_ROUNDOFF * magnitude(m))
}

impl CheckKind for MatrixTransform {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![matrix(self)])
    }

    /// Piecewise constant on the pixel grid: no slope, and at a pixel border a jump of at most
    /// `|amplitude|·(max S − min S) ≤ 2|amplitude|·max|S|`.
    fn regularity(&self) -> Option<Regularity> {
        Some(Regularity {
            slope: 0.0,
            jump: 2.0 * f64::from(self.amplitude).abs() * source_bound(self),
            magnitude: magnitude(self),
            cell: 1.0,
        })
    }
}
