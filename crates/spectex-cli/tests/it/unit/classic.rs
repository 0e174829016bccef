//! `spectex noise perlin|fbm|worley`'s flags against the classic builders (`src/noise/classic.rs`).

use clap::Parser;

use spectex_cli::noise::classic::*;
use spectex_model::ModelError;
use spectex_model::classic::{Basis, ClassicNoise, FeaturePoints, Metric, Worley};

#[derive(Debug, Parser)]
enum Noise {
    Perlin(ClassicArgs),
    Fbm(FbmArgs),
    Worley(WorleyNoiseArgs),
}

/// The model `spectex noise <flags> -o x.png` builds.
fn model(flags: &[&str]) -> ClassicNoise {
    let argv = ["noise"].iter().chain(flags).chain(&["-o", "x.png"]);
    let built = match Noise::try_parse_from(argv).expect("valid flags") {
        Noise::Perlin(args) => build(Basis::Gradient, None, &args),
        Noise::Fbm(args) => build(fbm_basis(&args), Some(&args.fractal), &args.classic),
        Noise::Worley(args) => build(worley_basis(&args.worley), None, &args.classic),
    };
    built.expect("the defaults are valid")
}

fn built(builder: Result<ClassicNoise, ModelError>) -> ClassicNoise {
    builder.expect("the defaults are valid")
}

#[test]
fn defaults_are_the_builders() {
    assert_eq!(model(&["perlin"]), built(ClassicNoise::perlin().build()));
    assert_eq!(model(&["fbm"]), built(ClassicNoise::fbm().build()));
    assert_eq!(
        model(&["fbm", "--sum", "turbulence"]),
        built(ClassicNoise::turbulence().build())
    );
    assert_eq!(
        model(&["fbm", "--sum", "ridged"]),
        built(ClassicNoise::ridged().build())
    );
    assert_eq!(
        model(&["fbm", "--basis", "worley"]),
        built(ClassicNoise::fbm().worley(Worley::default()).build())
    );
    assert_eq!(model(&["worley"]), built(ClassicNoise::worley().build()));
}

#[test]
fn flags_reach_the_model() {
    let noise = model(&[
        "fbm",
        "--basis",
        "simplex",
        "--octaves",
        "4",
        "--gain",
        "0.6",
        "--lacunarity",
        "2.5",
        "--seed",
        "3",
        "--dims",
        "3",
        "--cell",
        "40",
        "--mean",
        "0.1",
    ]);
    let expected = ClassicNoise::fbm()
        .basis(Basis::Simplex)
        .octaves(4)
        .gain(0.6)
        .lacunarity(2.5)
        .seed(3)
        .dimensions(3)
        .cell_size(40.0)
        .mean(0.1)
        .build();
    assert_eq!(noise, built(expected));
    let cells = model(&[
        "worley",
        "--coefficients",
        "-1,1,0,0",
        "--metric",
        "manhattan",
        "--poisson",
        "2",
    ]);
    let expected = ClassicNoise::worley().worley(Worley {
        metric: Metric::Manhattan,
        coefficients: [-1.0, 1.0, 0.0, 0.0],
        points: FeaturePoints::Poisson(2.0),
    });
    assert_eq!(cells, built(expected.build()));
}
