//! `spectex noise warp`'s flags against the warp builder (`src/noise/warp.rs`).

use clap::Parser;

use spectex_cli::noise::warp::*;
use spectex_model::Warp;

#[derive(Debug, Parser)]
struct WarpCommand {
    #[command(flatten)]
    args: WarpArgs,
}

#[test]
fn defaults_are_the_builders() {
    let args = WarpCommand::try_parse_from(["warp", "-o", "x.png", "--seed", "4"]);
    let args = args.expect("valid flags").args;
    let warp = builder(&args).expect("no file to read").build();
    let expected = Warp::builder().seed(4).build();
    assert_eq!(warp.expect("valid"), expected.expect("valid"));
    let plain = WarpCommand::try_parse_from(["warp", "-o", "x.png"]).expect("valid flags");
    let plain = builder(&plain.args).expect("no file to read");
    assert_eq!(plain, Warp::builder());
}
