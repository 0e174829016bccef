//! Dong et al. 2020, survey of procedural texture methods: the classic gallery (Perlin,
//! simplex, value, Worley combinations, fBm, turbulence, ridged, wavelet), the 1/f^β fractal's
//! slopes for β from ½ to 2 and fBm's, and relighting of height maps.

use ndarray::Array2;
use spectex_model::classic::{Metric, Worley};
use spectex_model::{ClassicNoise, Model, SpectralTarget, WaveletNoise};
use spectex_sampling::{FitOptions, Partition, fit_target};
use spectex_spectrum::relief::{Edges, shade};
use spectex_spectrum::{Fft2, log_log_fit, welch_psd_with_block};

use crate::plot::{Series, grey_png, grey_png_auto, line_plot};
use crate::{Context, Effort, Expect, Panel, Result, Session, render_grey};

pub(crate) fn reproduce(s: &mut Session<'_>) -> Result<()> {
    s.step("classic gallery");
    gallery(s)?;
    s.step("1/f^β slopes");
    slopes(s)?;
    s.step("relighting");
    relighting(s)
}

fn gallery(s: &mut Session<'_>) -> Result<()> {
    let worley = |metric, coefficients| {
        ClassicNoise::worley()
            .worley(Worley {
                metric,
                coefficients,
                ..Worley::default()
            })
            .cell_size(32.0)
            .build()
    };
    let models: Vec<(&str, Model)> = vec![
        (
            "Perlin",
            ClassicNoise::perlin()
                .cell_size(32.0)
                .build()
                .ctx("Perlin")?
                .into(),
        ),
        (
            "simplex",
            ClassicNoise::simplex()
                .cell_size(32.0)
                .build()
                .ctx("simplex")?
                .into(),
        ),
        (
            "value",
            ClassicNoise::value()
                .cell_size(32.0)
                .build()
                .ctx("value")?
                .into(),
        ),
        (
            "Worley F1",
            worley(Metric::Euclidean, [1.0, 0.0, 0.0, 0.0])
                .ctx("Worley")?
                .into(),
        ),
        (
            "Worley F2",
            worley(Metric::Euclidean, [0.0, 1.0, 0.0, 0.0])
                .ctx("Worley")?
                .into(),
        ),
        (
            "Worley F2 − F1",
            worley(Metric::Euclidean, [-1.0, 1.0, 0.0, 0.0])
                .ctx("Worley")?
                .into(),
        ),
        (
            "Worley F2 − F1, Manhattan",
            worley(Metric::Manhattan, [-1.0, 1.0, 0.0, 0.0])
                .ctx("Worley")?
                .into(),
        ),
        (
            "fBm",
            ClassicNoise::fbm()
                .cell_size(64.0)
                .build()
                .ctx("fBm")?
                .into(),
        ),
        (
            "turbulence",
            ClassicNoise::turbulence()
                .cell_size(64.0)
                .build()
                .ctx("turbulence")?
                .into(),
        ),
        (
            "ridged",
            ClassicNoise::ridged()
                .cell_size(64.0)
                .build()
                .ctx("ridged")?
                .into(),
        ),
        (
            "wavelet",
            WaveletNoise::builder()
                .cell_size(8.0)
                .build()
                .ctx("wavelet")?
                .into(),
        ),
    ];
    let mut panels = Vec::new();
    for (name, model) in &models {
        let (img, _) = render_grey(model, 192)?;
        let slug: String = name.chars().filter(char::is_ascii_alphanumeric).collect();
        let (path, file) = s.file(&format!("gallery-{slug}.png"));
        grey_png_auto(&path, img.view())?;
        panels.push(Panel {
            file,
            label: (*name).to_owned(),
        });
    }
    s.figure(
        "§3 (classic noises)",
        "The classic gallery: one octave of Perlin, simplex and value noise (cell 32), Worley \
         combinations (F1, F2, F2 − F1 Euclidean and Manhattan), fBm, turbulence and ridged \
         multifractal of Perlin noise (first cell 64), wavelet noise (cell 8); 192² each, \
         stretched to mean ± 2.5σ."
            .into(),
        panels,
        None,
    );
    Ok(())
}

