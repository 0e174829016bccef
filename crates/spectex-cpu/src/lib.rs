//! The CPU reference evaluator: evaluates any `spectex-model` model at any continuous position,
//! parallel over rows, bit-identical for any thread count and any tiling of the window.
//!
//! Depends on `spectex-model` only, so a game can evaluate a fitted model with these two crates.
//! Nothing is implemented here yet: the Local Random-Phase noise issue fills it.
