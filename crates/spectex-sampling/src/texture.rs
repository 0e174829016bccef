//! Texture by example (Gilet et al. 2014, §5, and the colour paragraph of §6): the structure
//! region `R`, its complexity-reduced blocks, the random-phase strata of the rest of the
//! spectrum, turbulence fitted from the exemplar's own spectrum, and colour by PCA.
//!
//! ## Steps, per channel
//! 1. `T` is the Welch block side of the exemplar; the Welch spectrum (scaled to the image's
//!    variance, [`exemplar_target`]) is the target of the random-phase part.
//! 2. **Region `R`** (§5.1): the top-left `T × T` block of the exemplar (its periodic component
//!    by default, so the structure tiles without the cross of border discontinuities; the raw
//!    block with [`TextureOptions::periodic`] false) is transformed; its non-zero frequencies
//!    are added to `R` by decreasing amplitude, a conjugate pair at a time, until `R` holds the
//!    share `r` of the block's energy. The *structure image* is the inverse transform of the
//!    block's spectrum on `R`.
//! 3. **Complexity reduction** (§5.3): `J_R = max(1, round(rJ))`. With `b = 1` block, the `J_R`
//!    highest-amplitude frequencies of the structure image are kept. The result is evaluated
//!    (with the model's own [`Structure::eval`]) at the `T²` pixels; while its mean absolute
//!    deviation from the structure image exceeds the colour precision (`1/256`), `b` doubles:
//!    each lattice point's `2Δ_R × 2Δ_R` square of the structure image is transformed and its
//!    `J_R` largest coefficients kept. At `Δ_R = 1` a square holds 4 coefficients, so any
//!    `J_R ≥ 4` is exact there.
//! 4. **Strata** (§5.3): the Welch spectrum with the bins of `R` removed is stratified with the
//!    remaining `J − J_R` cosines (no strata when none remain or no energy is left).
//! 5. The channel's constant is the block's mean when it has a structure (so `r = 1`
//!    reproduces the block), the image's mean otherwise (so `r = 0` is exactly the noise by
//!    example of [`fit_image`](crate::fit_image)).
//!
//! **Turbulence** (§5.2): the Welch spectrum of the first channel, scaled to unit variance,
//! fitted with a small budget ([`TextureOptions::turbulence_budget`] cosines in 2 strata), once per
//! axis with its own seeds; `centre = Σ_S √(2E_S/π)`, the mean of `Σ_S |n_S|` for Gaussian
//! strata of variance `E_S`.
//!
//! **Colour**: the RGB covariance of the exemplar is diagonalised (Jacobi rotations); each
//! principal component is fitted as a grey channel (own seed), and the model maps them back
//! with the eigenvectors. Decorrelated channels with independent random phases keep the
//! exemplar's colour covariance, and the structure keeps each channel's phases, so colours stay
//! on the exemplar's principal axes.

use ndarray::{Array2, ArrayView2, ArrayView3, Axis, s};
use num_complex::Complex64;
use rayon::prelude::*;
use spectex_model::texture::{
    ColourBasis, FixedCosine, MAX_STRUCTURE_COSINES, Structure, TextureChannel, TextureModel,
    Turbulence,
};
use spectex_spectrum::{Fft2, periodic_smooth, welch_block_size};

use crate::SamplingError;
use crate::fit::{FitOptions, exemplar_target, fit_psd, stratify};

/// The colour precision of §5.3: the structure blocks are subdivided until the mean absolute
/// deviation from the structure image is at most this.
pub const COLOUR_PRECISION: f64 = 1.0 / 256.0;
/// Default cosine budget of each turbulence field.
pub const DEFAULT_TURBULENCE_BUDGET: u32 = 8;
/// Strata of each turbulence field.
pub const TURBULENCE_STRATA: u32 = 2;