/// The survey's 1/f^β fractal (Eq. (8), dominant angle 0.5 rad, no angular term, lowest
/// frequency 1/128) as `spectex noise fractal` fits it: J = 48 cosines in 12 strata of equal
/// log-power spans (each about one octave; equal-energy strata put the whole weak tail of a
/// steep spectrum into one flat stratum). Shared with the CLI's classic fidelity test.
///
/// # Errors
/// The fit fails.
pub fn fractal_model(beta: f32) -> Result<Model> {
    let target = SpectralTarget::Fractal {
        beta,
        angle: 0.5,
        spread: None,
        min_frequency: 1.0 / 128.0,
    };
    let options = FitOptions {
        budget: 48,
        strata: 12,
        seed: 3,
        partition: Partition::LogPower,
        ..FitOptions::default()
    };
    Ok(Model::Lrp(
        fit_target(&target, 1.0, 256, &options).ctx("fractal fit")?,
    ))
}

/// A log–log fit: slope, intercept (natural logarithms) and the radial profile as
/// `(log10 f, log10 P)` points.
type SlopeFit = (f64, f64, Vec<(f64, f64)>);

/// The radial PSD of `model` at `side`, with its log–log fit over `[lo, hi]`.
fn slope_of(model: &Model, side: usize, lo: f64, hi: f64) -> Result<SlopeFit> {
    let (img, _) = render_grey(model, side)?;
    let mut fft = Fft2::new();
    let psd = welch_psd_with_block(img.view(), side / 4, &mut fft).ctx("Welch PSD")?;
    let (slope, intercept, _) = log_log_fit(psd.view(), lo, hi);
    let profile = spectex_spectrum::radial_profile(psd.view())
        .into_iter()
        .filter(|b| b.radius > 0.0 && b.power > 0.0)
        .map(|b| (b.radius.log10(), b.power.log10()))
        .collect();
    Ok((slope, intercept, profile))
}

