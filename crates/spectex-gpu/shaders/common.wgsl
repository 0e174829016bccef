// common.wgsl — the WGSL twin of the randomness contract (`spectex_model::random`, specified in
// docs/ARCHITECTURE.md) and of the scalar functions of `spectex_model::math` (cosine in turns,
// Kaiser–Bessel window, exponential). spectex-gpu prepends this file to every model shader.
//
// Integers: WGSL `u32` arithmetic wraps (mod 2^32), `>>` on `u32` is a logical shift and the
// shift amounts below are in 4..19, so every integer function here gives the same bits as the
// Rust one; `crates/spectex-gpu/tests/it/contract.rs` checks it on the device.
//
// Floats: every constant is written with the `f` suffix, which WGSL parses directly as a
// correctly rounded f32 (an unsuffixed literal is an abstract float rounded twice); the decimal
// strings are the shortest round-trip forms of the Rust f32 constants, and
// `crates/spectex-gpu/tests/it/shaders.rs` checks their bits through naga. The arithmetic is the CPU's, in the same
// order; a WGSL compiler may still contract `a * b + c` into a fused multiply-add, which WGSL
// cannot forbid, so these functions are accurate to the stated tolerances but not guaranteed to
// be bit-identical to the CPU (crates/spectex-gpu/tests/it/contract.rs reports how many bits differ on the adapter).
//
// Displacement convention (GPU warping):
//
// Every model shader is composed after `common.wgsl`, which declares bind group 1: binding 0
// `WarpParams { enabled: u32, pad ×3 }` (uniform) and binding 1 `warp_displacement:
// array<vec2<f32>>` (read-only storage), one `(dx, dy)` in model pixels per tile pixel, index
// `y·width + x` (the output's), already clamped and summed over nested warps on the host. The host
// binds group 1 for every dispatch (`enabled = 0` and one unused element when not warping). A
// shader that supports warping reads the displacement only when `enabled == 1` and applies it to
// the host's `(cell, f32 offset)` split of its pixel before taking neighbouring cells:
// `warp_relocate(cell, offset, d / cell_side)` (offset + d, the cell moved by the floor, the
// fraction kept; LRP rebuilds its four lattice offsets from the remainder the same way), so the
// arithmetic stays on numbers of the cell's size and positions near 10⁷ keep their precision.
// A shader whose host splits columns and rows on one cell grid (`GridAxis`: Gabor, phasor,
// texton, Voronoi, subdivision, matrix) takes its pixel through `grid_point`.
// Where the host draws cells for a tile (phasor), it widens the box to the displaced pixels' cells
// (plus one for the f32 relocation). `classic.wgsl` relocates each octave's (cell, offset) with
// `1/c_o` from its octave table (simplex noise skews the displacement, `d + (Σd)·F`, and adds it
// to the skewed fraction before the floor); `wavelet.wgsl` relocates each band's tile index
// (modulo the tile side) with `1/c_b`; `texture.wgsl` relocates its placement cells. Every model
// shader does this, so any model can be warped on the GPU; a new shader must apply `warp_relocate`
// to its axis splits too (the GPU warp tests shift every kind's window with constant
// displacements).

// ---------------------------------------------------------------------------------------------
// Integer hash and PRNG (PCG: Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020).

/// Multiplier of the 32-bit LCG step.
const LCG_MULTIPLIER: u32 = 747796405u;
/// Increment of the 32-bit LCG step.
const LCG_INCREMENT: u32 = 2891336453u;
/// Multiplier of PCG's RXS-M-XS output permutation.
const RXS_M_XS_MULTIPLIER: u32 = 277803737u;

/// PCG's RXS-M-XS output permutation, a bijection of u32.
fn permute(state: u32) -> u32 {
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * RXS_M_XS_MULTIPLIER;
    return (word >> 22u) ^ word;
}

/// One LCG step, the state transition of the PRNG.
fn lcg_step(state: u32) -> u32 {
    return state * LCG_MULTIPLIER + LCG_INCREMENT;
}

