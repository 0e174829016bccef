//! Gabor noise by example (Galerne, Lagae, Lefebvre & Drettakis 2012): an exemplar's power
//! spectrum approximated by a sparse non-negative sum of Gaussians centred on grids of
//! candidate frequencies, one bandwidth per grid; each bandwidth becomes a [`GaborNoise`] whose
//! impulses draw their frequency from the fitted weights
//! ([`Orientation::Spectrum`](spectex_model::Orientation)), and the model is their sum (the
//! paper's bandwidth-quantized Gabor noise; [`GaborFit::model`]).
//!
//! # The fit
//!
//! A Gabor kernel `e^{−πa²|x|²}cos(2π f_k·x)` has the Fourier transform
//! `(1/2a²)[e^{−π|ω−f_k|²/a²} + e^{−π|ω+f_k|²/a²}]`, so an impulse of component `k` adds to the
//! noise's power spectrum (up to a constant)
//! `B_k(ω) = G(ω − f_k) + G(ω + f_k) + 2e^{−2π|f_k|²/a²}·G(ω)`, `G(ω) = e^{−2π|ω|²/a²}`: the
//! two lobes the paper writes and their cross term, which matters only for `|f_k|` within a few
//! lobe widths of 0 and is kept so that the fit describes the noise exactly (up to the kernel's
//! 5% truncation). Frequencies wrap at the pixel grid (a render samples the noise at pixels),
//! so `ω − f_k` is taken per axis to its nearest alias.
//!
//! The weights minimise `½‖P − Σ_k c_k B_k‖²_W + λ‖c‖₁` with `c ≥ 0` (the paper's
//! non-negative basis pursuit denoising) over the exemplar's Welch spectrum `P` without its zero
//! frequency, by projected coordinate descent on the Gram matrix `BᵀWB` (each `B_k` is stored
//! sparsely: its lobes reach a few widths). `W` weighs each bin by the inverse of its 5×5
//! average power plus a floor (a relative least squares): with plain least squares the strong
//! low frequencies took every Gaussian and the weak, broad tail was dropped (gravel's L1 shape
//! distance 0.18 against 0.14 weighted, `cargo xtask reproduce gabor-example`).
//! `λ = sparsity · max_k (BᵀWP)_k`: `sparsity = 0` is the plain non-negative least squares, 1
//! keeps nothing.
//!
//! # The bandwidth
//!
//! Candidates lie on the grid `(i, j)/n` cycles per pixel (half plane, `|f| ≤ 0.5`), spacing
//! `Δ = 1/n`. A lobe `G` is a Gaussian of standard deviation `σ = a/(2√π)`; we take `σ = Δ/2`,
//! i.e. `a = √π/n`: a sum of such Gaussians on the grid with equal weights is flat to
//! `2e^{−2π²σ²/Δ²} ≈ 1.4%` (the Poisson summation formula), so a smooth spectrum is
//! representable without ripple, while a lobe stays narrower than the grid step is long (the
//! finest detail the grid can place). The paper's bandwidth-quantized noise likewise ties one
//! common bandwidth to the spacing of its frequency grid; the excerpts of the paper we could
//! read do not print its constant, so this one is ours, derived here.
//!
//! # Several bandwidths
//!
//! One bandwidth cannot follow a spectrum whose energy lies in the lowest few bins (a 1/f²
//! height map: on a 1/32 grid the lobes are 1/64 cycle per pixel wide, 4 bins of a 256-bin
//! Welch block). With [`GaborFitOptions::bandwidths`] `= m`, grids `n_s = n·2^s`, `s < m`, each
//! with `a_s = √π/n_s`, join the dictionary: the coarsest over the whole half disc, each finer
//! one within `|f| ≤ 8/n_s` (4 steps of the next coarser grid), no finer than the block's bins.
//! All candidates are fitted together. Each bandwidth that keeps a Gaussian becomes one noise
//! (its own grid of cells of its kernel radius, seed `seed + s`), with the variance share
//! `E_s/ΣE`, `E_s = Σ_k c_k|B_k|` (each column's sum over all bins, the zero frequency
//! included, the noise's own variance), and the impulses per kernel are shared in the same
//! proportion (each at least a tenth of an equal share), so the sum costs the kernel
//! evaluations of one noise with [`GaborFitOptions::impulses_per_kernel`]. On the four
//! exemplars of `cargo xtask reproduce gabor-example` (512², the exemplar's Welch block),
//! dirt's L1 shape distance fell from 0.80 (one bandwidth) to 0.29 (four).
//!
//! # Welch's estimate
//!
//! The spectrum fitted is a Welch estimate (Hann taper, each block's mean removed), and a
//! render is measured the same way: Gaussians fitted to the estimate are blurred a second time
//! when measured, which the narrow lobes near the zero frequency feel (as LRP's fit does,
//! [`crate::spectrum_fit::sharpen_welch`]). With [`GaborFitOptions::welch`] each column `B_k` is
//! replaced by its expected Welch estimate, so the fit compares like with like; this rather
//! than deconvolving the target, which amplified the estimate's noise (sand's distance 0.185
//! deconvolved against 0.130 modelled; dirt's 0.29 without either, 0.143 modelled).

