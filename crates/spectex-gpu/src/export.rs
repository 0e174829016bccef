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
//! A warp exports its three models and `export/warp.wgsl` composing them, a combination its
//! operands and `export/combine.wgsl` applying its operation per channel, a texture by
//! example its LRP models and its own shader (`ExportNode`). Where the compute path's host
//! computes per tile what a pixel reads, the glue computes it from the position: phasor
//! kernels and Voronoi sites are drawn in the shader with the randomness contract's WGSL
//! twin (`export/phasor.rs`, `export/voronoi.rs`), an Islamic pattern's lattice fractions
//! summed from fixed-point tables (`export/islamic.rs`), a matrix transformation's pixel cell
//! taken from the integer part. Tables are constants up to
//! [`MAX_TABLE_BYTES`]; with [`TableStorage::Buffer`] ([`export`]) they go to one read-only
//! storage buffer whose bytes [`Export::tables`] holds and whose layout the header lists.
//! Every kind exports; features with no exact export give [`GpuError::Unsupported`] naming
//! them (Voronoi Lloyd relaxation and image colours, a 3D phasor model with varying fields:
//! each kind's export module says why). A phasor model's varying fields are evaluated in the
//! shader in f32 (`export/phasor.rs`), image fields located with the lattice split.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use spectex_model::{Model, ModelKind};

use crate::GpuError;
use crate::kernel::{ShaderKernel, Table};

mod combine;
mod islamic;
mod matrix;
mod phasor;
mod voronoi;

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
    (
        "texton",
        include_str!("../../../shaders/export/texton.wgsl"),
    ),
    (
        "wavelet",
        include_str!("../../../shaders/export/wavelet.wgsl"),
    ),
    (
        "texture",
        include_str!("../../../shaders/export/texture.wgsl"),
    ),
    ("warp", include_str!("../../../shaders/export/warp.wgsl")),
    (
        "subdivision",
        include_str!("../../../shaders/export/subdivision.wgsl"),
    ),
    (
        "phasor",
        include_str!("../../../shaders/export/phasor.wgsl"),
    ),
    (
        "matrix",
        include_str!("../../../shaders/export/matrix.wgsl"),
    ),
    (
        "islamic",
        include_str!("../../../shaders/export/islamic.wgsl"),
    ),
    (
        "combine",
        include_str!("../../../shaders/export/combine.wgsl"),
    ),
    (
        "voronoi",
        include_str!("../../../shaders/export/voronoi.wgsl"),
    ),
];

/// Bytes of tables up to which an exported module is portable WGSL: the WGSL specification lets
/// an implementation refuse more than 8192 bytes in the `private` address space (Tint, in
/// browsers, does; naga, hence wgpu and Bevy, does not).
pub const PORTABLE_TABLE_BYTES: usize = 8192;

/// Bytes of tables above which [`TableStorage::Constants`] refuses a model: every table is a
/// constant array initialised per shader invocation, and a module this large already takes
/// lavapipe seconds to compile (a fitted LRP model with tens of thousands of frequencies,
/// 0.3–1 MB of tables, would take minutes and no driver promises to accept it). Such models
/// export with [`TableStorage::Buffer`]: the tables in one storage buffer.
pub const MAX_TABLE_BYTES: u64 = 65_536;

/// Bytes of tables up to which [`TableStorage::Buffer`] exports a model: WebGPU's default
/// `maxStorageBufferBindingSize` (128 MiB), which every adapter offers.
pub const MAX_BUFFER_BYTES: u64 = 128 << 20;

