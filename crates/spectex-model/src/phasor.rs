//! Phasor noise (Tricard et al. 2019): the instantaneous phase of a complex Gabor noise, fed to
//! an oscillation profile.
//!
//! The complex Gabor noise is `𝒢(x) = Σ_j a(x − x_j)·exp(i·2π(F_j u_j·(x − x_j) + ψ_j))` (Eqs.
//! 10, 15, with a uniform phase offset `ψ_j` per kernel, see spectex-cpu's `phasor.rs`)
//! with the Gaussian `a(x) = exp(−π b²|x|²)` (Eq. 6) truncated where it falls below
//! [`PHASOR_TRUNCATION`] of its peak; the impulses `x_j` are a Poisson process. Its modulus is the
//! intensity `I` (Eq. 8), its argument the phasor noise `φ` (Eq. 9), `Im 𝒢 = I·sin φ` is Gabor
//! noise (Eq. 13) and `sin φ` the phasor sine wave (Eq. 3). A profile `f` of period one turn
//! shapes the oscillations (Eq. 4, §3.3).
//!
//! Every parameter that the paper grades spatially (§4.1) is a [`Field`]: a constant, an
//! analytic linear ramp, or a greyscale image mapped to a range. Kernel parameters (frequency,
//! orientation) are read at each kernel's centre `x_j`; profile parameters (duty cycle, the
//! blend between two profiles) at the evaluated point.
//!
//! Its draws (layer 0 the kernels, layer 1 the coherent direction process) are specified in
//! [`crate::phasor_kernels`].

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_level, check_range};

pub(crate) mod builder;
pub use builder::PhasorNoiseBuilder;

/// Fraction of its peak at which the Gaussian kernel is truncated (as for Gabor noise, Lagae et
/// al. 2009): the kernel radius is `r = √(−ln 0.05 / π) / b`, the grid cell side.
pub const PHASOR_TRUNCATION: f64 = 0.05;

/// The paper's locally coherent isotropic setting (§3.2.2): directions drawn within `±2.4` rad.
pub const COHERENT_SPREAD: f32 = 2.4;
/// The paper's locally coherent isotropic setting: `b_f = b / 2`.
pub const COHERENT_BANDWIDTH_RATIO: f32 = 0.5;

/// How far a periodic phasor noise's cell sides (so its kernels' bandwidth) may move to tile
/// the period: 25%, as for Gabor noise.
pub const PHASOR_PERIOD_TOLERANCE: f64 = 0.25;

/// Positions at which linear fields are checked to stay in range, pixels: a ramp must keep its
/// values valid over `|x|, |y|, |z| ≤ RAMP_EXTENT`.
pub const RAMP_EXTENT: f64 = 1.0e4;

/// Largest side of an image field, pixels.
pub const MAX_FIELD_SIDE: usize = 4096;
/// Most samples of a sampled profile, and most harmonics of an additive one.
pub const MAX_PROFILE_SAMPLES: usize = 4096;

/// A scalar parameter over space.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Field {
    /// The same value everywhere.
    Constant {
        /// The value.
        value: f32,
    },
    /// `value + gradient·x` (per pixel), an analytic ramp; `gradient` has a z component used by
    /// 3D evaluation.
    Linear {
        /// Value at the origin.
        value: f32,
        /// Change per pixel along x, y, z.
        gradient: [f32; 3],
    },
    /// A greyscale image (values in `[0, 1]`, row-major) stretched over `[0, width·pixel_size] ×
    /// [0, height·pixel_size]` and repeated periodically, bilinearly interpolated, mapped to
    /// `min + grey·(max − min)`.
    Image {
        /// Image width, samples.
        width: usize,
        /// Image height, samples.
        height: usize,
        /// Grey levels in `[0, 1]`, `width·height` of them, row-major, row 0 at y = 0.
        grey: Vec<f32>,
        /// Output pixels per image sample.
        pixel_size: f32,
        /// Value at grey 0.
        min: f32,
        /// Value at grey 1.
        max: f32,
    },
}

impl Field {
    /// A constant field.
    #[must_use]
    pub const fn constant(value: f32) -> Self {
        Self::Constant { value }
    }

    /// The field at `(x, y, z)` pixels, in f64 (evaluators may round the result to f32).
    #[must_use]
    pub fn at(&self, x: f64, y: f64, z: f64) -> f64 {
        match self {
            Self::Constant { value } => f64::from(*value),
            Self::Linear { value, gradient } => {
                f64::from(*value)
                    + f64::from(gradient[0]) * x
                    + f64::from(gradient[1]) * y
                    + f64::from(gradient[2]) * z
            }
            Self::Image {
                width,
                height,
                grey,
                pixel_size,
                min,
                max,
            } => {
                let size = f64::from(*pixel_size);
                let (column, row) = (tap(x, *width, size), tap(y, *height, size));
                image_value(grey, *width, column, row, [*min, *max])
            }
        }
    }

