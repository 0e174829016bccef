//! A model as one self-contained WGSL module for someone else's shader (`spectex export
//! --wgsl`): [`wgsl_module`] writes `fn spectex_sample(p: vec2<f32>) -> f32` (`vec3<f32>` for
//! colour models), callable from a fragment shader at any position, and
//! `spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>)` for positions far from the origin.
//!
//! Generated, not written per kind: the module is the kind's own compute shader
//! (`shaders/<kind>.wgsl`, after `common.wgsl`) with its bindings and compute entry point
//! removed, the tables the device evaluator uploads (the same packers, the same bytes) emitted
//! as WGSL constants in place of the bindings (their types read from the shader by naga), and
//! the kind's glue from `shaders/export/` ([`EXPORT_SHADERS`]), which locates a position on the
//! kind's lattices itself (`export/split.wgsl`) instead of reading the host's per-tile tables.
//! Every name is prefixed (`spectex_` for the common functions, `spectex_m<k>_` for model `k`:
//! a warp's sub-models each get their own), so the module can be pasted into any shader.
//!
//! Kinds the exporter does not cover yet give [`GpuError::Unsupported`].

use std::collections::HashMap;
use std::fmt::Write as _;

use spectex_model::{Model, ModelKind};

use crate::GpuError;
use crate::kernel::{ShaderKernel, Table};

/// The files of `shaders/export/`: the lattice split every exported model uses and each
/// supported kind's glue (its `<kind>_sample_cell`).
pub const EXPORT_SHADERS: &[(&str, &str)] = &[
    ("split", include_str!("../../../shaders/export/split.wgsl")),
    ("lrp", include_str!("../../../shaders/export/lrp.wgsl")),
    ("gabor", include_str!("../../../shaders/export/gabor.wgsl")),
    (
        "classic",
        include_str!("../../../shaders/export/classic.wgsl"),
    ),
];

/// Bytes of tables up to which an exported module is portable WGSL: the WGSL specification lets
/// an implementation refuse more than 8192 bytes in the `private` address space (Tint, in
/// browsers, does; naga, hence wgpu and Bevy, does not).
pub const PORTABLE_TABLE_BYTES: usize = 8192;

/// Bytes of tables above which [`wgsl_module`] refuses a model: every table is a constant
/// array initialised per shader invocation, and a module this large already takes lavapipe
/// seconds to compile (a fitted LRP model with tens of thousands of frequencies, 0.3–1 MB of
/// tables, would take minutes and no driver promises to accept it). Such models need a
/// storage-buffer variant, which the exporter does not write yet.
pub const MAX_TABLE_BYTES: u64 = 65_536;

/// What a kind's export contributes: its shader, its glue, the values of its bindings and the
/// lattices its glue locates positions on.
#[derive(Debug, Clone)]
pub(crate) struct ExportParts {
    /// The kind's compute shader in the registry.
    shader: &'static str,
    /// Its glue in [`EXPORT_SHADERS`] (defines `<glue>_sample_cell`).
    glue: &'static str,
    /// Values per pixel: 1, or 3 for colour.
    channels: usize,
    /// The bytes of every group-0 binding but the output, in binding order (the uniform first).
    bindings: Vec<Vec<u8>>,
    /// Lattice sides (pixels) for `export/split.wgsl`, in the glue's order.
    lattices: Vec<f64>,
}

impl ExportParts {
    /// The parts of a shader kind: `kernel`'s uniform and per-tile tables for a one-pixel tile
    /// at the origin (the per-tile tables are emitted too, unused by the glue, so every name
    /// the shader declares exists), after its `resident` tables.
    pub(crate) fn of<K: ShaderKernel>(
        kernel: &K,
        resident: &[Table],
        lattices: Vec<f64>,
        glue: &'static str,
    ) -> Result<Self, GpuError> {
        let tile = kernel.tile_tables(&crate::GpuWindow::new(1, 1), None, u64::MAX)?;
        let mut bindings = vec![tile.uniform];
        bindings.extend(resident.iter().map(|t| t.bytes.clone()));
        bindings.extend(tile.tables.into_iter().map(|t| t.bytes));
        Ok(Self {
            shader: K::SHADER,
            glue,
            channels: kernel.output_channels(),
            bindings,
            lattices,
        })
    }
}

