//! The hand-made texture cases of `testdata/models/` (`texture-synthetic-grey.json`,
//! `texture-synthetic-colour.json`) are written by the generators below, from fixed seeds, so
//! what they hold is reviewable here rather than in JSON: small structures of a few cosines per
//! block, one or two random-phase strata, turbulence and random placement. This test checks that
//! the shipped files are exactly what the generators write; regenerate them deliberately with
//! `SPECTEX_BLESS=1 cargo test -p spectex-crosscheck --test it texture_fixtures`.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::PathBuf;

use spectex_model::random::{Prng, cell_hash};
use spectex_model::{
    ColourBasis, FixedCosine, Model, Stratum, Structure, TextureChannel, TextureModel, Turbulence,
};

/// Hash layer of the generators' draws (unrelated to any evaluation-time layer).
const FIXTURE_LAYER: u32 = 0x5445_5854; // "TEXT"

/// A stratum of period `delta` with `j` sub-strata of 4 frequencies in cycles per pixel on the
/// half plane, below 0.4 cycles per pixel.
fn stratum(prng: &mut Prng, delta: f32, amplitude: f32, j: usize) -> Stratum {
    Stratum {
        window_width: delta,
        amplitude,
        sub_strata: (0..j)
            .map(|_| {
                (0..4)
                    .map(|_| [0.8 * (prng.next_f32() - 0.5), 0.4 * prng.next_f32()])
                    .collect()
            })
            .collect(),
    }
}

/// `blocks²` blocks of `per_block` cosines, frequencies anywhere in `(−N/2, N/2]`.
fn structure(prng: &mut Prng, period: u32, blocks: u32, per_block: usize) -> Structure {
    let n = 2 * period / blocks;
    let k = |prng: &mut Prng| (prng.next_u32() % n) as i32 - (n / 2) as i32 + 1;
    Structure {
        blocks,
        cosines: (0..blocks * blocks)
            .map(|_| {
                (0..per_block)
                    .map(|_| FixedCosine {
                        frequency: [k(prng), k(prng)],
                        amplitude: 0.02 + 0.06 * prng.next_f32(),
                        phase: prng.next_f32(),
                    })
                    .collect()
            })
            .collect(),
    }
}

/// Grey: period 32, 4×4 blocks of 3 cosines, two strata, turbulence of two strata, placement.
fn grey() -> TextureModel {
    let mut prng = Prng::new(cell_hash(1, 0, FIXTURE_LAYER, 2024));
    TextureModel {
        seed: 7,
        period: 32,
        channels: vec![TextureChannel {
            seed: 11,
            mean: 0.5,
            strata: vec![
                stratum(&mut prng, 6.0, 0.06, 3),
                stratum(&mut prng, 12.5, 0.03, 2),
            ],
            structure: Some(structure(&mut prng, 32, 4, 3)),
        }],
        colour: None,
        turbulence: Some(Turbulence {
            sigma: 2.5,
            seeds: [101, 202],
            strata: vec![
                stratum(&mut prng, 8.0, 0.25, 2),
                stratum(&mut prng, 16.0, 0.15, 2),
            ],
            centre: 0.35,
        }),
        random_placement: true,
    }
}

/// Colour: period 16; channel 0 with 2×2 blocks, channel 1 with one block, channel 2 strata
/// only; a PCA-like basis; one turbulence stratum; placement.
fn colour() -> TextureModel {
    let mut prng = Prng::new(cell_hash(2, 0, FIXTURE_LAYER, 2024));
    let channel = |prng: &mut Prng, c: u32, amplitude: f32, blocks: Option<u32>| TextureChannel {
        seed: 30 + c,
        mean: 0.0,
        strata: vec![stratum(prng, 5.5, amplitude, 2)],
        structure: blocks.map(|b| structure(prng, 16, b, 3)),
    };
    TextureModel {
        seed: 8,
        period: 16,
        channels: vec![
            channel(&mut prng, 0, 0.05, Some(2)),
            channel(&mut prng, 1, 0.03, Some(1)),
            channel(&mut prng, 2, 0.02, None),
        ],
        colour: Some(ColourBasis {
            mean: [0.52, 0.45, 0.33],
            basis: [
                [0.62, 0.55, -0.56],
                [0.58, -0.01, 0.81],
                [0.53, -0.83, -0.16],
            ],
        }),
        turbulence: Some(Turbulence {
            sigma: 1.25,
            seeds: [303, 404],
            strata: vec![stratum(&mut prng, 7.0, 0.3, 3)],
            centre: 0.3,
        }),
        random_placement: true,
    }
}

fn models_dir() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models"
    ))
}

#[test]
fn shipped_texture_cases_are_the_generators_output() {
    let bless = std::env::var("SPECTEX_BLESS").is_ok_and(|v| v == "1");
    for (name, model) in [
        ("texture-synthetic-grey", grey()),
        ("texture-synthetic-colour", colour()),
    ] {
        let text = spectex_model::to_json(&Model::Texture(model)).unwrap();
        assert!(text.len() < 50_000, "{name}: {} bytes", text.len());
        let path = models_dir().join(format!("{name}.json"));
        if bless {
            std::fs::write(&path, &text).unwrap();
            continue;
        }
        let shipped = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; write it with SPECTEX_BLESS=1 cargo test -p spectex-crosscheck \
                 --test it texture_fixtures",
                path.display()
            )
        });
        assert!(
            shipped == text,
            "{} differs from its generator; regenerate it deliberately with SPECTEX_BLESS=1",
            path.display()
        );
        // And it reads back as the same model.
        assert_eq!(
            spectex_model::from_json(&shipped).unwrap(),
            spectex_model::from_json(&text).unwrap()
        );
    }
}
