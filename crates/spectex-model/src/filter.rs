//! Filtering of minified renders: what a pixel that covers more than one model pixel keeps of
//! each spectral component, defined once (in f64, on the host) for every evaluator.
//!
//! A render whose pixels lie `s > 1` model pixels apart ([`Window::footprint`](crate::Window::footprint))
//! can only represent frequencies below its Nyquist frequency `1/(2s)` per axis; what lies above
//! aliases. LRP §6 ("Texture filtering") fades such components out (frequency clamping), and
//! phasor noise §3.3 suggests adjusting its harmonics' weights for the same purpose. Each LRP
//! cosine (the texture's random-phase strata included) is multiplied by the amplitude gain
//! [`component_gain`] of its frequency ([`lrp_gains`]); each octave of fBm, turbulence and
//! ridged noise by the response at its RMS frequency, the nonlinear ones faded toward their
//! expected value ([`classic_fade`]); a square phasor profile's harmonics likewise
//! ([`filtered_square`]); a texture's fixed-phase structure blocks by
//! [`crate::texture::Structure::eval_filtered`] (their cosines faded, their zero frequencies
//! read from the mipmap of block means, §6). Worley octaves fade toward their measured
//! moments ([`worley_statistics`]); every phasor profile through its Fourier series
//! ([`filtered_sine`], [`filtered_triangle`], [`filtered_sawtooth`], [`filtered_samples`], the
//! explicit harmonics weighted alike). Not filtered yet: Gabor, wavelet and texton noise.
//!
//! **Which gain.** The reference a minified render is judged against is the field box-filtered
//! over the pixel's `s × s` footprint: it attenuates a cosine of frequency `f` by
//! `sinc(f_x·s)·sinc(f_y·s)` (`sinc(u) = sin(πu)/(πu)`), in band and out of it. The exact box
//! attenuation alone keeps 41% of the amplitude of a component at the Nyquist frequency and
//! lets side lobes through above it (they alias); a clamp alone (1 in band, 0 above) removes
//! the aliases but keeps in-band components at full amplitude where the box attenuates them
//! (to 0.64 at the Nyquist frequency), so the variance exceeds the reference's. The gain used
//! is their product, per axis `H(u) = sinc(u)·T(u)` with `u = |f|·s` and `T` a clamp that is 1
//! up to [`FADE_START`] and falls smoothly (`cos²`) to 0 at [`FADE_END`], across the Nyquist
//! frequency `u = ½`: in band it is the box's own attenuation (the variance follows the
//! reference's), nothing beyond `u = 0.55` survives, and the fade keeps the gain continuous in
//! `s` (no popping as a camera moves). The variance lost against the reference is the box's own
//! aliased energy (its side lobes above Nyquist) and the fade's share below Nyquist.
//!
//! **Where the fade sits** trades the two aliasing targets of issue 16 against each other (energy
//! above Nyquist ≤ 10% of an unfiltered render's, variance within 5% of the box-filtered
//! reference's). Predicted from `lrp-gravel`'s cosines and the Gaussian spread below, at a
//! footprint of 4 (energy ratio, variance error): fade over `[0.3, 0.5]`: 0.043, −10.7% (measured
//! by the CPU test: 0.042, −11.0%); `[0.4, 0.5]`: 0.061, −5.9%; `[0.45, 0.55]`: 0.073, −3.6%;
//! `[0.5, 0.7]`: 0.088, −1.4%. A fade that ends at Nyquist loses too much variance; one that
//! starts at it lets too much alias; `[0.45, 0.55]`, centred on Nyquist, leaves a margin on
//! both.
//!
//! **Components with a spread.** An LRP cosine is windowed (Kaiser–Bessel, width `Δ`): its
//! energy spreads around `f` with a per-axis standard deviation `σ = c/Δ`
//! ([`crate::window::window_bandwidth`]). Its energy gain is then the expectation of `H²` over
//! that spread, modelled as a Gaussian: `E[H(s·(f + σZ))²]` per axis, `Z` standard normal,
//! computed by Simpson's rule ([`axis_energy_gain`]). A narrow window (`Δ` of a few pixels at a
//! footprint of 4) spreads most of its energy past the Nyquist frequency and fades out whole.
//!
//! The mean is untouched: every faded component has zero mean (random phase); kinds whose
//! components do not (turbulence's `|noise|`) replace what they fade by its expected value.

/// Where the clamp `T` starts to fall, in cycles per output pixel (`u = |f|·s`). Below it the
/// gain is exactly the box filter's `sinc(u)`.
pub const FADE_START: f64 = 0.45;

/// Where the clamp `T` reaches 0, in cycles per output pixel: nothing beyond survives.
pub const FADE_END: f64 = 0.55;

/// The Nyquist frequency in cycles per output pixel.
pub const NYQUIST: f64 = 0.5;

