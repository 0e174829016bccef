//! The invariance checks every model kind must pass, on any evaluator ([`Backend`]), run over
//! [`Case`]s (every `testdata/models/*.json` by [`testdata_cases`]) by one [`check`] that
//! reports one line per model:
//!
//! - **tiles** (invariant 3): a window rendered whole equals, bit for bit, every tiling of it in
//!   [`Plan::tilings`] — grids of odd tile sizes, single rows and columns, 1×1 tiles over a
//!   patch, and loose rectangles — at `(10⁷ + 0.3, −10⁷ − 0.6)` and a fractional scale, plus a
//!   window wider than the CPU's 512-column chunks and a minified (filtered) one at scale 4;
//! - **threads** (invariant 4): the same window on rayon pools of 1, 2, 3 and 8 threads gives
//!   the same bits as on the default pool (backends without threads report `n/a`);
//! - **far** (invariant 2): windows at `(±10⁷, ±10⁷)` behave like windows near the origin.
//!   *No precision collapse*: rows sampled every 1/64 pixel (finer than f32's resolution at
//!   10⁷, a whole pixel) at `K` places spread over `±4096` pixels, and at the same places moved
//!   by 10⁷ into each quadrant in turn; per row, the share of bit-equal neighbours and the mean
//!   absolute step. The far rows' mean share may exceed the near rows' by at most 0.05 plus 6
//!   standard errors of the difference (positions rounded to f32 at 10⁷ make 63 neighbours in
//!   64 equal), and their mean step may be at most twice the near rows' plus 6 standard errors
//!   (a phase computed in f32 at 10⁷ turns into noise). *Same statistics*: the mean over the
//!   four far windows (one per quadrant) of each window's mean, and of its standard deviation,
//!   differs from the mean over `K` near windows spread over `±4096` pixels by at most 6
//!   standard errors of the difference (the windows' spread over the plane is the sampling
//!   error the comparison must allow). A model with a `linear` field is `n/a`: its ramps are
//!   clamped to their ends far away, so far windows see other parameters by design;
//! - **reseed** (`n/a` for a model without a seed): `Model::reseeded(1)` changes at least
//!   [`MIN_RESEED_CHANGE`] of the values and keeps the mean and standard deviation within
//!   `6·√2` standard deviations of the spread of `K` further reseedings (independent
//!   realisations of the same noise: the difference of two of them has `√2` times their
//!   spread).
//!
//! Each statistic is per output channel.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use spectex_model::{Model, Window};

/// A model prepared on one evaluator.
pub trait Prepared: Send + Sync {
    /// Values per pixel (interleaved).
    fn channels(&self) -> usize;

    /// Renders `window` row-major.
    ///
    /// # Errors
    /// The evaluator's error, as text.
    fn render(&self, window: &Window) -> Result<Vec<f32>, String>;

    /// Renders `window` on a pool of `threads` worker threads; `None` when the evaluator has no
    /// such notion (a GPU).
    fn render_on_threads(
        &self,
        window: &Window,
        threads: usize,
    ) -> Option<Result<Vec<f32>, String>> {
        let _ = (window, threads);
        None
    }
}

/// An evaluator the harness can drive: the CPU's ([`crate::cpu::CpuBackend`]), a GPU's (its
/// tests implement this in a few lines, so the kit does not link wgpu), or a test double.
pub trait Backend {
    /// A name for the report (`cpu`, `gpu llvmpipe`).
    fn name(&self) -> String;

    /// Prepares `model` on the plane `z`.
    ///
    /// # Errors
    /// The evaluator's error, as text.
    fn prepare(&self, model: &Model, z: f64) -> Result<Box<dyn Prepared>, String>;
}

/// One model to check.
#[derive(Debug, Clone)]
pub struct Case {
    /// Its name (the file stem of a testdata model).
    pub name: String,
    /// The model.
    pub model: Model,
    /// The plane of a 3D model (2D models ignore it).
    pub z: f64,
}

