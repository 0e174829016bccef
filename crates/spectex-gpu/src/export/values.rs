//! Binding values printed as WGSL: the constructor expression of a value of a naga type from
//! the bytes the device evaluator uploads, and the declarations replacing the bindings.

use crate::GpuError;

/// An f32 as a WGSL literal that parses to the same bits (`f` suffix: parsed directly as f32).
pub(crate) fn float(v: f32) -> String {
    if v.is_finite() {
        format!("{v:?}f")
    } else if v.is_nan() {
        "bitcast<f32>(0x7fc00000u)".to_owned()
    } else if v > 0.0 {
        "bitcast<f32>(0x7f800000u)".to_owned()
    } else {
        "bitcast<f32>(0xff800000u)".to_owned()
    }
}

/// The declaration replacing the binding `name` of type `ty`, holding `bytes`: a `const` for a
/// uniform struct, a `var<private>` array of the records for a storage array.
pub(super) fn declaration(
    module: &naga::Module,
    name: &str,
    ty: naga::Handle<naga::Type>,
    bytes: &[u8],
) -> Result<String, GpuError> {
    match &module.types[ty].inner {
        // A storage table, or a uniform one of a fixed capacity (`Table::uniform`): the
        // records given, however many the binding holds.
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Dynamic | naga::ArraySize::Constant(_),
            stride,
        } => {
            let stride = *stride as usize;
            let count = bytes.len().checked_div(stride).unwrap_or(0);
            let element = type_name(module, *base)?;
            let values = (0..count)
                .map(|i| value(module, *base, &bytes[i * stride..(i + 1) * stride]))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!(
                "var<private> {name}: array<{element}, {count}> = array<{element}, {count}>({});\n",
                values.join(", ")
            ))
        }
        _ => Ok(format!(
            "const {name}: {} = {};\n",
            type_name(module, ty)?,
            value(module, ty, bytes)?
        )),
    }
}

/// The declaration replacing the table binding `name` (an array of type `ty`) that no code of
/// the export reads: one zero element, so the names the shader declares all exist.
pub(super) fn placeholder(
    module: &naga::Module,
    name: &str,
    ty: naga::Handle<naga::Type>,
) -> Result<String, GpuError> {
    let naga::TypeInner::Array { base, .. } = &module.types[ty].inner else {
        return Err(unsupported_type("a placeholder of a non-array binding"));
    };
    Ok(format!(
        "var<private> {name}: array<{}, 1>;\n",
        type_name(module, *base)?
    ))
}

/// An error for a type the exporter cannot write.
pub(super) fn unsupported_type(what: &str) -> GpuError {
    GpuError::Unsupported {
        kind: "export",
        feature: format!("a binding of type {what}"),
    }
}

/// The WGSL name of a scalar.
pub(super) fn scalar_name(scalar: naga::Scalar) -> Result<&'static str, GpuError> {
    match (scalar.kind, scalar.width) {
        (naga::ScalarKind::Float, 4) => Ok("f32"),
        (naga::ScalarKind::Uint, 4) => Ok("u32"),
        (naga::ScalarKind::Sint, 4) => Ok("i32"),
        _ => Err(unsupported_type("other than f32, u32, i32")),
    }
}

/// The WGSL name of a type made of 4-byte scalars.
pub(super) fn type_name(
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
) -> Result<String, GpuError> {
    let t = &module.types[ty];
    match &t.inner {
        naga::TypeInner::Scalar(s) => Ok(scalar_name(*s)?.to_owned()),
        naga::TypeInner::Vector { size, scalar } => {
            Ok(format!("vec{}<{}>", *size as u32, scalar_name(*scalar)?))
        }
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            ..
        } => Ok(format!("array<{}, {n}>", type_name(module, *base)?)),
        naga::TypeInner::Struct { .. } => t
            .name
            .clone()
            .ok_or_else(|| unsupported_type("an anonymous struct")),
        _ => Err(unsupported_type("a matrix, pointer or runtime array")),
    }
}

/// A scalar's literal from its 4 bytes.
fn scalar_value(scalar: naga::Scalar, bytes: &[u8]) -> Result<String, GpuError> {
    let word = bytes
        .get(0..4)
        .and_then(|b| <[u8; 4]>::try_from(b).ok())
        .map(u32::from_ne_bytes)
        .ok_or_else(|| unsupported_type("shorter than its bytes"))?;
    Ok(match scalar_name(scalar)? {
        "f32" => float(f32::from_bits(word)),
        "u32" => format!("{word}u"),
        _ => {
            let v = word as i32;
            if v == i32::MIN {
                "(-2147483647i - 1i)".to_owned()
            } else {
                format!("{v}i")
            }
        }
    })
}

/// The constructor expression of a value of type `ty` laid out in `bytes` (naga's layout: the
/// one the device reads, which the layout tests hold the Rust records to).
fn value(
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
    bytes: &[u8],
) -> Result<String, GpuError> {
    let short = || unsupported_type("shorter than its bytes");
    match &module.types[ty].inner {
        naga::TypeInner::Scalar(s) => scalar_value(*s, bytes),
        naga::TypeInner::Vector { size, scalar } => {
            let parts = (0..*size as usize)
                .map(|i| scalar_value(*scalar, bytes.get(4 * i..).ok_or_else(short)?))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!("{}({})", type_name(module, ty)?, parts.join(", ")))
        }
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            stride,
        } => {
            let parts = (0..n.get() as usize)
                .map(|i| {
                    value(
                        module,
                        *base,
                        bytes.get(i * *stride as usize..).ok_or_else(short)?,
                    )
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!("{}({})", type_name(module, ty)?, parts.join(", ")))
        }
        naga::TypeInner::Struct { members, .. } => {
            let parts = members
                .iter()
                .map(|m| {
                    value(
                        module,
                        m.ty,
                        bytes.get(m.offset as usize..).ok_or_else(short)?,
                    )
                })
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!("{}({})", type_name(module, ty)?, parts.join(", ")))
        }
        _ => Err(unsupported_type("a matrix, pointer or runtime array")),
    }
}
