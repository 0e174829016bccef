//! Records the device reads: `#[repr(C)]` [`bytemuck::Pod`] structs that mirror the WGSL structs
//! of `shaders/` field for field, declared through [`wgsl_struct!`] so that a test can hold each
//! one against naga's layout of its WGSL twin (same field names, same offsets, same size).
//!
//! WGSL lays out `u32`, `i32` and `f32` at 4 bytes, `vec4<f32>` at 16 and a struct at its
//! largest member's alignment; every record here is made of 4-byte scalars and arrays of them,
//! with explicit `_pad` fields wherever the WGSL struct has them (uniforms are padded to whole
//! 16-byte rows, and a `vec4` member must start on a 16-byte boundary), so `repr(C)` adds no
//! padding of its own and `Pod` (which refuses implicit padding) holds.

/// One record's field names and byte offsets, in declaration order, for the layout test (the
/// only reader, so it exists with the `unit-tests` feature only).
#[cfg(feature = "unit-tests")]
pub(crate) trait WgslStruct: bytemuck::Pod {
    /// `(field name, byte offset)` of every field.
    const FIELDS: &'static [(&'static str, usize)];
}

/// Declares a `#[repr(C)]`, `Pod` record mirroring a WGSL struct (same field names, in the same
/// order) and, with the `unit-tests` feature, implements `WgslStruct` for it, so its offsets are checked
/// against naga's.
macro_rules! wgsl_struct {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $( $(#[$field_meta:meta])* $field:ident : $ty:ty ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        $vis struct $name {
            $( $(#[$field_meta])* pub $field: $ty ),*
        }

        #[cfg(feature = "unit-tests")]
        impl $crate::layout::WgslStruct for $name {
            const FIELDS: &'static [(&'static str, usize)] =
                &[$( (stringify!($field), ::core::mem::offset_of!($name, $field)) ),*];
        }
    };
}
pub(crate) use wgsl_struct;

#[cfg(feature = "unit-tests")]
pub(crate) mod check {
    //! The layout test's helper: naga's view of a WGSL struct against a Rust record.

    use super::WgslStruct;