/// The plane 3D models are checked on: off the lattice planes of every octave of the shipped
/// cases (as in the cross-check suite).
pub const SLICE_Z: f64 = 37.3;

/// The `testdata/models` directory of the workspace.
#[must_use]
pub fn testdata_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models")
}

/// Every `testdata/models/*.json`, sorted by name, on the plane [`SLICE_Z`].
///
/// # Panics
/// When the directory or a file cannot be read, or a file is not a valid model (each names the
/// file).
#[must_use]
pub fn testdata_cases() -> Vec<Case> {
    let dir = testdata_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| {
            e.unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
                .path()
        })
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|file| {
            let text =
                std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            let model = spectex_model::from_json(&text)
                .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            Case {
                name: file
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                model,
                z: SLICE_Z,
            }
        })
        .collect()
}

/// A rectangle `(x, y, width, height)` of a window, in its pixels.
pub type Rect = (usize, usize, usize, usize);

/// How a window is cut into tiles.
#[derive(Debug, Clone)]
pub enum Tiling {
    /// A grid of `width × height` tiles (smaller at the right and bottom edges).
    Grid(usize, usize),
    /// 1×1 tiles over one rectangle.
    Pixels(Rect),
    /// These rectangles, each compared alone.
    Rects(Vec<Rect>),
}

/// What the harness renders; [`Plan::standard`] for the CPU, [`Plan::light`] for slower
/// evaluators.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Windows whose tilings are compared, each with its tilings.
    pub tilings: Vec<(Window, Vec<Tiling>)>,
    /// Thread counts compared with the default pool (on the first tiling window).
    pub threads: Vec<usize>,
    /// Side of the square windows of the far statistics and the reseed check.
    pub stats_side: usize,
    /// Near windows of the far statistics (`K`).
    pub near_windows: usize,
    /// Fine rows near and far (each [`FINE_WIDTH`] pixels at scale [`FINE_SCALE`]).
    pub fine_rows: usize,
    /// Further reseedings that measure the reseed check's spread (`K`).
    pub reseed_realisations: u32,
}

/// Width of a fine row of the far check, pixels.
pub const FINE_WIDTH: usize = 256;
/// Scale of the fine rows: 1/64 model pixel per pixel, finer than f32's resolution at 10⁷.
pub const FINE_SCALE: f64 = 1.0 / 64.0;
/// Least share of values `reseeded(1)` must change: independent renders of a continuous noise
/// differ almost everywhere, a binary pattern of duty `p` on `2p(1 − p)` of them (0.18 for
/// `p = 0.1`).
pub const MIN_RESEED_CHANGE: f64 = 0.1;
/// Standard deviations of the sampling spread a statistic may move (normal tails beyond 6σ:
/// 2·10⁻⁹).
pub const SPREAD_SIGMAS: f64 = 6.0;
/// Extra share of equal neighbours far fine rows may have over the near ones (beyond the
/// standard errors).
pub const TIE_MARGIN: f64 = 0.05;
/// Factor by which far fine rows' mean step may exceed the near ones' (beyond the standard
/// errors).
pub const ROUGHNESS_FACTOR: f64 = 2.0;
/// Slack of the step comparison, relative to the near rows' largest step.
pub const ROUGHNESS_SLACK: f64 = 1e-3;

/// The window of the tile and thread checks: far, at a fractional scale.
#[must_use]
pub fn tile_window() -> Window {
    Window::new(70, 37).at([1.0e7 + 0.3, -1.0e7 - 0.6], 0.83)
}

/// A minified window (scale 4, far): the filtered renders (`spectex_model::filter`) must be as
/// invisible to tiling as the point-sampled ones.
#[must_use]
pub fn minified_window() -> Window {
    Window::new(40, 24).at([1.0e7 + 0.3, -1.0e7 - 0.6], 4.0)
}

/// A window wider than the CPU's 512-column chunks (wavelet noise shares column tables per
/// chunk), far and at a fractional scale.
#[must_use]
pub fn wide_window() -> Window {
    Window::new(600, 6).at([1.0e7 - 0.3, -2.5e6], 0.37)
}

