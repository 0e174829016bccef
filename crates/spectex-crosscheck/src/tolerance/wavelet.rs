//! Wavelet noise (Cook & DeRose 2005; `spectex_model::wavelet`): its tolerance and regularity.

use spectex_model::WaveletNoise;

use super::{CheckKind, F32_UNIT_ROUNDOFF, Regularity, SUMMATION_ROUNDINGS, Tolerance};

/// Roundings of one wavelet band per axis on either side: the B-spline weights `(1−f)²/2`,
/// `f²/2` and `1 − w₀ − w₂` (at most 4 roundings each, values ≤ 1), and the axis's weighted sum
/// of 3 values (3 products and 2 sums, which an FMA may fuse): 9 per axis.
pub const WAVELET_AXIS_ROUNDINGS: f64 = 9.0;

/// Wavelet noise (Cook & DeRose 2005; `spectex_model::wavelet`). Both sides read the same f32
/// tile at the same indices and f32 fractions (located on the host by one function). Per band
/// `b`, the value `a_b · Σ w T` has magnitude at most `|a_b| · max|T|` (the weights of each axis
/// sum to 1 and are non-negative), computed with [`WAVELET_AXIS_ROUNDINGS`] per axis over `d`
/// axes plus the product by `a_b` and the accumulation (2): each side is within
/// `(9d + 2)·u·|a_b|·max|T|` of the exact value, so the two sides within twice that; the final
/// `mean + acc` and the band order add [`SUMMATION_ROUNDINGS`] of `|mean| + Σ|a_b|·max|T|`.
#[must_use]
pub fn wavelet(m: &WaveletNoise) -> Tolerance {
    let u = F32_UNIT_ROUNDOFF;
    let peak = m
        .tile()
        .values
        .iter()
        .fold(0.0f64, |a, &v| a.max(f64::from(v).abs()));
    let per_band = 2.0 * (WAVELET_AXIS_ROUNDINGS * f64::from(m.dimensions) + 2.0) * u;
    let bands: f64 = m
        .bands()
        .iter()
        .map(|b| f64::from(b.amplitude).abs() * peak)
        .sum();
    let magnitude = f64::from(m.mean).abs() + bands;
    Tolerance::from_max(per_band * bands + SUMMATION_ROUNDINGS * u * magnitude)
}

impl CheckKind for WaveletNoise {
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![wavelet(self)])
    }

    fn regularity(&self) -> Option<Regularity> {
        let m = self;
        // Quadratic B-spline weights have derivatives −(1 − f), 1 − 2f, f: Σ|w'| ≤ 2, so a
        // band changes by at most 2·max|tile| per sample along an axis (the other axes'
        // weights form a convex combination), √2 of it for the plane; per pixel over the
        // band's sample side c_b, times |a_b|.
        let peak = m
            .tile()
            .values
            .iter()
            .fold(0.0f64, |a, &v| a.max(f64::from(v).abs()));
        let bands = m.bands();
        let slope = bands
            .iter()
            .map(|b| f64::from(b.amplitude).abs() * 2.0 * std::f64::consts::SQRT_2 * peak / b.side)
            .sum();
        let magnitude = bands
            .iter()
            .map(|b| f64::from(b.amplitude).abs() * peak)
            .sum::<f64>()
            + f64::from(m.mean).abs();
        Some(Regularity {
            slope,
            jump: 0.0,
            magnitude,
            cell: bands.iter().map(|b| b.side).fold(0.0, f64::max),
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::tolerance::tests::check_slope_on_fine_render;
    use crate::tolerance::tolerance;
    use spectex_model::Model;

    /// The slope bound of wavelet noise holds on fine CPU renders, in 2D and 3D (see
    /// [`check_slope_on_fine_render`]; within a factor 12 of the steepest step seen).
    pub fn wavelet_slope_bounds_hold_on_fine_renders() {
        let mut wavelet: WaveletNoise = serde_json::from_str(
            r#"{"seed": 3, "dimensions": 2, "tile_size": 32, "cell_size": 6.0,
                "bands": [1.0, 0.5], "amplitude": 0.4, "mean": 0.5}"#,
        )
        .unwrap();
        check_slope_on_fine_render("wavelet 2d", &Model::Wavelet(wavelet.clone()), 12.0);
        wavelet.dimensions = 3;
        check_slope_on_fine_render("wavelet 3d", &Model::Wavelet(wavelet), 12.0);
    }

    /// The wavelet bound is the derivation's sum: for one band of weight 1 and zero mean,
    /// `(2(9d + 2) + 64)·u·amplitude·max|T|`; it scales with the amplitude, grows with `d`, and
    /// a mean adds `64·u·|mean|`.
    pub fn wavelet_bound_follows_its_derivation() {
        let model = |dimensions: u32, amplitude: f32, mean: f32| WaveletNoise {
            seed: 4,
            dimensions,
            tile_size: 16,
            cell_size: 8.0,
            bands: vec![1.0],
            amplitude,
            mean,
        };
        let m = model(2, 0.5, 0.0);
        let peak = m
            .tile()
            .values
            .iter()
            .fold(0.0f64, |a, &v| a.max(f64::from(v).abs()));
        let want = (2.0 * 20.0 + 64.0) * F32_UNIT_ROUNDOFF * 0.5 * peak;
        assert!((wavelet(&m).max_abs / want - 1.0).abs() < 1e-12);
        let doubled = wavelet(&model(2, 1.0, 0.0)).max_abs;
        assert!((doubled / wavelet(&m).max_abs - 2.0).abs() < 1e-12);
        let with_mean = wavelet(&model(2, 0.5, 3.0)).max_abs - wavelet(&m).max_abs;
        assert!((with_mean - 64.0 * F32_UNIT_ROUNDOFF * 3.0).abs() < 1e-15);
        assert!(wavelet(&model(3, 0.5, 0.0)).max_abs > 0.0);
        assert_eq!(tolerance(&Model::Wavelet(m.clone())), Some(wavelet(&m)));
    }
}
