//! Noise by example (Gilet et al. 2014, §4.4): the public entry points that turn a power
//! spectrum, an image or a spectral target into an [`LrpNoise`], and the intermediate
//! [`Stratification`] they build (the paper's Fig. 4).

use ndarray::{Array2, ArrayView2};
use rayon::prelude::*;
use spectex_model::{LrpNoise, MAX_COSINES, MAX_STRATA, SpectralTarget, Stratum};
use spectex_spectrum::{Fft2, signed_frequency, welch_psd};

use crate::SamplingError;
use crate::amplitude::amplitude;
use crate::erosion::erode;
use crate::grid::{Bin, in_half_plane, mirror};
use crate::kmeans::sub_strata;
use crate::shrink::{MAX_COVERAGE, MIN_COVERAGE, shrink_unit};
use crate::spectrum_fit::{self, sharpen_welch, spectrum_tables};
use crate::stratify::{
    EnergyStratum, MAX_PSD_SIDE, Partition, distribute_budget, equal_energy_strata,
    log_power_strata, validate_psd, window_width,
};

/// Options of a fit. Build one with struct update syntax over [`FitOptions::default`]; every
/// fitting function validates it first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// `J`, the cosine budget: cosines per lattice point over all strata, `1..=1024` (§4.4: "the
    /// cosine budget J which defines the computation load"). Default 50. The spectrum fit uses
    /// fewer when its strata have fewer distinct frequencies in all
    /// ([`spectrum_fit::capped_budgets`](crate::spectrum_fit::capped_budgets)).
    pub budget: u32,
    /// `L`, the number of strata, `1..=64` and at most `budget` (§4.2: "we actually use L = 4 in
    /// all our examples"). Default 4.
    pub strata: u32,
    /// Seed of the fitted model (its evaluation randomness) and of k-means' random seeding.
    /// Default 0.
    pub seed: u32,
    /// Share of a window's spectral energy kept inside the shrink distance δ, `[0.05, 0.99]`
    /// (§4.3: "at least 75% … the 75% threshold is empirical"). Default 0.75.
    pub coverage: f64,
    /// How the power range is cut into the `L` strata. Default [`Partition::EqualEnergy`]
    /// (§4.2); [`Partition::LogPower`] for targets spanning decades of power.
    pub partition: Partition,
    /// How each stratum becomes cosine tables. Default [`FitMethod::Spectrum`];
    /// [`FitMethod::Paper`] reproduces the paper's models exactly.
    pub method: FitMethod,
}

/// How a stratum's cosines are fitted to its part of the spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FitMethod {
    /// Equal-energy sub-strata whose tables draw frequencies in proportion to the power, the
    /// whole stratum kept, no more cosines than the stratum has frequencies, `Δ_S ≥ 8` px
    /// ([`crate::spectrum_fit`]): the expected spectrum is the exemplar's, blurred by the
    /// window.
    #[default]
    Spectrum,
    /// Gilet et al. 2014, §4.3 as printed: the stratum shrunk by the window's 75% radius, k-means
    /// sub-strata whose bins are drawn uniformly, one amplitude per stratum.
    Paper,
}

impl FitMethod {
    /// The name used on the command line and in model files: `spectrum` or `paper`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Spectrum => "spectrum",
            Self::Paper => "paper",
        }
    }

    /// The method called `name` ([`FitMethod::name`]).
    ///
    /// # Errors
    /// [`SamplingError::UnknownFitMethod`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, SamplingError> {
        match name {
            "spectrum" => Ok(Self::Spectrum),
            "paper" => Ok(Self::Paper),
            _ => Err(SamplingError::UnknownFitMethod { name: name.into() }),
        }
    }
}

impl Default for FitOptions {
    /// Every option at its `DEFAULT_` constant (the `spectex fit` and `spectex synth` flags'
    /// defaults).
    fn default() -> Self {
        Self {
            budget: Self::DEFAULT_BUDGET,
            strata: Self::DEFAULT_STRATA,
            seed: Self::DEFAULT_SEED,
            coverage: Self::DEFAULT_COVERAGE,
            partition: Self::DEFAULT_PARTITION,
            method: Self::DEFAULT_METHOD,
        }
    }
}

