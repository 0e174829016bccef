//! The fuzz runner itself ([`spectex_testkit::fuzz`]) and the kit's image-file helpers: a
//! campaign finds panics, broken properties and hangs and shrinks them; its seed decides its
//! cases; an image saved through the kit opens with its pixels.

use std::sync::Arc;
use std::time::Duration;

use image::DynamicImage;
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use spectex_testkit::fuzz::{Failure, Finding, Observation, Settings, Target, run, seed_bytes};
use spectex_testkit::image_files;

#[test]
fn panics_properties_and_hangs_are_findings_and_shrink() {
    let settings = Settings {
        cases: 200,
        seed: 1,
        case_timeout: Duration::from_secs(5),
    };
    let target: Target<u32> = Arc::new(|&n: &u32| {
        assert!(n < 900, "too big: {n}");
        if n % 97 == 13 {
            return Err(format!("{n} is 13 mod 97"));
        }
        Ok(Observation {
            kind: Some("number"),
            accepted: n % 2 == 0,
            ..Observation::default()
        })
    });
    let report = run("unit", &settings, &(0u32..1000), |n| n.to_string(), &target);
    assert_eq!(report.cases, 200);
    let panics: Vec<&Finding> = report
        .findings
        .iter()
        .filter(|f| matches!(f.failure, Failure::Panic(_)))
        .collect();
    assert!(!panics.is_empty(), "{}", report.summary());
    // Shrinking goes down to the smallest failing number.
    assert!(
        panics
            .iter()
            .all(|f| f.shrunk.as_ref().is_some_and(|(input, _)| input == "900")),
        "{}",
        report.summary()
    );
    assert!(
        report
            .findings
            .iter()
            .any(|f| matches!(f.failure, Failure::Property(_))),
        "{}",
        report.summary()
    );
    let passed = report.cases as usize - report.findings.len();
    assert_eq!(
        report.accepted_total() + report.rejected["number"],
        passed as u32
    );

    let hang: Target<u32> = Arc::new(|_| {
        std::thread::sleep(Duration::from_secs(3));
        Ok(Observation::default())
    });
    let settings = Settings {
        cases: 5,
        seed: 1,
        case_timeout: Duration::from_millis(100),
    };
    let report = run("hang", &settings, &Just(1u32), |n| n.to_string(), &hang);
    assert_eq!(report.cases, 1, "a hang ends the campaign");
    assert!(matches!(report.findings[0].failure, Failure::Hang(_)));
}

#[test]
fn the_seed_decides_the_cases() {
    let draw = |seed: u64, name: &str| {
        let mut runner = TestRunner::new_with_rng(
            Config::default(),
            TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes(seed, name)),
        );
        (0..8)
            .map(|_| any::<u64>().new_tree(&mut runner).unwrap().current())
            .collect::<Vec<_>>()
    };
    assert_eq!(draw(3, "a"), draw(3, "a"));
    assert_ne!(draw(3, "a"), draw(4, "a"));
    assert_ne!(draw(3, "a"), draw(3, "b"));
}

#[test]
fn a_saved_png_opens_with_its_pixels() {
    let dir = std::env::temp_dir().join(format!("spectex-testkit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ramp.png");
    let ramp = image::GrayImage::from_fn(7, 3, |x, y| image::Luma([(x * 30 + y) as u8]));
    image_files::save(&DynamicImage::ImageLuma8(ramp.clone()), &path).unwrap();
    let back = image_files::open(&path).unwrap().into_luma8();
    let bytes = std::fs::read(&path).unwrap();
    let from_memory = image_files::load_from_memory(&bytes).unwrap().into_luma8();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(back, ramp);
    assert_eq!(from_memory, ramp);
}

/// `unit_tests!`'s check finds the bodies of a planted tree, and fails on one left out or one
/// named that has no body.
#[test]
fn the_unit_test_check_fails_on_a_body_not_run() {
    use spectex_testkit::unit::assert_every_body_is_run;
    let dir = std::env::temp_dir().join(format!("spectex-testkit-unit-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("inner")).unwrap();
    std::fs::write(
        dir.join("inner/a.rs"),
        "fn x() {}\n\n#[cfg(feature = \"unit-tests\")]\npub mod tests {\n    use super::*;\n\n    \
         pub fn first() {}\n\n    fn helper() {}\n\n    pub fn second() {\n        helper();\n    }\n}\n",
    )
    .unwrap();
    std::fs::write(dir.join("b.rs"), "pub fn not_a_test() {}\n").unwrap();
    assert_every_body_is_run(&dir, &["second", "first"]);
    for run in [&["first"][..], &["first", "second", "third"]] {
        let caught = std::panic::catch_unwind(|| assert_every_body_is_run(&dir, run));
        assert!(caught.is_err(), "{run:?} passed");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