/// Options of a texture fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureOptions {
    /// Budget `J`, strata, seed and coverage, as for noise by example.
    pub fit: FitOptions,
    /// `r ∈ [0, 1]`: share of the block's energy whose phases are kept. Default 0.
    pub structure: f64,
    /// `σ` in pixels, `[0, 1e4]`; 0 for no turbulence. Default 0.
    pub turbulence: f64,
    /// Random placement of half-period blocks. Default false.
    pub random_placement: bool,
    /// Take the structure from the block's periodic component (default true) or the raw block.
    pub periodic: bool,
    /// Cosines of each turbulence field, `2..=64`. Default 8.
    pub turbulence_budget: u32,
}

impl Default for TextureOptions {
    /// Every option at its `DEFAULT_` constant: plain noise by example (no structure, no
    /// turbulence, no random placement), the structure from the periodic component.
    fn default() -> Self {
        Self {
            fit: FitOptions::default(),
            structure: Self::DEFAULT_STRUCTURE,
            turbulence: Self::DEFAULT_TURBULENCE,
            random_placement: false,
            periodic: true,
            turbulence_budget: DEFAULT_TURBULENCE_BUDGET,
        }
    }
}

impl TextureOptions {
    /// `r`: no phases kept (the fit is LRP noise by example).
    pub const DEFAULT_STRUCTURE: f64 = 0.0;
    /// `σ`, pixels: no turbulence.
    pub const DEFAULT_TURBULENCE: f64 = 0.0;

    /// Checks every option.
    ///
    /// # Errors
    /// [`SamplingError::OutOfRange`] naming the option.
    pub fn validate(&self) -> Result<(), SamplingError> {
        self.fit.validate()?;
        if !(0.0..=1.0).contains(&self.structure) {
            return Err(SamplingError::OutOfRange {
                parameter: "structure",
                value: self.structure,
                range: "[0, 1] (share of the energy with fixed phases)",
            });
        }
        if !(0.0..=1e4).contains(&self.turbulence) {
            return Err(SamplingError::OutOfRange {
                parameter: "turbulence",
                value: self.turbulence,
                range: "[0, 1e4] pixels",
            });
        }
        if !(2..=64).contains(&self.turbulence_budget) {
            return Err(SamplingError::OutOfRange {
                parameter: "turbulence_budget",
                value: f64::from(self.turbulence_budget),
                range: "2..=64 cosines",
            });
        }
        Ok(())
    }
}

/// What the fit of one channel found (all zero for a channel without texture).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ChannelReport {
    /// Frequencies in `R` (whole grid, both halves of every pair).
    pub region_bins: usize,
    /// Share of the block's energy in `R`.
    pub region_energy: f64,
    /// `J_R`, cosines per block.
    pub structure_cosines: usize,
    /// `b`, blocks per side.
    pub blocks: u32,
    /// Mean absolute deviation of `n_R` from the structure image at its pixels.
    pub structure_error: f64,
    /// Cosines of the random-phase strata.
    pub strata_cosines: usize,
}

/// What a texture fit found.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureReport {
    /// `T`.
    pub period: usize,
    /// Per channel.
    pub channels: Vec<ChannelReport>,
    /// Eigenvalues of the colour covariance (largest first), for colour exemplars.
    pub colour_variances: Option<[f64; 3]>,
}

