// matrix.wgsl — matrix transformation (survey §2.4), the GPU twin of
// crates/spectex-cpu/src/matrix.rs; the definition is the module doc of
// crates/spectex-model/src/matrix.rs. Composed after common.wgsl.
//
// The host computes A = (M⁻¹)^k mod N in integers and each column's and row's cell on the pixel
// grid (side 1) with its f32 offset (spectex_model::grid::locate_cell, the CPU's split). A pixel
// reduces its cell modulo N and reads the source at A·q mod N: integers only (every product and
// sum is below 2²⁵), so the texel is the CPU's exactly; the value mean + amplitude·S is one
// rounding on each side (a contracted product-add may skip one).

/// Per-dispatch values and the model's constants.
struct MatrixParams {
    width: u32,
    height: u32,
    /// N.
    size: u32,
    /// 0: procedural rings, 1: image texels.
    image: u32,
    /// A = (M⁻¹)^k mod N by rows.
    a00: u32,
    a01: u32,
    a10: u32,
    a11: u32,
    /// Rings of the procedural source.
    rings: u32,
    amplitude: f32,
    mean: f32,
    _pad0: u32,
}

@group(0) @binding(0) var<uniform> params: MatrixParams;
/// The image source's N·N texels (one unused texel for the rings).
@group(0) @binding(1) var<storage, read> texels: array<f32>;
@group(0) @binding(2) var<storage, read> columns: array<GridAxis>;
@group(0) @binding(3) var<storage, read> rows: array<GridAxis>;
@group(0) @binding(4) var<storage, read_write> output: array<f32>;

// The model's shape (common.wgsl's "Shapes").
override MATRIX_IMAGE: u32 = 0xffffffffu;

fn matrix_image() -> u32 {
    return shape_or(MATRIX_IMAGE, params.image);
}

/// The procedural source ⌊rings·|d|²/N²⌋ mod 2, d = 2s + 1 − N (spectex_model::matrix::rings_value).
fn matrix_rings(s: vec2<u32>) -> f32 {
    let n = params.size;
    let dx = select(n - (2u * s.x + 1u), (2u * s.x + 1u) - n, 2u * s.x + 1u >= n);
    let dy = select(n - (2u * s.y + 1u), (2u * s.y + 1u) - n, 2u * s.y + 1u >= n);
    let r2 = dx * dx + dy * dy;
    return f32((params.rings * r2 / (n * n)) & 1u);
}

@compute @workgroup_size(8, 8, 1)
fn matrix_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let index = gid.y * params.width + gid.x;
    let at = grid_point(columns[gid.x], rows[gid.y], index, 1.0f);
    let column = at.column;
    let row = at.row;
    let n = i32(params.size);
    let qx = u32(select(0, wrap_cell(column.cell, n), column.valid == 1u));
    let qy = u32(select(0, wrap_cell(row.cell, n), row.valid == 1u));
    let s = vec2<u32>(
        (params.a00 * qx + params.a01 * qy) % params.size,
        (params.a10 * qx + params.a11 * qy) % params.size,
    );
    var v: f32;
    if (matrix_image() == 1u) {
        v = texels[s.y * params.size + s.x];
    } else {
        v = matrix_rings(s);
    }
    output[index] = params.mean + params.amplitude * v;
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a matrix transformation (after the kernel above and
// export/split.wgsl; no lattice: the pixel grid has side 1). The compute path's host gives
// each column and row its cell ⌊x⌋; here the position's integer part is that cell exactly
// (`export_normalise`), and the texel is read as `matrix_main` reads it: the cell reduced
// modulo N, mapped by A = (M⁻¹)^k mod N in integers.

/// The transformation at the position `cell + offset` (pixels).
fn matrix_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    let n = i32(params.size);
    let qx = u32(wrap_cell(at.n.x, n));
    let qy = u32(wrap_cell(at.n.y, n));
    let s = vec2<u32>(
        (params.a00 * qx + params.a01 * qy) % params.size,
        (params.a10 * qx + params.a11 * qy) % params.size,
    );
    var v: f32;
    if (matrix_image() == 1u) {
        v = texels[s.y * params.size + s.x];
    } else {
        v = matrix_rings(s);
    }
    return params.mean + params.amplitude * v;
}
