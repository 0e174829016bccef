//! The kit's registries name every model kind: a strategy and a cost bound per kind, and the
//! generated models cover them all.

use std::collections::BTreeSet;

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::TestRunner;
use spectex_model::KIND_NAMES;
use spectex_testkit::cpu::COST_BOUNDS;
use spectex_testkit::models::{KIND_STRATEGIES, any_model};

#[test]
fn every_kind_has_a_strategy_and_a_cost_bound() {
    let kinds: BTreeSet<&str> = KIND_NAMES.iter().copied().collect();
    let strategies: BTreeSet<&str> = KIND_STRATEGIES.iter().map(|(k, _)| *k).collect();
    let bounds: BTreeSet<&str> = COST_BOUNDS.iter().map(|(k, _)| *k).collect();
    assert_eq!(
        strategies, kinds,
        "spectex_testkit::models::KIND_STRATEGIES must list every kind once"
    );
    assert_eq!(
        bounds, kinds,
        "spectex_testkit::cpu::COST_BOUNDS must give every kind its bound"
    );
}

#[test]
fn generated_models_cover_every_kind_valid_and_invalid() {
    let mut runner = TestRunner::deterministic();
    let strategy = any_model();
    let (mut valid, mut invalid) = (BTreeSet::new(), BTreeSet::new());
    for _ in 0..600 {
        let model = strategy.new_tree(&mut runner).unwrap().current();
        if model.validate().is_ok() {
            valid.insert(model.kind());
        } else {
            invalid.insert(model.kind());
        }
    }
    let kinds: BTreeSet<&str> = KIND_NAMES.iter().copied().collect();
    assert_eq!(valid, kinds, "kinds with a valid model among 600");
    assert_eq!(invalid, kinds, "kinds with an invalid model among 600");
}
