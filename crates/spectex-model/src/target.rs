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