/// `pcg_hash`: permute(lcg_step(v)).
fn hash(v: u32) -> u32 {
    return permute(lcg_step(v));
}

/// The part of cell_hash that depends only on the layer and the seed.
fn layer_key(layer: u32, seed: u32) -> u32 {
    return hash(layer + hash(seed));
}

/// The part of cell_hash that depends only on the row; signed rows are reinterpreted as u32.
fn row_key(y: i32, key: u32) -> u32 {
    return hash(bitcast<u32>(y) + key);
}

/// cell_hash of cell x in the row whose row_key is given.
fn cell_hash_in_row(x: i32, key: u32) -> u32 {
    return hash(bitcast<u32>(x) + key);
}

/// Periodic models (spectex_model::period): lattice cell `c` as it enters the hash, wrapped into
/// 0..n for a lattice with n cells per period (the CPU's rem_euclid); unchanged for n = 0 (not
/// periodic). WGSL's % truncates toward zero, hence the correction of a negative remainder.
fn wrap_cell(c: i32, n: i32) -> i32 {
    if (n == 0) {
        return c;
    }
    let r = c % n;
    return select(r, r + n, r < 0);
}

/// The lower bound along one axis of the distance (cell units) from a point at `offset` in its
/// lattice cell to any point of the cell `d` away: `d − offset` for a cell after it,
/// `offset − (d + 1)` before it, 0 in its own (spectex_model::voronoi's `gap`). Rounding is
/// monotonic, so the f32 offset to a point of that cell is never smaller: a search that skips
/// cells whose gap already exceeds what it needs skips exactly what adds nothing.
fn cell_gap(offset: f32, d: i32) -> f32 {
    let before = select(0.0f, max(offset - f32(d + 1), 0.0f), d < 0);
    return select(before, max(f32(d) - offset, 0.0f), d > 0);
}

/// `cell_gap` squared: the lower bound of a squared distance's term along the axis.
fn cell_gap2(offset: f32, d: i32) -> f32 {
    let g = cell_gap(offset, d);
    return g * g;
}

/// hash(x + hash(y + hash(layer + hash(seed)))), wrapping addition.
fn cell_hash(x: i32, y: i32, layer: u32, seed: u32) -> u32 {
    return cell_hash_in_row(x, row_key(y, layer_key(layer, seed)));
}

/// Uniform f32 in [0, 1) from the top 24 bits: exact (an integer below 2^24 times 2^-24).
fn unit_f32(bits: u32) -> f32 {
    return f32(bits >> 8u) * 0x1p-24f;
}

/// The contract's stream: next_u32 returns hash(state) and advances state by one LCG step.
struct Prng {
    state: u32,
}

/// The next 32 random bits of `prng`.
fn prng_next_u32(prng: ptr<function, Prng>) -> u32 {
    (*prng).state = lcg_step((*prng).state);
    return permute((*prng).state);
}

/// The next uniform f32 in [0, 1) of `prng` (see unit_f32).
fn prng_next_f32(prng: ptr<function, Prng>) -> f32 {
    return unit_f32(prng_next_u32(prng));
}

// ---------------------------------------------------------------------------------------------
// Shapes. A kind's shader declares the fields of its uniform that fix a model's shape (a classic
// noise's basis, a phasor's output) again as pipeline-overridable constants defaulting to
// NO_SHAPE. The host sets them to the model's values (`ShaderKernel::constants`, one pipeline
// per shape), so the driver folds the branches and compiles only the ones the model takes;
// NO_SHAPE (the export's, where the uniform is a constant anyway) reads the uniform.

const NO_SHAPE: u32 = 0xffffffffu;

/// The shape constant `fixed`, or the uniform's `uniform` where it is NO_SHAPE.
fn shape_or(fixed: u32, uniform: u32) -> u32 {
    return select(fixed, uniform, fixed == NO_SHAPE);
}

