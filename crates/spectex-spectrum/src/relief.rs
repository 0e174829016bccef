//! Height maps as surfaces: normals by central differences (wrap-around for periodic inputs,
//! one-sided at the borders otherwise), tangent-space normal maps, and Lambertian shading under a
//! directional light, as the survey's figures show procedural height fields.
//!
//! The surface is `z = strength · h(x, y)` with `x` to the right and `y` down the image (rows),
//! one pixel per unit; its normal is `(−s·∂h/∂x, −s·∂h/∂y, 1)` normalised. A normal map stores
//! `(n + 1)/2` per component with `+y` pointing **up** the image (the OpenGL convention: the y
//! derivative's sign is flipped), so it can be used by engines without conversion.
//!
//! ```
//! use ndarray::Array2;
//! use spectex_spectrum::relief::{Edges, normals};
//!
//! // A plane of slope 0.5 in x has the same normal everywhere.
//! let h = Array2::from_shape_fn((8, 8), |(_, x)| 0.5 * x as f64);
//! let n = normals(h.view(), 1.0, Edges::Clamp).unwrap();
//! let want = [-0.5 / 1.25f64.sqrt(), 0.0, 1.0 / 1.25f64.sqrt()];
//! for c in 0..3 {
//!     assert!((n[[c, 3, 0]] - want[c]).abs() < 1e-12);
//! }
//! ```

use ndarray::{Array2, Array3, ArrayView2};

use crate::SpectrumError;

/// What lies beyond the image's borders.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edges {
    /// The height map tiles (a periodic texture): differences wrap around.
    Wrap,
    /// One-sided differences at the borders.
    Clamp,
}

fn check(height: ArrayView2<'_, f64>, strength: f64) -> Result<(), SpectrumError> {
    let (h, w) = height.dim();
    if h < 2 || w < 2 {
        return Err(SpectrumError::TooSmall {
            parameter: "height map",
            width: w,
            height: h,
            min_width: 2,
            min_height: 2,
        });
    }
    if !(strength.is_finite() && strength > 0.0 && strength <= 1e6) {
        return Err(SpectrumError::OutOfRange {
            parameter: "strength",
            value: strength,
            range: "(0, 1e6] height units per pixel",
        });
    }
    for ((row, column), &value) in height.indexed_iter() {
        if !value.is_finite() {
            return Err(SpectrumError::NonFinite {
                parameter: "height map",
                value,
                channel: 0,
                row,
                column,
            });
        }
    }
    Ok(())
}

/// `∂h/∂x` and `∂h/∂y` at `(y, x)`.
fn gradient(height: ArrayView2<'_, f64>, edges: Edges, y: usize, x: usize) -> (f64, f64) {
    let (h, w) = height.dim();
    let diff = |a: f64, b: f64, span: f64| (b - a) / span;
    let dx = match edges {
        Edges::Wrap => diff(height[[y, (x + w - 1) % w]], height[[y, (x + 1) % w]], 2.0),
        Edges::Clamp if x == 0 => diff(height[[y, 0]], height[[y, 1]], 1.0),
        Edges::Clamp if x == w - 1 => diff(height[[y, w - 2]], height[[y, w - 1]], 1.0),
        Edges::Clamp => diff(height[[y, x - 1]], height[[y, x + 1]], 2.0),
    };
    let dy = match edges {
        Edges::Wrap => diff(height[[(y + h - 1) % h, x]], height[[(y + 1) % h, x]], 2.0),
        Edges::Clamp if y == 0 => diff(height[[0, x]], height[[1, x]], 1.0),
        Edges::Clamp if y == h - 1 => diff(height[[h - 2, x]], height[[h - 1, x]], 1.0),
        Edges::Clamp => diff(height[[y - 1, x]], height[[y + 1, x]], 2.0),
    };
    (dx, dy)
}

/// Unit normals `(3, rows, columns)` (x right, y down, z out of the image) of
/// `z = strength · height`.
///
/// # Errors
/// A map smaller than 2×2, a non-finite height, or `strength` outside `(0, 1e6]`.
pub fn normals(
    height: ArrayView2<'_, f64>,
    strength: f64,
    edges: Edges,
) -> Result<Array3<f64>, SpectrumError> {
    check(height, strength)?;
    let (h, w) = height.dim();
    let mut out = Array3::zeros((3, h, w));
    for y in 0..h {
        for x in 0..w {
            let (dx, dy) = gradient(height, edges, y, x);
            let v = [-strength * dx, -strength * dy, 1.0];
            let len = (v[0] * v[0] + v[1] * v[1] + 1.0).sqrt();
            for c in 0..3 {
                out[[c, y, x]] = v[c] / len;
            }
        }
    }
    Ok(out)
}

/// A tangent-space normal map in `[0, 1]`: `(n + 1)/2` with `+y` up the image (OpenGL).
///
/// # Errors
/// As [`normals`].
pub fn normal_map(
    height: ArrayView2<'_, f64>,
    strength: f64,
    edges: Edges,
) -> Result<Array3<f64>, SpectrumError> {
    let mut n = normals(height, strength, edges)?;
    n.index_axis_mut(ndarray::Axis(0), 1).mapv_inplace(|v| -v);
    n.mapv_inplace(|v| 0.5 * (v + 1.0));
    Ok(n)
}

/// Lambertian shading `ambient + (1 − ambient)·max(0, n·l)` under a light at `azimuth` degrees
/// (0 = from the right, 90 = from the top of the image) and `elevation` degrees above the plane.
///
/// # Errors
/// As [`normals`], an `elevation` outside `[0, 90]`, a non-finite azimuth, or `ambient` outside
/// `[0, 1]`.
pub fn shade(
    height: ArrayView2<'_, f64>,
    strength: f64,
    edges: Edges,
    azimuth: f64,
    elevation: f64,
    ambient: f64,
) -> Result<Array2<f64>, SpectrumError> {
    if !azimuth.is_finite() {
        return Err(SpectrumError::OutOfRange {
            parameter: "light azimuth",
            value: azimuth,
            range: "finite degrees",
        });
    }
    if !(0.0..=90.0).contains(&elevation) {
        return Err(SpectrumError::OutOfRange {
            parameter: "light elevation",
            value: elevation,
            range: "[0, 90] degrees",
        });
    }
    if !(0.0..=1.0).contains(&ambient) {
        return Err(SpectrumError::OutOfRange {
            parameter: "ambient",
            value: ambient,
            range: "[0, 1]",
        });
    }
    let n = normals(height, strength, edges)?;
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    // y runs down the image, so "from the top" is −y.
    let l = [a.cos() * e.cos(), -a.sin() * e.cos(), e.sin()];
    let (_, h, w) = n.dim();
    Ok(Array2::from_shape_fn((h, w), |(y, x)| {
        let d = (0..3).map(|c| n[[c, y, x]] * l[c]).sum::<f64>();
        ambient + (1.0 - ambient) * d.max(0.0)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(gradient(sq.view(), Edges::Clamp, 1, 0).0, 1.0);
        assert_eq!(
            gradient(sq.view(), Edges::Wrap, 1, 0).0,
            (1.0 - 225.0) / 2.0
        );
        assert_eq!(gradient(sq.view(), Edges::Clamp, 1, w - 1).0, 225.0 - 196.0);
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
}
