//! The module's writer: per model its chunk (the kind's shader stripped of bindings and entry
//! point, the lattice split, the glue and the tables, every name prefixed), the storage
//! buffer's tables and layout, and the header comment; a combination's `combine_sample_cell`,
//! its operation per channel written in WGSL (the compute path applies it on the host).

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use spectex_model::Model;
use spectex_model::combine::{CombineOp, RampStop};

use super::values::{declaration, float, placeholder, scalar_name, type_name, unsupported_type};
use super::wgsl_text::{identifiers, rename, strip, top_level_names};
use super::{
    ExportNode, ExportParts, MAX_TABLE_BYTES, PORTABLE_TABLE_BYTES, TableStorage, export_shader,
};
use crate::GpuError;

/// One table of the storage buffer, for the header.
struct BufferTable {
    /// Its WGSL name (prefixed).
    name: String,
    /// Its element type.
    element: String,
    /// Bytes per element.
    stride: usize,
    /// Elements.
    count: usize,
    /// Byte offset in the buffer.
    offset: usize,
}

/// The state of one export: the tables collected into the buffer and the model count.
pub(super) struct Emitter<'a> {
    storage: TableStorage,
    common_map: &'a HashMap<String, String>,
    /// The buffer's bytes (native order until written out).
    buffer: Vec<u8>,
    layout: Vec<BufferTable>,
    /// Bytes of tables as constants.
    constant_bytes: usize,
    /// Models emitted so far (the next one's index).
    models: usize,
    /// Kinds' shaders and glue, for the header.
    sources: Vec<String>,
}

impl<'a> Emitter<'a> {
    /// An emitter with no model yet, its tables going to `storage`, the common functions
    /// renamed by `common_map`.
    pub(super) fn new(storage: TableStorage, common_map: &'a HashMap<String, String>) -> Self {
        Self {
            storage,
            common_map,
            buffer: Vec::new(),
            layout: Vec::new(),
            constant_bytes: 0,
            models: 0,
            sources: Vec::new(),
        }
    }

    /// The storage buffer's bytes as little-endian words, whatever the host's order.
    pub(super) fn buffer_le(&self) -> Vec<u8> {
        self.buffer
            .chunks_exact(4)
            .flat_map(|w| u32::from_ne_bytes([w[0], w[1], w[2], w[3]]).to_le_bytes())
            .collect()
    }
}