impl FitOptions {
    /// `J`, the cosine budget: 50 cosines per lattice point over all strata.
    pub const DEFAULT_BUDGET: u32 = 50;
    /// `L`, the strata (§4.2: "we actually use L = 4 in all our examples").
    pub const DEFAULT_STRATA: u32 = 4;
    /// Seed of the fitted model and of k-means' seeding.
    pub const DEFAULT_SEED: u32 = spectex_model::DEFAULT_SEED;
    /// Share of a window's energy kept inside the shrink distance (§4.3's empirical 75%).
    pub const DEFAULT_COVERAGE: f64 = 0.75;
    /// Equal-energy strata (§4.2).
    pub const DEFAULT_PARTITION: Partition = Partition::EqualEnergy;
    /// The spectrum fit.
    pub const DEFAULT_METHOD: FitMethod = FitMethod::Spectrum;

    /// Checks every option against its range.
    ///
    /// # Errors
    /// [`SamplingError::OutOfRange`] naming the option, or [`SamplingError::StrataExceedBudget`].
    pub fn validate(&self) -> Result<(), SamplingError> {
        if !(1..=MAX_COSINES as u32).contains(&self.budget) {
            return Err(SamplingError::OutOfRange {
                parameter: "budget",
                value: f64::from(self.budget),
                range: "1..=1024 cosines",
            });
        }
        if !(1..=MAX_STRATA as u32).contains(&self.strata) {
            return Err(SamplingError::OutOfRange {
                parameter: "strata",
                value: f64::from(self.strata),
                range: "1..=64",
            });
        }
        if self.strata > self.budget {
            return Err(SamplingError::StrataExceedBudget {
                strata: self.strata,
                budget: self.budget,
            });
        }
        if !(MIN_COVERAGE..=MAX_COVERAGE).contains(&self.coverage) {
            return Err(SamplingError::OutOfRange {
                parameter: "coverage",
                value: self.coverage,
                range: "[0.05, 0.99]",
            });
        }
        Ok(())
    }
}

/// One stratum of a [`Stratification`], with every quantity of §4.3 that its LRP noise uses.
#[derive(Debug, Clone, PartialEq)]
pub struct StratumPlan {
    /// Index of the stratum in the equal-energy partition (0 = lowest power, `L − 1` = highest);
    /// also the `level` of its k-means seeding (see [`crate::kmeans::KMEANS_LAYER`]).
    pub level: usize,
    /// The stratum `S` on the whole grid (with every bin its mirror).
    pub bins: Vec<Bin>,
    /// `E_S = Σ_{f∈S} P(f)/T²`: the variance it carries.
    pub energy: f64,
    /// Lowest symmetrised power in `S`.
    pub min_power: f64,
    /// Highest symmetrised power in `S`.
    pub max_power: f64,
    /// `J_S`, its cosines per lattice point.
    pub cosines: usize,
    /// `Δ_S = T·√J_S/√(2|S|)` pixels, clamped (see [`crate::stratify::window_width`]).
    pub window_width: f64,
    /// The shrink distance `δ = δ₀/Δ_S`, cycles per pixel.
    pub shrink: f64,
    /// `δ` in frequency bins, `δ·T`: the erosion radius asked for.
    pub shrink_bins: f64,
    /// Connected pieces of `S` (8-connected on the periodic grid).
    pub components: usize,
    /// Pieces of `S` thinner than `δ`, which keep their ridge ([`erode`]).
    pub thin_components: usize,
    /// The shrunk stratum on the whole grid.
    pub eroded: Vec<Bin>,
    /// The shrunk stratum on the half plane (where a bin's mirror is shrunk-in but the bin is
    /// not, the half-plane bin stands for it): the points k-means breaks into sub-strata.
    pub points: Vec<Bin>,
    /// `A_S` (Eq. 3, see [`crate::amplitude::amplitude`]).
    pub amplitude: f64,
}

/// A power spectrum stratified and prepared for sub-stratum sampling: everything of §4.2–4.3
/// except k-means. Only non-empty strata are listed, lowest power first.
#[derive(Debug, Clone, PartialEq)]
pub struct Stratification {
    /// `T`, the side of the spectrum.
    pub size: usize,
    /// Total energy `Σ_{f≠0} P(f)/T²` (the variance of the noise).
    pub energy: f64,
    /// `δ₀`: the shrink distance of a window of width 1, cycles per window width
    /// ([`crate::shrink::shrink_unit`]).
    pub shrink_unit: f64,
    /// The non-empty strata.
    pub strata: Vec<StratumPlan>,
}

impl Stratification {
    /// A `T × T` map (uncentred, like the spectrum) of the stratum `level` of every bin, `−1`
    /// outside every stratum; of the shrunk strata when `eroded` is true. For figures like the
    /// paper's Fig. 4(b, d).
    #[must_use]
    pub fn labels(&self, eroded: bool) -> Array2<i32> {
        let mut map = Array2::from_elem((self.size, self.size), -1);
        for s in &self.strata {
            for &b in if eroded { &s.eroded } else { &s.bins } {
                map[b] = s.level as i32;
            }
        }
        map
    }
}

