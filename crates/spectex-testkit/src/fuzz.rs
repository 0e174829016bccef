//! The fuzzing campaign runner: draws cases from a proptest strategy with a fixed seed, runs
//! each through a target on a worker thread under a watchdog, and collects findings — panics,
//! hangs and violated properties — with the shrunk input of each, instead of stopping at the
//! first. Targets say what they saw ([`Observation`]): whether validation accepted the input,
//! and how long a render took per pixel.
//!
//! The number of cases and the seed come from [`CASES_ENV`] and [`SEED_ENV`] when set, so a
//! test runs a short campaign by default and `cargo xtask fuzz --cases N` a long one.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// Environment variable giving the number of cases of every campaign (`cargo xtask fuzz` sets
/// it).
pub const CASES_ENV: &str = "SPECTEX_FUZZ_CASES";
/// Environment variable giving the campaigns' seed (a `u64`; each campaign mixes in its name).
pub const SEED_ENV: &str = "SPECTEX_FUZZ_SEED";
/// The seed when [`SEED_ENV`] is not set: CI runs the same cases every time.
pub const DEFAULT_SEED: u64 = 0x5EC7_E8F0_2200_0014;

/// How long one case may run before it counts as a hang. Far beyond any case's work (the
/// slowest accepted cases take a fraction of a second), so only a loop that does not end, or
/// work out of all proportion to the input, reaches it.
pub const CASE_TIMEOUT: Duration = Duration::from_secs(120);

/// Most shrinking steps spent on one finding.
pub const MAX_SHRINK_STEPS: u32 = 512;

/// How a campaign runs.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Cases drawn.
    pub cases: u32,
    /// Seed of the case generator.
    pub seed: u64,
    /// Watchdog limit of one case.
    pub case_timeout: Duration,
}

impl Settings {
    /// `cases` cases from [`DEFAULT_SEED`], with the [`CASE_TIMEOUT`] watchdog.
    #[must_use]
    pub fn new(cases: u32) -> Self {
        Self {
            cases,
            seed: DEFAULT_SEED,
            case_timeout: CASE_TIMEOUT,
        }
    }

    /// [`Settings::new`] with `default_cases`, overridden by [`CASES_ENV`] and [`SEED_ENV`].
    ///
    /// # Panics
    /// When one of them is set but is not a number, naming it.
    #[must_use]
    pub fn from_env(default_cases: u32) -> Self {
        let mut settings = Self::new(default_cases);
        if let Ok(v) = std::env::var(CASES_ENV) {
            settings.cases = v.trim().parse().unwrap_or_else(|_| {
                panic!("{CASES_ENV}={v:?} is not a case count (0 to 2^32 − 1)")
            });
        }
        if let Ok(v) = std::env::var(SEED_ENV) {
            settings.seed = v
                .trim()
                .parse()
                .unwrap_or_else(|_| panic!("{SEED_ENV}={v:?} is not a seed (0 to 2^64 − 1)"));
        }
        settings
    }
}

/// What a target saw in one case that passed.
#[derive(Debug, Clone, Default)]
pub struct Observation {
    /// The model kind, when the input got as far as naming one.
    pub kind: Option<&'static str>,
    /// Whether validation accepted the input.
    pub accepted: bool,
    /// Pixels rendered (0 when nothing was).
    pub pixels: usize,
    /// Seconds the render took.
    pub render_seconds: f64,
    /// Seconds building the evaluator took.
    pub build_seconds: f64,
    /// The evaluator's cost per pixel (its own units: cosines, kernels, lattice evaluations).
    pub cost_per_pixel: f64,
}

/// What went wrong in a case.
#[derive(Debug, Clone, PartialEq)]
pub enum Failure {
    /// The target panicked (or aborted the case's thread), with the message.
    Panic(String),
    /// The case ran past the watchdog limit.
    Hang(Duration),
    /// A property did not hold, with the target's explanation.
    Property(String),
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Panic(message) => write!(f, "panic: {message}"),
            Self::Hang(limit) => write!(f, "hang: no result after {} s", limit.as_secs()),
            Self::Property(message) => write!(f, "property: {message}"),
        }
    }
}

/// One failing case.
#[derive(Debug, Clone)]
pub struct Finding {
    /// Index of the case in the campaign.
    pub case: u32,
    /// What went wrong with the original input.
    pub failure: Failure,
    /// The original input, described.
    pub input: String,
    /// The smallest failing input shrinking found, and its failure (absent for hangs, which
    /// are not shrunk).
    pub shrunk: Option<(String, Failure)>,
}

/// The slowest render seen, per pixel.
#[derive(Debug, Clone)]
pub struct Worst {
    /// Nanoseconds per pixel.
    pub ns_per_pixel: f64,
    /// The case's kind.
    pub kind: Option<&'static str>,
    /// Its cost per pixel.
    pub cost_per_pixel: f64,
    /// Its index.
    pub case: u32,
}