impl Emitter<'_> {
    /// Emits `node` (sub-models first) into `out` and returns the name of its
    /// `fn(cell: vec2<i32>, offset: vec2<f32>) -> ret`.
    pub(super) fn node(
        &mut self,
        node: &ExportNode,
        ret: &str,
        out: &mut String,
    ) -> Result<String, GpuError> {
        match node {
            ExportNode::Leaf(parts) => {
                let k = self.models;
                self.models += 1;
                self.sources.push(format!(
                    "model {k}: shaders/{}.wgsl, glue of shaders/{}.wgsl",
                    parts.shader, parts.glue
                ));
                let chunk = self.model_chunk(parts, k)?;
                out.push_str(&chunk);
                Ok(format!("spectex_m{k}_{}_sample_cell", parts.glue))
            }
            ExportNode::Texture(t) => {
                // The LRP models first, then the texture reading them.
                let mut inputs = String::from(
                    "/// The LRP models' values at `cell + offset` (the glue of texture.wgsl).\n\
                     fn texture_inputs(cell: vec2<i32>, offset: vec2<f32>) -> TextureInputs {\n    \
                     var strata = array<f32, 3>(0.0f, 0.0f, 0.0f);\n",
                );
                for (c, channel) in t.strata.iter().enumerate() {
                    let value = match channel {
                        Ok(node) => format!("{}(cell, offset)", self.node(node, "f32", out)?),
                        Err(mean) => float(*mean),
                    };
                    let _ = writeln!(inputs, "    strata[{c}] = {value};");
                }
                match &t.turbulence {
                    Some((sigma, centre, axes)) => {
                        let mut sums = Vec::new();
                        for (axis, nodes) in axes.iter().enumerate() {
                            let _ = writeln!(inputs, "    var sum{axis} = 0.0f;");
                            for node in nodes {
                                let f = self.node(node, "f32", out)?;
                                let _ =
                                    writeln!(inputs, "    sum{axis} += abs({f}(cell, offset));");
                            }
                            sums.push(format!(
                                "{} * (sum{axis} - {})",
                                float(*sigma),
                                float(*centre)
                            ));
                        }
                        let _ = writeln!(
                            inputs,
                            "    return TextureInputs(strata, vec2<f32>({}));\n}}",
                            sums.join(", ")
                        );
                    }
                    None => {
                        let _ = writeln!(
                            inputs,
                            "    return TextureInputs(strata, vec2<f32>(0.0f, 0.0f));\n}}"
                        );
                    }
                }
                let mut leaf = t.leaf.clone();
                leaf.constants = inputs;
                let (value, result) = if leaf.channels == 1 {
                    ("f32", "v[0]")
                } else {
                    ("vec3<f32>", "vec3<f32>(v[0], v[1], v[2])")
                };
                leaf.substitutions = vec![
                    ("TEXTURE_VALUE", value.to_owned()),
                    ("TEXTURE_RESULT", result.to_owned()),
                ];
                self.node(&ExportNode::Leaf(leaf), ret, out)
            }
            ExportNode::Warp {
                base,
                x,
                y,
                strength,
            } => {
                let fx = self.node(x, "f32", out)?;
                let fy = self.node(y, "f32", out)?;
                let fb = self.node(base, ret, out)?;
                let k = self.models;
                self.models += 1;
                self.sources.push(format!(
                    "model {k}: a warp (glue shaders/warp.wgsl) of the models before it"
                ));
                let prefix = format!("spectex_m{k}_");
                let glue = export_shader("warp");
                let mut map = self.common_map.clone();
                for name in top_level_names(&glue)
                    .into_iter()
                    .chain(["warp_strength".to_owned()])
                {
                    map.insert(name.clone(), format!("{prefix}{name}"));
                }
                for (name, value) in [
                    ("WARP_BASE", fb.as_str()),
                    ("WARP_X", fx.as_str()),
                    ("WARP_Y", fy.as_str()),
                    ("WARP_VALUE", ret),
                ] {
                    map.insert(name.to_owned(), value.to_owned());
                }
                let _ = write!(
                    out,
                    "\n// ---- spectex: model {k}, a warp, prefix {prefix} ----\n\
                     const {prefix}warp_strength: f32 = {};\n",
                    float(*strength)
                );
                out.push_str(&rename(&glue, &map, &HashSet::new()));
                Ok(format!("{prefix}warp_sample_cell"))
            }
            ExportNode::Combine {
                op,
                operands,
                channels,
            } => self.combine(op, operands, *channels, ret, out),
        }
    }

    /// Model `k`'s part of the module: its kind shader without bindings and entry point, the
    /// split functions, its glue and its tables, every name prefixed `spectex_m<k>_`.
    fn model_chunk(&mut self, parts: &ExportParts, k: usize) -> Result<String, GpuError> {
        let prefix = format!("spectex_m{k}_");
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
        let mut globals: Vec<(u32, &naga::GlobalVariable)> = module
            .global_variables
            .iter()
            .filter_map(|(_, v)| match &v.binding {
                Some(b) if b.group == 0 => Some((b.binding, v)),
                _ => None,
            })
            .collect();
        globals.sort_by_key(|(b, _)| *b);
        // A name kept constant that the shader does not bind would silently keep nothing.
        if let Some(unknown) = parts.constant_tables.iter().find(|name| {
            !globals
                .iter()
                .any(|(_, v)| v.name.as_deref() == Some(**name))
        }) {
            return Err(GpuError::Validation(format!(
                "{}.wgsl: no binding `{unknown}` to keep constant",
                parts.shader
            )));
        }
        let mut names = Vec::new();
        // Tables read from the storage buffer through accessor functions.
        let mut accessors = HashSet::new();
        // What the glue reads: a binding only the compute path reads (a per-tile table, such
        // as a 3D Voronoi tile's 20 KB of sites) is declared with one zero element, so every
        // name the shader declares exists without its bytes.
        let mut used = identifiers(&glue);
        used.extend(identifiers(&parts.constants));
        for (_, replacement) in &parts.substitutions {
            used.extend(identifiers(replacement));
        }
        let read = read_globals(&module, &used);
        for (i, (_, var)) in globals.iter().enumerate() {
            let name = var.name.clone().unwrap_or_default();
            let Some(bytes) = parts.bindings.get(i) else {
                // The output (last binding): nothing to emit.
                continue;
            };
            names.push(name.clone());
            let array = matches!(module.types[var.ty].inner, naga::TypeInner::Array { .. });
            if array && !read.contains(&name) {
                tables.push_str(&placeholder(&module, &name, var.ty)?);
                continue;
            }
            let in_buffer = matches!(self.storage, TableStorage::Buffer { .. })
                && !matches!(var.space, naga::AddressSpace::Uniform)
                && !parts.constant_tables.contains(&name.as_str());
            let decl = if in_buffer {
                accessors.insert(name.clone());
                self.buffer_table(&module, &format!("{prefix}{name}"), &name, var.ty, bytes)?
            } else {
                // Tables, not the params uniform (a uniform table is an array).
                if array || !matches!(var.space, naga::AddressSpace::Uniform) {
                    self.constant_bytes += bytes.len();
                }
                declaration(&module, &name, var.ty, bytes)?
            };
            tables.push_str(&decl);
        }
        let modular: Vec<Option<Modular>> = parts.lattices.iter().map(|&s| modular(s)).collect();
        let (sides, quotients, remainders) = split_tables(&parts.lattices);
        let inverses: Vec<f32> = parts.lattices.iter().map(|s| (1.0 / s) as f32).collect();
        let whole = whole_sides(&parts.lattices);
        self.constant_bytes += lattice_bytes(&parts.lattices) as usize;
        let modular_values = if modular.is_empty() {
            "ExportModular()".to_owned()
        } else {
            join(modular.iter().map(|m| m.unwrap_or_default().wgsl()))
        };
        let _ = writeln!(
            tables,
            "var<private> export_modular: array<ExportModular, {n}> = array<ExportModular, {n}>({modular_values});",
            n = modular.len().max(1)
        );
        let _ = writeln!(
            tables,
            "var<private> export_whole: array<u32, {n}> = array<u32, {n}>({});",
            join(whole.iter().map(|v| format!("{v}u"))),
            n = whole.len()
        );
        for (name, ty, values) in [
            (
                "export_inv_sides",
                "f32",
                join(inverses.iter().map(|v| float(*v))),
            ),
            ("export_sides", "f32", join(sides.iter().map(|v| float(*v)))),
            (
                "export_quotients",
                "u32",
                join(quotients.iter().map(|v| format!("{v}u"))),
            ),
            (
                "export_remainders",
                "f32",
                join(remainders.iter().map(|v| float(*v))),
            ),
        ] {
            let n = if ty == "u32" {
                quotients.len()
            } else if name == "export_remainders" {
                remainders.len()
            } else {
                sides.len()
            };
            if n == 0 {
                // A kind without lattices: a one-element array keeps the split functions valid.
                let _ = writeln!(
                    tables,
                    "var<private> {name}: array<{ty}, 1> = array<{ty}, 1>({ty}());"
                );
            } else {
                let _ = writeln!(
                    tables,
                    "var<private> {name}: array<{ty}, {n}> = array<{ty}, {n}>({values});"
                );
            }
        }

        let mut map = self.common_map.clone();
        for name in top_level_names(&body)
            .into_iter()
            .chain(top_level_names(&split))
            .chain(top_level_names(&glue))
            .chain(top_level_names(&parts.constants))
            .chain(names)
            .chain(
                [
                    "export_sides",
                    "export_inv_sides",
                    "export_whole",
                    "export_modular",
                    "export_quotients",
                    "export_remainders",
                ]
                .map(String::from),
            )
        {
            map.insert(name.clone(), format!("{prefix}{name}"));
        }
        map.insert("spectex_tables".to_owned(), "spectex_tables".to_owned());
        // A replacement's own names are the chunk's (a call of the glue's functions).
        let substitutions: Vec<(String, String)> = parts
            .substitutions
            .iter()
            .map(|(name, value)| ((*name).to_owned(), rename(value, &map, &accessors)))
            .collect();
        map.extend(substitutions);
        let mut out = format!(
            "\n// ---- spectex: model {k}, {shader}.wgsl, prefix {prefix} ----\n",
            shader = parts.shader
        );
        out.push_str(&rename(&body, &map, &accessors));
        out.push_str("\n// ---- export/split.wgsl ----\n");
        out.push_str(&rename(&split, &map, &accessors));
        let _ = write!(out, "\n// ---- export/{}.wgsl ----\n", parts.glue);
        out.push_str(&rename(&glue, &map, &accessors));
        out.push_str(&rename(&parts.constants, &map, &accessors));
        out.push_str("\n// ---- tables (the bytes spectex's GPU evaluator uploads) ----\n");
        out.push_str(&rename(&tables, &map, &accessors));
        Ok(out)
    }

    /// Appends the binding `name` (a runtime array of type `ty`) holding `bytes` to the buffer
    /// and returns its accessor, `fn name(i: u32) -> element` (every `name[i]` of the shader
    /// becomes `name(u32(i))`), reading `spectex_tables` at the table's word offset.
    fn buffer_table(
        &mut self,
        module: &naga::Module,
        full_name: &str,
        name: &str,
        ty: naga::Handle<naga::Type>,
        bytes: &[u8],
    ) -> Result<String, GpuError> {
        let naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Dynamic,
            stride,
        } = &module.types[ty].inner
        else {
            return Err(unsupported_type(
                "a storage binding other than a runtime array",
            ));
        };
        let stride = *stride as usize;
        let offset = self.buffer.len();
        let count = bytes.len().checked_div(stride).unwrap_or(0);
        self.buffer.extend_from_slice(&bytes[..count * stride]);
        // A table read past its end by a shader guard still finds words (zeros).
        if count == 0 {
            self.buffer.extend_from_slice(&vec![0; stride.max(4)]);
        }
        let element = type_name(module, *base)?;
        self.layout.push(BufferTable {
            name: full_name.to_owned(),
            element: element.clone(),
            stride,
            count,
            offset,
        });
        let load = load_words(module, *base, 0)?;
        Ok(format!(
            "/// `{name}[i]`: {count} elements of {stride} bytes from byte {offset} of spectex_tables.\n\
             fn {name}(i: u32) -> {element} {{\n    let b = {}u + i * {}u;\n    return {load};\n}}\n",
            offset / 4,
            stride / 4
        ))
    }
}