// ---------------------------------------------------------------------------------------------
// Scalar functions (twins of crates/spectex-model/src/math.rs).

/// `t − round(t)` in [−0.5, 0.5], exact for |t| < 2^22.
///
/// The CPU writes the rounding as `(t + 1.5·2^23) − 1.5·2^23`, two exact IEEE operations, to
/// avoid a library call. A GPU compiler is free to simplify `(t + c) − c` to `t` for operations
/// not marked exact, which WGSL cannot request, so the GPU uses `round()` instead: WGSL's round
/// is round-half-to-even, the same integer the magic-number sum gives (ties to even, and
/// 1.5·2^23 is even), and `t − round(t)` is exact. The two forms therefore agree bit for bit.
fn fract_turns(t: f32) -> f32 {
    return t - round(t);
}

/// Minimax coefficients of cos(2πb) in b² on b ∈ [0, ¼], constant pinned to 1 (COS_TURNS in
/// spectex-model's math.rs, where the fit is described).
const COS_TURNS_0: f32 = 1.0f;
const COS_TURNS_1: f32 = -19.739182f;
const COS_TURNS_2: f32 = 64.93522f;
const COS_TURNS_3: f32 = -85.25401f;
const COS_TURNS_4: f32 = 56.34071f;

/// cos(2π·t) for an angle in turns (|t| < 2^22): exact reduction, fold to [0, ¼], degree-8
/// minimax polynomial by Horner's rule (absolute error below 2e-7 without contraction).
fn cos_turns(t: f32) -> f32 {
    let a = abs(fract_turns(t));
    let far = a > 0.25f;
    let b = select(a, 0.5f - a, far);
    let x = b * b;
    var p = COS_TURNS_4;
    p = p * x + COS_TURNS_3;
    p = p * x + COS_TURNS_2;
    p = p * x + COS_TURNS_1;
    p = p * x + COS_TURNS_0;
    return select(p, -p, far);
}

/// Minimax coefficients of P in w = u^{3/2}·P(u), u = 1 − r²/2.25 (KB_POLY in spectex-model's
/// math.rs, where the fit is described).
const KB_POLY_0: f32 = 0.017600192f;
const KB_POLY_1: f32 = 0.09834109f;
const KB_POLY_2: f32 = 0.21247686f;
const KB_POLY_3: f32 = 0.29003343f;
const KB_POLY_4: f32 = 0.15506108f;
const KB_POLY_5: f32 = 0.20569898f;
const KB_POLY_6: f32 = -0.027654441f;
const KB_POLY_7: f32 = 0.04844275f;
/// 1 / 2.25 rounded to f32 (the CPU's `1.0 / 2.25` folded in f32).
const KB_INV_SUPPORT2: f32 = 0.44444445f;
/// 2.25 = 1.5², the squared support radius in units of Δ.
const KB_SUPPORT2: f32 = 2.25f;

/// The Kaiser–Bessel window as a function of r² = (|x − x_i| / Δ)²; exactly 0 for r² ≥ 2.25.
fn kaiser_bessel_r2(r2: f32) -> f32 {
    let inside = 1.0f - r2 * KB_INV_SUPPORT2;
    let u = max(inside, 0.0f);
    var p = KB_POLY_7;
    p = p * u + KB_POLY_6;
    p = p * u + KB_POLY_5;
    p = p * u + KB_POLY_4;
    p = p * u + KB_POLY_3;
    p = p * u + KB_POLY_2;
    p = p * u + KB_POLY_1;
    p = p * u + KB_POLY_0;
    let w = u * sqrt(u) * p;
    return select(0.0f, w, inside > 0.0f);
}