/// Fits a texture to an exemplar of 1 (grey) or 3 (RGB) channels, `(channel, row, column)`.
///
/// # Errors
/// Invalid options; an image with another channel count; as [`exemplar_psd`] for each channel
/// (non-finite pixels, too small, constant).
pub fn fit_texture(
    image: ArrayView3<'_, f64>,
    options: &TextureOptions,
) -> Result<(TextureModel, TextureReport), SamplingError> {
    options.validate()?;
    let (nc, h, w) = image.dim();
    if nc != 1 && nc != 3 {
        return Err(SamplingError::OutOfRange {
            parameter: "image channels",
            value: nc as f64,
            range: "1 (grey) or 3 (RGB)",
        });
    }
    let t = welch_block_size(h, w)?;
    let (channels, colour, variances) = if nc == 3 {
        let (mean, vectors, values) = colour_pca(image)?;
        let comps: Vec<Array2<f64>> = (0..3)
            .map(|c| {
                Array2::from_shape_fn((h, w), |(y, x)| {
                    (0..3)
                        .map(|i| vectors[i][c] * (image[[i, y, x]] - mean[i]))
                        .sum()
                })
            })
            .collect();
        let basis = ColourBasis {
            mean: mean.map(|m| m as f32),
            basis: vectors.map(|row| row.map(|v| v as f32)),
        };
        (comps, Some(basis), Some(values))
    } else {
        (vec![image.index_axis(Axis(0), 0).to_owned()], None, None)
    };
    let mut model_channels = Vec::with_capacity(nc);
    let mut reports = Vec::with_capacity(nc);
    for (c, channel) in channels.iter().enumerate() {
        // A principal component with (almost) no variance is a constant channel, not an error.
        let seed = options.fit.seed.wrapping_add(c as u32);
        let (ch, report) = match fit_channel(channel.view(), t, seed, options) {
            Err(SamplingError::NoEnergy { .. }) if c > 0 => (
                TextureChannel {
                    seed,
                    mean: channel.mean().unwrap_or(0.0) as f32,
                    strata: vec![],
                    structure: None,
                },
                ChannelReport::default(),
            ),
            other => other?,
        };
        model_channels.push(ch);
        reports.push(report);
    }
    let turbulence = if options.turbulence > 0.0 {
        Some(fit_turbulence(channels[0].view(), options)?)
    } else {
        None
    };
    let model = TextureModel {
        seed: options.fit.seed,
        period: t as u32,
        channels: model_channels,
        colour,
        turbulence,
        random_placement: options.random_placement,
    };
    model.validate().map_err(SamplingError::Model)?;
    Ok((
        model,
        TextureReport {
            period: t,
            channels: reports,
            colour_variances: variances,
        },
    ))
}

fn fit_channel(
    channel: ArrayView2<'_, f64>,
    t: usize,
    seed: u32,
    options: &TextureOptions,
) -> Result<(TextureChannel, ChannelReport), SamplingError> {
    let (mut psd, mean) = exemplar_target(channel, options.fit.method)?;
    let budget = options.fit.budget as usize;
    let r = options.structure;
    let mut report = ChannelReport::default();
    let mut channel_mean = mean;
    let mut structure = None;
    let mut strata_budget = budget;
    if r > 0.0 {
        let raw = channel.slice(s![0..t, 0..t]);
        let mut fft = Fft2::new();
        let block = if options.periodic {
            periodic_smooth(raw, &mut fft).periodic
        } else {
            raw.to_owned()
        };
        channel_mean = block.mean().unwrap_or(mean);
        let (image, region) = structure_image(block.view(), r, &mut fft);
        let j_r = ((r * budget as f64).round() as usize).clamp(1, budget);
        let (st, blocks_error) = reduce(image.view(), j_r, &mut fft);
        report.region_bins = region.0;
        report.region_energy = region.1;
        report.structure_cosines = j_r;
        report.blocks = st.blocks;
        report.structure_error = blocks_error;
        structure = Some(st);
        strata_budget = budget - j_r;
        for &(ky, kx) in &region.2 {
            psd[[ky, kx]] = 0.0;
        }
    }
    let mut strata = vec![];
    if strata_budget > 0 {
        let fit = FitOptions {
            budget: strata_budget as u32,
            strata: options.fit.strata.min(strata_budget as u32),
            seed,
            ..options.fit
        };
        match fit_psd(psd.view(), channel_mean, &fit) {
            Ok(noise) => strata = noise.strata,
            // All the energy is in R (r = 1, or a pure sinusoid): no random-phase part.
            Err(SamplingError::NoEnergy { .. }) if structure.is_some() => {}
            Err(SamplingError::NoEnergy { .. }) => {
                return Err(SamplingError::NoEnergy { parameter: "image" });
            }
            Err(e) => return Err(e),
        }
    }
    report.strata_cosines = strata.iter().map(spectex_model::Stratum::cosines).sum();
    Ok((
        TextureChannel {
            seed,
            mean: channel_mean as f32,
            strata,
            structure,
        },
        report,
    ))
}

