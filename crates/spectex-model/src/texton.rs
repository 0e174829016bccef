//! Texton placement and spot noise (survey Dong et al. 2020, §2.3 "Texton Placement" and §3.1.5
//! "Spot Noise"): a texton — an ellipsoid of Eq. (6), a truncated Gaussian spot, or a small
//! image — placed on a jittered grid or at Poisson points, each with a random rotation, scale and
//! intensity, combined by the survey's addition or maximum rule (§2.3.3).
//!
//! # Definition
//!
//! A position `p` (pixels) is split per axis into its cell of side `C` and an f32 offset in
//! `[0, 1)` ([`crate::grid::locate_cell`]), so positions near 10⁷ keep their precision. Every
//! cell `(i, j)` within [`TextonNoise::reach`] cells of `p`'s, rows (`j`) outer and columns
//! inner, seeds `Prng::new(cell_hash(i, j, TEXTON_LAYER, seed))` and draws, in this order:
//! for Poisson placement one uniform `u`, the count being the number of `k < MAX_TEXTONS_PER_CELL`
//! with `u ≥ P(N ≤ k)` (the CDF rounded to f32; 1 point for grid placement); then per point its
//! offsets `o_x`, `o_y` (grid: `½ + jitter·(u − ½)`; Poisson: `u`), rotation `θ` (turns), scale
//! `s` and weight `w`, each `lo + (hi − lo)·u` over its range. The point's texton then reads
//!
//! ```text
//! (d_x, d_y) = ((f_x − (di + o_x))·C, (f_y − (dj + o_y))·C)      di, dj: cell − p's cell
//! u = cos θ·d_x + sin θ·d_y,   v = cos θ·d_y − sin θ·d_x           (texton axes turned by θ)
//! (q_u, q_v) = (u / (a·s), v / (b·s)),   ρ² = q_u² + q_v²
//! ```
//!
//! and contributes `w·g(q_u, q_v)` where `ρ² < 1` (nothing elsewhere), with `g` the
//! [`Spot`]: the ellipsoid of semi-axes `a`, `b` and height 1, `√(1 − ρ²)` (Eq. (6) prints as
//! `c²(1 − (row²/a² + col²/b²))` in the text we have, which is the square of that height up to
//! the constant; we take the ellipsoid's own height, which is what "an ellipsoid of height c"
//! places, and let the weight range play `c`); the Gaussian spot `exp(−ln 20·ρ²)`, truncated at
//! 5% of its peak like Gabor kernels; or a grey image stretched over the texton's box
//! `[−1, 1]²` and sampled bilinearly (texel centres at `((k + ½)/W)·2 − 1`, edges clamped).
//! The addition rule sums the contributions; the maximum rule keeps the largest, over a canvas
//! of 0 (so where no texton lies, and under negative weights, the value is 0). The value is
//! `mean + combined`.
//!
//! Every expression above is f32 with plain `*` and `+`, cosines by
//! [`crate::math::cos_turns`]/[`sin_turns`](crate::math::sin_turns), the Gaussian by
//! [`crate::math::exp_poly`], the square root by IEEE `sqrt` (correctly rounded on the CPU and
//! in WGSL's SPIR-V lowering on the adapters we test), so the WGSL twin can match bit for bit.

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_image, check_level, check_range};
use crate::math::{cos_turns, exp_poly, sin_turns};
use crate::random::{Prng, cell_hash};

pub(crate) mod builder;
pub use builder::TextonNoiseBuilder;

/// The random layer of texton cells ("TEXT").
pub const TEXTON_LAYER: u32 = 0x5445_5854;
/// Most textons in one cell (the cap of the Poisson count).
pub const MAX_TEXTONS_PER_CELL: u32 = 16;
/// Largest mean of the Poisson count, textons per cell.
pub const MAX_DENSITY: f32 = 8.0;
/// Most cells a texton reaches beyond its own in each direction: `(2·3 + 1)² = 49` cells per
/// pixel at most, which bounds the cost of a pixel.
pub const MAX_REACH: u32 = 3;
/// Largest side of an image texton, texels.
pub const MAX_IMAGE_SIDE: u32 = crate::error::MAX_IMAGE_SIDE;
/// Largest scale factor of a texton.
pub const MAX_SCALE: f32 = 16.0;