impl Plan {
    /// Every check at full size: for the CPU.
    #[must_use]
    pub fn standard() -> Self {
        Self {
            tilings: vec![
                (
                    tile_window(),
                    vec![
                        Tiling::Grid(7, 5),
                        Tiling::Grid(16, 16),
                        Tiling::Grid(70, 1),
                        Tiling::Grid(13, 37),
                        Tiling::Pixels((40, 20, 12, 8)),
                        Tiling::Rects(vec![
                            (0, 0, 13, 5),
                            (13, 5, 57, 32),
                            (3, 30, 1, 7),
                            (69, 0, 1, 1),
                        ]),
                    ],
                ),
                (
                    wide_window(),
                    vec![Tiling::Rects(vec![
                        (250, 1, 333, 4),
                        (0, 0, 600, 1),
                        (511, 2, 89, 4),
                    ])],
                ),
                (
                    minified_window(),
                    vec![
                        Tiling::Grid(7, 5),
                        Tiling::Rects(vec![(0, 0, 13, 5), (13, 5, 27, 19), (39, 0, 1, 1)]),
                    ],
                ),
            ],
            threads: vec![1, 2, 3, 8],
            stats_side: 48,
            near_windows: 16,
            fine_rows: 32,
            reseed_realisations: 12,
        }
    }

    /// Fewer and smaller renders, for evaluators where each render costs a dispatch (a GPU on a
    /// software adapter).
    #[must_use]
    pub fn light() -> Self {
        Self {
            tilings: vec![(
                tile_window(),
                vec![
                    Tiling::Grid(16, 16),
                    Tiling::Rects(vec![(0, 0, 13, 5), (13, 5, 57, 32), (69, 0, 1, 1)]),
                ],
            )],
            threads: Vec::new(),
            stats_side: 32,
            near_windows: 10,
            fine_rows: 8,
            reseed_realisations: 8,
        }
    }
}

/// The verdict of one check.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// It holds.
    Pass,
    /// It does not apply to this model or backend (why).
    NotApplicable(String),
    /// It does not hold (what differs).
    Fail(String),
}

/// One check's outcome.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// `tiles`, `threads`, `far` or `reseed`.
    pub check: &'static str,
    /// Its verdict.
    pub verdict: Verdict,
    /// Numbers behind it (tilings compared, statistics).
    pub detail: String,
}

/// Every check of one case on one backend.
#[derive(Debug, Clone)]
pub struct Report {
    /// The case.
    pub case: String,
    /// The backend.
    pub backend: String,
    /// One outcome per check.
    pub outcomes: Vec<Outcome>,
}

impl Report {
    /// Whether no check failed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.outcomes
            .iter()
            .all(|o| !matches!(o.verdict, Verdict::Fail(_)))
    }

    /// One line: `invariance: <case> on <backend>: tiles ok (…), threads ok (…), …`.
    #[must_use]
    pub fn line(&self) -> String {
        let mut s = format!("invariance: {:<28} on {}:", self.case, self.backend);
        for (i, o) in self.outcomes.iter().enumerate() {
            let sep = if i == 0 { " " } else { "; " };
            let verdict = match &o.verdict {
                Verdict::Pass => "ok".to_owned(),
                Verdict::NotApplicable(why) => format!("n/a ({why})"),
                Verdict::Fail(what) => format!("FAIL: {what}"),
            };
            let _ = write!(s, "{sep}{} {verdict}", o.check);
            if !o.detail.is_empty() {
                let _ = write!(s, " [{}]", o.detail);
            }
        }
        s
    }

    /// The verdict of check `name`.
    #[must_use]
    pub fn verdict(&self, name: &str) -> Option<&Verdict> {
        self.outcomes
            .iter()
            .find(|o| o.check == name)
            .map(|o| &o.verdict)
    }
}