/// The region `R`: how many bins (both halves of each pair), the share of the block's energy
/// they hold, and the bins `(row, column)`.
type Region = (usize, f64, Vec<(usize, usize)>);

/// The structure image of `block` for the share `r`, and `R`.
fn structure_image(
    block: ArrayView2<'_, f64>,
    r: f64,
    fft: &mut Fft2<f64>,
) -> (Array2<f64>, Region) {
    let t = block.nrows();
    let mean = block.mean().unwrap_or(0.0);
    let mut z = block.mapv(|v| Complex64::new(v - mean, 0.0));
    fft.forward(&mut z);
    // Bins by decreasing energy; a pair (k, −k) enters together (equal energies), its
    // representative being the first of the two in row-major order.
    let mut order: Vec<(f64, usize, usize)> = Vec::with_capacity(t * t / 2 + 2);
    let mut total = 0.0;
    for ky in 0..t {
        for kx in 0..t {
            let (my, mx) = ((t - ky) % t, (t - kx) % t);
            if (ky, kx) == (0, 0) || (my, mx) < (ky, kx) {
                continue;
            }
            let e = z[[ky, kx]].norm_sqr() * if (my, mx) == (ky, kx) { 1.0 } else { 2.0 };
            total += e;
            order.push((e, ky, kx));
        }
    }
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let mut keep = Array2::from_elem((t, t), false);
    let mut bins = Vec::new();
    let mut acc = 0.0;
    for &(e, ky, kx) in &order {
        if total <= 0.0 || acc >= r * total * (1.0 - 1e-12) {
            break;
        }
        acc += e;
        let (my, mx) = ((t - ky) % t, (t - kx) % t);
        keep[[ky, kx]] = true;
        keep[[my, mx]] = true;
        bins.push((ky, kx));
        if (my, mx) != (ky, kx) {
            bins.push((my, mx));
        }
    }
    for ((ky, kx), v) in z.indexed_iter_mut() {
        if !keep[[ky, kx]] {
            *v = Complex64::new(0.0, 0.0);
        }
    }
    fft.inverse_normalized(&mut z);
    let image = z.mapv(|c| c.re);
    let share = if total > 0.0 { acc / total } else { 0.0 };
    (image, (bins.len(), share, bins))
}

/// Complexity reduction (§5.3): the structure with `j_r` cosines per block and the fewest
/// blocks whose mean absolute deviation is within [`COLOUR_PRECISION`] (or `b = T`, or the
/// finest subdivision whose cosines fit a model, [`MAX_STRUCTURE_COSINES`]).
fn reduce(image: ArrayView2<'_, f64>, j_r: usize, fft: &mut Fft2<f64>) -> (Structure, f64) {
    let t = image.nrows();
    let mut b = 1usize;
    loop {
        let structure = blocks(image, b, j_r, fft);
        let error = deviation(&structure, image);
        let finer_fits = 4 * b * b * j_r <= MAX_STRUCTURE_COSINES;
        if error <= COLOUR_PRECISION || b >= t || !finer_fits {
            return (structure, error);
        }
        b *= 2;
    }
}