/// Stratifies a power spectrum and prepares every stratum for sampling (§4.2–4.3): equal-energy
/// strata ([`equal_energy_strata`]), budgets `J_S` ([`distribute_budget`]), window widths
/// `Δ_S`, shrink distances `δ = δ₀/Δ_S`, modified erosion ([`erode`]) and amplitudes `A_S`.
///
/// `psd` is `T × T`, uncentred, with `Σ P/T²` the variance ([`welch_psd`]'s convention);
/// `psd[[0, 0]]` is ignored.
///
/// # Errors
/// Invalid `options` ([`FitOptions::validate`]) or an invalid spectrum
/// ([`validate_psd`]).
pub fn stratify(
    psd: ArrayView2<'_, f64>,
    options: &FitOptions,
) -> Result<Stratification, SamplingError> {
    let (partition, budgets) = partition(psd, options)?;
    let size = psd.nrows();
    let partition_energy: f64 = partition.iter().map(|s| s.energy).sum();
    let delta0 = shrink_unit(options.coverage);
    let strata = partition
        .into_par_iter()
        .enumerate()
        .filter(|(_, s)| !s.bins.is_empty())
        .map(|(level, s)| {
            let cosines = budgets[level];
            let width = window_width(size, cosines, s.bins.len());
            let shrink = delta0 / width;
            let shrink_bins = shrink * size as f64;
            let mut mask = Array2::from_elem((size, size), false);
            for &b in &s.bins {
                mask[b] = true;
            }
            let erosion = erode(mask.view(), shrink_bins);
            let eroded: Vec<Bin> = erosion
                .mask
                .indexed_iter()
                .filter(|(_, m)| **m)
                .map(|((k, l), _)| [k, l])
                .collect();
            let points: Vec<Bin> = eroded
                .iter()
                .filter_map(|&b| {
                    let m = mirror(b, size);
                    if in_half_plane(b, size) {
                        Some(b)
                    } else if !erosion.mask[m] {
                        Some(m)
                    } else {
                        None
                    }
                })
                .collect::<std::collections::BTreeSet<Bin>>()
                .into_iter()
                .collect();
            StratumPlan {
                level,
                energy: s.energy,
                min_power: s.min_power,
                max_power: s.max_power,
                cosines,
                window_width: width,
                shrink,
                shrink_bins,
                components: erosion.components,
                thin_components: erosion.thin_components,
                eroded,
                points,
                amplitude: amplitude(s.energy, cosines),
                bins: s.bins,
            }
        })
        .collect();
    Ok(Stratification {
        size,
        energy: partition_energy,
        shrink_unit: delta0,
        strata,
    })
}

/// The strata of `options.partition` (after validating `options`) and their budgets `J_S`
/// (§4.2–4.3), shared by both fits.
fn partition(
    psd: ArrayView2<'_, f64>,
    options: &FitOptions,
) -> Result<(Vec<EnergyStratum>, Vec<usize>), SamplingError> {
    options.validate()?;
    let partition = match options.partition {
        Partition::EqualEnergy => equal_energy_strata(psd, options.strata as usize)?,
        Partition::LogPower => log_power_strata(psd, options.strata as usize)?,
    };
    let energies: Vec<f64> = partition.iter().map(|s| s.energy).collect();
    let budgets = distribute_budget(&energies, options.budget as usize);
    Ok((partition, budgets))
}

/// The fitted model, validated against a model file's ranges.
fn lrp_model(
    options: &FitOptions,
    mean: f64,
    strata: Vec<Stratum>,
) -> Result<LrpNoise, SamplingError> {
    let model = LrpNoise {
        seed: options.seed,
        mean: mean as f32,
        strata,
    };
    model.validate().map_err(SamplingError::Model)?;
    Ok(model)
}