/// `sin(πu)/(πu)`, 1 at 0.
#[must_use]
pub fn sinc(u: f64) -> f64 {
    if u.abs() < 1e-9 {
        1.0
    } else {
        let x = std::f64::consts::PI * u;
        x.sin() / x
    }
}

/// The clamp `T(u)`: 1 for `|u| ≤ FADE_START`, `cos²` down to 0 at `|u| = FADE_END`, 0 beyond.
#[must_use]
pub fn clamp_taper(u: f64) -> f64 {
    let u = u.abs();
    if u <= FADE_START {
        1.0
    } else if u >= FADE_END {
        0.0
    } else {
        let t = (u - FADE_START) / (FADE_END - FADE_START);
        let c = (std::f64::consts::FRAC_PI_2 * t).cos();
        c * c
    }
}

/// The per-axis amplitude response `H(u) = sinc(u)·T(u)` at `u` cycles per output pixel.
#[must_use]
pub fn axis_response(u: f64) -> f64 {
    sinc(u) * clamp_taper(u)
}

/// Simpson intervals of [`axis_energy_gain`] (even).
const SIMPSON_INTERVALS: usize = 256;

/// `E[H(s·(f + σZ))²]` for `Z` standard normal: the share of a component's energy along one
/// axis that a footprint of `s` model pixels keeps, for a component centred on `f` (cycles per
/// model pixel) whose energy spreads with standard deviation `sigma` (0: a pure cosine).
///
/// Computed over `u ∈ [−FADE_END, FADE_END] ∩ [u₀ − 6σ_u, u₀ + 6σ_u]` (`u₀ = f·s`, `σ_u = σ·s`; `H` is 0
/// outside the first, the Gaussian below 1e-8 outside the second) by Simpson's rule on
/// [`SIMPSON_INTERVALS`] intervals, whose step is then at most `σ_u/21` and `1/232`: the
/// quadrature error (the clamp's second derivative jumps at [`FADE_START`] and [`FADE_END`]) is below 1e-5.
#[must_use]
pub fn axis_energy_gain(f: f64, sigma: f64, s: f64) -> f64 {
    let (u0, su) = (f * s, sigma * s);
    if su < 1e-6 {
        return axis_response(u0).powi(2);
    }
    let lo = (-FADE_END).max(u0 - 6.0 * su);
    let hi = FADE_END.min(u0 + 6.0 * su);
    if lo >= hi {
        return 0.0;
    }
    let h = (hi - lo) / SIMPSON_INTERVALS as f64;
    let norm = 1.0 / (su * (2.0 * std::f64::consts::PI).sqrt());
    let g = |u: f64| {
        let z = (u - u0) / su;
        axis_response(u).powi(2) * norm * (-0.5 * z * z).exp()
    };
    let mut sum = g(lo) + g(hi);
    for i in 1..SIMPSON_INTERVALS {
        let w = if i % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * g(lo + i as f64 * h);
    }
    (sum * h / 3.0).clamp(0.0, 1.0)
}

/// The amplitude gain of a component of frequency `f = (f_x, f_y)` (cycles per model pixel)
/// with per-axis spread `sigma` at a footprint of `s` model pixels: the square root of the
/// product of the two axes' energy gains ([`axis_energy_gain`]). 1 for `s ≤ 1` is not implied:
/// callers filter only when [`Window::footprint`](crate::Window::footprint) is `Some`.
#[must_use]
pub fn component_gain(f: [f64; 2], sigma: f64, s: f64) -> f64 {
    (axis_energy_gain(f[0], sigma, s) * axis_energy_gain(f[1], sigma, s)).sqrt()
}

/// The gain of every frequency-table entry of an LRP noise at footprint `side`, per stratum, in
/// the order of the stratum's concatenated sub-strata tables: [`component_gain`] of the entry's
/// frequency with the spread of the stratum's window ([`window_bandwidth`](crate::window::window_bandwidth)
/// over `Δ_S`), rounded to f32. The CPU and GPU evaluators both take their gains from here.
///
/// A stratum of more than [`DIRECT_ENTRIES`] entries (tables may hold 2²⁰) takes each axis's
/// energy gain from [`AxisGainTable`] instead of a quadrature per entry, so that the cost of
/// the gains does not grow with the table beyond a lookup per entry.
#[must_use]
pub fn lrp_gains(model: &crate::LrpNoise, side: f64) -> Vec<Vec<f32>> {
    let bandwidth = crate::window::window_bandwidth();
    model
        .strata
        .iter()
        .map(|stratum| {
            let spread = bandwidth / f64::from(stratum.window_width);
            let entries = stratum.sub_strata.iter().map(Vec::len).sum::<usize>();
            let frequencies = stratum.sub_strata.iter().flatten();
            if entries <= DIRECT_ENTRIES {
                frequencies
                    .map(|f| {
                        component_gain([f64::from(f[0]), f64::from(f[1])], spread, side) as f32
                    })
                    .collect()
            } else {
                let table = AxisGainTable::new(spread, side);
                frequencies
                    .map(|f| {
                        let e = table.at(f64::from(f[0])) * table.at(f64::from(f[1]));
                        e.sqrt() as f32
                    })
                    .collect()
            }
        })
        .collect()
}