/// The expression of a value of type `ty` read from `spectex_tables` at word `b + word`.
fn load_words(
    module: &naga::Module,
    ty: naga::Handle<naga::Type>,
    word: usize,
) -> Result<String, GpuError> {
    let scalar = |s: naga::Scalar, w: usize| -> Result<String, GpuError> {
        let at = format!("spectex_tables[b + {w}u]");
        Ok(match scalar_name(s)? {
            "f32" => format!("bitcast<f32>({at})"),
            "i32" => format!("bitcast<i32>({at})"),
            _ => at,
        })
    };
    match &module.types[ty].inner {
        naga::TypeInner::Scalar(s) => scalar(*s, word),
        naga::TypeInner::Vector { size, scalar: s } => {
            let parts = (0..*size as usize)
                .map(|i| scalar(*s, word + i))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!("{}({})", type_name(module, ty)?, parts.join(", ")))
        }
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            stride,
        } => {
            let parts = (0..n.get() as usize)
                .map(|i| load_words(module, *base, word + i * *stride as usize / 4))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!("{}({})", type_name(module, ty)?, parts.join(", ")))
        }
        naga::TypeInner::Struct { members, .. } => {
            let parts = members
                .iter()
                .map(|m| load_words(module, m.ty, word + m.offset as usize / 4))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(format!("{}({})", type_name(module, ty)?, parts.join(", ")))
        }
        _ => Err(unsupported_type("a matrix, pointer or runtime array")),
    }
}

