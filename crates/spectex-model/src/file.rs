//! Model files: versioned JSON (`schema_version`), validated on load and on save.

use serde::{Deserialize, Serialize};

use crate::Model;
use crate::error::ModelError;
use crate::period::Period;

/// The `schema_version` this build writes.
pub const SCHEMA_VERSION: u32 = 1;
/// Every `schema_version` this build reads.
pub const SUPPORTED_SCHEMA_VERSIONS: &[u32] = &[1];

/// Which fit made a model, recorded in its file by `spectex fit` and `spectex synth` (absent
/// from files written otherwise, and from files written before it existed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Fit {
    /// The spectrum-matching fit (`spectex_sampling::FitMethod::Spectrum`, the default).
    Spectrum,
    /// Gilet et al. 2014, §4.3 as printed (`--fit paper`).
    Paper,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelFile {
    schema_version: u32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    fit: Option<Fit>,
    /// `[W, H]`: the model is evaluated exactly periodic with this period ([`crate::period`]).
    /// Absent from files of non-periodic models, so their bytes are unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    period: Option<[u32; 2]>,
    model: Model,
}

/// Everything a model file holds: the model, the fit that made it and its period.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelFileContents {
    /// The model.
    pub model: Model,
    /// The fit recorded by `spectex fit` / `synth` (`None` when absent).
    pub fit: Option<Fit>,
    /// The period a periodic model is evaluated with (`None`: not periodic). Evaluators take it
    /// as an argument (`spectex_cpu::Evaluator::periodic`); [`from_json`] drops it.
    pub period: Option<Period>,
}

/// Reads a model from its JSON text: checks `schema_version` first (so an old or new file gets
/// a message about versions, not about fields), then the shape (unknown fields are rejected),
/// then every value.
///
/// # Errors
/// Malformed JSON, an unsupported `schema_version`, an unknown or missing field, or a value
/// out of range.
pub fn from_json(text: &str) -> Result<Model, ModelError> {
    from_json_with_fit(text).map(|(model, _)| model)
}

/// [`from_json`], also returning the fit the file records (`"fit": "spectrum"` or `"paper"`;
/// `None` when absent). Any other value is an error naming the valid ones.
///
/// # Errors
/// As [`from_json`].
pub fn from_json_with_fit(text: &str) -> Result<(Model, Option<Fit>), ModelError> {
    from_json_file(text).map(|c| (c.model, c.fit))
}

/// [`from_json`], also returning the fit and the period the file records; a period is checked
/// against the model ([`Model::check_period`]).
///
/// # Errors
/// As [`from_json`], or a period out of range or one the model cannot take.
pub fn from_json_file(text: &str) -> Result<ModelFileContents, ModelError> {
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
    let period = file.period.map(|[w, h]| Period::new(w, h)).transpose()?;
    if let Some(p) = period {
        file.model.check_period(p)?;
    }
    Ok(ModelFileContents {
        model: file.model,
        fit: file.fit,
        period,
    })
}

/// Writes a model as pretty JSON with the current `schema_version`, after validating it.
///
/// # Errors
/// A value out of range (a model that could not be read back).
pub fn to_json(model: &Model) -> Result<String, ModelError> {
    to_json_with_fit(model, None)
}

/// [`to_json`] recording the fit that made the model (no `fit` field for `None`).
///
/// # Errors
/// As [`to_json`].
pub fn to_json_with_fit(model: &Model, fit: Option<Fit>) -> Result<String, ModelError> {
    to_json_file(model, fit, None)
}

/// [`to_json_with_fit`] recording a period too (no `period` field for `None`).
///
/// # Errors
/// As [`to_json`], or a period the model cannot take.
pub fn to_json_file(
    model: &Model,
    fit: Option<Fit>,
    period: Option<Period>,
) -> Result<String, ModelError> {
    model.validate()?;
    if let Some(p) = period {
        model.check_period(p)?;
    }
    let file = ModelFile {
        schema_version: SCHEMA_VERSION,
        fit,
        period: period.map(|p| p.to_array()),
        model: model.clone(),
    };
    Ok(serde_json::to_string_pretty(&file)?)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn a_file_records_the_fit_that_made_it() {
        let model = Model::Gabor(crate::fixtures::gabor_isotropic());
        let text = to_json_with_fit(&model, Some(Fit::Paper)).unwrap();
        assert!(text.contains("\"fit\": \"paper\""), "{text}");
        assert_eq!(
            from_json_with_fit(&text).unwrap(),
            (model.clone(), Some(Fit::Paper))
        );
        // Without a fit, no field: files written before it existed read the same.
        let plain = to_json(&model).unwrap();
        assert!(!plain.contains("\"fit\""));
        assert_eq!(from_json_with_fit(&plain).unwrap(), (model.clone(), None));
        // A period round-trips; a kind without a periodic form refuses it, naming the period.
        let lrp = Model::Lrp(crate::fixtures::lrp_four_strata(4));
        let p = Period::new(96, 64).unwrap();
        let periodic = to_json_file(&lrp, None, Some(p)).unwrap();
        assert!(periodic.contains("\"period\""), "{periodic}");
        let back = from_json_file(&periodic).unwrap();
        assert_eq!((back.model, back.period), (lrp, Some(p)));
        // 97×64: no common divisor near a Gabor kernel's radius.
        let odd = Period::new(97, 64).unwrap();
        let refused = to_json_file(&model, None, Some(odd))
            .unwrap_err()
            .to_string();
        assert!(
            refused.contains("period 97x64") && refused.contains("gabor"),
            "{refused}"
        );
        let zero = periodic.replace("96,", "0,");
        let err = from_json_file(&zero).unwrap_err().to_string();
        assert!(err.contains("period.width"), "{err}");
        let unknown = text.replace("\"paper\"", "\"magic\"");
        let err = from_json(&unknown).unwrap_err().to_string();
        assert!(err.contains("spectrum") && err.contains("paper"), "{err}");
    }
}
