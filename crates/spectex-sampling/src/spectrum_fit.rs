//! The spectrum-matching fit, [`FitMethod::Spectrum`](crate::FitMethod): the default of
//! [`fit_psd`](crate::fit_psd) and everything built on it.
//!
//! The paper's fit (§4.3) gives every cosine of a stratum the same amplitude `A_S` and draws its
//! frequency uniformly among the bins of its k-means sub-stratum. Over equal-energy strata that
//! span decades of power, that flattens each stratum's spectrum to its mean (the fidelity test's
//! "flat strata" floor), and the erosion that keeps a window's blur inside its stratum leaves
//! holes at the strata's edges. Measured on the shared height maps and photographs this gave a
//! relative L1 spectral distance of 0.38–0.51 at J = 10–200, growing with J.
//!
//! Here the same LRP model and evaluation contract (one amplitude per stratum, each lattice
//! point drawing one entry of each table uniformly) reproduce the spectrum itself:
//!
//! 0. An example image's Welch estimate is first sharpened ([`sharpen_welch`], through
//!    [`crate::exemplar_target`]): cosines fitted to the Hann-blurred estimate are blurred again
//!    when a render is measured the same way.
//! 1. Each stratum's bins (its whole, uneroded region, folded onto the half plane: a cosine puts
//!    power at `±f`) are cut into `J_S` sub-strata of **equal energy** by recursive bisection
//!    along the wider axis, at the energy quantile; a bin straddling a cut is shared between
//!    the two sides by weight. Equal energies make the one amplitude per stratum exact.
//! 2. Each sub-stratum's table lists its bins **in proportion to their power** (systematic
//!    sampling of the cumulative power into [`TABLE_ENTRIES`] entries, faint bins represented
//!    together rather than dropped): a uniform draw from the table is then a draw from the PSD,
//!    at no cost at evaluation.
//! 3. No stratum gets more cosines than it has distinct frequencies ([`capped_budgets`]): the
//!    cosines a height map's few-frequency strata cannot use go to the others.
//! 4. `Δ_S` ([`window_width`]) resolves the stratum's low frequencies ([`resolving_width`]),
//!    more widely the more cosines a window holds, and
//!    is at least [`MIN_WINDOW_WIDTH`] pixels: the window's own spectrum, which blurs every
//!    cosine by about `1/Δ_S`, then stays well inside the Nyquist band (the paper's formula gives
//!    2.6 px for the outer stratum of the gravel photograph, whose blur put 7.5% of the energy
//!    past Nyquist) and does not push a height map's first rings outward.
//!
//! The expected spectrum of the noise is then the PSD convolved with the window's spectrum, with
//! the variance and mean of the exemplar; evaluation costs at most what the paper's model of the
//! same `J` costs.

use spectex_model::MAX_TABLE;

use crate::grid::{Bin, frequency, in_half_plane, mirror};
use crate::stratify::MAX_WINDOW_WIDTH_PER_SIDE;

/// Entries of each sub-stratum's table. A bin of weight `w` (share of its sub-stratum's energy)
/// gets `w·TABLE_ENTRIES` entries rounded down or up (systematic sampling, [`weighted_table`]),
/// so the drawn spectrum is the PSD to a relative `1/(w·TABLE_ENTRIES)`; bins below an entry's
/// share are represented together by their neighbours, to the same precision per strip.
pub const TABLE_ENTRIES: usize = 2048;

/// Smallest window width `Δ_S`, pixels: a Kaiser–Bessel window this wide has 75% of its spectral
/// energy within `δ₀/Δ_S ≈ 0.05` cycles per pixel, a tenth of the Nyquist band.
pub const MIN_WINDOW_WIDTH: f64 = 8.0;

const _: () = assert!(TABLE_ENTRIES <= MAX_TABLE);

/// A frequency on the half plane and the share of power it carries.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Item {
    frequency: [f64; 2],
    weight: f64,
}