/// The header comment: what the module provides, its conventions and its size.
pub(super) fn header(model: &Model, emitter: &Emitter<'_>, ret: &str, z: f64) -> String {
    let plane = if z == 0.0 {
        String::new()
    } else {
        format!("// Plane: the 3D model is exported on the plane z = {z} (pixels).\n")
    };
    let sources = emitter
        .sources
        .iter()
        .map(|s| format!("//   {s}\n"))
        .collect::<String>();
    let size = match emitter.storage {
        TableStorage::Constants => {
            let portable = if emitter.constant_bytes <= PORTABLE_TABLE_BYTES {
                "within"
            } else {
                "OVER"
            };
            format!(
                "// Size: {bytes} bytes of tables, as `var<private>` arrays initialised with constants
// (no bind group, no buffers): {portable} the {limit} bytes of private memory that the WGSL
// specification guarantees (naga — wgpu, Bevy — accepts more; browsers' Tint may not).
// Models with more than {max} bytes of tables export to a storage buffer instead
// (`spectex export --tables OUT.bin`).
",
                bytes = emitter.constant_bytes,
                limit = PORTABLE_TABLE_BYTES,
                max = MAX_TABLE_BYTES,
            )
        }
        TableStorage::Buffer { group, binding } => {
            let rows = emitter
                .layout
                .iter()
                .map(|t| {
                    format!(
                        "//   byte {:>9}  {:>8} × {:>3} bytes  {}: array<{}>\n",
                        t.offset, t.count, t.stride, t.name, t.element
                    )
                })
                .collect::<String>();
            format!(
                "// Tables: in one read-only storage buffer the caller binds,
//     @group({group}) @binding({binding}) var<storage, read> spectex_tables: array<u32>;
// (`spectex export --group G --binding B` chose these), {bytes} bytes written by
// `spectex export --tables OUT.bin`: upload the file's bytes as they are. The buffer is the
// concatenation of the tables below, each an array of records laid out as WGSL lays out the
// struct named (naga's storage layout: every member a 4-byte f32/u32/i32 word at its offset),
// every word little-endian; byte offsets from the start of the buffer:
{rows}// Each table is read through a function `name(i)` = element i. The few words of the lattice
// split ({constant} bytes) and the parameters stay constants in the module.
",
                bytes = emitter.buffer.len(),
                constant = emitter.constant_bytes,
            )
        }
    };
    format!(
        "// spectex model exported to WGSL by `spectex export --wgsl` (spectex {version}).
// Model kind: {kind} ({channels} value(s) per pixel). Generated from spectex's own shaders
// (each after common.wgsl) and the tables its GPU evaluator uploads; do not edit, re-export:
{sources}{plane}//
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
// `spectex_sample_cell(floor(p), p − floor(p))`. A warp adds its f32 displacement to the
// fraction, its whole pixels to the integer part.
//
// Filtering: none. The module point-samples the model: a minified view (more than one model
// pixel per screen pixel) matches `spectex render --no-filter`, not the default render, which
// fades what its pixels cannot resolve; filter or mip in your shader where that matters.
//
{size}",
        version = env!("CARGO_PKG_VERSION"),
        kind = model.kind(),
        channels = emitter_channels(ret),
    )
}