/// Default bind group of the tables' storage buffer (`spectex export --group`): the last of
/// the four groups WebGPU guarantees, so it stays clear of groups 0–2 that renderers (Bevy's
/// view, mesh and 2D material groups among them) fill.
pub const DEFAULT_GROUP: u32 = 3;
/// Default binding of the tables' storage buffer (`spectex export --binding`): far above the
/// bindings a material declares from 0, so the buffer can also join a material's own group.
pub const DEFAULT_BINDING: u32 = 100;

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
    /// Further small constants the glue reads (WGSL declarations, prefixed like the rest).
    constants: String,
    /// Placeholders of the glue and their replacements (not prefixed).
    substitutions: Vec<(&'static str, String)>,
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
    ) -> Result<ExportNode, GpuError> {
        let tile = kernel.tile_tables(&crate::GpuWindow::new(1, 1), None, u64::MAX)?;
        let mut bindings = vec![tile.uniform];
        bindings.extend(resident.iter().map(|t| t.bytes.clone()));
        bindings.extend(tile.tables.into_iter().map(|t| t.bytes));
        Ok(ExportNode::Leaf(Self {
            shader: K::SHADER,
            glue,
            channels: kernel.output_channels(),
            bindings,
            lattices,
            constants: String::new(),
            substitutions: Vec::new(),
        }))
    }

    /// The parts of a kind whose bindings the caller packed (`bindings`: every group-0
    /// binding but the output, in binding order, the uniform first).
    pub(crate) fn new(
        shader: &'static str,
        glue: &'static str,
        channels: usize,
        bindings: Vec<Vec<u8>>,
        lattices: Vec<f64>,
    ) -> Self {
        Self {
            shader,
            glue,
            channels,
            bindings,
            lattices,
            constants: String::new(),
            substitutions: Vec::new(),
        }
    }
}

/// A texture by example as the exporter sees it: its own shader's parts and the LRP models
/// whose values it reads (export/texture.wgsl).
#[derive(Debug, Clone)]
pub(crate) struct TextureExport {
    /// The texture shader's parts.
    pub(crate) leaf: ExportParts,
    /// Per channel: its random-phase strata as an LRP model, or (no strata) its mean.
    pub(crate) strata: Vec<Result<ExportNode, f32>>,
    /// The turbulence: σ, the centre and per axis its strata as LRP models, in order.
    pub(crate) turbulence: Option<(f32, f32, [Vec<ExportNode>; 2])>,
}

/// A model as the exporter sees it: one kind's parts, or a warp of three models.
#[derive(Debug, Clone)]
pub(crate) enum ExportNode {
    /// A kind with a shader.
    Leaf(ExportParts),
    /// A texture by example and the LRP models it reads.
    Texture(Box<TextureExport>),
    /// `base(p + D(x(p), y(p)))` (`spectex_model::warp`).
    Warp {
        /// The displaced model.
        base: Box<ExportNode>,
        /// The displacement models.
        x: Box<ExportNode>,
        y: Box<ExportNode>,
        /// Pixels per unit of x and y.
        strength: f32,
    },
    /// `op` applied per channel to the operands' values (`spectex_model::combine`).
    Combine {
        /// The operation.
        op: spectex_model::combine::CombineOp,
        /// The operands, in the operation's order.
        operands: Vec<ExportNode>,
        /// Values per pixel of the result.
        channels: usize,
    },
}

impl ExportNode {
    /// Adds WGSL declarations the glue reads (a leaf's; ignored by a warp).
    pub(crate) fn with_constants(mut self, declarations: String) -> Self {
        if let Self::Leaf(parts) = &mut self {
            parts.constants = declarations;
        }
        self
    }

    /// Values per pixel.
    fn channels(&self) -> usize {
        match self {
            Self::Leaf(p) => p.channels,
            Self::Texture(t) => t.leaf.channels,
            Self::Warp { base, .. } => base.channels(),
            Self::Combine { channels, .. } => *channels,
        }
    }
}

/// The export layer of a model kind.
pub(crate) trait ExportKind: ModelKind {
    /// The parts of a **validated** model on the plane `z` (ignored by 2D models).
    ///
    /// # Errors
    /// [`GpuError::Unsupported`] for a kind (or a feature of it) the exporter lacks.
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError>;
}

/// Kinds the exporter does not cover (yet): `export_parts` gives [`GpuError::Unsupported`].
/// Kept for kinds being added: list a new kind here until its export exists (none is listed
/// today: every kind exports, some features of phasor and Voronoi models excepted).
#[allow(
    unused_macros,
    reason = "kept for kinds being added, which list themselves here until they export"
)]
macro_rules! unsupported_export {
    ($($kind:ty),*) => {$(
        impl ExportKind for $kind {
            fn export_parts(&self, _z: f64) -> Result<ExportNode, GpuError> {
                Err(GpuError::Unsupported {
                    kind: <$kind as ModelKind>::NAME,
                    feature: "WGSL export (spectex export --wgsl)".into(),
                })
            }
        }
    )*};
}

