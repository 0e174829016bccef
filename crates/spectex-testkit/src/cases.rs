//! Fuzz inputs that pair a model with where it is rendered: windows (tiny ones, near the origin,
//! far away, at the edge of the position range, and invalid ones: empty, too large, NaN
//! offsets, zero scales, corners past `i64`) and planes `z` for 3D models; and the model file
//! text of any model, valid or not.

use proptest::prelude::*;
use spectex_model::{MAX_POSITION, MAX_WINDOW_SIDE, Model, Window};

use crate::models::any_model;

/// One model case: a model, a window and a plane.
#[derive(Debug, Clone)]
pub struct ModelCase {
    /// The model, valid or not.
    pub model: Model,
    /// Where it is rendered (valid or not).
    pub window: Window,
    /// The plane of 3D models (valid or not).
    pub z: f64,
}

/// Largest window a valid case renders, in pixels: 8 × 8, so that the slowest valid model (a
/// deep warp of large textures) stays a fraction of a second.
pub const MAX_CASE_PIXELS: usize = 64;

/// Model cases of every kind ([`any_model`]) with [`window`]s and [`plane`]s.
pub fn model_cases() -> BoxedStrategy<ModelCase> {
    (any_model(), window(), plane())
        .prop_map(|(model, window, z)| ModelCase { model, window, z })
        .boxed()
}

/// A render window: usually valid and at most 8 × 8 pixels, anywhere from the origin to the
/// edge of the position range; sometimes invalid in one parameter.
pub fn window() -> BoxedStrategy<Window> {
    let size = (1usize..=8, 1usize..=8);
    let offset = prop_oneof![
        3 => Just([0.0, 0.0]),
        3 => [-1e3f64..1e3, -1e3f64..1e3],
        2 => [far(), far()],
        1 => [edge(), edge()],
    ];
    let scale = prop_oneof![
        4 => Just(1.0f64),
        2 => Just(0.37f64),
        2 => (-20.0f64..20.0).prop_map(|e| e.exp2()),
        1 => Just(1e-6f64),
        1 => Just(1e6f64),
    ];
    let corner = prop_oneof![8 => Just(0i64), 2 => -1000i64..1000];
    let valid = (size, offset, scale, corner.clone(), corner)
        .prop_map(|((width, height), offset, scale, x0, y0)| Window {
            offset,
            scale,
            x0,
            y0,
            width,
            height,
            filter: spectex_model::grid::Filter::Pixel,
        })
        .boxed();
    let invalid = (valid.clone(), 0usize..8).prop_map(|(w, which)| match which {
        0 => Window { width: 0, ..w },
        1 => Window {
            width: MAX_WINDOW_SIDE + 1,
            ..w
        },
        // Each side within its limit, the pixel count past 2^30: refused before allocating.
        2 => Window {
            width: MAX_WINDOW_SIDE,
            height: MAX_WINDOW_SIDE / 2 + 1,
            ..w
        },
        3 => Window {
            offset: [f64::NAN, 0.0],
            ..w
        },
        4 => Window {
            offset: [0.0, f64::NEG_INFINITY],
            ..w
        },
        5 => Window { scale: 0.0, ..w },
        6 => Window {
            offset: [2.0 * MAX_POSITION, -3.0],
            ..w
        },
        // Corners whose pixel index overflows i64.
        _ => Window {
            x0: i64::MAX - 2,
            y0: i64::MIN,
            ..w
        },
    });
    prop_oneof![9 => valid, 1 => invalid].boxed()
}

/// `±10⁷` plus a fraction of a pixel.
fn far() -> BoxedStrategy<f64> {
    (any::<bool>(), 0.0f64..1.0)
        .prop_map(|(negative, f)| if negative { -1e7 - f } else { 1e7 + f })
        .boxed()
}

/// Within a few hundred pixels of `±MAX_POSITION` (corners may land just past it).
fn edge() -> BoxedStrategy<f64> {
    (any::<bool>(), 0.0f64..300.0)
        .prop_map(|(negative, d)| {
            let v = MAX_POSITION - d;
            if negative { -v } else { v }
        })
        .boxed()
}

/// A plane `z` for 3D models (2D ones ignore it): usually modest, sometimes far, sometimes
/// invalid (NaN, infinite, past the position range).
pub fn plane() -> BoxedStrategy<f64> {
    prop_oneof![
        4 => Just(0.0f64),
        4 => -1e3f64..1e3,
        1 => Just(37.3f64),
        1 => far(),
        1 => prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(2.0 * MAX_POSITION)],
    ]
    .boxed()
}

/// The text of a model file holding `model` as it is, without validating it (serde_json writes
/// NaN and infinities as `null`, which the reader then rejects as a type error).
#[must_use]
pub fn model_file_text(model: &Model) -> String {
    let value = serde_json::json!({
        "schema_version": spectex_model::SCHEMA_VERSION,
        "model": serde_json::to_value(model).unwrap_or(serde_json::Value::Null),
    });
    value.to_string()
}

/// A case as a finding shows it: the model's `Debug` (which keeps NaN and infinities), the
/// window and the plane, cut to a readable length.
#[must_use]
pub fn describe(case: &ModelCase) -> String {
    let text = format!("{:?} in {:?} at z = {}", case.model, case.window, case.z);
    shorten(&text, 4000)
}

/// `text` cut to at most `max` bytes (at a character boundary), saying how much was cut.
#[must_use]
pub fn shorten(text: &str, max: usize) -> String {
    if text.len() <= max {
        return text.to_owned();
    }
    let mut end = max;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}… ({} more bytes)", &text[..end], text.len() - end)
}

/// Checks that `model`'s file text reads back as validation says it should: a valid model as
/// itself (the round trip `to_json` → `from_json` is exact), an invalid one as an error; and
/// that `to_json` writes exactly the valid models.
///
/// # Errors
/// The property that does not hold.
pub fn check_file_round_trip(model: &Model) -> Result<(), String> {
    let verdict = model.validate();
    let read = spectex_model::from_json(&model_file_text(model));
    let written = spectex_model::to_json(model);
    match (&verdict, read, written) {
        (Ok(()), Ok(back), Ok(text)) => {
            if &back != model {
                return Err(format!(
                    "a valid model reads back from its file text as a different model: {}",
                    shorten(&format!("{back:?}"), 2000)
                ));
            }
            match spectex_model::from_json(&text) {
                Ok(again) if &again == model => Ok(()),
                Ok(_) => Err("to_json's text reads back as a different model".into()),
                Err(e) => Err(format!("to_json's text does not read back: {e}")),
            }
        }
        (Ok(()), Err(e), _) => Err(format!(
            "validation accepts the model but its file text is refused: {e}"
        )),
        (Ok(()), _, Err(e)) => Err(format!(
            "validation accepts the model but to_json refuses it: {e}"
        )),
        (Err(_), Ok(_), _) => Err(format!(
            "validation refuses the model ({}) but its file text is accepted",
            verdict
                .as_ref()
                .err()
                .map(ToString::to_string)
                .unwrap_or_default()
        )),
        (Err(_), _, Ok(_)) => Err("validation refuses the model but to_json writes it".into()),
        (Err(_), Err(_), Err(_)) => Ok(()),
    }
}
