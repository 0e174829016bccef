//! Shrinking a stratum by morphological erosion on the periodic frequency grid (§4.3), modified
//! so that no piece of a stratum thinner than the shrink distance is swept out: every piece keeps
//! at least its ridge (the bins at a local maximum of the distance to the complement).
//!
//! The erosion of a bin set `S` by the disc of radius `r` (in bins) keeps the bins `p ∈ S` such
//! that every grid point `q` with `|q − p| ≤ r` (periodic offsets) lies in `S`; equivalently the
//! bins whose Euclidean distance to the complement of `S` exceeds `r`. That distance is computed
//! for all bins at once by an exact squared Euclidean distance transform (Felzenszwalb &
//! Huttenlocher 2012, lower envelope of parabolas, one pass per axis), made periodic by
//! repeating each line three times.

use ndarray::{Array2, ArrayView2};

/// Squared distance used for "no complement bin at all" (a mask that is all `true`).
pub const UNREACHABLE: u32 = u32::MAX;

/// For every bin, the squared Euclidean distance (in bins, periodic in both axes) to the
/// nearest bin where `mask` is `false`; 0 on those bins, [`UNREACHABLE`] everywhere when the
/// mask has no `false` bin. (Squared distances on a periodic grid are at most `(h² + w²)/4`,
/// which fits a `u32` for every grid side up to 65535.)
#[must_use]
pub fn squared_distance_to_complement(mask: ArrayView2<'_, bool>) -> Array2<u32> {
    let (height, width) = mask.dim();
    if height == 0 || width == 0 {
        return Array2::zeros((height, width));
    }
    if mask.iter().all(|&m| m) {
        return Array2::from_elem((height, width), UNREACHABLE);
    }
    // Column pass: exact squared vertical distance (as f64: every value is an integer
    // below 2^53, so the arithmetic is exact), then the row pass on it.
    let mut vertical = Array2::<f64>::zeros((height, width));
    let mut line = vec![0.0; height];
    let mut out_line = vec![0.0; height];
    let mut scratch = Scratch::default();
    for x in 0..width {
        for y in 0..height {
            line[y] = if mask[[y, x]] { f64::INFINITY } else { 0.0 };
        }
        periodic_distance_1d(&line, &mut out_line, &mut scratch);
        for y in 0..height {
            vertical[[y, x]] = out_line[y];
        }
    }
    let mut out = Array2::<u32>::zeros((height, width));
    let mut line = vec![0.0; width];
    let mut out_line = vec![0.0; width];
    for y in 0..height {
        for x in 0..width {
            line[x] = vertical[[y, x]];
        }
        periodic_distance_1d(&line, &mut out_line, &mut scratch);
        for x in 0..width {
            out[[y, x]] = out_line[x] as u32;
        }
    }
    out
}

#[derive(Default)]
struct Scratch {
    sites: Vec<f64>,
    values: Vec<f64>,
    hull_sites: Vec<usize>,
    bounds: Vec<f64>,
}

/// `out[x] = min_j ((x − j) mod± n)² + f[j]`: the 1D squared distance transform of sampled
/// function `f` on a periodic line of length `n`, by the lower envelope of the parabolas rooted
/// at `j − n`, `j` and `j + n` (for `x, j ∈ [0, n)` the nearest periodic image is one of them).
fn periodic_distance_1d(f: &[f64], out: &mut [f64], s: &mut Scratch) {
    let n = f.len();
    s.sites.clear();
    s.values.clear();
    for copy in -1i64..=1 {
        for (j, &v) in f.iter().enumerate() {
            if v.is_finite() {
                s.sites.push((j as i64 + copy * n as i64) as f64);
                s.values.push(v);
            }
        }
    }
    if s.sites.is_empty() {
        out.fill(f64::INFINITY);
        return;
    }
    // Lower envelope: hull_sites[i] is the i-th parabola on it, visible on
    // [bounds[i], bounds[i + 1]).
    s.hull_sites.clear();
    s.bounds.clear();
    s.hull_sites.push(0);
    s.bounds.push(f64::NEG_INFINITY);
    s.bounds.push(f64::INFINITY);
    for q in 1..s.sites.len() {
        let (xq, fq) = (s.sites[q], s.values[q]);
        loop {
            let v = *s.hull_sites.last().unwrap_or(&0);
            let (xv, fv) = (s.sites[v], s.values[v]);
            let cross = ((fq + xq * xq) - (fv + xv * xv)) / (2.0 * (xq - xv));
            let k = s.hull_sites.len() - 1;
            if cross <= s.bounds[k] && k > 0 {
                s.hull_sites.pop();
                s.bounds.pop();
            } else {
                let last = s.bounds.len() - 1;
                s.bounds[last] = cross;
                s.hull_sites.push(q);
                s.bounds.push(f64::INFINITY);
                break;
            }
        }
    }
    let mut k = 0;
    for (x, o) in out.iter_mut().enumerate() {
        let x = x as f64;
        while s.bounds[k + 1] < x {
            k += 1;
        }
        let v = s.hull_sites[k];
        let d = x - s.sites[v];
        *o = d * d + s.values[v];
    }
}

