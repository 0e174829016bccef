//! Gabor noise by sparse convolution (Lagae et al. 2009): Poisson-distributed impulses per grid
//! cell, each a truncated Gaussian times a cosine.
//!
//! # Randomness contract (layer 0)
//!
//! Cell `(i, j)` seeds its PRNG with `cell_hash(i, j, 0, seed)` and draws a Poisson count, then
//! per impulse its offsets, weight and (isotropic) direction, or for [`Orientation::Spectrum`]
//! one uniform `u` that picks the impulse's component: the smallest `k` with `u < C_k` in the
//! table [`cumulative_weights`] (the last component if none), appended after the weight where
//! the isotropic direction would be, so the other orientations keep their draws and bytes.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_level, check_range};

pub(crate) mod builder;
pub use builder::GaborNoiseBuilder;

/// How far a periodic Gabor noise's kernel radius (so its bandwidth) may move to tile the
/// period: 25%, a bandwidth still within a quarter of the model's.
pub const GABOR_PERIOD_TOLERANCE: f64 = 0.25;
/// Fraction of the kernel's peak at which the Gaussian is truncated (Lagae et al. use 0.05):
/// the kernel radius is `r = √(−ln 0.05 / π) / a` and the grid cell size equals `r`.
pub const GABOR_TRUNCATION: f64 = 0.05;

/// `−ln 20 = ln 0.05`, rounded to f32: the Gaussian's exponent at the truncation radius, so on a
/// grid of cells of side `r` the kernel is `exp(NEG_LN_20·d²)` for `d` in cell units (`π a² r² =
/// ln 20`). Shared by Gabor and phasor noise (same truncation).
pub const NEG_LN_20: f32 = -2.995_732_3;

/// Most components a [`Orientation::Spectrum`] table may hold.
pub const MAX_GABOR_COMPONENTS: usize = 1024;

/// Orientation of the kernels' frequency vector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Orientation {
    /// All kernels share one direction, `angle` in radians from the x axis.
    Anisotropic {
        /// Angle of the frequency vector, radians.
        angle: f32,
    },
    /// Each impulse draws its direction uniformly in `[min, max]` radians (`[0, 2π]` is fully
    /// isotropic).
    Isotropic {
        /// Smallest angle, radians.
        min: f32,
        /// Largest angle, radians.
        max: f32,
    },
    /// Gabor noise by example (Galerne, Lagae, Lefebvre & Drettakis 2012): each impulse draws
    /// its frequency vector from a discrete distribution, component `k` with probability
    /// `weights[k] / Σ weights`, so the noise's power spectrum is the weighted sum of the
    /// components' Gaussian lobes. `frequency` (`F₀`) is not used by this orientation (the fit
    /// writes 0).
    Spectrum {
        /// Frequency vectors `(f_x, f_y)`, cycles per pixel, each `|f| ≤ 0.5`.
        frequencies: Vec<[f32; 2]>,
        /// Non-negative weights, one per frequency, not all 0.
        weights: Vec<f32>,
    },
}

/// The cumulative table a [`Orientation::Spectrum`] impulse searches: `C_k = (Σ_{i≤k} w_i) /
/// (Σ_i w_i)`, summed in f64 and rounded to f32 (monotone, as rounding is), the last entry
/// exactly 1. Component `k` is drawn for the uniform `u` when `k` is the number of entries
/// `≤ u` (at most `n − 1`): any search over the monotone table gives the same index, so the CPU
/// and the GPU agree bit for bit.
#[must_use]
pub fn cumulative_weights(weights: &[f32]) -> Vec<f32> {
    let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
    let mut acc = 0.0f64;
    let mut out: Vec<f32> = weights
        .iter()
        .map(|&w| {
            acc += f64::from(w);
            (acc / total) as f32
        })
        .collect();
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    out
}

/// The component a uniform `u ∈ [0, 1)` picks in the table `cumulative` (see
/// [`cumulative_weights`]): the number of entries `≤ u`, at most `len − 1`.
#[must_use]
pub fn pick_component(cumulative: &[f32], u: f32) -> usize {
    cumulative
        .partition_point(|&c| c <= u)
        .min(cumulative.len().saturating_sub(1))
}