/// The frequencies of one stratum, on the half plane, with their powers: a bin of the half plane
/// carries `P(b) + P(−b)` (a cosine of frequency `f` puts half its power at `f` and half at
/// `−f`), a self-mirrored bin `P(b)`. Bins of zero power are left out.
fn half_plane_items(bins: &[Bin], psd: &dyn Fn(Bin) -> f64, size: usize) -> Vec<Item> {
    let in_stratum: std::collections::BTreeSet<Bin> = bins.iter().copied().collect();
    let mut items = Vec::new();
    for &b in &in_stratum {
        let m = mirror(b, size);
        let weight = if m == b {
            psd(b)
        } else if in_half_plane(b, size) {
            psd(b) + if in_stratum.contains(&m) { psd(m) } else { 0.0 }
        } else if in_stratum.contains(&m) {
            // Counted with its half-plane mirror.
            continue;
        } else {
            // Its mirror is in another stratum: the cosine stands at the half-plane bin.
            psd(b)
        };
        if weight > 0.0 && weight.is_finite() {
            let rep = if in_half_plane(b, size) { b } else { m };
            items.push(Item {
                frequency: frequency(rep, size),
                weight,
            });
        }
    }
    items
}

/// Cuts `items` into `parts` groups of equal total weight by recursive bisection along the wider
/// axis of each group (a k-d tree whose cuts are energy quantiles), a straddling item shared
/// between the two sides. Deterministic: ties are broken by the other coordinate.
fn equal_energy_groups(items: Vec<Item>, parts: usize, out: &mut Vec<Vec<Item>>) {
    if parts <= 1 {
        out.push(items);
        return;
    }
    let mut items = items;
    let extent = |axis: usize| {
        let (lo, hi) = items.iter().fold((f64::MAX, f64::MIN), |(lo, hi), it| {
            (lo.min(it.frequency[axis]), hi.max(it.frequency[axis]))
        });
        hi - lo
    };
    let axis = usize::from(extent(1) > extent(0));
    items.sort_by(|a, b| {
        a.frequency[axis]
            .total_cmp(&b.frequency[axis])
            .then(a.frequency[1 - axis].total_cmp(&b.frequency[1 - axis]))
    });
    let left_parts = parts / 2;
    let total: f64 = items.iter().map(|it| it.weight).sum();
    let target = total * left_parts as f64 / parts as f64;
    let mut left = Vec::new();
    let mut right = Vec::new();
    let mut acc = 0.0;
    for it in items {
        if acc >= target {
            right.push(it);
        } else if acc + it.weight <= target {
            acc += it.weight;
            left.push(it);
        } else {
            let share = target - acc;
            acc = target;
            left.push(Item {
                weight: share,
                ..it
            });
            right.push(Item {
                weight: it.weight - share,
                ..it
            });
        }
    }
    // Rounding can leave the last item whole on the left; the right side needs weight too.
    if right.is_empty()
        && let Some(last) = left.last_mut()
    {
        last.weight *= 0.5;
        right.push(*last);
    }
    equal_energy_groups(left, left_parts, out);
    equal_energy_groups(right, parts - left_parts, out);
}

/// A table of `entries` frequencies in which each item appears in proportion to its weight, by
/// systematic sampling of the items' cumulative weight: entry `k` is the item whose share of the
/// cumulative weight holds the quantile `(k + ½)/entries`. Every item gets its quota rounded down
/// or up, and so does every run of consecutive items: weak bins too many and too faint for an
/// entry each (a photograph's fine grain, spread over the outer sub-strata) are represented
/// together, by the bins the quantiles fall on, instead of being dropped. Items are listed in
/// the order [`equal_energy_groups`] leaves them (sorted along one axis, ties by the other), so a
/// run is a strip of neighbouring bins.
fn weighted_table(items: &[Item], entries: usize) -> Vec<[f32; 2]> {
    let total: f64 = items.iter().map(|it| it.weight).sum();
    if items.is_empty() || total <= 0.0 || !total.is_finite() {
        return Vec::new();
    }
    let mut table = Vec::with_capacity(entries);
    let mut items_iter = items.iter();
    let mut current = items_iter.next();
    let mut upper = current.map_or(0.0, |it| it.weight);
    for k in 0..entries {
        let quantile = (k as f64 + 0.5) / entries as f64 * total;
        while upper <= quantile {
            match items_iter.next() {
                Some(it) => {
                    upper += it.weight;
                    current = Some(it);
                }
                // Rounding at the very end: the last item holds the rest.
                None => break,
            }
        }
        if let Some(it) = current {
            table.push([it.frequency[0] as f32, it.frequency[1] as f32]);
        }
    }
    table
}

