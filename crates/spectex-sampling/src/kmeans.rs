//! Sub-strata by k-means with random seeding (§4.3: "the shrunk stratum is broken into J_S
//! sub-strata using k-means with random seeding"), and their frequency tables.

use rayon::prelude::*;
use spectex_model::MAX_TABLE;
use spectex_model::random::{Prng, cell_hash};

use crate::grid::{Bin, frequency};

/// Layer of the randomness contract from which k-means seeding draws:
/// `Prng::new(cell_hash(level, 0, KMEANS_LAYER, seed))` for the stratum of level `level` (its
/// index in the equal-energy partition, 0 = lowest power) and the fit's seed. Evaluation uses
/// layers `0..64` (one per stratum), so fitting draws from a layer far from them.
pub const KMEANS_LAYER: u32 = 0x8000_0001;

/// Most Lloyd iterations before k-means stops without having converged.
pub const MAX_LLOYD_ITERATIONS: usize = 100;

/// Points × clusters above which the assignment step runs on rayon's pool. Each point's
/// nearest centroid is computed independently, so the result does not depend on the threads.
const PARALLEL_WORK: usize = 1 << 15;

/// The outcome of [`kmeans`].
#[derive(Debug, Clone, PartialEq)]
pub struct KMeans {
    /// Cluster of each point, in `0..clusters`; every cluster has at least one point.
    pub assignment: Vec<usize>,
    /// Centroid of each cluster: the mean of its points.
    pub centroids: Vec<[f64; 2]>,
    /// Lloyd iterations run.
    pub iterations: usize,
    /// Whether an iteration changed no assignment (else [`MAX_LLOYD_ITERATIONS`] was reached).
    pub converged: bool,
}

/// A uniform integer in `0..n` from 32 random bits, by multiply-and-shift (Lemire). The bias is
/// below `n / 2³²`, irrelevant for seeding.
fn below(prng: &mut Prng, n: usize) -> usize {
    ((u64::from(prng.next_u32()) * n as u64) >> 32) as usize
}

fn squared_distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    dx * dx + dy * dy
}

/// Nearest centroid of `p` (ties to the lowest index) and the squared distance to it, by
/// trying every centroid: the definition [`CentroidIndex::nearest`] is tested against.
fn nearest_direct(p: [f64; 2], centroids: &[[f64; 2]]) -> (usize, f64) {
    let mut best = (0, f64::INFINITY);
    for (c, &q) in centroids.iter().enumerate() {
        let d = squared_distance(p, q);
        if d < best.1 {
            best = (c, d);
        }
    }
    best
}

/// Centroids sorted by `x`, for nearest-centroid queries that only look at centroids whose
/// `x` is within the best distance found so far (exact: the same answer as
/// [`nearest_direct`], ties included).
struct CentroidIndex {
    /// `(x, y, original index)`, sorted by `x` then index.
    sorted: Vec<(f64, f64, usize)>,
}

impl CentroidIndex {
    fn new(centroids: &[[f64; 2]]) -> Self {
        let mut sorted: Vec<(f64, f64, usize)> = centroids
            .iter()
            .enumerate()
            .map(|(i, c)| (c[0], c[1], i))
            .collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        Self { sorted }
    }

    /// The lexicographically smallest `(squared distance, index)`: the nearest centroid, ties to
    /// the lowest index.
    fn nearest(&self, p: [f64; 2]) -> (usize, f64) {
        let s = &self.sorted;
        let start = s.partition_point(|c| c.0 < p[0]);
        let mut best = (usize::MAX, f64::INFINITY);
        let consider = |c: &(f64, f64, usize), best: &mut (usize, f64)| {
            let d = squared_distance(p, [c.0, c.1]);
            if d < best.1 || (d == best.1 && c.2 < best.0) {
                *best = (c.2, d);
            }
        };
        // Walk right then left from p's x; stop once the x gap alone exceeds the best distance
        // (`>`, not `≥`, so an equally distant centroid of lower index is still seen).
        for c in &s[start..] {
            let dx = c.0 - p[0];
            if dx * dx > best.1 {
                break;
            }
            consider(c, &mut best);
        }
        for c in s[..start].iter().rev() {
            let dx = p[0] - c.0;
            if dx * dx > best.1 {
                break;
            }
            consider(c, &mut best);
        }
        (best.0, best.1)
    }
}

