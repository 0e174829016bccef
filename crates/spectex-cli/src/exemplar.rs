//! The built-in default exemplar: a 256×256 colour micro-texture that spectex generated itself
//! (`crates/spectex-cli/default_exemplar.png`, inside the crate so that it packages), so every command runs with no input file at hand.
//!
//! It is a spot noise of a few thousand small anisotropic Gaussian spots in an earthy palette
//! over fine grain, with a gentle light gradient. Spots are cut at the borders, so the image is
//! not periodic: exactly the case where the periodic component matters. The generator in
//! `tests/it/unit/exemplar.rs` is the definition; `shipped_file_matches_the_generator` checks the
//! file against it, and `SPECTEX_BLESS=1 cargo test -p spectex-cli exemplar` rewrites the file
//! deliberately.

/// The PNG bytes of the built-in exemplar.
pub const DEFAULT_EXEMPLAR_PNG: &[u8] = include_bytes!("../default_exemplar.png");

/// How the built-in exemplar is named in messages.
pub const DEFAULT_EXEMPLAR_NAME: &str = "the built-in exemplar (spectex-cli/default_exemplar.png)";