/// What is placed: the texton's shape `g` over its normalised coordinates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Spot {
    /// The ellipsoid of Eq. (6) with height 1: `√(1 − ρ²)`.
    Ellipsoid,
    /// A Gaussian spot `exp(−ln 20·ρ²)`, truncated at `ρ = 1` (5% of its peak).
    Gaussian,
    /// A grey image stretched over the texton's box, sampled bilinearly.
    Image {
        /// Texels per row (`1..=1024`).
        width: u32,
        /// Rows (`1..=1024`).
        height: u32,
        /// `width·height` values, row-major, top row first.
        values: Vec<f32>,
    },
}

/// Where textons go (survey §2.3.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Placement {
    /// One texton per cell, at the centre moved by `jitter·(u − ½)` cells per axis: 0 is the
    /// survey's regular grid, more its random grid.
    Grid {
        /// In `[0, 1]`.
        jitter: f32,
    },
    /// A Poisson number of textons per cell (this mean, `(0, 8]`), uniformly placed: spot
    /// noise's random positions.
    Poisson {
        /// Mean textons per cell.
        density: f32,
    },
}

/// How overlapping textons combine (survey §2.3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Combine {
    /// The addition rule: contributions add up.
    Sum,
    /// The maximum rule: the largest contribution, over a canvas of 0.
    Max,
}

/// Texton placement / spot noise (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextonNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// `C`, the cell side in pixels, in `[1, 4096]`.
    pub cell_size: f32,
    /// Where textons go.
    pub placement: Placement,
    /// What is placed.
    pub spot: Spot,
    /// `(a, b)`, the texton's semi-axes in pixels before scaling (along its own x and y).
    pub radii: [f32; 2],
    /// Range of the rotation `θ`, turns (`[0, 1]` is every direction).
    pub rotation: [f32; 2],
    /// Range of the scale `s`, in `(0, 16]`.
    pub scale: [f32; 2],
    /// Range of the weight `w` (the survey's height `c`).
    pub intensity: [f32; 2],
    /// Addition or maximum rule.
    pub combine: Combine,
    /// Constant added to the combined textons.
    pub mean: f32,
}

/// Linear interpolation `lo + (hi − lo)·u` of a range, the one expression every evaluator uses.
#[inline]
#[must_use]
pub fn lerp_range(range: [f32; 2], u: f32) -> f32 {
    range[0] + (range[1] - range[0]) * u
}

/// One placed texton of a cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texton {
    /// Offsets `(o_x, o_y)` in the cell, cell units.
    pub offset: [f32; 2],
    /// `(cos θ, sin θ)`.
    pub rotation: [f32; 2],
    /// `(1/(a·s), 1/(b·s))`.
    pub inv_axes: [f32; 2],
    /// `w`.
    pub weight: f32,
}

impl TextonNoise {
    /// Cells beyond a pixel's own that its textons can reach: `⌈max(a, b)·max s / C⌉`.
    #[must_use]
    pub fn reach(&self) -> i32 {
        (self.support_radius() / f64::from(self.cell_size))
            .ceil()
            .max(0.0) as i32
    }

    /// The largest distance from its centre at which a texton contributes, pixels:
    /// `max(a, b)·max s`.
    #[must_use]
    pub fn support_radius(&self) -> f64 {
        f64::from(self.radii[0].max(self.radii[1])) * f64::from(self.scale[0].max(self.scale[1]))
    }