use ndarray::{Array2, ArrayView2};
use spectex_model::combine::CombineOp;
use spectex_model::{Combine, GaborNoise, Model};

use crate::SamplingError;
use crate::fit::exemplar_psd;
use crate::spectrum_fit::WelchOperator;

/// Smallest exemplar side accepted: the Welch block (a power of two below the side) is then at
/// least 8 bins, a spectrum with some shape.
pub const MIN_GABOR_EXEMPLAR_SIDE: usize = 16;

/// Options of [`fit_gabor`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaborFitOptions {
    /// `n`: candidates at multiples of `1/n` cycles per pixel, `4..=48` (at 48 the half disc
    /// holds 905 candidates, under the model's 1024 components). Capped at the Welch block's
    /// side (no finer than its bins).
    pub grid: u32,
    /// `λ / max_k (BᵀP)_k`, `[0, 1)`: 0 is the plain non-negative least squares.
    pub sparsity: f64,
    /// Mean impulses per kernel footprint of the noise, `[0.01, 1000]`.
    pub impulses_per_kernel: f32,
    /// The noise's seed.
    pub seed: u32,
    /// Bandwidths, `1..=4`: 1 is one bandwidth on the `1/n` grid; each further one halves the
    /// grid's spacing and the bandwidth near the zero frequency (module docs), no finer than the
    /// Welch block's bins.
    pub bandwidths: u32,
    /// Whether each Gaussian is compared with the spectrum as Welch's estimate would measure
    /// it (its expected estimate: the Hann taper's `[1/6, 2/3, 1/6]` blur per axis and each
    /// block's mean removed, as [`crate::spectrum_fit::sharpen_welch`] models it for LRP)
    /// rather than as it is: the spectrum given is a Welch estimate, and a render is measured
    /// the same way (module docs). `false` fits the estimate as a spectrum.
    pub welch: bool,
}

impl GaborFitOptions {
    /// `n = 32`: a 1/32 cycles-per-pixel grid, lobes of bandwidth `a = √π/32 ≈ 0.055`, kernels
    /// of radius about 18 pixels.
    pub const DEFAULT_GRID: u32 = 32;
    /// A little sparsity: weights below 1% of the strongest correlation are dropped.
    pub const DEFAULT_SPARSITY: f64 = 0.01;
    /// Lagae et al.'s examples use tens of impulses per kernel.
    pub const DEFAULT_IMPULSES_PER_KERNEL: f32 = 32.0;
    /// The project's default seed.
    pub const DEFAULT_SEED: u32 = spectex_model::DEFAULT_SEED;
    /// Four bandwidths: down to a lobe of `1/(16n)` cycles per pixel near the zero frequency,
    /// which a 1/f² spectrum (a height map's) needs.
    pub const DEFAULT_BANDWIDTHS: u32 = 4;

    /// Checks every option against its range.
    ///
    /// # Errors
    /// [`SamplingError::OutOfRange`] naming the option.
    pub fn validate(&self) -> Result<(), SamplingError> {
        if !(4..=48).contains(&self.grid) {
            return Err(SamplingError::OutOfRange {
                parameter: "grid",
                value: f64::from(self.grid),
                range: "4..=48 candidate frequencies per cycle",
            });
        }
        if !(self.sparsity >= 0.0 && self.sparsity < 1.0) {
            return Err(SamplingError::OutOfRange {
                parameter: "sparsity",
                value: self.sparsity,
                range: "[0, 1)",
            });
        }
        if !(1..=MAX_BANDWIDTHS).contains(&self.bandwidths) {
            return Err(SamplingError::OutOfRange {
                parameter: "bandwidths",
                value: f64::from(self.bandwidths),
                range: "1..=4 bandwidths",
            });
        }
        let ipk = f64::from(self.impulses_per_kernel);
        if !(0.01..=1000.0).contains(&ipk) && ipk != f64::from(0.01f32) {
            return Err(SamplingError::OutOfRange {
                parameter: "impulses_per_kernel",
                value: ipk,
                range: "[0.01, 1000]",
            });
        }
        Ok(())
    }
}

impl Default for GaborFitOptions {
    fn default() -> Self {
        Self {
            grid: Self::DEFAULT_GRID,
            sparsity: Self::DEFAULT_SPARSITY,
            impulses_per_kernel: Self::DEFAULT_IMPULSES_PER_KERNEL,
            seed: Self::DEFAULT_SEED,
            bandwidths: Self::DEFAULT_BANDWIDTHS,
            welch: true,
        }
    }
}