/// The export layer of a model kind.
pub(crate) trait ExportKind: ModelKind {
    /// The parts of a **validated** model on the plane `z` (ignored by 2D models).
    ///
    /// # Errors
    /// [`GpuError::Unsupported`] for a kind (or a feature of it) the exporter lacks.
    fn export_parts(&self, z: f64) -> Result<ExportParts, GpuError>;
}

/// The kinds the exporter does not cover yet.
macro_rules! unsupported_export {
    ($($kind:ty),*) => {$(
        impl ExportKind for $kind {
            fn export_parts(&self, _z: f64) -> Result<ExportParts, GpuError> {
                Err(GpuError::Unsupported {
                    kind: <$kind as ModelKind>::NAME,
                    feature: "WGSL export (spectex export --wgsl)".into(),
                })
            }
        }
    )*};
}
unsupported_export!(
    spectex_model::PhasorNoise,
    spectex_model::TextureModel,
    spectex_model::Warp,
    spectex_model::WaveletNoise,
    spectex_model::TextonNoise,
    spectex_model::VoronoiNoise,
    spectex_model::Combine
);

/// The parts of one model: the one dispatch over kinds of the exporter.
fn parts(model: &Model, z: f64) -> Result<ExportParts, GpuError> {
    spectex_model::for_each_kind!(model, m: K => <K as ExportKind>::export_parts(m, z))
}

/// Options of [`wgsl_module`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExportOptions {
    /// The plane of a 3D model (pixels); 2D models ignore it.
    pub z: f64,
}

impl Default for ExportOptions {
    fn default() -> Self {
        Self { z: 0.0 }
    }
}

/// The WGSL module of `model` (see the module doc and the header comment it starts with).
///
/// # Errors
/// [`GpuError::Model`] for an invalid model, [`GpuError::Window`] for a non-finite or far `z`,
/// [`GpuError::Unsupported`] for a kind the exporter does not cover,
/// [`GpuError::LimitsExceeded`] for tables over [`MAX_TABLE_BYTES`].
pub fn wgsl_module(model: &Model, options: &ExportOptions) -> Result<String, GpuError> {
    model.validate()?;
    let z = options.z;
    if !(z.is_finite() && z.abs() <= crate::MAX_POSITION) {
        return Err(GpuError::Window {
            parameter: "z",
            value: z,
            range: "finite, |z| ≤ 2³⁰ pixels",
        });
    }
    let parts = parts(model, z)?;
    // The tables' bytes as emitted: every binding but the uniform, and per lattice a side, its
    // inverse and 32 quotient and remainder words.
    let needed = parts
        .bindings
        .iter()
        .skip(1)
        .map(|b| b.len() as u64)
        .sum::<u64>()
        + 4 * 66 * parts.lattices.len() as u64;
    if needed > MAX_TABLE_BYTES {
        return Err(GpuError::LimitsExceeded {
            what: "bytes of model tables in one exported WGSL module (spectex_gpu::export::MAX_TABLE_BYTES)",
            value: needed,
            limit: MAX_TABLE_BYTES,
        });
    }
    let common = crate::wgsl_source("common").unwrap_or_default();
    // Domain warping is the compute evaluator's (bind group 1): here it is off, a constant.
    let common_body = format!(
        "{}\n/// No displacement: the exported module evaluates the model where it is asked to.\n\
         const warp_params: WarpParams = WarpParams(0u, 0u, 0u, 0u);\n",
        strip(&common)
    );
    let common_names = top_level_names(&common_body);
    let common_map: HashMap<String, String> = common_names
        .iter()
        .map(|n| (n.clone(), format!("spectex_{n}")))
        .collect();

    let (chunk, table_bytes) = model_chunk(&parts, 0, &common_map)?;
    let ret = match parts.channels {
        1 => "f32",
        _ => "vec3<f32>",
    };
    let mut out = header(model, &parts, table_bytes, ret, z);
    out.push_str("\n// ---- spectex: common functions (common.wgsl), prefix spectex_ ----\n");
    out.push_str(&rename(&common_body, &common_map));
    out.push_str(&chunk);
    let _ = write!(
        out,
        "
// ---- spectex: entry points ----

/// The model's value at the position `cell + offset` in model pixels: the precise entry (see
/// the header).
fn spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> {ret} {{
    return spectex_m0_{glue}_sample_cell(cell, offset);
}}

/// The model's value at the position `p` in model pixels (`|p| < 2²⁴` for whole pixels to be
/// exact; see the header for positions farther out).
fn spectex_sample(p: vec2<f32>) -> {ret} {{
    let whole = floor(p);
    return spectex_sample_cell(vec2<i32>(whole), p - whole);
}}
",
        glue = parts.glue
    );
    Ok(out)
}

