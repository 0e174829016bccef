//! The shader registry: every WGSL file of `shaders/`, embedded with `include_str!`, and how a
//! module is composed at load time (the common module prepended to each model shader). A
//! kind's file is its compute shader, then from the [`GLUE_MARKER`] line its export glue
//! ([`crate::export::EXPORT_SHADERS`]); [`SHADERS`] holds the compute part.
//!
//! `tests/it/shaders.rs` checks that this table and the files in `shaders/` match exactly and that
//! every composed module parses and validates with naga.

/// The WGSL twin of the randomness contract and of the CPU's scalar functions.
use std::sync::LazyLock;

use crate::kernel::GpuKind;

const COMMON: &str = include_str!("../shaders/common.wgsl");

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

/// The start of the line of a kind's `shaders/<kind>.wgsl` that ends its compute shader and
/// starts its export glue (`spectex export --wgsl`, [`crate::export`]).
pub const GLUE_MARKER: &str = "// ---- export glue";

/// A kind's `shaders/<kind>.wgsl` split at its [`GLUE_MARKER`] line: the compute shader before
/// it (empty for a kind without one: warp, combine) and the export glue from it. Evaluated at
/// compile time, so a kind's file without the line does not compile.
pub(crate) const fn kernel_and_glue(text: &'static str) -> (&'static str, &'static str) {
    let bytes = text.as_bytes();
    let marker = GLUE_MARKER.as_bytes();
    let mut at = 0;
    while at + marker.len() <= bytes.len() {
        if at == 0 || bytes[at - 1] == b'\n' {
            let mut k = 0;
            while k < marker.len() && bytes[at + k] == marker[k] {
                k += 1;
            }
            if k == marker.len() {
                return text.split_at(at);
            }
        }
        at += 1;
    }
    panic!("a kind's shader has no `// ---- export glue` line");
}

/// Every file of `shaders/`, by name.
pub static SHADERS: LazyLock<Vec<ShaderFile>> = LazyLock::new(|| {
    let mut files = vec![
        ShaderFile {
            name: "common",
            source: COMMON,
            needs_common: false,
            entry_points: &[],
        },
        ShaderFile {
            name: "simulate",
            source: include_str!("../shaders/simulate.wgsl"),
            needs_common: false,
            entry_points: &[
                "gray_scott_step",
                "life_step",
                "cyclic_step",
                "elementary_step",
                "elementary_tick",
            ],
        },
        ShaderFile {
            name: "output",
            source: include_str!("../shaders/output.wgsl"),
            needs_common: false,
            entry_points: &["pack_unorm8", "pack_unorm16", "pack_f16"],
        },
        ShaderFile {
            name: "compose",
            source: include_str!("../shaders/compose.wgsl"),
            needs_common: false,
            entry_points: &["warp_displace", "warp_displace_range"],
        },
        ShaderFile {
            name: "exact",
            source: include_str!("../shaders/exact.wgsl"),
            needs_common: true,
            entry_points: &[],
        },
        ShaderFile {
            name: "probe",
            source: include_str!("../shaders/probe.wgsl"),
            needs_common: true,
            entry_points: &["probe_integers", "probe_floats"],
        },
    ];
    // Each kind's compute shader, as the kind declares it (`GpuKind::SHADER`: its file up to
    // the export glue).
    spectex_model::for_each_kind!(types: K => {
        if let Some(file) = <K as GpuKind>::SHADER {
            files.push(file);
        }
    });
    files
});

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

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// Parses and validates the composed module `name`, panicking with naga's annotated source.
    fn parse(name: &str) -> (naga::Module, naga::valid::ModuleInfo) {
        let source = wgsl_source(name).unwrap_or_default();
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{name}.wgsl:\n{}", e.emit_to_string(&source)));
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}.wgsl:\n{}", e.emit_to_string(&source)));
        (module, info)
    }

    /// A model shader's pipeline layout is derived from the shader (`layout: None`), and such a
    /// layout holds only the bindings its entry point uses, while the host binds every binding
    /// the file declares (`pipeline::Shaded`): so in a model shader (composed after
    /// `common.wgsl`, one entry point) that entry point must use them all. Group 0 must also follow the convention the
    /// host binds by: the uniform at 0, read-only tables at 1, 2, … (storage, or a uniform
    /// array: `kernel::Table::uniform`) and the output last; group 1
    /// is `common.wgsl`'s displacement. (The probe's two entry points bind disjoint halves of
    /// its group 0, and its tests bind each half on its own.)
    pub fn model_shaders_use_every_binding_in_the_host_order() {
        use naga::{AddressSpace, StorageAccess};
        for file in SHADERS
            .iter()
            .filter(|f| f.needs_common && f.entry_points.len() == 1)
        {
            let (module, info) = parse(file.name);
            let uses = info.get_entry_point(0);
            let mut group0 = Vec::new();
            let mut group1 = Vec::new();
            for (handle, var) in module.global_variables.iter() {
                let Some(binding) = &var.binding else {
                    continue;
                };
                let name = var.name.as_deref().unwrap_or("?");
                assert!(
                    !uses[handle].is_empty(),
                    "{}.wgsl: {} does not use @group({}) @binding({}) {name}",
                    file.name,
                    file.entry_points[0],
                    binding.group,
                    binding.binding
                );
                match binding.group {
                    0 => group0.push((binding.binding, var.space)),
                    1 => group1.push((binding.binding, name)),
                    g => panic!("{}.wgsl: {name} in group {g}", file.name),
                }
            }
            group0.sort_by_key(|(b, _)| *b);
            group1.sort_unstable();
            let read = AddressSpace::Storage {
                access: StorageAccess::LOAD,
            };
            let write = AddressSpace::Storage {
                access: StorageAccess::LOAD | StorageAccess::STORE,
            };
            let last = group0.len().saturating_sub(1);
            for (k, &(binding, space)) in group0.iter().enumerate() {
                let want = match k {
                    0 => AddressSpace::Uniform,
                    k if k == last => write,
                    _ if space == AddressSpace::Uniform => space,
                    _ => read,
                };
                assert_eq!(
                    (binding, space),
                    (k as u32, want),
                    "{}.wgsl: group 0 binding {k}",
                    file.name
                );
            }
            assert!(group0.len() >= 2, "{}.wgsl: group 0 {group0:?}", file.name);
            assert_eq!(
                group1,
                [(0, "warp_params"), (1, "warp_displacement")],
                "{}.wgsl: group 1",
                file.name
            );
        }
    }

    pub fn names_are_unique_and_composition_prepends_common() {
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