/// A fitted Gabor noise by example and how well its Gaussians match the spectrum.
#[derive(Debug, Clone, PartialEq)]
pub struct GaborFit {
    /// The validated noises, one per bandwidth that kept a Gaussian, the coarsest (the `1/n`
    /// grid's) first; their sum ([`GaborFit::model`]) has the exemplar's mean and variance.
    pub noises: Vec<GaborNoise>,
    /// Candidates the fit kept (the model's components).
    pub components: usize,
    /// Candidates considered.
    pub candidates: usize,
    /// `‖P − Σ c_k B_k‖ / ‖P‖` over the non-zero frequencies.
    pub relative_residual: f64,
    /// The candidate grid `n` used (the option, capped at the Welch block).
    pub grid: u32,
}

/// Most bandwidths of a fit ([`GaborFitOptions::bandwidths`]).
pub const MAX_BANDWIDTHS: u32 = 4;

/// A finer bandwidth's candidates lie within this many of its grid steps of the zero frequency
/// (4 steps of the next coarser grid, 8 of its lobes' standard deviations).
const FINE_REACH: f64 = 8.0;

impl GaborFit {
    /// The model: the one noise, or the sum ([`CombineOp::Add`]) of one noise per bandwidth
    /// (the paper's bandwidth-quantized Gabor noise), costing the sum of their kernel
    /// evaluations.
    ///
    /// # Errors
    /// [`SamplingError::Model`] if the sum is refused (more than 8 operands: never, at most
    /// [`MAX_BANDWIDTHS`]).
    pub fn model(&self) -> Result<Model, SamplingError> {
        match self.noises.as_slice() {
            [one] => Ok(Model::Gabor(one.clone())),
            many => Ok(Combine::builder()
                .op(CombineOp::Add)
                .operands(many.iter().cloned().map(Model::Gabor).collect())
                .build()
                .map_err(SamplingError::Model)?
                .into()),
        }
    }
}

/// Fits a Gabor noise by example to one grey channel: its Welch spectrum, variance and mean
/// ([`crate::exemplar_psd`]), then [`fit_gabor_psd`].
///
/// # Errors
/// An option out of range, an image with a smaller side below [`MIN_GABOR_EXEMPLAR_SIDE`]
/// (`OutOfRange` naming `exemplar's smaller side`), a non-finite pixel
/// ([`SamplingError::NonFinite`]), a constant image ([`SamplingError::NoEnergy`]).
pub fn fit_gabor(
    channel: ArrayView2<'_, f64>,
    options: &GaborFitOptions,
) -> Result<GaborFit, SamplingError> {
    options.validate()?;
    let side = channel.nrows().min(channel.ncols());
    if side < MIN_GABOR_EXEMPLAR_SIDE {
        return Err(SamplingError::OutOfRange {
            parameter: "exemplar's smaller side",
            value: side as f64,
            range: "16..=8192 pixels",
        });
    }
    let (psd, mean) = exemplar_psd(channel)?;
    match fit_gabor_psd(psd.view(), mean, options) {
        Err(SamplingError::NoEnergy { .. }) => Err(SamplingError::NoEnergy { parameter: "image" }),
        other => other,
    }
}