/// Entries of a stratum up to which [`lrp_gains`] computes each gain by quadrature.
pub const DIRECT_ENTRIES: usize = 4096;

/// Samples of [`AxisGainTable`].
const TABLE_SAMPLES: usize = 4097;

/// [`axis_energy_gain`] for one spread and footprint, sampled at [`TABLE_SAMPLES`] frequencies
/// evenly over its support (`|f·s| < FADE_END + 6σ·s`; 0 beyond) and interpolated linearly:
/// within 1e-4 of the quadrature (test `gain_table_matches_the_quadrature`).
#[derive(Debug, Clone)]
pub struct AxisGainTable {
    /// Half the support, in cycles per model pixel.
    reach: f64,
    samples: Vec<f64>,
    spread: f64,
    side: f64,
}

impl AxisGainTable {
    /// The table of a spread `spread` (cycles per model pixel) at footprint `side`.
    #[must_use]
    pub fn new(spread: f64, side: f64) -> Self {
        let reach = (FADE_END + 6.0 * spread * side) / side;
        let step = 2.0 * reach / (TABLE_SAMPLES - 1) as f64;
        let samples = (0..TABLE_SAMPLES)
            .map(|i| axis_energy_gain(-reach + i as f64 * step, spread, side))
            .collect();
        Self {
            reach,
            samples,
            spread,
            side,
        }
    }

    /// The energy gain along one axis at frequency `f` (cycles per model pixel).
    #[must_use]
    pub fn at(&self, f: f64) -> f64 {
        if self.spread * self.side < 1e-6 {
            return axis_energy_gain(f, self.spread, self.side);
        }
        if f.is_nan() || f.abs() >= self.reach {
            return 0.0;
        }
        let x = (f + self.reach) / (2.0 * self.reach) * (TABLE_SAMPLES - 1) as f64;
        let i = (x.floor() as usize).min(TABLE_SAMPLES - 2);
        let t = x - i as f64;
        self.samples[i] * (1.0 - t) + self.samples[i + 1] * t
    }
}

/// What the filter needs of one octave of a classic basis ([`basis_statistics`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BasisStatistics {
    /// The per-axis RMS frequency, in cycles per cell (divide by the cell side for cycles per
    /// pixel), from which an octave's fade is found ([`classic_fade`]).
    pub spread: f64,
    /// `[E n, E|n|, E[n²]]`: what an octave is faded toward (its expected value for fBm, its
    /// expected magnitude for turbulence, the ridged signal's expectation from both moments).
    pub moments: [f64; 3],
}

/// The [`BasisStatistics`] of `basis` in `dimensions` (2 or 3). Lattice bases (gradient,
/// simplex, value: zero mean) take the constants below, estimated from renders and checked by
/// the CPU tests `octave_spreads_match_the_bases` and `octave_moments_match_the_bases`. Worley
/// bases, whose statistics depend on the metric, the feature points and the coefficients, are
/// measured here ([`worley_statistics`]).
#[must_use]
pub fn basis_statistics(basis: &crate::classic::Basis, dimensions: u32) -> BasisStatistics {
    use crate::classic::Basis;
    let lattice = |spread, [mean_abs, mean_square]: [f64; 2]| BasisStatistics {
        spread,
        moments: [0.0, mean_abs, mean_square],
    };
    match basis {
        Basis::Gradient => lattice(GRADIENT_SPREAD, GRADIENT_MOMENTS),
        Basis::Simplex => lattice(SIMPLEX_SPREAD, SIMPLEX_MOMENTS),
        Basis::Value => lattice(VALUE_SPREAD, VALUE_MOMENTS),
        Basis::Kensler => lattice(KENSLER_SPREAD, KENSLER_MOMENTS),
        Basis::Worley(w) => worley_statistics(w, dimensions == 3),
    }
}

/// Per-axis RMS frequency of gradient noise (measured 0.4164, cell 64, seed 5, 1025×256
/// pixels).
pub const GRADIENT_SPREAD: f64 = 0.416;
/// Per-axis RMS frequency of simplex noise.
pub const SIMPLEX_SPREAD: f64 = 0.743;
/// Per-axis RMS frequency of value noise.
pub const VALUE_SPREAD: f64 = 0.270;

/// Per-axis RMS frequency of Kensler noise, closed form in 2D: `σ_f² = E[(∂ₓn)²]/(4π² Var n)`
/// with both expectations integrals of the corner kernel `w(|δ|)δ` (midpoint rule, 800²
/// samples): 0.2358.
pub const KENSLER_SPREAD: f64 = 0.236;

/// `[E|n|, E[n²]]` of Kensler noise: `E[n²] = ¼²` by its output scale, `E|n| = ¼·√(2/π)` (a
/// sum of about 13 independent corners, near Gaussian).
pub const KENSLER_MOMENTS: [f64; 2] = [0.1995, 0.0625];