/// The `b × b` block structure with the `j_r` largest coefficients of each lattice point's
/// `2Δ × 2Δ` square (for `b = 1`, of the image itself, period `T`).
fn blocks(image: ArrayView2<'_, f64>, b: usize, j_r: usize, fft: &mut Fft2<f64>) -> Structure {
    let t = image.nrows();
    let delta = t / b;
    let n = 2 * delta;
    let mut cosines = Vec::with_capacity(b * b);
    for j in 0..b {
        for i in 0..b {
            let (side, origin) = if b == 1 {
                (t, (0, 0))
            } else {
                // Pixel m of the square is image pixel (iΔ − Δ + m) mod T.
                (
                    n,
                    ((j * delta + t - delta) % t, (i * delta + t - delta) % t),
                )
            };
            let mut z = Array2::from_shape_fn((side, side), |(y, x)| {
                Complex64::new(image[[(origin.0 + y) % t, (origin.1 + x) % t]], 0.0)
            });
            fft.forward(&mut z);
            cosines.push(top_cosines(&z, j_r, b == 1));
        }
    }
    Structure {
        blocks: b as u32,
        cosines,
    }
}

/// The `j_r` largest conjugate pairs of a square's spectrum as fixed cosines in the model's
/// convention: `u` relative to the lattice point, frequency in cycles per `N = 2Δ` (for the
/// whole period, `N = 2T` and the frequency is doubled).
fn top_cosines(z: &Array2<Complex64>, j_r: usize, whole: bool) -> Vec<FixedCosine> {
    let side = z.nrows();
    let norm = (side * side) as f64;
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for ky in 0..side {
        for kx in 0..side {
            let (my, mx) = ((side - ky) % side, (side - kx) % side);
            if (my, mx) < (ky, kx) {
                continue;
            }
            let self_pair = (my, mx) == (ky, kx);
            let a = z[[ky, kx]].norm() / norm * if self_pair { 1.0 } else { 2.0 };
            if a > 0.0 {
                pairs.push((a, ky, kx));
            }
        }
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    pairs.truncate(j_r);
    let signed = |k: usize| -> i32 {
        if 2 * k > side {
            k as i32 - side as i32
        } else {
            k as i32
        }
    };
    pairs
        .into_iter()
        .map(|(a, ky, kx)| {
            let (fx, fy) = (signed(kx), signed(ky));
            let arg = z[[ky, kx]].arg() / std::f64::consts::TAU;
            // The square's pixel m sits at u = m − Δ (N = 2Δ): the phase gains k·Δ/N = (kx+ky)/2.
            let shift = if whole { 0.0 } else { f64::from(fx + fy) * 0.5 };
            let phase = (arg + shift).rem_euclid(1.0);
            let scale = if whole { 2 } else { 1 };
            FixedCosine {
                frequency: [fx * scale, fy * scale],
                amplitude: a as f32,
                phase: if phase >= 1.0 { 0.0 } else { phase as f32 },
            }
        })
        .collect()
}

/// Mean absolute deviation of the structure (evaluated by the model) from `image`; rows in
/// parallel, summed in row order (the same result for any thread count).
fn deviation(structure: &Structure, image: ArrayView2<'_, f64>) -> f64 {
    let t = image.nrows();
    let rows: Vec<f64> = (0..t)
        .into_par_iter()
        .map(|y| {
            (0..t)
                .map(|x| {
                    let got = structure.eval(t as u32, [x as f32, y as f32]);
                    (f64::from(got) - image[[y, x]]).abs()
                })
                .sum()
        })
        .collect();
    rows.iter().sum::<f64>() / (t * t) as f64
}

fn fit_turbulence(
    channel: ArrayView2<'_, f64>,
    options: &TextureOptions,
) -> Result<Turbulence, SamplingError> {
    let (mut psd, _) = exemplar_target(channel, options.fit.method)?;
    let size = psd.nrows();
    let variance = (psd.sum() - psd[[0, 0]]) / (size * size) as f64;
    psd.mapv_inplace(|p| p / variance);
    psd[[0, 0]] = 0.0;
    let fit = FitOptions {
        budget: options.turbulence_budget,
        strata: TURBULENCE_STRATA,
        seed: options.fit.seed ^ 0x7475_7262,
        ..options.fit
    };
    let noise = fit_psd(psd.view(), 0.0, &fit)?;
    let plan = stratify(psd.view(), &fit)?;
    let centre: f64 = plan
        .strata
        .iter()
        .map(|s| (2.0 * s.energy / std::f64::consts::PI).sqrt())
        .sum();
    let seed = options.fit.seed;
    Ok(Turbulence {
        sigma: options.turbulence as f32,
        seeds: [seed ^ 0x5455_5258, seed ^ 0x5455_5259],
        strata: noise.strata,
        centre: centre as f32,
    })
}

/// Mean colour, eigenvectors (columns, `vectors[i][c]`) and eigenvalues (largest first).
pub(crate) type Pca = ([f64; 3], [[f64; 3]; 3], [f64; 3]);

/// The PCA of the RGB values, by cyclic Jacobi rotations on their covariance.
pub(crate) fn colour_pca(image: ArrayView3<'_, f64>) -> Result<Pca, SamplingError> {
    let (_, h, w) = image.dim();
    let n = (h * w) as f64;
    let mut mean = [0.0; 3];
    for (c, m) in mean.iter_mut().enumerate() {
        *m = image.index_axis(Axis(0), c).sum() / n;
        if !m.is_finite() {
            return Err(SamplingError::OutOfRange {
                parameter: "image",
                value: *m,
                range: "finite pixel values",
            });
        }
    }
    let mut a = [[0.0f64; 3]; 3];
    for y in 0..h {
        for x in 0..w {
            let d = [
                image[[0, y, x]] - mean[0],
                image[[1, y, x]] - mean[1],
                image[[2, y, x]] - mean[2],
            ];
            for i in 0..3 {
                for j in 0..3 {
                    a[i][j] += d[i] * d[j] / n;
                }
            }
        }
    }
    let (values, vectors) = jacobi3(a);
    Ok((mean, vectors, values))
}

/// Eigen-decomposition of a symmetric 3×3 matrix: eigenvalues (descending) and eigenvectors as
/// columns, with each column's largest component positive (a deterministic sign).
fn jacobi3(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..64 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off < 1e-300 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let tn = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let tn = if theta == 0.0 { 1.0 } else { tn };
            let c = 1.0 / (tn * tn + 1.0).sqrt();
            let s = tn * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let values = order.map(|i| a[i][i]);
    let mut vectors = [[0.0; 3]; 3];
    for (c, &i) in order.iter().enumerate() {
        let col = [v[0][i], v[1][i], v[2][i]];
        let big = col
            .iter()
            .copied()
            .fold(0.0f64, |m, x| if x.abs() > m.abs() { x } else { m });
        let sign = if big < 0.0 { -1.0 } else { 1.0 };
        for r in 0..3 {
            vectors[r][c] = sign * col[r];
        }
    }
    (values, vectors)
}

/// Side of the colour grid [`false_colour_fraction`] buckets the exemplar's colours in.
const COLOUR_GRID: usize = 32;

/// The share of `output`'s pixels (clamped to `[0, 1]`, as displayed) whose nearest colour of
/// `exemplar` (8-bit quantised) is farther than `distance` (Euclidean, RGB in `[0, 1]`): colours
/// the exemplar does not have. Both images are `(3, rows, columns)`; exact nearest-neighbour
/// distances, searched in a bucket grid.
///
/// # Panics
/// Never for 3-channel inputs; other channel counts give 0.
#[must_use]
pub fn false_colour_fraction(
    exemplar: ArrayView3<'_, f64>,
    output: ArrayView3<'_, f64>,
    distance: f64,
) -> f64 {
    if exemplar.dim().0 != 3 || output.dim().0 != 3 || output.is_empty() {
        return 0.0;
    }
    let g = COLOUR_GRID;
    let cell = |v: f64| ((v.clamp(0.0, 1.0) * g as f64) as usize).min(g - 1);
    let mut seen = std::collections::HashSet::new();
    let mut buckets: Vec<Vec<[f64; 3]>> = vec![Vec::new(); g * g * g];
    let (_, h, w) = exemplar.dim();
    for y in 0..h {
        for x in 0..w {
            let q = [0, 1, 2].map(|c| (exemplar[[c, y, x]].clamp(0.0, 1.0) * 255.0).round() as u8);
            if seen.insert(q) {
                let v = q.map(|c| f64::from(c) / 255.0);
                buckets[(cell(v[0]) * g + cell(v[1])) * g + cell(v[2])].push(v);
            }
        }
    }
    let reach = (distance * g as f64).ceil() as isize + 1;
    let d2 = distance * distance;
    let (_, oh, ow) = output.dim();
    let mut far = 0usize;
    for y in 0..oh {
        for x in 0..ow {
            let v = [0, 1, 2].map(|c| output[[c, y, x]].clamp(0.0, 1.0));
            let centre = v.map(cell);
            let mut near = false;
            'search: for dr in -reach..=reach {
                for dg in -reach..=reach {
                    for db in -reach..=reach {
                        let idx = [dr, dg, db]
                            .iter()
                            .zip(centre)
                            .map(|(d, c)| c as isize + d)
                            .collect::<Vec<_>>();
                        if idx.iter().any(|&i| i < 0 || i >= g as isize) {
                            continue;
                        }
                        let b = (idx[0] as usize * g + idx[1] as usize) * g + idx[2] as usize;
                        for e in &buckets[b] {
                            let dd = (e[0] - v[0]).powi(2)
                                + (e[1] - v[1]).powi(2)
                                + (e[2] - v[2]).powi(2);
                            if dd <= d2 {
                                near = true;
                                break 'search;
                            }
                        }
                    }
                }
            }
            if !near {
                far += 1;
            }
        }
    }
    far as f64 / (oh * ow) as f64
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use ndarray::Array3;

    /// A textured test image: a few sinusoids plus hashed noise, values in about [0, 1].
    fn image(h: usize, w: usize, seed: u32) -> Array2<f64> {
        use spectex_model::random::{Prng, cell_hash};
        Array2::from_shape_fn((h, w), |(y, x)| {
            let mut p = Prng::new(cell_hash(x as i32, y as i32, 3, seed));
            let (xf, yf) = (x as f64, y as f64);
            0.5 + 0.15 * (0.3 * xf + 0.1 * yf).sin()
                + 0.1 * (0.05 * xf - 0.21 * yf + 1.0).cos()
                + 0.08 * (p.next_f64() - 0.5)
        })
    }

    /// Two sinusoids on the grid: two pairs, so two cosines in one block are exact and one
    /// cosine is not (the blocks subdivide until the deviation is within 1/256 or b = T).
    pub fn subdivision_starts_with_one_block_and_refines_only_when_needed() {
        let t = 32;
        let img = Array2::from_shape_fn((t, t), |(y, x)| {
            let (x, y) = (x as f64, y as f64);
            0.1 * (std::f64::consts::TAU * (3.0 * x + y) / 32.0 + 0.4).cos()
                + 0.05 * (std::f64::consts::TAU * (-2.0 * x + 5.0 * y) / 32.0).cos()
        });
        let mut fft = Fft2::new();
        let (two, err) = reduce(img.view(), 2, &mut fft);
        assert_eq!(two.blocks, 1);
        assert!(err < 1e-6, "two cosines, one block: {err}");
        // The fitted cosines are the definition's: frequency doubled on N = 2T, amplitude, phase.
        let c = two.cosines[0][0];
        assert_eq!(c.frequency, [6, 2]);
        assert!(
            (c.amplitude - 0.1).abs() < 1e-6
                && (c.phase - 0.4 / std::f32::consts::TAU).abs() < 1e-6
        );
        let (one, err) = reduce(img.view(), 1, &mut fft);
        assert!(
            one.blocks > 1,
            "one cosine cannot hold two sinusoids in one block"
        );
        assert!(err <= COLOUR_PRECISION || one.blocks == t as u32, "{err}");
        // The coarser level was not good enough (that is why it subdivided).
        let coarser = blocks(img.view(), one.blocks as usize / 2, 1, &mut fft);
        assert!(deviation(&coarser, img.view()) > COLOUR_PRECISION);
    }

    pub fn false_colours_are_counted_exactly() {
        // Exemplar: pure red and pure blue. Output: red, blue, their mean (purple, 0.707 from
        // both) and a red off by 0.05.
        let ex = Array3::from_shape_fn((3, 1, 2), |(c, _, x)| match (c, x) {
            (0, 0) | (2, 1) => 1.0,
            _ => 0.0,
        });
        let out = Array3::from_shape_vec(
            (3, 1, 4),
            vec![1.0, 0.0, 0.5, 0.95, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.0],
        )
        .unwrap();
        assert_eq!(false_colour_fraction(ex.view(), out.view(), 0.1), 0.25);
        assert_eq!(false_colour_fraction(ex.view(), out.view(), 0.04), 0.5);
        assert_eq!(false_colour_fraction(ex.view(), out.view(), 0.75), 0.0);
    }

    pub fn jacobi_diagonalises_a_symmetric_matrix() {
        let a = [[2.0, 0.3, -0.4], [0.3, 1.0, 0.25], [-0.4, 0.25, 0.5]];
        let (values, v) = jacobi3(a);
        assert!(values[0] >= values[1] && values[1] >= values[2]);
        // A v_c = λ_c v_c and V is orthonormal.
        for c in 0..3 {
            for i in 0..3 {
                let av: f64 = (0..3).map(|k| a[i][k] * v[k][c]).sum();
                assert!(
                    (av - values[c] * v[i][c]).abs() < 1e-12,
                    "column {c}, row {i}"
                );
            }
            for d in 0..3 {
                let dot: f64 = (0..3).map(|k| v[k][c] * v[k][d]).sum();
                assert!((dot - if c == d { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        // Trace is invariant.
        assert!((values.iter().sum::<f64>() - 3.5).abs() < 1e-12);
    }

    pub fn region_holds_the_requested_share_of_energy() {
        let img = image(64, 64, 1);
        let block = img.slice(s![0..32, 0..32]);
        let mut fft = Fft2::new();
        for r in [0.05, 0.2, 0.5, 0.9] {
            let (structure, (bins, share, _)) = structure_image(block, r, &mut fft);
            assert!(share >= r - 1e-12, "r {r}: share {share}");
            assert!(bins > 0 && bins < 32 * 32);
            // The structure image's variance is the region's energy (Parseval).
            let m = block.mean().unwrap();
            let total: f64 = block.iter().map(|v| (v - m).powi(2)).sum();
            let kept: f64 = structure.iter().map(|v| v * v).sum();
            assert!(
                (kept / total - share).abs() < 1e-9,
                "r {r}: {} vs {share}",
                kept / total
            );
        }
    }

    pub fn options_are_validated() {
        let img = Array3::from_shape_fn((1, 32, 32), |(_, y, x)| image(32, 32, 2)[[y, x]]);
        for (opts, name) in [
            (
                TextureOptions {
                    structure: 1.5,
                    ..TextureOptions::default()
                },
                "structure",
            ),
            (
                TextureOptions {
                    turbulence: f64::NAN,
                    ..TextureOptions::default()
                },
                "turbulence",
            ),
            (
                TextureOptions {
                    turbulence_budget: 0,
                    ..TextureOptions::default()
                },
                "turbulence_budget",
            ),
        ] {
            let e = fit_texture(img.view(), &opts).unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
        let two = Array3::<f64>::zeros((2, 32, 32));
        let e = fit_texture(two.view(), &TextureOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("channels"), "{e}");
    }
}