/// Fits a Gabor noise by example to an uncentred `T × T` power spectrum normalised so that
/// `Σ_{f≠0} P/T²` is the variance (as [`crate::exemplar_psd`] returns it), with mean `mean`.
///
/// # Errors
/// A spectrum that is not square with a side in `8..=4096` ([`SamplingError::Shape`]), has a
/// non-finite or negative value, or no energy outside the zero frequency; an option out of
/// range; a model out of range ([`SamplingError::Model`]).
pub fn fit_gabor_psd(
    psd: ArrayView2<'_, f64>,
    mean: f64,
    options: &GaborFitOptions,
) -> Result<GaborFit, SamplingError> {
    options.validate()?;
    let (h, w) = psd.dim();
    if h != w || !(8..=4096).contains(&h) {
        return Err(SamplingError::Shape {
            parameter: "power spectrum",
            height: h,
            width: w,
            min_side: 8,
            max_side: 4096,
        });
    }
    for ((row, column), &value) in psd.indexed_iter() {
        if !value.is_finite() {
            return Err(SamplingError::NonFinite {
                parameter: "power spectrum",
                value,
                row,
                column,
            });
        }
        if value < 0.0 {
            return Err(SamplingError::Negative {
                parameter: "power spectrum",
                value,
                row,
                column,
            });
        }
    }
    if !mean.is_finite() {
        return Err(SamplingError::OutOfRange {
            parameter: "mean",
            value: mean,
            range: "finite",
        });
    }
    let t = h;
    let mut target = psd.to_owned();
    target[[0, 0]] = 0.0;
    let variance = target.sum() / (t * t) as f64;
    if variance <= 0.0 {
        return Err(SamplingError::NoEnergy {
            parameter: "power spectrum",
        });
    }
    let n = (options.grid as usize).min(t);
    // Every bandwidth's grid `n_s = n·2^s` (at most the block's bins, and a ≥ 0.001) and its
    // candidates: the whole half disc for the coarsest, `|f| ≤ 8/n_s` for the finer ones.
    let mut scales: Vec<(usize, usize)> = Vec::new(); // (grid, first candidate)
    let mut all: Vec<([f32; 2], f64)> = Vec::new();
    for s in 0..options.bandwidths {
        let ns = n << s;
        if s > 0 && ns > t.min(1024) {
            break;
        }
        let a = std::f64::consts::PI.sqrt() / ns as f64;
        scales.push((ns, all.len()));
        all.extend(
            candidates(ns)
                .into_iter()
                .filter(|f| {
                    s == 0 || f64::from(f[0]).hypot(f64::from(f[1])) * ns as f64 <= FINE_REACH
                })
                .map(|f| (f, a)),
        );
    }
    let basis = Basis::new(&all, t, options.welch);
    // Relative least squares: each bin weighted by 1/(its 5×5 average power + a floor), so a
    // spectrum's weak tail counts as much as its strong peak (the shape distance is L1).
    let smooth = spectex_spectrum::normalised_smoothed(target.view());
    let floor = 1e-3 / (t * t) as f64;
    let weight = smooth.mapv(|v| 1.0 / (v + floor));
    let weighted = &target * &weight;
    let b: Vec<f64> = basis.columns.iter().map(|c| c.dot(&weighted)).collect();
    let gram = basis.gram(weight.as_slice().unwrap_or(&[]));
    let lambda = options.sparsity * b.iter().copied().fold(0.0, f64::max);
    let c = nonnegative_lasso(&gram, &b, lambda);

    // Σ c_k B_k, flat row-major (the columns never touch the zero frequency).
    let mut fitted = vec![0.0f64; t * t];
    for (col, &ck) in basis.columns.iter().zip(&c) {
        if ck > 0.0 {
            for &(i, v) in &col.entries {
                fitted[i as usize] += ck * v;
            }
        }
    }
    let norm = target.iter().map(|p| p * p).sum::<f64>().sqrt();
    let residual = target
        .iter()
        .zip(fitted.iter())
        .map(|(p, q)| (p - q).powi(2))
        .sum::<f64>()
        .sqrt();

    // Per bandwidth: its kept components (weights relative to its largest) and its power
    // `E_s = Σ c_k·|B_k|` (the lobes' whole sum, zero frequency included: the noise's variance).
    /// A bandwidth's grid, kept `(frequency, relative weight)` and power `E_s`.
    type Group = (usize, Vec<([f32; 2], f32)>, f64);
    let mut groups: Vec<Group> = Vec::new();
    for (s, &(ns, first)) in scales.iter().enumerate() {
        let last = scales.get(s + 1).map_or(all.len(), |&(_, f)| f);
        let range = first..last;
        let largest = c[range.clone()].iter().copied().fold(0.0, f64::max);
        let kept: Vec<([f32; 2], f32)> = range
            .clone()
            .filter(|&k| c[k] > 0.0 && (c[k] / largest) as f32 > 0.0)
            .map(|k| (all[k].0, (c[k] / largest) as f32))
            .collect();
        let power: f64 = range.map(|k| c[k] * basis.power[k]).sum();
        if !kept.is_empty() && power > 0.0 {
            groups.push((ns, kept, power));
        }
    }
    if groups.is_empty() {
        return Err(SamplingError::NoEnergy {
            parameter: "power spectrum",
        });
    }
    let total_power: f64 = groups.iter().map(|g| g.2).sum();
    // The impulses per kernel are shared in proportion to the variances (at least a tenth of an
    // equal share each), so the sum costs what one noise of `impulses_per_kernel` would.
    let floor_share = 0.1 / groups.len() as f64;
    let shares: Vec<f64> = groups
        .iter()
        .map(|g| (g.2 / total_power).max(floor_share))
        .collect();
    let share_sum: f64 = shares.iter().sum();
    let mut noises = Vec::with_capacity(groups.len());
    let mut components = 0;
    for (s, ((ns, kept, power), share)) in groups.into_iter().zip(shares).enumerate() {
        let (frequencies, weights): (Vec<[f32; 2]>, Vec<f32>) = kept.into_iter().unzip();
        components += frequencies.len();
        let ipk = if s == 0 && share == share_sum {
            options.impulses_per_kernel
        } else {
            (f64::from(options.impulses_per_kernel) * share / share_sum).max(0.01) as f32
        };
        let noise = GaborNoise::builder()
            .seed(options.seed.wrapping_add(s as u32))
            .mean(if s == 0 { mean as f32 } else { 0.0 })
            .bandwidth((std::f64::consts::PI.sqrt() / ns as f64) as f32)
            .impulses_per_kernel(ipk)
            .spectrum(frequencies, weights)
            .std_dev((variance * power / total_power).sqrt() as f32)
            .build()
            .map_err(SamplingError::Model)?;
        noises.push(noise);
    }
    Ok(GaborFit {
        noises,
        components,
        candidates: all.len(),
        relative_residual: residual / norm,
        grid: n as u32,
    })
}

