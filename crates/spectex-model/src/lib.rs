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

pub mod classic;
mod error;
mod file;
pub mod fixtures;
mod gabor;
pub mod grid;
pub mod kind;
mod lrp;
pub mod math;
mod phasor;
pub mod phasor_kernels;
pub mod random;
mod target;
pub mod texton;
pub mod texture;
pub mod warp;
pub mod wavelet;
pub mod window;

pub use classic::ClassicNoise;
pub use error::ModelError;
pub use file::{SCHEMA_VERSION, SUPPORTED_SCHEMA_VERSIONS, from_json, to_json};
pub use gabor::{GABOR_TRUNCATION, GaborNoise, NEG_LN_20, Orientation};
pub use grid::{MAX_POSITION, MAX_WINDOW_PIXELS, MAX_WINDOW_SIDE, Window, WindowError};
pub use kind::{KIND_NAMES, Model, ModelKind};
pub use lrp::{LrpNoise, MAX_COSINES, MAX_STRATA, MAX_TABLE, Stratum};
pub use phasor::{
    COHERENT_BANDWIDTH_RATIO, COHERENT_SPREAD, Field, Harmonic, MAX_FIELD_SIDE,
    MAX_PROFILE_SAMPLES, PHASOR_TRUNCATION, PhasorNoise, PhasorOrientation, PhasorOutput, Profile,
    RAMP_EXTENT,
};
pub use target::SpectralTarget;
pub use texton::TextonNoise;
pub use texture::{ColourBasis, FixedCosine, Structure, TextureChannel, TextureModel, Turbulence};
pub use warp::{MAX_WARP, Warp};
pub use wavelet::WaveletNoise;
