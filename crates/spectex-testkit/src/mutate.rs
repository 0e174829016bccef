//! Mutations of model file texts (the shipped `testdata/models/*.json`, or any): a field deleted,
//! a value of another type, a number perturbed (negated, scaled past f32's range, made
//! fractional for an integer, pushed past `u32`), a list emptied or repeated, an unknown field
//! added; and mutations of the bytes themselves (truncation, a byte changed, nesting past the
//! JSON reader's recursion limit).

use proptest::prelude::*;
use proptest::sample::Index;
use serde_json::Value;

/// A JSON text with the paths (JSON pointers) of all its nodes, computed once per text.
#[derive(Debug, Clone)]
pub struct Subject {
    /// A name for findings (the file stem).
    pub name: String,
    /// The original text.
    pub text: String,
    value: Value,
    paths: Vec<String>,
}

impl Subject {
    /// Parses `text`.
    ///
    /// # Panics
    /// When `text` is not JSON (subjects are known-good files).
    #[must_use]
    pub fn new(name: &str, text: &str) -> Self {
        let value: Value =
            serde_json::from_str(text).unwrap_or_else(|e| panic!("{name} is not JSON: {e}"));
        let mut paths = Vec::new();
        collect_paths(&value, String::new(), &mut paths);
        Self {
            name: name.to_owned(),
            text: text.to_owned(),
            value,
            paths,
        }
    }
}

fn collect_paths(v: &Value, here: String, out: &mut Vec<String>) {
    match v {
        Value::Object(map) => {
            for (k, child) in map {
                let key = k.replace('~', "~0").replace('/', "~1");
                collect_paths(child, format!("{here}/{key}"), out);
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                collect_paths(child, format!("{here}/{i}"), out);
            }
        }
        _ => {}
    }
    out.push(here);
}

/// What to do to one node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edit {
    /// Remove it from its object or array.
    Delete,
    /// Replace it by `null`.
    Null,
    /// Replace it by a string.
    Text,
    /// Replace it by `true`.
    Bool,
    /// Replace it by `[]`.
    EmptyList,
    /// Replace it by `{}`.
    EmptyObject,
    /// Negate a number.
    Negate,
    /// Multiply a number by 1000.
    Grow,
    /// A number past f32's range (`1e39`: read as f32 infinity).
    PastF32,
    /// A number past f64's range (`1e400`).
    PastF64,
    /// A number past `u32` (`4294967296`).
    PastU32,
    /// An integer made fractional (`+ 0.5`).
    Fraction,
    /// Zero.
    Zero,
    /// A list or object repeated ten times (lists) / an unknown field added (objects).
    Repeat,
}

/// Edits and their weights: numbers changed within their type more often than types broken, so
/// that a good share of mutated files is still valid and gets evaluated.
const EDITS: &[(u32, Edit)] = &[
    (2, Edit::Delete),
    (1, Edit::Null),
    (1, Edit::Text),
    (1, Edit::Bool),
    (1, Edit::EmptyList),
    (1, Edit::EmptyObject),
    (4, Edit::Negate),
    (4, Edit::Grow),
    (1, Edit::PastF32),
    (1, Edit::PastF64),
    (1, Edit::PastU32),
    (4, Edit::Fraction),
    (4, Edit::Zero),
    (2, Edit::Repeat),
];

fn edit() -> BoxedStrategy<Edit> {
    proptest::strategy::Union::new_weighted(
        EDITS.iter().map(|&(w, e)| (w, Just(e).boxed())).collect(),
    )
    .boxed()
}

/// What to do to the text.
#[derive(Debug, Clone)]
pub enum Mutation {
    /// Edits of nodes (by index into the subject's paths).
    Nodes(Vec<(Index, Edit)>),
    /// The text cut at a byte.
    Truncate(Index),
    /// One byte replaced.
    Byte(Index, u8),
    /// The model wrapped in `depth` arrays (past serde_json's recursion limit of 128 at 200).
    Nest(usize),
}

/// Mutations: mostly one or two node edits, sometimes byte-level ones.
pub fn mutation() -> BoxedStrategy<Mutation> {
    prop_oneof![
        12 => proptest::collection::vec((any::<Index>(), edit()), 1..=2).prop_map(Mutation::Nodes),
        2 => any::<Index>().prop_map(Mutation::Truncate),
        2 => (any::<Index>(), any::<u8>()).prop_map(|(i, b)| Mutation::Byte(i, b)),
        1 => prop_oneof![Just(5usize), Just(127), Just(200), Just(100_000)].prop_map(Mutation::Nest),
    ]
    .boxed()
}