/// Centroids above which the sorted index beats trying every centroid.
const INDEXED_CENTROIDS: usize = 32;

fn assign_all(points: &[[f64; 2]], centroids: &[[f64; 2]]) -> Vec<(usize, f64)> {
    let parallel = points.len() * centroids.len() >= PARALLEL_WORK;
    if centroids.len() > INDEXED_CENTROIDS {
        let index = CentroidIndex::new(centroids);
        if parallel {
            points.par_iter().map(|&p| index.nearest(p)).collect()
        } else {
            points.iter().map(|&p| index.nearest(p)).collect()
        }
    } else if parallel {
        points
            .par_iter()
            .map(|&p| nearest_direct(p, centroids))
            .collect()
    } else {
        points
            .iter()
            .map(|&p| nearest_direct(p, centroids))
            .collect()
    }
}

/// Means of the clusters (sequential sums in point order, so bit-identical for any thread
/// count) and their sizes; an empty cluster keeps its previous centroid.
fn update(
    points: &[[f64; 2]],
    assigned: &[(usize, f64)],
    centroids: &mut [[f64; 2]],
) -> Vec<usize> {
    let k = centroids.len();
    let mut sums = vec![[0.0f64; 2]; k];
    let mut counts = vec![0usize; k];
    for (p, &(c, _)) in points.iter().zip(assigned) {
        sums[c][0] += p[0];
        sums[c][1] += p[1];
        counts[c] += 1;
    }
    for c in 0..k {
        if counts[c] > 0 {
            let n = counts[c] as f64;
            centroids[c] = [sums[c][0] / n, sums[c][1] / n];
        }
    }
    counts
}

/// Gives every empty cluster the point farthest from its own centroid among clusters of more
/// than one point (ties to the lowest point index). Returns whether any cluster was empty.
fn refill_empty(
    points: &[[f64; 2]],
    assigned: &mut [(usize, f64)],
    counts: &mut [usize],
    centroids: &mut [[f64; 2]],
) -> bool {
    let mut any = false;
    for c in 0..counts.len() {
        if counts[c] > 0 {
            continue;
        }
        any = true;
        let mut far: Option<usize> = None;
        for (i, &(owner, d)) in assigned.iter().enumerate() {
            if counts[owner] > 1 && far.is_none_or(|f| d > assigned[f].1) {
                far = Some(i);
            }
        }
        // With more points than clusters some cluster always has two points.
        if let Some(i) = far {
            counts[assigned[i].0] -= 1;
            assigned[i] = (c, 0.0);
            counts[c] = 1;
            centroids[c] = points[i];
        }
    }
    any
}

/// Lloyd's k-means of 2D `points` into `clusters` clusters, seeded by `clusters` distinct points
/// drawn uniformly from `prng` (Forgy's random seeding, by a partial Fisher–Yates shuffle).
///
/// Each iteration moves every centroid to its cluster's mean, then reassigns every point to its
/// nearest centroid (ties to the lowest cluster index). A cluster left empty takes the point
/// farthest from its own centroid (among clusters of two points or more). The loop stops when an
/// iteration needed no refill and changed no assignment (converged: every point is then in the
/// cluster of its nearest centroid, which is its cluster's mean), or after
/// [`MAX_LLOYD_ITERATIONS`]; either way empty clusters are refilled once more and the centroids
/// are the final means, so every cluster has a point.
///
/// With no more points than clusters, each point is its own cluster and there are only
/// `points.len()` clusters. The result depends only on the inputs, not on rayon's thread count.
#[must_use]
pub fn kmeans(points: &[[f64; 2]], clusters: usize, prng: &mut Prng) -> KMeans {
    let n = points.len();
    if n <= clusters {
        return KMeans {
            assignment: (0..n).collect(),
            centroids: points.to_vec(),
            iterations: 0,
            converged: true,
        };
    }
    let mut order: Vec<usize> = (0..n).collect();
    let mut centroids = Vec::with_capacity(clusters);
    for i in 0..clusters {
        let j = i + below(prng, n - i);
        order.swap(i, j);
        centroids.push(points[order[i]]);
    }
    let mut assigned = assign_all(points, &centroids);
    let (mut iterations, mut converged) = (0, false);
    while iterations < MAX_LLOYD_ITERATIONS {
        iterations += 1;
        let mut counts = update(points, &assigned, &mut centroids);
        let refilled = refill_empty(points, &mut assigned, &mut counts, &mut centroids);
        let next = assign_all(points, &centroids);
        let unchanged = next.iter().zip(&assigned).all(|(a, b)| a.0 == b.0);
        assigned = next;
        if unchanged && !refilled {
            converged = true;
            break;
        }
    }
    let mut counts = update(points, &assigned, &mut centroids);
    if refill_empty(points, &mut assigned, &mut counts, &mut centroids) {
        update(points, &assigned, &mut centroids);
    }
    KMeans {
        assignment: assigned.iter().map(|a| a.0).collect(),
        centroids,
        iterations,
        converged,
    }
}

