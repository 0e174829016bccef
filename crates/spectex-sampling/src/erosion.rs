//! Shrinking a stratum by morphological erosion on the periodic frequency grid (§4.3), modified
//! so that no piece of a stratum thinner than the shrink distance is swept out.
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

/// The radius by which a set whose deepest bin lies at squared distance `deepest` from the
/// complement is eroded when `radius` is asked for: `radius` itself if that leaves a bin
/// (`deepest > radius²`), else the largest whole step `k ≤ ⌈radius⌉ − 1` with `k² < deepest`,
/// or 0 (erosion would leave nothing even at one step).
#[must_use]
pub fn step_radius(deepest: u32, radius: f64) -> f64 {
    let radius = if radius.is_nan() {
        0.0
    } else {
        radius.max(0.0)
    };
    let keeps_some = |r: f64| f64::from(deepest) > r * r;
    if keeps_some(radius) {
        return radius;
    }
    let steps = (radius.ceil() as u64).saturating_sub(1);
    let mut k = (f64::from(deepest).sqrt().ceil() as u64).min(steps);
    while k > 0 && !keeps_some(k as f64) {
        k -= 1;
    }
    while k < steps && keeps_some((k + 1) as f64) {
        k += 1;
    }
    k as f64
}

/// A shrunk stratum: the bins kept and how.
#[derive(Debug, Clone, PartialEq)]
pub struct Erosion {
    /// Bins kept, as a mask of the grid.
    pub mask: Array2<bool>,
    /// Connected pieces (8-connected, periodic) of the set that was eroded.
    pub components: usize,
    /// Pieces too thin for the full radius, eroded by a smaller step (see [`erode`]).
    pub thin_components: usize,
    /// The smallest radius applied to a piece, in bins (the radius asked for when no piece is
    /// thin; 0 for an empty set).
    pub smallest_radius: f64,
}

/// Shrinks the bin set `mask` by the disc of radius `radius` bins (§4.3: "discrete shrinking is
/// performed by morphological erosion, modified so that strata smaller than δ are not
/// completely swept out").
///
/// Exactly: each 8-connected piece `C` of the set (on the periodic grid) is eroded on its own
/// by the radius [`step_radius`]`(deepest_C, radius)`, where `deepest_C` is the largest squared
/// distance of a bin of `C` to the complement. That is, the radii `1, 2, …, ⌈r⌉ − 1` and then
/// `r` are tried in turn on the piece (each eroding the original piece, not the previous
/// result), and the piece keeps the erosion by the largest of them, or by 0 (itself), that
/// leaves at least one of its bins. A piece thicker than `r` somewhere is eroded by `r`
/// exactly; a thinner one keeps its deepest part (its centre line, or centre bins) instead of
/// vanishing.
///
/// Why per piece and not for the stratum as a whole: strata of a measured spectrum are
/// fragmented rings and speckle. A whole-stratum rule keeps only the deepest bins of the whole
/// stratum once its thickest piece is thinner than `δ` — on the gravel photograph (T = 256,
/// J = 50) it shrank three of the four strata, of 2058, 640 and 314 bins, to 12, 4 and 12 bins,
/// fewer frequencies than cosines. Per piece, every part of a stratum keeps a footprint, which
/// is the coverage goal of §4.3, while thick parts are eroded by the full `δ`, the leakage goal.
/// Erosion of a piece only depends on its own bins (the distance from a bin of `C` to the
/// complement of the set is the distance to the complement of `C`: pieces are separated by the
/// complement), so the rule is also mirror-symmetric.
#[must_use]
pub fn erode(mask: ArrayView2<'_, bool>, radius: f64) -> Erosion {
    let distance = squared_distance_to_complement(mask);
    let (labels, components) = connected_components(mask);
    let mut deepest = vec![0u32; components];
    for (&c, &d) in labels.iter().zip(distance.iter()) {
        if c != NO_COMPONENT {
            deepest[c as usize] = deepest[c as usize].max(d);
        }
    }
    let applied: Vec<f64> = deepest.iter().map(|&d| step_radius(d, radius)).collect();
    let asked = if radius.is_nan() {
        0.0
    } else {
        radius.max(0.0)
    };
    let thin_components = applied.iter().filter(|&&a| a < asked).count();
    let smallest_radius = applied.iter().copied().fold(f64::INFINITY, f64::min);
    let kept = Array2::from_shape_fn(mask.dim(), |p| {
        let c = labels[p];
        c != NO_COMPONENT && {
            let r = applied[c as usize];
            f64::from(distance[p]) > r * r
        }
    });
    Erosion {
        mask: kept,
        components,
        thin_components,
        smallest_radius: if components == 0 {
            0.0
        } else {
            smallest_radius
        },
    }
}

#[cfg(test)]
mod tests {
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

    /// The modified erosion by its definition: erode by 1, 2, …, ⌈r⌉ − 1, r and keep the last
    /// non-empty result.
    fn slow_modified_erosion(mask: &Array2<bool>, r: f64) -> (Array2<bool>, f64) {
        let mut radii: Vec<f64> = (1..r.ceil() as u64).map(|k| k as f64).collect();
        if r > 0.0 {
            radii.push(r);
        }
        let mut best = (mask.clone(), 0.0);
        for radius in radii {
            let e = slow_erosion(mask, radius);
            if e.iter().any(|&b| b) {
                best = (e, radius);
            } else {
                break;
            }
        }
        best
    }

    #[test]
    fn distance_transform_matches_the_direct_minimum() {
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

    #[test]
    fn components_match_their_definition() {
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

    #[test]
    fn erosion_matches_the_direct_modified_definition() {
        for (h, w) in [(8, 8), (16, 16), (20, 13), (32, 32)] {
            for seed in 0..4 {
                let mask = random_mask(h, w, seed);
                let pieces = slow_components(&mask);
                for r in [0.0, 0.5, 1.0, 1.4, 2.0, 2.5, 3.7, 6.0, 40.0] {
                    let fast = erode(mask.view(), r);
                    // The definition: each piece eroded alone by its last non-empty step.
                    let mut slow = Array2::from_elem((h, w), false);
                    let mut thin = 0;
                    for piece in &pieces {
                        let (kept, radius) = slow_modified_erosion(piece, r);
                        thin += usize::from(radius < r);
                        for (s, &k) in slow.iter_mut().zip(kept.iter()) {
                            *s |= k;
                        }
                        assert!(kept.iter().any(|&b| b), "a piece was swept out at r {r}");
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

    #[test]
    fn a_full_grid_and_an_empty_set_are_left_alone() {
        let full = Array2::from_elem((6, 6), true);
        let e = erode(full.view(), 3.0);
        assert_eq!(e.mask, full);
        assert_eq!(
            (e.components, e.thin_components, e.smallest_radius),
            (1, 0, 3.0)
        );
        let empty = Array2::from_elem((6, 6), false);
        let e = erode(empty.view(), 3.0);
        assert_eq!(e.mask, empty);
        assert_eq!(
            (e.components, e.thin_components, e.smallest_radius),
            (0, 0, 0.0)
        );
    }
}