/// Fits an LRP noise to a discrete power spectrum (§4.4, "noise by example with discrete
/// PSD"): [`stratify`], then each shrunk stratum broken into `J_S` sub-strata by k-means
/// ([`sub_strata`]), whose bins' frequencies become the stratum's tables.
///
/// `psd` is `T × T`, uncentred (zero frequency at `[0, 0]`; index `[k, l]` is the frequency
/// `(f_y, f_x) = (signed_frequency(k, T), signed_frequency(l, T))` cycles per pixel), normalised
/// so that `Σ P/T²` is the variance — [`welch_psd`]'s output. The model's spatially averaged
/// variance is then `Σ_{f≠0} P/T²` and its mean `mean`. The result is deterministic: the same
/// inputs give the same model for any thread count.
///
/// # Errors
/// Invalid options or spectrum (as [`stratify`]), a non-finite `mean` or one outside
/// `[−1e9, 1e9]`, or a model out of a model file's ranges ([`SamplingError::Model`]).
pub fn fit_psd(
    psd: ArrayView2<'_, f64>,
    mean: f64,
    options: &FitOptions,
) -> Result<LrpNoise, SamplingError> {
    if !mean.is_finite() || mean.abs() > 1e9 {
        return Err(SamplingError::OutOfRange {
            parameter: "mean",
            value: mean,
            range: "[-1e9, 1e9]",
        });
    }
    if options.method == FitMethod::Spectrum {
        return fit_psd_spectrum(psd, mean, options);
    }
    let plan = stratify(psd, options)?;
    let size = plan.size;
    let strata = plan
        .strata
        .par_iter()
        .map(|s| Stratum {
            window_width: s.window_width as f32,
            amplitude: s.amplitude as f32,
            sub_strata: sub_strata(&s.points, size, s.cosines, s.level, options.seed),
        })
        .collect();
    lrp_model(options, mean, strata)
}

/// [`fit_psd`] with [`FitMethod::Spectrum`]: the strata of the chosen partition, their budgets
/// as in the paper but none above the stratum's distinct frequencies
/// ([`spectrum_fit::capped_budgets`]), amplitudes by Eq. (3) for those budgets, tables from
/// [`spectrum_tables`] and `Δ_S` from [`spectrum_fit::window_width`] of the stratum's capped
/// budget `J_S`.
///
/// Why the capped `J_S` for `Δ_S`: its `(J_S/12)^¼` factor balances the window's blur against
/// the randomness of the frequencies a window draws; a capped stratum draws each of its few
/// frequencies about once per lattice point, and the width of the equal share (before capping)
/// made its windows wider, with fewer lattice points in a render to average that randomness over.
/// With the exact Welch sharpening ([`sharpen_welch`]), mean relative L1 over the fidelity
/// test's 8 seeds at J = 10 / 50 / 100, the share's width against the capped `J_S`'s:
/// dirt 0.111 / 0.071 / 0.093 against 0.130 / 0.106 / 0.096 (the share's J = 100 broke the
/// falling-with-J bound); sand 0.084 / 0.091 / 0.094 against 0.084 / 0.076 / 0.071; gravel and
/// grass unchanged to the third decimal. (With the blur-only sharpening the share
/// had been better: dirt 0.124 / 0.109 against 0.140 / 0.127 at J = 50 / 100.)
fn fit_psd_spectrum(
    psd: ArrayView2<'_, f64>,
    mean: f64,
    options: &FitOptions,
) -> Result<LrpNoise, SamplingError> {
    let (partition, budgets) = partition(psd, options)?;
    let size = psd.nrows();
    let power = |b: Bin| psd[b];
    let capacities: Vec<usize> = partition
        .iter()
        .map(|s| spectrum_fit::distinct_frequencies(&s.bins, &power, size))
        .collect();
    let energies: Vec<f64> = partition.iter().map(|s| s.energy).collect();
    let cosines = spectrum_fit::capped_budgets(&budgets, &capacities, &energies);
    let strata = partition
        .par_iter()
        .zip(cosines.par_iter())
        .filter(|(s, cosines)| !s.bins.is_empty() && **cosines > 0)
        .map(|(s, &cosines)| Stratum {
            window_width: spectrum_fit::window_width(&s.bins, &power, size, cosines) as f32,
            amplitude: amplitude(s.energy, cosines) as f32,
            sub_strata: spectrum_tables(&s.bins, &power, size, cosines),
        })
        .filter(|s| !s.sub_strata.is_empty())
        .collect();
    lrp_model(options, mean, strata)
}

/// Largest smaller side of an image accepted by [`fit_image`]: its Welch spectrum then has side
/// at most [`MAX_PSD_SIDE`].
pub const MAX_IMAGE_SIDE: usize = 2 * MAX_PSD_SIDE;

