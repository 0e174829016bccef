//! Integration tests of reading and writing model files.
//!
//! One test binary for the crate, a module per file: every test binary is another link of all
//! the dependencies.

mod model_files;
mod unit;