/// The header comment: what the module provides, its conventions and its size.
fn header(model: &Model, parts: &ExportParts, table_bytes: usize, ret: &str, z: f64) -> String {
    let portable = if table_bytes <= PORTABLE_TABLE_BYTES {
        "within"
    } else {
        "OVER"
    };
    let plane = if z == 0.0 {
        String::new()
    } else {
        format!("// Plane: the 3D model is exported on the plane z = {z} (pixels).\n")
    };
    format!(
        "// spectex model exported to WGSL by `spectex export --wgsl` (spectex {version}).
// Model kind: {kind} ({channels} value(s) per pixel). Generated from spectex's own shaders
// (shaders/{shader}.wgsl after common.wgsl, glue shaders/export/{glue}.wgsl) and the tables its GPU
// evaluator uploads; do not edit, re-export instead.
{plane}//
// Entry points (everything else is prefixed `spectex_` and may change between versions):
//   fn spectex_sample(p: vec2<f32>) -> {ret}
//   fn spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> {ret}
// Both evaluate the model at a position in model pixels, the unit of the CPU evaluator's
// `Window`: pixel (i, j) of `spectex render --offset ox,oy --scale s` is the model at
// (ox + i·s, oy + j·s) — pixel centres sit on those positions, so in a fragment shader whose
// framebuffer pixel (i, j) has `@builtin(position)` (i + 0.5, j + 0.5):
//     let ij = frag.xy - vec2<f32>(0.5);
//     let v = spectex_sample(vec2<f32>(ox, oy) + ij * s);
// Values agree with the CPU evaluator within the CPU–GPU tolerances of spectex-crosscheck plus
// the position rounding below (tests render this module through a wgpu render pipeline).
//
// Precision far from the origin: f32 positions lose their fraction beyond 2²⁴ pixels and
// gain error long before. `spectex_sample_cell` takes the position as an integer part `cell`
// (i32 pixels) plus an f32 `offset` (any size; its floor is moved into the integer part): each
// lattice of the model (LRP's Δ_s, a Gabor kernel radius) locates the integer part from
// tables computed in f64 by the exporter (header of the `export_split` section below), exactly
// where the lattice side is an f32, so a point at (10⁷, 10⁷) is as precise as one at the
// origin. Keep large coordinates as integer + fraction in your shader (e.g. a tile index times
// a tile size plus a UV) and pass them to `spectex_sample_cell`. `spectex_sample(p)` is
// `spectex_sample_cell(floor(p), p − floor(p))`.
//
// Filtering: none. The module point-samples the model: a minified view (more than one model
// pixel per screen pixel) matches `spectex render --no-filter`, not the default render, which
// fades what its pixels cannot resolve; filter or mip in your shader where that matters.
//
// Size: {table_bytes} bytes of tables, as `var<private>` arrays initialised with constants
// (no bind group, no buffers): {portable} the {limit} bytes of private memory that the WGSL
// specification guarantees (naga — wgpu, Bevy — accepts more; browsers' Tint may not).
// The exporter refuses models with more than {max} bytes of tables (fitted LRP models with
// tens of thousands of frequencies): a storage-buffer variant for those is not written yet.
",
        version = env!("CARGO_PKG_VERSION"),
        kind = model.kind(),
        channels = parts.channels,
        shader = parts.shader,
        glue = parts.glue,
        limit = PORTABLE_TABLE_BYTES,
        max = MAX_TABLE_BYTES,
    )
}

