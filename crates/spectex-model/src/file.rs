//! Model files: versioned JSON (`schema_version`), validated on load and on save.

use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::{ClassicNoise, GaborNoise, LrpNoise, PhasorNoise, TextureModel, Warp, WaveletNoise};

/// The `schema_version` this build writes.
pub const SCHEMA_VERSION: u32 = 1;
/// Every `schema_version` this build reads.
pub const SUPPORTED_SCHEMA_VERSIONS: &[u32] = &[1];

/// Any procedural model spectex evaluates: one variant per kind, each a [`crate::ModelKind`].
///
/// Deliberately not `#[non_exhaustive]`: a `match` over it in another crate must name every
/// kind, so the compiler points at each place a new kind is missed (the tidy test forbids
/// wildcard arms over `Model` outside this crate).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
#[allow(
    clippy::large_enum_variant,
    reason = "a model is built once per render and never stored in bulk"
)]
pub enum Model {
    /// Local Random-Phase noise.
    Lrp(LrpNoise),
    /// Gabor noise.
    Gabor(GaborNoise),
    /// Phasor noise.
    Phasor(PhasorNoise),
    /// Texture by example: structure, strata, turbulence, placement, colour.
    Texture(TextureModel),
    /// A classic pointwise noise (gradient, simplex, value, Worley; fractal sums of them).
    Classic(ClassicNoise),
    /// Domain warping: a model evaluated at positions displaced by two others
    /// ([`crate::warp`]).
    Warp(Warp),
    /// Wavelet noise (Cook & DeRose 2005): a band-limited tile summed over octave bands.
    Wavelet(WaveletNoise),
}

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
