//! Tiling and blending by example (Heitz & Neyret 2018; Deliot & Heitz 2019): an exemplar
//! becomes a [`TilingTexture`] — its colours decorrelated by PCA, each channel Gaussianised by
//! rank (`g = Φ⁻¹(p)`, `p` the value's rank among the values weighed by how often a render's
//! taps read each texel, [`tap_density`]; ties by position), and the inverse tabulated: `T⁻¹(g)`
//! is the channel's sorted values read at rank `Φ(g)·n − ½` (linear between ranks, clamped to
//! the extremes), so a render's histogram is the exemplar's.

use ndarray::ArrayView3;
use spectex_model::tiling::{
    Blend, LUT_ENTRIES, Lattice, MAX_SIDE, MIN_SIDE, TilingTexture, lut_node,
};

use spectex_spectrum::{standard_normal_cdf, standard_normal_quantile};

use crate::SamplingError;
use crate::texture::colour_pca;

/// Options of [`fit_tiling`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TilingOptions {
    /// Side of the lattice's triangles, pixels; `None`: a sixth of the exemplar's smaller
    /// side.
    pub tile: Option<f32>,
    /// The blend.
    pub blend: Blend,
    /// Seed of the vertices' offsets.
    pub seed: u32,
}

impl Default for TilingOptions {
    fn default() -> Self {
        Self {
            tile: None,
            blend: TilingTexture::DEFAULT_BLEND,
            seed: spectex_model::DEFAULT_SEED,
        }
    }
}

/// Gaussianises one channel: the standard normal score of each value's rank among the values
/// weighed by `density` (a texel's share of the taps, [`tap_density`]), and the channel's values
/// sorted. With the density, a render's taps — not the exemplar's texels — are standard normal:
/// the taps read the exemplar's centre more often than its border, and an exemplar whose border
/// differs from its centre would otherwise shift the output's histogram.
fn gaussianise(values: &[f64], density: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = values.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
    let total: f64 = density.iter().sum();
    let mut scores = vec![0.0; n];
    let mut below = 0.0;
    for &i in &order {
        let p = ((below + 0.5 * density[i]) / total).clamp(1e-12, 1.0 - 1e-12);
        scores[i] = standard_normal_quantile(p);
        below += density[i];
    }
    let sorted = order.iter().map(|&i| values[i]).collect();
    (scores, sorted)
}

/// How often a render at scale 1 reads each texel of a `width × height` exemplar: a tap reads
/// `o + d`, the vertex's offset `o` uniform over the whole texels `[lo, lo + span]` per axis
/// ([`Lattice::spans`]) and the displacement `d` uniform over the whole pixels of the hexagon of
/// the vertex's six triangles (`|α|, |β|, |α + β| ≤ 1` in lattice coordinates `d = α·a₁ + β·a₂`):
/// the box of offsets summed over the hexagon's pixels, by a difference array.
#[must_use]
pub fn tap_density(width: usize, height: usize, lattice: &Lattice) -> Vec<f64> {
    let Some((lo, [sx, sy])) = lattice.spans(width as u32, height as u32) else {
        return vec![1.0; width * height];
    };
    let (lo, sx, sy) = (lo as i64, i64::from(sx), i64::from(sy));
    let reach = lattice.reach().ceil() as i64;
    let (w, h) = (width as i64, height as i64);
    let mut diff = vec![0.0f64; ((w + 1) * (h + 1)) as usize];
    let mut add = |x: i64, y: i64, v: f64| {
        if (0..=w).contains(&x) && (0..=h).contains(&y) {
            diff[(y * (w + 1) + x) as usize] += v;
        }
    };
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let beta = dy as f64 / lattice.row;
            let alpha = dx as f64 / lattice.side - beta / 2.0;
            if alpha.abs() > 1.0 || beta.abs() > 1.0 || (alpha + beta).abs() > 1.0 {
                continue;
            }
            let (x0, x1) = ((lo + dx).clamp(0, w - 1), (lo + sx + dx).clamp(0, w - 1));
            let (y0, y1) = ((lo + dy).clamp(0, h - 1), (lo + sy + dy).clamp(0, h - 1));
            add(x0, y0, 1.0);
            add(x1 + 1, y0, -1.0);
            add(x0, y1 + 1, -1.0);
            add(x1 + 1, y1 + 1, 1.0);
        }
    }
    let stride = (w + 1) as usize;
    for y in 0..=h as usize {
        for x in 0..=w as usize {
            let left = if x > 0 { diff[y * stride + x - 1] } else { 0.0 };
            let up = if y > 0 {
                diff[(y - 1) * stride + x]
            } else {
                0.0
            };
            let corner = if x > 0 && y > 0 {
                diff[(y - 1) * stride + x - 1]
            } else {
                0.0
            };
            diff[y * stride + x] += left + up - corner;
        }
    }
    (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .map(|(x, y)| diff[y * stride + x].max(0.0))
        .collect()
}