/// The candidate frequencies `(i, j)/n`, cycles per pixel, of the half plane (`j > 0`, or
/// `j = 0` and `i ≥ 0`: `f` and `−f` are one component) with `|f| ≤ 0.5` as the model checks it
/// (on the f32 values).
#[must_use]
pub fn candidates(n: usize) -> Vec<[f32; 2]> {
    let half = (n / 2) as i64;
    let mut out = Vec::new();
    for j in 0..=half {
        for i in -half..=half {
            if j == 0 && i < 0 {
                continue;
            }
            let f = [(i as f64 / n as f64) as f32, (j as f64 / n as f64) as f32];
            if f64::from(f[0]).hypot(f64::from(f[1])) <= 0.5 {
                out.push(f);
            }
        }
    }
    out
}

/// One basis function `B_k` on the `T × T` grid, sparse: (flat index, value), indices sorted.
#[derive(Debug, Clone)]
struct Column {
    entries: Vec<(u32, f64)>,
}

impl Column {
    fn dot(&self, dense: &Array2<f64>) -> f64 {
        let s = dense.as_slice().unwrap_or(&[]);
        self.entries
            .iter()
            .map(|&(i, v)| v * s.get(i as usize).copied().unwrap_or(0.0))
            .sum()
    }
}

/// The basis functions of every candidate and where their lobes lie (for the Gram matrix).
struct Basis {
    columns: Vec<Column>,
    /// Each column's lobe centres, in bins (signed, unwrapped).
    centres: Vec<Vec<[f64; 2]>>,
    /// The reach of each column's lobes, bins.
    reach: Vec<f64>,
    /// Each column's sum over every bin, the zero frequency included.
    power: Vec<f64>,
    t: usize,
}

impl Basis {
    /// The columns of the candidates `(f, a)`: frequency, cycles per pixel, and bandwidth.
    /// With `welch`, each column is Welch's expected estimate of its lobes
    /// ([`WelchOperator`]); its power stays the lobes' own.
    fn new(candidates: &[([f32; 2], f64)], t: usize, welch: bool) -> Self {
        let op = WelchOperator { n: t };
        let mut dense = if welch {
            Array2::zeros((t, t))
        } else {
            Array2::zeros((0, 0))
        };
        let tf = t as f64;
        let mut scratch = vec![0.0f64; t * t];
        let mut touched: Vec<u32> = Vec::new();
        let mut columns = Vec::with_capacity(candidates.len());
        let mut centres = Vec::with_capacity(candidates.len());
        let mut reaches = Vec::with_capacity(candidates.len());
        let mut powers = Vec::with_capacity(candidates.len());
        for &(f, a) in candidates {
            // A lobe is e^{−|ω|²/(2σ²)} with σ = a/(2√π); beyond 6σ it is below 1.6e-8 of its
            // peak.
            let sigma = a / (2.0 * std::f64::consts::PI.sqrt());
            let reach = (6.0 * sigma * tf).ceil();
            let f = [f64::from(f[0]), f64::from(f[1])];
            let cross =
                2.0 * (-2.0 * std::f64::consts::PI * (f[0] * f[0] + f[1] * f[1]) / (a * a)).exp();
            let mut lobes = vec![(f, 1.0), ([-f[0], -f[1]], 1.0)];
            if cross > 1e-12 {
                lobes.push(([0.0, 0.0], cross));
            }
            let mut power = 0.0;
            for &(c, weight) in &lobes {
                // Bins within `reach` of the centre, each at its nearest alias of the centre.
                let (cx, cy) = (c[0] * tf, c[1] * tf);
                let (x0, x1) = ((cx - reach).ceil() as i64, (cx + reach).floor() as i64);
                let (y0, y1) = ((cy - reach).ceil() as i64, (cy + reach).floor() as i64);
                for y in y0..=y1.min(y0 + t as i64 - 1) {
                    for x in x0..=x1.min(x0 + t as i64 - 1) {
                        let (dx, dy) = ((x as f64 - cx) / tf, (y as f64 - cy) / tf);
                        let g = (-2.0 * std::f64::consts::PI * (dx * dx + dy * dy) / (a * a)).exp();
                        power += weight * g;
                        let k =
                            y.rem_euclid(t as i64) as usize * t + x.rem_euclid(t as i64) as usize;
                        if k == 0 {
                            continue; // the zero frequency is not fitted
                        }
                        if scratch[k] == 0.0 {
                            touched.push(k as u32);
                        }
                        scratch[k] += weight * g;
                    }
                }
            }
            touched.sort_unstable();
            let entries = if welch {
                for &k in &touched {
                    dense[[k as usize / t, k as usize % t]] = scratch[k as usize];
                }
                let measured = op.apply(&dense);
                for &k in &touched {
                    dense[[k as usize / t, k as usize % t]] = 0.0;
                }
                measured
                    .iter()
                    .enumerate()
                    .filter(|&(k, &v)| k != 0 && v != 0.0)
                    .map(|(k, &v)| (k as u32, v))
                    .collect()
            } else {
                touched.iter().map(|&k| (k, scratch[k as usize])).collect()
            };
            for &k in &touched {
                scratch[k as usize] = 0.0;
            }
            touched.clear();
            columns.push(Column { entries });
            centres.push(lobes.iter().map(|(c, _)| [c[0] * tf, c[1] * tf]).collect());
            reaches.push(reach);
            powers.push(power);
        }
        Self {
            columns,
            centres,
            reach: reaches,
            power: powers,
            t,
        }
    }