    /// An image field's taps along one axis (`axis` 0: columns at `x = c`, 1: rows at
    /// `y = c`): the two samples [`at`](Self::at) interpolates between and its fraction, as
    /// `(i0, i1, t)`; `None` for other fields or a position that is not finite (where `at`
    /// reads sample 0). The axes are independent, so an evaluator on a grid of positions
    /// locates each column and each row once and interpolates per pixel.
    #[must_use]
    pub fn image_tap(&self, c: f64, axis: usize) -> Option<(usize, usize, f64)> {
        let Self::Image {
            width,
            height,
            pixel_size,
            ..
        } = self
        else {
            return None;
        };
        let n = if axis == 0 { *width } else { *height };
        tap(c, n, f64::from(*pixel_size)).map(|t| (t.i0, t.i1, t.t))
    }

    /// The image field's gradient direction at `(x, y)` in radians (`atan2` of the grey level's
    /// central differences), or `None` for other fields or a flat spot.
    #[must_use]
    pub fn gradient_angle(&self, x: f64, y: f64) -> Option<f64> {
        let Self::Image {
            width,
            height,
            grey,
            pixel_size,
            ..
        } = self
        else {
            return None;
        };
        let h = f64::from(*pixel_size);
        let g = |x: f64, y: f64| bilinear_periodic(grey, *width, *height, x, y, h);
        let gx = g(x + h, y) - g(x - h, y);
        let gy = g(x, y + h) - g(x, y - h);
        (gx != 0.0 || gy != 0.0).then(|| gy.atan2(gx))
    }

    fn validate(
        &self,
        name: &str,
        lo: f64,
        hi: f64,
        range: &'static str,
    ) -> Result<(), ModelError> {
        match self {
            Self::Constant { value } => {
                check_range(|| format!("{name}.value"), f64::from(*value), lo, hi, range)
            }
            Self::Linear { value, gradient } => {
                check_range(|| format!("{name}.value"), f64::from(*value), lo, hi, range)?;
                for (k, g) in gradient.iter().enumerate() {
                    check_range(
                        || format!("{name}.gradient[{k}]"),
                        f64::from(*g),
                        -1e3,
                        1e3,
                        "[-1000, 1000] per pixel",
                    )?;
                }
                Ok(())
            }
            Self::Image {
                width,
                height,
                grey,
                pixel_size,
                min,
                max,
            } => {
                check_range(
                    || format!("{name}.width"),
                    *width as f64,
                    1.0,
                    MAX_FIELD_SIDE as f64,
                    "[1, 4096]",
                )?;
                check_range(
                    || format!("{name}.height"),
                    *height as f64,
                    1.0,
                    MAX_FIELD_SIDE as f64,
                    "[1, 4096]",
                )?;
                if grey.len() != width * height {
                    return Err(ModelError::Length {
                        field: format!("{name}.grey"),
                        len: grey.len(),
                        range: "width·height values",
                    });
                }
                if let Some((k, g)) = grey
                    .iter()
                    .enumerate()
                    .find(|(_, g)| !(0.0..=1.0).contains(*g))
                {
                    return Err(ModelError::OutOfRange {
                        field: format!("{name}.grey[{k}]"),
                        value: f64::from(*g),
                        range: "[0, 1]",
                    });
                }
                check_range(
                    || format!("{name}.pixel_size"),
                    f64::from(*pixel_size),
                    1e-3,
                    1e6,
                    "[0.001, 1e6] output pixels per sample",
                )?;
                check_range(|| format!("{name}.min"), f64::from(*min), lo, hi, range)?;
                check_range(|| format!("{name}.max"), f64::from(*max), lo, hi, range)
            }
        }
    }

    /// Whether the field repeats with `period` (model pixels along x and y): a constant does,
    /// an image does when its repeat (`width·pixel_size`, `height·pixel_size`) divides the
    /// period's sides exactly, a ramp never does.
    #[must_use]
    pub fn repeats_with(&self, period: crate::Period) -> bool {
        match self {
            Self::Constant { .. } => true,
            Self::Linear { .. } => false,
            Self::Image {
                width,
                height,
                pixel_size,
                ..
            } => {
                let [w, h] = period.sides();
                let divides = |side: f64, repeat: f64| {
                    let n = (side / repeat).round();
                    n >= 1.0 && n * repeat == side
                };
                let p = f64::from(*pixel_size);
                divides(w, *width as f64 * p) && divides(h, *height as f64 * p)
            }
        }
    }

