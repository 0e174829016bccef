//! `spectex phasor`'s flags against the phasor builders (`src/phasor.rs`).

use clap::Parser;

use spectex_cli::phasor::*;
use spectex_model::{PhasorNoise, PhasorOrientation, PhasorOutput, Profile};

#[derive(Debug, Parser)]
struct Phasor {
    #[command(flatten)]
    cmd: PhasorCommand,
}

fn model(flags: &[&str]) -> PhasorNoise {
    let argv = ["phasor", "-o", "x.png"].iter().chain(flags);
    let cmd = Phasor::try_parse_from(argv).expect("valid flags").cmd;
    build(&cmd, 512).expect("valid model")
}

#[test]
fn defaults_are_the_builders() {
    let built = PhasorNoise::builder().build().expect("defaults are valid");
    assert_eq!(model(&[]), built);
    let pwm = PhasorNoise::builder()
        .profile(Profile::square(0.25))
        .orientation(PhasorOrientation::coherent())
        .build();
    let flags = ["--profile", "square", "--duty", "0.25", "--coherent"];
    assert_eq!(model(&flags), pwm.expect("valid"));
}

#[test]
fn outputs_are_shown_in_the_unit_interval() {
    for (kind, output) in [
        ("phase", PhasorOutput::Phase),
        ("intensity", PhasorOutput::Intensity),
        ("gabor", PhasorOutput::Gabor),
    ] {
        let noise = model(&["--output-kind", kind]);
        let levels = PhasorNoise::default_levels(output, &Profile::Sine);
        assert_eq!(
            (noise.output, noise.mean, noise.amplitude),
            (output, levels.mean, levels.amplitude)
        );
    }
}
