//! Spectral targets an LRP noise can be built from: continuous power spectra given by formulas
//! (ring, anisotropic lobe pair, band-pass annulus, weighted sums) and discrete ones (a PSD array
//! measured from an example).

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_range};

/// A target power spectral density `P(f)`, `f` in cycles per pixel. Shapes only: the noise's
/// variance is set separately when a model is built.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum SpectralTarget {
    /// A ring: `P(f) = exp(−(|f| − radius)² / (2·width²))` (isotropic noise of one scale).
    Ring {
        /// Ring radius, cycles per pixel.
        radius: f32,
        /// Gaussian half-width of the ring's profile, cycles per pixel.
        width: f32,
    },
    /// Two Gaussian lobes at `±frequency·(cos angle, sin angle)`, of standard deviation `width`
    /// (anisotropic, oriented noise).
    Lobes {
        /// Distance of the lobes from the origin, cycles per pixel.
        frequency: f32,
        /// Direction of the lobes, radians.
        angle: f32,
        /// Standard deviation of each lobe, cycles per pixel.
        width: f32,
    },
    /// A band-pass annulus: `P(f) = 1` for `min ≤ |f| ≤ max`, else 0.
    Band {
        /// Inner radius, cycles per pixel.
        min: f32,
        /// Outer radius, cycles per pixel.
        max: f32,
    },
    /// A random-phase 1/f^β fractal with the angular term of Eq. (8) of the texture survey
    /// (Dong et al. 2020, §3.1.4): magnitude `M(f, θ) = f^{−β}·exp(−(θ − θ₀)²/(2σ²))`, so the
    /// power is `P = f^{−2β}·exp(−(θ − θ₀)²/σ²)` for `min_frequency ≤ f ≤ ½`, 0 elsewhere (the
    /// infinite power at `f → 0` needs a floor: the largest feature is `1/min_frequency`
    /// pixels). `θ − θ₀` is taken modulo π (a real texture's spectrum is symmetric). The RMS
    /// roughness normalisation `δ/δₙ` is the variance given when a model is built.
    Fractal {
        /// `β`, the roll-off of the magnitude spectrum.
        beta: f32,
        /// `θ₀`, the dominant direction of the frequencies, radians.
        angle: f32,
        /// `σ`, the angular standard deviation, radians; isotropic if absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        spread: Option<f32>,
        /// Lowest frequency with power, cycles per pixel.
        min_frequency: f32,
    },
    /// A weighted sum of targets.
    Sum {
        /// `(weight, target)` pairs.
        terms: Vec<(f32, SpectralTarget)>,
    },
    /// A discrete `size × size` PSD on the DFT grid (zero frequency at index 0, row-major,
    /// `psd[k·size + l]` at `f = (l/size, k/size)` taken as signed frequencies).
    Discrete {
        /// Side `T` of the grid.
        size: u32,
        /// `T²` non-negative values.
        psd: Vec<f32>,
    },
}