    /// The smallest and largest value the field takes over `|x|, |y|, |z| ≤` [`RAMP_EXTENT`]
    /// (the whole plane for constant and image fields; a ramp beyond that extent is clamped to
    /// this range by the evaluators where it matters).
    #[must_use]
    pub fn range(&self) -> (f64, f64) {
        match self {
            Self::Constant { value } => (f64::from(*value), f64::from(*value)),
            Self::Linear { value, gradient } => {
                let spread: f64 = gradient
                    .iter()
                    .map(|g| f64::from(*g).abs() * RAMP_EXTENT)
                    .sum();
                (f64::from(*value) - spread, f64::from(*value) + spread)
            }
            Self::Image { min, max, .. } => {
                let (a, b) = (f64::from(*min), f64::from(*max));
                (a.min(b), a.max(b))
            }
        }
    }

    /// Every value a linear field takes inside the usable region must be valid too; a ramp is
    /// accepted when its value stays in range over `|x|, |y|, |z| ≤ extent`.
    fn validate_ramp(
        &self,
        name: &str,
        lo: f64,
        hi: f64,
        range: &'static str,
        extent: f64,
    ) -> Result<(), ModelError> {
        if let Self::Linear { value, gradient } = self {
            let spread: f64 = gradient.iter().map(|g| f64::from(*g).abs() * extent).sum();
            let v = f64::from(*value);
            check_range(
                || format!("{name} (ramp minimum)"),
                v - spread,
                lo,
                hi,
                range,
            )?;
            check_range(
                || format!("{name} (ramp maximum)"),
                v + spread,
                lo,
                hi,
                range,
            )?;
        }
        Ok(())
    }
}

/// Bilinear interpolation of a periodic grid of `w × h` samples, sample `(i, j)` centred at
/// `((i + ½)·h, (j + ½)·h)` pixels for sample size `h`.
fn bilinear_periodic(grey: &[f32], w: usize, h: usize, x: f64, y: f64, size: f64) -> f64 {
    bilinear(grey, w, tap(x, w, size), tap(y, h, size))
}

/// Where a position falls along one axis of a periodic grid of `n` samples of side `size`:
/// the two samples it interpolates, its fraction between them, or `None` where the position
/// is not finite. The axes are independent, so a grid of positions locates each column and
/// each row once ([`FieldGrid`]).
#[derive(Debug, Clone, Copy)]
struct Tap {
    i0: usize,
    i1: usize,
    t: f64,
}

fn tap(c: f64, n: usize, size: f64) -> Option<Tap> {
    let u = c / size - 0.5;
    if !u.is_finite() {
        return None;
    }
    let fu = u.floor();
    let i0 = fu.rem_euclid(n as f64) as usize % n;
    Some(Tap {
        i0,
        i1: (i0 + 1) % n,
        t: u - fu,
    })
}

/// The bilinear sample of `grey` (`w` samples a row) between the taps; sample 0 where either
/// position is not finite.
fn bilinear(grey: &[f32], w: usize, x: Option<Tap>, y: Option<Tap>) -> f64 {
    let (Some(x), Some(y)) = (x, y) else {
        return f64::from(grey[0]);
    };
    let s = |i: usize, j: usize| f64::from(grey[j * w + i]);
    let top = s(x.i0, y.i0) * (1.0 - x.t) + s(x.i1, y.i0) * x.t;
    let bottom = s(x.i0, y.i1) * (1.0 - x.t) + s(x.i1, y.i1) * x.t;
    top * (1.0 - y.t) + bottom * y.t
}

/// An image field's value between its taps: `min + g·(max − min)` of the bilinear sample `g`
/// ([`Field::at`] and [`FieldGrid::row`] alike).
fn image_value(grey: &[f32], w: usize, x: Option<Tap>, y: Option<Tap>, range: [f32; 2]) -> f64 {
    let [min, max] = range.map(f64::from);
    min + bilinear(grey, w, x, y) * (max - min)
}

/// A field read on the grid of positions `(xs[i], y, z)`, row by row: each value is
/// [`Field::at`]'s, bit for bit, but an image field's samples and fractions are located once
/// per column and once per row instead of once per pixel (a division, a floor and a float
/// remainder on each axis; the per-pixel tables of the GPU's phasor tiles spent most of their
/// time there).
#[derive(Debug, Clone)]
pub struct FieldGrid<'f> {
    field: &'f Field,
    xs: Vec<f64>,
    /// An image field's taps of the columns (empty for other fields).
    columns: Vec<Option<Tap>>,
    z: f64,
}

impl<'f> FieldGrid<'f> {
    /// The grid of columns `xs` on the plane `z`.
    #[must_use]
    pub fn new(field: &'f Field, xs: Vec<f64>, z: f64) -> Self {
        let columns = match field {
            Field::Image {
                width, pixel_size, ..
            } => xs
                .iter()
                .map(|&x| tap(x, *width, f64::from(*pixel_size)))
                .collect(),
            _ => Vec::new(),
        };
        Self {
            field,
            xs,
            columns,
            z,
        }
    }