/// `[E|n|, E[n²]]` of gradient noise (measured at cell 8, seed 9, 1024×256 pixels).
pub const GRADIENT_MOMENTS: [f64; 2] = [0.2027, 0.0627];
/// `[E|n|, E[n²]]` of simplex noise.
pub const SIMPLEX_MOMENTS: [f64; 2] = [0.3820, 0.1985];
/// `[E|n|, E[n²]]` of value noise.
pub const VALUE_MOMENTS: [f64; 2] = [0.3782, 0.2042];

/// Cells per side of the square (2D) or the plane `z = ½` (3D) [`worley_statistics`] samples
/// one point in each of: 4096 nearly independent samples, so an estimated mean is within about
/// `σ/64` (1.6% of the standard deviation) of the true one.
const WORLEY_SAMPLE_SIDE: i32 = 64;

/// Step of the central differences of [`worley_statistics`], in cells.
const WORLEY_DIFFERENCE: f64 = 1.0 / 64.0;

/// The [`BasisStatistics`] of a Worley basis, measured on its own point process: one sample
/// per cell over a [`WORLEY_SAMPLE_SIDE`]² block, each `n = Σ C_i F_i` found by an exhaustive
/// f64 search (every point of the rings of cells around the sample, ring by ring until the
/// needed `F_n` is no farther than the unsearched cells, capped as the evaluators cap it), the
/// spread by Parseval from central differences (`σ² = E[(∂_x n)²]/(4π² Var n)`). The point
/// process is the randomness contract's (`cell_hash` of a fixed seed, [`crate::random::Prng`]
/// draws, the capped Poisson count): a statistic of the process, not of one model's seed. A
/// few milliseconds; evaluators compute it once.
#[must_use]
pub fn worley_statistics(worley: &crate::classic::Worley, three_d: bool) -> BasisStatistics {
    let (mut sum, mut sum_abs, mut sum_sq, mut sum_dx) = (0.0, 0.0, 0.0, 0.0);
    let mut count = 0.0;
    let mut jitter = crate::random::Prng::new(crate::random::cell_hash(3, 1, 4, 1_596));
    for j in 0..WORLEY_SAMPLE_SIDE {
        for i in 0..WORLEY_SAMPLE_SIDE {
            let p = [
                f64::from(i) + jitter.next_f64(),
                f64::from(j) + jitter.next_f64(),
                0.5,
            ];
            let n = worley_value(worley, p, three_d);
            let dx = (worley_value(worley, [p[0] + WORLEY_DIFFERENCE, p[1], p[2]], three_d)
                - worley_value(worley, [p[0] - WORLEY_DIFFERENCE, p[1], p[2]], three_d))
                / (2.0 * WORLEY_DIFFERENCE);
            sum += n;
            sum_abs += n.abs();
            sum_sq += n * n;
            sum_dx += dx * dx;
            count += 1.0;
        }
    }
    let (mean, mean_abs, mean_square) = (sum / count, sum_abs / count, sum_sq / count);
    let variance = (mean_square - mean * mean).max(0.0);
    let spread = if variance > 0.0 {
        (sum_dx / count / variance).sqrt() / (2.0 * std::f64::consts::PI)
    } else {
        0.0
    };
    BasisStatistics {
        spread,
        moments: [mean, mean_abs, mean_square],
    }
}