/// Model `k`'s part of the module: its kind shader without bindings and entry point, the split
/// functions, its glue and its tables, every name prefixed `spectex_m<k>_`; and its table bytes.
fn model_chunk(
    parts: &ExportParts,
    k: usize,
    common_map: &HashMap<String, String>,
) -> Result<(String, usize), GpuError> {
    let composed = crate::wgsl_source(parts.shader).unwrap_or_default();
    let module = naga::front::wgsl::parse_str(&composed).map_err(|e| {
        GpuError::Validation(format!(
            "{}.wgsl: {}",
            parts.shader,
            e.emit_to_string(&composed)
        ))
    })?;
    let kind_source = crate::SHADERS
        .iter()
        .find(|f| f.name == parts.shader)
        .map_or("", |f| f.source);
    let body = strip(kind_source);
    let split = export_shader("split");
    let glue = export_shader(parts.glue);

    // The values in place of the bindings.
    let mut tables = String::new();
    let mut table_bytes = 0;
    let mut globals: Vec<(u32, &naga::GlobalVariable)> = module
        .global_variables
        .iter()
        .filter_map(|(_, v)| match &v.binding {
            Some(b) if b.group == 0 => Some((b.binding, v)),
            _ => None,
        })
        .collect();
    globals.sort_by_key(|(b, _)| *b);
    let mut names = Vec::new();
    for (i, (_, var)) in globals.iter().enumerate() {
        let name = var.name.clone().unwrap_or_default();
        let Some(bytes) = parts.bindings.get(i) else {
            // The output (last binding): nothing to emit.
            continue;
        };
        names.push(name.clone());
        let decl = declaration(&module, &name, var.ty, bytes)?;
        if !matches!(var.space, naga::AddressSpace::Uniform) {
            table_bytes += bytes.len();
        }
        tables.push_str(&decl);
    }
    let (sides, quotients, remainders) = lattice_tables(&parts.lattices);
    let inverses: Vec<f32> = parts.lattices.iter().map(|s| (1.0 / s) as f32).collect();
    table_bytes += 4 * (sides.len() + inverses.len() + quotients.len() + remainders.len());
    let _ = writeln!(
        tables,
        "var<private> export_inv_sides: array<f32, {}> = array<f32, {}>({});",
        inverses.len(),
        inverses.len(),
        join(inverses.iter().map(|v| float(*v)))
    );
    let _ = writeln!(
        tables,
        "var<private> export_sides: array<f32, {}> = array<f32, {}>({});",
        sides.len(),
        sides.len(),
        join(sides.iter().map(|v| float(*v)))
    );
    let _ = writeln!(
        tables,
        "var<private> export_quotients: array<u32, {}> = array<u32, {}>({});",
        quotients.len(),
        quotients.len(),
        join(quotients.iter().map(|v| format!("{v}u")))
    );
    let _ = writeln!(
        tables,
        "var<private> export_remainders: array<f32, {}> = array<f32, {}>({});",
        remainders.len(),
        remainders.len(),
        join(remainders.iter().map(|v| float(*v)))
    );

    let prefix = format!("spectex_m{k}_");
    let mut map = common_map.clone();
    for name in top_level_names(&body)
        .into_iter()
        .chain(top_level_names(&split))
        .chain(top_level_names(&glue))
        .chain(names)
        .chain(
            [
                "export_sides",
                "export_inv_sides",
                "export_quotients",
                "export_remainders",
            ]
            .map(String::from),
        )
    {
        map.insert(name.clone(), format!("{prefix}{name}"));
    }
    let mut out = format!(
        "\n// ---- spectex: model {k}, {shader}.wgsl, prefix {prefix} ----\n",
        shader = parts.shader
    );
    out.push_str(&rename(&body, &map));
    out.push_str("\n// ---- export/split.wgsl ----\n");
    out.push_str(&rename(&split, &map));
    let _ = write!(out, "\n// ---- export/{}.wgsl ----\n", parts.glue);
    out.push_str(&rename(&glue, &map));
    out.push_str("\n// ---- tables (the bytes spectex's GPU evaluator uploads) ----\n");
    out.push_str(&rename(&tables, &map));
    Ok((out, table_bytes))
}

/// A file of [`EXPORT_SHADERS`] (empty for an unknown name, which naga then rejects).
fn export_shader(name: &str) -> String {
    EXPORT_SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map_or_else(String::new, |(_, s)| (*s).to_owned())
}

