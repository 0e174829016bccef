//! `spectex fit`'s flags against the library defaults (`src/fit.rs`).

use clap::Parser;

use spectex_cli::fit::*;
use spectex_sampling::{FitOptions, TextureOptions};

/// `spectex fit`'s flags alone.
#[derive(Debug, Parser)]
struct Fit {
    #[command(flatten)]
    fit: FitArgs,
}

#[test]
fn fit_defaults_are_the_library_defaults() {
    let args = Fit::try_parse_from(["fit"]).expect("no flag is required");
    assert_eq!(args.fit.options(), FitOptions::default());
    assert_eq!(args.fit.texture_options(), TextureOptions::default());
    assert!(!args.fit.wants_texture());
}