impl SpectralTarget {
    /// Radius of the `spectex noise ring` target, cycles per pixel: a 16-pixel period (the
    /// paper's Fig. 10).
    pub const DEFAULT_RING_RADIUS: f32 = 0.0625;
    /// Gaussian half-width of the `spectex noise ring` target, cycles per pixel: a thin ring.
    pub const DEFAULT_RING_WIDTH: f32 = 0.005;
    /// Distance of the `spectex noise lobe` lobes from the origin, cycles per pixel.
    pub const DEFAULT_LOBE_FREQUENCY: f32 = 0.1;
    /// Direction of the `spectex noise lobe` lobes, **degrees** as the command takes them (the
    /// model's `angle` is in radians).
    pub const DEFAULT_LOBE_ANGLE_DEGREES: f32 = 30.0;
    /// Standard deviation of each `spectex noise lobe` lobe, cycles per pixel.
    pub const DEFAULT_LOBE_WIDTH: f32 = 0.01;
    /// Inner radius of the `spectex noise band` annulus, cycles per pixel.
    pub const DEFAULT_BAND_MIN: f32 = 0.05;
    /// Outer radius of the `spectex noise band` annulus, cycles per pixel: one octave.
    pub const DEFAULT_BAND_MAX: f32 = 0.1;
    /// `β` of the `spectex noise fractal` target: power `f^−3`, a Brownian surface (`H = ½`).
    pub const DEFAULT_FRACTAL_BETA: f32 = 1.5;
    /// `θ₀` of the `spectex noise fractal` target, **degrees** as the command takes them.
    pub const DEFAULT_FRACTAL_ANGLE_DEGREES: f32 = 0.0;
    /// Lowest frequency with power of the `spectex noise fractal` target, cycles per pixel:
    /// features up to 128 pixels.
    pub const DEFAULT_FRACTAL_MIN_FREQUENCY: f32 = 1.0 / 128.0;

    /// The target density at frequency `(fx, fy)` in cycles per pixel (continuous targets; a
    /// discrete one answers with its nearest grid value).
    #[must_use]
    pub fn power(&self, fx: f64, fy: f64) -> f64 {
        let r = (fx * fx + fy * fy).sqrt();
        match self {
            Self::Ring { radius, width } => {
                let d = r - f64::from(*radius);
                (-d * d / (2.0 * f64::from(*width).powi(2))).exp()
            }
            Self::Lobes {
                frequency,
                angle,
                width,
            } => {
                let (cx, cy) = (
                    f64::from(*frequency) * f64::from(*angle).cos(),
                    f64::from(*frequency) * f64::from(*angle).sin(),
                );
                let s2 = 2.0 * f64::from(*width).powi(2);
                let lobe = |x: f64, y: f64| (-(x * x + y * y) / s2).exp();
                lobe(fx - cx, fy - cy) + lobe(fx + cx, fy + cy)
            }
            Self::Band { min, max } => {
                if r >= f64::from(*min) && r <= f64::from(*max) {
                    1.0
                } else {
                    0.0
                }
            }
            Self::Fractal {
                beta,
                angle,
                spread,
                min_frequency,
            } => {
                if r < f64::from(*min_frequency) || r > 0.5 {
                    return 0.0;
                }
                let radial = r.powf(-2.0 * f64::from(*beta));
                let angular = spread.map_or(1.0, |s| {
                    let pi = std::f64::consts::PI;
                    let d = (fy.atan2(fx) - f64::from(*angle)).rem_euclid(pi);
                    let d = if d > pi / 2.0 { d - pi } else { d };
                    (-d * d / f64::from(s).powi(2)).exp()
                });
                radial * angular
            }
            Self::Sum { terms } => terms
                .iter()
                .map(|(w, t)| f64::from(*w) * t.power(fx, fy))
                .sum(),
            Self::Discrete { size, psd } => {
                let n = f64::from(*size);
                let k = ((fy * n).round().rem_euclid(n)) as usize;
                let l = ((fx * n).round().rem_euclid(n)) as usize;
                f64::from(psd[k * *size as usize + l])
            }
        }
    }

