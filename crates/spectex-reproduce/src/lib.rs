//! Reproduction of the papers spectex is built from (`cargo xtask reproduce`): each paper's
//! figures that spectex can compute, regenerated, and its measurable claims, each measured
//! independently and judged against the number the paper prints.
//!
//! [`run`] measures the [`Paper`]s a [`Config`] names and returns a [`Report`]; [`write_report`]
//! writes it as `index.html`, the Markdown report and `claims.json` beside the figures. A claim is
//! *reproduced* when our measurement meets the paper's statement; one that does not is
//! *differs* with the documented reason when we know why (a typo in the paper, another machine),
//! and a **regression** otherwise: [`Report::regressions`] lists them and the command exits 1.
//!
//! ```no_run
//! use spectex_reproduce::{Config, Effort, Paper, run, write_report};
//! let config = Config::new(vec![Paper::Lrp], Effort::Quick, "target/reproduce".into());
//! let report = run(&config, &mut |_| {})?;
//! write_report(&report, &config.out_dir)?;
//! assert!(report.regressions().is_empty());
//! # Ok::<(), spectex_reproduce::ReproduceError>(())
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use ndarray::{Array2, Array3};
use spectex_cpu::{Evaluator, Filter, Window};
use spectex_model::Model;

pub mod gabor_example;
pub mod lrp;
pub mod phasor;
pub mod plot;
mod report;
mod rpn;
pub mod survey;
pub mod table1;
pub mod tiling;

pub use report::write_report;

/// What went wrong while reproducing.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReproduceError {
    /// A paper name that is not one of [`Paper::ALL`].
    #[error("unknown paper `{name}`; valid papers: lrp, rpn, phasor, survey, gabor-example")]
    UnknownPaper {
        /// The name given.
        name: String,
    },
    /// Reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A measurement that could not be made (a fit, a render, a spectrum, a plot).
    #[error("{what}: {message}")]
    Measure {
        /// What was being measured.
        what: String,
        /// The underlying error, as text.
        message: String,
    },
}

/// The result type of this crate.
pub type Result<T> = std::result::Result<T, ReproduceError>;

/// Turns any displayable error into [`ReproduceError::Measure`] naming what was measured.
pub(crate) trait Context<T> {
    fn ctx(self, what: &str) -> Result<T>;
}

impl<T, E: std::fmt::Display> Context<T> for std::result::Result<T, E> {
    fn ctx(self, what: &str) -> Result<T> {
        self.map_err(|e| ReproduceError::Measure {
            what: what.to_owned(),
            message: e.to_string(),
        })
    }
}

/// One of the papers in `../shared/papers/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Paper {
    /// Gilet et al. 2014, Local random-phase noise for procedural texturing.
    Lrp,
    /// Galerne, Gousseau & Morel, Random Phase Textures (IPOL).
    Rpn,
    /// Tricard et al. 2019, Procedural phasor noise.
    Phasor,
    /// Dong et al. 2020, Survey of procedural methods for two-dimensional texture generation.
    Survey,
    /// Galerne, Lagae, Lefebvre & Drettakis 2012, Gabor noise by example.
    GaborExample,
    /// Heitz & Neyret 2018, tiling and blending by example, and the four by-example methods
    /// side by side.
    Tiling,
}

impl Paper {
    /// Every paper, in report order.
    pub const ALL: [Paper; 6] = [
        Paper::Lrp,
        Paper::Rpn,
        Paper::Phasor,
        Paper::Survey,
        Paper::GaborExample,
        Paper::Tiling,
    ];

