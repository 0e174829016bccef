//! The report's pictures: images and spectra as PNG (through `image`), plots as SVG (through
//! `plotters`: line plots of radial spectra and slope fits, bar charts of timings).

use std::path::Path;

use ndarray::{Array2, Array3, ArrayView2};
use plotters::prelude::*;
use spectex_spectrum::{Fft2, log_magnitude_spectrum};

use crate::{Context, Result};

/// Plot size in SVG pixels.
const PLOT_SIZE: (u32, u32) = (560, 360);

/// The colours of successive series.
const SERIES_COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// Writes a grey image, mapped linearly from `[lo, hi]` to `[0, 255]` (clamped).
///
/// # Errors
/// The file cannot be written.
pub fn grey_png(path: &Path, a: ArrayView2<'_, f64>, lo: f64, hi: f64) -> Result<()> {
    let (h, w) = a.dim();
    let scale = if hi > lo { 255.0 / (hi - lo) } else { 0.0 };
    let img = image::GrayImage::from_fn(w as u32, h as u32, |x, y| {
        image::Luma([((a[[y as usize, x as usize]] - lo) * scale)
            .round()
            .clamp(0.0, 255.0) as u8])
    });
    img.save(path).ctx(&format!("writing {}", path.display()))
}

/// Writes a grey image stretched to its mean ± 2.5 standard deviations.
///
/// # Errors
/// The file cannot be written.
pub fn grey_png_auto(path: &Path, a: ArrayView2<'_, f64>) -> Result<()> {
    let (m, v) = spectex_spectrum::mean_variance(a);
    let sd = v.sqrt().max(1e-12);
    grey_png(path, a, m - 2.5 * sd, m + 2.5 * sd)
}

/// Writes planes `(channels, h, w)` in `[0, 1]`: RGB for 3 channels, grey for 1.
///
/// # Errors
/// The file cannot be written.
pub fn planes_png(path: &Path, a: &Array3<f64>) -> Result<()> {
    let (c, h, w) = a.dim();
    if c != 3 {
        return grey_png(path, a.index_axis(ndarray::Axis(0), 0), 0.0, 1.0);
    }
    let img = image::RgbImage::from_fn(w as u32, h as u32, |x, y| {
        let at = |k: usize| {
            (a[[k, y as usize, x as usize]] * 255.0)
                .round()
                .clamp(0.0, 255.0) as u8
        };
        image::Rgb([at(0), at(1), at(2)])
    });
    img.save(path).ctx(&format!("writing {}", path.display()))
}

/// Writes the centred log-magnitude spectrum of `a` (mean removed), stretched to its range.
///
/// # Errors
/// The file cannot be written.
pub fn spectrum_png(path: &Path, a: ArrayView2<'_, f64>, fft: &mut Fft2<f64>) -> Result<()> {
    let m = a.mean().unwrap_or(0.0);
    let s = log_magnitude_spectrum(a.mapv(|v| v - m).view(), fft);
    let hi = s.iter().copied().fold(0.0f64, f64::max);
    grey_png(path, s.view(), 0.0, hi)
}

/// Writes an uncentred power spectrum as a centred image of `ln(1 + P/max P · 1e4)`.
///
/// # Errors
/// The file cannot be written.
pub fn psd_png(path: &Path, psd: ArrayView2<'_, f64>) -> Result<()> {
    let max = psd.iter().copied().fold(0.0f64, f64::max).max(1e-300);
    let c: Array2<f64> = spectex_spectrum::centered(psd).mapv(|p| (p / max * 1e4).ln_1p());
    let hi = c.iter().copied().fold(0.0f64, f64::max);
    grey_png(path, c.view(), 0.0, hi)
}

/// One series of a line plot.
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// `(x, y)` points.
    pub points: Vec<(f64, f64)>,
    /// Dots instead of a line.
    pub dots: bool,
    /// Index into the palette; the series' own position when `None` (a fit drawn in its
    /// data's colour).
    pub colour: Option<usize>,
}

/// Writes an SVG line plot of `series`.
///
/// # Errors
/// The plot cannot be drawn or written.
pub fn line_plot(
    path: &Path,
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[Series],
) -> Result<()> {
    let what = format!("plotting {}", path.display());
    let all = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() || !y0.is_finite() {
        // No finite point: an empty unit square.
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if x0 >= x1 {
        (x0, x1) = (x0 - 1.0, x0 + 1.0);
    }
    if y0 >= y1 {
        (y0, y1) = (y0 - 1.0, y0 + 1.0);
    }
    let pad = 0.05 * (y1 - y0);
    let root = SVGBackend::new(path, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).ctx(&what)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
        .ctx(&what)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .ctx(&what)?;
    for (i, s) in series.iter().enumerate() {
        let colour = SERIES_COLOURS[s.colour.unwrap_or(i) % SERIES_COLOURS.len()];
        let points: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        let drawn = if s.dots {
            chart.draw_series(
                points
                    .into_iter()
                    .map(|p| Circle::new(p, 2, colour.filled())),
            )
        } else {
            chart.draw_series(LineSeries::new(points, colour.stroke_width(2)))
        }
        .ctx(&what)?;
        drawn.label(s.name.clone()).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2))
        });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .ctx(&what)?;
    root.present().ctx(&what)
}

/// Writes an SVG bar chart of `bars` (label, value).
///
/// # Errors
/// The plot cannot be drawn or written.
pub fn bar_plot(path: &Path, title: &str, y_label: &str, bars: &[(String, f64)]) -> Result<()> {
    let what = format!("plotting {}", path.display());
    let top = bars.iter().map(|b| b.1).fold(0.0f64, f64::max).max(1e-12) * 1.15;
    let n = bars.len().max(1);
    let root =
        SVGBackend::new(path, (PLOT_SIZE.0.max(90 * n as u32), PLOT_SIZE.1)).into_drawing_area();
    root.fill(&WHITE).ctx(&what)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(10)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..n as f64, 0.0..top)
        .ctx(&what)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .disable_x_axis()
        .y_desc(y_label)
        .draw()
        .ctx(&what)?;
    chart
        .draw_series(bars.iter().enumerate().map(|(i, b)| {
            let colour = SERIES_COLOURS[i % SERIES_COLOURS.len()];
            Rectangle::new(
                [(i as f64 + 0.15, 0.0), (i as f64 + 0.85, b.1)],
                colour.filled(),
            )
        }))
        .ctx(&what)?;
    chart
        .draw_series(bars.iter().enumerate().map(|(i, b)| {
            Text::new(
                format!("{:.3}", b.1),
                (i as f64 + 0.2, b.1 + top * 0.02),
                ("sans-serif", 13),
            )
        }))
        .ctx(&what)?;
    chart
        .draw_series(bars.iter().enumerate().map(|(i, b)| {
            Text::new(
                b.0.clone(),
                (i as f64 + 0.2, b.1 + top * 0.07),
                ("sans-serif", 12),
            )
        }))
        .ctx(&what)?;
    root.present().ctx(&what)
}