/// The outcome of a campaign.
#[derive(Debug, Clone)]
pub struct Report {
    /// The campaign's name.
    pub name: String,
    /// Cases run.
    pub cases: u32,
    /// Cases whose input validation accepted, by kind (`"?"` when no kind was named).
    pub accepted: BTreeMap<&'static str, u32>,
    /// Cases whose input validation rejected, by kind.
    pub rejected: BTreeMap<&'static str, u32>,
    /// Every failing case.
    pub findings: Vec<Finding>,
    /// The slowest render per pixel.
    pub worst_render: Option<Worst>,
    /// The slowest evaluator build, seconds, and its case.
    pub worst_build: Option<(f64, u32)>,
    /// The slowest case as a whole (generation excluded), seconds, its index and input.
    pub slowest_case: Option<(f64, u32, String)>,
    /// Wall time of the campaign, seconds.
    pub seconds: f64,
}

impl Report {
    /// A few lines: cases, accepted and rejected per kind, worst times, findings.
    #[must_use]
    pub fn summary(&self) -> String {
        let total = |m: &BTreeMap<&str, u32>| m.values().sum::<u32>();
        let mut s = format!(
            "fuzz {}: {} cases in {:.1} s, {} accepted, {} rejected, {} finding(s)",
            self.name,
            self.cases,
            self.seconds,
            total(&self.accepted),
            total(&self.rejected),
            self.findings.len()
        );
        let kinds: std::collections::BTreeSet<&str> = self
            .accepted
            .keys()
            .chain(self.rejected.keys())
            .copied()
            .collect();
        for kind in kinds {
            let _ = write!(
                s,
                "\n  {kind:<8} accepted {:>6}, rejected {:>6}",
                self.accepted.get(kind).copied().unwrap_or(0),
                self.rejected.get(kind).copied().unwrap_or(0)
            );
        }
        if let Some(w) = &self.worst_render {
            let _ = write!(
                s,
                "\n  slowest render: {:.1} µs per pixel ({}, cost {:.0} per pixel, case {})",
                w.ns_per_pixel / 1e3,
                w.kind.unwrap_or("?"),
                w.cost_per_pixel,
                w.case
            );
        }
        if let Some((seconds, case)) = self.worst_build {
            let _ = write!(
                s,
                "\n  slowest evaluator build: {:.1} ms (case {case})",
                seconds * 1e3
            );
        }
        if let Some((seconds, case, input)) = &self.slowest_case {
            let _ = write!(
                s,
                "\n  slowest case: {seconds:.2} s (case {case}): {}",
                crate::cases::shorten(input, 300)
            );
        }
        for f in &self.findings {
            let _ = write!(
                s,
                "\n  FINDING case {}: {}\n    input: {}",
                f.case, f.failure, f.input
            );
            if let Some((input, failure)) = &f.shrunk {
                let _ = write!(s, "\n    shrunk: {failure}\n    shrunk input: {input}");
            }
        }
        s
    }

    /// Cases accepted, over all kinds.
    #[must_use]
    pub fn accepted_total(&self) -> u32 {
        self.accepted.values().sum()
    }
}

/// A target: runs one input, returns what it saw or the property it found broken. It may
/// panic; the runner catches that.
pub type Target<T> = Arc<dyn Fn(&T) -> Result<Observation, String> + Send + Sync>;

/// Runs `settings.cases` cases drawn from `strategy` through `target`; `describe` turns an
/// input into the text a finding shows.
///
/// # Panics
/// When the strategy cannot produce a value (it rejects every draw).
pub fn run<S>(
    name: &str,
    settings: &Settings,
    strategy: &S,
    describe: fn(&S::Value) -> String,
    target: &Target<S::Value>,
) -> Report
where
    S: Strategy,
    S::Value: Send + 'static,
{
    let started = Instant::now();
    let mut runner = TestRunner::new_with_rng(
        Config {
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes(settings.seed, name)),
    );
    let mut report = Report {
        name: name.to_owned(),
        cases: 0,
        accepted: BTreeMap::new(),
        rejected: BTreeMap::new(),
        findings: Vec::new(),
        worst_render: None,
        worst_build: None,
        slowest_case: None,
        seconds: 0.0,
    };
    for case in 0..settings.cases {
        let mut tree = strategy
            .new_tree(&mut runner)
            .unwrap_or_else(|e| panic!("fuzz {name}: the strategy produced no case: {e}"));
        let input = tree.current();
        let description = describe(&input);
        report.cases += 1;
        let case_started = Instant::now();
        let result = execute(target, input, settings.case_timeout);
        let case_seconds = case_started.elapsed().as_secs_f64();
        if report
            .slowest_case
            .as_ref()
            .is_none_or(|(s, _, _)| case_seconds > *s)
        {
            report.slowest_case = Some((case_seconds, case, description.clone()));
        }
        match result {
            Ok(observation) => record(&mut report, case, &observation),
            Err(failure @ Failure::Hang(_)) => {
                // The hung thread cannot be stopped; running on beside it would only slow
                // every later case.
                report.findings.push(Finding {
                    case,
                    failure,
                    input: description,
                    shrunk: None,
                });
                break;
            }
            Err(failure) => {
                let shrunk = shrink(&mut tree, &failure, describe, target, settings.case_timeout);
                report.findings.push(Finding {
                    case,
                    failure,
                    input: description,
                    shrunk,
                });
            }
        }
    }
    report.seconds = started.elapsed().as_secs_f64();
    report
}