    /// The short name used on the command line and in file names.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Paper::Lrp => "lrp",
            Paper::Rpn => "rpn",
            Paper::Phasor => "phasor",
            Paper::Survey => "survey",
            Paper::GaborExample => "gabor-example",
            Paper::Tiling => "tiling",
        }
    }

    /// The paper's title and its file in `../shared/papers/`.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Paper::Lrp => {
                "Gilet, Sauvage, Vanhoey, Dischler, Ghazanfarpour 2014: Local random-phase noise \
                 for procedural texturing (lrp-noise-gilet-2014.txt)"
            }
            Paper::Rpn => {
                "Galerne, Gousseau, Morel: Random Phase Textures, IPOL \
                 (random-phase-noise-galerne-ipol.txt)"
            }
            Paper::Phasor => {
                "Tricard, Efremov, Zanni, Neyret, Martínez, Lefebvre 2019: Procedural phasor \
                 noise (phasor-noise-tricard-2019.txt)"
            }
            Paper::Survey => {
                "Dong, Wang, Ji, Zhang 2020: Survey of procedural methods for two-dimensional \
                 texture generation (procedural-texture-survey-2020.txt)"
            }
            Paper::GaborExample => {
                "Galerne, Lagae, Lefebvre, Drettakis 2012: Gabor noise by example (SIGGRAPH \
                 2012; not in ../shared/papers: its equations were checked from public copies)"
            }
            Paper::Tiling => {
                "Heitz & Neyret 2018: High-performance by-example noise using a \
                 histogram-preserving blending operator (HPG 2018; with Deliot & Heitz 2019 and \
                 Mikkelsen 2022; not in ../shared/papers)"
            }
        }
    }

    /// The paper called `name` (case-insensitive).
    ///
    /// # Errors
    /// [`ReproduceError::UnknownPaper`].
    pub fn from_name(name: &str) -> Result<Paper> {
        Paper::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(name))
            .ok_or_else(|| ReproduceError::UnknownPaper {
                name: name.to_owned(),
            })
    }
}

/// How much to measure: image sizes, repetitions and exemplars.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effort {
    /// Tiny sizes for the crate's own test: every path runs, the statistical verdicts are
    /// noisy.
    Tiny,
    /// `--quick`: the built-in exemplar and one shared one, 512² renders (under 2 minutes).
    Quick,
    /// Everything at the papers' sizes (under 10 minutes on 2 cores).
    Full,
}

impl Effort {
    /// Side of the renders whose spectra are measured.
    #[must_use]
    pub fn side(self) -> usize {
        match self {
            Effort::Tiny => 128,
            Effort::Quick => 512,
            Effort::Full => 1024,
        }
    }

    /// The name in the report.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Effort::Tiny => "tiny",
            Effort::Quick => "quick",
            Effort::Full => "full",
        }
    }
}

/// What to reproduce and where.
#[derive(Debug, Clone)]
pub struct Config {
    /// The papers, in order.
    pub papers: Vec<Paper>,
    /// Sizes and repetitions.
    pub effort: Effort,
    /// Directory for the report and its figures (created).
    pub out_dir: PathBuf,
    /// `testdata/textures` of `../shared`, or `None` (exemplar figures use the built-in only).
    pub shared_textures: Option<PathBuf>,
    /// Whether to time the GPU evaluator (Table 1) when an adapter exists.
    pub gpu: bool,
}

impl Config {
    /// `papers` at `effort` into `out_dir`, with `../shared` found beside the workspace when
    /// it is there and the GPU timed when an adapter exists.
    #[must_use]
    pub fn new(papers: Vec<Paper>, effort: Effort, out_dir: PathBuf) -> Self {
        let shared =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/testdata/textures");
        Self {
            papers,
            effort,
            out_dir,
            shared_textures: shared.is_dir().then_some(shared),
            gpu: true,
        }
    }
}

/// The paper's expectation of a claim, decided before measuring.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Expect {
    /// Our measurement should meet the paper's statement; not meeting it is a regression.
    Holds,
    /// Known not to meet it, for this documented reason.
    Differs(String),
}

/// One measurable claim of a paper, with our measurement.
#[derive(Debug, Clone)]
pub struct Claim {
    /// The paper.
    pub paper: Paper,
    /// A stable identifier (`lrp-envelope`).
    pub id: &'static str,
    /// Section, figure or table of the paper.
    pub section: &'static str,
    /// The paper's statement, quoted or closely paraphrased.
    pub statement: String,
    /// The paper's number.
    pub paper_value: String,
    /// Our measurement.
    pub ours: String,
    /// How it was measured (the command, and the test that checks the same number).
    pub command: String,
    /// Whether our measurement meets the paper's statement (the criterion is in `statement`).
    pub holds: bool,
    /// What we expected.
    pub expect: Expect,
}

/// A claim's verdict.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// Our measurement meets the paper's statement.
    Reproduced,
    /// It does not, for the documented reason.
    Differs(String),
    /// It does not, and it should: something regressed.
    Regression,
}

impl Claim {
    /// The verdict from `holds` and `expect`.
    #[must_use]
    pub fn verdict(&self) -> Verdict {
        match (&self.expect, self.holds) {
            (_, true) => Verdict::Reproduced,
            (Expect::Differs(reason), false) => Verdict::Differs(reason.clone()),
            (Expect::Holds, false) => Verdict::Regression,
        }
    }
}

/// One image of a figure: a file under the output directory and its label.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Path relative to the output directory (`lrp/fig10-lrp-j3.png`).
    pub file: String,
    /// What it shows.
    pub label: String,
}