/// High part of ln 2 (n·LN2_HI is exact for |n| < 512) and the remainder.
const EXP_LN2_HI: f32 = 0.69314575f;
const EXP_LN2_LO: f32 = 1.4286068e-6f;
const EXP_LOG2_E: f32 = 1.442695f;
/// Taylor coefficients 1/k!, k = 2..7, rounded to f32 (k = 0, 1 are 1).
const EXP_TAYLOR_2: f32 = 0.5f;
const EXP_TAYLOR_3: f32 = 0.16666667f;
const EXP_TAYLOR_4: f32 = 0.041666668f;
const EXP_TAYLOR_5: f32 = 0.008333334f;
const EXP_TAYLOR_6: f32 = 0.0013888889f;
const EXP_TAYLOR_7: f32 = 0.0001984127f;

/// e^z in f32 (twin of the CPU's exp_poly): z clamped to [−87, 88], n = round(z·log2 e),
/// Cody–Waite reduction, degree-7 Taylor polynomial, 2^n from its exponent bits. The CPU rounds
/// with the magic number; round() gives the same n (see fract_turns).
fn exp_poly(z_in: f32) -> f32 {
    let z = min(max(z_in, -87.0f), 88.0f);
    let n = round(z * EXP_LOG2_E);
    let f = (z - n * EXP_LN2_HI) - n * EXP_LN2_LO;
    var p = EXP_TAYLOR_7;
    p = p * f + EXP_TAYLOR_6;
    p = p * f + EXP_TAYLOR_5;
    p = p * f + EXP_TAYLOR_4;
    p = p * f + EXP_TAYLOR_3;
    p = p * f + EXP_TAYLOR_2;
    p = p * f + 1.0f;
    p = p * f + 1.0f;
    let two_n = bitcast<f32>(u32(i32(n) + 127) << 23u);
    return p * two_n;
}

/// sin(2π·t) for an angle in turns: cos_turns(t − ¼) (spectex_model::math::sin_turns).
fn sin_turns(t: f32) -> f32 {
    return cos_turns(t - 0.25f);
}

/// Minimax coefficients of atan(a)/(2π) = a·P(a²) on a ∈ [0, 1] (ATAN_TURNS in
/// spectex-model's math.rs, where the fit is described).
const ATAN_TURNS_0: f32 = 0.15915483f;
const ATAN_TURNS_1: f32 = -0.053046122f;
const ATAN_TURNS_2: f32 = 0.031745948f;
const ATAN_TURNS_3: f32 = -0.022136277f;
const ATAN_TURNS_4: f32 = 0.015346049f;
const ATAN_TURNS_5: f32 = -0.008898746f;
const ATAN_TURNS_6: f32 = 0.0034796142f;
const ATAN_TURNS_7: f32 = -0.00064530916f;

/// atan2(y, x) / 2π in turns, in [−½, ½]; 0 at the origin (spectex_model::math::atan2_turns).
fn atan2_turns(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let steep = ay > ax;
    let lo = select(ay, ax, steep);
    let hi = select(ax, ay, steep);
    var a = 0.0f;
    if (hi > 0.0f) {
        a = lo / hi;
    }
    let s = a * a;
    var p = ATAN_TURNS_7;
    p = p * s + ATAN_TURNS_6;
    p = p * s + ATAN_TURNS_5;
    p = p * s + ATAN_TURNS_4;
    p = p * s + ATAN_TURNS_3;
    p = p * s + ATAN_TURNS_2;
    p = p * s + ATAN_TURNS_1;
    p = p * s + ATAN_TURNS_0;
    var r = a * p;
    if (steep) {
        r = 0.25f - r;
    }
    if (x < 0.0f) {
        r = 0.5f - r;
    }
    return select(r, -r, y < 0.0f);
}