/// The `cosines` tables of one stratum (see the module documentation): `bins` on the whole grid
/// (with their mirrors), `psd` the power of a bin, `size` the spectrum's side. Frequencies are
/// `[f_x, f_y]` cycles per pixel, as the model stores them. No power gives no tables.
#[must_use]
pub fn spectrum_tables(
    bins: &[Bin],
    psd: &dyn Fn(Bin) -> f64,
    size: usize,
    cosines: usize,
) -> Vec<Vec<[f32; 2]>> {
    let items = half_plane_items(bins, psd, size);
    if items.is_empty() || cosines == 0 {
        return Vec::new();
    }
    let mut groups = Vec::with_capacity(cosines);
    equal_energy_groups(items, cosines, &mut groups);
    groups
        .iter()
        .map(|g| weighted_table(g, TABLE_ENTRIES))
        .collect()
}

/// The distinct frequencies of a stratum ([`spectrum_tables`]'s arguments): its bins of
/// non-zero power, a bin and its mirror counted once. A lattice point drawing more cosines than
/// this from one stratum draws some frequency twice ([`capped_budgets`]).
#[must_use]
pub fn distinct_frequencies(bins: &[Bin], psd: &dyn Fn(Bin) -> f64, size: usize) -> usize {
    half_plane_items(bins, psd, size).len()
}

/// The budgets `J_S` of [`distribute_budget`](crate::stratify::distribute_budget) with each
/// stratum given no more cosines than it has distinct frequencies (`capacities`,
/// [`distinct_frequencies`]), the cosines so freed shared equally among the other strata
/// (water-filling: the strata below the common share keep their capacity, the rest get the
/// share, one more for the highest-`energies` ones while cosines remain, as
/// `distribute_budget` does). When every stratum is full the rest of the budget is left unused:
/// `Σ J_S ≤ Σ budgets`. Without a binding capacity the budgets are returned unchanged.
///
/// Why: in a stratum of fewer frequencies than cosines, one lattice point draws some frequency
/// several times with independent phases, and their sum is a single cosine of random (Rayleigh)
/// amplitude. That is the same cost for more randomness: a render's power at the frequency then
/// spreads as a Gaussian process's would (exponentially, not about one value). A height map
/// puts a quarter of its variance on one or a few frequency pairs (the dirt height map's top
/// stratum is one bin pair, given 13 of J = 50 cosines), so that randomness was most of the
/// spread between renders, and it grew with `J` (sand: 0.075 at J = 50, 0.092 at J = 100).
#[must_use]
pub fn capped_budgets(budgets: &[usize], capacities: &[usize], energies: &[f64]) -> Vec<usize> {
    let n = budgets.len();
    let mut out = vec![0; n];
    let mut remaining: usize = budgets.iter().sum();
    let mut open: Vec<usize> = (0..n)
        .filter(|&s| budgets[s] > 0 && capacities[s] > 0)
        .collect();
    loop {
        if open.is_empty() {
            return out;
        }
        let share = remaining / open.len();
        let full: Vec<usize> = open
            .iter()
            .copied()
            .filter(|&s| capacities[s] <= share)
            .collect();
        if full.is_empty() {
            let mut order = open.clone();
            order.sort_by(|&a, &b| energies[b].total_cmp(&energies[a]).then(b.cmp(&a)));
            for &s in &open {
                out[s] = share;
            }
            for &s in order.iter().take(remaining % open.len()) {
                out[s] += 1;
            }
            return out;
        }
        for s in full {
            out[s] = capacities[s];
            remaining -= capacities[s];
            open.retain(|&o| o != s);
        }
    }
}

/// Periods of a stratum's low frequencies a window spans ([`resolving_width`]).
pub const RESOLVING_PERIODS: f64 = 2.0;

/// The window width that resolves a stratum's low frequencies: [`RESOLVING_PERIODS`] periods of
/// the power-weighted first quartile of `|f|` over its bins. The window's spectrum blurs a
/// cosine by about `1/Δ_S`; for a stratum close to the zero frequency (a height map's first
/// rings) the paper's width blurs by about a ring's radius, pushing power outward onto the
/// larger outer rings, and a render's lowest octave had half its power.
#[must_use]
pub fn resolving_width(bins: &[Bin], psd: &dyn Fn(Bin) -> f64, size: usize) -> f64 {
    let mut radii: Vec<(f64, f64)> = bins
        .iter()
        .map(|&b| {
            let [fx, fy] = frequency(b, size);
            (fx.hypot(fy), psd(b).max(0.0))
        })
        .filter(|&(r, w)| r > 0.0 && w > 0.0)
        .collect();
    radii.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = radii.iter().map(|r| r.1).sum();
    let mut acc = 0.0;
    for (r, w) in radii {
        acc += w;
        if acc >= 0.25 * total {
            return RESOLVING_PERIODS / r;
        }
    }
    0.0
}

