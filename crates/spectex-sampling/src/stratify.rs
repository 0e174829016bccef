//! Strata building (Gilet et al. 2014, §4.2) and the per-stratum sampling densities of §4.3:
//! equal-energy stratification of a discrete power spectrum, the budget `J_S` of each stratum
//! and its window width `Δ_S`.

use ndarray::ArrayView2;

use crate::SamplingError;
use crate::grid::{Bin, in_half_plane, mirror};

/// Smallest side of a power spectrum accepted by the fitting functions.
pub const MIN_PSD_SIDE: usize = 2;
/// Largest side of a power spectrum accepted by the fitting functions (a 8192² image's Welch
/// spectrum has side 4096).
pub const MAX_PSD_SIDE: usize = 4096;

/// Checks that `psd` is a square `T × T` array with `T` in
/// [`MIN_PSD_SIDE`]`..=`[`MAX_PSD_SIDE`], every value finite and `≥ 0`, and some energy away from
/// the zero frequency (`psd[[0, 0]]` is ignored: the model carries the mean separately).
///
/// # Errors
/// [`SamplingError::Shape`], [`SamplingError::NonFinite`], [`SamplingError::Negative`] or
/// [`SamplingError::NoEnergy`] naming `parameter`.
pub fn validate_psd(
    psd: ArrayView2<'_, f64>,
    parameter: &'static str,
) -> Result<(), SamplingError> {
    let (height, width) = psd.dim();
    if height != width || !(MIN_PSD_SIDE..=MAX_PSD_SIDE).contains(&height) {
        return Err(SamplingError::Shape {
            parameter,
            height,
            width,
            min_side: MIN_PSD_SIDE,
            max_side: MAX_PSD_SIDE,
        });
    }
    let mut energy = false;
    for ((row, column), &value) in psd.indexed_iter() {
        if !value.is_finite() {
            return Err(SamplingError::NonFinite {
                parameter,
                value,
                row,
                column,
            });
        }
        if value < 0.0 {
            return Err(SamplingError::Negative {
                parameter,
                value,
                row,
                column,
            });
        }
        energy |= value > 0.0 && (row, column) != (0, 0);
    }
    if energy {
        Ok(())
    } else {
        Err(SamplingError::NoEnergy { parameter })
    }
}

/// One stratum of an equal-energy partition of a power spectrum (§4.2).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyStratum {
    /// The bins of the stratum on the whole (periodic) grid; with every bin its mirror `−f`.
    pub bins: Vec<Bin>,
    /// `E_S = Σ_{f ∈ S} P(f) / T²`, both halves counted: the part of the signal's variance
    /// carried by the stratum.
    pub energy: f64,
    /// Lowest symmetrised power `½(P(f) + P(−f))` of the stratum (0 when it is empty).
    pub min_power: f64,
    /// Highest symmetrised power of the stratum (0 when it is empty).
    pub max_power: f64,
}

/// A mirror pair `{f, −f}` (one bin when the bin is its own mirror), the unit the partition
/// moves, so that every stratum is symmetric like the spectrum of a real noise.
struct Unit {
    representative: Bin,
    bins: usize,
    weight: f64,
    power: f64,
}