/// A Gabor noise: `n(x) = mean + Σ_i w_i · K·exp(−π a²|x − x_i|²)·cos(2π F₀ ω_i·(x − x_i))`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaborNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// Constant added to the noise.
    pub mean: f32,
    /// `K`, the kernel magnitude.
    pub amplitude: f32,
    /// `a`, the Gaussian bandwidth, in 1/pixels.
    pub bandwidth: f32,
    /// `F₀`, the kernel frequency, in cycles per pixel.
    pub frequency: f32,
    /// Direction of the frequency vector.
    pub orientation: Orientation,
    /// Mean number of impulses per kernel footprint (`λ·π r²`, Lagae's "number of impulses per
    /// kernel").
    pub impulses_per_kernel: f32,
}

impl GaborNoise {
    /// Kernel radius `r = √(−ln t / π) / a` for the truncation `t` = [`GABOR_TRUNCATION`].
    #[must_use]
    pub fn kernel_radius(&self) -> f64 {
        (-GABOR_TRUNCATION.ln() / std::f64::consts::PI).sqrt() / f64::from(self.bandwidth)
    }

    /// The kernel radius (and cell side) of this noise made periodic with `period`: `g / m`
    /// with `g` the largest side dividing both `W` and `H` ([`crate::Period::common_side`]) and
    /// `m = max(1, round(g / r))`, so that square cells tile the period; `None` when that
    /// moves `r` (and the bandwidth `a ∝ 1/r`) by more than [`GABOR_PERIOD_TOLERANCE`].
    #[must_use]
    pub fn periodic_radius(&self, period: crate::Period) -> Option<f64> {
        let r = self.kernel_radius();
        let g = f64::from(period.common_side());
        let fitted = g / crate::period::cells_in(g, r) as f64;
        ((fitted / r - 1.0).abs() <= GABOR_PERIOD_TOLERANCE).then_some(fitted)
    }

    /// The largest frequency `|f|` an impulse's kernel may have, cycles per pixel: `F₀`, or
    /// for [`Orientation::Spectrum`] the largest `|f_k|` of the table (zero-weight components
    /// included: a bound, not a statistic).
    #[must_use]
    pub fn largest_frequency(&self) -> f64 {
        match &self.orientation {
            Orientation::Spectrum { frequencies, .. } => frequencies
                .iter()
                .map(|f| f64::from(f[0]).hypot(f64::from(f[1])))
                .fold(0.0, f64::max),
            _ => f64::from(self.frequency),
        }
    }

    /// Mean impulses per grid cell of side `r`: `impulses_per_kernel / π`.
    #[must_use]
    pub fn impulses_per_cell(&self) -> f64 {
        f64::from(self.impulses_per_kernel) / std::f64::consts::PI
    }

