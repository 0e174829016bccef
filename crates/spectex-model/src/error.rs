//! The error type of spectex-model: loading and validating models.

/// Why a model could not be loaded or is not valid. Messages name the field, the value and the
/// accepted range.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The text is not JSON, or not a model of a known shape (unknown field, missing field, …).
    #[error("the model is not valid JSON for spectex: {0}")]
    Json(#[from] serde_json::Error),
    /// `schema_version` is missing or one this build does not understand.
    #[error(
        "schema_version {found} is not understood; this build of spectex reads schema_version {supported}"
    )]
    SchemaVersion {
        /// What the file says (`missing` if absent).
        found: String,
        /// Versions this build reads.
        supported: String,
    },
    /// A numeric field is NaN, infinite or outside its range.
    #[error("{field} = {value} is outside its valid range {range}")]
    OutOfRange {
        /// Dotted path of the field, e.g. `strata[2].window_width`.
        field: String,
        /// The value found.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
    /// A period the model cannot be made periodic with (`--periodic`, a file's `period`).
    #[error("period {period} cannot be used with this {kind} model: {requirement}")]
    Period {
        /// The period asked for, `WxH`.
        period: String,
        /// The model kind.
        kind: &'static str,
        /// What the kind needs of a period (or that it has no periodic form).
        requirement: String,
    },
    /// A simulation's rule string is malformed (`spectex_model::simulation`).
    #[error("{field} = '{value}' is not a valid rule; write {expected}")]
    SimulationRule {
        /// Dotted path of the field.
        field: String,
        /// The value found.
        value: String,
        /// The accepted form.
        expected: &'static str,
    },
    /// A list has a length outside its range.
    #[error("{field} has {len} entries; it must have {range}")]
    Length {
        /// Dotted path of the field.
        field: String,
        /// Entries found.
        len: usize,
        /// The accepted count.
        range: &'static str,
    },
}

/// Checks a constant or a gain (a mean, an amplitude): finite and within `[−1e9, 1e9]`.
pub(crate) fn check_level(field: impl FnOnce() -> String, value: f32) -> Result<(), ModelError> {
    check_range(field, f64::from(value), -1e9, 1e9, "[-1e9, 1e9]")
}

/// Checks that `value` is finite and within `[min, max]`. A bound that f32 cannot hold (0.01,
/// π) is also met by the f32 nearest it: that is what a model file writing the bound reads as
/// (`0.01` is 0.0099999998 as f32), and it must not be refused.
pub(crate) fn check_range(
    field: impl FnOnce() -> String,
    value: f64,
    min: f64,
    max: f64,
    range: &'static str,
) -> Result<(), ModelError> {
    let at_f32_bound = |bound: f64| value == f64::from(bound as f32);
    if value.is_finite()
        && (value >= min || at_f32_bound(min))
        && (value <= max || at_f32_bound(max))
    {
        Ok(())
    } else {
        Err(ModelError::OutOfRange {
            field: field(),
            value,
            range,
        })
    }
}

/// Checks that a list length is within `[min, max]`.
pub(crate) fn check_len(
    field: impl FnOnce() -> String,
    len: usize,
    min: usize,
    max: usize,
    range: &'static str,
) -> Result<(), ModelError> {
    if (min..=max).contains(&len) {
        Ok(())
    } else {
        Err(ModelError::Length {
            field: field(),
            len,
            range,
        })
    }
}

/// Checks an image stored in a model: `width` and `height` in `[1, 1024]` texels, `width·height`
/// texels of `C` levels each (row-major), every level finite within `[−1e9, 1e9]`. Field paths
/// are `{at}.width`, `{at}.height`, `{at}.{texels}` and `{at}.{texels}[k]` (`[k][n]` when a texel
/// has several channels).
pub(crate) fn check_image<const C: usize>(
    at: &str,
    width: u32,
    height: u32,
    texels_name: &str,
    texels: &[[f32; C]],
) -> Result<(), ModelError> {
    for (name, side) in [("width", width), ("height", height)] {
        check_range(
            || format!("{at}.{name}"),
            f64::from(side),
            1.0,
            f64::from(MAX_IMAGE_SIDE),
            "[1, 1024] texels",
        )?;
    }
    let n = (width as usize) * (height as usize);
    check_len(
        || format!("{at}.{texels_name}"),
        texels.len(),
        n,
        n,
        "width·height texels",
    )?;
    for (k, texel) in texels.iter().enumerate() {
        for (c, &v) in texel.iter().enumerate() {
            check_level(
                || match C {
                    1 => format!("{at}.{texels_name}[{k}]"),
                    _ => format!("{at}.{texels_name}[{k}][{c}]"),
                },
                v,
            )?;
        }
    }
    Ok(())
}

/// Largest side of an image stored in a model (a texton's spot, Voronoi colours), texels.
pub(crate) const MAX_IMAGE_SIDE: u32 = 1024;

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn a_bound_is_met_by_the_f32_nearest_it() {
        let check =
            |v: f32, lo: f64, hi: f64| check_range(|| "f".into(), f64::from(v), lo, hi, "r");
        // 0.01f32 lies below 0.01 and π as f32 above π: both are the bound a file writes.
        assert!(check(0.01, 0.01, 1000.0).is_ok());
        assert!(check(std::f32::consts::PI, 0.0, std::f64::consts::PI).is_ok());
        assert!(check(0.01f32.next_down(), 0.01, 1000.0).is_err());
        assert!(check(std::f32::consts::PI.next_up(), 0.0, std::f64::consts::PI).is_err());
        assert!(check(f32::NAN, 0.0, 1.0).is_err());
    }
}
