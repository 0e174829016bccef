//! The invariance harness over every model in `testdata/models/` on the CPU (one line per
//! model), and proofs that each check fails on an evaluator that breaks its invariant.

use spectex_model::{Model, Window};
use spectex_testkit::cpu::CpuBackend;
use spectex_testkit::invariance::{
    Backend, Case, Plan, Prepared, Verdict, check, is_position_graded, testdata_cases,
};

#[test]
fn every_testdata_model_passes_every_invariance_check_on_the_cpu() {
    let cases = testdata_cases();
    assert!(cases.len() >= 20, "testdata/models holds the shipped cases");
    let plan = Plan::standard();
    let mut failed = Vec::new();
    for case in &cases {
        let report = check(case, &CpuBackend, &plan);
        println!("{}", report.line());
        if !report.passed() {
            failed.push(report.line());
        }
        // Every check runs on the CPU, but the far check on position-graded models and the
        // reseed check on models without a seed: nothing is skipped silently.
        let seedless = case.model.reseeded(1) == case.model;
        for name in ["tiles", "threads", "far", "reseed"] {
            let skipped = matches!(report.verdict(name), Some(Verdict::NotApplicable(_)) | None);
            assert!(
                !skipped
                    || (name == "far" && is_position_graded(&case.model))
                    || (name == "reseed" && seedless),
                "{}: {name} did not run",
                case.name
            );
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

/// A CPU backend whose renders are broken in one way.
struct Broken(Breakage);

#[derive(Clone, Copy)]
enum Breakage {
    /// Adds the window's first column to every value (tiles differ).
    TileDependent,
    /// Adds 1 on pools of one thread.
    ThreadDependent,
    /// Rounds positions to f32 before rendering each pixel (precision collapses at 10⁷).
    F32Positions,
}

struct BrokenPrepared {
    inner: Box<dyn Prepared>,
    breakage: Breakage,
}

impl Prepared for BrokenPrepared {
    fn channels(&self) -> usize {
        self.inner.channels()
    }

    fn render(&self, window: &Window) -> Result<Vec<f32>, String> {
        match self.breakage {
            Breakage::TileDependent => Ok(self
                .inner
                .render(window)?
                .into_iter()
                .map(|v| v + window.x0 as f32)
                .collect()),
            Breakage::F32Positions => {
                let mut out = Vec::new();
                for j in 0..window.height {
                    for i in 0..window.width {
                        let p = [window.x(i) as f32 as f64, window.y(j) as f32 as f64];
                        out.extend(self.inner.render(&Window::new(1, 1).at(p, 1.0))?);
                    }
                }
                Ok(out)
            }
            Breakage::ThreadDependent => self.inner.render(window),
        }
    }

    fn render_on_threads(
        &self,
        window: &Window,
        threads: usize,
    ) -> Option<Result<Vec<f32>, String>> {
        let rendered = self.inner.render_on_threads(window, threads)?;
        Some(match self.breakage {
            Breakage::ThreadDependent if threads == 1 => {
                rendered.map(|v| v.into_iter().map(|x| x + 1.0).collect())
            }
            _ => rendered,
        })
    }
}

impl Backend for Broken {
    fn name(&self) -> String {
        "broken cpu".into()
    }

    fn prepare(&self, model: &Model, z: f64) -> Result<Box<dyn Prepared>, String> {
        let inner = CpuBackend.prepare(model, z)?;
        Ok(Box::new(BrokenPrepared {
            inner,
            breakage: self.0,
        }))
    }
}

/// A seed-blind backend: every reseeding renders the original seed's model.
struct SeedBlind(Model);

impl Backend for SeedBlind {
    fn name(&self) -> String {
        "seed-blind cpu".into()
    }

    fn prepare(&self, _model: &Model, z: f64) -> Result<Box<dyn Prepared>, String> {
        CpuBackend.prepare(&self.0, z)
    }
}

fn case(name: &str) -> Case {
    testdata_cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("testdata/models/{name}.json"))
}

fn assert_fails(report: &spectex_testkit::invariance::Report, check: &str) {
    assert!(
        matches!(report.verdict(check), Some(Verdict::Fail(_))),
        "{check} should fail: {}",
        report.line()
    );
}

#[test]
fn each_check_fails_on_an_evaluator_that_breaks_its_invariant() {
    let plan = Plan::light();
    let mut plan_threads = Plan::light();
    plan_threads.threads = vec![1, 4];
    let gabor = case("gabor-isotropic");

    let report = check(&gabor, &Broken(Breakage::TileDependent), &plan);
    assert_fails(&report, "tiles");

    let report = check(&gabor, &Broken(Breakage::ThreadDependent), &plan_threads);
    assert_fails(&report, "threads");
    assert_eq!(
        report.verdict("tiles"),
        Some(&Verdict::Pass),
        "{}",
        report.line()
    );

    for name in ["lrp-ring", "classic-perlin-fbm"] {
        let report = check(&case(name), &Broken(Breakage::F32Positions), &plan);
        assert_fails(&report, "far");
    }

    let report = check(&gabor, &SeedBlind(gabor.model.clone()), &plan);
    assert_fails(&report, "reseed");
}

/// Far statistics fail when the far windows render another model: the mean moves by more than
/// the near windows' spread.
#[test]
fn far_statistics_fail_when_far_windows_differ() {
    struct Shifted;
    struct ShiftedPrepared(Box<dyn Prepared>);
    impl Prepared for ShiftedPrepared {
        fn channels(&self) -> usize {
            self.0.channels()
        }
        fn render(&self, window: &Window) -> Result<Vec<f32>, String> {
            let values = self.0.render(window)?;
            // Far away, half a standard deviation higher (about 0.05 for this model).
            let far = window.offset[0].abs() > 1e6;
            Ok(values
                .into_iter()
                .map(|v| if far { v + 0.05 } else { v })
                .collect())
        }
    }
    impl Backend for Shifted {
        fn name(&self) -> String {
            "shifted far".into()
        }
        fn prepare(&self, model: &Model, z: f64) -> Result<Box<dyn Prepared>, String> {
            Ok(Box::new(ShiftedPrepared(CpuBackend.prepare(model, z)?)))
        }
    }
    let report = check(&case("gabor-isotropic"), &Shifted, &Plan::light());
    assert_fails(&report, "far");
}