    /// Whether some lobes of columns `i` and `j` come within two reaches (on the torus).
    fn overlap(&self, i: usize, j: usize) -> bool {
        let t = self.t as f64;
        let wrap = |d: f64| {
            let d = d.rem_euclid(t);
            d.min(t - d)
        };
        self.centres[i].iter().any(|a| {
            self.centres[j].iter().any(|b| {
                wrap(a[0] - b[0]).hypot(wrap(a[1] - b[1])) <= self.reach[i] + self.reach[j] + 1.5
            })
        })
    }

    /// `BᵀWB` for the bin weights `weight`, dense (its pairs of distant candidates are 0).
    fn gram(&self, weight: &[f64]) -> Vec<Vec<f64>> {
        let k = self.columns.len();
        let mut q = vec![vec![0.0; k]; k];
        let mut scratch = vec![0.0f64; self.t * self.t];
        for i in 0..k {
            for &(e, v) in &self.columns[i].entries {
                scratch[e as usize] = v * weight.get(e as usize).copied().unwrap_or(1.0);
            }
            for j in i..k {
                if !self.overlap(i, j) {
                    continue;
                }
                let d: f64 = self.columns[j]
                    .entries
                    .iter()
                    .map(|&(e, v)| v * scratch[e as usize])
                    .sum();
                q[i][j] = d;
                q[j][i] = d;
            }
            for &(e, _) in &self.columns[i].entries {
                scratch[e as usize] = 0.0;
            }
        }
        q
    }
}

/// Most sweeps of the coordinate descent.
const MAX_SWEEPS: usize = 20_000;

