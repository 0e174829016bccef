//! Structure-aware random models of every kind, for fuzzing: each field drawn around and beyond
//! its valid range ([`crate::strategy`]), lists empty, typical or one past their limit, profiles
//! and warps nested up to and past their depth limits.
//!
//! Each kind declares its strategy as its [`FuzzKind`], in its own module here (`<kind>.rs`,
//! beside its `CostBound` for the CPU targets, [`crate::cpu`]); [`KIND_STRATEGIES`] collects
//! them through `spectex_model::for_each_kind!`, so a new kind without a strategy does not
//! compile. This file holds what the kinds share: the collection, the choice of a kind, and the
//! seed, level and angle strategies.

use std::sync::LazyLock;

use proptest::prelude::*;
use spectex_model::warp::MAX_WARP_DEPTH;
use spectex_model::{Model, ModelKind};

use crate::strategy::{Odds, f32_in, odds};

// One module per kind (`<kind>.rs`: its strategy, `FuzzKind` and `CostBound`), declared from
// the one list of kinds.
spectex_model::for_each_kind!(pub mod);

/// A model-producing strategy for one kind, given the case's odds and how many warps may still
/// nest inside it.
pub type KindStrategy = fn(Odds, usize) -> BoxedStrategy<Model>;

/// What the kit generates of one kind: its structure-aware strategy. Every kind implements it
/// (the collection below goes through `spectex_model::for_each_kind!`, so a kind without one
/// does not compile).
pub trait FuzzKind: ModelKind {
    /// Models of the kind, given the case's odds and how many warps may still nest inside.
    fn strategy(o: Odds, depth: usize) -> BoxedStrategy<Model>;
}

/// One strategy per model kind, by [`spectex_model::ModelKind::NAME`], in the order of
/// [`Model`]'s variants: what each kind declares as its [`FuzzKind`].
pub static KIND_STRATEGIES: LazyLock<Vec<(&'static str, KindStrategy)>> = LazyLock::new(|| {
    let mut strategies: Vec<(&'static str, KindStrategy)> = Vec::new();
    spectex_model::for_each_kind!(types: K => {
        strategies.push((<K as ModelKind>::NAME, <K as FuzzKind>::strategy));
    });
    strategies
});

/// Warps nested at most in generated models: two past [`MAX_WARP_DEPTH`], so the limit itself
/// and what lies beyond it are both drawn.
pub const MAX_GENERATED_WARP_DEPTH: usize = MAX_WARP_DEPTH + 2;

/// A model of any kind (every kind equally often), with the odds drawn per case.
pub fn any_model() -> BoxedStrategy<Model> {
    odds()
        .prop_flat_map(|o| model(o, MAX_GENERATED_WARP_DEPTH))
        .boxed()
}

/// A model of any kind with odds `o`, nesting at most `depth` warps.
pub fn model(o: Odds, depth: usize) -> BoxedStrategy<Model> {
    let kinds: Vec<BoxedStrategy<Model>> = KIND_STRATEGIES
        .iter()
        .filter(|(name, _)| depth > 0 || (*name != "warp" && *name != "combine"))
        .map(|(_, strategy)| strategy(o, depth))
        .collect();
    proptest::strategy::Union::new(kinds).boxed()
}

/// A model of the kind named `kind` (a [`spectex_model::KIND_NAMES`] entry), or `None`.
pub fn model_of_kind(kind: &str, o: Odds) -> Option<BoxedStrategy<Model>> {
    KIND_STRATEGIES
        .iter()
        .find(|(name, _)| *name == kind)
        .map(|(_, strategy)| strategy(o, MAX_GENERATED_WARP_DEPTH))
}

fn seed() -> BoxedStrategy<u32> {
    prop_oneof![any::<u32>(), Just(0u32), Just(u32::MAX)].boxed()
}

/// A mean or gain: valid in `[−1e9, 1e9]`, usually near `[−1, 1]`.
fn level(o: Odds) -> BoxedStrategy<f32> {
    f32_in(-1e9, 1e9, o)
}

/// An angle in radians, valid in `[−1000, 1000]`.
fn angle(o: Odds) -> BoxedStrategy<f32> {
    f32_in(-1e3, 1e3, o)
}