/// Runs every check of `plan` on `case` with `backend`.
#[must_use]
pub fn check(case: &Case, backend: &dyn Backend, plan: &Plan) -> Report {
    let mut report = Report {
        case: case.name.clone(),
        backend: backend.name(),
        outcomes: Vec::new(),
    };
    let prepared = match backend.prepare(&case.model, case.z) {
        Ok(p) => p,
        Err(e) => {
            for name in ["tiles", "threads", "far", "reseed"] {
                report.outcomes.push(Outcome {
                    check: name,
                    verdict: Verdict::Fail(format!("the model could not be prepared: {e}")),
                    detail: String::new(),
                });
            }
            return report;
        }
    };
    let p = prepared.as_ref();
    report.outcomes.push(tiles(p, plan));
    report.outcomes.push(threads(p, plan));
    report.outcomes.push(far(p, &case.model, plan));
    report.outcomes.push(reseed(p, case, backend, plan));
    report
}

/// Runs `f`, turning an error into a failed outcome of `check`.
fn outcome(check: &'static str, f: impl FnOnce() -> Result<(Verdict, String), String>) -> Outcome {
    match f() {
        Ok((verdict, detail)) => Outcome {
            check,
            verdict,
            detail,
        },
        Err(e) => Outcome {
            check,
            verdict: Verdict::Fail(e),
            detail: String::new(),
        },
    }
}

/// The rectangles of a tiling of a `width × height` window.
fn rects(tiling: &Tiling, width: usize, height: usize) -> Vec<Rect> {
    match tiling {
        Tiling::Grid(tw, th) => {
            let mut out = Vec::new();
            for y in (0..height).step_by(*th) {
                for x in (0..width).step_by(*tw) {
                    out.push((x, y, (*tw).min(width - x), (*th).min(height - y)));
                }
            }
            out
        }
        Tiling::Pixels((x0, y0, w, h)) => (*y0..y0 + h)
            .flat_map(|y| (*x0..x0 + w).map(move |x| (x, y, 1, 1)))
            .collect(),
        Tiling::Rects(list) => list.clone(),
    }
}

/// The first index where `a` and `b` differ bit for bit (lengths included).
fn first_difference(a: &[f32], b: &[f32]) -> Option<usize> {
    if a.len() != b.len() {
        return Some(a.len().min(b.len()));
    }
    a.iter()
        .zip(b)
        .position(|(x, y)| x.to_bits() != y.to_bits())
}

fn tiles(p: &dyn Prepared, plan: &Plan) -> Outcome {
    outcome("tiles", || {
        let nc = p.channels();
        let mut compared = 0usize;
        for (window, tilings) in &plan.tilings {
            let whole = p.render(window)?;
            for tiling in tilings {
                for (x, y, w, h) in rects(tiling, window.width, window.height) {
                    let tile = p.render(&window.tile(x, y, w, h))?;
                    compared += 1;
                    for r in 0..h {
                        let start = ((y + r) * window.width + x) * nc;
                        let expected = &whole[start..start + w * nc];
                        let got = tile.get(r * w * nc..(r + 1) * w * nc).unwrap_or(&[]);
                        if let Some(i) = first_difference(got, expected) {
                            let (px, c) = (i / nc, i % nc);
                            return Ok((
                                Verdict::Fail(format!(
                                    "{tiling:?} of the {}×{} window at {:?}: tile ({x}, {y}, \
                                     {w}×{h}) pixel ({}, {}) channel {c}: {:?} whole vs {:?} tiled",
                                    window.width,
                                    window.height,
                                    window.offset,
                                    x + px,
                                    y + r,
                                    expected.get(i),
                                    got.get(i)
                                )),
                                String::new(),
                            ));
                        }
                    }
                }
            }
        }
        Ok((Verdict::Pass, format!("{compared} tiles")))
    })
}

