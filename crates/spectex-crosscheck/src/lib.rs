//! Renders the same model windows through `spectex-cpu` and `spectex-gpu` and compares them:
//! max / mean absolute error, error percentiles and the distance between their Welch spectra
//! (from `spectex-spectrum`), writing actual and difference images and a report on failure.
//!
//! Nothing is implemented here yet: the GPU evaluator issue fills it.
