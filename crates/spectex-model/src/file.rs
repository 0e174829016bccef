//! Model files: versioned JSON (`schema_version`), validated on load and on save.

use serde::{Deserialize, Serialize};

use crate::Model;
use crate::error::ModelError;

/// The `schema_version` this build writes.
pub const SCHEMA_VERSION: u32 = 1;
/// Every `schema_version` this build reads.
pub const SUPPORTED_SCHEMA_VERSIONS: &[u32] = &[1];

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelFile {
    schema_version: u32,
    model: Model,
}

/// Reads a model from its JSON text: checks `schema_version` first (so an old or new file gets
/// a message about versions, not about fields), then the shape (unknown fields are rejected),
/// then every value.
///
/// # Errors
/// Malformed JSON, an unsupported `schema_version`, an unknown or missing field, or a value
/// out of range.
pub fn from_json(text: &str) -> Result<Model, ModelError> {
    let value: serde_json::Value = serde_json::from_str(text)?;
    let supported = SUPPORTED_SCHEMA_VERSIONS
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    match value.get("schema_version") {
        Some(v)
            if v.as_u64()
                .is_some_and(|n| SUPPORTED_SCHEMA_VERSIONS.iter().any(|&s| u64::from(s) == n)) => {}
        Some(v) => {
            return Err(ModelError::SchemaVersion {
                found: v.to_string(),
                supported,
            });
        }
        None => {
            return Err(ModelError::SchemaVersion {
                found: "missing".into(),
                supported,
            });
        }
    }
    let file: ModelFile = serde_json::from_value(value)?;
    file.model.validate()?;
    Ok(file.model)
}

/// Writes a model as pretty JSON with the current `schema_version`, after validating it.
///
/// # Errors
/// A value out of range (a model that could not be read back).
pub fn to_json(model: &Model) -> Result<String, ModelError> {
    model.validate()?;
    let file = ModelFile {
        schema_version: SCHEMA_VERSION,
        model: model.clone(),
    };
    Ok(serde_json::to_string_pretty(&file)?)
}
