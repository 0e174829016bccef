//! Matrix transformation against its definition: the image made by moving every source pixel
//! forward `k` times by `M` (a naive loop), the cat map's period against Pisano periods from the
//! literature and a naive orbit search, bijectivity (every source texel shown once per period
//! tile), and periodicity with `N` near the origin and at 10⁷.

use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::matrix::{MatrixSource, MatrixTransform};

/// A source whose texels are all different: texel `i` is `i / N²` (exact in f32 for `N² ≤ 2²⁴`).
fn numbered(n: u32) -> MatrixSource {
    let count = n * n;
    MatrixSource::Image {
        texels: (0..count).map(|i| i as f32 / count as f32).collect(),
    }
}

fn model(matrix: [[u32; 2]; 2], k: u64, n: u32, source: MatrixSource) -> MatrixTransform {
    let m = MatrixTransform {
        matrix,
        iterations: k,
        size: n,
        source,
        amplitude: 1.0,
        mean: 0.0,
    };
    m.validate().expect("test model is valid");
    m
}

fn render(m: &MatrixTransform, window: &Window) -> Vec<f32> {
    Evaluator::new(&Model::Matrix(m.clone()))
        .expect("valid model")
        .render(window)
        .expect("render")
}

/// The survey's procedure literally: every source pixel `s` moved `k` times, `s ← M·s mod N`,
/// and its value written there.
fn forward_image(m: &MatrixTransform) -> Vec<f32> {
    let n = u64::from(m.size);
    let a = m.matrix.map(|r| r.map(u64::from));
    let mut out = vec![f32::NAN; (n * n) as usize];
    for y in 0..n {
        for x in 0..n {
            let (mut px, mut py) = (x, y);
            for _ in 0..m.iterations {
                (px, py) = (
                    (a[0][0] * px + a[0][1] * py) % n,
                    (a[1][0] * px + a[1][1] * py) % n,
                );
            }
            out[(py * n + px) as usize] = m.source_value([x as u32, y as u32]);
        }
    }
    out
}

/// The smallest `k > 0` with `M^k = I mod N`, by iterating the map on the two unit vectors.
fn naive_period(matrix: [[u32; 2]; 2], n: u64) -> u64 {
    let a = matrix.map(|r| r.map(u64::from));
    let step = |(x, y): (u64, u64)| {
        (
            (a[0][0] * x + a[0][1] * y) % n,
            (a[1][0] * x + a[1][1] * y) % n,
        )
    };
    let (mut e1, mut e2) = ((1 % n, 0), (0, 1 % n));
    for k in 1..=6 * n {
        e1 = step(e1);
        e2 = step(e2);
        if e1 == (1 % n, 0) && e2 == (0, 1 % n) {
            return k;
        }
    }
    panic!("no period found for {matrix:?} mod {n}");
}

#[test]
fn renders_are_the_forward_moved_image() {
    for (matrix, k, n) in [
        ([[1, 1], [1, 2]], 1, 16),
        ([[1, 1], [1, 2]], 7, 32),
        ([[3, 0], [0, 5]], 4, 64),
        ([[2, 1], [1, 1]], 11, 27),
        ([[1, 2], [3, 5]], 3, 20),
    ] {
        for source in [numbered(n), MatrixSource::Rings { rings: 5 }] {
            let m = model(matrix, k, n, source);
            let want = forward_image(&m);
            let got = render(&m, &Window::new(n as usize, n as usize));
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(
                    g.to_bits(),
                    w.to_bits(),
                    "{matrix:?}, k = {k}, N = {n}: first difference at pixel ({}, {})",
                    i % n as usize,
                    i / n as usize
                );
            }
        }
    }
}

/// The cat map `[[1, 1], [1, 2]] = Q²` with `Q = [[0, 1], [1, 1]]`, whose order modulo `N` is
/// the Pisano period `π(N)`; so the cat map's period is `π(N)/2` for `N > 2` (Dyson & Falk 1992):
/// `π(4) = 6, π(5) = 20, π(10) = 60, π(256) = 3·2⁷ = 384` (`π(2ᵏ) = 3·2ᵏ⁻¹`, so the cat map
/// repeats after `3N/4` iterations for `N = 2ᵏ ≥ 4`).
#[test]
fn the_cat_map_period_is_half_the_pisano_period() {
    let cat = [[1, 1], [1, 2]];
    for (n, pisano) in [(4u32, 6u64), (5, 20), (10, 60), (256, 384)] {
        assert_eq!(naive_period(cat, u64::from(n)), pisano / 2, "N = {n}");
        let side = n.min(32);
        let window = Window::new(side as usize, side as usize);
        let source = render(&model(cat, 0, n, numbered(n)), &window);
        let full = render(&model(cat, pisano / 2, n, numbered(n)), &window);
        assert_eq!(full, source, "N = {n}: k = period gives the source back");
        // Twice the period plus 1 is 1 (every period here is at least 3).
        let one = render(&model(cat, 1, n, numbered(n)), &window);
        let wrapped = render(&model(cat, pisano + 1, n, numbered(n)), &window);
        assert_eq!(one, wrapped, "N = {n}: k modulo the period");
        assert_ne!(one, source, "N = {n}: k = 1 moves pixels");
    }
}

/// Every source texel appears exactly once in a period tile: the map is a bijection of the
/// torus when `det M` is prime to `N`.
#[test]
fn a_period_tile_shows_every_texel_once() {
    for (matrix, n) in [
        ([[1, 1], [1, 2]], 64),
        ([[7, 0], [0, 11]], 256),
        ([[5, 3], [8, 5]], 36),
    ] {
        let m = model(matrix, 9, n, numbered(n));
        let mut got = render(&m, &Window::new(n as usize, n as usize));
        got.sort_by(f32::total_cmp);
        let count = n * n;
        for (i, v) in got.iter().enumerate() {
            assert_eq!(*v, i as f32 / count as f32, "{matrix:?} mod {n}: texel {i}");
        }
    }
}

#[test]
fn the_texture_repeats_with_period_n_near_and_far() {
    let n = 40;
    let m = model([[1, 1], [1, 2]], 5, n, MatrixSource::Rings { rings: 7 });
    let base = render(&m, &Window::new(24, 24).at([3.0, 5.0], 1.0));
    for offset in [
        [3.0 + 40.0 * 3.0, 5.0 - 40.0 * 7.0],
        [3.0 + 40.0 * 250_000.0, 5.0 - 40.0 * 75_000.0],
    ] {
        let moved = render(&m, &Window::new(24, 24).at(offset, 1.0));
        assert_eq!(moved, base, "offset {offset:?}");
    }
}