impl ExportKind for spectex_model::Warp {
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        Ok(ExportNode::Warp {
            base: Box::new(parts(&self.base, z)?),
            x: Box::new(parts(&self.x, z)?),
            y: Box::new(parts(&self.y, z)?),
            strength: self.strength,
        })
    }
}

/// The parts of one model: the one dispatch over kinds of the exporter.
fn parts(model: &Model, z: f64) -> Result<ExportNode, GpuError> {
    spectex_model::for_each_kind!(model, m: K => <K as ExportKind>::export_parts(m, z))
}

/// A model's export parts, for kinds made of other models (a texture's LRP strata).
pub(crate) trait ExportNodeOf {
    /// [`ExportKind::export_parts`] of the model's kind.
    fn export_node(&self, z: f64) -> Result<ExportNode, GpuError>;
}

impl ExportNodeOf for Model {
    fn export_node(&self, z: f64) -> Result<ExportNode, GpuError> {
        parts(self, z)
    }
}

/// Where an exported module keeps its tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableStorage {
    /// WGSL constants in the module: self-contained, no bind group (up to
    /// [`MAX_TABLE_BYTES`]).
    Constants,
    /// One read-only storage buffer `var<storage, read> spectex_tables: array<u32>` at
    /// `@group(group) @binding(binding)`, whose bytes [`Export::tables`] holds (layout in the
    /// module's header; up to [`MAX_BUFFER_BYTES`]).
    Buffer {
        /// The bind group.
        group: u32,
        /// The binding in it.
        binding: u32,
    },
}

/// Options of [`export`] and [`wgsl_module`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExportOptions {
    /// The plane of a 3D model (pixels); 2D models ignore it.
    pub z: f64,
    /// Where the tables go.
    pub tables: TableStorage,
}

impl Default for ExportOptions {
    fn default() -> Self {
        Self {
            z: 0.0,
            tables: TableStorage::Constants,
        }
    }
}

/// An exported model: the WGSL module and, for [`TableStorage::Buffer`], the storage buffer's
/// bytes (little-endian 32-bit words).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Export {
    /// The module's source.
    pub wgsl: String,
    /// The bytes to upload to `spectex_tables` (empty for [`TableStorage::Constants`]).
    pub tables: Vec<u8>,
}

/// The WGSL module of `model` with its tables as constants (see [`export`]).
///
/// # Errors
/// As [`export`]; with [`TableStorage::Buffer`] in `options`,
/// [`GpuError::Unsupported`] (this function returns no buffer).
pub fn wgsl_module(model: &Model, options: &ExportOptions) -> Result<String, GpuError> {
    if options.tables != TableStorage::Constants {
        return Err(GpuError::Unsupported {
            kind: "export",
            feature: "a storage buffer from wgsl_module (call export)".into(),
        });
    }
    Ok(export(model, options)?.wgsl)
}

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
struct Emitter<'a> {
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