    /// A device for the unit test `test`, or `None` after printing why it skips; with
    /// `SPECTEX_REQUIRE_GPU=1`, no device is a failure (tests/it/common's `gpu_or_skip`, for
    /// the unit tests, which cannot reach it).
    pub fn context_or_skip(test: &str) -> Option<crate::GpuContext> {
        match crate::GpuContext::new() {
            Ok(context) => Some(context),
            Err(e) if std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1") => {
                panic!("{test}: SPECTEX_REQUIRE_GPU=1 but no GPU: {e}")
            }
            Err(e) => {
                eprintln!("SKIPPED {test}: {e}");
                None
            }
        }
    }

    /// `source` parsed and validated as wgpu has naga do it; a failure panics with naga's
    /// excerpt of the source, annotated under the name `label`. Shared by the layout check and
    /// the integration tests of the shaders and the exports.
    pub fn validated_module(label: &str, source: &str) -> naga::Module {
        let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| {
            panic!(
                "{label} does not parse:\n{}",
                e.emit_to_string_with_path(source, label)
            )
        });
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| {
            panic!(
                "{label} does not validate:\n{}",
                e.emit_to_string_with_path(source, label)
            )
        });
        module
    }

    /// Panics unless `K::SHAPE` names exactly the pipeline-overridable constants of `K`'s
    /// shader, each defaulting to `NO_SHAPE` (so a pipeline without them reads the uniform).
    pub(crate) fn assert_shape_is_the_overrides<K: crate::kernel::ShaderKernel>() {
        let source = crate::wgsl_source(K::SHADER).unwrap_or_default();
        let module = validated_module(&format!("{}.wgsl", K::SHADER), &source);
        let mut declared: Vec<&str> = Vec::new();
        for (_, o) in module.overrides.iter() {
            let name = o.name.as_deref().unwrap_or("?");
            declared.push(name);
            let default = o.init.map(|e| &module.global_expressions[e]);
            assert!(
                matches!(
                    default,
                    Some(naga::Expression::Literal(naga::Literal::U32(u32::MAX)))
                ),
                "{}.wgsl: {name} defaults to {default:?}, not NO_SHAPE",
                K::SHADER
            );
        }
        let mut shape = K::SHAPE.to_vec();
        shape.sort_unstable();
        declared.sort_unstable();
        assert_eq!(shape, declared, "{}.wgsl's overrides", K::SHADER);
    }

    /// Panics unless the struct `wgsl_name` of the composed module `shader` has exactly the
    /// fields of `T` (names and byte offsets, as naga lays them out) and `T`'s size is the
    /// struct's array stride (its size rounded to its alignment: what one element of a
    /// `Vec<T>` upload must occupy, and for a uniform the struct's size).
    pub(crate) fn assert_matches_wgsl<T: WgslStruct>(shader: &str, wgsl_name: &str) {
        let source = crate::wgsl_source(shader)
            .unwrap_or_else(|| panic!("{shader} is not in the shader registry"));
        assert_source_matches_wgsl::<T>(shader, &source, wgsl_name);
    }

    /// Panics unless `table` (a [`Table::uniform`](crate::kernel::Table::uniform)'s bytes)
    /// fills exactly the `var<uniform>` array `binding` of `shader`: the capacity the host pads
    /// to is the array's, so no record past the shader's array goes unread.
    pub(crate) fn assert_fills_uniform_array(shader: &str, binding: &str, table: &[u8]) {
        let source = crate::wgsl_source(shader)
            .unwrap_or_else(|| panic!("{shader} is not in the shader registry"));
        let module = validated_module(&format!("{shader}.wgsl"), &source);
        let var = module
            .global_variables
            .iter()
            .map(|(_, v)| v)
            .find(|v| v.name.as_deref() == Some(binding))
            .unwrap_or_else(|| panic!("{shader}.wgsl has no binding {binding}"));
        assert_eq!(
            var.space,
            naga::AddressSpace::Uniform,
            "{shader}.wgsl {binding}"
        );
        let size = module.types[var.ty].inner.size(module.to_ctx()) as usize;
        assert_eq!(
            table.len(),
            size,
            "{shader}.wgsl {binding}: bytes of the host's table vs the shader's array"
        );
    }

    /// [`assert_matches_wgsl`] of a module written at run time (`source`, named `shader` in
    /// the messages: a texture store shader, a combination pass), which must also pass naga's
    /// validation.
    pub(crate) fn assert_source_matches_wgsl<T: WgslStruct>(
        shader: &str,
        source: &str,
        wgsl_name: &str,
    ) {
        let module = validated_module(&format!("{shader}.wgsl"), source);
        let mut layouter = naga::proc::Layouter::default();
        layouter
            .update(module.to_ctx())
            .unwrap_or_else(|e| panic!("{shader}.wgsl: naga cannot lay out its types: {e}"));
        let (handle, members) = module
            .types
            .iter()
            .find_map(|(handle, ty)| match &ty.inner {
                naga::TypeInner::Struct { members, .. }
                    if ty.name.as_deref() == Some(wgsl_name) =>
                {
                    Some((handle, members))
                }
                _ => None,
            })
            .unwrap_or_else(|| panic!("{shader}.wgsl has no struct {wgsl_name}"));
        let wgsl: Vec<(&str, usize)> = members
            .iter()
            .map(|m| (m.name.as_deref().unwrap_or("?"), m.offset as usize))
            .collect();
        assert_eq!(
            T::FIELDS,
            wgsl.as_slice(),
            "{shader}.wgsl {wgsl_name}: (field, offset) of the Rust record vs naga's layout"
        );
        let stride = layouter[handle].to_stride() as usize;
        assert_eq!(
            size_of::<T>(),
            stride,
            "{shader}.wgsl {wgsl_name}: size of the Rust record vs naga's stride"
        );
    }
}