/// Label of the bins outside every component in [`connected_components`].
pub const NO_COMPONENT: u32 = u32::MAX;

/// Labels of the 8-connected components of `mask` on the periodic grid: `c` in `0..count` on
/// the `true` bins (numbered in row-major order of their first bin), [`NO_COMPONENT`]
/// elsewhere; and `count`.
#[must_use]
pub fn connected_components(mask: ArrayView2<'_, bool>) -> (Array2<u32>, usize) {
    let (h, w) = mask.dim();
    let mut labels = Array2::from_elem((h, w), NO_COMPONENT);
    let mut count = 0u32;
    let mut stack = Vec::new();
    for start in 0..h * w {
        let (y0, x0) = (start / w, start % w);
        if !mask[[y0, x0]] || labels[[y0, x0]] != NO_COMPONENT {
            continue;
        }
        labels[[y0, x0]] = count;
        stack.push((y0, x0));
        while let Some((y, x)) = stack.pop() {
            for dy in [h - 1, 0, 1] {
                for dx in [w - 1, 0, 1] {
                    let (qy, qx) = ((y + dy) % h, (x + dx) % w);
                    if mask[[qy, qx]] && labels[[qy, qx]] == NO_COMPONENT {
                        labels[[qy, qx]] = count;
                        stack.push((qy, qx));
                    }
                }
            }
        }
        count += 1;
    }
    (labels, count as usize)
}

/// A shrunk stratum: the bins kept and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Erosion {
    /// Bins kept, as a mask of the grid.
    pub mask: Array2<bool>,
    /// Connected pieces (8-connected, periodic) of the set that was eroded.
    pub components: usize,
    /// Pieces that plain erosion by the radius would sweep out (no bin deeper than the radius);
    /// each keeps its ridge instead.
    pub thin_components: usize,
}

/// Whether `p` is a ridge bin of the distance map: no 8-neighbour (periodic) lies deeper.
fn is_ridge(distance: &Array2<u32>, (y, x): (usize, usize)) -> bool {
    let (h, w) = distance.dim();
    let d = distance[[y, x]];
    [h - 1, 0, 1].iter().all(|&dy| {
        [w - 1, 0, 1]
            .iter()
            .all(|&dx| distance[[(y + dy) % h, (x + dx) % w]] <= d)
    })
}

