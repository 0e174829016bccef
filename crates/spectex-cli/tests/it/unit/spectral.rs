//! `spectex noise ring|fractal`'s flags against the spectral builders (`src/noise/lrp.rs`).

use clap::Parser;
use spectex_sampling::{FitOptions, Partition};

use spectex_cli::noise::lrp::*;
use spectex_model::SpectralTarget;
use spectex_sampling::LrpFromTarget;

#[derive(Debug, Parser)]
enum Noise {
    Ring(RingArgs),
    Fractal(FractalArgs),
}

#[test]
fn defaults_are_the_builders() {
    let Ok(Noise::Ring(ring)) = Noise::try_parse_from(["noise", "ring", "-o", "x.png"]) else {
        panic!("ring parses");
    };
    let target = SpectralTarget::Ring {
        radius: 0.0625,
        width: 0.005,
    };
    assert_eq!(
        builder(target.clone(), &ring.common),
        LrpFromTarget::new(target)
    );
    let Ok(Noise::Fractal(fractal)) = Noise::try_parse_from(["noise", "fractal", "-o", "x.png"])
    else {
        panic!("fractal parses");
    };
    let target = SpectralTarget::Fractal {
        beta: 1.5,
        angle: 0.0,
        spread: None,
        min_frequency: 1.0 / 128.0,
    };
    let options = builder(target, &fractal.common).options();
    assert_eq!(
        options,
        FitOptions {
            budget: 48,
            strata: 12,
            seed: 0,
            partition: Partition::LogPower,
            ..FitOptions::default()
        }
    );
}