/// The WGSL module of `model` (see the module doc and the header comment it starts with) and,
/// for [`TableStorage::Buffer`], its tables' bytes.
///
/// # Errors
/// [`GpuError::Model`] for an invalid model, [`GpuError::Window`] for a non-finite or far `z`,
/// [`GpuError::Unsupported`] for a kind the exporter does not cover,
/// [`GpuError::LimitsExceeded`] for tables over [`MAX_TABLE_BYTES`] as constants (export them
/// with [`TableStorage::Buffer`]) or over [`MAX_BUFFER_BYTES`] in a buffer.
pub fn export(model: &Model, options: &ExportOptions) -> Result<Export, GpuError> {
    model.validate()?;
    let z = options.z;
    if !(z.is_finite() && z.abs() <= crate::MAX_POSITION) {
        return Err(GpuError::Window {
            parameter: "z",
            value: z,
            range: "finite, |z| ≤ 2³⁰ pixels",
        });
    }
    let node = parts(model, z)?;
    let needed = node_bytes(&node);
    match options.tables {
        TableStorage::Constants if needed > MAX_TABLE_BYTES => {
            return Err(GpuError::LimitsExceeded {
                what: "bytes of model tables as constants of one WGSL module (spectex_gpu::export::MAX_TABLE_BYTES; export them to a storage buffer: spectex export --tables)",
                value: needed,
                limit: MAX_TABLE_BYTES,
            });
        }
        TableStorage::Buffer { .. } if needed > MAX_BUFFER_BYTES => {
            return Err(GpuError::LimitsExceeded {
                what: "bytes of model tables in the export's storage buffer (spectex_gpu::export::MAX_BUFFER_BYTES)",
                value: needed,
                limit: MAX_BUFFER_BYTES,
            });
        }
        _ => {}
    }
    let common = crate::wgsl_source("common").unwrap_or_default();
    // Domain warping is the compute evaluator's (bind group 1): here it is off, a constant.
    let common_body = format!(
        "{}\n/// No displacement: the exported module evaluates the model where it is asked to.\n\
         const warp_params: WarpParams = WarpParams(0u, 0u, 0u, 0u);\n\
         /// Never read (`warp_params.enabled` is 0): what `grid_point` names in place of the\n\
         /// compute evaluator's displacement binding.\n\
         var<private> warp_displacement: array<vec2<f32>, 1>;\n",
        strip(&common)
    );
    let common_names = top_level_names(&common_body);
    let common_map: HashMap<String, String> = common_names
        .iter()
        .map(|n| (n.clone(), format!("spectex_{n}")))
        .collect();

    let mut emitter = Emitter {
        storage: options.tables,
        common_map: &common_map,
        buffer: Vec::new(),
        layout: Vec::new(),
        constant_bytes: 0,
        models: 0,
        sources: Vec::new(),
    };
    let ret = match node.channels() {
        1 => "f32",
        _ => "vec3<f32>",
    };
    let mut chunks = String::new();
    let top = emitter.node(&node, ret, &mut chunks)?;
    let mut out = header(model, &emitter, ret, z);
    out.push_str("\n// ---- spectex: common functions (common.wgsl), prefix spectex_ ----\n");
    out.push_str(&rename(&common_body, &common_map, &HashSet::new()));
    if let TableStorage::Buffer { group, binding } = options.tables {
        let _ = write!(
            out,
            "\n/// The model's tables (layout in the header), 32-bit little-endian words.\n\
             @group({group}) @binding({binding}) var<storage, read> spectex_tables: array<u32>;\n"
        );
    }
    out.push_str(&chunks);
    let _ = write!(
        out,
        "
// ---- spectex: entry points ----

/// The model's value at the position `cell + offset` in model pixels: the precise entry (see
/// the header).
fn spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> {ret} {{
    return {top}(cell, offset);
}}

/// The model's value at the position `p` in model pixels (`|p| < 2²⁴` for whole pixels to be
/// exact; see the header for positions farther out).
fn spectex_sample(p: vec2<f32>) -> {ret} {{
    let whole = floor(p);
    return spectex_sample_cell(vec2<i32>(whole), p - whole);
}}
"
    );
    let out = composable_members(&out);
    // Little-endian words, whatever the host's order.
    let tables = emitter
        .buffer
        .chunks_exact(4)
        .flat_map(|w| u32::from_ne_bytes([w[0], w[1], w[2], w[3]]).to_le_bytes())
        .collect();
    Ok(Export { wgsl: out, tables })
}

/// Bytes of tables of a node: every binding but the uniform, and per lattice a side, its
/// inverse and 32 quotient and remainder words.
fn node_bytes(node: &ExportNode) -> u64 {
    match node {
        ExportNode::Leaf(parts) => {
            parts
                .bindings
                .iter()
                .skip(1)
                .map(|b| b.len() as u64)
                .sum::<u64>()
                + 4 * 66 * parts.lattices.len() as u64
        }
        ExportNode::Texture(t) => {
            node_bytes(&ExportNode::Leaf(t.leaf.clone()))
                + t.strata
                    .iter()
                    .flatten()
                    .chain(
                        t.turbulence
                            .iter()
                            .flat_map(|(_, _, axes)| axes.iter().flatten()),
                    )
                    .map(node_bytes)
                    .sum::<u64>()
        }
        ExportNode::Warp { base, x, y, .. } => node_bytes(base) + node_bytes(x) + node_bytes(y),
        ExportNode::Combine { op, operands, .. } => {
            operands.iter().map(node_bytes).sum::<u64>() + combine::table_bytes(op)
        }
    }
}