/// `T⁻¹` at the table's nodes: the sorted values at rank `Φ(g)·n − ½`.
fn inverse_table(sorted: &[f64]) -> Vec<f32> {
    let n = sorted.len();
    (0..LUT_ENTRIES)
        .map(|k| {
            let rank =
                (standard_normal_cdf(lut_node(k)) * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
            let i = (rank.floor() as usize).min(n.saturating_sub(2));
            let f = rank - i as f64;
            let hi = sorted[(i + 1).min(n - 1)];
            (sorted[i] + f * (hi - sorted[i])) as f32
        })
        .collect()
}

/// Fits tiling and blending to an exemplar of 1 (grey) or 3 (RGB) channels, `(channel, row,
/// column)`.
///
/// # Errors
/// Another channel count; a side outside `8..=4096`; a non-finite pixel; a constant exemplar; a
/// tile the exemplar cannot hold (the lattice's reach must leave room for an offset,
/// `spectex_model::tiling::Lattice::spans`).
pub fn fit_tiling(
    image: ArrayView3<'_, f64>,
    options: &TilingOptions,
) -> Result<TilingTexture, SamplingError> {
    let (nc, h, w) = image.dim();
    if nc != 1 && nc != 3 {
        return Err(SamplingError::OutOfRange {
            parameter: "image channels",
            value: nc as f64,
            range: "1 (grey) or 3 (RGB); an alpha channel has no place in a tiled texture",
        });
    }
    for side in [w, h] {
        if side < MIN_SIDE as usize || side > MAX_SIDE as usize {
            return Err(SamplingError::OutOfRange {
                parameter: "image side",
                value: side as f64,
                range: "8 to 4096 pixels",
            });
        }
    }
    for ((c, y, x), &v) in image.indexed_iter() {
        if !v.is_finite() {
            return Err(SamplingError::NonFinite {
                parameter: if c == 0 {
                    "image"
                } else {
                    "image (a colour channel)"
                },
                value: v,
                row: y,
                column: x,
            });
        }
    }
    let tile = options.tile.unwrap_or((w.min(h) / 6) as f32);
    let largest = ((w.min(h) - 1) / 2) as f64;
    if !tile.is_finite() || tile < 1.0 || f64::from(tile) > largest {
        return Err(SamplingError::OutOfRange {
            parameter: "tile",
            value: f64::from(tile),
            range: "1 to (min(width, height) − 1)/2 pixels: the exemplar must hold a whole tile \
                    around each lattice vertex",
        });
    }
    let (mean, vectors) = if nc == 3 {
        let (mean, vectors, _) = colour_pca(image)?;
        (mean.to_vec(), vectors)
    } else {
        let m = image.sum() / (w * h) as f64;
        (vec![m], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    };
    // The taps' density on the lattice the model will have (validated below with the model).
    let density = tap_density(w, h, &Lattice::of_tile(tile));
    let mut gaussian = vec![0.0f32; w * h * nc];
    let mut lut = Vec::with_capacity(nc * LUT_ENTRIES);
    let mut spread = 0.0f64;
    for c in 0..nc {
        // Channel c: the projection on eigenvector c (grey: the value less the mean).
        let values: Vec<f64> = (0..h * w)
            .map(|i| {
                let (y, x) = (i / w, i % w);
                (0..nc)
                    .map(|k| vectors[k][c] * (image[[k, y, x]] - mean[k]))
                    .sum()
            })
            .collect();
        let (scores, sorted) = gaussianise(&values, &density);
        spread = spread.max(sorted[sorted.len() - 1] - sorted[0]);
        for (i, s) in scores.iter().enumerate() {
            gaussian[i * nc + c] = *s as f32;
        }
        lut.extend(inverse_table(&sorted));
    }
    if spread <= 0.0 {
        return Err(SamplingError::OutOfRange {
            parameter: "image",
            value: mean[0],
            range: "an image whose values vary (a constant exemplar has no texture to tile)",
        });
    }
    let basis = (0..nc)
        .flat_map(|i| (0..nc).map(move |c| (i, c)))
        .map(|(i, c)| vectors[i][c] as f32)
        .collect();
    let model = TilingTexture {
        seed: options.seed,
        width: w as u32,
        height: h as u32,
        channels: nc as u32,
        tile,
        blend: options.blend,
        gaussian,
        lut,
        mean: mean.iter().map(|&m| m as f32).collect(),
        basis,
    };
    model.validate().map_err(SamplingError::Model)?;
    Ok(model)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use ndarray::Array3;

    /// The table maps standard normal values to the exemplar's histogram: the table read at
    /// the normal quantiles of `n` evenly spaced probabilities gives the exemplar's sorted
    /// values; and the scores, weighed by the taps' density, are standard normal.
    pub fn the_table_maps_normal_values_to_the_histogram() {
        let (h, w) = (24, 20);
        let image = Array3::from_shape_fn((1, h, w), |(_, y, x)| {
            let v = ((x * 7 + y * 13) % 17) as f64 / 16.0;
            v * v
        });
        let m = fit_tiling(
            image.view(),
            &TilingOptions {
                tile: Some(5.0),
                ..TilingOptions::default()
            },
        )
        .unwrap();
        assert_eq!(
            fit_tiling(image.view(), &TilingOptions::default())
                .unwrap()
                .tile,
            3.0,
            "a sixth of 20"
        );
        let lut = &m.lut[..LUT_ENTRIES];
        let (mean, scale) = (f64::from(m.mean[0]), f64::from(m.basis[0]));
        let n = h * w;
        let mut want: Vec<f64> = image.iter().copied().collect();
        want.sort_by(f64::total_cmp);
        for (k, v) in want.iter().enumerate() {
            let g = standard_normal_quantile((k as f64 + 0.5) / n as f64);
            let back = mean + scale * spectex_model::tiling::lut_f64(lut, g);
            // Between two table nodes the quantile moves by at most the gap between
            // neighbouring sorted values (here at most 33/256).
            assert!((back - v).abs() < 0.13, "{k}: {back} vs {v}");
        }
        let lattice = m.lattice(None).unwrap();
        let density = tap_density(w, h, &lattice);
        let total: f64 = density.iter().sum();
        let moment = |p: i32| -> f64 {
            m.gaussian
                .iter()
                .zip(&density)
                .map(|(&g, d)| d * f64::from(g).powi(p))
                .sum::<f64>()
                / total
        };
        assert!(
            moment(1).abs() < 1e-3 && (moment(2) - 1.0).abs() < 0.05,
            "{} {}",
            moment(1),
            moment(2)
        );
    }

    /// The density is the box of offsets summed over the hexagon's pixels: its total is the
    /// hexagon's pixel count times the box's area, and it is largest at the centre.
    pub fn tap_density_counts_every_tap_once() {
        let lattice = Lattice {
            side: 6.0,
            row: 5.0,
            wrap: None,
        };
        let (w, h) = (40usize, 30usize);
        let d = tap_density(w, h, &lattice);
        let (lo, [sx, sy]) = lattice.spans(w as u32, h as u32).unwrap();
        assert_eq!(lo, 6);
        let mut hexagon = 0.0;
        for dy in -6i32..=6 {
            for dx in -6i32..=6 {
                let beta = f64::from(dy) / 5.0;
                let alpha = f64::from(dx) / 6.0 - beta / 2.0;
                if alpha.abs() <= 1.0 && beta.abs() <= 1.0 && (alpha + beta).abs() <= 1.0 {
                    hexagon += 1.0;
                }
            }
        }
        let total: f64 = d.iter().sum();
        let box_area = f64::from((sx + 1) * (sy + 1));
        assert!(
            (total - hexagon * box_area).abs() < 1e-6,
            "{total} vs {}",
            hexagon * box_area
        );
        // The middle of the left edge is read (by the hexagon's left corner), the corner never.
        assert!(d[15 * w + 20] > d[15 * w] && d[15 * w] > 0.0 && d[0] == 0.0);
    }

    pub fn bad_exemplars_are_refused_by_name() {
        let param = |r: Result<TilingTexture, SamplingError>| match r {
            Err(SamplingError::OutOfRange { parameter, .. })
            | Err(SamplingError::NonFinite { parameter, .. }) => parameter,
            other => panic!("{other:?}"),
        };
        let ok = Array3::from_shape_fn((3, 16, 16), |(c, y, x)| ((c + x * y) % 5) as f64);
        let options = TilingOptions::default();
        assert!(fit_tiling(ok.view(), &options).is_ok());
        let rgba = Array3::from_shape_fn((4, 16, 16), |(c, y, x)| ((c + x * y) % 5) as f64);
        assert_eq!(param(fit_tiling(rgba.view(), &options)), "image channels");
        let small = Array3::from_shape_fn((1, 4, 16), |(_, y, x)| (x + y) as f64);
        assert_eq!(param(fit_tiling(small.view(), &options)), "image side");
        let constant = Array3::from_elem((1, 16, 16), 0.25);
        assert_eq!(param(fit_tiling(constant.view(), &options)), "image");
        let mut nan = ok.clone();
        nan[[0, 3, 4]] = f64::NAN;
        assert_eq!(param(fit_tiling(nan.view(), &options)), "image");
        let big_tile = TilingOptions {
            tile: Some(8.0),
            ..options
        };
        assert_eq!(param(fit_tiling(ok.view(), &big_tile)), "tile");
    }
}