/// `Δ_S` of a stratum of `cosines` sub-strata: [`resolving_width`] times `(J_S/12)^¼`, within
/// `[`[`MIN_WINDOW_WIDTH`]`, 4T]` (the paper's upper clamp, [`MAX_WINDOW_WIDTH_PER_SIDE`]).
///
/// Why the factor: a render's spectrum departs from the expected one by the window's blur, a
/// bias falling as `1/Δ_S`, and by the randomness of the frequencies drawn, which a render sees
/// `J_S` per window over `(side/Δ_S)²` windows: a relative error growing as `Δ_S/√J_S`. Their
/// sum is least at `Δ_S ∝ J_S^¼`; at `J_S = 12` (J = 50 over 4 strata) [`RESOLVING_PERIODS`]
/// was best of 1 and 2 periods. Measured with the blur-only sharpening that [`sharpen_welch`]
/// replaced (mean relative L1 over 8 seeds, `J` = 10 / 50 / 100):
/// gravel 0.100 / 0.067 / 0.062 with 2 periods at every `J`, 0.082 / 0.079 / 0.078 with 1, and
/// 0.085 / 0.067 / 0.062 with the factor; grass 0.109 / 0.079 / 0.074, 0.095 / 0.090 / 0.089
/// and 0.095 / 0.079 / 0.071.
#[must_use]
pub fn window_width(bins: &[Bin], psd: &dyn Fn(Bin) -> f64, size: usize, cosines: usize) -> f64 {
    let periods = (cosines.max(1) as f64 / 12.0).powf(0.25);
    MIN_WINDOW_WIDTH
        .max(periods * resolving_width(bins, psd, size))
        .min(MAX_WINDOW_WIDTH_PER_SIDE * size as f64)
}

/// Richardson–Lucy iterations of [`sharpen_welch`].
pub const SHARPEN_ITERATIONS: usize = 30;

/// `ĥ(a)`: the DFT of the periodic Hann window of side `T` at bin offset `a` (modulo `T`),
/// divided by its value at 0 (`T/2`): 1 at 0, −½ at ±1, 0 elsewhere.
fn hann_dft(a: usize, n: usize) -> f64 {
    if a == 0 {
        1.0
    } else if a == 1 || a == n - 1 {
        -0.5
    } else {
        0.0
    }
}

/// The expected Welch estimate, and its transpose, of a spectrum whose power sits on the DFT
/// grid of the blocks ([`spectex_spectrum::welch_psd`]'s convention: separable periodic Hann
/// taper, each block's window-weighted mean removed).
///
/// A complex exponential at bin `k` gives a block the DFT `Ŵ(f − k) − Ŵ(−k)·Ŵ(f)/Ŵ(0)` (the
/// tapered exponential less its tapered mean), `Ŵ(a) = ŵ(a_y)·ŵ(a_x)·T²/4` with `ŵ` =
/// [`hann_dft`]; divided by the taper's energy its power is
/// `K(f, k) = (ŵ(f − k) − ŵ(k)·ŵ(f))² / 9/4`. Away from the zero frequency (`ŵ(k) = 0`) that
/// is the separable `[1/6, 2/3, 1/6]` blur; the eight bins next to it (a height map's first
/// ring) lose what their taper puts on the block mean: a bin `(0, 1)` keeps `(1 − ½·½)² = 9/16`
/// of the blur's share `4/9` at its own bin and puts `1/36` on its mirror `(0, −1)`.
pub(crate) struct WelchOperator {
    pub(crate) n: usize,
}

impl WelchOperator {
    /// `ŵ` of the 2D bin offset `(a_y, a_x)` (modulo `n`).
    fn w(&self, ay: usize, ax: usize) -> f64 {
        hann_dft(ay, self.n) * hann_dft(ax, self.n)
    }