/// A regenerated figure or table of a paper.
#[derive(Debug, Clone)]
pub struct Figure {
    /// The paper.
    pub paper: Paper,
    /// Which figure of the paper (`Fig. 10`).
    pub reference: &'static str,
    /// What it shows, with the exemplar or parameters.
    pub caption: String,
    /// Its images and plots, in order.
    pub panels: Vec<Panel>,
    /// A Markdown table, if the figure is a table.
    pub table: Option<String>,
}

/// Everything measured.
#[derive(Debug, Clone)]
pub struct Report {
    /// The effort it was measured at.
    pub effort: Effort,
    /// The claims, paper by paper.
    pub claims: Vec<Claim>,
    /// The figures, paper by paper.
    pub figures: Vec<Figure>,
    /// Seconds each paper took.
    pub seconds: Vec<(Paper, f64)>,
    /// Notes: what was skipped and why.
    pub notes: Vec<String>,
}

impl Report {
    /// How many claims are reproduced, differ (documented), and regressed.
    #[must_use]
    pub fn counts(&self) -> (usize, usize, usize) {
        let count =
            |f: &dyn Fn(&Verdict) -> bool| self.claims.iter().filter(|c| f(&c.verdict())).count();
        (
            count(&|v| *v == Verdict::Reproduced),
            count(&|v| matches!(v, Verdict::Differs(_))),
            count(&|v| *v == Verdict::Regression),
        )
    }

    /// The claims that should hold and do not.
    #[must_use]
    pub fn regressions(&self) -> Vec<&Claim> {
        self.claims
            .iter()
            .filter(|c| c.verdict() == Verdict::Regression)
            .collect()
    }
}

/// What a paper's reproduction works with: the configuration, the report being filled and a
/// progress callback.
pub(crate) struct Session<'a> {
    pub config: &'a Config,
    pub report: Report,
    pub progress: &'a mut dyn FnMut(&str),
    paper: Paper,
}

impl Session<'_> {
    pub fn effort(&self) -> Effort {
        self.config.effort
    }

    pub fn step(&mut self, what: &str) {
        (self.progress)(&format!("{}: {what}", self.paper.name()));
    }

    /// Writes a file path under the paper's folder and returns it relative to the output dir.
    pub fn file(&self, name: &str) -> (PathBuf, String) {
        let rel = format!("{}/{name}", self.paper.name());
        (self.config.out_dir.join(&rel), rel)
    }

    #[allow(
        clippy::too_many_arguments,
        reason = "a claim's fields, named at each call"
    )]
    pub fn claim(
        &mut self,
        id: &'static str,
        section: &'static str,
        statement: &str,
        paper_value: &str,
        ours: String,
        test: Option<&str>,
        holds: bool,
        expect: Expect,
    ) {
        let mut command = format!("cargo xtask reproduce {} (claim {id})", self.paper.name());
        if let Some(test) = test {
            command.push_str("; checked by ");
            command.push_str(test);
        }
        self.report.claims.push(Claim {
            paper: self.paper,
            id,
            section,
            statement: statement.to_owned(),
            paper_value: paper_value.to_owned(),
            ours,
            command,
            holds,
            expect,
        });
    }

    pub fn figure(
        &mut self,
        reference: &'static str,
        caption: String,
        panels: Vec<Panel>,
        table: Option<String>,
    ) {
        self.report.figures.push(Figure {
            paper: self.paper,
            reference,
            caption,
            panels,
            table,
        });
    }

    pub fn note(&mut self, note: String) {
        self.report.notes.push(note);
    }

    /// A shared texture by file name, or `None` (with a note) when `../shared` is absent.
    pub fn shared_texture(&mut self, name: &str) -> Result<Option<Array3<f64>>> {
        let Some(dir) = &self.config.shared_textures else {
            self.note(format!(
                "{}: {name} skipped: ../shared/testdata/textures is absent",
                self.paper.name()
            ));
            return Ok(None);
        };
        load_planes(&dir.join(name)).map(Some)
    }
}

/// The grey exemplars of noise by example (`../shared/testdata/textures/`): LRP's and Gabor
/// noise by example's claims, and the side-by-side table of the by-example methods.
pub(crate) const NOISE_EXEMPLARS: [&str; 4] = [
    "skimage_gravel.png",
    "astex_ambientcg_sand_height_512.png",
    "skimage_grass.png",
    "astex_ambientcg_dirt_height_512.png",
];