    /// Calls `each(i, value)` for every column `i` of the row at `y`, in order.
    pub fn row(&self, y: f64, mut each: impl FnMut(usize, f64)) {
        match self.field {
            Field::Image {
                width,
                height,
                grey,
                pixel_size,
                min,
                max,
            } => {
                let row = tap(y, *height, f64::from(*pixel_size));
                for (i, &column) in self.columns.iter().enumerate() {
                    each(i, image_value(grey, *width, column, row, [*min, *max]));
                }
            }
            field => {
                for (i, &x) in self.xs.iter().enumerate() {
                    each(i, field.at(x, y, self.z));
                }
            }
        }
    }
}

/// How the kernels' directions `u_j` are chosen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum PhasorOrientation {
    /// The bi-lobe case (§3.1): every kernel along `angle` (radians from x, in the xy plane),
    /// graded by a field read at the kernel's centre.
    Aligned {
        /// Direction angle, radians.
        angle: Field,
    },
    /// Directions along an image field's gradient at each kernel's centre, plus `offset`
    /// radians (`π/2` follows the iso-grey lines, Fig. 14); kernels on a flat spot use
    /// `offset` alone.
    Gradient {
        /// The image whose gradient steers the kernels (its `min`/`max` are unused).
        image: Field,
        /// Angle added to the gradient direction, radians.
        offset: f32,
    },
    /// Two bi-lobes (§3.2.1): each kernel takes `angle_a` or `angle_b` with equal probability.
    /// When the angle between them exceeds `π/2` the second direction is reversed (the paper's
    /// dual formulation), which swaps the low-frequency interaction lobes `±(u_a − u_b)` for the
    /// high ones.
    TwoLobes {
        /// First direction, radians.
        angle_a: f32,
        /// Second direction, radians.
        angle_b: f32,
    },
    /// Independent uniform directions (the standard isotropic noise): uniform angle in 2D,
    /// uniform on the sphere in 3D.
    Isotropic,
    /// The locally coherent isotropic direction field of §3.2.2: at each kernel's centre, the
    /// normalised sum of a Gaussian sparse convolution (bandwidth `b_f = bandwidth_ratio·b`) of
    /// random unit vectors within `±spread` radians of the x axis. The paper's isotropic
    /// setting is `spread = 2.4`, `bandwidth_ratio = 0.5` ([`COHERENT_SPREAD`],
    /// [`COHERENT_BANDWIDTH_RATIO`]).
    Coherent {
        /// `ω_f`, radians.
        spread: f32,
        /// `b_f / b`.
        bandwidth_ratio: f32,
    },
}

/// The oscillation profile `f`, a function of the phase in turns `t ∈ [0, 1)` (Eq. 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Profile {
    /// `sin(2πt)`: the phasor sine wave (Eq. 3), in `[−1, 1]`.
    Sine,
    /// Pulse-width modulation: 1 for `t < duty`, else 0 (Figs. 14–16).
    Square {
        /// Fraction of each period at 1, in `[0, 1]`, read at the evaluated point.
        duty: Field,
    },
    /// A triangle wave in phase with the sine (1 at `t = ¼`, −1 at `t = ¾`): `1 − 4|s − ½|` with
    /// `s = frac(t + ¼)`, in `[−1, 1]`.
    Triangle,
    /// `2t − 1`, in `[−1, 1)`.
    Sawtooth,
    /// A periodic profile given as samples over one period, linearly interpolated.
    Samples {
        /// Values at `t = k / n`, `k = 0..n`.
        values: Vec<f32>,
    },
    /// Additive synthesis (Fig. 13): `Σ_k w_k·sin(2π(k·t) + φ_k)`.
    Harmonics {
        /// `(k, w_k, φ_k)`: integer harmonic (≥ 1), weight, phase in radians.
        terms: Vec<Harmonic>,
    },
    /// `(1 − s)·a + s·b`, `s` read from a field at the evaluated point and clamped to `[0, 1]`:
    /// profiles interpolated spatially (Fig. 1).
    Blend {
        /// Profile at `s = 0`.
        a: Box<Profile>,
        /// Profile at `s = 1`.
        b: Box<Profile>,
        /// The blend weight.
        weight: Field,
    },
}

/// One term of an additive profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Harmonic {
    /// Harmonic number, ≥ 1.
    pub k: u32,
    /// Weight.
    pub weight: f32,
    /// Phase shift, radians.
    pub phase: f32,
}

/// What a render writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum PhasorOutput {
    /// `f(φ)`: the profiled phasor noise.
    #[default]
    Profiled,
    /// `φ` in turns, in `(−½, ½]`.
    Phase,
    /// `I`, the modulus of the complex Gabor noise.
    Intensity,
    /// `Im 𝒢 = I·sin φ`, the Gabor noise of the same kernels (Eq. 13).
    Gabor,
}