    /// Checks every number.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        let freq = |name: &'static str, v: f32| {
            check_range(
                || name.into(),
                f64::from(v),
                0.0,
                0.5,
                "[0, 0.5] cycles per pixel",
            )
        };
        match self {
            Self::Ring { radius, width } => {
                freq("ring.radius", *radius)?;
                check_range(
                    || "ring.width".into(),
                    f64::from(*width),
                    1e-4,
                    0.5,
                    "[0.0001, 0.5] cycles per pixel",
                )
            }
            Self::Lobes {
                frequency,
                angle,
                width,
            } => {
                freq("lobes.frequency", *frequency)?;
                check_range(
                    || "lobes.angle".into(),
                    f64::from(*angle),
                    -1e3,
                    1e3,
                    "[-1000, 1000] radians",
                )?;
                check_range(
                    || "lobes.width".into(),
                    f64::from(*width),
                    1e-4,
                    0.5,
                    "[0.0001, 0.5] cycles per pixel",
                )
            }
            Self::Band { min, max } => {
                freq("band.min", *min)?;
                check_range(
                    || "band.max".into(),
                    f64::from(*max),
                    f64::from(*min) + 1e-4,
                    0.75,
                    "(min, 0.75] cycles per pixel",
                )
            }
            Self::Fractal {
                beta,
                angle,
                spread,
                min_frequency,
            } => {
                check_range(
                    || "fractal.beta".into(),
                    f64::from(*beta),
                    0.0,
                    4.0,
                    "[0, 4]",
                )?;
                check_range(
                    || "fractal.angle".into(),
                    f64::from(*angle),
                    -1e3,
                    1e3,
                    "[-1000, 1000] radians",
                )?;
                if let Some(s) = spread {
                    check_range(
                        || "fractal.spread".into(),
                        f64::from(*s),
                        0.01,
                        100.0,
                        "[0.01, 100] radians",
                    )?;
                }
                check_range(
                    || "fractal.min_frequency".into(),
                    f64::from(*min_frequency),
                    1.0 / 8192.0,
                    0.25,
                    "[1/8192, 0.25] cycles per pixel",
                )
            }
            Self::Sum { terms } => {
                check_len(|| "sum.terms".into(), terms.len(), 1, 64, "1 to 64 terms")?;
                for (i, (w, t)) in terms.iter().enumerate() {
                    check_range(
                        || format!("sum.terms[{i}].weight"),
                        f64::from(*w),
                        0.0,
                        1e9,
                        "[0, 1e9]",
                    )?;
                    t.validate()?;
                }
                Ok(())
            }
            Self::Discrete { size, psd } => {
                check_range(
                    || "discrete.size".into(),
                    f64::from(*size),
                    2.0,
                    8192.0,
                    "[2, 8192]",
                )?;
                check_len(
                    || "discrete.psd".into(),
                    psd.len(),
                    (*size as usize).pow(2),
                    (*size as usize).pow(2),
                    "size² values",
                )?;
                for (i, v) in psd.iter().enumerate() {
                    check_range(
                        || format!("discrete.psd[{i}]"),
                        f64::from(*v),
                        0.0,
                        1e30,
                        "[0, 1e30]",
                    )?;
                }
                Ok(())
            }
        }
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn fractal_power_follows_eq_8() {
        let t = SpectralTarget::Fractal {
            beta: 1.5,
            angle: 0.5,
            spread: Some(0.25),
            min_frequency: 0.01,
        };
        t.validate().unwrap();
        let at = |r: f64, theta: f64| t.power(r * theta.cos(), r * theta.sin());
        // Radial: doubling f divides the power by 2^{2β} = 8, along the dominant direction.
        assert!((at(0.05, 0.5) / at(0.1, 0.5) - 8.0).abs() < 1e-9);
        // Angular: exp(−Δθ²/σ²) and symmetric under f → −f.
        assert!((at(0.1, 0.75) / at(0.1, 0.5) - (-1.0f64).exp()).abs() < 1e-9);
        assert!((at(0.1, 0.5 + std::f64::consts::PI) / at(0.1, 0.5) - 1.0).abs() < 1e-9);
        // Nothing below the floor or past Nyquist.
        assert_eq!(at(0.009, 0.5), 0.0);
        assert_eq!(at(0.51, 0.5), 0.0);
        let bad = SpectralTarget::Fractal {
            beta: 5.0,
            angle: 0.0,
            spread: None,
            min_frequency: 0.01,
        };
        assert!(matches!(
            bad.validate(),
            Err(ModelError::OutOfRange { field, .. }) if field == "fractal.beta"
        ));
    }
}