/// The built-in exemplar `crates/spectex-cli/default_exemplar.png` (256² RGB, made by the project).
pub(crate) fn builtin_exemplar() -> Result<Array3<f64>> {
    load_planes(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../spectex-cli/default_exemplar.png"))
}

/// An image file as planes (see [`planes`]).
pub(crate) fn load_planes(path: &Path) -> Result<Array3<f64>> {
    Ok(planes(
        &image::open(path).ctx(&format!("reading {}", path.display()))?,
    ))
}

/// An image as `(channels, height, width)` values in `[0, 1]`: 3 planes for a colour image, 1 for
/// a grey one (as `spectex` reads exemplars).
#[must_use]
pub fn planes(img: &image::DynamicImage) -> Array3<f64> {
    if img.color().has_color() {
        let img = img.to_rgb32f();
        let (w, h) = img.dimensions();
        Array3::from_shape_fn((3, h as usize, w as usize), |(c, y, x)| {
            f64::from(img.get_pixel(x as u32, y as u32).0[c])
        })
    } else {
        let img = img.to_luma32f();
        let (w, h) = img.dimensions();
        Array3::from_shape_fn((1, h as usize, w as usize), |(_, y, x)| {
            f64::from(img.get_pixel(x as u32, y as u32).0[0])
        })
    }
}

/// The mean of the planes of an image (its grey level).
pub(crate) fn grey(a: &Array3<f64>) -> Array2<f64> {
    let n = a.dim().0 as f64;
    a.sum_axis(ndarray::Axis(0)).mapv(|v| v / n)
}

/// Renders `model` over `window` into `(channels, height, width)`, with the seconds it took.
pub(crate) fn render(model: &Model, window: &Window) -> Result<(Array3<f64>, f64)> {
    let eval = Evaluator::new(model).ctx("building the CPU evaluator")?;
    let start = Instant::now();
    let v = eval.render(window).ctx("rendering on the CPU")?;
    let seconds = start.elapsed().as_secs_f64();
    let c = eval.output_channels();
    let (w, h) = (window.width, window.height);
    // The evaluator interleaves channels per pixel.
    let a = Array3::from_shape_fn((c, h, w), |(k, y, x)| f64::from(v[(y * w + x) * c + k]));
    Ok((a, seconds))
}

/// A square grey render of side `side` far from the origin (one channel, or the first).
pub(crate) fn render_grey(model: &Model, side: usize) -> Result<(Array2<f64>, f64)> {
    let (a, s) = render(model, &Window::new(side, side).at([3.0e3, -7.0e3], 1.0))?;
    Ok((a.index_axis(ndarray::Axis(0), 0).to_owned(), s))
}

/// Point samples of `model` far apart (no filtering): the model's own moments.
pub(crate) fn sparse_samples(model: &Model, side: usize, step: f64) -> Result<Array2<f64>> {
    let (a, _) = render(
        model,
        &Window::new(side, side)
            .at([-5.0e3, 9.0e3], step)
            .filtered(Filter::Off),
    )?;
    Ok(a.index_axis(ndarray::Axis(0), 0).to_owned())
}

/// Measures `config.papers` and returns the report; `progress` hears one line per step.
///
/// # Errors
/// A measurement that could not be made or a file that could not be written.
pub fn run(config: &Config, progress: &mut dyn FnMut(&str)) -> Result<Report> {
    std::fs::create_dir_all(&config.out_dir).map_err(|source| ReproduceError::Io {
        path: config.out_dir.clone(),
        source,
    })?;
    let mut session = Session {
        config,
        report: Report {
            effort: config.effort,
            claims: Vec::new(),
            figures: Vec::new(),
            seconds: Vec::new(),
            notes: Vec::new(),
        },
        progress,
        paper: Paper::Lrp,
    };
    for &paper in &config.papers {
        session.paper = paper;
        let dir = config.out_dir.join(paper.name());
        std::fs::create_dir_all(&dir).map_err(|source| ReproduceError::Io { path: dir, source })?;
        let start = Instant::now();
        match paper {
            Paper::Lrp => lrp::reproduce(&mut session)?,
            Paper::Rpn => rpn::reproduce(&mut session)?,
            Paper::Phasor => phasor::reproduce(&mut session)?,
            Paper::Survey => survey::reproduce(&mut session)?,
            Paper::GaborExample => gabor_example::reproduce(&mut session)?,
            Paper::Tiling => tiling::reproduce(&mut session)?,
        }
        session
            .report
            .seconds
            .push((paper, start.elapsed().as_secs_f64()));
    }
    Ok(session.report)
}