    /// The Poisson CDF `P(N ≤ k)`, `k < MAX_TEXTONS_PER_CELL`, rounded to f32 (f64 sums), or
    /// `None` for grid placement.
    #[must_use]
    pub fn poisson_cdf(&self) -> Option<[f32; MAX_TEXTONS_PER_CELL as usize]> {
        let Placement::Poisson { density } = self.placement else {
            return None;
        };
        Some(crate::random::poisson_cdf(f64::from(density)))
    }

    /// Calls `visit` with the textons of cell `(i, j)`, in draw order (module docs).
    pub fn cell_textons(
        &self,
        i: i32,
        j: i32,
        cdf: Option<&[f32; MAX_TEXTONS_PER_CELL as usize]>,
        mut visit: impl FnMut(Texton),
    ) {
        let mut prng = Prng::new(cell_hash(i, j, TEXTON_LAYER, self.seed));
        let count = match cdf {
            Some(cdf) => {
                let u = prng.next_f32();
                cdf.iter().filter(|&&c| u >= c).count()
            }
            None => 1,
        };
        for _ in 0..count {
            let (ox, oy) = match self.placement {
                Placement::Grid { jitter } => {
                    let ox = 0.5 + jitter * (prng.next_f32() - 0.5);
                    let oy = 0.5 + jitter * (prng.next_f32() - 0.5);
                    (ox, oy)
                }
                Placement::Poisson { .. } => (prng.next_f32(), prng.next_f32()),
            };
            let turns = lerp_range(self.rotation, prng.next_f32());
            let scale = lerp_range(self.scale, prng.next_f32());
            let weight = lerp_range(self.intensity, prng.next_f32());
            visit(Texton {
                offset: [ox, oy],
                rotation: [cos_turns(turns), sin_turns(turns)],
                inv_axes: [1.0 / (self.radii[0] * scale), 1.0 / (self.radii[1] * scale)],
                weight,
            });
        }
    }

    /// The contribution of `texton` at the offset `(t_x, t_y)` = `f − (d + o)` in cell units
    /// (module docs), before the weight; 0 outside its support.
    #[inline]
    #[must_use]
    pub fn spot_at(&self, texton: &Texton, tx: f32, ty: f32) -> f32 {
        let dx = tx * self.cell_size;
        let dy = ty * self.cell_size;
        let [c, s] = texton.rotation;
        let u = c * dx + s * dy;
        let v = c * dy - s * dx;
        let qu = u * texton.inv_axes[0];
        let qv = v * texton.inv_axes[1];
        let r2 = qu * qu + qv * qv;
        if r2 >= 1.0 {
            return 0.0;
        }
        match &self.spot {
            Spot::Ellipsoid => (1.0 - r2).sqrt(),
            Spot::Gaussian => exp_poly(crate::NEG_LN_20 * r2),
            Spot::Image {
                width,
                height,
                values,
            } => bilinear(values, *width, *height, qu, qv),
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "texton.cell_size".into(),
            f64::from(self.cell_size),
            1.0,
            4096.0,
            "[1, 4096] pixels",
        )?;
        match self.placement {
            Placement::Grid { jitter } => check_range(
                || "texton.placement.grid.jitter".into(),
                f64::from(jitter),
                0.0,
                1.0,
                "[0, 1]",
            )?,
            Placement::Poisson { density } => {
                check_range(
                    || "texton.placement.poisson.density".into(),
                    f64::from(density),
                    0.0,
                    f64::from(MAX_DENSITY),
                    "(0, 8] textons per cell",
                )?;
                if density <= 0.0 {
                    return Err(ModelError::OutOfRange {
                        field: "texton.placement.poisson.density".into(),
                        value: f64::from(density),
                        range: "(0, 8] textons per cell",
                    });
                }
            }
        }
        if let Spot::Image {
            width,
            height,
            values,
        } = &self.spot
        {
            check_image(
                "texton.spot.image",
                *width,
                *height,
                "values",
                values.as_chunks::<1>().0,
            )?;
        }
        for (k, &r) in self.radii.iter().enumerate() {
            check_range(
                || format!("texton.radii[{k}]"),
                f64::from(r),
                1e-3,
                65_536.0,
                "[0.001, 65536] pixels",
            )?;
        }
        for (k, &t) in self.rotation.iter().enumerate() {
            check_range(
                || format!("texton.rotation[{k}]"),
                f64::from(t),
                -1e4,
                1e4,
                "[-1e4, 1e4] turns",
            )?;
        }
        for (k, &s) in self.scale.iter().enumerate() {
            check_range(
                || format!("texton.scale[{k}]"),
                f64::from(s),
                1e-3,
                f64::from(MAX_SCALE),
                "[0.001, 16]",
            )?;
        }
        for (k, &w) in self.intensity.iter().enumerate() {
            check_level(|| format!("texton.intensity[{k}]"), w)?;
        }
        check_level(|| "texton.mean".into(), self.mean)?;
        let reach = self.reach();
        if reach > MAX_REACH as i32 {
            return Err(ModelError::OutOfRange {
                field: "texton.radii".into(),
                value: self.support_radius(),
                range: "max(radii)·max(scale) ≤ 3·cell_size (a texton reaches 3 cells at most)",
            });
        }
        Ok(())
    }