/// The power spectrum and mean an example image is fitted to (§4.4, "computing the input
/// PSD"): its Welch power spectrum ([`welch_psd`], blocks of side `T`, the largest power of two
/// below the smaller side), scaled so that its total `Σ_{f≠0} P/T²` is the image's own variance,
/// and its mean.
///
/// Why the scaling: Welch's total is the Hann-weighted variance of the blocks, which weighs their
/// centres and, on a 512² height map (9 overlapping blocks), differs from the image's variance by
/// up to 11% (dirt: +11%, sand: +6%). The spectrum's shape is Welch's; the contrast a user sees
/// is the image's.
///
/// # Errors
/// A non-finite pixel ([`SamplingError::NonFinite`]), an image whose smaller side is below 3
/// ([`SamplingError::Spectrum`]) or above [`MAX_IMAGE_SIDE`], a constant image
/// ([`SamplingError::NoEnergy`]; an image whose variance is below `(64·ε·max|v|)²`, the level of
/// rounding noise, counts as constant).
pub fn exemplar_psd(channel: ArrayView2<'_, f64>) -> Result<(Array2<f64>, f64), SamplingError> {
    for ((row, column), &value) in channel.indexed_iter() {
        if !value.is_finite() {
            return Err(SamplingError::NonFinite {
                parameter: "image",
                value,
                row,
                column,
            });
        }
    }
    let side = channel.nrows().min(channel.ncols());
    if side > MAX_IMAGE_SIDE {
        return Err(SamplingError::OutOfRange {
            parameter: "image's smaller side",
            value: side as f64,
            range: "3..=8192 pixels",
        });
    }
    let mut psd = welch_psd(channel, &mut Fft2::new())?;
    let mean = channel.mean().unwrap_or(0.0);
    let variance = channel.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / channel.len() as f64;
    // A constant image's spectrum is rounding noise of variance about (ε·|v|)², not texture.
    let scale = channel.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let t = psd.nrows();
    let welch_variance = (psd.sum() - psd[[0, 0]]) / (t * t) as f64;
    if variance <= (64.0 * f64::EPSILON * scale).powi(2) || welch_variance <= 0.0 {
        return Err(SamplingError::NoEnergy { parameter: "image" });
    }
    let ratio = variance / welch_variance;
    psd.mapv_inplace(|p| p * ratio);
    Ok((psd, mean))
}

/// The spectrum and mean a fit by `method` targets for one channel of an example image:
/// [`exemplar_psd`], and for [`FitMethod::Spectrum`] the spectrum whose Welch estimate that is
/// ([`sharpen_welch`]: cosines fitted to the blurred estimate would be blurred again when a
/// render is measured). Noise by example, texture strata and turbulence all fit this.
///
/// # Errors
/// As [`exemplar_psd`].
pub fn exemplar_target(
    channel: ArrayView2<'_, f64>,
    method: FitMethod,
) -> Result<(Array2<f64>, f64), SamplingError> {
    let (psd, mean) = exemplar_psd(channel)?;
    Ok(match method {
        FitMethod::Spectrum => (sharpen_welch(&psd), mean),
        FitMethod::Paper => (psd, mean),
    })
}

/// Fits an LRP noise to one channel of an example image (§4.4): [`exemplar_target`] (the Welch
/// spectrum's shape, the image's variance and mean), through [`fit_psd`].
///
/// # Errors
/// Invalid options, or as [`exemplar_psd`] and [`fit_psd`].
pub fn fit_image(
    channel: ArrayView2<'_, f64>,
    options: &FitOptions,
) -> Result<LrpNoise, SamplingError> {
    options.validate()?;
    let (psd, mean) = exemplar_target(channel, options.method)?;
    match fit_psd(psd.view(), mean, options) {
        Err(SamplingError::NoEnergy { .. }) => Err(SamplingError::NoEnergy { parameter: "image" }),
        other => other,
    }
}

/// Share of a continuous target's energy left out in its weakest bins ([`fit_target`]).
pub const NEGLIGIBLE_TAIL: f64 = 1e-3;

/// Zeroes the weakest bins of `psd` that together hold at most [`NEGLIGIBLE_TAIL`] of its
/// energy. A continuous density such as a Gaussian ring is positive until it underflows, ~38σ
/// from its centre; without this cut the lowest stratum would be that whole disc, its `|S|`
/// would set a window width far too small (§4.3: `Δ_S = T·√J_S/√(2|S|)`) and the erosion would
/// keep the wrong frequencies. The bins cut carry 0.1% of the variance; they are restored by
/// the amplitudes, which are computed from the kept energy scaled back to the whole.
fn drop_negligible_tail(psd: &mut Array2<f64>) {
    let total: f64 = psd.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return;
    }
    let mut order: Vec<(f64, usize)> = psd.iter().copied().zip(0..).collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut dropped = 0.0;
    let flat = psd.as_slice_mut().expect("a fresh array is contiguous");
    for (p, i) in order {
        if p > 0.0 {
            if dropped + p > NEGLIGIBLE_TAIL * total {
                break;
            }
            dropped += p;
            flat[i] = 0.0;
        }
    }
}

