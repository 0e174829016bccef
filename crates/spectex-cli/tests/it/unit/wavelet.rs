//! `spectex noise wavelet`'s flags against the wavelet builder (`src/noise/wavelet.rs`).

use clap::Parser;

use spectex_cli::noise::wavelet::*;
use spectex_model::WaveletNoise;

#[derive(Debug, Parser)]
struct Wavelet {
    #[command(flatten)]
    args: WaveletArgs,
}

fn parse(flags: &[&str]) -> WaveletArgs {
    let argv = ["wavelet", "-o", "x.png"].iter().chain(flags);
    Wavelet::try_parse_from(argv).expect("valid flags").args
}

#[test]
fn defaults_are_the_builders() {
    assert_eq!(builder(&parse(&[])), WaveletNoise::builder());
    let volume = builder(&parse(&["--dims", "3"])).build();
    let expected = WaveletNoise::builder().dimensions(3).build();
    assert_eq!(volume.expect("valid"), expected.expect("valid"));
}
