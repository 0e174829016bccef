//! Integration tests of spectex-reproduce: the whole reproduction on tiny sizes (so the
//! command cannot rot) and the command line's handling of bad input.
//!
//! One test binary for the crate, a module per file.

mod run;
