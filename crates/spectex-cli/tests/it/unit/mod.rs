//! The command's unit tests: its flag parsing and the pure functions behind the commands,
//! called through the `spectex_cli` library (`src/lib.rs`) rather than in a unit-test harness of
//! the library, which would compile the whole command a second time. A module per source module.

mod classic;
mod exemplar;
mod fit;
mod gabor;
mod io;
mod phasor;
mod spectral;
mod stream;
mod warp;
mod wavelet;

use spectex_cli::args::parse_size;

#[test]
fn sizes_parse() {
    assert_eq!(parse_size("1024x768"), Ok((1024, 768)));
    assert_eq!(parse_size("5X6"), Ok((5, 6)));
    assert_eq!(parse_size("0x0"), Ok((0, 0)));
    assert!(parse_size("1024").is_err());
    assert!(parse_size("ax3").is_err());
    assert!(parse_size("-1x3").is_err());
}

#[test]
fn cli_is_well_formed() {
    use clap::CommandFactory;
    spectex_cli::Cli::command().debug_assert();
}