fn slopes(s: &mut Session<'_>) -> Result<()> {
    let side = match s.effort() {
        Effort::Tiny => 256,
        Effort::Quick => 512,
        Effort::Full => 1024,
    };
    let mut series = Vec::new();
    let mut rows = Vec::new();
    let mut worst = 0.0f64;
    let mut panels = Vec::new();
    for (i, beta) in [0.5f32, 1.0, 1.5, 2.0].into_iter().enumerate() {
        let model = fractal_model(beta)?;
        let (slope, intercept, profile) = slope_of(&model, side, 0.03, 0.3)?;
        worst = worst.max((slope + 2.0 * f64::from(beta)).abs());
        rows.push(format!("β = {beta}: {slope:.3} (want {})", -2.0 * beta));
        series.push(Series {
            name: format!("β = {beta}"),
            // The decade around the fitted range: the fits' cut-off beyond it would squeeze it.
            points: profile
                .into_iter()
                .filter(|p| (-2.2..=-0.4).contains(&p.0))
                .collect(),
            dots: true,
            colour: Some(i),
        });
        series.push(Series {
            name: format!("fit, slope {slope:.2}"),
            colour: Some(i),
            points: [0.03f64, 0.3]
                .iter()
                .map(|&f| {
                    (
                        f.log10(),
                        (intercept + slope * f.ln()) / std::f64::consts::LN_10,
                    )
                })
                .collect(),
            dots: false,
        });
        if beta == 1.0 || beta == 2.0 {
            let (img, _) = render_grey(&model, 256)?;
            let (path, file) = s.file(&format!("fractal-beta{beta}.png"));
            grey_png_auto(&path, img.view())?;
            panels.push(Panel {
                file,
                label: format!("1/f^β fractal, β = {beta}"),
            });
        }
    }
    s.claim(
        "survey-fractal-slopes",
        "§3.3, Eq. (8)",
        "1/f^β noise: magnitude M(f) ∝ 1/f^β, so the radial power falls as f^(−2β) (fitted \
         slope within 0.1, β from ½ to 2, over 0.03–0.3 cycle/pixel)",
        "−2β",
        rows.join("; "),
        Some("cargo test --release -p spectex-cli --test it classic_fidelity::"),
        worst < 0.1,
        Expect::Holds,
    );
    let (path, file) = s.file("fractal-slopes.svg");
    line_plot(
        &path,
        "Radial PSD of 1/f^β fractals and their fitted lines",
        ("log10 frequency (cycles/pixel)", "log10 power"),
        &series,
    )?;
    panels.insert(
        0,
        Panel {
            file,
            label: "radial power spectra and slope fits".into(),
        },
    );
    // fBm: independent octaves give P(λf) = g²λ⁻² P(f), a slope of −2 + 2 ln g / ln λ.
    let mut fbm_rows = Vec::new();
    let mut fbm_worst = 0.0f64;
    for (gain, lacunarity) in [(0.5f32, 2.0f32), (std::f32::consts::FRAC_1_SQRT_2, 2.0)] {
        let model: Model = ClassicNoise::fbm()
            .cell_size(128.0)
            .octaves(8)
            .gain(gain)
            .lacunarity(lacunarity)
            .seed(9)
            .build()
            .ctx("fBm")?
            .into();
        let want = -2.0 + 2.0 * f64::from(gain).ln() / f64::from(lacunarity).ln();
        let (slope, _, _) = slope_of(&model, side, 1.0 / 32.0, 1.0 / 8.0)?;
        fbm_worst = fbm_worst.max((slope - want).abs());
        fbm_rows.push(format!(
            "g = {gain:.3}, λ = {lacunarity}: {slope:.3} (want {want:.3})"
        ));
    }
    s.claim(
        "survey-fbm-slope",
        "§3.3 (fBm)",
        "fBm's self-similar octaves: gain g and lacunarity λ give a radial power slope \
         −2 + 2 ln g / ln λ between its first and last octaves (within 0.25)",
        "−4 (g = ½), −3 (g = 1/√2)",
        fbm_rows.join("; "),
        Some("cargo test --release -p spectex-cli --test it classic_fidelity::"),
        fbm_worst < 0.25,
        Expect::Holds,
    );
    s.figure(
        "Eq. (8) (1/f^β fractals)",
        format!(
            "LRP fits of the 1/f^β spectrum (J = 48 in 12 strata of equal log power), {side}² \
             renders, Welch PSD with {}² blocks, least-squares slopes over 0.03–0.3 cycle/pixel.",
            side / 4
        ),
        panels,
        None,
    );
    Ok(())
}

fn relighting(s: &mut Session<'_>) -> Result<()> {
    let height: Array2<f64> = {
        let model: Model = WaveletNoise::builder()
            .cell_size(6.0)
            .build()
            .ctx("wavelet")?
            .into();
        render_grey(&model, 256)?.0
    };
    let mut panels = Vec::new();
    let (path, file) = s.file("relight-height.png");
    grey_png_auto(&path, height.view())?;
    panels.push(Panel {
        file,
        label: "height map (wavelet noise)".into(),
    });
    for azimuth in [0.0, 120.0, 240.0] {
        let lit = shade(height.view(), 8.0, Edges::Clamp, azimuth, 40.0, 0.1).ctx("shading")?;
        let (path, file) = s.file(&format!("relight-az{azimuth}.png"));
        grey_png(&path, lit.view(), 0.0, 1.0)?;
        panels.push(Panel {
            file,
            label: format!("relit, light azimuth {azimuth}°, elevation 40°"),
        });
    }
    s.figure(
        "§3.4 (relighting)",
        "\"We use a wavelet noise function to generate 3D surface height maps and then relight \
         them\": a wavelet noise height map under three light directions (Lambert, ambient 0.1)."
            .into(),
        panels,
        None,
    );
    Ok(())
}