/// The split tables of `export/split.wgsl` for lattices of sides `sides` (f64 pixels): per
/// lattice and bit k, `⌊w_k/Δ⌋ mod 2³²` and `w_k − ⌊w_k/Δ⌋·Δ` with `w_k = 2^k` (`−2³¹` for
/// k = 31), computed in f64 (exact: |w_k| ≤ 2³¹ and Δ has 53 bits, the product of the quotient
/// and Δ is formed with one rounding of a number within Δ of w_k).
fn lattice_tables(sides: &[f64]) -> (Vec<f32>, Vec<u32>, Vec<f32>) {
    let mut quotients = Vec::with_capacity(32 * sides.len());
    let mut remainders = Vec::with_capacity(32 * sides.len());
    for &side in sides {
        for k in 0..32 {
            let w = if k == 31 {
                -2_147_483_648.0
            } else {
                f64::from(1u32 << k)
            };
            let (q, r) = floor_div(w, side);
            quotients.push(q as u32);
            remainders.push(r);
        }
    }
    let sides = sides.iter().map(|&s| s as f32).collect();
    (sides, quotients, remainders)
}

/// `(⌊w/side⌋ mod 2³² as i64, w − ⌊w/side⌋·side rounded to f32 in [0, side))`.
fn floor_div(w: f64, side: f64) -> (i64, f32) {
    let mut q = (w / side).floor();
    // The remainder in f64: w and q·side are both below 2³¹ in magnitude; `mul_add` forms
    // w − q·side with one rounding.
    let mut r = (-q).mul_add(side, w);
    if r < 0.0 {
        q -= 1.0;
        r += side;
    } else if r >= side {
        q += 1.0;
        r -= side;
    }
    let mut rf = r as f32;
    if f64::from(rf) >= side {
        rf = 0.0;
        q += 1.0;
    }
    ((q as i64).rem_euclid(1 << 32), rf)
}

/// `items` separated by `, `.
fn join(items: impl Iterator<Item = String>) -> String {
    items.collect::<Vec<_>>().join(", ")
}