    /// The bins within one of the zero frequency on each axis, `(y, x)`.
    fn near_zero(&self) -> [(usize, usize); 9] {
        let n = self.n;
        let m = [n - 1, 0, 1];
        let mut out = [(0, 0); 9];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = (m[i / 3], m[i % 3]);
        }
        out
    }

    /// `K(f, k) − ŵ(f − k)²/(9/4)`: what the mean's removal changes, non-zero only for `f` and
    /// `k` both within one bin of the zero frequency.
    fn correction(&self, f: (usize, usize), k: (usize, usize)) -> f64 {
        let n = self.n;
        let (wf, wk) = (self.w(f.0, f.1), self.w(k.0, k.1));
        let wd = self.w((f.0 + n - k.0) % n, (f.1 + n - k.1) % n);
        (wk * wk * wf * wf - 2.0 * wd * wk * wf) / 2.25
    }

    /// The shift-invariant part, the separable periodic `[1/6, 2/3, 1/6]` blur (symmetric).
    fn blur(&self, a: &ndarray::Array2<f64>) -> ndarray::Array2<f64> {
        const K: [f64; 3] = [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0];
        let n = self.n;
        let rows = ndarray::Array2::from_shape_fn((n, n), |(y, x)| {
            K[0] * a[[y, (x + n - 1) % n]] + K[1] * a[[y, x]] + K[2] * a[[y, (x + 1) % n]]
        });
        ndarray::Array2::from_shape_fn((n, n), |(y, x)| {
            K[0] * rows[[(y + n - 1) % n, x]] + K[1] * rows[[y, x]] + K[2] * rows[[(y + 1) % n, x]]
        })
    }

    /// `Σ_k K(f, k)·a(k)`: the expected Welch estimate of the spectrum `a`.
    pub(crate) fn apply(&self, a: &ndarray::Array2<f64>) -> ndarray::Array2<f64> {
        let mut out = self.blur(a);
        for f in self.near_zero() {
            out[[f.0, f.1]] += self
                .near_zero()
                .iter()
                .map(|&k| self.correction(f, k) * a[[k.0, k.1]])
                .sum::<f64>();
        }
        out
    }

    /// `Σ_f K(f, k)·r(f)`: the transpose of [`WelchOperator::apply`].
    fn transpose(&self, r: &ndarray::Array2<f64>) -> ndarray::Array2<f64> {
        let mut out = self.blur(r);
        for k in self.near_zero() {
            out[[k.0, k.1]] += self
                .near_zero()
                .iter()
                .map(|&f| self.correction(f, k) * r[[f.0, f.1]])
                .sum::<f64>();
        }
        out
    }
}

