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

/// The relief of `spectex relight` unless `--strength` is given: a height of 1 is 16 pixels
/// high.
pub const DEFAULT_STRENGTH: f64 = 16.0;

/// The light of `spectex relight` unless `--light` is given, `[azimuth, elevation]` in
/// degrees: from the top left, 45° above the surface (the cartographic convention).
pub const DEFAULT_LIGHT: [f64; 2] = [135.0, 45.0];

/// The ambient light of `spectex relight` unless `--ambient` is given: faces turned away from
/// the light stay just visible.
pub const DEFAULT_AMBIENT: f64 = 0.1;

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
