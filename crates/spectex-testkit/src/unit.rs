//! Unit tests run from a crate's `it` binary.
//!
//! A unit-test harness compiles its whole crate a second time, with `cfg(test)`: for the SIMD
//! kernels of spectex-cpu, or spectex-model's 141 tests, longer than the tests take. So a crate's
//! unit tests' bodies are `pub fn`s of a `pub mod tests` in their module, behind the crate's
//! `unit-tests` feature (its dev-dependency on itself turns it on, so one compilation serves the
//! tests and the dependents), re-exported by its `unit_tests` module, and its `tests/it/unit.rs`
//! runs each as a `#[test]` through [`unit_tests!`](crate::unit_tests), which also checks that
//! every body under `src/` is run.

use std::path::{Path, PathBuf};

/// One `#[test]` per body, a module per source module, and a test that every `pub fn` of every
/// `pub mod tests` under the crate's `src/` is run and nothing else:
///
/// ```ignore
/// spectex_testkit::unit_tests! {
///     spectex_cpu;
///     gabor: poisson_count_has_poisson_moments, kept_impulses_follow_the_draw_order;
///     voronoi: a_regular_grid_has_known_distances;
/// }
/// ```
#[macro_export]
macro_rules! unit_tests {
    ($krate:ident; $($module:ident: $($test:ident),+;)+) => {
        $(
            mod $module {
                $(
                    #[test]
                    fn $test() {
                        $krate::unit_tests::$module::$test();
                    }
                )+
            }
        )+

        /// Every body under `src/` is run above, and nothing else is.
        #[test]
        fn every_unit_test_is_run() {
            $crate::unit::assert_every_body_is_run(
                ::std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/src")),
                &[$($(stringify!($test)),+),+],
            );
        }
    };
}

/// Panics unless the `pub fn`s of the `pub mod tests` (and the modules after it) of the `.rs`
/// files under `src` are exactly `run`.
pub fn assert_every_body_is_run(src: &Path, run: &[&str]) {
    let mut bodies = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.map(|e| e.path()))
            .collect::<Result<_, _>>()
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        entries.sort();
        for path in entries {
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                bodies.extend(bodies_in(&text));
            }
        }
    }
    bodies.sort();
    let mut run: Vec<String> = run.iter().map(|s| (*s).to_owned()).collect();
    run.sort();
    assert_eq!(
        bodies,
        run,
        "the unit-test bodies under {} against the tests run",
        src.display()
    );
}

/// The names of the `pub fn`s at one indent after a line `pub mod tests {`.
fn bodies_in(text: &str) -> Vec<String> {
    let Some((_, tests)) = text.split_once("\npub mod tests {") else {
        return Vec::new();
    };
    tests
        .lines()
        .filter_map(|l| {
            let name = l.strip_prefix("    pub fn ")?;
            Some(name[..name.find('(')?].to_owned())
        })
        .collect()
}
