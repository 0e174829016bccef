//! Model definitions for spectex, and the scalar contract every evaluator shares.
//!
//! It holds the serde types of every model ([`LrpNoise`], [`GaborNoise`], the
//! [`SpectralTarget`]s an LRP noise is built from), versioned model files ([`from_json`],
//! [`to_json`]), the Kaiser–Bessel window ([`window`]), and the **randomness contract** (invariant 1, specified in
//! `docs/ARCHITECTURE.md`): one integer hash of (cell x, cell y, layer, seed) and one `u32`
//! PRNG stepped with wrapping integer arithmetic. Every random choice spectex makes — a phase
//! of Random Phase Noise today, a frequency index or an impulse position of a procedural model
//! later — is drawn from it, so integer results are bit-identical on every machine and, once
//! the WGSL twin exists, on the GPU.
//!
//! ```
//! use spectex_model::random::{cell_hash, Prng};
//!
//! // The same (cell, layer, seed) always gives the same stream.
//! let mut a = Prng::new(cell_hash(-3, 7, 0, 42));
//! let mut b = Prng::new(cell_hash(-3, 7, 0, 42));
//! assert_eq!(a.next_u32(), b.next_u32());
//! let u = a.next_f32();
//! assert!((0.0..1.0).contains(&u));
//! ```
//!
//! Every kind has a builder whose defaults are documented constants (`ClassicNoise::DEFAULT_OCTAVES`,
//! `GaborNoise::DEFAULT_FREQUENCY`, …, the `spectex` command's defaults) and whose `build()`
//! validates, naming the field and its range on error; after it, evaluation cannot fail on the
//! model's parameters. A kind struct becomes a [`Model`] (what the evaluators and model files
//! take) by `into()`. LRP noise from a spectrum and textures by example come from
//! `spectex_sampling` instead (`LrpFromTarget`, `fit_image`, `fit_texture`).
//!
//! ```
//! use spectex_model::{ClassicNoise, Model, WaveletNoise, from_json, to_json};
//!
//! let fbm: Model = ClassicNoise::fbm().octaves(5).seed(3).build()?.into();
//! let wavelet: Model = WaveletNoise::builder().bands(vec![1.0, 0.5]).build()?.into();
//! // Models are files: versioned JSON, validated on load.
//! for model in [fbm, wavelet] {
//!     assert_eq!(from_json(&to_json(&model)?)?, model);
//! }
//! # Ok::<(), spectex_model::ModelError>(())
//! ```

mod defaults;
mod error;
mod file;
pub mod filter;
pub mod fixtures;
pub mod grid;
pub mod kind;
pub mod math;
pub mod period;
pub mod phasor_kernels;
pub mod random;
pub mod simulation;
mod target;
pub mod window;

// One module per kind (`<kind>.rs`: its serde struct, `ModelKind` impl and builder), declared
// from the one list of kinds, each kind struct re-exported here.
crate::for_each_kind!(pub mod);
crate::for_each_kind!(pub use);

pub use classic::{ClassicNoiseBuilder, FractalNoiseBuilder};
pub use combine::CombineBuilder;
pub use defaults::{DEFAULT_MEAN, DEFAULT_SEED, DEFAULT_STD_DEV, Levels};
pub use error::ModelError;
pub use file::{
    Fit, ModelFileContents, SCHEMA_VERSION, SUPPORTED_SCHEMA_VERSIONS, from_json, from_json_file,
    from_json_with_fit, to_json, to_json_file, to_json_with_fit,
};
pub use gabor::{
    GABOR_PERIOD_TOLERANCE, GABOR_TRUNCATION, GaborNoiseBuilder, MAX_GABOR_COMPONENTS, NEG_LN_20,
    Orientation, cumulative_weights, pick_component,
};
pub use grid::{Filter, MAX_POSITION, MAX_WINDOW_PIXELS, MAX_WINDOW_SIDE, Window, WindowError};
pub use islamic::IslamicPatternBuilder;
pub use kind::{KIND_NAMES, Model, ModelKind, PERIODIC_KINDS};
pub use lrp::{LrpNoiseBuilder, MAX_COSINES, MAX_STRATA, MAX_TABLE, Stratum};
pub use matrix::MatrixTransformBuilder;
pub use period::Period;
pub use phasor::{
    COHERENT_BANDWIDTH_RATIO, COHERENT_SPREAD, Field, FieldGrid, Harmonic, MAX_FIELD_SIDE,
    MAX_PROFILE_SAMPLES, PHASOR_PERIOD_TOLERANCE, PHASOR_TRUNCATION, PhasorNoiseBuilder,
    PhasorOrientation, PhasorOutput, Profile, RAMP_EXTENT,
};
pub use subdivision::StochasticSubdivisionBuilder;
pub use target::SpectralTarget;
pub use texton::TextonNoiseBuilder;
pub use texture::{ColourBasis, FixedCosine, Structure, TextureChannel, Turbulence};
pub use voronoi::VoronoiNoiseBuilder;
pub use warp::{MAX_WARP, WarpBuilder};
pub use wavelet::WaveletNoiseBuilder;

/// The unit tests' bodies, one module per source module (`pub mod tests` behind this feature),
/// run by `tests/it/unit.rs`: a unit-test harness would compile the crate a second time.
#[cfg(feature = "unit-tests")]
#[doc(hidden)]
pub mod unit_tests {
    pub use crate::classic::builder::tests as classic_builder;
    pub use crate::classic::tests as classic;
    pub use crate::combine::builder::tests as combine_builder;
    pub use crate::combine::tests as combine;
    pub use crate::error::tests as error;
    pub use crate::file::tests as file;
    pub use crate::filter::tests as filter;
    pub use crate::fixtures::tests as fixtures;
    pub use crate::gabor::builder::tests as gabor_builder;
    pub use crate::gabor::tests as gabor;
    pub use crate::grid::tests as grid;
    pub use crate::islamic::builder::tests as islamic_builder;
    pub use crate::islamic::tests as islamic;
    pub use crate::kind::tests as kind;
    pub use crate::lrp::builder::tests as lrp_builder;
    pub use crate::math::tests as math;
    pub use crate::matrix::builder::tests as matrix_builder;
    pub use crate::matrix::tests as matrix;
    pub use crate::period::tests as period;
    pub use crate::phasor::builder::tests as phasor_builder;
    pub use crate::phasor::tests as phasor;
    pub use crate::phasor_kernels::tests as phasor_kernels;
    pub use crate::random::tests as random;
    pub use crate::simulation::tests as simulation;
    pub use crate::subdivision::builder::tests as subdivision_builder;
    pub use crate::subdivision::tests as subdivision;
    pub use crate::target::tests as target;
    pub use crate::texton::builder::tests as texton_builder;
    pub use crate::texton::tests as texton;
    pub use crate::texture::tests as texture;
    pub use crate::tiling::tests as tiling;
    pub use crate::voronoi::builder::tests as voronoi_builder;
    pub use crate::voronoi::tests as voronoi;
    pub use crate::warp::builder::tests as warp_builder;
    pub use crate::warp::tests as warp;
    pub use crate::wavelet::builder::tests as wavelet_builder;
    pub use crate::wavelet::tests as wavelet;
    pub use crate::window::tests as window;
}