    /// Standard deviation of this noise's kernel sum with `K = 1` (the value is
    /// `mean + amplitude·n`, so `amplitude = σ / unit_std_dev()` gives the standard deviation
    /// `σ`).
    ///
    /// By Campbell's theorem the variance of a Poisson sparse convolution is the impulse
    /// density `λ = impulses_per_kernel/(πr²)` times `E[w²] = 1/3` (weights uniform in
    /// `[−1, 1]`) times `∫ e^{−2πa²|x|²} cos²(2πF₀ ω·x) dx` over the kernel's disc of radius
    /// `r` ([`Self::kernel_radius`]). The integral does not depend on the direction `ω` (the
    /// disc and the Gaussian are rotation-invariant), so it is taken along `x`, by the midpoint
    /// rule on a 400 × 400 grid over the disc's bounding square (about 10⁻⁶ from the exact
    /// value; a test compares it with a polar integration).
    ///
    /// For [`Orientation::Spectrum`] the integral depends on each component's `|f_k|`, and the
    /// variance is their average weighted by the draw probabilities `w_k / Σ w` (Campbell's
    /// theorem over the mark distribution); the same midpoint grid is summed over `y` first, so
    /// each component costs one pass over the 400 columns.
    #[must_use]
    pub fn unit_std_dev(&self) -> f64 {
        if let Orientation::Spectrum {
            frequencies,
            weights,
        } = &self.orientation
        {
            return self.spectrum_unit_std_dev(frequencies, weights);
        }
        let r = self.kernel_radius();
        let a = f64::from(self.bandwidth);
        let f = f64::from(self.frequency);
        let n = 400;
        let h = 2.0 * r / n as f64;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (-r + (i as f64 + 0.5) * h, -r + (j as f64 + 0.5) * h);
                let d2 = x * x + y * y;
                if d2 <= r * r {
                    let c = (2.0 * std::f64::consts::PI * f * x).cos();
                    integral += (-2.0 * std::f64::consts::PI * a * a * d2).exp() * c * c * h * h;
                }
            }
        }
        let density = f64::from(self.impulses_per_kernel) / (std::f64::consts::PI * r * r);
        (density * integral / 3.0).sqrt()
    }

    fn spectrum_unit_std_dev(&self, frequencies: &[[f32; 2]], weights: &[f32]) -> f64 {
        let r = self.kernel_radius();
        let a = f64::from(self.bandwidth);
        let n = 400;
        let h = 2.0 * r / n as f64;
        // column[i] = Σ_j h² e^{−2πa²|x|²} over the disc: the integrand without its cosine.
        let column: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let x = -r + (i as f64 + 0.5) * h;
                let mut sum = 0.0;
                for j in 0..n {
                    let y = -r + (j as f64 + 0.5) * h;
                    let d2 = x * x + y * y;
                    if d2 <= r * r {
                        sum += (-2.0 * std::f64::consts::PI * a * a * d2).exp() * h * h;
                    }
                }
                (x, sum)
            })
            .collect();
        let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
        let mut integral = 0.0;
        for (f, &w) in frequencies.iter().zip(weights) {
            if w <= 0.0 {
                continue;
            }
            let f = f64::from(f[0]).hypot(f64::from(f[1]));
            let one: f64 = column
                .iter()
                .map(|&(x, g)| {
                    let c = (2.0 * std::f64::consts::PI * f * x).cos();
                    g * c * c
                })
                .sum();
            integral += f64::from(w) / total * one;
        }
        let density = f64::from(self.impulses_per_kernel) / (std::f64::consts::PI * r * r);
        (density * integral / 3.0).sqrt()
    }

    /// Checks every number.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_level(|| "gabor.mean".into(), self.mean)?;
        check_range(
            || "gabor.amplitude".into(),
            f64::from(self.amplitude),
            0.0,
            1e9,
            "[0, 1e9]",
        )?;
        check_range(
            || "gabor.bandwidth".into(),
            f64::from(self.bandwidth),
            1e-3,
            10.0,
            "[0.001, 10] per pixel",
        )?;
        check_range(
            || "gabor.frequency".into(),
            f64::from(self.frequency),
            0.0,
            0.5,
            "[0, 0.5] cycles per pixel",
        )?;
        check_range(
            || "gabor.impulses_per_kernel".into(),
            f64::from(self.impulses_per_kernel),
            0.01,
            1000.0,
            "[0.01, 1000]",
        )?;
        match &self.orientation {
            &Orientation::Anisotropic { angle } => check_range(
                || "gabor.orientation.anisotropic.angle".into(),
                f64::from(angle),
                -1e3,
                1e3,
                "[-1000, 1000] radians",
            ),
            &Orientation::Isotropic { min, max } => {
                check_range(
                    || "gabor.orientation.isotropic.min".into(),
                    f64::from(min),
                    -1e3,
                    1e3,
                    "[-1000, 1000] radians",
                )?;
                check_range(
                    || "gabor.orientation.isotropic.max".into(),
                    f64::from(max),
                    f64::from(min),
                    1e3,
                    "[min, 1000] radians",
                )
            }
            Orientation::Spectrum {
                frequencies,
                weights,
            } => validate_spectrum(frequencies, weights),
        }
    }
}

