//! The short fixed-seed campaign of generated models of every kind through JSON, validation and
//! the CPU evaluator (`cargo xtask fuzz --cases N` runs a long one).

use spectex_testkit::cases::{describe, model_cases};
use spectex_testkit::cpu::model_target;
use spectex_testkit::fuzz::{Settings, run};

/// Cases of the campaign CI runs: a few seconds on two cores.
const CI_CASES: u32 = 600;

#[test]
fn generated_models_never_panic_hang_or_break_a_property() {
    let settings = Settings::from_env(CI_CASES);
    let report = run(
        "models-cpu",
        &settings,
        &model_cases(),
        describe,
        &model_target(),
    );
    println!("{}", report.summary());
    assert!(report.findings.is_empty(), "{}", report.summary());
    assert!(
        report.accepted_total() >= report.cases / 4,
        "too few valid models to exercise evaluation: {}",
        report.summary()
    );
}