/// Power below which [`fit_target`] drops a bin under [`Partition::LogPower`], relative to the
/// target's highest power: 100 dB, an amplitude ratio of 10⁻⁵, far below what an 8-bit or
/// 16-bit output shows.
pub const LOG_POWER_FLOOR: f64 = 1e-10;

/// Zeroes the bins of `psd` below [`LOG_POWER_FLOOR`] times its largest value. Under the
/// log-power partition the weak tail is what the partition is for (a `1/f^β` target with
/// β = 2 has 0.1% of its energy beyond a quarter of the sampling rate, which
/// [`drop_negligible_tail`] would cut); only the underflowing tail of a density such as a
/// Gaussian is dropped, so that it does not stretch the log range the strata divide.
fn drop_below_floor(psd: &mut Array2<f64>) {
    let max = psd.iter().copied().fold(0.0, f64::max);
    psd.mapv_inplace(|p| if p < LOG_POWER_FLOOR * max { 0.0 } else { p });
}

/// Grid side used for a continuous target when a caller has no reason to choose another.
pub const DEFAULT_TARGET_GRID: usize = 256;
/// Smallest grid side accepted by [`fit_target`].
pub const MIN_TARGET_GRID: usize = 8;
/// Largest grid side accepted by [`fit_target`].
pub const MAX_TARGET_GRID: usize = MAX_PSD_SIDE;