/// Values per pixel of a return type.
fn emitter_channels(ret: &str) -> usize {
    if ret == "f32" { 1 } else { 3 }
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

/// [`lattice_tables`] where some lattice needs them ([`modular`] is `None`), else one zero
/// quotient and remainder: the loop reading them is then never run.
fn split_tables(lattices: &[f64]) -> (Vec<f32>, Vec<u32>, Vec<f32>) {
    let (sides, quotients, remainders) = lattice_tables(lattices);
    if lattices.iter().all(|&s| modular(s).is_some()) {
        (sides, vec![0], vec![0.0])
    } else {
        (sides, quotients, remainders)
    }
}

/// Bytes of the lattice split's tables (`export/split.wgsl`) for lattices of sides `lattices`:
/// per lattice its side, inverse and `ExportModular`, the 32-step tables (or their zero
/// entries) and `export_whole`'s words.
pub(super) fn lattice_bytes(lattices: &[f64]) -> u64 {
    let (sides, quotients, remainders) = split_tables(lattices);
    4 * (2 * sides.len()
        + quotients.len()
        + remainders.len()
        + whole_sides(lattices).len()
        + MODULAR_WORDS * lattices.len().max(1)) as u64
}

/// Words of one `ExportModular` (`export/split.wgsl`).
const MODULAR_WORDS: usize = 8;

/// A lattice's closed-form split (`export/split.wgsl`'s `ExportModular`): `f32(Δ) = M·2^−s`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Modular {
    /// M, 2 to 2²⁴.
    modulus: u32,
    /// s, 0 to 23.
    shift: u32,
    /// Δ − f32(Δ), rounded to f32.
    low: f32,
}

impl Modular {
    /// 2^s.
    fn power(self) -> u32 {
        1 << self.shift
    }

    /// The `ExportModular(…)` constructor of WGSL (all zero: the table split).
    fn wgsl(self) -> String {
        if self.modulus == 0 {
            return "ExportModular()".to_owned();
        }
        let (m, p) = (self.modulus, self.power());
        format!(
            "ExportModular({m}i, {}, {p}u, {}u, {}u, {}, {}, {})",
            float((1.0 / f64::from(m)) as f32),
            p % m,
            p / m,
            float((f64::from(p % m) / f64::from(m)) as f32),
            float((1.0 / f64::from(p)) as f32),
            float(self.low),
        )
    }
}

/// The closed-form split of a lattice of side `side` (f64 pixels), where `f32(side)` is 1 to
/// 2²⁴ (`M·2^−s` with `2 ≤ M ≤ 2²⁴`, `s ≤ 23`); `None` elsewhere (the tables split it).
fn modular(side: f64) -> Option<Modular> {
    let hi = side as f32;
    if !(side.is_finite() && (1.0..=16_777_216.0).contains(&hi)) {
        return None;
    }
    let hi = f64::from(hi);
    let mut shift = 0;
    while (hi * f64::from(1u32 << shift)).fract() != 0.0 || hi * f64::from(1u32 << shift) < 2.0 {
        shift += 1;
        if shift > 23 {
            return None;
        }
    }
    let modulus = hi * f64::from(1u32 << shift);
    if modulus > 16_777_216.0 {
        return None;
    }
    Some(Modular {
        modulus: modulus as u32,
        shift,
        low: (side - hi) as f32,
    })
}