fn threads(p: &dyn Prepared, plan: &Plan) -> Outcome {
    outcome("threads", || {
        let Some((window, _)) = plan.tilings.first() else {
            return Ok((Verdict::NotApplicable("no window".into()), String::new()));
        };
        if plan.threads.is_empty() {
            return Ok((
                Verdict::NotApplicable("not in this plan".into()),
                String::new(),
            ));
        }
        let whole = p.render(window)?;
        for &threads in &plan.threads {
            let Some(again) = p.render_on_threads(window, threads) else {
                return Ok((
                    Verdict::NotApplicable("the backend has no threads".into()),
                    String::new(),
                ));
            };
            if let Some(i) = first_difference(&again?, &whole) {
                return Ok((
                    Verdict::Fail(format!(
                        "{threads} thread(s) differ from the default pool at value {i}"
                    )),
                    String::new(),
                ));
            }
        }
        Ok((Verdict::Pass, format!("{:?} threads", plan.threads)))
    })
}

/// Mean and standard deviation of each channel of interleaved `values`.
fn moments(values: &[f32], nc: usize) -> Vec<(f64, f64)> {
    (0..nc)
        .map(|c| {
            let v: Vec<f64> = values
                .iter()
                .skip(c)
                .step_by(nc)
                .map(|&x| f64::from(x))
                .collect();
            let n = v.len().max(1) as f64;
            let mean = v.iter().sum::<f64>() / n;
            let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
            (mean, var.sqrt())
        })
        .collect()
}