/// A phasor noise model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhasorNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// 2 for images, 3 for volumes (evaluated slice by slice at a given z).
    pub dimensions: u8,
    /// `b`, the Gaussian bandwidth per pixel, `a(x) = exp(−π b²|x|²)`, read at each kernel's
    /// centre. Where it varies, kernels keep `impulses_per_kernel` per footprint: the process
    /// is drawn at the density of the narrowest kernels (largest `b`) and thinned (see
    /// `spectex_model::phasor_kernels`); the grid's cells fit the widest kernels.
    pub bandwidth: Field,
    /// `F`, cycles per pixel, read at each kernel's centre.
    pub frequency: Field,
    /// How kernel directions are chosen.
    pub orientation: PhasorOrientation,
    /// Mean number of impulses per kernel footprint (disc of radius `r` in 2D, ball in 3D), at
    /// most 200 (so the mean per cell stays below 64 and Knuth's Poisson draw works in f32).
    pub impulses_per_kernel: f32,
    /// The oscillation profile.
    pub profile: Profile,
    /// What is written.
    #[serde(default)]
    pub output: PhasorOutput,
    /// The written value is `mean + amplitude·v` for the output `v` (default 0 and 1; the CLI maps
    /// `[−1, 1]` profiles to `[0, 1]` with 0.5 and 0.5).
    #[serde(default)]
    pub mean: f32,
    /// See [`PhasorNoise::mean`].
    #[serde(default = "one")]
    pub amplitude: f32,
}

fn one() -> f32 {
    1.0
}

impl PhasorNoise {
    /// The smallest and largest bandwidth the kernels take.
    #[must_use]
    pub fn bandwidth_range(&self) -> (f64, f64) {
        self.bandwidth.range()
    }

    /// Radius `r = √(−ln t / π) / b` of the widest kernel (smallest `b`) for the truncation
    /// `t` = [`PHASOR_TRUNCATION`], pixels; also the grid cell side.
    #[must_use]
    pub fn kernel_radius(&self) -> f64 {
        (-PHASOR_TRUNCATION.ln() / std::f64::consts::PI).sqrt() / self.bandwidth_range().0
    }

    /// The cell sides of this noise made periodic with `period`, pixels: the kernel grid's
    /// (the kernel radius `r`) and, for a coherent orientation, the direction process's
    /// (`r / bandwidth_ratio`), each `g / max(1, round(g / side))` with `g` the largest side
    /// dividing both `W` and `H` ([`crate::Period::common_side`]), so that square cells tile the
    /// period (as Gabor noise's, [`crate::GaborNoise::periodic_radius`]); the kernels scale
    /// with their cells. `None` when a side moves by more than [`PHASOR_PERIOD_TOLERANCE`].
    #[must_use]
    pub fn periodic_sides(&self, period: crate::Period) -> Option<(f64, Option<f64>)> {
        let g = f64::from(period.common_side());
        let fit = |side: f64| {
            let fitted = g / crate::period::cells_in(g, side) as f64;
            ((fitted / side - 1.0).abs() <= PHASOR_PERIOD_TOLERANCE).then_some(fitted)
        };
        let r = self.kernel_radius();
        let kernel = fit(r)?;
        let directions = match &self.orientation {
            PhasorOrientation::Coherent {
                bandwidth_ratio, ..
            } => Some(fit(r / f64::from(*bandwidth_ratio))?),
            _ => None,
        };
        Some((kernel, directions))
    }

    /// The first field that does not repeat with `period` ([`Field::repeats_with`]), by its
    /// dotted path: a periodic phasor noise reads its fields at kernel centres and at the
    /// evaluated point, so each must repeat with the period.
    fn field_not_repeating(&self, period: crate::Period) -> Option<String> {
        fn profile_fields<'a>(p: &'a Profile, path: String, out: &mut Vec<(String, &'a Field)>) {
            match p {
                Profile::Square { duty } => out.push((format!("{path}.square.duty"), duty)),
                Profile::Blend { a, b, weight } => {
                    out.push((format!("{path}.blend.weight"), weight));
                    profile_fields(a, format!("{path}.blend.a"), out);
                    profile_fields(b, format!("{path}.blend.b"), out);
                }
                Profile::Sine
                | Profile::Triangle
                | Profile::Sawtooth
                | Profile::Samples { .. }
                | Profile::Harmonics { .. } => {}
            }
        }
        let mut fields = vec![
            ("phasor.bandwidth".to_owned(), &self.bandwidth),
            ("phasor.frequency".to_owned(), &self.frequency),
        ];
        match &self.orientation {
            PhasorOrientation::Aligned { angle } => {
                fields.push(("phasor.orientation.aligned.angle".to_owned(), angle));
            }
            PhasorOrientation::Gradient { image, .. } => {
                fields.push(("phasor.orientation.gradient.image".to_owned(), image));
            }
            PhasorOrientation::TwoLobes { .. }
            | PhasorOrientation::Isotropic
            | PhasorOrientation::Coherent { .. } => {}
        }
        profile_fields(&self.profile, "phasor.profile".to_owned(), &mut fields);
        fields
            .into_iter()
            .find(|(_, f)| !f.repeats_with(period))
            .map(|(path, _)| path)
    }

