//! Loading model files: versions, unknown fields, out-of-range values, and a round trip.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use spectex_model::{
    GaborNoise, LrpNoise, Model, ModelError, Orientation, Stratum, from_json, to_json,
};

fn lrp() -> Model {
    Model::Lrp(LrpNoise {
        seed: 3,
        mean: 0.5,
        strata: vec![Stratum {
            window_width: 12.5,
            amplitude: 0.1,
            sub_strata: vec![vec![[0.1, 0.0], [0.12, 0.01]], vec![[0.0, 0.2]]],
        }],
    })
}

fn gabor() -> Model {
    Model::Gabor(GaborNoise {
        seed: 1,
        mean: 0.0,
        amplitude: 1.0,
        bandwidth: 0.05,
        frequency: 0.0625,
        orientation: Orientation::Isotropic {
            min: 0.0,
            max: std::f32::consts::TAU,
        },
        impulses_per_kernel: 64.0,
    })
}

#[test]
fn round_trip() {
    for m in [lrp(), gabor()] {
        let text = to_json(&m).unwrap();
        assert!(text.contains("\"schema_version\": 1"));
        assert_eq!(from_json(&text).unwrap(), m);
    }
}

#[test]
fn wrong_or_missing_schema_version_says_which_are_understood() {
    let text = to_json(&lrp())
        .unwrap()
        .replace("\"schema_version\": 1", "\"schema_version\": 7");
    let e = from_json(&text).unwrap_err();
    assert!(matches!(e, ModelError::SchemaVersion { .. }));
    assert!(
        e.to_string().contains("7") && e.to_string().contains("reads schema_version 1"),
        "{e}"
    );
    let text = to_json(&lrp())
        .unwrap()
        .replace("\"schema_version\": 1,", "");
    assert!(
        from_json(&text)
            .unwrap_err()
            .to_string()
            .contains("missing")
    );
}

#[test]
fn unknown_fields_are_rejected() {
    let text = to_json(&lrp())
        .unwrap()
        .replace("\"seed\": 3", "\"seed\": 3, \"sead\": 4");
    let e = from_json(&text).unwrap_err();
    assert!(e.to_string().contains("unknown field `sead`"), "{e}");
    let text = to_json(&gabor())
        .unwrap()
        .replace("\"model\"", "\"extra\": 1, \"model\"");
    assert!(
        from_json(&text)
            .unwrap_err()
            .to_string()
            .contains("unknown field `extra`")
    );
}

#[test]
fn values_out_of_range_name_the_field() {
    let text = to_json(&lrp()).unwrap().replace("12.5", "-1.0");
    let e = from_json(&text).unwrap_err();
    assert!(
        e.to_string().contains("lrp.strata[0].window_width = -1"),
        "{e}"
    );
    let text = to_json(&lrp()).unwrap().replace("0.2", "0.7");
    assert!(
        from_json(&text)
            .unwrap_err()
            .to_string()
            .contains("sub_strata[1][0][1]")
    );
    // JSON has no NaN: a NaN written by another tool is a syntax error, reported as such.
    let text = to_json(&gabor()).unwrap().replace("0.0625", "NaN");
    assert!(matches!(from_json(&text).unwrap_err(), ModelError::Json(_)));
    let mut m = lrp();
    if let Model::Lrp(l) = &mut m {
        l.strata[0].amplitude = f32::NAN;
    }
    assert!(
        to_json(&m)
            .unwrap_err()
            .to_string()
            .contains("amplitude = NaN")
    );
    let mut m = lrp();
    if let Model::Lrp(l) = &mut m {
        l.strata[0].sub_strata.clear();
    }
    assert!(
        to_json(&m)
            .unwrap_err()
            .to_string()
            .contains("has 0 entries")
    );
}
