//! spectex's test kit (dev-only, never published): what the other crates' tests share.
//!
//! - **Fuzzing** ([`fuzz`]): structure-aware random models of every kind ([`models`], from
//!   number and list strategies drawn around and beyond each field's range, [`strategy`]),
//!   mutated model files ([`mutate`]), models at and past every limit ([`limits`]), and image
//!   files with any header ([`images`]); a runner with a watchdog that collects panics, hangs
//!   and broken properties with shrunk inputs. The CPU targets ([`cpu`]) run an input through
//!   JSON → `from_json` → `spectex_cpu::Evaluator` and check that what validation accepts
//!   renders finite values in bounded time per pixel ([`cpu::COST_BOUNDS`]).
//! - **References** ([`reference`]): slow f64 direct sums of the definitions (LRP, Gabor noise)
//!   that the CPU and the GPU tests both compare against.
//! - **Unit tests** ([`unit`]): a crate's unit tests run from its `it` binary, the crate compiled
//!   once.
//! - **Image files** ([`image_files`]): `image`'s open, decode and save, compiled once here
//!   instead of in every test binary that reads a PNG.
//! - **Benches** ([`bench`]): window sizes that shrink when a bench runs once as a test.
//! - **Invariance** ([`invariance`]): the checks every kind must pass — tiles, thread counts,
//!   far offsets, reseeding — over every `testdata/models/*.json` by one
//!   [`check`](invariance::check), on any evaluator implementing
//!   [`Backend`](invariance::Backend).
//!
//! The kit never depends on `spectex-gpu`: a GPU test implements
//! [`Backend`](invariance::Backend) and a fuzz [`Target`](fuzz::Target) for its evaluator
//! itself, so test binaries that do not touch the GPU do not link wgpu (a cargo feature would
//! not do: `cargo test --workspace` unifies features across the workspace, so one crate
//! enabling it would make every user of the kit link wgpu). The CPU parts sit behind the
//! default `cpu` feature, which a GPU test leaves off.
//!
//! ```
//! use spectex_testkit::invariance::{check, Case, Plan};
//! use spectex_testkit::cpu::CpuBackend;
//!
//! let case = Case {
//!     name: "constant".into(),
//!     model: spectex_model::fixtures::constant(0.5),
//!     z: 0.0,
//! };
//! let report = check(&case, &CpuBackend, &Plan::light());
//! println!("{}", report.line());
//! // A constant ignores its seed, so only the reseed check fails.
//! assert!(report.verdict("tiles") == Some(&spectex_testkit::invariance::Verdict::Pass));
//! ```

pub mod bench;
pub mod cases;
#[cfg(feature = "cpu")]
pub mod cpu;
pub mod fixtures;
pub mod fuzz;
pub mod image_files;
pub mod images;
pub mod invariance;
pub mod limits;
pub mod models;
pub mod mutate;
pub mod reference;
pub mod strategy;
pub mod unit;

/// The property-testing crate the strategies are built with, for tests composing them.
pub use proptest;