/// `export/split.wgsl`'s `export_whole`: bit `l % 32` of word `l / 32` set where lattice `l`'s
/// side is a whole number of pixels from 1 to 2²⁴ (exactly, in f64), which `export_split` then
/// divides in integers: `n mod Δ` is exact there, as the tables make it. One word at least.
fn whole_sides(sides: &[f64]) -> Vec<u32> {
    let mut words = vec![0u32; sides.len().div_ceil(32).max(1)];
    for (l, &side) in sides.iter().enumerate() {
        if side.fract() == 0.0 && (1.0..=16_777_216.0).contains(&side) {
            words[l / 32] |= 1 << (l % 32);
        }
    }
    words
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

// ---------------------------------------------------------------------------------------------
// A combination (`spectex_model::combine`): its operation per channel, written in WGSL.

/// Bytes of the constant tables a combination adds: a histogram's table, a ramp's stops
/// (their position and colour), or the one unused entry of each.
pub(super) fn combine_table_bytes(op: &CombineOp) -> u64 {
    let (knots, stops) = tables(op);
    4 * knots.len() as u64 + 16 * stops.len() as u64
}

/// The histogram table (two zeros without one) and the ramp stops (one zero stop without).
fn tables(op: &CombineOp) -> (Vec<f32>, Vec<RampStop>) {
    let knots = match op {
        CombineOp::Histogram { table, .. } => table.clone(),
        _ => vec![0.0, 0.0],
    };
    let stops = match op {
        CombineOp::Ramp { stops } => stops.clone(),
        _ => vec![RampStop {
            at: 0.0,
            colour: [0.0; 3],
        }],
    };
    (knots, stops)
}

/// Channel `c` of operand `k`'s value `v<k>` (`width` channels).
fn channel(k: usize, width: usize, c: usize) -> String {
    if width == 1 {
        format!("v{k}")
    } else {
        format!("v{k}[{c}]")
    }
}

/// The WGSL expression of `op` for output channel `c` over the operands of `widths`
/// (`CombineOp::apply`, the same operations in the same order, in the glue's `arith_*`),
/// operand `k` read from `v<k>` (an `f32`, or a `vec3<f32>` for 3 channels): the export's
/// `combine_sample_cell` and the compute path's combination pass (`crate::combine`).
pub(crate) fn combine_expression(op: &CombineOp, widths: &[usize], c: usize) -> String {
    let ch = |k: usize, c: usize| channel(k, widths[k], c);
    let fold =
        |f: &str| (1..widths.len()).fold(ch(0, c), |acc, k| format!("{f}({acc}, {})", ch(k, c)));
    match op {
        CombineOp::Add => fold("arith_add"),
        CombineOp::Multiply => fold("arith_mul"),
        CombineOp::Min => fold("min"),
        CombineOp::Max => fold("max"),
        CombineOp::Mix => format!("combine_mix({}, {}, {})", ch(0, c), ch(1, c), ch(2, 0)),
        CombineOp::Smoothstep { edges } => format!(
            "combine_smoothstep({}, {}, {})",
            float(edges[0]),
            float(edges[1]),
            ch(0, c)
        ),
        CombineOp::AbsFold {
            offset,
            step,
            folds,
        } => format!(
            "combine_abs_fold({}, {}, {}, {folds}u)",
            ch(0, c),
            float(*offset),
            float(*step)
        ),
        CombineOp::SinFold { gain } => {
            format!("combine_sin_fold({}, {})", float(*gain), ch(0, c))
        }
        CombineOp::Histogram { domain, .. } => format!(
            "combine_lookup({}, {}, {})",
            float(domain[0]),
            float(domain[1]),
            ch(0, c)
        ),
        CombineOp::Ramp { .. } => format!("combine_ramp({}, {c}u)", ch(0, 0)),
    }
}

/// The combination glue's `arith_*` in the shader's own operators, for an exported module:
/// as cheap as WGSL makes it (a compiler may fuse a multiply and an add; the compute path's
/// pass computes them in `exact.wgsl` instead).
const SHADER_ARITHMETIC: &str = "
fn arith_add(a: f32, b: f32) -> f32 {
    return a + b;
}

fn arith_sub(a: f32, b: f32) -> f32 {
    return a - b;
}

fn arith_mul(a: f32, b: f32) -> f32 {
    return a * b;
}

fn arith_div(a: f32, b: f32) -> f32 {
    return a / b;
}

fn arith_clamp(v: f32, lo: f32, hi: f32) -> f32 {
    return clamp(v, lo, hi);
}

fn arith_is_nan(v: f32) -> bool {
    return !(v == v);
}

fn arith_sin_turns(t: f32) -> f32 {
    return sin_turns(t);
}
";

/// The constant tables of a combination's glue (`shaders/combine.wgsl`): a histogram's table and
/// a ramp's stops, or one unused entry of each.
pub(crate) fn combine_constants(op: &CombineOp) -> String {
    let (knots, stops) = tables(op);
    let mut code = String::new();
    let _ = write!(
        code,
        "\nconst combine_knots: u32 = {n}u;\n\
         var<private> combine_table: array<f32, {n}> = array<f32, {n}>({});\n\
         const combine_stops: u32 = {s}u;\n\
         var<private> combine_stops_at: array<f32, {s}> = array<f32, {s}>({});\n\
         var<private> combine_stops_colour: array<vec3<f32>, {s}> = \
         array<vec3<f32>, {s}>({});\n",
        knots
            .iter()
            .map(|v| float(*v))
            .collect::<Vec<_>>()
            .join(", "),
        stops
            .iter()
            .map(|s| float(s.at))
            .collect::<Vec<_>>()
            .join(", "),
        stops
            .iter()
            .map(|s| format!(
                "vec3<f32>({}, {}, {})",
                float(s.colour[0]),
                float(s.colour[1]),
                float(s.colour[2])
            ))
            .collect::<Vec<_>>()
            .join(", "),
        n = knots.len(),
        s = stops.len(),
    );
    code
}

impl Emitter<'_> {
    /// Emits a combination's operands (each its own model), then its glue and
    /// `combine_sample_cell` under its own prefix; returns that function's name.
    fn combine(
        &mut self,
        op: &CombineOp,
        operands: &[ExportNode],
        channels: usize,
        ret: &str,
        out: &mut String,
    ) -> Result<String, GpuError> {
        let mut names = Vec::new();
        let mut widths = Vec::new();
        for node in operands {
            let width = node.channels();
            let value = if width == 1 { "f32" } else { "vec3<f32>" };
            names.push(self.node(node, value, out)?);
            widths.push(width);
        }
        let k = self.models;
        self.models += 1;
        self.sources.push(format!(
            "model {k}: a combination (glue shaders/combine.wgsl) of the models before it"
        ));
        let prefix = format!("spectex_m{k}_");
        self.constant_bytes += combine_table_bytes(op) as usize;
        let mut code = export_shader("combine");
        code.push_str(SHADER_ARITHMETIC);
        code.push_str(&combine_constants(op));
        let _ = write!(
            code,
            "\n/// The combination at the position `cell + offset` (pixels): its operands there, \
             then the operation per channel.\n\
             fn combine_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> {ret} {{\n"
        );
        for (k, name) in names.iter().enumerate() {
            let _ = writeln!(code, "    let v{k} = {name}(cell, offset);");
        }
        let exprs: Vec<String> = (0..channels)
            .map(|c| combine_expression(op, &widths, c))
            .collect();
        if channels == 1 {
            let _ = writeln!(code, "    return {};\n}}", exprs[0]);
        } else {
            let _ = writeln!(code, "    return {ret}({});\n}}", exprs.join(", "));
        }
        let mut map = self.common_map.clone();
        for name in top_level_names(&code) {
            map.insert(name.clone(), format!("{prefix}{name}"));
        }
        let _ = write!(
            out,
            "\n// ---- spectex: model {k}, a combination, prefix {prefix} ----\n"
        );
        out.push_str(&rename(&code, &map, &HashSet::new()));
        Ok(format!("{prefix}combine_sample_cell"))
    }
}

