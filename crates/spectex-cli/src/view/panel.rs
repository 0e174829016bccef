//! The parameter panel's description of a model, found by probing the model's own validation:
//! each numeric field is set, one at a time, to a value far out of any range, and the error
//! `spectex-model` gives (`{field} = {value} is outside its valid range {range}`) names the
//! field's range; a string field set to a value no kind uses gets serde's list of the variants
//! it accepts. No list of kinds or fields is kept here: every kind, nested ones included, is
//! described by the validation it already has.

use serde::Deserialize as _;
use serde_json::{Map, Value, json};
use spectex_model::simulation::SimulationSpec;
use spectex_model::{Model, ModelError};

/// Lists longer than this are not entered (a fitted model's frequencies): shown as a count.
const MAX_LIST: usize = 16;
/// Fields described at most (the rest are shown without a range).
const MAX_FIELDS: usize = 400;

/// Whether the model in `json` (`{"kind": {…}}`) deserializes and validates.
pub(crate) fn check(json: &Value) -> Result<Model, ModelError> {
    let model = Model::deserialize(json)?;
    model.validate()?;
    Ok(model)
}

/// Whether the simulation spec in `json` deserializes and validates.
pub(crate) fn check_simulation(json: &Value) -> Result<SimulationSpec, ModelError> {
    let spec = SimulationSpec::deserialize(json)?;
    spec.validate()?;
    Ok(spec)
}

/// What the panel probes: deserialization and validation of the whole value.
type Check<'a> = &'a dyn Fn(&Value) -> Result<(), ModelError>;

/// The panel description of the model `json`: `{"fields": {pointer: field}}`, where a numeric
/// field is `{"min", "max", "min_open", "max_open", "range", "integer"}` (`min`/`max` null where
/// the range has no numeric bound) and a string field with a fixed set of values is
/// `{"options": […]}`. Pointers are JSON pointers into `json`.
pub(crate) fn describe(json: &Value) -> Value {
    describe_with(json, &|v| check(v).map(|_| ()))
}

/// [`describe`] of a value that `check` validates (a model, a simulation spec).
pub(crate) fn describe_with(json: &Value, check: Check<'_>) -> Value {
    let mut leaves = Vec::new();
    collect(json, String::new(), &mut leaves);
    let mut probe = json.clone();
    let mut fields = Map::new();
    for (pointer, segment) in leaves.into_iter().take(MAX_FIELDS) {
        let Some(original) = probe.pointer(&pointer).cloned() else {
            continue;
        };
        let described = match &original {
            Value::Number(n) => describe_number(&mut probe, &pointer, &segment, n.is_f64(), check),
            Value::String(_) => describe_string(&mut probe, &pointer, check),
            _ => None,
        };
        if let Some(slot) = probe.pointer_mut(&pointer) {
            *slot = original;
        }
        if let Some(d) = described {
            fields.insert(pointer, d);
        }
    }
    json!({ "fields": fields })
}

/// The leaves (numbers and strings) of `value` under `pointer`, with the name validation gives
/// their last path segment (`key` or `key[k]`).
fn collect(value: &Value, pointer: String, out: &mut Vec<(String, String)>) {
    match value {
        Value::Object(map) => {
            for (key, v) in map {
                let p = format!("{pointer}/{}", key.replace('~', "~0").replace('/', "~1"));
                match v {
                    Value::Array(items) if items.len() <= MAX_LIST => {
                        for (k, item) in items.iter().enumerate() {
                            let pk = format!("{p}/{k}");
                            if item.is_number() || item.is_string() {
                                out.push((pk, format!("{key}[{k}]")));
                            } else {
                                collect(item, pk, out);
                            }
                        }
                    }
                    Value::Array(_) => {}
                    Value::Number(_) | Value::String(_) => out.push((p, key.clone())),
                    _ => collect(v, p, out),
                }
            }
        }
        Value::Array(items) if items.len() <= MAX_LIST => {
            for (k, item) in items.iter().enumerate() {
                collect(item, format!("{pointer}/{k}"), out);
            }
        }
        _ => {}
    }
}

/// What validation says of the model with the field at `pointer` set to `candidate`.
fn probe(
    json: &mut Value,
    pointer: &str,
    candidate: Value,
    check: Check<'_>,
) -> Result<(), ModelError> {
    if let Some(slot) = json.pointer_mut(pointer) {
        *slot = candidate;
    }
    check(json)
}

