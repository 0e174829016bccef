//! The kit's registries name every model kind: a strategy and a cost bound per kind, and the
//! generated models cover them all.

use std::collections::BTreeSet;

use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::TestRunner;
use spectex_model::KIND_NAMES;
use spectex_testkit::cpu::COST_BOUNDS;
use spectex_testkit::models::{KIND_STRATEGIES, any_model};

#[test]
fn each_kinds_strategy_makes_models_of_that_kind_and_its_bound_is_finite() {
    // The registries are collected from the kinds (`FuzzKind`, `CostBound`) through
    // `for_each_kind!`, so every kind is in them; what can still go wrong is a kind's
    // declaration itself: a strategy that builds another kind's models, a bound that is no bound.
    let mut runner = TestRunner::deterministic();
    for (kind, strategy) in KIND_STRATEGIES.iter() {
        let strategy = strategy(spectex_testkit::strategy::Odds::VALID, 1);
        for _ in 0..20 {
            let model = strategy.new_tree(&mut runner).unwrap().current();
            assert_eq!(
                model.kind(),
                *kind,
                "the {kind} strategy made a {} model",
                model.kind()
            );
        }
    }
    for (kind, bound) in COST_BOUNDS.iter() {
        assert!(
            bound.is_finite() && *bound >= 1.0,
            "{kind}: cost bound {bound}"
        );
    }
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
