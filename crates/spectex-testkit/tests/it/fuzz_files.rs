//! Mutated texts of every shipped model file (fields deleted, types changed, numbers pushed
//! past their ranges, lists emptied or repeated, bytes cut or changed) through `from_json` and
//! the CPU evaluator.

use proptest::prelude::*;
use spectex_testkit::cases::shorten;
use spectex_testkit::cpu::text_target;
use std::sync::Arc;

use spectex_testkit::fuzz::{Settings, Target, run};
use spectex_testkit::invariance::testdata_dir;
use spectex_testkit::mutate::{Subject, apply, mutation};

/// Cases CI runs.
const CI_CASES: u32 = 400;

fn subjects() -> Vec<Subject> {
    let mut files: Vec<_> = std::fs::read_dir(testdata_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            Subject::new(
                &p.file_stem().unwrap().to_string_lossy(),
                &std::fs::read_to_string(p).unwrap(),
            )
        })
        .collect()
}

#[test]
fn mutated_model_files_never_panic_hang_or_break_a_property() {
    let subjects = subjects();
    assert!(
        subjects.len() >= 20,
        "testdata/models holds the shipped cases"
    );
    let texts = (proptest::sample::select(subjects), mutation()).prop_map(|(s, m)| {
        let (text, what) = apply(&s, &m);
        (format!("{}: {what}", s.name), text)
    });
    let text = text_target();
    let target: Target<(String, String)> = Arc::new(move |(_, t): &(String, String)| text(t));
    let report = run(
        "files-cpu",
        &Settings::from_env(CI_CASES),
        &texts,
        |(what, text): &(String, String)| format!("{what}\n      text: {}", shorten(text, 600)),
        &target,
    );
    println!("{}", report.summary());
    assert!(report.findings.is_empty(), "{}", report.summary());
    assert!(
        report.accepted_total() > 0 && report.rejected.values().sum::<u32>() > 0,
        "mutations should give both accepted and refused files: {}",
        report.summary()
    );
}