/// Shrinks the bin set `mask` by the disc of radius `radius` bins (§4.3: "discrete shrinking is
/// performed by morphological erosion, modified so that strata smaller than δ are not
/// completely swept out").
///
/// Exactly: a bin of the set is kept when its Euclidean distance to the complement exceeds
/// `radius` (plain erosion by the disc: every grid point within `radius` is in the set), or when
/// it lies on the set's **ridge** — no 8-neighbour is farther from the complement than it is.
/// The ridge is a discrete medial axis: a ring-shaped piece thinner than `2·radius` keeps its
/// centre line all the way round, a speckle of one or two bins keeps itself, and a thick piece
/// keeps its eroded core plus the thin spine of its medial axis. Each piece's deepest bin is on
/// the ridge, so no piece is ever swept out.
///
/// Why the ridge and not "the deepest bins": strata of a measured spectrum are fragmented rings
/// and speckle whose thickness varies along them. Keeping, per piece, only the bins deeper than
/// the largest radius that leaves something (an earlier version) kept a few isolated spots of a
/// ring (on the gravel photograph, T = 256, J = 50: 2058 bins shrunk to 96), so the sub-strata
/// covered a fraction of the stratum and the spectral L1 error grew with J. The ridge keeps the
/// coverage goal of §4.3 along the whole piece while thick parts are eroded by the full `δ`,
/// the leakage goal. Distances are to the complement of the set, so the rule is mirror-symmetric
/// whenever the set is.
#[must_use]
pub fn erode(mask: ArrayView2<'_, bool>, radius: f64) -> Erosion {
    let radius = if radius.is_nan() {
        0.0
    } else {
        radius.max(0.0)
    };
    let distance = squared_distance_to_complement(mask);
    let (labels, components) = connected_components(mask);
    let mut deepest = vec![0u32; components];
    for (&c, &d) in labels.iter().zip(distance.iter()) {
        if c != NO_COMPONENT {
            deepest[c as usize] = deepest[c as usize].max(d);
        }
    }
    let thin_components = deepest
        .iter()
        .filter(|&&d| f64::from(d) <= radius * radius)
        .count();
    let kept = Array2::from_shape_fn(mask.dim(), |p| {
        mask[p] && (f64::from(distance[p]) > radius * radius || is_ridge(&distance, p))
    });
    Erosion {
        mask: kept,
        components,
        thin_components,
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::random::{Prng, cell_hash};

    /// Random blobs: a union of discs and rectangles on a periodic grid, plus noise bins.
    fn random_mask(h: usize, w: usize, seed: u32) -> Array2<bool> {
        let mut prng = Prng::new(cell_hash(h as i32, w as i32, 3, seed));
        let mut mask = Array2::from_elem((h, w), false);
        for _ in 0..4 {
            let (cy, cx) = (prng.next_f64() * h as f64, prng.next_f64() * w as f64);
            let r = prng.next_f64() * h.min(w) as f64 * 0.4;
            for ((y, x), m) in mask.indexed_iter_mut() {
                let dy = (y as f64 - cy).rem_euclid(h as f64);
                let dx = (x as f64 - cx).rem_euclid(w as f64);
                let dy = dy.min(h as f64 - dy);
                let dx = dx.min(w as f64 - dx);
                if dy * dy + dx * dx <= r * r || (dy < r * 0.3 && dx < r * 1.5) {
                    *m = true;
                }
            }
        }
        for m in &mut mask {
            if prng.next_f64() < 0.05 {
                *m = !*m;
            }
        }
        mask
    }

    /// Direct definition: the squared distance to the nearest complement bin over all bins.
    fn slow_distance(mask: &Array2<bool>) -> Array2<u32> {
        let (h, w) = mask.dim();
        Array2::from_shape_fn((h, w), |(y, x)| {
            let mut best = UNREACHABLE;
            for ((qy, qx), &m) in mask.indexed_iter() {
                if !m {
                    let dy = (y as i64 - qy as i64).rem_euclid(h as i64);
                    let dx = (x as i64 - qx as i64).rem_euclid(w as i64);
                    let dy = dy.min(h as i64 - dy);
                    let dx = dx.min(w as i64 - dx);
                    best = best.min((dy * dy + dx * dx) as u32);
                }
            }
            best
        })
    }

    /// Direct definition of the erosion by a disc: every offset within the disc stays inside.
    fn slow_erosion(mask: &Array2<bool>, r: f64) -> Array2<bool> {
        let (h, w) = mask.dim();
        let reach = r.floor() as i64;
        Array2::from_shape_fn((h, w), |(y, x)| {
            if !mask[[y, x]] {
                return false;
            }
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    if ((dy * dy + dx * dx) as f64) <= r * r {
                        let qy = (y as i64 + dy).rem_euclid(h as i64) as usize;
                        let qx = (x as i64 + dx).rem_euclid(w as i64) as usize;
                        if !mask[[qy, qx]] {
                            return false;
                        }
                    }
                }
            }
            true
        })
    }

    /// The modified erosion by its definition: plain erosion by the disc, plus every bin with no
    /// 8-neighbour farther from the complement (distances by the direct minimum).
    fn slow_modified_erosion(mask: &Array2<bool>, r: f64) -> Array2<bool> {
        let (h, w) = mask.dim();
        let plain = slow_erosion(mask, r);
        let d = slow_distance(mask);
        Array2::from_shape_fn((h, w), |(y, x)| {
            if !mask[[y, x]] {
                return false;
            }
            let mut ridge = true;
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let qy = (y as i64 + dy).rem_euclid(h as i64) as usize;
                    let qx = (x as i64 + dx).rem_euclid(w as i64) as usize;
                    ridge &= d[[qy, qx]] <= d[[y, x]];
                }
            }
            plain[[y, x]] || ridge
        })
    }

    pub fn distance_transform_matches_the_direct_minimum() {
        for (h, w) in [(1, 1), (1, 7), (5, 5), (8, 8), (13, 9), (16, 16), (31, 24)] {
            for seed in 0..3 {
                let mask = random_mask(h, w, seed);
                let fast = squared_distance_to_complement(mask.view());
                let slow = slow_distance(&mask);
                if let Some(((y, x), _)) = fast.indexed_iter().find(|(p, v)| **v != slow[*p]) {
                    panic!(
                        "{h}×{w}, seed {seed}: first difference at [{y}, {x}]: {} vs {}",
                        fast[[y, x]],
                        slow[[y, x]]
                    );
                }
            }
        }
    }

    /// Connected pieces by their definition: grow each piece by repeated 8-neighbour sweeps.
    fn slow_components(mask: &Array2<bool>) -> Vec<Array2<bool>> {
        let (h, w) = mask.dim();
        let mut taken = Array2::from_elem((h, w), false);
        let mut pieces = Vec::new();
        for ((y, x), &m) in mask.indexed_iter() {
            if !m || taken[[y, x]] {
                continue;
            }
            let mut piece = Array2::from_elem((h, w), false);
            piece[[y, x]] = true;
            loop {
                let mut grown = piece.clone();
                for ((py, px), &inside) in piece.indexed_iter() {
                    if !inside {
                        continue;
                    }
                    for dy in -1i64..=1 {
                        for dx in -1i64..=1 {
                            let qy = (py as i64 + dy).rem_euclid(h as i64) as usize;
                            let qx = (px as i64 + dx).rem_euclid(w as i64) as usize;
                            if mask[[qy, qx]] {
                                grown[[qy, qx]] = true;
                            }
                        }
                    }
                }
                if grown == piece {
                    break;
                }
                piece = grown;
            }
            for (t, &p) in taken.iter_mut().zip(piece.iter()) {
                *t |= p;
            }
            pieces.push(piece);
        }
        pieces
    }

    pub fn components_match_their_definition() {
        for (h, w) in [(1, 1), (4, 4), (9, 13), (16, 16)] {
            for seed in 0..4 {
                let mask = random_mask(h, w, seed);
                let (labels, count) = connected_components(mask.view());
                let pieces = slow_components(&mask);
                assert_eq!(count, pieces.len(), "{h}×{w}, seed {seed}");
                for (c, piece) in pieces.iter().enumerate() {
                    for ((y, x), &inside) in piece.indexed_iter() {
                        assert_eq!(
                            labels[[y, x]] == c as u32,
                            inside,
                            "{h}×{w}, seed {seed}: piece {c} at [{y}, {x}]"
                        );
                    }
                }
            }
        }
    }

    pub fn erosion_matches_the_direct_modified_definition() {
        for (h, w) in [(8, 8), (16, 16), (20, 13), (32, 32)] {
            for seed in 0..4 {
                let mask = random_mask(h, w, seed);
                let pieces = slow_components(&mask);
                for r in [0.0, 0.5, 1.0, 1.4, 2.0, 2.5, 3.7, 6.0, 40.0] {
                    let fast = erode(mask.view(), r);
                    let slow = slow_modified_erosion(&mask, r);
                    let mut thin = 0;
                    for piece in &pieces {
                        let survivors = piece
                            .iter()
                            .zip(fast.mask.iter())
                            .filter(|(p, k)| **p && **k);
                        assert!(
                            survivors.count() > 0,
                            "{h}×{w}, seed {seed}: a piece was swept out at r {r}"
                        );
                        thin += usize::from(!slow_erosion(piece, r).iter().any(|&b| b));
                    }
                    assert_eq!(fast.components, pieces.len());
                    assert_eq!(fast.thin_components, thin, "{h}×{w}, seed {seed}, r {r}");
                    if let Some(((y, x), _)) =
                        fast.mask.indexed_iter().find(|(p, v)| **v != slow[*p])
                    {
                        panic!("{h}×{w}, seed {seed}, r {r}: first difference at [{y}, {x}]");
                    }
                }
            }
        }
    }

    /// A ring thinner than the radius keeps its whole centre line, not a few spots.
    pub fn a_thin_ring_keeps_its_centre_line_all_the_way_round() {
        let n = 64;
        let mask = Array2::from_shape_fn((n, n), |(y, x)| {
            let (dy, dx) = (y as f64 - 32.0, x as f64 - 32.0);
            ((dy * dy + dx * dx).sqrt() - 16.0).abs() <= 1.6
        });
        let e = erode(mask.view(), 5.0);
        assert_eq!((e.components, e.thin_components), (1, 1));
        // Every angular sector of the ring keeps bins.
        for sector in 0..32 {
            let a = std::f64::consts::TAU * (sector as f64 + 0.5) / 32.0;
            let (cy, cx) = (32.0 + 16.0 * a.sin(), 32.0 + 16.0 * a.cos());
            let near = e.mask.indexed_iter().any(|((y, x), &k)| {
                k && (y as f64 - cy).powi(2) + (x as f64 - cx).powi(2) <= 2.5 * 2.5
            });
            assert!(near, "sector {sector} of the ring was swept out");
        }
        // And only its middle: nothing on the ring's edges.
        let kept = e.mask.iter().filter(|&&k| k).count();
        let all = mask.iter().filter(|&&k| k).count();
        assert!(kept * 2 < all, "kept {kept} of {all} bins");
    }

    pub fn a_full_grid_and_an_empty_set_are_left_alone() {
        let full = Array2::from_elem((6, 6), true);
        let e = erode(full.view(), 3.0);
        assert_eq!(e.mask, full);
        assert_eq!((e.components, e.thin_components), (1, 0));
        let empty = Array2::from_elem((6, 6), false);
        let e = erode(empty.view(), 3.0);
        assert_eq!(e.mask, empty);
        assert_eq!((e.components, e.thin_components), (0, 0));
    }
}
