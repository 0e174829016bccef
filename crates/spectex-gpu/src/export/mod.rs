//! A model as one self-contained WGSL module for someone else's shader (`spectex export
//! --wgsl`): [`wgsl_module`] writes `fn spectex_sample(p: vec2<f32>) -> f32` (`vec3<f32>` for
//! colour models), callable from a fragment shader at any position, and
//! `spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>)` for positions far from the origin.
//!
//! Generated, not written per kind: the module is the kind's own compute shader
//! (`shaders/<kind>.wgsl`, after `common.wgsl`) with its bindings and compute entry point
//! removed, the tables the device evaluator uploads (the same packers, the same bytes) emitted
//! as WGSL constants in place of the bindings (their types read from the shader by naga), and
//! the kind's glue (the end of its `shaders/<kind>.wgsl`, [`EXPORT_SHADERS`]), which locates a position on the
//! kind's lattices itself (`export/split.wgsl`) instead of reading the host's per-tile tables.
//! Every name is prefixed (`spectex_` for the common functions, `spectex_m<k>_` for model `k`:
//! a warp's sub-models each get their own), so the module can be pasted into any shader.
//!
//! A warp exports its three models and the glue of `warp.wgsl` composing them, a combination its
//! operands and the glue of `combine.wgsl` applying its operation per channel, a texture by
//! example its LRP models and its own shader (`ExportNode`). Where the compute path's host
//! computes per tile what a pixel reads, the glue computes it from the position: phasor
//! kernels and Voronoi sites are drawn in the shader with the randomness contract's WGSL
//! twin (`phasor.rs`, `voronoi.rs`), an Islamic pattern's lattice fractions
//! summed from fixed-point tables (`islamic.rs`), a matrix transformation's pixel cell
//! taken from the integer part. Tables are constants up to
//! [`MAX_TABLE_BYTES`]; with [`TableStorage::Buffer`] ([`export`]) they go to one read-only
//! storage buffer whose bytes [`Export::tables`] holds and whose layout the header lists.
//! Every kind exports; features with no exact export give [`GpuError::Unsupported`] naming
//! them (Voronoi Lloyd relaxation and image colours, a 3D phasor model with varying fields:
//! each kind's module says why). A phasor model's varying fields are evaluated in the
//! shader in f32 (`phasor.rs`), image fields located with the lattice split.
//!
//! Layout: this file holds the public API and the kind dispatch; `emitter` writes the module
//! (per model its chunk, the storage buffer's layout, the header), `values` prints binding
//! values as WGSL of their naga types, `wgsl_text` rewrites WGSL sources (bindings and entry
//! points stripped, names prefixed), and each kind's `ExportKind` impl is in its module
//! (`crate::<kind>`, beside its `GpuKind`).

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::sync::LazyLock;

use spectex_model::{Model, ModelKind};

use crate::GpuError;
use crate::kernel::{ShaderKernel, Table, TileDisplacement};

use emitter::{Emitter, header};
pub(crate) use values::float;
use wgsl_text::{composable_members, rename, strip, top_level_names};

pub(crate) mod emitter;
mod values;
pub(crate) mod wgsl_text;

/// The lattice split every exported model uses (`shaders/export/split.wgsl`) and each kind's
/// glue (its `<kind>_sample_cell`, the end of its `shaders/<kind>.wgsl`), as the kind declares
/// it ([`ExportKind::GLUE`]).
pub static EXPORT_SHADERS: LazyLock<Vec<(&'static str, &'static str)>> = LazyLock::new(|| {
    let mut files = vec![("split", include_str!("../../shaders/export/split.wgsl"))];
    spectex_model::for_each_kind!(types: K => {
        files.push((<K as ModelKind>::NAME, <K as ExportKind>::GLUE));
    });
    files
});

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
    /// Placeholders of the glue and their replacements (WGSL whose names are the chunk's,
    /// prefixed like the glue).
    substitutions: Vec<(&'static str, String)>,
    /// Bindings kept as constants with [`TableStorage::Buffer`] too: small tables the glue
    /// reads at literal indexes only (per octave, per stratum), which a driver then folds.
    constant_tables: &'static [&'static str],
}