/// `Σ C_i F_i` at `p` (cell units) for the point process of [`worley_statistics`].
fn worley_value(worley: &crate::classic::Worley, p: [f64; 3], three_d: bool) -> f64 {
    use crate::classic::{FeaturePoints, Metric, WORLEY_MAX_POINTS, WORLEY_MAX_RING};
    let cell = p.map(|v| v.floor() as i32);
    let needed = worley
        .coefficients
        .iter()
        .rposition(|&c| c != 0.0)
        .unwrap_or(0);
    let cdf = match worley.points {
        FeaturePoints::Poisson(mean) => {
            Some(crate::random::poisson_cdf::<{ WORLEY_MAX_POINTS as usize }>(f64::from(mean)))
        }
        FeaturePoints::Fixed(_) => None,
    };
    let cap = f64::from(WORLEY_MAX_RING + 1);
    let mut nearest = [cap; 4];
    for ring in 0..=WORLEY_MAX_RING {
        let zr = if three_d { ring } else { 0 };
        for dz in -zr..=zr {
            for dy in -ring..=ring {
                for dx in -ring..=ring {
                    if dx.abs().max(dy.abs()).max(dz.abs()) != ring {
                        continue;
                    }
                    let c = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                    let h = crate::random::cell_hash(c[0], c[1], c[2].cast_unsigned(), 1_596);
                    let mut prng = crate::random::Prng::new(h);
                    let points = match (worley.points, &cdf) {
                        (FeaturePoints::Fixed(k), _) => k,
                        (_, Some(cdf)) => {
                            let u = prng.next_f32();
                            cdf.iter().map(|&q| u32::from(u >= q)).sum()
                        }
                        (FeaturePoints::Poisson(_), None) => 0,
                    };
                    for _ in 0..points {
                        let q = [
                            f64::from(c[0]) + prng.next_f64(),
                            f64::from(c[1]) + prng.next_f64(),
                            if three_d {
                                f64::from(c[2]) + prng.next_f64()
                            } else {
                                p[2]
                            },
                        ];
                        let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
                        let distance = match worley.metric {
                            Metric::Euclidean => (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
                            Metric::Manhattan => d[0].abs() + d[1].abs() + d[2].abs(),
                            Metric::Chebyshev => d[0].abs().max(d[1].abs()).max(d[2].abs()),
                        };
                        if let Some(slot) = nearest.iter().position(|&f| distance < f) {
                            nearest.copy_within(slot..3, slot + 1);
                            nearest[slot] = distance.min(cap);
                        }
                    }
                }
            }
        }
        // Every unsearched cell is at least `ring` cells away along one axis.
        if nearest[needed] <= f64::from(ring) {
            break;
        }
    }
    worley
        .coefficients
        .iter()
        .zip(nearest)
        .map(|(&c, f)| f64::from(c) * f)
        .sum()
}

/// How a minified classic noise takes each octave, from [`classic_fade`].
#[derive(Debug, Clone, PartialEq)]
pub struct OctaveFade {
    /// Per octave, what multiplies its term: `gain^o·g` (fBm, turbulence) or `g` (ridged).
    pub scale: Vec<f32>,
    /// Per octave, the constant added in its place: `gain^o·(1 − g)·E|n|` (turbulence) or
    /// `(1 − g)·E[(offset − |n|)²]` (ridged, before the cascade's weight); 0 for fBm.
    pub constant: Vec<f32>,
}

/// How a minified classic noise takes each octave at footprint `side`, its basis's
/// [`BasisStatistics`] given ([`basis_statistics`], which evaluators compute once). Octave `o`
/// has the gain `g = H(√2·σ·s/c)` ([`axis_response`] at the octave's RMS radial frequency:
/// spread `σ`, cell `c`):
///
/// - fBm: weight `gain^o·g`, and `gain^o·(1 − g)·E n` in place of what is faded (0 for the
///   zero-mean lattice bases; Worley distances have a positive mean, which the fade keeps).
/// - Turbulence `Σ gain^o |n_o|` is nonlinear: `|n_o|` has mean `E|n|`, which a faded octave
///   must keep, so its term becomes `gain^o·(g·|n_o| + (1 − g)·E|n|)` — faded toward its
///   expected value.
/// - Ridged: an octave's signal `(offset − |n_o|)²` becomes `g·(offset − |n_o|)² + (1 − g)·m`,
///   `m = E[(offset − |n|)²] = offset² − 2·offset·E|n| + E[n²]`, before the cascade's weight
///   (which then follows the faded signals).
///
/// An octave with `scale` 0 is not evaluated (its term is its constant alone).
///
/// Why a single frequency rather than a spread as for LRP cosines: an octave's spectrum is a
/// band around its RMS frequency, not a Gaussian around 0, and with the Gaussian model a
/// gradient fBm kept 32% of its unfiltered energy above Nyquist (measured by the CPU test).
/// Measured on one gradient octave at a footprint of 4 (8× supersampled, box-filtered variance
/// over point-sampled variance, against `H²` here): cell 8: 0.72 vs 0.76, cell 16: 0.92 vs 0.93,
/// cell 32: 0.98 vs 0.98; its energy above Nyquist: cell 4: 57%, cell 8: 1.6%, cell 16: 0.01% —
/// cell 4 (`√2·σ·s/c = 0.59`) is dropped, cell 8 kept.
#[must_use]
pub fn classic_fade(
    model: &crate::ClassicNoise,
    side: f64,
    statistics: &BasisStatistics,
) -> OctaveFade {
    use crate::classic::FractalKind;
    let [mean, mean_abs, mean_square] = statistics.moments;
    let radial = std::f64::consts::SQRT_2 * statistics.spread;
    let kind = model.fractal.as_ref().map_or(FractalKind::Fbm, |f| f.kind);
    let (mut scale, mut constant) = (Vec::new(), Vec::new());
    for o in 0..model.octaves() {
        let g = axis_response(radial * side / model.octave_cell(o));
        let w = f64::from(model.octave_weight(o));
        let (a, c) = match kind {
            FractalKind::Fbm => (w * g, w * (1.0 - g) * mean),
            FractalKind::Turbulence => (w * g, w * (1.0 - g) * mean_abs),
            FractalKind::Ridged { offset, .. } => {
                let offset = f64::from(offset);
                let m = offset * offset - 2.0 * offset * mean_abs + mean_square;
                (g, (1.0 - g) * m)
            }
        };
        scale.push(a as f32);
        constant.push(c as f32);
    }
    OctaveFade { scale, constant }
}

/// Most harmonics of a filtered square profile ([`filtered_square`]): the series is cut there
/// when a footprint barely above 1 would let more through (`F·s < FADE_END / 64`).
pub const MAX_SQUARE_HARMONICS: u32 = 64;

/// [`axis_response`] in f32, from the shared `sin_turns`/`cos_turns` (the GPU's twin is
/// `filter_response` in `shaders/phasor.wgsl`).
#[must_use]
pub fn response_f32(v: f32) -> f32 {
    use crate::math::{cos_turns, sin_turns};
    let sinc = if v < 1e-6 {
        1.0
    } else {
        sin_turns(0.5 * v) / (std::f32::consts::PI * v)
    };
    let taper = if v <= FADE_START as f32 {
        1.0
    } else if v >= FADE_END as f32 {
        0.0
    } else {
        let c = cos_turns(0.25 * (v - FADE_START as f32) / (FADE_END - FADE_START) as f32);
        c * c
    };
    sinc * taper
}

/// A square (PWM) profile of duty `duty` at phase `t` (turns) filtered at `u = F·s` cycles per
/// output pixel (the local frequency `F` times the footprint `s`): its Fourier series
/// `d + Σ_k (2/(πk))·sin(πkd)·cos(2πk(t − d/2))` with harmonic `k` (frequency `k·F`) weighted by
/// [`response_f32`]`(k·u)` — phasor §3.3's harmonics "dynamically adjusted for filtering". The
/// constant term `d` is the profile's mean, which the fade keeps. A harmonic is taken along one
/// axis (`H(k·u)`, not `H(k·u·cos θ)·H(k·u·sin θ)`: the direction varies from pixel to pixel),
/// which fades diagonal stripes slightly early. f32 with the shared `sin_turns`/`cos_turns`;
/// `square_filtered` in `shaders/phasor.wgsl` is its twin.
#[must_use]
pub fn filtered_square(t: f32, duty: f32, u: f32) -> f32 {
    use crate::math::{cos_turns, sin_turns};
    let shift = t - 0.5 * duty;
    let mut sum = duty;
    for k in 1..=MAX_SQUARE_HARMONICS {
        let kf = k as f32;
        let v = kf * u;
        if v.is_nan() || v >= FADE_END as f32 {
            break;
        }
        let c = 2.0 / (std::f32::consts::PI * kf) * sin_turns(0.5 * kf * duty);
        sum += response_f32(v) * c * cos_turns(kf * shift);
    }
    sum
}

/// A sine profile (`im/I`, the phasor sine wave) filtered at `u`: its one harmonic weighted by
/// [`response_f32`]`(u)`.
#[must_use]
pub fn filtered_sine(sine: f32, u: f32) -> f32 {
    response_f32(u) * sine
}

/// The triangle profile (`1 − 4|s − ½|`, `s = frac(t + ¼)`, in phase with the sine) at phase
/// `t` filtered at `u`: its Fourier series `(8/π²) Σ_{n odd} (−1)^{(n−1)/2} sin(2πnt)/n²` with
/// harmonic `n` weighted by [`response_f32`]`(n·u)`, cut at [`MAX_SQUARE_HARMONICS`] as the
/// square's. `triangle_filtered` in `shaders/phasor.wgsl` is its twin.
#[must_use]
pub fn filtered_triangle(t: f32, u: f32) -> f32 {
    use crate::math::sin_turns;
    let mut sum = 0.0f32;
    let mut k = 1u32;
    while k <= MAX_SQUARE_HARMONICS {
        let kf = k as f32;
        let v = kf * u;
        if v.is_nan() || v >= FADE_END as f32 {
            break;
        }
        let sign = if k % 4 == 1 { 1.0f32 } else { -1.0f32 };
        let c = sign * 8.0 / (std::f32::consts::PI * std::f32::consts::PI * kf * kf);
        sum += response_f32(v) * c * sin_turns(kf * t);
        k += 2;
    }
    sum
}

/// The sawtooth profile (`2t − 1`) at phase `t` filtered at `u`: its Fourier series
/// `−(2/π) Σ_k sin(2πkt)/k` with harmonic `k` weighted by [`response_f32`]`(k·u)`, cut at
/// [`MAX_SQUARE_HARMONICS`]. `sawtooth_filtered` in `shaders/phasor.wgsl` is its twin.
#[must_use]
pub fn filtered_sawtooth(t: f32, u: f32) -> f32 {
    use crate::math::sin_turns;
    let mut sum = 0.0f32;
    for k in 1..=MAX_SQUARE_HARMONICS {
        let kf = k as f32;
        let v = kf * u;
        if v.is_nan() || v >= FADE_END as f32 {
            break;
        }
        sum += response_f32(v) * (-2.0 / (std::f32::consts::PI * kf)) * sin_turns(kf * t);
    }
    sum
}

/// The Fourier series of a [`Profile::Samples`](crate::phasor::Profile) profile (`values` at
/// `t = j/n`, linearly interpolated, periodic): `[c₀, a₁, b₁, a₂, b₂, …]` up to
/// [`MAX_SQUARE_HARMONICS`], the profile being `c₀ + Σ_k a_k cos(2πkt) + b_k sin(2πkt)`.
/// Linear interpolation is the samples convolved with a hat of half-width `1/n`, so
/// `c_k = sinc²(k/n)·(1/n)·Σ_j v_j e^{−2πikj/n}` (`a_k = 2 Re c_k`, `b_k = −2 Im c_k`), in f64
/// with `kj` reduced modulo `n` before the trigonometric call, rounded to f32 once.
#[must_use]
pub fn samples_series(values: &[f32]) -> Vec<f32> {
    let n = values.len();
    if n == 0 {
        return vec![0.0];
    }
    let mean = values.iter().map(|&v| f64::from(v)).sum::<f64>() / n as f64;
    let mut series = vec![mean as f32];
    for k in 1..=MAX_SQUARE_HARMONICS as usize {
        let (mut re, mut im) = (0.0f64, 0.0f64);
        for (j, &v) in values.iter().enumerate() {
            let angle = -std::f64::consts::TAU * ((k * j) % n) as f64 / n as f64;
            re += f64::from(v) * angle.cos();
            im += f64::from(v) * angle.sin();
        }
        let hat = sinc(k as f64 / n as f64).powi(2) / n as f64;
        series.extend([(2.0 * re * hat) as f32, (-2.0 * im * hat) as f32]);
    }
    series
}

/// A [`samples_series`] profile at phase `t` filtered at `u`: harmonic `k` weighted by
/// [`response_f32`]`(k·u)`, the mean `c₀` kept. `samples_filtered` in `shaders/phasor.wgsl`
/// is its twin.
#[must_use]
pub fn filtered_samples(series: &[f32], t: f32, u: f32) -> f32 {
    use crate::math::{cos_turns, sin_turns};
    let mut sum = series.first().copied().unwrap_or(0.0);
    for (i, ab) in series.get(1..).unwrap_or(&[]).chunks_exact(2).enumerate() {
        let kf = (i + 1) as f32;
        let v = kf * u;
        if v.is_nan() || v >= FADE_END as f32 {
            break;
        }
        sum += response_f32(v) * (ab[0] * cos_turns(kf * t) + ab[1] * sin_turns(kf * t));
    }
    sum
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// In band, below the fade, the gain is the box filter's attenuation `sinc(f_x s)·sinc(f_y s)`.
    pub fn pure_cosines_in_band_get_the_box_attenuation() {
        // Every |f|·s here is at most FADE_START.
        for (f, s) in [([0.05, 0.0], 4.0), ([0.02, 0.07], 4.0), ([0.1, 0.1], 2.5)] {
            let want = sinc(f[0] * s) * sinc(f[1] * s);
            let got = component_gain(f, 0.0, s);
            assert!((got - want).abs() < 1e-12, "{f:?} at {s}: {got} vs {want}");
        }
        // At f = 0.05, s = 4: sin(0.2π)/(0.2π) = 0.935489… (a value of sin, not of this code).
        assert!((sinc(0.2) - 0.935_489_283_788_639_7).abs() < 1e-12);
    }

    pub fn nothing_survives_past_the_fade() {
        // FADE_END / 4 = 0.1375 cycles per model pixel at a footprint of 4.
        for f in [0.1375, 0.14, 0.2, 0.5] {
            assert_eq!(component_gain([f, 0.0], 0.0, 4.0), 0.0, "f = {f}");
            assert_eq!(component_gain([0.0, -f], 0.0, 4.0), 0.0, "f = {f}");
        }
    }

    /// The gain falls continuously with the footprint (no popping as a camera zooms out).
    pub fn the_gain_is_continuous_and_falls_with_the_footprint() {
        let mut prev = 1.0;
        for i in 0..=600 {
            let s = 1.0 + f64::from(i) * 0.01;
            let g = component_gain([0.11, 0.04], 0.01, s);
            assert!(g <= prev + 1e-12, "s = {s}: {g} > {prev}");
            assert!(prev - g < 0.03, "jump at s = {s}: {prev} → {g}");
            prev = g;
        }
        assert!(prev < 5e-3, "still {prev} at s = 7");
    }

    pub fn gain_table_matches_the_quadrature() {
        for (sigma, s) in [
            (0.2, 4.0),
            (0.02, 4.0),
            (0.005, 3.0),
            (1e-9, 2.0),
            (0.3, 1e6),
        ] {
            let table = AxisGainTable::new(sigma, s);
            let mut worst = 0.0f64;
            for i in 0..2000 {
                let f = (f64::from(i) / 1000.0 - 1.0) * (0.6 / s + 7.0 * sigma);
                let d = (table.at(f) - axis_energy_gain(f, sigma, s)).abs();
                worst = worst.max(d);
            }
            assert!(worst < 1e-4, "σ {sigma} s {s}: {worst}");
        }
    }

    /// The filtered square against its definition: at `u → 0` with 64 harmonics, the series of
    /// a 25% duty square (Fejér-free, so within Gibbs' 9% near the edges, exact far from them);
    /// at `u ≥ 0.55` only the mean; its mean over a period is the duty (the fade keeps it).
    pub fn filtered_square_keeps_the_mean_and_converges() {
        let d = 0.25f32;
        // Far from the edges (0 and d) the 64-term series of a square is within 1/(π·64·dist).
        for (t, want) in [(0.125f32, 1.0f32), (0.6, 0.0), (0.9, 0.0)] {
            let got = filtered_square(t, d, 1e-4);
            assert!((got - want).abs() < 0.03, "t {t}: {got} vs {want}");
        }
        assert_eq!(filtered_square(0.1, d, 0.6), d);
        for u in [0.05f32, 0.2, 0.4] {
            let n = 4000;
            let mean = (0..n)
                .map(|i| f64::from(filtered_square((i as f32 + 0.5) / n as f32, d, u)))
                .sum::<f64>()
                / f64::from(n);
            assert!((mean - 0.25).abs() < 1e-5, "u {u}: mean {mean}");
        }
        // One harmonic at u = 0.2: d + sinc(0.2)·(2/π)·sin(π/4)·cos(2π(t − d/2)).
        let t = 0.3f32;
        let want = 0.25
            + sinc(0.2)
                * (2.0 / std::f64::consts::PI)
                * (std::f64::consts::PI / 4.0).sin()
                * (std::f64::consts::TAU * (0.3 - 0.125)).cos();
        // Two harmonics at u = 0.2 (k·u = 0.2, 0.4 < FADE_START); add the second.
        let want2 = want
            + sinc(0.4)
                * (2.0 / (2.0 * std::f64::consts::PI))
                * (std::f64::consts::PI / 2.0).sin()
                * (2.0 * std::f64::consts::TAU * (0.3 - 0.125)).cos();
        let got = f64::from(filtered_square(t, d, 0.2));
        assert!((got - want2).abs() < 1e-5, "{got} vs {want2}");
    }

    /// A spread component's energy gain is the Gaussian average of `H²`: checked against a
    /// plain Riemann sum over a wide range on a fine grid.
    pub fn spread_gain_matches_a_direct_average() {
        for (f, sigma, s) in [
            (0.05, 0.02, 4.0),
            (0.1, 0.3, 4.0),
            (0.0, 0.05, 2.0),
            (0.3, 0.1, 1.5),
        ] {
            let n = 200_000;
            let (lo, hi) = (f - 8.0 * sigma, f + 8.0 * sigma);
            let dx = (hi - lo) / f64::from(n);
            let mut want = 0.0;
            for i in 0..n {
                let v = lo + (f64::from(i) + 0.5) * dx;
                let z = (v - f) / sigma;
                want += axis_response(v * s).powi(2) * (-0.5 * z * z).exp() * dx
                    / (sigma * (2.0 * std::f64::consts::PI).sqrt());
            }
            let got = axis_energy_gain(f, sigma, s);
            assert!(
                (got - want).abs() < 1e-5,
                "f {f} σ {sigma} s {s}: {got} vs {want}"
            );
        }
    }

    /// The filtered series of the triangle, sawtooth and a samples profile against their
    /// definitions: at `u → 0` (every harmonic kept) the series is the profile to within its
    /// truncation after 64 harmonics (away from the sawtooth's jump), and past the fade only
    /// the mean is left.
    pub fn profile_series_converge_to_their_profiles() {
        let u = 1e-5f32;
        let values = [0.0f32, 1.0, 0.25, 0.75, -0.5];
        let series = samples_series(&values);
        for i in 0..200 {
            let t = (i as f32 + 0.5) / 200.0;
            let s = (t + 0.25).fract();
            let triangle = 1.0 - 4.0 * (s - 0.5).abs();
            assert!((filtered_triangle(t, u) - triangle).abs() < 0.01, "t {t}");
            if (0.1..0.9).contains(&t) {
                let saw = 2.0 * t - 1.0;
                assert!((filtered_sawtooth(t, u) - saw).abs() < 0.05, "t {t}");
            }
            let pos = t * values.len() as f32;
            let j = pos as usize;
            let f = pos - j as f32;
            let linear = values[j] * (1.0 - f) + values[(j + 1) % values.len()] * f;
            assert!(
                (filtered_samples(&series, t, u) - linear).abs() < 0.01,
                "t {t}"
            );
            assert_eq!(filtered_triangle(t, 0.6), 0.0);
            assert_eq!(filtered_sawtooth(t, 0.6), 0.0);
            assert_eq!(filtered_samples(&series, t, 0.6), series[0]);
        }
        // c₀ is the mean of a piecewise-linear periodic profile: the mean of its samples.
        assert!((series[0] - 0.3).abs() < 1e-6);
    }
}
