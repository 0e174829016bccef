//! `spectex analyze`: the periodic + smooth decomposition, spectra and radial profile of an
//! image, written as files into a directory.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result, anyhow};
use ndarray::{Array2, Array3, Axis};
use spectex_spectrum::{
    Fft2, centered, log_magnitude_spectrum, periodic_smooth, radial_profile, validate_image,
    variance_spectrum, welch_psd,
};

use crate::io::{self, BitDepth, Format};

/// How spectra are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SpectraFormat {
    /// 16-bit PNG, display-mapped to [0, 1].
    Png,
    /// 32-bit float OpenEXR, raw values.
    Exr,
}

/// Decades of power shown by a display-mapped power spectrum.
const DISPLAY_DECADES: f64 = 6.0;

/// Maps a log-magnitude image linearly onto [0, 1] by its own range.
fn normalise(a: &Array2<f64>) -> Array2<f64> {
    let (lo, hi) = a
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let span = if hi > lo { hi - lo } else { 1.0 };
    a.mapv(|v| (v - lo) / span)
}

/// Maps a power spectrum to [0, 1] on a log scale over [`DISPLAY_DECADES`] below its maximum.
fn display_power(p: &Array2<f64>) -> Array2<f64> {
    let max = p.iter().fold(0.0f64, |m, &v| m.max(v));
    if max <= 0.0 {
        return Array2::zeros(p.dim());
    }
    p.mapv(|v| ((v / max).max(1e-300).log10() / DISPLAY_DECADES + 1.0).clamp(0.0, 1.0))
}

fn one(a: Array2<f64>) -> Array3<f64> {
    a.insert_axis(Axis(0))
}

/// Runs every analysis of `img` and writes the files into `dir`.
pub fn run(img: &Array3<f64>, name: &str, dir: &Path, format: SpectraFormat) -> Result<()> {
    validate_image("image", img.view()).with_context(|| format!("cannot analyse {name}"))?;
    let (channels, h, w) = img.dim();
    // Welch needs blocks of at least 2×2: check before creating anything.
    spectex_spectrum::welch_block_size(h, w)
        .with_context(|| format!("cannot analyse {name}"))
        .map_err(|e| anyhow!("{e:#}; give an image of at least 3×3 pixels"))?;
    std::fs::create_dir_all(dir).map_err(|e| {
        anyhow!(
            "cannot create the output directory '{}': {e}; choose a writable location",
            dir.display()
        )
    })?;
    let mut fft = Fft2::new();

    let mut periodic = Array3::zeros(img.dim());
    let mut smooth = Array3::zeros(img.dim());
    for c in 0..channels {
        let d = periodic_smooth(img.index_axis(Axis(0), c), &mut fft);
        periodic.index_axis_mut(Axis(0), c).assign(&d.periodic);
        smooth
            .index_axis_mut(Axis(0), c)
            .assign(&d.smooth.mapv(|v| v + 0.5));
    }
    let luma = io::luminance(img);
    let luma_p = io::luminance(&periodic);
    let psd = welch_psd(luma.view(), &mut fft)?;
    let var = variance_spectrum(luma.view(), &mut fft)?;
    let log_raw = log_magnitude_spectrum(luma.view(), &mut fft);
    let log_per = log_magnitude_spectrum(luma_p.view(), &mut fft);

    let mut written = Vec::new();
    let mut put = |file: &str, data: &Array3<f64>, fmt: Format| -> Result<()> {
        let path = dir.join(file);
        io::save(&path, data, fmt)?;
        written.push(path);
        Ok(())
    };
    let image_fmt = Format::Png(BitDepth::Sixteen);
    put("periodic.png", &periodic, image_fmt)?;
    put("smooth.png", &smooth, image_fmt)?;
    let spectra: [(&str, Array2<f64>, Array2<f64>); 4] = [
        ("log_spectrum", normalise(&log_raw), log_raw.clone()),
        (
            "log_spectrum_periodic",
            normalise(&log_per),
            log_per.clone(),
        ),
        (
            "welch_psd",
            display_power(&centered(psd.view())),
            centered(psd.view()),
        ),
        (
            "variance_spectrum",
            display_power(&centered(var.view())),
            centered(var.view()),
        ),
    ];
    for (stem, display, raw) in spectra {
        match format {
            SpectraFormat::Png => put(&format!("{stem}.png"), &one(display), image_fmt)?,
            SpectraFormat::Exr => put(&format!("{stem}.exr"), &one(raw), Format::Exr)?,
        }
    }

    // Radial profile: one Welch PSD per channel (and the luminance for colour images).
    let mut columns: Vec<(String, Vec<spectex_spectrum::RadialBin>)> = Vec::new();
    let names: Vec<String> = if channels == 3 {
        vec!["red".into(), "green".into(), "blue".into()]
    } else {
        (0..channels).map(|c| format!("channel{c}")).collect()
    };
    for (c, n) in names.into_iter().enumerate() {
        let p = welch_psd(img.index_axis(Axis(0), c), &mut fft)?;
        columns.push((n, radial_profile(p.view())));
    }
    if channels == 3 {
        columns.push(("luminance".into(), radial_profile(psd.view())));
    }
    let csv = radial_csv(&columns);
    let csv_path = dir.join("radial_profile.csv");
    io::write_text_atomically(&csv_path, &csv)?;
    written.push(csv_path);

    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "analysed {name} ({w}×{h}, {channels} channel{}):",
            if channels == 1 { "" } else { "s" }
        );
        for p in &written {
            println!("  {}", p.display());
        }
    }
    Ok(())
}

fn radial_csv(columns: &[(String, Vec<spectex_spectrum::RadialBin>)]) -> String {
    let mut s = String::from("radius_cycles_per_pixel,count");
    for (n, _) in columns {
        let _ = write!(s, ",{n}");
    }
    s.push('\n');
    let rows = columns.first().map_or(0, |c| c.1.len());
    for i in 0..rows {
        let b = columns[0].1[i];
        let _ = write!(s, "{:.6},{}", b.radius, b.count);
        for (_, col) in columns {
            let _ = write!(s, ",{:.9e}", col[i].power);
        }
        s.push('\n');
    }
    s
}