// ---------------------------------------------------------------------------------------------
// Domain warping: the per-pixel displacement convention (spectex_model::warp), shared by every
// model shader that can be warped. Bind group 1 holds
//   binding 0: WarpParams (uniform) — `enabled` is 1 when the dispatch is displaced;
//   binding 1: warp_displacement (read-only storage) — one vec2<f32> per pixel of the tile,
//              row-major (index y·width + x, the output's pixel index), in model pixels,
//              already clamped to ±MAX_WARP on the host; one unused element when disabled.
// A shader applies it to the host's (cell, f32 offset) split of its pixel *before* it takes
// the neighbouring cells: offset + d in cell units, then the cell moves by floor of that and
// the offset keeps the fraction (warp_relocate), so the arithmetic stays on small numbers and a
// warp at (10⁷, 10⁷) is as precise as at the origin. When `enabled` is 0 a shader must not
// touch its positions at all (so an unwarped render keeps its bits). The host always binds
// group 1 (a disabled one for unwarped renders).

/// Whether this dispatch is displaced, and nothing else (padding to 16 bytes).
struct WarpParams {
    enabled: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(1) @binding(0) var<uniform> warp_params: WarpParams;
@group(1) @binding(1) var<storage, read> warp_displacement: array<vec2<f32>>;

/// A point's cell on a grid and its offset in the cell (cell units, nominally [0, 1)).
struct Located {
    cell: i32,
    offset: f32,
}

/// The point at `offset` in `cell` moved by `d` cell units: the cell shifts by ⌊offset + d⌋
/// (wrapping like the CPU's i32 cells) and the offset keeps the fraction.
fn warp_relocate(cell: i32, offset: f32, d: f32) -> Located {
    let u = offset + d;
    let shift = floor(u);
    return Located(bitcast<i32>(bitcast<u32>(cell) + bitcast<u32>(i32(shift))), u - shift);
}

/// One column (or row) of a tile on a cell grid, as the host splits it in f64 (spectex-gpu's
/// `axis::CellAxis`, packed by `axis::cell_axis`): its cell, the offset in the cell (cell units)
/// and whether it is inside the usable range (0: the kind's out-of-range value).
struct GridAxis {
    cell: i32,
    offset: f32,
    valid: u32,
}

/// A pixel's column and row on a cell grid.
struct GridPoint {
    column: GridAxis,
    row: GridAxis,
}

/// The pixel `index` of the tile at `column` and `row` (the host's split), moved by its
/// displacement in cell units, `warp_displacement[index]·inv_side` (`inv_side` = 1/cell side),
/// when the dispatch is displaced (`warp_relocate` on each axis, the valid flags kept), and
/// untouched otherwise: the warp-relocation prologue of every shader on a cell grid.
fn grid_point(column: GridAxis, row: GridAxis, index: u32, inv_side: f32) -> GridPoint {
    var at = GridPoint(column, row);
    if (warp_params.enabled == 1u) {
        let d = warp_displacement[index] * inv_side;
        let cx = warp_relocate(column.cell, column.offset, d.x);
        let cy = warp_relocate(row.cell, row.offset, d.y);
        at.column.cell = cx.cell;
        at.column.offset = cx.offset;
        at.row.cell = cy.cell;
        at.row.offset = cy.offset;
    }
    return at;
}

/// spectex_model::filter's FADE_START and FADE_END: the clamp of a minified render's filter
/// fades from the first to the second (cycles per output pixel).
const FILTER_FADE_START: f32 = 0.45f;
const FILTER_FADE_END: f32 = 0.55f;
const FILTER_PI: f32 = 3.1415927f;

/// spectex_model::filter::response_f32: sinc(v) times the clamp faded over
/// [FILTER_FADE_START, FILTER_FADE_END], v in cycles per output pixel.
fn filter_response(v: f32) -> f32 {
    var sinc = 1.0f;
    if (v >= 1e-6f) {
        sinc = sin_turns(0.5f * v) / (FILTER_PI * v);
    }
    var taper = 1.0f;
    if (v >= FILTER_FADE_END) {
        taper = 0.0f;
    } else if (v > FILTER_FADE_START) {
        let c = cos_turns(0.25f * (v - FILTER_FADE_START) / (FILTER_FADE_END - FILTER_FADE_START));
        taper = c * c;
    }
    return sinc * taper;
}