/// The generator seed for a campaign: `seed` mixed with the campaign's name, so two campaigns
/// with one seed draw different cases.
pub fn seed_bytes(seed: u64, name: &str) -> [u8; 32] {
    let mut h = seed ^ 0x9E37_79B9_7F4A_7C15;
    for b in name.bytes() {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3);
    }
    let mut bytes = [0u8; 32];
    for (i, chunk) in bytes.chunks_mut(8).enumerate() {
        let v = h.rotate_left(17 * i as u32).wrapping_add(i as u64);
        chunk.copy_from_slice(&v.to_le_bytes());
    }
    bytes
}

fn record(report: &mut Report, case: u32, o: &Observation) {
    let kind = o.kind.unwrap_or("?");
    let counts = if o.accepted {
        &mut report.accepted
    } else {
        &mut report.rejected
    };
    *counts.entry(kind).or_insert(0) += 1;
    if o.pixels > 0 {
        let ns_per_pixel = o.render_seconds * 1e9 / o.pixels as f64;
        if report
            .worst_render
            .as_ref()
            .is_none_or(|w| ns_per_pixel > w.ns_per_pixel)
        {
            report.worst_render = Some(Worst {
                ns_per_pixel,
                kind: o.kind,
                cost_per_pixel: o.cost_per_pixel,
                case,
            });
        }
    }
    if o.build_seconds > 0.0 && report.worst_build.is_none_or(|(s, _)| o.build_seconds > s) {
        report.worst_build = Some((o.build_seconds, case));
    }
}

/// Runs `target` on `input` on its own thread, catching panics, waiting at most `timeout`.
///
/// # Errors
/// The failure: a panic, a hang or a broken property.
pub fn execute<T: Send + 'static>(
    target: &Target<T>,
    input: T,
    timeout: Duration,
) -> Result<Observation, Failure> {
    let (send, receive) = mpsc::channel();
    let target = Arc::clone(target);
    let spawned = std::thread::Builder::new()
        .name("fuzz-case".into())
        // Deserialising and validating nested models recurses; give it room.
        .stack_size(64 << 20)
        .spawn(move || {
            let result = catch_unwind(AssertUnwindSafe(|| target(&input)));
            // The receiver is gone only after a timeout; nothing is left to tell then.
            let _ = send.send(result);
        });
    if let Err(e) = spawned {
        return Err(Failure::Panic(format!(
            "could not start the case's thread: {e}"
        )));
    }
    match receive.recv_timeout(timeout) {
        Ok(Ok(Ok(observation))) => Ok(observation),
        Ok(Ok(Err(property))) => Err(Failure::Property(property)),
        Ok(Err(payload)) => Err(Failure::Panic(panic_message(payload.as_ref()))),
        Err(mpsc::RecvTimeoutError::Timeout) => Err(Failure::Hang(timeout)),
        Err(mpsc::RecvTimeoutError::Disconnected) => Err(Failure::Panic(
            "the case's thread ended without a result".into(),
        )),
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a message)".into())
}

/// Shrinks a failing case with proptest's value tree: simplify while it still fails the same
/// way (a panic, or a broken property), complicate when a simplification does not.
fn shrink<V: ValueTree>(
    tree: &mut V,
    original: &Failure,
    describe: fn(&V::Value) -> String,
    target: &Target<V::Value>,
    timeout: Duration,
) -> Option<(String, Failure)>
where
    V::Value: Send + 'static,
{
    let mut smallest = None;
    if !tree.simplify() {
        return None;
    }
    for _ in 0..MAX_SHRINK_STEPS {
        let candidate = tree.current();
        let description = describe(&candidate);
        match execute(target, candidate, timeout) {
            Err(Failure::Hang(_)) => break,
            Err(failure)
                if std::mem::discriminant(&failure) == std::mem::discriminant(original) =>
            {
                smallest = Some((description, failure));
                if !tree.simplify() {
                    break;
                }
            }
            _ => {
                if !tree.complicate() {
                    break;
                }
            }
        }
    }
    smallest
}