/// The last segment of a validation error's dotted field path (`a.b[2].c (unit)` → `c`).
fn last_segment(field: &str) -> &str {
    let field = field.split(' ').next().unwrap_or(field);
    field.rsplit('.').next().unwrap_or(field)
}

/// The range of the numeric field at `pointer` (last segment `segment`).
fn describe_number(
    json: &mut Value,
    pointer: &str,
    segment: &str,
    float: bool,
    check: Check<'_>,
) -> Option<Value> {
    let range_of = |result: Result<(), ModelError>| match result {
        Err(ModelError::OutOfRange { field, range, .. }) if last_segment(&field) == segment => {
            Some(Ok(range))
        }
        Ok(()) => None,
        Err(e) => Some(Err(e.to_string())),
    };
    if float {
        for candidate in [1e300, -1e300] {
            if let Some(Ok(range)) = range_of(probe(json, pointer, json!(candidate), check)) {
                return Some(numeric(range, false));
            }
        }
        return Some(
            json!({ "min": null, "max": null, "range": "any finite number",
                            "integer": false, "min_open": false, "max_open": false }),
        );
    }
    // Whole numbers: the type's bounds (serde refuses a value out of them), then validation's.
    let mut bounds = [None, None];
    for (side, candidates) in [
        (1, &[4_294_967_295i64, 65_535, 255][..]),
        (0, &[-2_147_483_648i64, 0][..]),
    ] {
        for &candidate in candidates {
            match range_of(probe(json, pointer, json!(candidate), check)) {
                Some(Ok(range)) => return Some(numeric(range, true)),
                None => {
                    bounds[side] = Some(candidate);
                    break;
                }
                Some(Err(_)) => {}
            }
        }
    }
    let [min, max] = bounds;
    Some(json!({
        "min": min, "max": max, "min_open": false, "max_open": false, "integer": true,
        "range": format!("[{}, {}]",
            min.map_or("?".to_owned(), |v| v.to_string()),
            max.map_or("?".to_owned(), |v| v.to_string())),
    }))
}

/// A numeric field's description from its validation range text (`[0, 1e6] pixels`).
fn numeric(range: &str, integer: bool) -> Value {
    let parsed = parse_range(range);
    json!({
        "min": parsed.map(|r| r.0),
        "max": parsed.map(|r| r.1),
        "min_open": range.starts_with('('),
        "max_open": parsed.is_some_and(|r| r.2),
        "range": range,
        "integer": integer,
    })
}

/// The numeric bounds of a range text `[a, b]`, `(a, b]` … and whether `b` is excluded; `None`
/// bounds where the text names another field (`[min, 1000]`), `None` for other texts.
#[allow(clippy::type_complexity)]
fn parse_range(range: &str) -> Option<(Option<f64>, Option<f64>, bool)> {
    let open = range.chars().next()?;
    if open != '[' && open != '(' {
        return None;
    }
    let close = range.find([']', ')'])?;
    let inner = &range[open.len_utf8()..close];
    let (a, b) = inner.split_once(',')?;
    Some((
        bound(a.trim()),
        bound(b.trim()),
        range[close..].starts_with(')'),
    ))
}

/// A bound's value: a number, `π`, `a^b`, `a/b`, with a sign (`−` too); `None` otherwise.
fn bound(text: &str) -> Option<f64> {
    let text = text.replace('−', "-");
    if let Some(rest) = text.strip_prefix('-') {
        return bound(rest).map(|v| -v);
    }
    if text == "π" {
        return Some(std::f64::consts::PI);
    }
    if let Some((a, b)) = text.split_once('^') {
        return Some(bound(a)?.powf(bound(b)?));
    }
    if let Some((a, b)) = text.split_once('/') {
        return Some(bound(a)? / bound(b)?);
    }
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The values a string field accepts, from serde's `unknown variant` message.
fn describe_string(json: &mut Value, pointer: &str, check: Check<'_>) -> Option<Value> {
    let Err(ModelError::Json(e)) = probe(json, pointer, json!("\u{1}"), check) else {
        return None;
    };
    let text = e.to_string();
    let expected = text.split("expected").nth(1)?;
    let options: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    (!options.is_empty()).then(|| json!({ "options": options }))
}