impl ExportParts {
    /// The parts of a shader kind: `kernel`'s uniform and per-tile tables for a one-pixel tile
    /// at the origin, after its `resident` tables. A table no code the glue reaches reads (a
    /// per-tile one, mostly) is emitted with one zero element, so every name the shader
    /// declares exists (`Emitter::model_chunk`).
    pub(crate) fn of<K: ShaderKernel>(
        kernel: &K,
        resident: &[Table],
        lattices: Vec<f64>,
        glue: &'static str,
    ) -> Result<ExportNode, GpuError> {
        let tile = kernel.tile_tables(
            &crate::GpuWindow::new(1, 1),
            TileDisplacement::None,
            u64::MAX,
        )?;
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
            constant_tables: &[],
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
            constant_tables: &[],
        }
    }
}

/// A texture by example as the exporter sees it: its own shader's parts and the LRP models
/// whose values it reads (the glue of texture.wgsl).
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

    /// Sets the glue's placeholders and their replacements (a leaf's; ignored by a warp).
    pub(crate) fn with_substitutions(mut self, substitutions: Vec<(&'static str, String)>) -> Self {
        if let Self::Leaf(parts) = &mut self {
            parts.substitutions = substitutions;
        }
        self
    }

    /// Replaces the glue's placeholder `name` with `count` statements, `statement(i)` for the
    /// literal index `i` in order: a loop written out, so every table the loop's body reads at
    /// the index is read at a constant one, which a driver folds (classic's octaves, LRP's
    /// strata).
    pub(crate) fn with_unrolled(
        self,
        name: &'static str,
        count: usize,
        statement: impl Fn(usize) -> String,
    ) -> Self {
        let body = (0..count).map(statement).collect::<Vec<_>>().join("\n    ");
        self.with_substitutions(vec![(name, body)])
    }

    /// Keeps these bindings (a leaf's) as constants in a storage-buffer export too
    /// ([`ExportParts::constant_tables`]).
    pub(crate) fn with_constant_tables(mut self, names: &'static [&'static str]) -> Self {
        if let Self::Leaf(parts) = &mut self {
            parts.constant_tables = names;
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
    /// The kind's glue: `shaders/<kind>.wgsl` from its `GLUE_MARKER` line (defines
    /// `<kind>_sample_cell`), listed in [`EXPORT_SHADERS`] under the kind's name.
    const GLUE: &'static str;

    /// The parts of a **validated** model on the plane `z` (ignored by 2D models).
    ///
    /// # Errors
    /// [`GpuError::Unsupported`] for a kind (or a feature of it) the exporter lacks.
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError>;
}

/// The parts of one model: the one dispatch over kinds of the exporter.
pub(super) fn parts(model: &Model, z: f64) -> Result<ExportNode, GpuError> {
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
    emit(model, &parts(model, z)?, options)
}

/// The module of `model` from its export parts `node` (what [`export`] does after taking
/// them).
pub(crate) fn emit(
    model: &Model,
    node: &ExportNode,
    options: &ExportOptions,
) -> Result<Export, GpuError> {
    let z = options.z;
    let needed = node_bytes(node);
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

    let mut emitter = Emitter::new(options.tables, &common_map);
    let ret = match node.channels() {
        1 => "f32",
        _ => "vec3<f32>",
    };
    let mut chunks = String::new();
    let top = emitter.node(node, ret, &mut chunks)?;
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
    Ok(Export {
        wgsl: out,
        tables: emitter.buffer_le(),
    })
}

/// Bytes of tables of a node: every binding but the uniform and the lattice split's tables
/// (`emitter::lattice_bytes`).
pub(super) fn node_bytes(node: &ExportNode) -> u64 {
    match node {
        ExportNode::Leaf(parts) => {
            parts
                .bindings
                .iter()
                .skip(1)
                .map(|b| b.len() as u64)
                .sum::<u64>()
                + emitter::lattice_bytes(&parts.lattices)
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
            operands.iter().map(node_bytes).sum::<u64>() + emitter::combine_table_bytes(op)
        }
    }
}

/// A file of [`EXPORT_SHADERS`] (empty for an unknown name, which naga then rejects).
pub(super) fn export_shader(name: &str) -> String {
    EXPORT_SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map_or_else(String::new, |(_, s)| (*s).to_owned())
}
