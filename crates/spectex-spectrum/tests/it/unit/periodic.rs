//! Moisan's periodic + smooth decomposition against its defining equations (`src/periodic.rs`).

use ndarray::Array2;
use spectex_model::random::{Prng, cell_hash};
use spectex_spectrum::Fft2;
use spectex_spectrum::periodic::*;

fn random_image(h: usize, w: usize, seed: u32) -> Array2<f64> {
    let mut prng = Prng::new(cell_hash(h as i32, w as i32, 9, seed));
    // A ramp plus noise: strongly non-periodic, like a photograph with a light gradient.
    Array2::from_shape_fn((h, w), |(y, x)| {
        prng.next_f64() + 0.02 * x as f64 - 0.01 * y as f64
    })
}

fn check(h: &Array2<f64>, label: &str) {
    let mut fft = Fft2::new();
    let d = periodic_smooth(h.view(), &mut fft);
    let lhs = periodic_laplacian(d.periodic.view());
    let rhs = interior_laplacian(h.view());
    for ((idx, a), b) in lhs.indexed_iter().zip(rhs.iter()) {
        assert!(
            (a - b).abs() <= 1e-9,
            "{label}: Δp ≠ Δᵢh at {idx:?}: {a} vs {b}"
        );
    }
    let (mp, mh) = (d.periodic.mean().unwrap(), h.mean().unwrap());
    assert!(
        (mp - mh).abs() <= 1e-12 * mh.abs().max(1.0),
        "{label}: mean {mp} vs {mh}"
    );
}

/// The discrete equations of the paper hold to 1e-9 in f64 over a sweep of sizes,
/// odd, even, non-square and degenerate (one row or one column).
#[test]
fn periodic_component_solves_the_poisson_equation() {
    let mut sizes: Vec<(usize, usize)> = (1..=17).map(|n| (n, n)).collect();
    sizes.extend([
        (1, 9),
        (9, 1),
        (2, 3),
        (30, 45),
        (45, 30),
        (64, 64),
        (300, 300),
    ]);
    for (i, &(r, c)) in sizes.iter().enumerate() {
        check(&random_image(r, c, i as u32), &format!("{r}×{c} seed {i}"));
    }
}

#[test]
fn packed_pair_equals_separate_channels() {
    let (a, b) = (random_image(20, 33, 1), random_image(20, 33, 2));
    let mut fft = Fft2::new();
    let (pa, pb) = periodic_pair(a.view(), Some(b.view()), &mut fft);
    let sa = periodic_smooth(a.view(), &mut fft).periodic;
    let sb = periodic_smooth(b.view(), &mut fft).periodic;
    let e = pa.iter().zip(&sa).chain(pb.iter().zip(&sb));
    assert!(e.map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) < 1e-12);
}
