//! The shader registry: every WGSL file of `shaders/`, embedded with `include_str!`, and how a
//! module is composed at load time (the common module prepended to each model shader).
//!
//! `tests/shaders.rs` checks that this table and the files in `shaders/` match exactly and that
//! every composed module parses and validates with naga.

/// The WGSL twin of the randomness contract and of the CPU's scalar functions.
const COMMON: &str = include_str!("../../../shaders/common.wgsl");

/// One WGSL file of `shaders/`.
#[derive(Debug, Clone, Copy)]
pub struct ShaderFile {
    /// File name without `.wgsl`.
    pub name: &'static str,
    /// The file's text.
    pub source: &'static str,
    /// Whether [`wgsl_source`] prepends `common.wgsl` to it.
    pub needs_common: bool,
    /// The compute entry points it defines (empty for a library module).
    pub entry_points: &'static [&'static str],
}

/// Every file of `shaders/`, by name.
pub const SHADERS: &[ShaderFile] = &[
    ShaderFile {
        name: "common",
        source: COMMON,
        needs_common: false,
        entry_points: &[],
    },
    ShaderFile {
        name: "lrp",
        source: include_str!("../../../shaders/lrp.wgsl"),
        needs_common: true,
        entry_points: &["lrp_main"],
    },
    ShaderFile {
        name: "gabor",
        source: include_str!("../../../shaders/gabor.wgsl"),
        needs_common: true,
        entry_points: &["gabor_main"],
    },
    ShaderFile {
        name: "phasor",
        source: include_str!("../../../shaders/phasor.wgsl"),
        needs_common: true,
        entry_points: &["phasor_main"],
    },
    ShaderFile {
        name: "texture",
        source: include_str!("../../../shaders/texture.wgsl"),
        needs_common: true,
        entry_points: &["texture_main"],
    },
    ShaderFile {
        name: "classic",
        source: include_str!("../../../shaders/classic.wgsl"),
        needs_common: true,
        entry_points: &["classic_main"],
    },
    ShaderFile {
        name: "wavelet",
        source: include_str!("../../../shaders/wavelet.wgsl"),
        needs_common: true,
        entry_points: &["wavelet_main"],
    },
    ShaderFile {
        name: "probe",
        source: include_str!("../../../shaders/probe.wgsl"),
        needs_common: true,
        entry_points: &["probe_integers", "probe_floats"],
    },
];

/// The complete WGSL module `name` as the device receives it (`common.wgsl` first where the
/// file needs it), or `None` for a name not in [`SHADERS`].
#[must_use]
pub fn wgsl_source(name: &str) -> Option<String> {
    let file = SHADERS.iter().find(|f| f.name == name)?;
    Some(if file.needs_common {
        format!("{COMMON}\n// ---- {name}.wgsl ----\n{}", file.source)
    } else {
        file.source.to_owned()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_composition_prepends_common() {
        for (i, a) in SHADERS.iter().enumerate() {
            assert!(
                SHADERS[i + 1..].iter().all(|b| b.name != a.name),
                "{}",
                a.name
            );
        }
        let lrp = wgsl_source("lrp").unwrap_or_default();
        assert!(lrp.starts_with(COMMON) && lrp.contains("fn lrp_main"));
        assert_eq!(wgsl_source("common").as_deref(), Some(COMMON));
        assert!(wgsl_source("nope").is_none());
    }
}