/// The checks of an [`Orientation::Spectrum`] table.
fn validate_spectrum(frequencies: &[[f32; 2]], weights: &[f32]) -> Result<(), ModelError> {
    const AT: &str = "gabor.orientation.spectrum";
    check_len(
        || format!("{AT}.frequencies"),
        frequencies.len(),
        1,
        MAX_GABOR_COMPONENTS,
        "1 to 1024 components",
    )?;
    check_len(
        || format!("{AT}.weights"),
        weights.len(),
        frequencies.len(),
        frequencies.len(),
        "as many entries as frequencies",
    )?;
    for (k, f) in frequencies.iter().enumerate() {
        for (c, v) in f.iter().enumerate() {
            check_range(
                || format!("{AT}.frequencies[{k}][{c}]"),
                f64::from(*v),
                -0.5,
                0.5,
                "[-0.5, 0.5] cycles per pixel",
            )?;
        }
        let norm = f64::from(f[0]).hypot(f64::from(f[1]));
        check_range(
            || format!("{AT}.frequencies[{k}] (its length |f|)"),
            norm,
            0.0,
            0.5,
            "[0, 0.5] cycles per pixel",
        )?;
    }
    for (k, w) in weights.iter().enumerate() {
        check_range(
            || format!("{AT}.weights[{k}]"),
            f64::from(*w),
            0.0,
            1e30,
            "[0, 1e30]",
        )?;
    }
    let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
    if total <= 0.0 {
        return Err(ModelError::OutOfRange {
            field: format!("{AT}.weights (their sum)"),
            value: total,
            range: "(0, 1e30·1024]: at least one weight must be positive",
        });
    }
    Ok(())
}

impl crate::ModelKind for GaborNoise {
    const PERIODIC: bool = true;