impl Emitter<'_> {
    /// Emits `node` (sub-models first) into `out` and returns the name of its
    /// `fn(cell: vec2<i32>, offset: vec2<f32>) -> ret`.
    fn node(&mut self, node: &ExportNode, ret: &str, out: &mut String) -> Result<String, GpuError> {
        match node {
            ExportNode::Leaf(parts) => {
                let k = self.models;
                self.models += 1;
                self.sources.push(format!(
                    "model {k}: shaders/{}.wgsl, glue shaders/export/{}.wgsl",
                    parts.shader, parts.glue
                ));
                let chunk = self.model_chunk(parts, k)?;
                out.push_str(&chunk);
                Ok(format!("spectex_m{k}_{}_sample_cell", parts.glue))
            }
            ExportNode::Texture(t) => {
                // The LRP models first, then the texture reading them.
                let mut inputs = String::from(
                    "/// The LRP models' values at `cell + offset` (export/texture.wgsl).\n\
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
                    "model {k}: a warp (glue shaders/export/warp.wgsl) of the models before it"
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
        let mut names = Vec::new();
        // Tables read from the storage buffer through accessor functions.
        let mut accessors = HashSet::new();
        for (i, (_, var)) in globals.iter().enumerate() {
            let name = var.name.clone().unwrap_or_default();
            let Some(bytes) = parts.bindings.get(i) else {
                // The output (last binding): nothing to emit.
                continue;
            };
            names.push(name.clone());
            let in_buffer = matches!(self.storage, TableStorage::Buffer { .. })
                && !matches!(var.space, naga::AddressSpace::Uniform);
            let decl = if in_buffer {
                accessors.insert(name.clone());
                self.buffer_table(&module, &format!("{prefix}{name}"), &name, var.ty, bytes)?
            } else {
                if !matches!(var.space, naga::AddressSpace::Uniform) {
                    self.constant_bytes += bytes.len();
                }
                declaration(&module, &name, var.ty, bytes)?
            };
            tables.push_str(&decl);
        }
        let (sides, quotients, remainders) = lattice_tables(&parts.lattices);
        let inverses: Vec<f32> = parts.lattices.iter().map(|s| (1.0 / s) as f32).collect();
        self.constant_bytes +=
            4 * (sides.len() + inverses.len() + quotients.len() + remainders.len());
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
                    "export_quotients",
                    "export_remainders",
                ]
                .map(String::from),
            )
        {
            map.insert(name.clone(), format!("{prefix}{name}"));
        }
        map.insert("spectex_tables".to_owned(), "spectex_tables".to_owned());
        for (name, value) in &parts.substitutions {
            map.insert((*name).to_owned(), value.clone());
        }
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
fn header(model: &Model, emitter: &Emitter<'_>, ret: &str, z: f64) -> String {
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

/// `source` with every struct member name that naga's namer would change on writing the
/// module back (one ending in a digit or `_`, or holding `__`: `proc::Namer` appends `_`)
/// given a letter suffix, `_m`, everywhere it appears (member accesses too; comments are
/// left alone). Bevy composes a material's imports with naga_oil, which writes each module
/// back through naga and refuses one whose struct members come back renamed ("Composable module
/// identifiers must not require substitution"), as the compute shaders' `_pad0` and `a00`
/// would; top-level names are suffixed by naga_oil itself and need nothing. Renaming an
/// identifier everywhere is a pure renaming: no value changes.
fn composable_members(source: &str) -> String {
    let unsafe_name =
        |n: &str| n.ends_with(|c: char| c.is_ascii_digit() || c == '_') || n.contains("__");
    let mut map: HashMap<String, String> = HashMap::new();
    let mut in_struct = false;
    for line in source.lines() {
        let line = line.trim();
        if line.starts_with("struct ") {
            in_struct = true;
        } else if in_struct && line.starts_with('}') {
            in_struct = false;
        } else if in_struct {
            // A member line is `[@attr(..) ]name: type,`: the identifier before `:`.
            let code = line.split_once("//").map_or(line, |(code, _)| code);
            let decl = code
                .rsplit_once(')')
                .map_or(code, |(_, after)| after.trim());
            if let Some((field, _)) = decl.split_once(':') {
                let field = field.trim();
                if !field.is_empty()
                    && field.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                    && unsafe_name(field)
                {
                    map.insert(
                        field.to_owned(),
                        format!("{}_m", field.trim_end_matches('_')),
                    );
                }
            }
        }
    }
    if map.is_empty() {
        return source.to_owned();
    }
    replace_identifiers(source, &map, &HashSet::new(), true)
}

/// `source` with every identifier in `map` replaced, except member names: after a `.`, and
/// field declarations (an identifier followed by `:` inside a struct's braces); and every
/// indexing `name[i]` of a name in `calls` (tables in the storage buffer) turned into the
/// call `name(u32(i))` of its accessor. Comments are copied unchanged.
pub(crate) fn rename(
    source: &str,
    map: &HashMap<String, String>,
    calls: &HashSet<String>,
) -> String {
    replace_identifiers(source, map, calls, false)
}

/// [`rename`], member names included where `members` (accesses after a `.` and field
/// declarations are then replaced too).
fn replace_identifiers(
    source: &str,
    map: &HashMap<String, String>,
    calls: &HashSet<String>,
    members: bool,
) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len() + source.len() / 4);
    let mut i = 0;
    let mut depth = 0usize;
    let mut struct_depth: Option<usize> = None;
    let mut pending_struct = false;
    let mut last_significant = ' ';
    // Per open `[`: whether it opened an accessor call (closed by `))`).
    let mut brackets: Vec<bool> = Vec::new();
    let mut call_pending = false;
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
                Some(new) if members || (last_significant != '.' && !is_field) => {
                    out.push_str(new);
                }
                _ => out.push_str(&word),
            }
            call_pending =
                last_significant != '.' && calls.contains(&word) && chars.get(j) == Some(&'[');
            last_significant = 'a';
            continue;
        }
        match c {
            '[' if call_pending => {
                brackets.push(true);
                // Drop the blanks between the name and the bracket.
                while out.ends_with(char::is_whitespace) {
                    out.pop();
                }
                out.push_str("(u32(");
                call_pending = false;
                last_significant = '(';
                i += 1;
                continue;
            }
            '[' => brackets.push(false),
            ']' if brackets.last() == Some(&true) => {
                brackets.pop();
                out.push_str("))");
                last_significant = ')';
                i += 1;
                continue;
            }
            ']' => {
                brackets.pop();
            }
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
    fn members_naga_would_rename_get_a_letter_suffix_everywhere() {
        let src = "struct P {\n    a00: f32,\n    @align(16) _pad0: u32,\n    key: u32, // key2\n}\n\
                   fn f(p: P) -> f32 { let a00 = p.a00; return a00 + f32(p.key); } // a00\n";
        assert_eq!(
            composable_members(src),
            "struct P {\n    a00_m: f32,\n    @align(16) _pad0_m: u32,\n    key: u32, // key2\n}\n\
             fn f(p: P) -> f32 { let a00_m = p.a00_m; return a00_m + f32(p.key); } // a00\n"
        );
    }

    #[test]
    fn rename_skips_members_fields_and_comments() {
        let map: HashMap<String, String> = [("strata", "p_strata"), ("S", "p_S")]
            .map(|(a, b)| (a.to_owned(), b.to_owned()))
            .into();
        let src = "struct S {\n    strata: u32,\n    s: S,\n}\n// strata\nfn f() { let a = strata[params.strata]; }\n";
        let out = rename(src, &map, &HashSet::new());
        assert_eq!(
            out,
            "struct p_S {\n    strata: u32,\n    s: p_S,\n}\n// strata\nfn f() { let a = p_strata[params.strata]; }\n"
        );
    }

    #[test]
    fn rename_turns_buffer_tables_into_accessor_calls() {
        let map: HashMap<String, String> = [("t", "p_t"), ("u", "p_u")]
            .map(|(a, b)| (a.to_owned(), b.to_owned()))
            .into();
        let calls: HashSet<String> = ["t".to_owned()].into();
        let src = "let a = t [u[i] + t[j].x] + s.t[2];\nfn t(i: u32) {}\n";
        assert_eq!(
            rename(src, &map, &calls),
            "let a = p_t(u32(p_u[i] + p_t(u32(j)).x)) + s.t[2];\nfn p_t(i: u32) {}\n"
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
