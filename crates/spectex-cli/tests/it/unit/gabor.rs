//! `spectex noise gabor`'s flags against the Gabor builder (`src/noise/gabor.rs`).

use clap::Parser;
use spectex_model::Orientation;

use spectex_cli::noise::gabor::*;
use spectex_model::GaborNoise;

#[derive(Debug, Parser)]
struct Gabor {
    #[command(flatten)]
    args: GaborArgs,
}

fn parse(flags: &[&str]) -> GaborArgs {
    let argv = ["gabor", "-o", "x.png"].iter().chain(flags);
    Gabor::try_parse_from(argv).expect("valid flags").args
}

#[test]
fn defaults_are_the_builders() {
    assert_eq!(builder(&parse(&[])), GaborNoise::builder());
}

#[test]
fn flags_reach_the_model() {
    let noise = builder(&parse(&[
        "--angle",
        "30",
        "--frequency",
        "0.1",
        "--impulses",
        "16",
        "--contrast",
        "0.1",
        "--seed",
        "5",
    ]))
    .build()
    .expect("valid");
    assert_eq!(
        noise.orientation,
        Orientation::Anisotropic {
            angle: 30f32.to_radians()
        }
    );
    assert_eq!(
        (noise.frequency, noise.impulses_per_kernel, noise.seed),
        (0.1, 16.0, 5)
    );
    assert!((f64::from(noise.amplitude) * noise.unit_std_dev() - 0.1).abs() < 1e-6);
}