    /// A period whose common side (the gcd of `W` and `H`) holds a whole number of cells of
    /// about the kernel radius ([`GaborNoise::periodic_radius`]).
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        if self.periodic_radius(period).is_some() {
            return Ok(());
        }
        Err(ModelError::Period {
            period: period.to_string(),
            kind: "gabor",
            requirement: format!(
                "its kernel radius {:.2} pixels must become a divisor of gcd(W, H) = {} within \
                 25%; take a period whose sides share a large common divisor (a square one, or \
                 multiples of {})",
                self.kernel_radius(),
                period.common_side(),
                self.kernel_radius().ceil()
            ),
        })
    }

    const NAME: &'static str = "gabor";

    fn validate(&self) -> Result<(), ModelError> {
        GaborNoise::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// `J₀(z) = (1/π) ∫₀^π cos(z sin t) dt` by Simpson's rule.
    fn bessel_j0(z: f64) -> f64 {
        let n = 256;
        let h = PI / f64::from(n);
        let sum: f64 = (0..=n)
            .map(|k| {
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * (z * (f64::from(k) * h).sin()).cos()
            })
            .sum();
        sum * h / 3.0 / PI
    }

    /// The variance with `K = 1` integrated in polar coordinates, independently of the
    /// Cartesian grid of `unit_std_dev`: the angular integral of `cos²(2πFρ cos θ)` is
    /// `π(1 + J₀(4πFρ))`, and the radial one runs over `[0, r]` by Simpson's rule.
    fn polar_variance(g: &GaborNoise) -> f64 {
        let r = g.kernel_radius();
        let a = f64::from(g.bandwidth);
        let f = f64::from(g.frequency);
        let n = 2000;
        let h = r / f64::from(n);
        let integrand = |rho: f64| {
            (-2.0 * PI * a * a * rho * rho).exp() * rho * PI * (1.0 + bessel_j0(4.0 * PI * f * rho))
        };
        let integral: f64 = (0..=n)
            .map(|k| {
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * integrand(f64::from(k) * h)
            })
            .sum::<f64>()
            * h
            / 3.0;
        f64::from(g.impulses_per_kernel) / (PI * r * r) * integral / 3.0
    }

    fn noise(bandwidth: f32, frequency: f32, impulses_per_kernel: f32) -> GaborNoise {
        GaborNoise {
            seed: 0,
            mean: 0.0,
            amplitude: 1.0,
            bandwidth,
            frequency,
            orientation: Orientation::Isotropic {
                min: 0.0,
                max: std::f32::consts::TAU,
            },
            impulses_per_kernel,
        }
    }

    pub fn unit_std_dev_matches_a_polar_integration() {
        for (a, f, n) in [
            (0.05, 0.0625, 32.0),
            (0.05, 0.0, 16.0),
            (0.02, 0.01, 8.0),
            (0.2, 0.4, 100.0),
            (0.01, 0.005, 1.0),
        ] {
            let g = noise(a, f, n);
            let grid = g.unit_std_dev();
            let polar = polar_variance(&g).sqrt();
            let rel = (grid / polar - 1.0).abs();
            assert!(
                rel < 1e-4,
                "a = {a}, F0 = {f}, N = {n}: grid {grid}, polar {polar}, rel {rel:e}"
            );
        }
    }

    /// A spectrum table's variance is the draw-weighted average of each component's polar
    /// variance (Campbell's theorem over the marks), the components' directions irrelevant.
    pub fn spectrum_unit_std_dev_is_the_weighted_polar_variance() {
        let freqs = [[0.1f32, 0.0], [0.0, -0.25], [0.03, 0.04], [0.3, 0.3]];
        let weights = [1.0f32, 3.0, 0.0, 2.0];
        let mut g = noise(0.05, 0.0, 20.0);
        g.orientation = Orientation::Spectrum {
            frequencies: freqs.to_vec(),
            weights: weights.to_vec(),
        };
        g.validate().unwrap();
        let mut want = 0.0;
        for (f, w) in freqs.iter().zip(weights) {
            let one = noise(0.05, f64::from(f[0]).hypot(f64::from(f[1])) as f32, 20.0);
            want += f64::from(w) / 6.0 * polar_variance(&one);
        }
        let rel = (g.unit_std_dev() / want.sqrt() - 1.0).abs();
        assert!(
            rel < 1e-4,
            "grid {} polar {}, rel {rel:e}",
            g.unit_std_dev(),
            want.sqrt()
        );
    }

    pub fn spectrum_tables_are_checked_with_field_paths() {
        let spectrum = |frequencies: Vec<[f32; 2]>, weights: Vec<f32>| {
            let mut g = noise(0.05, 0.0, 20.0);
            g.orientation = Orientation::Spectrum {
                frequencies,
                weights,
            };
            g.validate()
        };
        let at = "gabor.orientation.spectrum";
        let cases = [
            (spectrum(vec![], vec![]), format!("{at}.frequencies")),
            (spectrum(vec![[0.1, 0.0]], vec![]), format!("{at}.weights")),
            (
                spectrum(vec![[0.1, f32::NAN]], vec![1.0]),
                format!("{at}.frequencies[0][1]"),
            ),
            (
                spectrum(vec![[0.1, 0.0], [0.4, 0.4]], vec![1.0, 1.0]),
                format!("{at}.frequencies[1] (its length |f|)"),
            ),
            (
                spectrum(vec![[0.1, 0.0], [0.2, 0.0]], vec![1.0, -1.0]),
                format!("{at}.weights[1]"),
            ),
            (
                spectrum(vec![[0.1, 0.0]], vec![0.0]),
                format!("{at}.weights (their sum)"),
            ),
            (
                spectrum(
                    vec![[0.0, 0.0]; MAX_GABOR_COMPONENTS + 1],
                    vec![1.0; MAX_GABOR_COMPONENTS + 1],
                ),
                format!("{at}.frequencies"),
            ),
        ];
        for (result, field) in cases {
            match result {
                Err(
                    ModelError::OutOfRange { field: f, .. } | ModelError::Length { field: f, .. },
                ) => {
                    assert_eq!(f, field);
                }
                other => panic!("{field}: {other:?}"),
            }
        }
    }

    /// The cumulative table ends at 1, skips zero weights and picks by counting entries ≤ u.
    pub fn components_are_picked_from_the_cumulative_table() {
        let c = cumulative_weights(&[1.0, 0.0, 3.0]);
        assert_eq!(c, vec![0.25, 0.25, 1.0]);
        assert_eq!(pick_component(&c, 0.0), 0);
        assert_eq!(pick_component(&c, 0.2499), 0);
        assert_eq!(pick_component(&c, 0.25), 2);
        assert_eq!(pick_component(&c, 0.999_999_9), 2);
        assert_eq!(pick_component(&[1.0], 0.5), 0);
    }

    pub fn unit_std_dev_at_zero_frequency_has_a_closed_form() {
        // F₀ = 0: ∫_disc e^{−2πa²|x|²} dx = (1 − e^{−2πa²r²})/(2a²) and πa²r² = ln 20, so
        // the variance is λ/3 · (1 − 1/400)/(2a²) with λ = N/(πr²).
        let g = noise(0.05, 0.0, 16.0);
        let (a, r) = (f64::from(g.bandwidth), g.kernel_radius());
        let closed = (16.0 / (PI * r * r) / 3.0 * (1.0 - 1.0 / 400.0) / (2.0 * a * a)).sqrt();
        let rel = (g.unit_std_dev() / closed - 1.0).abs();
        assert!(
            rel < 1e-4,
            "grid {} closed form {closed}, rel {rel:e}",
            g.unit_std_dev()
        );
    }
}
