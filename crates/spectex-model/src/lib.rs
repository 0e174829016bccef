//! Model definitions for spectex, and the scalar contract every evaluator shares.
//!
//! Today this crate holds the **randomness contract** (DESIGN.md invariant 1, specified in
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

pub mod random;