    /// Mean impulses drawn per grid cell, before thinning: the footprint (`π r²` or `4/3 π r³`)
    /// of the narrowest kernel holds `impulses_per_kernel`, so a cell of the widest one's radius
    /// holds that times `(b_max/b_min)^dimensions`.
    #[must_use]
    pub fn impulses_per_cell(&self) -> f64 {
        let (footprint, dims) = if self.dimensions == 3 {
            (4.0 / 3.0 * std::f64::consts::PI, 3)
        } else {
            (std::f64::consts::PI, 2)
        };
        let (lo, hi) = self.bandwidth_range();
        f64::from(self.impulses_per_kernel) / footprint * (hi / lo).powi(dims)
    }

    /// Checks every number.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "phasor.dimensions".into(),
            f64::from(self.dimensions),
            2.0,
            3.0,
            "2 or 3",
        )?;
        check_level(|| "phasor.mean".into(), self.mean)?;
        check_level(|| "phasor.amplitude".into(), self.amplitude)?;
        let band = "[0.001, 1] per pixel";
        self.bandwidth
            .validate("phasor.bandwidth", 1e-3, 1.0, band)?;
        self.bandwidth
            .validate_ramp("phasor.bandwidth", 1e-3, 1.0, band, RAMP_EXTENT)?;
        let freq = "[0, 0.5] cycles per pixel";
        self.frequency
            .validate("phasor.frequency", 0.0, 0.5, freq)?;
        self.frequency
            .validate_ramp("phasor.frequency", 0.0, 0.5, freq, RAMP_EXTENT)?;
        check_range(
            || "phasor.impulses_per_kernel".into(),
            f64::from(self.impulses_per_kernel),
            0.01,
            200.0,
            "[0.01, 200]",
        )?;
        // Knuth's Poisson draw in f32 needs exp(−λ) normal: λ < 64 per cell.
        let lambda = self.impulses_per_cell();
        if lambda >= 64.0 {
            return Err(ModelError::OutOfRange {
                field: "phasor.impulses_per_kernel × (largest / smallest bandwidth)^dimensions / footprint".into(),
                value: lambda,
                range: "below 64 impulses per cell: narrow the bandwidth range or lower impulses_per_kernel",
            });
        }
        match &self.orientation {
            PhasorOrientation::Aligned { angle } => {
                angle.validate("phasor.orientation.aligned.angle", -1e3, 1e3, ANGLE_RANGE)?;
            }
            PhasorOrientation::Gradient { image, offset } => {
                if !matches!(image, Field::Image { .. }) {
                    return Err(ModelError::OutOfRange {
                        field: "phasor.orientation.gradient.image".into(),
                        value: f64::NAN,
                        range: "an image field",
                    });
                }
                image.validate("phasor.orientation.gradient.image", -1e9, 1e9, "any")?;
                check_angle("phasor.orientation.gradient.offset", *offset)?;
            }
            PhasorOrientation::TwoLobes { angle_a, angle_b } => {
                check_angle("phasor.orientation.two_lobes.angle_a", *angle_a)?;
                check_angle("phasor.orientation.two_lobes.angle_b", *angle_b)?;
            }
            PhasorOrientation::Isotropic => {}
            PhasorOrientation::Coherent {
                spread,
                bandwidth_ratio,
            } => {
                check_range(
                    || "phasor.orientation.coherent.spread".into(),
                    f64::from(*spread),
                    0.0,
                    std::f64::consts::PI,
                    "[0, π] radians",
                )?;
                check_range(
                    || "phasor.orientation.coherent.bandwidth_ratio".into(),
                    f64::from(*bandwidth_ratio),
                    0.05,
                    4.0,
                    "[0.05, 4]",
                )?;
            }
        }
        validate_profile(&self.profile, "phasor.profile", 0)
    }
}

/// An angle in radians, finite and within ±1000.
fn check_angle(field: &str, value: f32) -> Result<(), ModelError> {
    check_range(|| field.into(), f64::from(value), -1e3, 1e3, ANGLE_RANGE)
}

/// The range of every angle field.
const ANGLE_RANGE: &str = "[-1000, 1000] radians";