/// The frequency tables of one stratum's `cosines` (`J_S`) sub-strata (§4.3), from the shrunk
/// stratum's bins on the half plane, `points`, of a `size × size` spectrum.
///
/// - More points than cosines: [`kmeans`] on the points' frequencies (cycles per pixel) seeded
///   by `Prng::new(cell_hash(level, 0, KMEANS_LAYER, seed))`; table `j` lists the frequencies
///   `[f_x, f_y]` of cluster `j`'s bins in the order of `points`.
/// - No more points than cosines: table `j` is the single frequency of point `j mod n`, so the
///   points are repeated cyclically and every cosine still has a table.
/// - A table longer than [`MAX_TABLE`] keeps the `MAX_TABLE` entries at indices `⌊i·len/MAX_TABLE⌋`
///   (only spectra of side above 1448 can produce one).
///
/// No points gives no tables.
#[must_use]
pub fn sub_strata(
    points: &[Bin],
    size: usize,
    cosines: usize,
    level: usize,
    seed: u32,
) -> Vec<Vec<[f32; 2]>> {
    let n = points.len();
    if n == 0 || cosines == 0 {
        return Vec::new();
    }
    let as_f32 = |b: Bin| {
        let f = frequency(b, size);
        [f[0] as f32, f[1] as f32]
    };
    if n <= cosines {
        return (0..cosines).map(|j| vec![as_f32(points[j % n])]).collect();
    }
    let freqs: Vec<[f64; 2]> = points.iter().map(|&b| frequency(b, size)).collect();
    let mut prng = Prng::new(cell_hash(level as i32, 0, KMEANS_LAYER, seed));
    let result = kmeans(&freqs, cosines, &mut prng);
    let mut tables = vec![Vec::new(); cosines];
    for (&b, &c) in points.iter().zip(&result.assignment) {
        tables[c].push(as_f32(b));
    }
    for table in &mut tables {
        if table.len() > MAX_TABLE {
            let len = table.len();
            *table = (0..MAX_TABLE).map(|i| table[i * len / MAX_TABLE]).collect();
        }
    }
    tables
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// Points of a few irregular blobs on a 64×64 frequency grid.
    fn blob_points(seed: u32, n: usize) -> Vec<[f64; 2]> {
        let mut prng = Prng::new(cell_hash(7, 7, 11, seed));
        let centres: Vec<[f64; 2]> = (0..5)
            .map(|_| [prng.next_f64() - 0.5, prng.next_f64() * 0.5])
            .collect();
        (0..n)
            .map(|i| {
                let c = centres[i % centres.len()];
                let spread = 0.02 + 0.05 * (i % 3) as f64;
                [
                    c[0] + spread * (prng.next_f64() - 0.5),
                    c[1] + spread * (prng.next_f64() - 0.5),
                ]
            })
            .collect()
    }

    pub fn converged_clusters_hold_the_points_nearest_their_means() {
        for seed in 0..6 {
            for (n, k) in [(50usize, 3usize), (400, 12), (2000, 7), (3000, 40)] {
                let points = blob_points(seed, n);
                let r = kmeans(&points, k, &mut Prng::new(seed));
                assert!(r.converged, "n {n}, k {k}, seed {seed}: not converged");
                assert_eq!(r.assignment.len(), n);
                assert_eq!(r.centroids.len(), k);
                // Recompute the means directly and check the nearest-mean property.
                let mut sums = vec![[0.0f64; 3]; k];
                for (p, &c) in points.iter().zip(&r.assignment) {
                    assert!(c < k);
                    sums[c][0] += p[0];
                    sums[c][1] += p[1];
                    sums[c][2] += 1.0;
                }
                for (c, s) in sums.iter().enumerate() {
                    assert!(s[2] > 0.0, "n {n}, k {k}, seed {seed}: cluster {c} empty");
                    let mean = [s[0] / s[2], s[1] / s[2]];
                    assert!(squared_distance(mean, r.centroids[c]) < 1e-24);
                }
                for (i, &p) in points.iter().enumerate() {
                    let own = squared_distance(p, r.centroids[r.assignment[i]]);
                    for (c, &q) in r.centroids.iter().enumerate() {
                        assert!(
                            own <= squared_distance(p, q),
                            "n {n}, k {k}, seed {seed}: point {i} nearer cluster {c} than its own {}",
                            r.assignment[i]
                        );
                    }
                }
            }
        }
    }

    pub fn indexed_nearest_centroid_matches_the_direct_search() {
        let mut prng = Prng::new(5);
        for k in [1usize, 2, 3, 17, 256] {
            // Centroids on a coarse lattice, with duplicates, so that exact ties happen.
            let centroids: Vec<[f64; 2]> = (0..k)
                .map(|_| {
                    [
                        f64::from(prng.next_u32() % 9) / 8.0 - 0.5,
                        f64::from(prng.next_u32() % 5) / 8.0,
                    ]
                })
                .collect();
            let index = CentroidIndex::new(&centroids);
            for i in 0..4000 {
                let p = if i % 2 == 0 {
                    [prng.next_f64() - 0.5, prng.next_f64() * 0.5]
                } else {
                    [
                        f64::from(prng.next_u32() % 17) / 16.0 - 0.5,
                        f64::from(prng.next_u32() % 9) / 16.0,
                    ]
                };
                let (a, b) = (index.nearest(p), nearest_direct(p, &centroids));
                assert_eq!(a.0, b.0, "k {k}, point {i} at {p:?}");
                assert_eq!(a.1.to_bits(), b.1.to_bits());
            }
        }
    }

    pub fn kmeans_is_deterministic_for_any_thread_count() {
        let points = blob_points(3, 20_000);
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map(|pool| pool.install(|| kmeans(&points, 25, &mut Prng::new(42))))
        };
        let (Ok(one), Ok(four)) = (run(1), run(4)) else {
            panic!("could not build rayon pools");
        };
        assert_eq!(one, four);
        assert_eq!(one, kmeans(&points, 25, &mut Prng::new(42)));
        assert_ne!(one, kmeans(&points, 25, &mut Prng::new(43)));
    }

    pub fn few_points_each_get_their_own_cluster() {
        let points = [[0.1, 0.2], [0.3, 0.0]];
        let r = kmeans(&points, 5, &mut Prng::new(1));
        assert_eq!(r.assignment, [0, 1]);
        assert_eq!(r.centroids, points.to_vec());
        let tables = sub_strata(&[[1, 2], [0, 3]], 8, 5, 0, 1);
        let want = [[0.25f32, 0.125], [0.375, 0.0]];
        assert_eq!(tables.len(), 5);
        for (j, t) in tables.iter().enumerate() {
            assert_eq!(t, &vec![want[j % 2]], "table {j}");
        }
    }

    pub fn tables_partition_the_points() {
        let size = 32;
        let points: Vec<Bin> = (1..size / 2)
            .flat_map(|k| (0..size).map(move |l| [k, l]))
            .filter(|&[k, l]| (k * 7 + l * 3) % 5 != 0)
            .collect();
        let tables = sub_strata(&points, size, 9, 2, 77);
        assert_eq!(tables.len(), 9);
        let mut all: Vec<[f32; 2]> = tables.iter().flatten().copied().collect();
        assert!(tables.iter().all(|t| !t.is_empty()));
        let mut want: Vec<[f32; 2]> = points
            .iter()
            .map(|&b| {
                let f = frequency(b, size);
                [f[0] as f32, f[1] as f32]
            })
            .collect();
        let key = |a: &[f32; 2], b: &[f32; 2]| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1]));
        all.sort_by(key);
        want.sort_by(key);
        assert_eq!(all, want);
        assert_eq!(tables, sub_strata(&points, size, 9, 2, 77));
    }
}
