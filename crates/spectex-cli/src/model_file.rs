//! Model files on the command line: read and validated, or validated and written whole.

use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use spectex_model::{Fit, Model, ModelFileContents};

use crate::io;

/// Writes `model` to `path` (which must end in `.json`), through a temporary file renamed into
/// place.
pub(crate) fn write_model(path: &Path, model: &Model) -> Result<()> {
    write_fitted_model(path, model, None)
}

/// [`write_model`], recording the fit that made the model in the file.
pub(crate) fn write_fitted_model(path: &Path, model: &Model, fit: Option<Fit>) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("json") {
        bail!("model file '{}' must end in .json", path.display());
    }
    let text = spectex_model::to_json_with_fit(model, fit)
        .context("internal: the fitted model is invalid")?;
    io::write_text_atomically(path, &text)
}

/// Reads and validates the model file at `path`.
pub(crate) fn read_model(path: &Path) -> Result<Model> {
    read_model_file(path).map(|f| f.model)
}

/// Reads and validates the model file at `path`, with the fit and period it records.
pub(crate) fn read_model_file(path: &Path) -> Result<ModelFileContents> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        anyhow!(
            "cannot open model '{}': {e}; check the path",
            path.display()
        )
    })?;
    spectex_model::from_json_file(&text).map_err(|e| {
        anyhow!(
            "model '{}' is not usable: {e}; write it with `spectex fit` or fix that field",
            path.display()
        )
    })
}