/// Fits a zero-mean LRP noise of spatially averaged variance `variance` to a spectral target
/// (§4: "the target PSD may be continuous or discrete").
///
/// The target's density is sampled at the frequencies of a `grid × grid` DFT grid
/// (`P[k, l] = target.power(signed_frequency(l, grid), signed_frequency(k, grid))`; `grid` a
/// power of two in `8..=4096`, [`DEFAULT_TARGET_GRID`] = 256 is a good default: its frequency
/// step `1/256` resolves features of width ≥ 0.01 cycles per pixel), the zero frequency is set to
/// 0 (the noise is zero-mean), the samples are scaled so that `Σ P/grid² = variance`, and the
/// result goes through [`fit_psd`] with mean 0. Frequencies in cycles per pixel, so the noise's
/// pixel is the target's.
///
/// # Errors
/// An invalid target ([`SamplingError::Target`]), `variance` outside `(0, 1e12]`, a `grid` that
/// is not a power of two in range, a target with no power on the grid
/// ([`SamplingError::NoEnergy`]), or as [`fit_psd`].
pub fn fit_target(
    target: &SpectralTarget,
    variance: f64,
    grid: usize,
    options: &FitOptions,
) -> Result<LrpNoise, SamplingError> {
    options.validate()?;
    target.validate().map_err(SamplingError::Target)?;
    if !(variance.is_finite() && variance > 0.0 && variance <= 1e12) {
        return Err(SamplingError::OutOfRange {
            parameter: "variance",
            value: variance,
            range: "(0, 1e12]",
        });
    }
    if !grid.is_power_of_two() || !(MIN_TARGET_GRID..=MAX_TARGET_GRID).contains(&grid) {
        return Err(SamplingError::OutOfRange {
            parameter: "grid",
            value: grid as f64,
            range: "a power of two in 8..=4096",
        });
    }
    let mut psd = Array2::from_shape_fn((grid, grid), |(k, l)| {
        target.power(signed_frequency(l, grid), signed_frequency(k, grid))
    });
    psd[[0, 0]] = 0.0;
    match options.partition {
        Partition::EqualEnergy => drop_negligible_tail(&mut psd),
        Partition::LogPower => drop_below_floor(&mut psd),
    }
    // Checked before scaling, so that a NaN or a negative density is reported where it is.
    validate_psd(psd.view(), "spectral target")?;
    let sum: f64 = psd.iter().sum();
    let scale = variance * (grid * grid) as f64 / sum;
    psd.mapv_inplace(|p| p * scale);
    fit_psd(psd.view(), 0.0, options)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod tests {
    #![allow(
        clippy::unwrap_used,
        reason = "a test fails loudly on the first unexpected None or Err"
    )]

    use super::*;
    use crate::amplitude::stratum_variance;
    use spectex_model::random::{Prng, cell_hash};

    fn synthetic_image(h: usize, w: usize, seed: u32) -> Array2<f64> {
        let mut prng = Prng::new(cell_hash(h as i32, w as i32, 2, seed));
        Array2::from_shape_fn((h, w), |(y, x)| {
            0.5 + 0.2 * (0.7 * x as f64 + 0.2 * y as f64).sin()
                + 0.1 * (0.13 * y as f64).cos()
                + 0.1 * prng.next_f64()
        })
    }

    pub fn options_are_validated_with_their_name_and_range() {
        let bad = |o: FitOptions| o.validate().unwrap_err().to_string();
        let d = FitOptions::default();
        assert!(bad(FitOptions { budget: 0, ..d }).contains("budget = 0"));
        assert!(bad(FitOptions { budget: 1025, ..d }).contains("1..=1024"));
        assert!(bad(FitOptions { strata: 0, ..d }).contains("strata = 0"));
        assert!(
            bad(FitOptions {
                strata: 65,
                budget: 100,
                ..d
            })
            .contains("1..=64")
        );
        assert!(
            bad(FitOptions {
                strata: 5,
                budget: 3,
                ..d
            })
            .contains("exceeds budget = 3")
        );
        assert!(
            bad(FitOptions {
                coverage: f64::NAN,
                ..d
            })
            .contains("coverage = NaN")
        );
        assert!(bad(FitOptions { coverage: 1.0, ..d }).contains("[0.05, 0.99]"));
        d.validate().unwrap();
    }

    pub fn fitted_psd_keeps_budget_energy_and_ranges() {
        let img = synthetic_image(100, 90, 1);
        let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
        let t = psd.nrows();
        let total = (psd.iter().sum::<f64>() - psd[[0, 0]]) / (t * t) as f64;
        for (budget, strata) in [(1u32, 1u32), (7, 4), (50, 4), (64, 8), (300, 3)] {
            let options = FitOptions {
                budget,
                strata,
                seed: 5,
                ..FitOptions::default()
            };
            let plan = stratify(psd.view(), &options).unwrap();
            let model = fit_psd(psd.view(), 0.25, &options).unwrap();
            assert_eq!(model.budget(), budget as usize, "J {budget}, L {strata}");
            assert_eq!(model.strata.len(), plan.strata.len());
            let energy: f64 = plan.strata.iter().map(|s| s.energy).sum();
            let variance: f64 = plan
                .strata
                .iter()
                .map(|s| stratum_variance(s.amplitude, s.cosines))
                .sum();
            assert!((energy - total).abs() < 1e-12 * total);
            assert!((variance - total).abs() < 1e-12 * total);
            for (s, st) in model.strata.iter().enumerate() {
                assert!(st.sub_strata.iter().all(|t| !t.is_empty()), "stratum {s}");
                let p = &plan.strata[s];
                assert!(!p.points.is_empty() && p.eroded.len() <= p.bins.len());
                assert!(p.thin_components <= p.components);
            }
            assert_eq!(model, fit_psd(psd.view(), 0.25, &options).unwrap());
        }
    }

    pub fn eroded_strata_are_inside_their_strata_and_symmetric() {
        let img = synthetic_image(129, 129, 3);
        let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
        let plan = stratify(psd.view(), &FitOptions::default()).unwrap();
        let labels = plan.labels(false);
        let eroded = plan.labels(true);
        for ((k, l), &e) in eroded.indexed_iter() {
            if e >= 0 {
                assert_eq!(labels[[k, l]], e);
            }
            assert_eq!(e, eroded[mirror([k, l], plan.size)]);
        }
        for s in &plan.strata {
            for &p in &s.points {
                assert!(in_half_plane(p, plan.size));
            }
            // Every shrunk mirror pair has its one representative among the points.
            let pairs: std::collections::BTreeSet<Bin> = s
                .eroded
                .iter()
                .map(|&b| crate::grid::half_plane_representative(b, plan.size))
                .collect();
            assert_eq!(pairs.into_iter().collect::<Vec<_>>(), s.points);
        }
    }

    pub fn targets_are_fitted_with_the_requested_variance() {
        let targets = [
            SpectralTarget::Ring {
                radius: 0.2,
                width: 0.03,
            },
            SpectralTarget::Lobes {
                frequency: 0.15,
                angle: 0.6,
                width: 0.02,
            },
            SpectralTarget::Band { min: 0.1, max: 0.3 },
        ];
        for target in &targets {
            let options = FitOptions {
                budget: 24,
                ..FitOptions::default()
            };
            let model = fit_target(target, 2.5, 64, &options).unwrap();
            let variance: f64 = model
                .strata
                .iter()
                .map(|s| stratum_variance(f64::from(s.amplitude), s.cosines()))
                .sum();
            assert!((variance - 2.5).abs() < 1e-5, "{target:?}: {variance}");
            assert_eq!(model.mean, 0.0);
            assert_eq!(model.budget(), 24);
            // Band: every frequency drawn lies in the band.
            if let SpectralTarget::Band { min, max } = target {
                for f in model
                    .strata
                    .iter()
                    .flat_map(|s| s.sub_strata.iter().flatten())
                {
                    let r = f64::from(f[0]).hypot(f64::from(f[1]));
                    assert!(r >= f64::from(*min) - 1e-6 && r <= f64::from(*max) + 1e-6);
                }
            }
        }
        assert!(matches!(
            fit_target(&targets[0], 1.0, 100, &FitOptions::default()),
            Err(SamplingError::OutOfRange {
                parameter: "grid",
                ..
            })
        ));
        assert!(matches!(
            fit_target(&targets[0], 0.0, 64, &FitOptions::default()),
            Err(SamplingError::OutOfRange {
                parameter: "variance",
                ..
            })
        ));
        let bad = SpectralTarget::Ring {
            radius: 2.0,
            width: 0.1,
        };
        assert!(matches!(
            fit_target(&bad, 1.0, 64, &FitOptions::default()),
            Err(SamplingError::Target(_))
        ));
    }

    pub fn bad_inputs_are_errors_not_panics() {
        let d = FitOptions::default();
        let flat = Array2::from_elem((40, 40), 0.3);
        assert!(matches!(
            fit_image(flat.view(), &d),
            Err(SamplingError::NoEnergy { parameter: "image" })
        ));
        let mut nan = synthetic_image(40, 40, 1);
        nan[[3, 4]] = f64::NAN;
        assert!(matches!(
            fit_image(nan.view(), &d),
            Err(SamplingError::NonFinite {
                row: 3,
                column: 4,
                ..
            })
        ));
        assert!(matches!(
            fit_image(Array2::zeros((2, 50)).view(), &d),
            Err(SamplingError::Spectrum(_))
        ));
        let psd = Array2::from_elem((16, 16), 1.0);
        assert!(matches!(
            fit_psd(psd.view(), f64::INFINITY, &d),
            Err(SamplingError::OutOfRange {
                parameter: "mean",
                ..
            })
        ));
        let huge = Array2::from_elem((16, 16), 1e300);
        assert!(matches!(
            fit_psd(huge.view(), 0.0, &d),
            Err(SamplingError::Model(_))
        ));
        assert!(matches!(
            fit_psd(Array2::<f64>::ones((16, 8)).view(), 0.0, &d),
            Err(SamplingError::Shape { .. })
        ));
    }

    /// A spectrum of one strong frequency pair (two thirds of the energy) over a flat floor:
    /// with four equal-energy strata the pair is a stratum of one frequency, which the spectrum
    /// fit gives one cosine (its capacity), the other 49 going to the floor's strata; the
    /// paper's fit gives it its equal share.
    pub fn a_stratum_of_one_frequency_gets_one_cosine() {
        let t = 32;
        let mut psd = Array2::from_elem((t, t), 1.0);
        psd[[0, 0]] = 0.0;
        psd[[3, 5]] = 1000.0;
        psd[[t - 3, t - 5]] = 1000.0;
        let peak = [5.0 / 32.0, 3.0 / 32.0];
        let model = fit_psd(psd.view(), 0.0, &FitOptions::default()).unwrap();
        assert_eq!(model.budget(), 50);
        let lone: Vec<&Stratum> = model
            .strata
            .iter()
            .filter(|s| {
                s.sub_strata.iter().flatten().all(|f| {
                    [1.0, -1.0].contains(&(f64::from(f[0]) / peak[0]))
                        && f64::from(f[0]) / peak[0] == f64::from(f[1]) / peak[1]
                })
            })
            .collect();
        assert_eq!(lone.len(), 1, "{model:?}");
        assert_eq!(lone[0].cosines(), 1);
        let paper = FitOptions {
            method: FitMethod::Paper,
            ..FitOptions::default()
        };
        let model = fit_psd(psd.view(), 0.0, &paper).unwrap();
        assert_eq!(model.budget(), 50);
        assert!(model.strata.iter().all(|s| s.cosines() >= 12), "{model:?}");
    }

    pub fn a_pure_sinusoid_gets_one_stratum_of_one_frequency_pair() {
        let img = Array2::from_shape_fn((64, 64), |(y, x)| {
            (2.0 * std::f64::consts::PI * (4.0 * x as f64 + 2.0 * y as f64) / 32.0).cos()
        });
        let psd = welch_psd(img.view(), &mut Fft2::new()).unwrap();
        let model = fit_image(img.view(), &FitOptions::default()).unwrap();
        assert_eq!(model.budget(), 50);
        let plan = stratify(psd.view(), &FitOptions::default()).unwrap();
        // The top stratum holds the peak bin pair itself.
        let top = plan.strata.last().unwrap();
        assert!(top.bins.contains(&[2, 4]) && top.bins.contains(&[30, 28]));
    }
}