/// Partitions the spectrum into `strata` (`L`) strata of equal energy and homogeneous power
/// (§4.2: "we partition the PSD range into L intervals I_S and define the strata
/// S = {f | A²(f) ∈ I_S} … such that the stratum energies are equal").
///
/// `psd` is uncentred `T × T` (zero frequency at `[0, 0]`), normalised so that `Σ P / T²` is
/// the variance (as [`spectex_spectrum::welch_psd`] returns it). The result has exactly `L`
/// entries, stratum 0 holding the lowest powers.
///
/// Exactly how:
/// - **Symmetry.** Bins are grouped into mirror pairs `{f, −f}` and a pair is never split: a real
///   noise's spectrum is symmetric and one cosine of the model feeds both `f` and `−f`. A pair is
///   ranked by its symmetrised power `½(P(f) + P(−f))` (`P(f)` itself for a self-mirrored bin);
///   its energy is the exact sum `P(f) + P(−f)`, so an asymmetric input loses no energy.
/// - **Excluded bins.** The zero frequency (the mean is carried separately, and Welch makes it 0)
///   and every pair of zero power: a frequency where the target has nothing gets no cosine.
/// - **Cut.** Pairs are sorted by increasing power (ties by the representative's row-major
///   index, so the result is deterministic). With `C` the energy of the pairs before a pair of
///   energy `e` and `E` the total, the pair goes to stratum `⌊L·(C + e/2)/E⌋` (its midpoint
///   decides; clamped to `L − 1`). Hence every stratum's energy is within half a pair's energy
///   at each of its two ends of `E/L`: within one pair's energy in all.
/// - **Empty strata.** A pair whose energy exceeds `E/L` (a strong peak) makes a neighbouring
///   stratum empty; empty strata are kept in this result (with zero energy) and left out by
///   the fitting functions.
///
/// # Errors
/// As [`validate_psd`], and [`SamplingError::OutOfRange`] for `strata` outside
/// `1..=`[`spectex_model::MAX_STRATA`].
pub fn equal_energy_strata(
    psd: ArrayView2<'_, f64>,
    strata: usize,
) -> Result<Vec<EnergyStratum>, SamplingError> {
    let (units, size) = sorted_units(psd, strata)?;
    let total: f64 = units.iter().map(|u| u.weight).sum();
    let mut before = 0.0;
    Ok(assign(&units, size, strata, |unit| {
        let midpoint = before + 0.5 * unit.weight;
        before += unit.weight;
        ((midpoint * strata as f64 / total).floor() as usize).min(strata - 1)
    }))
}

/// The mirror pairs of `psd` with power, sorted by increasing power (ties by the
/// representative's row-major index), after checking `psd` and `strata`; and the side `T`.
fn sorted_units(
    psd: ArrayView2<'_, f64>,
    strata: usize,
) -> Result<(Vec<Unit>, usize), SamplingError> {
    validate_psd(psd, "power spectrum")?;
    if !(1..=spectex_model::MAX_STRATA).contains(&strata) {
        return Err(SamplingError::OutOfRange {
            parameter: "strata",
            value: strata as f64,
            range: "1..=64",
        });
    }
    let size = psd.nrows();
    let mut units = Vec::with_capacity(size * size / 2 + 2);
    for k in 0..size {
        for l in 0..size {
            let bin = [k, l];
            if bin == [0, 0] || !in_half_plane(bin, size) {
                continue;
            }
            let m = mirror(bin, size);
            let (bins, weight) = if m == bin {
                (1, psd[bin])
            } else {
                (2, psd[bin] + psd[m])
            };
            if weight > 0.0 {
                units.push(Unit {
                    representative: bin,
                    bins,
                    weight,
                    power: weight / bins as f64,
                });
            }
        }
    }
    // Row-major push order makes the stable sort's tie-break the representative's index.
    units.sort_by(|a, b| a.power.total_cmp(&b.power));
    Ok((units, size))
}

/// Puts each of the sorted `units`, in order, into the stratum `choose` names.
fn assign(
    units: &[Unit],
    size: usize,
    strata: usize,
    mut choose: impl FnMut(&Unit) -> usize,
) -> Vec<EnergyStratum> {
    let area = (size * size) as f64;
    let mut out: Vec<EnergyStratum> = (0..strata)
        .map(|_| EnergyStratum {
            bins: Vec::new(),
            energy: 0.0,
            min_power: 0.0,
            max_power: 0.0,
        })
        .collect();
    for unit in units {
        let stratum = &mut out[choose(unit)];
        if stratum.bins.is_empty() {
            stratum.min_power = unit.power;
        }
        stratum.max_power = unit.power;
        stratum.energy += unit.weight / area;
        stratum.bins.push(unit.representative);
        if unit.bins == 2 {
            stratum.bins.push(mirror(unit.representative, size));
        }
    }
    out
}