    /// Expected textons visited per pixel: `(2·reach + 1)²` cells times the textons per cell.
    #[must_use]
    pub fn textons_per_pixel(&self) -> f64 {
        let side = f64::from(2 * self.reach() + 1);
        let per_cell = match self.placement {
            Placement::Grid { .. } => 1.0,
            Placement::Poisson { density } => f64::from(density),
        };
        side * side * per_cell
    }
}

/// Bilinear sample of a `width × height` image stretched over `[−1, 1]²` at `(qu, qv)`, texel
/// centres at `((k + ½)/W)·2 − 1`, indices clamped to the edges.
#[inline]
#[must_use]
pub fn bilinear(values: &[f32], width: u32, height: u32, qu: f32, qv: f32) -> f32 {
    let x = (qu + 1.0) * 0.5 * width as f32 - 0.5;
    let y = (qv + 1.0) * 0.5 * height as f32 - 0.5;
    let x0 = x.floor();
    let y0 = y.floor();
    let fx = x - x0;
    let fy = y - y0;
    let clamp = |k: f32, n: u32| (k.max(0.0) as u32).min(n - 1) as usize;
    let (xa, xb) = (clamp(x0, width), clamp(x0 + 1.0, width));
    let (ya, yb) = (clamp(y0, height), clamp(y0 + 1.0, height));
    let w = width as usize;
    let top = values[ya * w + xa] + (values[ya * w + xb] - values[ya * w + xa]) * fx;
    let bottom = values[yb * w + xa] + (values[yb * w + xb] - values[yb * w + xa]) * fx;
    top + (bottom - top) * fy
}

impl From<TextonNoise> for crate::Model {
    fn from(model: TextonNoise) -> Self {
        Self::Texton(model)
    }
}

impl crate::ModelKind for TextonNoise {
    const PERIODIC: bool = true;

    const NAME: &'static str = "texton";