/// An f32 as a WGSL literal that parses to the same bits (`f` suffix: parsed directly as f32).
fn float(v: f32) -> String {
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
fn declaration(
    module: &naga::Module,
    name: &str,
    ty: naga::Handle<naga::Type>,
    bytes: &[u8],
) -> Result<String, GpuError> {
    match &module.types[ty].inner {
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Dynamic,
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

/// An error for a type the exporter cannot write.
fn unsupported_type(what: &str) -> GpuError {
    GpuError::Unsupported {
        kind: "export",
        feature: format!("a binding of type {what}"),
    }
}

/// The WGSL name of a scalar.
fn scalar_name(scalar: naga::Scalar) -> Result<&'static str, GpuError> {
    match (scalar.kind, scalar.width) {
        (naga::ScalarKind::Float, 4) => Ok("f32"),
        (naga::ScalarKind::Uint, 4) => Ok("u32"),
        (naga::ScalarKind::Sint, 4) => Ok("i32"),
        _ => Err(unsupported_type("other than f32, u32, i32")),
    }
}

/// The WGSL name of a type made of 4-byte scalars.
fn type_name(module: &naga::Module, ty: naga::Handle<naga::Type>) -> Result<String, GpuError> {
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

/// `source` without its resource bindings (lines starting `@group(`, with the `///` doc lines
/// just above them) and without its compute entry points (from `@compute` to the closing
/// brace at the start of a line).
pub(crate) fn strip(source: &str) -> String {
    let mut kept: Vec<&str> = Vec::new();
    let mut in_entry = false;
    for line in source.lines() {
        if in_entry {
            if line.starts_with('}') {
                in_entry = false;
            }
            continue;
        }
        if line.starts_with("@compute") {
            in_entry = true;
            drop_doc_lines(&mut kept);
            continue;
        }
        if line.starts_with("@group(") {
            drop_doc_lines(&mut kept);
            continue;
        }
        kept.push(line);
    }
    let mut out = kept.join("\n");
    out.push('\n');
    out
}

/// Removes the `///` lines at the end of `kept` (the doc of a removed declaration).
fn drop_doc_lines(kept: &mut Vec<&str>) {
    while kept.last().is_some_and(|l| l.starts_with("///")) {
        kept.pop();
    }
}

/// The names a WGSL source declares at module scope (declarations start a line).
pub(crate) fn top_level_names(source: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in source.lines() {
        let rest = ["fn ", "const ", "struct ", "alias ", "override "]
            .iter()
            .find_map(|k| line.strip_prefix(k))
            .or_else(|| {
                line.strip_prefix("var")
                    .map(|r| r.split_once('>').map_or(r, |(_, after)| after))
            });
        if let Some(rest) = rest {
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                names.push(name);
            }
        }
    }
    names
}

/// `source` with every identifier in `map` replaced, except member names: after a `.`, and
/// field declarations (an identifier followed by `:` inside a struct's braces). Comments are
/// copied unchanged.
pub(crate) fn rename(source: &str, map: &HashMap<String, String>) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len() + source.len() / 4);
    let mut i = 0;
    let mut depth = 0usize;
    let mut struct_depth: Option<usize> = None;
    let mut pending_struct = false;
    let mut last_significant = ' ';
    while i < chars.len() {
        let c = chars[i];
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                out.push(chars[i]);
                i += 1;
            }
            continue;
        }
        if c == '/' && chars.get(i + 1) == Some(&'*') {
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                out.push(chars[i]);
                i += 1;
            }
            out.push_str("*/");
            i += 2;
            continue;
        }
        if c.is_ascii_digit() {
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric() || matches!(chars[i], '_' | '.'))
            {
                out.push(chars[i]);
                i += 1;
            }
            last_significant = '0';
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let mut j = i;
            while j < chars.len() && chars[j].is_whitespace() {
                j += 1;
            }
            let is_field = struct_depth == Some(depth)
                && chars.get(j) == Some(&':')
                && chars.get(j + 1) != Some(&':');
            if word == "struct" {
                pending_struct = true;
            }
            match map.get(&word) {
                Some(new) if last_significant != '.' && !is_field => out.push_str(new),
                _ => out.push_str(&word),
            }
            last_significant = 'a';
            continue;
        }
        match c {
            '{' => {
                depth += 1;
                if pending_struct {
                    struct_depth = Some(depth);
                    pending_struct = false;
                }
            }
            '}' => {
                if struct_depth == Some(depth) {
                    struct_depth = None;
                }
                depth = depth.saturating_sub(1);
            }
            _ => {}
        }
        if !c.is_whitespace() {
            last_significant = c;
        }
        out.push(c);
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_tables_decompose_every_bit_weight() {
        // Δ = 9.5 (an f32): remainders are multiples of 0.5 below 9.5, exact.
        let (sides, q, r) = lattice_tables(&[9.5]);
        assert_eq!(sides, [9.5]);
        for k in 0..32 {
            let w: i64 = if k == 31 { -(1 << 31) } else { 1 << k };
            let want_q = (w as f64 / 9.5).floor() as i64;
            let want_r = w as f64 - want_q as f64 * 9.5;
            assert_eq!(i64::from(q[k]), want_q.rem_euclid(1 << 32), "bit {k}");
            assert_eq!(f64::from(r[k]), want_r, "bit {k}");
            assert!((0.0..9.5).contains(&want_r));
        }
    }

    #[test]
    fn rename_skips_members_fields_and_comments() {
        let map: HashMap<String, String> = [("strata", "p_strata"), ("S", "p_S")]
            .map(|(a, b)| (a.to_owned(), b.to_owned()))
            .into();
        let src = "struct S {\n    strata: u32,\n    s: S,\n}\n// strata\nfn f() { let a = strata[params.strata]; }\n";
        let out = rename(src, &map);
        assert_eq!(
            out,
            "struct p_S {\n    strata: u32,\n    s: p_S,\n}\n// strata\nfn f() { let a = p_strata[params.strata]; }\n"
        );
    }

    #[test]
    fn strip_removes_bindings_and_entry_points() {
        let src = "const A: u32 = 1u;\n/// doc\n@group(0) @binding(0) var<uniform> p: P;\n@compute @workgroup_size(8, 8, 1)\nfn main() {\n    let x = 1;\n}\nfn g() {}\n";
        assert_eq!(strip(src), "const A: u32 = 1u;\nfn g() {}\n");
        assert_eq!(
            top_level_names("fn a(x: u32) {}\nconst B = 1;\nvar<private> c: u32;\nstruct D {}\n"),
            ["a", "B", "c", "D"]
        );
    }
}