fn validate_profile(p: &Profile, name: &str, depth: usize) -> Result<(), ModelError> {
    if depth > 4 {
        return Err(ModelError::Length {
            field: name.into(),
            len: depth,
            range: "at most 4 nested blends",
        });
    }
    match p {
        Profile::Sine | Profile::Triangle | Profile::Sawtooth => Ok(()),
        Profile::Square { duty } => {
            let range = "[0, 1]";
            duty.validate(&format!("{name}.square.duty"), 0.0, 1.0, range)?;
            duty.validate_ramp(&format!("{name}.square.duty"), 0.0, 1.0, range, RAMP_EXTENT)
        }
        Profile::Samples { values } => {
            check_len(
                || format!("{name}.samples.values"),
                values.len(),
                2,
                MAX_PROFILE_SAMPLES,
                "2 to 4096 values",
            )?;
            for (k, v) in values.iter().enumerate() {
                check_range(
                    || format!("{name}.samples.values[{k}]"),
                    f64::from(*v),
                    -1e6,
                    1e6,
                    "[-1e6, 1e6]",
                )?;
            }
            Ok(())
        }
        Profile::Harmonics { terms } => {
            check_len(
                || format!("{name}.harmonics.terms"),
                terms.len(),
                1,
                MAX_PROFILE_SAMPLES,
                "1 to 4096 terms",
            )?;
            for (k, t) in terms.iter().enumerate() {
                check_range(
                    || format!("{name}.harmonics.terms[{k}].k"),
                    f64::from(t.k),
                    1.0,
                    1024.0,
                    "[1, 1024]",
                )?;
                check_range(
                    || format!("{name}.harmonics.terms[{k}].weight"),
                    f64::from(t.weight),
                    -1e6,
                    1e6,
                    "[-1e6, 1e6]",
                )?;
                check_range(
                    || format!("{name}.harmonics.terms[{k}].phase"),
                    f64::from(t.phase),
                    -1e3,
                    1e3,
                    "[-1000, 1000] radians",
                )?;
            }
            Ok(())
        }
        Profile::Blend { a, b, weight } => {
            weight.validate(
                &format!("{name}.blend.weight"),
                -1e9,
                1e9,
                "any finite value",
            )?;
            validate_profile(a, &format!("{name}.blend.a"), depth + 1)?;
            validate_profile(b, &format!("{name}.blend.b"), depth + 1)
        }
    }
}

impl crate::ModelKind for PhasorNoise {
    const PERIODIC: bool = true;

    const NAME: &'static str = "phasor";

