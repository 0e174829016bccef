//! Integration tests of spectex-simulate: steppers against slow references and identities,
//! thread-count invariance, golden images.

mod golden;
mod steppers;