/// How the power range of a spectrum is cut into strata ([`crate::FitOptions::partition`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Partition {
    /// Equal energies (§4.2, the paper's choice; [`equal_energy_strata`]): right for exemplars,
    /// whose power is concentrated in a few levels.
    #[default]
    EqualEnergy,
    /// Equal shares of the logarithm of the power range ([`log_power_strata`]): for targets
    /// whose power spans decades, such as `1/f^β` fractals. There an equal-energy cut puts
    /// all the weak high frequencies of a steep spectrum (or all the strong low ones of a
    /// shallow one) into one stratum, where the model's density is flat: its spectrum becomes a
    /// plateau where the target falls by decades.
    LogPower,
}

/// Partitions the spectrum into `strata` (`L`) strata of equal spans of `ln P` (§4.2's
/// "partition the PSD range into L intervals I_S", with intervals equal on a log scale instead
/// of in energy): with `p₀` and `p₁` the lowest and highest symmetrised powers, a mirror pair of
/// power `p` goes to stratum `⌊L·ln(p/p₀)/ln(p₁/p₀)⌋` (clamped to `L − 1`; all to stratum 0
/// when `p₀ = p₁`). Within a stratum the power then varies by at most the factor
/// `(p₁/p₀)^(1/L)`, so the flat density the model gives a stratum follows the target within
/// that factor, whatever the spectrum's dynamic range. Pairs, exclusions, the order of bins and
/// the result's fields are as in [`equal_energy_strata`]; strata may be empty and have any
/// energy.
///
/// # Errors
/// As [`equal_energy_strata`].
pub fn log_power_strata(
    psd: ArrayView2<'_, f64>,
    strata: usize,
) -> Result<Vec<EnergyStratum>, SamplingError> {
    let (units, size) = sorted_units(psd, strata)?;
    let (low, high) = match (units.first(), units.last()) {
        (Some(a), Some(b)) => (a.power, b.power),
        _ => (1.0, 1.0),
    };
    let span = (high / low).ln();
    Ok(assign(&units, size, strata, |unit| {
        if span > 0.0 {
            ((strata as f64 * (unit.power / low).ln() / span).floor() as usize).min(strata - 1)
        } else {
            0
        }
    }))
}

/// Distributes the cosine budget `J` over strata of the given energies (§4.2: "we then
/// distribute the sampling budget uniformly, J_S = J/L").
///
/// Each stratum gets `⌊J/L⌋`; the remainder `J mod L` goes one cosine each to the strata of
/// highest energy (ties to the stratum of higher index, which holds higher powers). Strata of
/// zero energy get nothing and do not count in `L`. The result sums to `J` whenever some energy
/// is positive.
#[must_use]
pub fn distribute_budget(energies: &[f64], budget: usize) -> Vec<usize> {
    let used: Vec<usize> = (0..energies.len()).filter(|&s| energies[s] > 0.0).collect();
    let mut cosines = vec![0; energies.len()];
    if used.is_empty() {
        return cosines;
    }
    let (each, remainder) = (budget / used.len(), budget % used.len());
    let mut order = used.clone();
    order.sort_by(|&a, &b| energies[b].total_cmp(&energies[a]).then(b.cmp(&a)));
    for &s in &used {
        cosines[s] = each;
    }
    for &s in order.iter().take(remainder) {
        cosines[s] += 1;
    }
    cosines
}

/// Smallest window width `Δ_S` given to a stratum, in pixels. Below one pixel the window's
/// spectral footprint (a disc of radius `1/Δ_S`, §4.3) already spans the whole period
/// `[−½, ½]²` of a pixel grid, so narrower windows cannot cover a stratum better; they would
/// only leak more energy outside it.
pub const MIN_WINDOW_WIDTH: f64 = 1.0;
/// Largest window width `Δ_S` given to a stratum, as a multiple of the spectrum's side `T`.
/// At `Δ_S = 4T` the footprint's radius is a quarter of a frequency bin: the measured spectrum
/// (whose own resolution is `1/T`, widened by Welch's Hann window) cannot justify a finer one,
/// and wider windows only make the cosines' regularity visible over spans of several exemplars
/// ("lacks randomness", §3.5). Only strata of a few bins with many cosines reach it.
pub const MAX_WINDOW_WIDTH_PER_SIDE: f64 = 4.0;