/// The power spectrum whose Welch estimate is `psd` ([`spectex_spectrum::welch_psd`]'s
/// convention), by Richardson–Lucy deconvolution of the estimate's expected value
/// ([`WelchOperator`]: the Hann taper's blur and the removal of each block's mean).
///
/// Why: a Welch estimate is the true spectrum convolved with the taper's power spectrum, which
/// on the DFT grid of a periodic Hann window of side `T` (DFT `T·[−¼, ½, −¼]` per axis) is the
/// separable kernel `[1/6, 2/3, 1/6]` per axis. Cosines fitted to the blurred estimate are
/// blurred a second time when a render is measured the same way: a height map whose power sits
/// in the first rings lost half of its lowest octave (a third of each ring-1 cosine's measured
/// power falls on the zero frequency and ring 2). Removing each block's mean also takes power
/// from the eight bins next to the zero frequency (a height map's first ring): a cosine at
/// `(0, 1)` is measured at its own bin with 5/18 of its power where the blur alone gives 4/9
/// ([`WelchOperator`]). With that left out (the blur alone deconvolved), renders of the dirt
/// height map at J = 50 and Gaussian fields of the sharpened spectrum alike measured about 0.03
/// of their normalised power short on rings 1–3 (spectra averaged over 32 renders), and the
/// mean distance over 32 renders (1024², Welch T = 256) was 0.124 and 0.112; with it, 0.082 and
/// 0.058 (`fidelity_dirt`'s harness, the fidelity test's window). Richardson–Lucy keeps the
/// estimate non-negative; the zero frequency (the mean, not a cosine) is neither data nor
/// unknown. The result is rescaled to `psd`'s total, so the variance is unchanged.
#[must_use]
pub fn sharpen_welch(psd: &ndarray::Array2<f64>) -> ndarray::Array2<f64> {
    let n = psd.nrows();
    if n < 3 || psd.ncols() != n {
        return psd.clone();
    }
    let op = WelchOperator { n };
    let mut estimate = psd.mapv(|p| p.max(0.0));
    estimate[[0, 0]] = 0.0;
    let total: f64 = estimate.sum();
    if total <= 0.0 || !total.is_finite() {
        return psd.clone();
    }
    // Richardson–Lucy over the data f ≠ 0: each unknown's update is its column's weighted
    // ratio, divided by the column's sum.
    let mut ones = ndarray::Array2::from_elem((n, n), 1.0);
    ones[[0, 0]] = 0.0;
    let columns = op.transpose(&ones);
    for _ in 0..SHARPEN_ITERATIONS {
        let predicted = op.apply(&estimate);
        let mut ratio = ndarray::Array2::from_shape_fn((n, n), |(y, x)| {
            let (p, q) = (psd[[y, x]].max(0.0), predicted[[y, x]]);
            if q > 0.0 { p / q } else { 1.0 }
        });
        ratio[[0, 0]] = 0.0;
        let correction = op.transpose(&ratio);
        ndarray::Zip::from(&mut estimate)
            .and(&correction)
            .and(&columns)
            .for_each(|e, &c, &s| {
                if s > 0.0 {
                    *e *= c / s;
                }
            });
        estimate[[0, 0]] = 0.0;
    }
    let scale = total / estimate.sum();
    estimate.mapv_inplace(|e| e * scale);
    estimate[[0, 0]] = psd[[0, 0]];
    estimate
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use ndarray::Array2;
    use spectex_model::random::{Prng, cell_hash};

    fn random_items(n: usize, seed: u32) -> Vec<Item> {
        let mut prng = Prng::new(cell_hash(n as i32, 3, 5, seed));
        (0..n)
            .map(|_| Item {
                frequency: [prng.next_f64() - 0.5, prng.next_f64() * 0.5],
                // Powers over four decades, as in an exemplar's strata.
                weight: 10f64.powf(4.0 * prng.next_f64()),
            })
            .collect()
    }

    pub fn groups_carry_equal_energy_and_the_whole() {
        for (n, parts) in [
            (1usize, 1usize),
            (1, 5),
            (2, 7),
            (40, 3),
            (500, 13),
            (3000, 50),
        ] {
            let items = random_items(n, 1);
            let total: f64 = items.iter().map(|it| it.weight).sum();
            let mut groups = Vec::new();
            equal_energy_groups(items, parts, &mut groups);
            assert_eq!(groups.len(), parts, "n {n}");
            let sums: Vec<f64> = groups
                .iter()
                .map(|g| g.iter().map(|it| it.weight).sum())
                .collect();
            let all: f64 = sums.iter().sum();
            assert!(
                (all - total).abs() <= 1e-12 * total,
                "n {n}: {all} vs {total}"
            );
            for (j, s) in sums.iter().enumerate() {
                let want = total / parts as f64;
                assert!(
                    (s - want).abs() <= 1e-9 * total,
                    "n {n}, parts {parts}: group {j} holds {s}, want {want}"
                );
                assert!(!groups[j].is_empty());
            }
        }
    }

    pub fn tables_list_frequencies_in_proportion_to_power() {
        let items = random_items(300, 2);
        let total: f64 = items.iter().map(|it| it.weight).sum();
        let table = weighted_table(&items, TABLE_ENTRIES);
        assert_eq!(table.len(), TABLE_ENTRIES);
        for it in &items {
            let f = [it.frequency[0] as f32, it.frequency[1] as f32];
            let count = table.iter().filter(|&&e| e == f).count() as f64;
            let quota = it.weight / total * TABLE_ENTRIES as f64;
            // Every count is the quota rounded down or up.
            assert!(
                (count - quota).abs() < 1.0,
                "frequency {f:?}: {count} entries for a quota of {quota}"
            );
        }
    }

    /// A few strong bins and thousands of faint ones (each a hundredth of an entry's share, a
    /// tenth of the power together): the faint ones are not dropped but represented together,
    /// every run of consecutive items getting its quota to within one entry.
    pub fn faint_bins_keep_their_share_together() {
        let mut items = Vec::new();
        for i in 0..4096 {
            let strong = i % 512 == 0;
            items.push(Item {
                frequency: [i as f64 / 8192.0, 0.25],
                // 8 strong bins of 0.9/8 of the power, 4088 faint ones sharing 0.1.
                weight: if strong { 0.9 / 8.0 } else { 0.1 / 4088.0 },
            });
        }
        let table = weighted_table(&items, TABLE_ENTRIES);
        assert_eq!(table.len(), TABLE_ENTRIES);
        let index = |e: &[f32; 2]| (f64::from(e[0]) * 8192.0).round() as usize;
        for (start, len) in [(0usize, 4096usize), (1, 511), (600, 300), (2049, 2047)] {
            let quota: f64 = items[start..start + len]
                .iter()
                .map(|it| it.weight * TABLE_ENTRIES as f64)
                .sum();
            let count = table
                .iter()
                .filter(|e| (start..start + len).contains(&index(e)))
                .count() as f64;
            assert!(
                (count - quota).abs() < 1.0,
                "items {start}..{}: {count} entries for a quota of {quota:.2}",
                start + len
            );
        }
    }

    /// Worked by hand: the dirt height map's J = 50 over four equal-energy strata of 3712, 12, 3
    /// and 1 frequencies. The three small strata keep one cosine per frequency; the 16 cosines
    /// they hold leave 34 for the first.
    pub fn capped_budgets_give_freed_cosines_to_the_other_strata() {
        let equal = [1.0; 4];
        assert_eq!(
            capped_budgets(&[12, 12, 13, 13], &[3712, 12, 3, 1], &equal),
            vec![34, 12, 3, 1]
        );
        // No binding capacity: unchanged.
        assert_eq!(
            capped_budgets(&[12, 12, 13, 13], &[100, 100, 100, 100], &equal),
            vec![12, 12, 13, 13]
        );
        // Every stratum full: the rest of the budget is unused.
        assert_eq!(
            capped_budgets(&[12, 12, 13, 13], &[1, 2, 3, 4], &equal),
            vec![1, 2, 3, 4]
        );
        // 20 over capacities 2 and ∞, ∞: 2, then 18 shared 9 and 9.
        assert_eq!(
            capped_budgets(&[7, 7, 6], &[2, 50, 50], &[1.0, 2.0, 3.0]),
            vec![2, 9, 9]
        );
        // An odd remainder goes to the higher energy, as `distribute_budget` gives it.
        assert_eq!(
            capped_budgets(&[7, 7, 7], &[2, 50, 50], &[1.0, 2.0, 3.0]),
            vec![2, 9, 10]
        );
    }

    /// The water-filling's defining properties on random inputs: no stratum above its
    /// capacity, no cosine created, a cosine left unused only when every stratum is full, and
    /// any stratum below its capacity within one cosine of the largest share.
    pub fn capped_budgets_fill_water_levels() {
        let mut prng = Prng::new(11);
        for case in 0..2000 {
            let n = 1 + (prng.next_u32() % 8) as usize;
            let budgets: Vec<usize> = (0..n).map(|_| (prng.next_u32() % 40) as usize).collect();
            let capacities: Vec<usize> = (0..n).map(|_| (prng.next_u32() % 30) as usize).collect();
            let energies: Vec<f64> = (0..n).map(|_| prng.next_f64()).collect();
            let out = capped_budgets(&budgets, &capacities, &energies);
            let open = |s: usize| budgets[s] > 0 && capacities[s] > 0;
            let total: usize = budgets.iter().sum();
            let used: usize = out.iter().sum();
            assert!(used <= total, "case {case}: {out:?} from {budgets:?}");
            let top = out.iter().copied().max().unwrap_or(0);
            for s in 0..n {
                assert!(out[s] <= capacities[s], "case {case}: stratum {s}");
                if !open(s) {
                    assert_eq!(out[s], 0, "case {case}: stratum {s}");
                } else if out[s] < capacities[s] {
                    assert!(
                        out[s] + 1 >= top,
                        "case {case}: {out:?}, caps {capacities:?}"
                    );
                }
            }
            if used < total {
                assert!(
                    (0..n).all(|s| !open(s) || out[s] == capacities[s]),
                    "case {case}: {used} of {total} used in {out:?}, caps {capacities:?}"
                );
            }
        }
    }

    pub fn resolving_width_spans_the_periods_of_the_low_quartile() {
        // All power on the ring of radius 4 bins of a 64-bin grid: |f| = 1/16 cycle per pixel.
        let size = 64;
        let bins: Vec<Bin> = vec![[0, 4], [0, 60], [4, 0], [60, 0]];
        let w = resolving_width(&bins, &|_| 1.0, size);
        assert!((w - RESOLVING_PERIODS * 16.0).abs() < 1e-9, "{w}");
    }

    /// Welch's own estimate ([`spectex_spectrum::welch_psd_with_block`], blocks of `n`) of a
    /// cosine of amplitude `a` at bin `(k_y, k_x)` of a `2n`² image, averaged over the phases
    /// 0.3 and 0.3 + π/2: the interference of the cosine's two exponentials (which depends on
    /// twice the phase) cancels, leaving the expected estimate of a cosine of random phase.
    fn welch_of_cosine(n: usize, k: (usize, usize), a: f64) -> Array2<f64> {
        let mut fft = spectex_spectrum::Fft2::new();
        let mut sum = Array2::zeros((n, n));
        for phase in [0.3, 0.3 + std::f64::consts::FRAC_PI_2] {
            let img = Array2::from_shape_fn((2 * n, 2 * n), |(y, x)| {
                let turns = (k.0 * y + k.1 * x) as f64 / n as f64;
                a * (std::f64::consts::TAU * turns + phase).cos()
            });
            sum = sum + spectex_spectrum::welch_psd_with_block(img.view(), n, &mut fft).unwrap();
        }
        sum / 2.0
    }

    /// The spectrum of a cosine of amplitude `a` at bin `k` in Welch's convention (`Σ P/T²` is
    /// the variance `a²/2`, half at `k` and half at its mirror).
    fn cosine_power(n: usize, k: (usize, usize), a: f64) -> Array2<f64> {
        let mut p = Array2::zeros((n, n));
        let quarter = (n * n) as f64 * a * a / 4.0;
        p[[k.0, k.1]] += quarter;
        p[[(n - k.0) % n, (n - k.1) % n]] += quarter;
        p
    }

    /// The operator against the estimator it models: cosines next to the zero frequency (where
    /// the block mean's removal matters), on the axes' Nyquist bins and elsewhere.
    pub fn the_welch_operator_is_welchs_estimate_of_grid_cosines() {
        let n = 32;
        let op = WelchOperator { n };
        for k in [
            (0, 1),
            (1, 0),
            (1, 1),
            (1, 31),
            (0, 2),
            (2, 1),
            (16, 0),
            (3, 5),
            (20, 30),
        ] {
            let measured = welch_of_cosine(n, k, 1.5);
            let predicted = op.apply(&cosine_power(n, k, 1.5));
            let worst = measured
                .iter()
                .zip(&predicted)
                .map(|(m, p)| (m - p).abs())
                .fold(0.0, f64::max);
            assert!(
                worst < 1e-9 * (n * n) as f64,
                "bin {k:?}: worst difference {worst}"
            );
        }
        // The mean's removal, by hand: a cosine at (0, 1) of power `P` at (0, 1) and at its
        // mirror (0, −1) is measured at (0, 1) as `P·(1 − ½·½)²/(9/4)` from itself plus
        // `P·(0 − ½·½)²/(9/4)` from its mirror (two bins away, out of the blur's reach):
        // `P·(1/4 + 1/36) = 5P/18`, where the blur alone gives `4P/9`.
        let measured = welch_of_cosine(n, (0, 1), 1.0);
        let own = cosine_power(n, (0, 1), 1.0)[[0, 1]];
        let ratio = measured[[0, 1]] / own;
        assert!((ratio - 5.0 / 18.0).abs() < 1e-12, "{ratio}");
    }

    /// Sharpened, Welch's estimate of a few cosines (ring 1 and farther out, each measured by
    /// the estimator itself) gives back their powers: within 5% at every cosine's bin, where the
    /// blur alone (the mean's removal left out) left the first ring 44% short.
    pub fn sharpening_inverts_welchs_estimate_and_keeps_the_total() {
        let n = 32;
        let cosines = [
            ((0, 1), 2.0),
            ((1, 1), 1.0),
            ((3, 5), 1.5),
            ((7, 2), 1.0),
            ((20, 30), 0.7),
        ];
        let mut measured = Array2::zeros((n, n));
        let mut truth = Array2::zeros((n, n));
        for &(k, a) in &cosines {
            measured = measured + welch_of_cosine(n, k, a);
            truth = truth + cosine_power(n, k, a);
        }
        let sharp = sharpen_welch(&measured);
        let total = |a: &Array2<f64>| a.sum() - a[[0, 0]];
        assert!((total(&sharp) - total(&measured)).abs() <= 1e-12 * total(&measured));
        assert!(sharp.iter().all(|&v| v >= 0.0));
        // The estimate's total is short of the truth's by what the block means took; compare
        // shapes (the fit rescales to the image's variance).
        let scale = total(&truth) / total(&sharp);
        for &(k, _) in &cosines {
            let (got, want) = (sharp[[k.0, k.1]] * scale, truth[[k.0, k.1]]);
            assert!(
                (got / want - 1.0).abs() < 0.05,
                "bin {k:?}: sharpened {got}, truth {want}"
            );
        }
    }
}
