//! Normals and shading of height maps (`src/relief.rs`).

use ndarray::{Array2, ArrayView2};
use spectex_spectrum::relief::*;

/// `(∂h/∂x, ∂h/∂y)` at `(y, x)`, read back from the unit normal `(−∂h/∂x, −∂h/∂y, 1)/len` of
/// strength 1 (the library's own difference rule is private).
fn gradient(height: ArrayView2<'_, f64>, edges: Edges, y: usize, x: usize) -> (f64, f64) {
    let n = normals(height, 1.0, edges).unwrap();
    (-n[[0, y, x]] / n[[2, y, x]], -n[[1, y, x]] / n[[2, y, x]])
}

#[test]
fn a_plane_has_one_normal_and_its_exact_shading() {
    let (a, b) = (0.3, -0.7);
    let h = Array2::from_shape_fn((9, 11), |(y, x)| a * x as f64 + b * y as f64);
    let n = normals(h.view(), 2.0, Edges::Clamp).unwrap();
    let len = (4.0 * a * a + 4.0 * b * b + 1.0_f64).sqrt();
    let want = [-2.0 * a / len, -2.0 * b / len, 1.0 / len];
    for y in 0..9 {
        for x in 0..11 {
            for c in 0..3 {
                assert!((n[[c, y, x]] - want[c]).abs() < 1e-12, "({x}, {y}) c {c}");
            }
        }
    }
    // Light straight overhead: n·l = n_z.
    let s = shade(h.view(), 2.0, Edges::Clamp, 0.0, 90.0, 0.0).unwrap();
    assert!((s[[4, 5]] - 1.0 / len).abs() < 1e-12);
    // Flat map, light at 30° elevation: sin 30° everywhere, plus ambient.
    let flat = Array2::<f64>::zeros((4, 4));
    let s = shade(flat.view(), 1.0, Edges::Wrap, 123.0, 30.0, 0.2).unwrap();
    assert!(s.iter().all(|v| (v - (0.2 + 0.8 * 0.5)).abs() < 1e-12));
}

#[test]
fn wrap_uses_the_other_side_and_matches_the_derivative_of_a_periodic_surface() {
    // h = sin(2πx/16): the central difference at x = 0 with wrap-around is the interior
    // formula (sin(2π/16) − sin(−2π/16))/2, not a one-sided difference.
    let w = 16;
    let h = Array2::from_shape_fn((4, w), |(_, x)| {
        (std::f64::consts::TAU * x as f64 / w as f64).sin()
    });
    let (dx, dy) = gradient(h.view(), Edges::Wrap, 2, 0);
    assert!((dx - (std::f64::consts::TAU / 16.0).sin()).abs() < 1e-12);
    assert_eq!(dy, 0.0);
    // On h = x² the two rules differ at the border: one-sided (1 − 0)/1 against the wrapped
    // (h[1] − h[w − 1])/2.
    let sq = Array2::from_shape_fn((3, w), |(_, x)| (x * x) as f64);
    let close = |got: f64, want: f64| (got - want).abs() <= 1e-12 * want.abs().max(1.0);
    assert!(close(gradient(sq.view(), Edges::Clamp, 1, 0).0, 1.0));
    assert!(close(
        gradient(sq.view(), Edges::Wrap, 1, 0).0,
        (1.0 - 225.0) / 2.0
    ));
    assert!(close(
        gradient(sq.view(), Edges::Clamp, 1, w - 1).0,
        225.0 - 196.0
    ));
    // Periodic: the wrap normals of a map and of its circular shift are shifted copies.
    let shifted = Array2::from_shape_fn((4, w), |(y, x)| h[[y, (x + 5) % w]]);
    let a = normals(h.view(), 1.0, Edges::Wrap).unwrap();
    let b = normals(shifted.view(), 1.0, Edges::Wrap).unwrap();
    for x in 0..w {
        for c in 0..3 {
            assert_eq!(a[[c, 1, (x + 5) % w]], b[[c, 1, x]]);
        }
    }
}

#[test]
fn normal_map_is_opengl_encoded() {
    // Height rising down the image (∂h/∂y > 0): the normal leans to −y (up the image),
    // which OpenGL stores as +y: green above 0.5.
    let h = Array2::from_shape_fn((5, 5), |(y, _)| y as f64);
    let m = normal_map(h.view(), 1.0, Edges::Clamp).unwrap();
    assert!((m[[0, 2, 2]] - 0.5).abs() < 1e-12);
    assert!(m[[1, 2, 2]] > 0.5);
    assert!(m[[2, 2, 2]] > 0.5);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let h = Array2::<f64>::zeros((1, 5));
    assert!(
        normals(h.view(), 1.0, Edges::Wrap)
            .unwrap_err()
            .to_string()
            .contains("height map")
    );
    let mut h = Array2::<f64>::zeros((3, 3));
    h[[1, 2]] = f64::NAN;
    assert!(
        normals(h.view(), 1.0, Edges::Wrap)
            .unwrap_err()
            .to_string()
            .contains("row 1, column 2")
    );
    let h = Array2::<f64>::zeros((3, 3));
    assert!(
        normals(h.view(), 0.0, Edges::Wrap)
            .unwrap_err()
            .to_string()
            .contains("strength")
    );
    assert!(
        shade(h.view(), 1.0, Edges::Wrap, 0.0, 95.0, 0.1)
            .unwrap_err()
            .to_string()
            .contains("elevation")
    );
    assert!(
        shade(h.view(), 1.0, Edges::Wrap, 0.0, 45.0, 1.5)
            .unwrap_err()
            .to_string()
            .contains("ambient")
    );
}