/// The unclamped window width of §4.3, `Δ_S = T·√J_S / √(2|S|)` pixels, for a spectrum of side
/// `T = size`, `J_S = cosines` and `|S| = bins` (the stratum's bins on the whole grid).
#[must_use]
pub fn raw_window_width(size: usize, cosines: usize, bins: usize) -> f64 {
    size as f64 * (cosines as f64).sqrt() / (2.0 * bins as f64).sqrt()
}

/// [`raw_window_width`] clamped to `[`[`MIN_WINDOW_WIDTH`]`, `[`MAX_WINDOW_WIDTH_PER_SIDE`]`·T]`
/// (reasons on the constants).
#[must_use]
pub fn window_width(size: usize, cosines: usize, bins: usize) -> f64 {
    let upper = MAX_WINDOW_WIDTH_PER_SIDE * size as f64;
    let raw = raw_window_width(size, cosines, bins);
    if raw.is_nan() {
        return upper.max(MIN_WINDOW_WIDTH);
    }
    raw.clamp(MIN_WINDOW_WIDTH, upper.max(MIN_WINDOW_WIDTH))
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod tests {
    #![allow(
        clippy::unwrap_used,
        reason = "a test fails loudly on the first unexpected None or Err"
    )]

    use super::*;
    use ndarray::Array2;
    use spectex_model::random::{Prng, cell_hash};

    /// Random PSDs with a few strong peaks, ties, zeros, and a slight asymmetry.
    fn random_psd(size: usize, seed: u32) -> Array2<f64> {
        let mut prng = Prng::new(cell_hash(size as i32, 0, 9, seed));
        let mut psd = Array2::from_shape_fn((size, size), |_| {
            let u = prng.next_f64();
            if u < 0.1 {
                0.0
            } else if u < 0.2 {
                0.5 // many exact ties
            } else {
                u * u * 3.0
            }
        });
        for _ in 0..3 {
            let (k, l) = (
                prng.next_u32() as usize % size,
                prng.next_u32() as usize % size,
            );
            psd[[k, l]] += 20.0 * prng.next_f64();
        }
        psd[[0, 0]] = 7.0; // ignored
        psd
    }

    fn symmetrised(psd: &Array2<f64>, bin: Bin) -> f64 {
        let size = psd.nrows();
        0.5 * (psd[bin] + psd[mirror(bin, size)])
    }

    pub fn strata_energies_are_equal_within_one_mirror_pair() {
        for size in [2usize, 3, 8, 17, 32, 64] {
            for seed in 0..4 {
                for strata in [1usize, 2, 4, 7] {
                    let psd = random_psd(size, seed);
                    let out = equal_energy_strata(psd.view(), strata).unwrap();
                    let area = (size * size) as f64;
                    let total: f64 = psd.iter().sum::<f64>() - psd[[0, 0]];
                    let largest_pair = psd
                        .indexed_iter()
                        .map(|((k, l), _)| 2.0 * symmetrised(&psd, [k, l]))
                        .fold(0.0, f64::max)
                        / area;
                    let sum: f64 = out.iter().map(|s| s.energy).sum();
                    assert!(
                        (sum - total / area).abs() <= 1e-12 * total / area,
                        "size {size}, seed {seed}, L {strata}: Σ E_S {sum} vs {}",
                        total / area
                    );
                    for (s, st) in out.iter().enumerate() {
                        let direct: f64 = st.bins.iter().map(|&b| psd[b]).sum::<f64>() / area;
                        assert!((direct - st.energy).abs() <= 1e-12 * total);
                        assert!(
                            (st.energy - total / area / strata as f64).abs()
                                <= largest_pair * (1.0 + 1e-12),
                            "size {size}, seed {seed}, L {strata}, stratum {s}: E_S {} vs E/L {}",
                            st.energy,
                            total / area / strata as f64
                        );
                    }
                }
            }
        }
    }

    pub fn strata_are_disjoint_symmetric_and_cover_every_bin_with_power() {
        for size in [2usize, 5, 16, 33] {
            for seed in 0..3 {
                let psd = random_psd(size, seed);
                let out = equal_energy_strata(psd.view(), 4).unwrap();
                let mut owner = Array2::<i32>::from_elem((size, size), -1);
                for (s, st) in out.iter().enumerate() {
                    for &b in &st.bins {
                        assert_eq!(owner[b], -1, "size {size}, seed {seed}: {b:?} twice");
                        owner[b] = s as i32;
                    }
                }
                for ((k, l), &o) in owner.indexed_iter() {
                    let has_power = (k, l) != (0, 0) && symmetrised(&psd, [k, l]) > 0.0;
                    assert_eq!(
                        o >= 0,
                        has_power,
                        "size {size}, seed {seed}: bin [{k}, {l}] owner {o}"
                    );
                    assert_eq!(
                        o,
                        owner[mirror([k, l], size)],
                        "not symmetric at [{k}, {l}]"
                    );
                }
            }
        }
    }

    pub fn higher_strata_hold_higher_powers() {
        for size in [8usize, 31, 64] {
            for seed in 0..4 {
                let psd = random_psd(size, seed);
                let out = equal_energy_strata(psd.view(), 5).unwrap();
                let mut floor = 0.0;
                for (s, st) in out.iter().enumerate() {
                    if st.bins.is_empty() {
                        continue;
                    }
                    let powers: Vec<f64> = st.bins.iter().map(|&b| symmetrised(&psd, b)).collect();
                    let lo = powers.iter().copied().fold(f64::INFINITY, f64::min);
                    let hi = powers.iter().copied().fold(0.0, f64::max);
                    assert_eq!((lo, hi), (st.min_power, st.max_power));
                    assert!(
                        lo >= floor,
                        "size {size}, seed {seed}: stratum {s} starts at {lo} below {floor}"
                    );
                    floor = hi;
                }
            }
        }
    }

    pub fn a_single_peak_leaves_empty_strata() {
        let mut psd = Array2::zeros((16, 16));
        psd[[0, 3]] = 1.0;
        psd[[0, 13]] = 1.0;
        let out = equal_energy_strata(psd.view(), 4).unwrap();
        let sizes: Vec<usize> = out.iter().map(|s| s.bins.len()).collect();
        assert_eq!(sizes, [0, 0, 2, 0]);
        assert!((out[2].energy - 2.0 / 256.0).abs() < 1e-15);
    }

    pub fn budget_sums_to_j_with_the_remainder_on_the_highest_energies() {
        let energies = [1.0, 1.2, 0.0, 0.9, 1.2];
        let got = distribute_budget(&energies, 10);
        // 4 strata with energy: 2 each, remainder 2 to the two of energy 1.2 (index 4, then 1).
        assert_eq!(got, [2, 3, 0, 2, 3]);
        for budget in 4..40 {
            assert_eq!(
                distribute_budget(&energies, budget).iter().sum::<usize>(),
                budget
            );
        }
        assert_eq!(distribute_budget(&[0.0, 0.0], 5), [0, 0]);
    }

    pub fn window_width_follows_section_4_3_and_is_clamped() {
        // Δ = T √J / √(2|S|) = 256 · √12 / √(2·600)
        let want = 256.0 * 12f64.sqrt() / 1200f64.sqrt();
        assert!((window_width(256, 12, 600) - want).abs() < 1e-12);
        assert_eq!(window_width(64, 1, 64 * 64 - 1), MIN_WINDOW_WIDTH);
        assert_eq!(window_width(64, 1024, 2), 4.0 * 64.0);
        assert_eq!(window_width(64, 3, 0), 4.0 * 64.0);
    }

    pub fn invalid_spectra_are_rejected_with_their_position() {
        let mut psd = Array2::<f64>::ones((8, 8));
        psd[[2, 3]] = f64::NAN;
        assert!(matches!(
            equal_energy_strata(psd.view(), 4),
            Err(SamplingError::NonFinite {
                row: 2,
                column: 3,
                ..
            })
        ));
        psd[[2, 3]] = -1.0;
        assert!(matches!(
            equal_energy_strata(psd.view(), 4),
            Err(SamplingError::Negative {
                row: 2,
                column: 3,
                ..
            })
        ));
        let mut dc_only = Array2::<f64>::zeros((8, 8));
        dc_only[[0, 0]] = 5.0;
        assert!(matches!(
            equal_energy_strata(dc_only.view(), 4),
            Err(SamplingError::NoEnergy { .. })
        ));
        let rect = Array2::<f64>::ones((8, 4));
        assert!(matches!(
            equal_energy_strata(rect.view(), 4),
            Err(SamplingError::Shape {
                height: 8,
                width: 4,
                ..
            })
        ));
        assert!(matches!(
            equal_energy_strata(Array2::<f64>::ones((8, 8)).view(), 0),
            Err(SamplingError::OutOfRange {
                parameter: "strata",
                ..
            })
        ));
    }

    /// Every bin with power lands in exactly one stratum, a mirror pair is never split, the
    /// energies add up, and within a stratum the power varies by at most `(p₁/p₀)^(1/L)`;
    /// the stratum of each pair is the one its log-power names, recomputed here directly.
    pub fn log_power_strata_bound_the_power_ratio_within_each_stratum() {
        for size in [4usize, 16, 33] {
            for seed in 0..3 {
                let psd = random_psd(size, seed);
                for strata in [1usize, 3, 8] {
                    let out = log_power_strata(psd.view(), strata).unwrap();
                    assert_eq!(out.len(), strata);
                    let powers: Vec<f64> = psd
                        .indexed_iter()
                        .filter(|&((k, l), _)| (k, l) != (0, 0))
                        .map(|((k, l), _)| symmetrised(&psd, [k, l]))
                        .filter(|&p| p > 0.0)
                        .collect();
                    let p0 = powers.iter().copied().fold(f64::INFINITY, f64::min);
                    let p1 = powers.iter().copied().fold(0.0, f64::max);
                    let ratio = (p1 / p0).powf(1.0 / strata as f64);
                    let mut owner = Array2::<i32>::from_elem((size, size), -1);
                    let mut energy = 0.0;
                    for (s, st) in out.iter().enumerate() {
                        energy += st.energy;
                        for &b in &st.bins {
                            assert_eq!(owner[b], -1, "{b:?} twice");
                            owner[b] = s as i32;
                            let p = symmetrised(&psd, b);
                            let expected =
                                ((strata as f64 * (p / p0).ln() / (p1 / p0).ln()).floor() as usize)
                                    .min(strata - 1);
                            assert_eq!(s, expected, "size {size}, seed {seed}, bin {b:?}");
                        }
                        if !st.bins.is_empty() {
                            assert!(st.max_power <= st.min_power * ratio * (1.0 + 1e-12));
                        }
                    }
                    for ((k, l), &o) in owner.indexed_iter() {
                        let has_power = (k, l) != (0, 0) && symmetrised(&psd, [k, l]) > 0.0;
                        assert_eq!(o >= 0, has_power, "size {size}, bin ({k}, {l})");
                        assert_eq!(o, owner[mirror([k, l], size)], "a mirror pair split");
                    }
                    let total = (psd.iter().sum::<f64>() - psd[[0, 0]]) / (size * size) as f64;
                    assert!((energy - total).abs() <= 1e-12 * total);
                }
            }
        }
        // A flat spectrum has no log range: one stratum holds everything.
        let flat = Array2::<f64>::ones((8, 8));
        let out = log_power_strata(flat.view(), 4).unwrap();
        assert_eq!(out[0].bins.len(), 63);
        assert!(out[1..].iter().all(|s| s.bins.is_empty()));
    }
}