    /// A period that is a whole number of cells along x and y: the cells wrap.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let side = f64::from(self.cell_size);
        if period.sides().iter().all(|&p| p % side == 0.0) {
            return Ok(());
        }
        Err(ModelError::Period {
            period: period.to_string(),
            kind: "texton",
            requirement: format!(
                "its cell of {side} pixels must divide the period's width and height"
            ),
        })
    }

    fn validate(&self) -> Result<(), ModelError> {
        TextonNoise::validate(self)
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

    pub fn defaults_validate_and_reach_one_cell() {
        let t = TextonNoise::default();
        t.validate().expect("defaults are valid");
        // 14 px · 1.25 = 17.5 px < 32 px.
        assert_eq!(t.reach(), 1);
        assert!((t.textons_per_pixel() - 9.0).abs() < 1e-12);
    }

    pub fn validation_names_the_field_and_range() {
        let cases: Vec<(TextonNoise, &str)> = vec![
            (
                TextonNoise {
                    cell_size: 0.5,
                    ..TextonNoise::default()
                },
                "texton.cell_size",
            ),
            (
                TextonNoise {
                    radii: [200.0, 7.0],
                    ..TextonNoise::default()
                },
                "texton.radii",
            ),
            (
                TextonNoise {
                    scale: [f32::NAN, 1.0],
                    ..TextonNoise::default()
                },
                "texton.scale[0]",
            ),
            (
                TextonNoise {
                    placement: Placement::Poisson { density: 0.0 },
                    ..TextonNoise::default()
                },
                "texton.placement.poisson.density",
            ),
            (
                TextonNoise {
                    spot: Spot::Image {
                        width: 2,
                        height: 2,
                        values: vec![0.0; 3],
                    },
                    ..TextonNoise::default()
                },
                "texton.spot.image.values",
            ),
            (
                TextonNoise {
                    spot: Spot::Image {
                        width: 1,
                        height: 1,
                        values: vec![f32::INFINITY],
                    },
                    ..TextonNoise::default()
                },
                "texton.spot.image.values[0]",
            ),
        ];
        for (model, field) in cases {
            let err = model.validate().expect_err(field);
            assert!(err.to_string().starts_with(field), "{field}: {err}");
        }
    }

    pub fn poisson_counts_follow_the_pmf() {
        // Independent estimate: the mean count over many cells equals λ (capped at 16, where the
        // tail beyond is below 1e-9 for λ = 3).
        let t = TextonNoise {
            placement: Placement::Poisson { density: 3.0 },
            ..TextonNoise::default()
        };
        let cdf = t.poisson_cdf().expect("poisson");
        let mut total = 0usize;
        let cells = 40_000;
        for k in 0..cells {
            t.cell_textons(k % 200, k / 200, Some(&cdf), |_| total += 1);
        }
        let mean = total as f64 / f64::from(cells);
        // Standard error √(3/40000) ≈ 0.0087; 5 sigma.
        assert!((mean - 3.0).abs() < 0.045, "mean count {mean}");
    }

    pub fn ellipsoid_height_and_support() {
        let t = TextonNoise {
            radii: [10.0, 5.0],
            ..TextonNoise::default()
        };
        let texton = Texton {
            offset: [0.5, 0.5],
            rotation: [1.0, 0.0],
            inv_axes: [0.1, 0.2],
            weight: 1.0,
        };
        let c = t.cell_size;
        // At the centre the height is 1; at (a/2, 0) it is √(1 − ¼).
        assert_eq!(t.spot_at(&texton, 0.0, 0.0), 1.0);
        let half = t.spot_at(&texton, 5.0 / c, 0.0);
        assert!((half - 0.75f32.sqrt()).abs() < 1e-6, "{half}");
        // Just outside b along y, nothing.
        assert_eq!(t.spot_at(&texton, 0.0, 5.01 / c), 0.0);
        // A quarter turn swaps the axes: (0, a/2) now gives the same height.
        let turned = Texton {
            rotation: [0.0, 1.0],
            ..texton
        };
        let v = t.spot_at(&turned, 0.0, 5.0 / c);
        assert!((v - 0.75f32.sqrt()).abs() < 1e-6, "{v}");
    }

    pub fn bilinear_reproduces_texels_and_interpolates() {
        let values = [0.0, 1.0, 2.0, 3.0];
        // Texel (0, 0)'s centre is at qu = qv = −½.
        assert_eq!(bilinear(&values, 2, 2, -0.5, -0.5), 0.0);
        assert_eq!(bilinear(&values, 2, 2, 0.5, 0.5), 3.0);
        // Halfway between the four centres: their mean.
        assert!((bilinear(&values, 2, 2, 0.0, 0.0) - 1.5).abs() < 1e-6);
        // Clamped beyond the centres.
        assert_eq!(bilinear(&values, 2, 2, -0.99, -0.99), 0.0);
    }
}