/// Markers replaced after serialisation by numbers `serde_json::Value` cannot hold.
const PAST_F64: &str = "@@past-f64@@";

/// Applies `m` to `subject`, returning the new text and a description of what was done.
#[must_use]
pub fn apply(subject: &Subject, m: &Mutation) -> (String, String) {
    match m {
        Mutation::Nodes(edits) => {
            let mut value = subject.value.clone();
            let mut done = Vec::new();
            for (index, edit) in edits {
                let path = &subject.paths[index.index(subject.paths.len())];
                if edit_node(&mut value, path, *edit) {
                    done.push(format!("{edit:?} at {path:?}"));
                }
            }
            let text = value
                .to_string()
                .replace(&format!("\"{PAST_F64}\""), "1e400");
            (text, done.join(", "))
        }
        Mutation::Truncate(index) => {
            let mut end = index.index(subject.text.len().max(1));
            while !subject.text.is_char_boundary(end) {
                end -= 1;
            }
            (
                subject.text[..end].to_owned(),
                format!("truncated to {end} bytes"),
            )
        }
        Mutation::Byte(index, byte) => {
            let mut bytes = subject.text.as_bytes().to_vec();
            let at = index
                .index(bytes.len().max(1))
                .min(bytes.len().saturating_sub(1));
            if let Some(b) = bytes.get_mut(at) {
                *b = *byte;
            }
            (
                String::from_utf8_lossy(&bytes).into_owned(),
                format!("byte {at} set to {byte:#04x}"),
            )
        }
        Mutation::Nest(depth) => {
            let model = subject
                .value
                .get("model")
                .map_or_else(String::new, Value::to_string);
            let text = format!(
                "{{\"schema_version\": 1, \"model\": {}{model}{}}}",
                "[".repeat(*depth),
                "]".repeat(*depth)
            );
            (text, format!("model nested in {depth} arrays"))
        }
    }
}

/// Edits the node at `path`; `false` when it no longer exists (an earlier edit removed it) or the
/// edit does not apply to it.
fn edit_node(root: &mut Value, path: &str, edit: Edit) -> bool {
    if edit == Edit::Delete {
        let Some((parent, last)) = path.rsplit_once('/') else {
            return false;
        };
        let key = last.replace("~1", "/").replace("~0", "~");
        return match root.pointer_mut(parent) {
            Some(Value::Object(map)) => map.remove(&key).is_some(),
            Some(Value::Array(items)) => match key.parse::<usize>() {
                Ok(i) if i < items.len() => {
                    items.remove(i);
                    true
                }
                _ => false,
            },
            _ => false,
        };
    }
    let Some(node) = root.pointer_mut(path) else {
        return false;
    };
    let number = node.as_f64();
    let replacement = match (edit, &*node) {
        (Edit::Null, _) => Value::Null,
        (Edit::Text, _) => Value::from("not a number"),
        (Edit::Bool, _) => Value::from(true),
        (Edit::EmptyList, _) => Value::Array(Vec::new()),
        (Edit::EmptyObject, _) => Value::Object(serde_json::Map::new()),
        (Edit::PastF32, _) => Value::from(1e39),
        (Edit::PastF64, _) => Value::from(PAST_F64),
        (Edit::PastU32, _) => Value::from(4_294_967_296u64),
        (Edit::Zero, _) => Value::from(0),
        (Edit::Negate, Value::Number(n)) => match (n.as_i64(), number) {
            (Some(i), _) => Value::from(i.wrapping_neg()),
            (None, Some(f)) => Value::from(-f),
            _ => return false,
        },
        (Edit::Grow, Value::Number(_)) => match number {
            Some(f) => Value::from(f * 1000.0),
            None => return false,
        },
        (Edit::Fraction, Value::Number(_)) => match number {
            Some(f) => Value::from(f + 0.5),
            None => return false,
        },
        (Edit::Repeat, Value::Array(items)) => {
            let items = items.clone();
            Value::Array((0..10).flat_map(|_| items.iter().cloned()).collect())
        }
        (Edit::Repeat, Value::Object(map)) => {
            let mut map = map.clone();
            map.insert("unknown_field".into(), Value::from(1));
            Value::Object(map)
        }
        _ => return false,
    };
    *node = replacement;
    true
}