    /// Periodic when every field repeats with the period (constants, or images whose repeat
    /// divides it) and the kernel cells (and a coherent orientation's direction cells) can be
    /// fitted to it ([`PhasorNoise::periodic_sides`]).
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let refuse = |requirement: String| {
            Err(ModelError::Period {
                period: period.to_string(),
                kind: "phasor",
                requirement,
            })
        };
        if let Some(path) = self.field_not_repeating(period) {
            return refuse(format!(
                "every field must repeat with the period, and {path} does not (a ramp never \
                 does; an image does when its repeat, width·pixel_size by height·pixel_size, \
                 divides the period)"
            ));
        }
        if self.periodic_sides(period).is_none() {
            return refuse(format!(
                "its kernel radius {:.2} pixels (and a coherent orientation's direction cells, \
                 radius / bandwidth_ratio) must become a divisor of gcd(W, H) = {} within 25%; \
                 take a period whose sides share a large common divisor (a square one, or \
                 multiples of {})",
                self.kernel_radius(),
                period.common_side(),
                self.kernel_radius().ceil()
            ));
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), ModelError> {
        PhasorNoise::validate(self)
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

    fn model() -> PhasorNoise {
        PhasorNoise {
            seed: 1,
            dimensions: 2,
            bandwidth: Field::constant(0.05),
            frequency: Field::constant(0.1),
            orientation: PhasorOrientation::Aligned {
                angle: Field::constant(0.5),
            },
            impulses_per_kernel: 30.0,
            profile: Profile::Square {
                duty: Field::constant(0.25),
            },
            output: PhasorOutput::Profiled,
            mean: 0.0,
            amplitude: 1.0,
        }
    }

    pub fn valid_model_and_named_errors() {
        model().validate().unwrap();
        let mut m = model();
        m.frequency = Field::constant(f32::NAN);
        let e = m.validate().unwrap_err().to_string();
        assert!(
            e.contains("phasor.frequency.value") && e.contains("[0, 0.5]"),
            "{e}"
        );
        let mut m = model();
        m.profile = Profile::Square {
            duty: Field::Linear {
                value: 0.5,
                gradient: [1e-3, 0.0, 0.0],
            },
        };
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("ramp"), "{e}");
        // A bandwidth range multiplies the impulses drawn per cell by (max/min)²: 150 per
        // footprint with a range of 1.5 is 150/π·2.25 ≈ 107 per cell, beyond Knuth's 64.
        let mut m = model();
        m.impulses_per_kernel = 150.0;
        m.bandwidth = Field::Image {
            width: 1,
            height: 2,
            grey: vec![0.0, 1.0],
            pixel_size: 1.0,
            min: 0.02,
            max: 0.03,
        };
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains("below 64 impulses per cell"), "{e}");
        m.impulses_per_kernel = 50.0;
        m.validate().unwrap();
        let mut m = model();
        m.dimensions = 4;
        assert!(m.validate().unwrap_err().to_string().contains("dimensions"));
        let mut m = model();
        m.orientation = PhasorOrientation::Gradient {
            image: Field::constant(1.0),
            offset: 0.0,
        };
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("image field")
        );
    }

    /// A field read on a grid, row by row, is `Field::at` at each position, bit for bit: an
    /// image (negative, far, sub-sample and non-finite positions, a wrap on each axis), a ramp
    /// and a constant.
    pub fn field_grids_read_what_at_reads() {
        let image = Field::Image {
            width: 5,
            height: 3,
            grey: (0..15).map(|k| ((k * 7) % 11) as f32 / 10.0).collect(),
            pixel_size: 6.5,
            min: 0.2,
            max: 0.7,
        };
        let ramp = Field::Linear {
            value: 0.25,
            gradient: [1e-4, -3e-5, 2e-3],
        };
        let xs = vec![
            -1e7 - 0.3,
            -13.0,
            -0.25,
            0.0,
            3.25,
            6.5,
            32.4,
            1e7 + 0.7,
            f64::NAN,
            f64::INFINITY,
        ];
        let ys = [-7.75, 0.0, 9.5, 19.49, 1e7, f64::NEG_INFINITY];
        for field in [image, ramp, Field::constant(0.4)] {
            let grid = FieldGrid::new(&field, xs.clone(), 3.0);
            for &y in &ys {
                let mut seen = 0;
                grid.row(y, |i, v| {
                    assert_eq!(seen, i);
                    seen += 1;
                    let want = field.at(xs[i], y, 3.0);
                    assert!(
                        v.to_bits() == want.to_bits(),
                        "{field:?} at ({}, {y}): {v} against {want}",
                        xs[i]
                    );
                });
                assert_eq!(seen, xs.len());
            }
        }
    }

    pub fn fields_repeat_with_periods_their_repeat_divides() {
        let period = |w, h| crate::Period::new(w, h).unwrap();
        assert!(Field::constant(0.3).repeats_with(period(7, 5)));
        let ramp = Field::Linear {
            value: 0.1,
            gradient: [0.0, 1e-9, 0.0],
        };
        assert!(!ramp.repeats_with(period(256, 256)));
        // 64 × 32 samples of 2 pixels: a 128 × 64 pixel repeat.
        let image = Field::Image {
            width: 64,
            height: 32,
            grey: vec![0.5; 64 * 32],
            pixel_size: 2.0,
            min: 0.0,
            max: 1.0,
        };
        assert!(image.repeats_with(period(128, 64)));
        assert!(image.repeats_with(period(384, 128)));
        assert!(!image.repeats_with(period(128, 96)));
        assert!(!image.repeats_with(period(64, 64)));
        // A model whose duty cycle is that image is periodic exactly where the image repeats.
        let mut m = model();
        m.profile = Profile::Square { duty: image };
        assert!(crate::ModelKind::check_period(&m, period(384, 128)).is_ok());
        let err = crate::ModelKind::check_period(&m, period(384, 96)).unwrap_err();
        assert!(
            err.to_string().contains("phasor.profile.square.duty"),
            "{err}"
        );
    }

    pub fn image_field_interpolates_and_wraps() {
        let f = Field::Image {
            width: 2,
            height: 1,
            grey: vec![0.0, 1.0],
            pixel_size: 10.0,
            min: 2.0,
            max: 4.0,
        };
        // Sample centres at x = 5 and 15; halfway between them, and periodic with period 20.
        assert!((f.at(5.0, 5.0, 0.0) - 2.0).abs() < 1e-12);
        assert!((f.at(15.0, 5.0, 0.0) - 4.0).abs() < 1e-12);
        assert!((f.at(10.0, 5.0, 0.0) - 3.0).abs() < 1e-12);
        assert!((f.at(25.0, -15.0, 0.0) - 2.0).abs() < 1e-12);
        assert!((f.at(0.0, 0.0, 0.0) - 3.0).abs() < 1e-12);
        let ramp = Field::Image {
            width: 4,
            height: 1,
            grey: vec![0.0, 0.5, 1.0, 0.5],
            pixel_size: 10.0,
            min: 0.0,
            max: 1.0,
        };
        // Grey rises along +x through the centre at x = 15: the gradient points along x.
        let a = ramp.gradient_angle(15.0, 5.0).unwrap();
        assert!(a.abs() < 1e-12, "{a}");
        // and falls through x = 35.
        let a = ramp.gradient_angle(35.0, 5.0).unwrap();
        assert!((a.abs() - std::f64::consts::PI).abs() < 1e-12, "{a}");
    }

    pub fn radius_and_density() {
        let m = model();
        let r = m.kernel_radius();
        // a(r) = 0.05 by definition.
        let a = (-std::f64::consts::PI * m.bandwidth_range().0.powi(2) * r * r).exp();
        assert!((a - PHASOR_TRUNCATION).abs() < 1e-12);
        assert!((m.impulses_per_cell() * std::f64::consts::PI - 30.0).abs() < 1e-9);
    }
}