/// The global variables of `module` that code reachable from the names `used` reads: those
/// named there, and those the functions named there read, directly or through their calls.
fn read_globals(module: &naga::Module, used: &HashSet<String>) -> HashSet<String> {
    fn calls(block: &naga::Block, out: &mut Vec<naga::Handle<naga::Function>>) {
        for statement in block.iter() {
            match statement {
                naga::Statement::Call { function, .. } => out.push(*function),
                naga::Statement::Block(b) => calls(b, out),
                naga::Statement::If { accept, reject, .. } => {
                    calls(accept, out);
                    calls(reject, out);
                }
                naga::Statement::Switch { cases, .. } => {
                    for case in cases {
                        calls(&case.body, out);
                    }
                }
                naga::Statement::Loop {
                    body, continuing, ..
                } => {
                    calls(body, out);
                    calls(continuing, out);
                }
                _ => {}
            }
        }
    }
    let mut read: HashSet<String> = module
        .global_variables
        .iter()
        .filter_map(|(_, v)| v.name.clone())
        .filter(|name| used.contains(name))
        .collect();
    let mut stack: Vec<naga::Handle<naga::Function>> = module
        .functions
        .iter()
        .filter(|(_, f)| f.name.as_ref().is_some_and(|n| used.contains(n)))
        .map(|(h, _)| h)
        .collect();
    let mut seen: HashSet<naga::Handle<naga::Function>> = stack.iter().copied().collect();
    while let Some(h) = stack.pop() {
        let function = &module.functions[h];
        for (_, expression) in function.expressions.iter() {
            if let naga::Expression::GlobalVariable(g) = expression
                && let Some(name) = &module.global_variables[*g].name
            {
                read.insert(name.clone());
            }
        }
        let mut callees = Vec::new();
        calls(&function.body, &mut callees);
        for callee in callees {
            if seen.insert(callee) {
                stack.push(callee);
            }
        }
    }
    read
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn whole_sides_are_integers_up_to_2_pow_24() {
        assert_eq!(whole_sides(&[]), [0]);
        assert_eq!(
            whole_sides(&[32.0, 9.5, 1.0, 0.5, 16_777_216.0, 16_777_218.0]),
            [0b10101]
        );
        let mut many = vec![2.5; 33];
        many[32] = 7.0;
        assert_eq!(whole_sides(&many), [0, 1]);
    }

    pub fn lattice_tables_decompose_every_bit_weight() {
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

    /// `export/split.wgsl`'s `export_split_modular` in the same f32 and wrapping integer
    /// operations (no contraction: the shader may fuse `rem − cell·low`, one rounding fewer).
    fn split_modular(n: i32, side: f64) -> (i32, f32) {
        let k = modular(side).unwrap();
        let m = k.modulus as i32;
        let inv = (1.0 / f64::from(k.modulus)) as f32;
        let p = k.power();
        let frac = (f64::from(p % k.modulus) / f64::from(k.modulus)) as f32;
        let mut qa = (n as f32 * inv).floor() as i32;
        let mut a = n.wrapping_sub(qa.wrapping_mul(m));
        let qb = (a as f32 * inv).floor() as i32;
        a -= qb * m;
        qa = qa.wrapping_add(qb);
        if a < 0 {
            a += m;
            qa = qa.wrapping_sub(1);
        } else if a >= m {
            a -= m;
            qa = qa.wrapping_add(1);
        }
        let au = a as u32;
        let mut t = (a as f32 * frac).floor() as i32;
        let mut r = au
            .wrapping_mul(p % k.modulus)
            .wrapping_sub((t as u32).wrapping_mul(m as u32)) as i32;
        let tc = (r as f32 * inv).floor() as i32;
        r -= tc * m;
        t += tc;
        if r < 0 {
            r += m;
            t -= 1;
        } else if r >= m {
            r -= m;
            t += 1;
        }
        let mut cell = (qa as u32)
            .wrapping_mul(p)
            .wrapping_add(au.wrapping_mul(p / k.modulus))
            .wrapping_add(t as u32) as i32;
        let mut rem = r as f32 * (1.0 / f64::from(p)) as f32;
        if k.low != 0.0 {
            let s = side as f32;
            rem -= cell as f32 * k.low;
            loop {
                if rem < 0.0 {
                    rem += s;
                    cell = cell.wrapping_sub(1);
                } else if rem >= s {
                    rem -= s;
                    cell = cell.wrapping_add(1);
                } else {
                    break;
                }
            }
        }
        (cell, rem)
    }

    /// `export/split.wgsl`'s 32-step table sum.
    fn split_tables_sum(n: i32, side: f64) -> (i32, f32) {
        let (sides, q, rk) = lattice_tables(&[side]);
        let s = sides[0];
        let (mut qs, mut r) = (0u32, 0.0f32);
        for k in 0..32 {
            if (n as u32 >> k) & 1 == 1 {
                qs = qs.wrapping_add(q[k]);
                let room = s - rk[k];
                if r >= room {
                    r -= room;
                    qs = qs.wrapping_add(1);
                } else {
                    r += rk[k];
                }
            }
        }
        (qs as i32, r)
    }

    /// The closed-form split is the tables' exact split where the side is an f32, and within
    /// a few f32 roundings of the f64 truth where it is not (simplex's skew lattices, a Gabor
    /// radius), however far n is from the origin.
    pub fn modular_split_is_exact_for_f32_sides() {
        let f2 = (3f64.sqrt() - 1.0) / 2.0;
        let sides = [
            9.5,
            20.0 / (1.0 + f2),
            20.0 / f2,
            10.0 / (1.0 + f2),
            32.0 / f2,
            1.0,
            1.0 + 1e-9,
            1.5,
            3.0,
            16.000_001,
            13.370_000_839_233_398,
            13.37,
            97.125,
            4_095.999_7,
            16_777_215.0,
            1_234.567_891_234,
        ];
        let mut ns: Vec<i32> = vec![
            0,
            1,
            -1,
            2,
            -2,
            7,
            i32::MAX,
            i32::MIN,
            i32::MIN + 1,
            i32::MAX - 1,
            10_000_000,
            -10_000_000,
            10_000_123,
            16_777_216,
            16_777_217,
            -16_777_217,
        ];
        let mut x = 0x9E37_79B9u32;
        for _ in 0..4000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            ns.push(x as i32);
            ns.push((x as i32) >> (x % 31));
        }
        for &side in &sides {
            assert!(modular(side).is_some(), "{side}");
            let s = side as f32;
            for &n in &ns {
                let (cell, rem) = split_modular(n, side);
                assert!((0.0..s).contains(&rem), "{side} {n}: {rem}");
                if f64::from(s) == side {
                    assert_eq!((cell, rem), split_tables_sum(n, side), "{side} {n}");
                } else {
                    // The truth n − cell·Δ (cell wrapped to i32 as the CPU's): within a few
                    // roundings of a number below Δ.
                    let want = f64::from(n) - f64::from(cell) * side;
                    let ulp = f64::from(s) * 2f64.powi(-23);
                    assert!(
                        (f64::from(rem) - want).abs()
                            <= 2.0 * ulp + f64::from(n).abs() * 2f64.powi(-46),
                        "{side} {n}: {rem} vs {want}"
                    );
                    let (_, table_rem) = split_tables_sum(n, side);
                    let _ = table_rem;
                }
            }
        }
        // Lattices the closed form leaves to the tables.
        for side in [0.5, 0.999, 16_777_218.0, 3e9, f64::INFINITY] {
            assert!(modular(side).is_none(), "{side}");
        }
    }
}