/// `argmin_{c ≥ 0} ½cᵀQc − bᵀc + λΣc` by projected (cyclic) coordinate descent: each step sets
/// `c_k` to its exact minimiser given the others, `max(0, c_k − (g_k + λ)/Q_kk)` with the
/// gradient `g = Qc − b` kept up to date. Stops when a sweep moves no coordinate by more than
/// 1e-13 of the largest (converged to rounding) or after [`MAX_SWEEPS`].
#[must_use]
pub fn nonnegative_lasso(q: &[Vec<f64>], b: &[f64], lambda: f64) -> Vec<f64> {
    let k = b.len();
    let mut c = vec![0.0; k];
    let mut g: Vec<f64> = b.iter().map(|v| -v).collect();
    for _ in 0..MAX_SWEEPS {
        let mut moved = 0.0f64;
        for i in 0..k {
            let qii = q[i][i];
            if qii <= 0.0 {
                continue;
            }
            let next = (c[i] - (g[i] + lambda) / qii).max(0.0);
            let delta = next - c[i];
            if delta != 0.0 {
                c[i] = next;
                for (gj, qij) in g.iter_mut().zip(&q[i]) {
                    *gj += qij * delta;
                }
                moved = moved.max(delta.abs() * qii.sqrt());
            }
        }
        let scale = c
            .iter()
            .zip(q)
            .enumerate()
            .map(|(i, (ci, row))| ci * row[i].sqrt())
            .fold(0.0, f64::max);
        if moved <= 1e-13 * scale.max(f64::MIN_POSITIVE) {
            break;
        }
    }
    c
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::MAX_GABOR_COMPONENTS;
    use std::f64::consts::PI;

    /// A spectrum that is exactly three of the noise's basis functions on the grid, written here
    /// from the kernel's Fourier transform (`|ĝ|²` of `e^{−πa²|x|²}cos(2πf·x)`, up to a
    /// constant: `[e^{−π|ω−f|²/a²} + e^{−π|ω+f|²/a²}]²`, on the nearest alias of `ω`), not from
    /// the fit's code: the weights come back.
    pub fn fit_recovers_three_gaussians_on_the_grid() {
        let (t, n) = (64usize, 16usize);
        let a = PI.sqrt() / n as f64;
        let truth = [([3i32, 2i32], 1.0f64), ([-4, 5], 0.5), ([1, 0], 0.25)];
        let signed = |k: usize| {
            if k < t / 2 {
                k as f64 / t as f64
            } else {
                k as f64 / t as f64 - 1.0
            }
        };
        let psd = Array2::from_shape_fn((t, t), |(y, x)| {
            let w = [signed(x), signed(y)];
            truth
                .iter()
                .map(|&(ij, c)| {
                    let f = [f64::from(ij[0]) / n as f64, f64::from(ij[1]) / n as f64];
                    let lobe = |s: f64| {
                        let dx = w[0] - s * f[0];
                        let dy = w[1] - s * f[1];
                        let wrap = |d: f64| d - d.round();
                        (-PI * (wrap(dx).powi(2) + wrap(dy).powi(2)) / (a * a)).exp()
                    };
                    c * (lobe(1.0) + lobe(-1.0)).powi(2)
                })
                .sum::<f64>()
        });
        let options = GaborFitOptions {
            grid: n as u32,
            sparsity: 0.0,
            bandwidths: 1,
            welch: false,
            ..GaborFitOptions::default()
        };
        let fit = fit_gabor_psd(psd.view(), 0.5, &options).unwrap();
        assert!(
            fit.relative_residual < 1e-6,
            "residual {}",
            fit.relative_residual
        );
        let [model] = fit.noises.as_slice() else {
            panic!("one bandwidth asked, {} noises", fit.noises.len())
        };
        let spectex_model::Orientation::Spectrum {
            frequencies,
            weights,
        } = &model.orientation
        else {
            panic!("not a spectrum: {:?}", model.orientation)
        };
        let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
        for &(ij, c) in &truth {
            let f = [ij[0] as f32 / n as f32, ij[1] as f32 / n as f32];
            let k = frequencies
                .iter()
                .position(|g| *g == f)
                .unwrap_or_else(|| panic!("component {f:?} missing from {frequencies:?}"));
            let p = f64::from(weights[k]) / total;
            assert!(
                (p - c / 1.75).abs() < 1e-5,
                "{f:?}: weight {p} vs {}",
                c / 1.75
            );
        }
        let stray: f64 = frequencies
            .iter()
            .zip(weights)
            .filter(|(f, _)| {
                !truth
                    .iter()
                    .any(|(ij, _)| **f == [ij[0] as f32 / n as f32, ij[1] as f32 / n as f32])
            })
            .map(|(_, &w)| f64::from(w) / total)
            .sum();
        assert!(stray < 1e-5, "weight {stray} on other components");
        assert_eq!(model.bandwidth, a as f32);
        assert_eq!(model.mean, 0.5);
    }

    /// The model's variance (the noises' `(amplitude · unit_std_dev)²` summed: independent
    /// noises) is the spectrum's `Σ_{f≠0} P/T²`, with one bandwidth and with several.
    pub fn fitted_variance_is_the_spectrum_total() {
        let t = 64;
        // A ring at radius 6 bins plus a 1/f² peak at the zero frequency (which the finer
        // bandwidths fit).
        let psd = Array2::from_shape_fn((t, t), |(y, x)| {
            let r2 = (x.min(t - x).pow(2) + y.min(t - y).pow(2)) as f64;
            (-(r2 - 36.0).powi(2) / 20.0).exp() + 1.0 / r2.max(1.0)
        });
        let want = (psd.sum() - psd[[0, 0]]) / (t * t) as f64;
        for bandwidths in [1, 2, 4] {
            let options = GaborFitOptions {
                bandwidths,
                ..GaborFitOptions::default()
            };
            let fit = fit_gabor_psd(psd.view(), 0.25, &options).unwrap();
            let got: f64 = fit
                .noises
                .iter()
                .map(|g| (f64::from(g.amplitude) * g.unit_std_dev()).powi(2))
                .sum();
            assert!(
                (got / want - 1.0).abs() < 1e-5,
                "{bandwidths} bandwidths: {got} vs {want}"
            );
            assert!(fit.noises.len() <= bandwidths as usize);
            // The mean is carried by the first noise only.
            let means: Vec<f32> = fit.noises.iter().map(|g| g.mean).collect();
            assert_eq!(means[0], 0.25, "{means:?}");
            assert!(means[1..].iter().all(|&m| m == 0.0), "{means:?}");
            for g in &fit.noises {
                let spectex_model::Orientation::Spectrum { frequencies, .. } = &g.orientation
                else {
                    panic!("not a spectrum: {:?}", g.orientation)
                };
                assert!(frequencies.len() <= MAX_GABOR_COMPONENTS);
            }
        }
    }

    /// Several bandwidths: each noise's bandwidth is `√π/n_s` on the grids `n·2^s` (capped at
    /// the block's bins: 16, 32 and 64 for a 64-bin block and n = 16, no 128), the impulses per
    /// kernel add up to the option's, and the model is their sum.
    pub fn several_bandwidths_sum_at_the_same_cost() {
        let t = 64;
        let psd = Array2::from_shape_fn((t, t), |(y, x)| {
            let r2 = (x.min(t - x).pow(2) + y.min(t - y).pow(2)) as f64;
            (-(r2 - 100.0).powi(2) / 40.0).exp() + 4.0 / r2.max(1.0).powi(2)
        });
        let options = GaborFitOptions {
            grid: 16,
            sparsity: 0.0,
            bandwidths: 4,
            impulses_per_kernel: 40.0,
            ..GaborFitOptions::default()
        };
        let fit = fit_gabor_psd(psd.view(), 0.5, &options).unwrap();
        let got: Vec<f32> = fit.noises.iter().map(|g| g.bandwidth).collect();
        let want: Vec<f32> = [16.0, 32.0, 64.0]
            .iter()
            .map(|n: &f64| (PI.sqrt() / n) as f32)
            .collect();
        assert_eq!(got, want);
        let ipk: f64 = fit
            .noises
            .iter()
            .map(|g| f64::from(g.impulses_per_kernel))
            .sum();
        assert!((ipk - 40.0).abs() < 1e-4, "{ipk}");
        let seeds: Vec<u32> = fit.noises.iter().map(|g| g.seed).collect();
        assert_eq!(
            seeds,
            vec![options.seed, options.seed + 1, options.seed + 2]
        );
        let Model::Combine(c) = fit.model().unwrap() else {
            panic!("three bandwidths: not a sum")
        };
        assert_eq!(c.op, CombineOp::Add);
        assert_eq!(
            c.operands,
            fit.noises
                .iter()
                .cloned()
                .map(Model::Gabor)
                .collect::<Vec<_>>()
        );
        // One bandwidth: the plain noise.
        let one = GaborFitOptions {
            bandwidths: 1,
            ..options
        };
        let fit = fit_gabor_psd(psd.view(), 0.5, &one).unwrap();
        assert!(matches!(fit.model().unwrap(), Model::Gabor(_)));
        assert_eq!(fit.noises[0].impulses_per_kernel, 40.0);
    }

    pub fn bad_inputs_name_the_parameter() {
        let ok = GaborFitOptions::default();
        let image = Array2::from_shape_fn((32, 32), |(y, x)| ((x * 7 + y * 3) % 5) as f64);
        let out_of_range = |r: Result<GaborFit, SamplingError>| match r {
            Err(SamplingError::OutOfRange { parameter, .. }) => parameter,
            other => panic!("{other:?}"),
        };
        for (options, name) in [
            (GaborFitOptions { grid: 3, ..ok }, "grid"),
            (GaborFitOptions { grid: 49, ..ok }, "grid"),
            (
                GaborFitOptions {
                    bandwidths: 0,
                    ..ok
                },
                "bandwidths",
            ),
            (
                GaborFitOptions {
                    bandwidths: 5,
                    ..ok
                },
                "bandwidths",
            ),
            (
                GaborFitOptions {
                    sparsity: 1.0,
                    ..ok
                },
                "sparsity",
            ),
            (
                GaborFitOptions {
                    sparsity: f64::NAN,
                    ..ok
                },
                "sparsity",
            ),
            (
                GaborFitOptions {
                    impulses_per_kernel: 0.0,
                    ..ok
                },
                "impulses_per_kernel",
            ),
        ] {
            assert_eq!(out_of_range(fit_gabor(image.view(), &options)), name);
        }
        let small = Array2::from_elem((8, 64), 0.5);
        assert_eq!(
            out_of_range(fit_gabor(small.view(), &ok)),
            "exemplar's smaller side"
        );
        let constant = Array2::from_elem((32, 32), 0.5);
        assert!(matches!(
            fit_gabor(constant.view(), &ok),
            Err(SamplingError::NoEnergy { parameter: "image" })
        ));
        let mut nan = image.clone();
        nan[[3, 4]] = f64::NAN;
        assert!(matches!(
            fit_gabor(nan.view(), &ok),
            Err(SamplingError::NonFinite {
                row: 3,
                column: 4,
                ..
            })
        ));
        let oblong = Array2::<f64>::zeros((16, 32));
        assert!(matches!(
            fit_gabor_psd(oblong.view(), 0.0, &ok),
            Err(SamplingError::Shape { .. })
        ));
    }

    /// Every candidate is inside the model's range and the count stays under its cap.
    pub fn candidates_fit_the_model() {
        for n in [4usize, 5, 16, 32, 48] {
            let c = candidates(n);
            assert!(c.len() <= MAX_GABOR_COMPONENTS, "n = {n}: {}", c.len());
            assert!(
                c.iter()
                    .all(|f| f64::from(f[0]).hypot(f64::from(f[1])) <= 0.5)
            );
        }
    }
}