/// Mean and (sample) standard deviation of a list.
fn spread(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// Near-window offsets: spread over `±4096` pixels by a fixed sequence (far enough apart to be
/// nearly independent samples of every shipped model, near enough for f32 positions to keep
/// 2⁻¹¹ pixel).
fn near_offsets(count: usize) -> Vec<[f64; 2]> {
    (0..count)
        .map(|k| {
            let h = spectex_model::random::cell_hash(k as i32, 0, 0x4E45_4152, 7);
            let g = spectex_model::random::cell_hash(k as i32, 1, 0x4E45_4152, 7);
            let to = |b: u32| (f64::from(b) / f64::from(u32::MAX) - 0.5) * 8192.0;
            [to(h).round() + 0.3, to(g).round() - 0.45]
        })
        .collect()
}

/// The four far offsets, one per quadrant, a fraction of a pixel off the integers.
fn far_offsets() -> [[f64; 2]; 4] {
    [
        [1.0e7 + 0.3, 1.0e7 - 0.45],
        [-1.0e7 + 0.3, 1.0e7 + 0.55],
        [1.0e7 - 0.7, -1.0e7 - 0.45],
        [-1.0e7 - 0.7, -1.0e7 + 0.55],
    ]
}

/// Per fine row and channel: the share of bit-equal horizontal neighbours and the mean
/// absolute step (interleaved channels, `width` pixels per row).
fn fine_row_statistics(row: &[f32], width: usize, nc: usize) -> Vec<(f64, f64)> {
    (0..nc)
        .map(|c| {
            let v: Vec<f32> = row.iter().skip(c).step_by(nc).copied().collect();
            let pairs = width.min(v.len()).saturating_sub(1).max(1) as f64;
            let (mut ties, mut step) = (0usize, 0.0f64);
            for i in 1..width.min(v.len()) {
                ties += usize::from(v[i].to_bits() == v[i - 1].to_bits());
                step += (f64::from(v[i]) - f64::from(v[i - 1])).abs();
            }
            (ties as f64 / pairs, step / pairs)
        })
        .collect()
}

/// Whether the far sample `far` exceeds the near sample `near` by more than `factor` times its
/// mean plus `margin` plus [`SPREAD_SIGMAS`] standard errors of the difference; with the two
/// means.
fn exceeds(near: &[f64], far: &[f64], factor: f64, margin: f64) -> (bool, f64, f64) {
    let (mn, sn) = spread(near);
    let (mf, sf) = spread(far);
    let se = (sn * sn / near.len() as f64 + sf * sf / far.len() as f64).sqrt();
    (mf > factor * mn + margin + SPREAD_SIGMAS * se, mf, mn)
}

/// Whether a model's statistics depend on the position by design: it holds a `linear` field (a
/// ramp, clamped to its range beyond `RAMP_EXTENT`, so far windows see its clamped end).
#[must_use]
pub fn is_position_graded(model: &Model) -> bool {
    fn has_linear(v: &serde_json::Value) -> bool {
        match v {
            serde_json::Value::Object(map) => map
                .iter()
                .any(|(k, v)| (k == "linear" && v.get("gradient").is_some()) || has_linear(v)),
            serde_json::Value::Array(items) => items.iter().any(has_linear),
            _ => false,
        }
    }
    serde_json::to_value(model).is_ok_and(|v| has_linear(&v))
}

fn far(p: &dyn Prepared, model: &Model, plan: &Plan) -> Outcome {
    outcome("far", || {
        if is_position_graded(model) {
            return Ok((
                Verdict::NotApplicable(
                    "position-graded: a linear field is clamped to its range's end far away, so \
                     far windows see other parameters"
                        .into(),
                ),
                String::new(),
            ));
        }
        let nc = p.channels();
        // No precision collapse: fine rows spread over the plane near the origin, and the same
        // rows moved by 10⁷ into each quadrant in turn.
        let rows = near_offsets(plan.fine_rows);
        let quadrants = far_offsets();
        let mut near_rows = Vec::new();
        let mut far_rows = Vec::new();
        for (k, o) in rows.iter().enumerate() {
            let q = quadrants[k % quadrants.len()];
            let fine = |at: [f64; 2]| p.render(&Window::new(FINE_WIDTH, 1).at(at, FINE_SCALE));
            near_rows.push(fine_row_statistics(&fine(*o)?, FINE_WIDTH, nc));
            far_rows.push(fine_row_statistics(
                &fine([q[0] + o[0], q[1] + o[1]])?,
                FINE_WIDTH,
                nc,
            ));
        }
        let mut detail = String::new();
        for c in 0..nc {
            let column = |rows: &[Vec<(f64, f64)>], pick: fn(&(f64, f64)) -> f64| {
                rows.iter().map(|r| pick(&r[c])).collect::<Vec<f64>>()
            };
            let (tied, tf, tn) = exceeds(
                &column(&near_rows, |s| s.0),
                &column(&far_rows, |s| s.0),
                1.0,
                TIE_MARGIN,
            );
            let (rough, rf, rn) = exceeds(
                &column(&near_rows, |s| s.1),
                &column(&far_rows, |s| s.1),
                ROUGHNESS_FACTOR,
                ROUGHNESS_SLACK * rn_scale(&near_rows, c),
            );
            let _ = write!(
                detail,
                "{}ties {tf:.3}/{tn:.3}, step {rf:.2e}/{rn:.2e}",
                if c == 0 { "" } else { ", " }
            );
            if tied {
                return Ok((
                    Verdict::Fail(format!(
                        "channel {c}: {:.1}% of far neighbours 1/64 px apart are equal vs \
                         {:.1}% near (positions quantised?)",
                        100.0 * tf,
                        100.0 * tn
                    )),
                    detail,
                ));
            }
            if rough {
                return Ok((
                    Verdict::Fail(format!(
                        "channel {c}: far rows are rougher: mean step {rf:.3e} vs {rn:.3e} near \
                         (phases lost precision?)"
                    )),
                    detail,
                ));
            }
        }
        // Same statistics: the far windows' mean and standard deviation against the near
        // windows', two samples of one distribution if positions keep their precision.
        let side = plan.stats_side;
        let stats = |o: [f64; 2]| -> Result<Vec<(f64, f64)>, String> {
            Ok(moments(&p.render(&Window::new(side, side).at(o, 1.0))?, nc))
        };
        let near: Vec<Vec<(f64, f64)>> = near_offsets(plan.near_windows)
            .into_iter()
            .map(stats)
            .collect::<Result<_, _>>()?;
        let far: Vec<Vec<(f64, f64)>> = far_offsets()
            .into_iter()
            .map(stats)
            .collect::<Result<_, _>>()?;
        for c in 0..nc {
            for (name, moment) in [("mean", 0), ("standard deviation", 1)] {
                let pick = |s: &Vec<(f64, f64)>| if moment == 0 { s[c].0 } else { s[c].1 };
                let n: Vec<f64> = near.iter().map(pick).collect();
                let f: Vec<f64> = far.iter().map(pick).collect();
                let (mn, sn) = spread(&n);
                let (mf, sf) = spread(&f);
                let se = (sn * sn / n.len() as f64 + sf * sf / f.len() as f64).sqrt();
                let slack = 1e-6 * mn.abs().max(mf.abs()) + 1e-12;
                if (mf - mn).abs() > SPREAD_SIGMAS * se + slack {
                    return Ok((
                        Verdict::Fail(format!(
                            "channel {c}: far windows' {name} {mf:.5} vs {mn:.5} near \
                             (standard error of the difference {se:.2e})"
                        )),
                        detail,
                    ));
                }
            }
        }
        let _ = write!(
            detail,
            "; {} far and {} near windows agree",
            far.len(),
            near.len()
        );
        Ok((Verdict::Pass, detail))
    })
}

/// The scale of channel `c`'s values on the near fine rows (their largest mean step, at least
/// 10⁻³⁰), so that the roughness slack is relative.
fn rn_scale(rows: &[Vec<(f64, f64)>], c: usize) -> f64 {
    rows.iter().map(|r| r[c].1).fold(1e-30, f64::max)
}

fn reseed(p: &dyn Prepared, case: &Case, backend: &dyn Backend, plan: &Plan) -> Outcome {
    outcome("reseed", || {
        // A kind without a seed (a matrix transformation) is one deterministic texture.
        if case.model.reseeded(1) == case.model {
            return Ok((
                Verdict::NotApplicable("the model has no seed".into()),
                String::new(),
            ));
        }
        let nc = p.channels();
        let side = plan.stats_side;
        let window = Window::new(side, side).at([-150.5, 80.25], 1.0);
        let render = |delta: u32| -> Result<Vec<f32>, String> {
            if delta == 0 {
                return p.render(&window);
            }
            backend
                .prepare(&case.model.reseeded(delta), case.z)?
                .render(&window)
        };
        let original = render(0)?;
        let changed = render(1)?;
        let differing = original
            .iter()
            .zip(&changed)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count() as f64
            / original.len().max(1) as f64;
        let mut detail = format!("{:.0}% changed", 100.0 * differing);
        if differing < MIN_RESEED_CHANGE {
            return Ok((
                Verdict::Fail(format!(
                    "reseeded(1) changes only {:.1}% of the values",
                    100.0 * differing
                )),
                detail,
            ));
        }
        let others: Vec<Vec<(f64, f64)>> = (2..2 + plan.reseed_realisations)
            .map(|d| render(d).map(|v| moments(&v, nc)))
            .collect::<Result<_, _>>()?;
        let (a, b) = (moments(&original, nc), moments(&changed, nc));
        let allowance = SPREAD_SIGMAS * std::f64::consts::SQRT_2;
        for c in 0..nc {
            let (_, mean_spread) = spread(&others.iter().map(|s| s[c].0).collect::<Vec<_>>());
            let (sd_n, sd_spread) = spread(&others.iter().map(|s| s[c].1).collect::<Vec<_>>());
            let slack = 1e-6 * (a[c].0.abs() + sd_n) + 1e-12;
            let _ = write!(
                detail,
                ", mean {:.4}→{:.4} (spread {mean_spread:.1e}), sd {:.4}→{:.4} (spread \
                 {sd_spread:.1e})",
                a[c].0, b[c].0, a[c].1, b[c].1
            );
            if (a[c].0 - b[c].0).abs() > allowance * mean_spread + slack {
                return Ok((
                    Verdict::Fail(format!("channel {c}: reseeding moved the mean")),
                    detail,
                ));
            }
            if (a[c].1 - b[c].1).abs() > allowance * sd_spread + slack {
                return Ok((
                    Verdict::Fail(format!(
                        "channel {c}: reseeding moved the standard deviation"
                    )),
                    detail,
                ));
            }
        }
        Ok((Verdict::Pass, detail))
    })
}
