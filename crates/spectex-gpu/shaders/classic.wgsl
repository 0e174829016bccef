// classic.wgsl — the classic pointwise noises (improved Perlin gradient, simplex, value, Kensler
// and Worley noise, in 2D or on a plane z of 3D) and their fractal sums (fBm, turbulence, ridged),
// the GPU twin of crates/spectex-cpu/src/classic/mod.rs; the definitions and the randomness
// contract are in crates/spectex-model/src/classic.rs. Composed after common.wgsl.
//
// Randomness: octave o is layer o. A 2D corner (i, j) hashes to cell_hash(i, j, o, seed), a 3D
// corner (i, j, k) to cell_hash(i, j, o, cell_hash(k, 0, o, seed)); gradients take h >> 28,
// value noise 2·unit_f32(h) − 1, a Worley cell seeds Prng(h) and draws a Poisson count (one
// uniform against the f32 CDF) when the count is not fixed, then per point x, y (, z). Integer
// work only, so every draw is the CPU's bit for bit.
//
// Positions (DESIGN invariant 2): no f64 here. The host computes in f64, per tile column and
// row and per octave, p = x / c_o, the cell ⌊p⌋ and the offset f32(p − ⌊p⌋) (the CPU's own
// split, so the lattice bases and Worley see the CPU's offsets bit for bit), and for simplex
// noise the two parts p·(1 + F) and p·F of the skewed coordinates, each as an integer and an
// f32 fraction. The skewed coordinate X = px + (px + py (+ pz))·F is not separable per pixel,
// but it is a sum of per-axis parts: X = px·(1 + F) + py·F (+ pz·F), so the shader adds the
// integer parts as integers and the fractions (each in [0, 1)) in f32, then takes the floor of
// the fraction sum. The fractions lose nothing with the distance from the origin.
//
// The step position → (cell, offset) is one function per kind of basis (lattice_position,
// simplex_position): a per-pixel displacement (domain warping) is to be added to the in-cell
// offset there, before the floor that moves it into its cell.
//
// Floats: the CPU's f32 formulas in the CPU's order (fade by Horner, lerps a + t·(b − a),
// gradients by selects and sign-bit flips, Worley distances and the min/max insertion network);
// only FMA contraction by the compiler can make them differ (see spectex_crosscheck::tolerance::
// classic). Simplex offsets are formed from the skewed fractions here and from f64 on the CPU,
// so simplex noise agrees within that tolerance, not bit for bit.

/// Per-dispatch values and the model's constants.
struct ClassicParams {
    width: u32,
    height: u32,
    seed: u32,
    octaves: u32,
    /// 0 gradient, 1 simplex, 2 value, 3 Worley, 4 Kensler.
    basis: u32,
    /// 1 for a 3D model (on the plane z of the octave table), 0 for 2D.
    three_d: u32,
    /// 0 none or fBm, 1 turbulence, 2 ridged.
    fractal: u32,
    /// Worley: 0 Euclidean, 1 Manhattan, 2 Chebyshev.
    metric: u32,
    /// Worley: the fixed count of points per cell, or 0 for a Poisson count.
    fixed_count: u32,
    /// Worley: n − 1 for the largest n with C_n ≠ 0.
    needed: u32,
    /// 1: a minified render, octave o taken as `faded[o]` = (scale, constant) says
    /// (spectex_model::filter::classic_fade, computed by the host as the CPU does).
    filtered: u32,
    _pad1: u32,
    amplitude: f32,
    mean: f32,
    ridge_offset: f32,
    weight_gain: f32,
    /// Worley: C₁..C₄.
    coefficients: vec4<f32>,
    /// Worley: the largest distance kept (squared for the Euclidean metric).
    cap: f32,
    _pad2: u32,
    _pad3: u32,
    _pad4: u32,
    /// Worley: the Poisson CDF P(N ≤ k), k = 0..15, rounded to f32.
    cdf: array<vec4<f32>, 4>,
}

/// What one octave needs (host, f64 work rounded once).
struct ClassicOctave {
    /// gain^o.
    weight: f32,
    /// The plane z: its cell and offset (lattice bases and Worley, 3D).
    z_cell: i32,
    z_offset: f32,
    /// layer_key(o, seed), for 2D hashes.
    key2: u32,
    /// The plane z's parts of the skewed coordinates (simplex, 3D; zero in 2D): pz·F as
    /// cell + fraction (added to X and Y) and pz·(1 + F) (added to Z).
    z_other_cell: i32,
    z_other_frac: f32,
    z_own_cell: i32,
    z_own_frac: f32,
    /// 1 / c_o, cells per pixel (f32 of the f64 value), for domain warping.
    inv_cell: f32,
    /// Cells per period along x and y of a periodic model (0: not periodic): a corner's x and
    /// y enter the hash wrapped modulo them (wrap_cell, common.wgsl), as on the CPU.
    cells_x: i32,
    cells_y: i32,
    /// To a 16-byte stride, as a uniform array's element must be.
    _pad0: u32,
}

/// One column (or row) of the tile for one octave: p = x / c_o split as ⌊p⌋ and f32(p − ⌊p⌋);
/// the skew parts p·(1 + F) ("own": added to the same axis) and p·F ("other": added to the other
/// axes), each split the same way.
struct ClassicAxis {
    cell: i32,
    offset: f32,
    own_cell: i32,
    own_frac: f32,
    other_cell: i32,
    other_frac: f32,
}

@group(0) @binding(0) var<uniform> params: ClassicParams;
/// Read by every invocation at the same octave: a uniform (lavapipe read the storage table
/// lane by lane). MAX_OCTAVES (spectex_model::classic) records.
@group(0) @binding(1) var<uniform> octaves: array<ClassicOctave, 16>;
@group(0) @binding(2) var<storage, read> columns: array<ClassicAxis>;
@group(0) @binding(3) var<storage, read> rows: array<ClassicAxis>;
/// Per octave: (scale, constant) of a minified render; read only when params.filtered == 1.
@group(0) @binding(4) var<storage, read> faded: array<vec2<f32>>;
@group(0) @binding(5) var<storage, read_write> output: array<f32>;

/// The most rings of cells the Worley search visits (spectex_model::classic::WORLEY_MAX_RING).
const WORLEY_MAX_RING: i32 = 6;
/// (3 − √3)/6 and 1/6 rounded to f32 (the CPU's `SIMPLEX_G2 as f32`, `SIMPLEX_G3 as f32`).
const SIMPLEX_G2: f32 = 0.21132487f;
const SIMPLEX_G3: f32 = 0.16666667f;
/// (√3 − 1)/2 and 1/3 rounded to f32: the skew of a warp's displacement.
const SIMPLEX_F2: f32 = 0.36602542f;
const SIMPLEX_F3: f32 = 0.33333334f;
/// Squared kernel radii and output scales (spectex_model::classic).
const SIMPLEX2_R2: f32 = 0.5f;
const SIMPLEX2_SCALE: f32 = 70.0f;
const SIMPLEX3_R2: f32 = 0.6f;
const SIMPLEX3_SCALE: f32 = 32.0f;
/// Kensler noise's output scales (spectex_model::classic::KENSLER2_SCALE, KENSLER3_SCALE).
const KENSLER2_SCALE: f32 = 0.16739757f;
const KENSLER3_SCALE: f32 = 0.1369134f;

// The model's shape (common.wgsl's "Shapes"): a kernel keeping every basis ran perlin fBm 9×
// slower on lavapipe, bit for bit the same.
override CLASSIC_BASIS: u32 = 0xffffffffu;
override CLASSIC_THREE_D: u32 = 0xffffffffu;
override CLASSIC_FRACTAL: u32 = 0xffffffffu;
override CLASSIC_METRIC: u32 = 0xffffffffu;
/// 0: not periodic, so no corner is wrapped. The octave's cells per period are data, so a
/// kernel that may wrap keeps `wrap_cell`'s branch and modulo by a runtime count at every
/// corner; lavapipe runs both sides of it per lane (perlin fBm at 0.6× the speed of this).
override CLASSIC_PERIODIC: u32 = 0xffffffffu;
/// Worley: the fixed count of points per cell (0: Poisson), and n − 1 for the farthest F_n
/// the search needs, which indexes its four distances (a runtime index keeps that array in
/// per-invocation memory).
override CLASSIC_FIXED_COUNT: u32 = 0xffffffffu;
override CLASSIC_NEEDED: u32 = 0xffffffffu;

fn classic_basis() -> u32 {
    return shape_or(CLASSIC_BASIS, params.basis);
}

fn classic_three_d() -> u32 {
    return shape_or(CLASSIC_THREE_D, params.three_d);
}

fn classic_fractal() -> u32 {
    return shape_or(CLASSIC_FRACTAL, params.fractal);
}

fn classic_metric() -> u32 {
    return shape_or(CLASSIC_METRIC, params.metric);
}

/// Corner `c` as it enters the hash: wrapped into a periodic octave's cells (`wrap_cell`,
/// which leaves it where the count is 0), as it is where CLASSIC_PERIODIC is 0.
fn classic_wrap(c: i32, cells: i32) -> i32 {
    if (CLASSIC_PERIODIC == 0u) {
        return c;
    }
    return wrap_cell(c, cells);
}

/// a + b on i32 with wrapping (as the CPU's wrapping_add).
fn wrap_add(a: i32, b: i32) -> i32 {
    return bitcast<i32>(bitcast<u32>(a) + bitcast<u32>(b));
}

fn wrap_add3(a: vec3<i32>, b: vec3<i32>) -> vec3<i32> {
    return bitcast<vec3<i32>>(bitcast<vec3<u32>>(a) + bitcast<vec3<u32>>(b));
}

/// The hash of 2D corner (i, j) of the octave whose layer key is `key2`.
fn hash2(i: i32, j: i32, key2: u32) -> u32 {
    return cell_hash_in_row(i, row_key(j, key2));
}

/// The hash of 3D corner (i, j, k) of octave o: cell_hash(i, j, o, cell_hash(k, 0, o, seed)).
fn hash3(i: i32, j: i32, k: i32, o: u32) -> u32 {
    return cell_hash(i, j, o, cell_hash(k, 0, o, params.seed));
}

fn corner_hash(c: vec3<i32>, o: u32, octave: ClassicOctave) -> u32 {
    let i = classic_wrap(c.x, octave.cells_x);
    let j = classic_wrap(c.y, octave.cells_y);
    if (classic_three_d() == 1u) {
        return hash3(i, j, c.z, o);
    }
    return hash2(i, j, octave.key2);
}

/// 6t⁵ − 15t⁴ + 10t³ by Horner's rule (spectex_model::classic::fade).
fn fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

/// Perlin's grad(hash, x, y, z) chosen by the top four bits of h, by selects and sign-bit flips
/// (spectex_model::classic::gradient_dot).
fn gradient_dot(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let g = h >> 28u;
    let u = select(y, x, g < 8u);
    let v = select(select(z, x, g == 12u || g == 14u), y, g < 4u);
    let su = bitcast<f32>(bitcast<u32>(u) ^ ((g & 1u) << 31u));
    let sv = bitcast<f32>(bitcast<u32>(v) ^ ((g & 2u) << 30u));
    return su + sv;
}

/// 2·unit_f32(h) − 1, exact (spectex_model::classic::lattice_value).
fn lattice_value(h: u32) -> f32 {
    return f32(h >> 8u) * 0x1p-23f - 1.0f;
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + t * (b - a);
}

// ---------------------------------------------------------------------------------------------
// Position → (cell, offset).

/// A point of a lattice basis or of Worley noise: its cell and its offset in the cell.
struct Located3 {
    cell: vec3<i32>,
    offset: vec3<f32>,
}

/// The cell and in-cell offset of the pixel (column, row) for an octave: the host's split.
/// Offsets in [0, 1] are kept as they are (the host's f32 rounding can give exactly 1, as the
/// CPU's split does, and the CPU keeps it); an offset outside (after a displacement is added
/// here) moves to its own cell by the floor.
fn lattice_position(column: ClassicAxis, row: ClassicAxis, octave: ClassicOctave, d: vec2<f32>) -> Located3 {
    if (warp_params.enabled == 1u) {
        // Domain warping (common.wgsl): the displacement in cells moves the plane's point.
        let x = warp_relocate(column.cell, column.offset, d.x * octave.inv_cell);
        let y = warp_relocate(row.cell, row.offset, d.y * octave.inv_cell);
        let z = octave.z_offset;
        let fz = select(floor(z), 0.0f, z >= 0.0f && z <= 1.0f);
        let cz = bitcast<i32>(bitcast<u32>(octave.z_cell) + bitcast<u32>(i32(fz)));
        return Located3(vec3<i32>(x.cell, y.cell, cz), vec3<f32>(x.offset, y.offset, z - fz));
    }
    let u = vec3<f32>(column.offset, row.offset, octave.z_offset);
    let inside = u >= vec3<f32>(0.0f) & u <= vec3<f32>(1.0f);
    let f = select(floor(u), vec3<f32>(0.0f), inside);
    let cell = wrap_add3(vec3<i32>(column.cell, row.cell, octave.z_cell), vec3<i32>(f));
    return Located3(cell, u - f);
}

/// The skewed simplex cell (i, j, k) and the fraction in it of the pixel (column, row): per
/// axis, the axis's own part plus the other axes' parts (integers added as integers, fractions
/// in f32, in the order column, row, plane), then the floor of the fraction sum (in [0, 3)). A
/// warp's displacement d (pixels; cells after `inv_cell`) is skewed, d + (Σd)·F, and added to
/// the fraction sum before the floor.
fn simplex_position(column: ClassicAxis, row: ClassicAxis, octave: ClassicOctave, d: vec2<f32>) -> Located3 {
    let cells = wrap_add3(
        wrap_add3(
            vec3<i32>(column.own_cell, column.other_cell, column.other_cell),
            vec3<i32>(row.other_cell, row.own_cell, row.other_cell),
        ),
        vec3<i32>(octave.z_other_cell, octave.z_other_cell, octave.z_own_cell),
    );
    let fractions = (vec3<f32>(column.own_frac, column.other_frac, column.other_frac)
        + vec3<f32>(row.other_frac, row.own_frac, row.other_frac))
        + vec3<f32>(octave.z_other_frac, octave.z_other_frac, octave.z_own_frac);
    var moved = fractions;
    if (warp_params.enabled == 1u) {
        let dc = d * octave.inv_cell;
        let skew = select(SIMPLEX_F2, SIMPLEX_F3, classic_three_d() == 1u) * (dc.x + dc.y);
        moved = fractions + vec3<f32>(dc.x + skew, dc.y + skew, skew);
    }
    let f = floor(moved);
    return Located3(wrap_add3(cells, vec3<i32>(f)), moved - f);
}

// ---------------------------------------------------------------------------------------------
// Bases.

/// Gradient (gradient = true) or value noise at p (2D: the z cell and offset are ignored).
fn lattice_noise(p: Located3, o: u32, octave: ClassicOctave, gradient: bool) -> f32 {
    let u = p.offset;
    let sx = fade(u.x);
    let sy = fade(u.y);
    var c: array<f32, 8>;
    let layers = select(1, 2, classic_three_d() == 1u);
    for (var dz = 0; dz < layers; dz++) {
        for (var dy = 0; dy < 2; dy++) {
            for (var dx = 0; dx < 2; dx++) {
                let h = corner_hash(wrap_add3(p.cell, vec3<i32>(dx, dy, dz)), o, octave);
                var v: f32;
                if (gradient) {
                    let z = select(0.0f, u.z - f32(dz), classic_three_d() == 1u);
                    v = gradient_dot(h, u.x - f32(dx), u.y - f32(dy), z);
                } else {
                    v = lattice_value(h);
                }
                c[dz * 4 + dy * 2 + dx] = v;
            }
        }
    }
    let y0 = lerp(lerp(c[0], c[1], sx), lerp(c[2], c[3], sx), sy);
    if (classic_three_d() == 0u) {
        return y0;
    }
    let y1 = lerp(lerp(c[4], c[5], sx), lerp(c[6], c[7], sx), sy);
    return lerp(y0, y1, fade(u.z));
}

/// Kensler noise's kernel fade(1 − r²/4), 0 for r² ≥ 4 (spectex_model::classic::kensler_weight).
fn kensler_weight(r2: f32) -> f32 {
    let t = 1.0f - r2 * 0.25f;
    return select(0.0f, fade(t), t > 0.0f);
}

/// g · δ for the gradient chosen by hash(h) (spectex_model::classic::kensler_dot): 2D, direction
/// hash(h) >> 29 at multiples of 45° as c·(a_x, a_y), a in {0, ±1}, c = 1 or 1/√2; 3D, Perlin's
/// cube edge hash(h) % 12 over √2. Same operations in the same order as the CPU.
fn kensler_dot(h: u32, x: f32, y: f32, z: f32) -> f32 {
    let g = hash(h);
    if (classic_three_d() == 1u) {
        let e = g % 12u;
        // Edges 0–3 (±1, ±1, 0), 4–7 (±1, 0, ±1), 8–11 (0, ±1, ±1); signs: bit 0 flips the
        // first non-zero coordinate, bit 1 the second.
        let s0 = select(1.0f, -1.0f, (e & 1u) == 1u);
        let s1 = select(1.0f, -1.0f, (e & 2u) == 2u);
        let ax = select(s0, 0.0f, e >= 8u);
        let ay = select(select(0.0f, s1, e < 4u), s0, e >= 8u);
        let az = select(select(s1, 0.0f, e < 4u), s1, e >= 8u);
        return ((ax * x + ay * y) + az * z) * 0.70710677f;
    }
    let k = g >> 29u;
    // Directions k·45°: x component 1, 1, 0, −1, −1, −1, 0, 1; y the same turned by 90°.
    let ax = select(select(-1.0f, 0.0f, k == 2u || k == 6u), 1.0f, k <= 1u || k == 7u);
    let ay = select(select(-1.0f, 0.0f, k == 0u || k == 4u), 1.0f, k >= 1u && k <= 3u);
    let c = select(1.0f, 0.70710677f, (k & 1u) == 1u);
    return (ax * x + ay * y) * c;
}

/// Kensler noise at p: the 4×4 (4×4×4) corners from p.cell − 1 to p.cell + 2, visited z, y, x,
/// each adding kensler_weight(r²)·kensler_dot(P_x ⊕ P_y (⊕ P_z), δ) with the per-axis entries
/// P_a[n] = cell_hash(n, a, o, seed) (x and y wrapped by a periodic octave's cells); in 2D one
/// plane with δz = 0 and P_z = 0. The CPU's `kensler` in the same order.
fn kensler(p: Located3, o: u32, octave: ClassicOctave) -> f32 {
    let kx = row_key(0, octave.key2);
    let ky = row_key(1, octave.key2);
    let u = p.offset;
    var px: array<u32, 4>;
    var py: array<u32, 4>;
    var pz: array<u32, 4>;
    for (var d = 0; d < 4; d++) {
        let x = classic_wrap(wrap_add(p.cell.x, d - 1), octave.cells_x);
        let y = classic_wrap(wrap_add(p.cell.y, d - 1), octave.cells_y);
        px[d] = cell_hash_in_row(x, kx);
        py[d] = cell_hash_in_row(y, ky);
        pz[d] = cell_hash(wrap_add(p.cell.z, d - 1), 2, o, params.seed);
    }
    let three_d = classic_three_d() == 1u;
    let planes = select(1, 4, three_d);
    var sum = 0.0f;
    for (var dz = 0; dz < planes; dz++) {
        let hz = select(0u, pz[dz], three_d);
        let vz = select(0.0f, u.z - f32(dz - 1), three_d);
        for (var dy = 0; dy < 4; dy++) {
            let vy = u.y - f32(dy - 1);
            for (var dx = 0; dx < 4; dx++) {
                let vx = u.x - f32(dx - 1);
                let r2 = (vx * vx + vy * vy) + vz * vz;
                let w = kensler_weight(r2);
                let h = (px[dx] ^ py[dy]) ^ hz;
                sum += w * kensler_dot(h, vx, vy, vz);
            }
        }
    }
    return select(KENSLER2_SCALE, KENSLER3_SCALE, three_d) * sum;
}

/// One simplex corner's term max(0, r² − |δ|²)⁴ · (g · δ).
fn simplex_term(h: u32, r2: f32, dx: f32, dy: f32, dz: f32) -> f32 {
    let t = max(r2 - (dx * dx + dy * dy + dz * dz), 0.0f);
    let t2 = t * t;
    return t2 * t2 * gradient_dot(h, dx, dy, dz);
}

/// 2D simplex noise (Gustavson 2005) from the skewed cell and fraction.
fn simplex2(p: Located3, key2: u32) -> f32 {
    let t = (p.offset.x + p.offset.y) * SIMPLEX_G2;
    let x0 = p.offset.x - t;
    let y0 = p.offset.y - t;
    let step_x = x0 > y0;
    let i1 = select(0, 1, step_x);
    let j1 = select(1, 0, step_x);
    let x1 = (x0 - f32(i1)) + SIMPLEX_G2;
    let y1 = (y0 - f32(j1)) + SIMPLEX_G2;
    let x2 = (x0 - 1.0f) + 2.0f * SIMPLEX_G2;
    let y2 = (y0 - 1.0f) + 2.0f * SIMPLEX_G2;
    let i = p.cell.x;
    let j = p.cell.y;
    let h0 = hash2(i, j, key2);
    let h1 = hash2(wrap_add(i, i1), wrap_add(j, j1), key2);
    let h2 = hash2(wrap_add(i, 1), wrap_add(j, 1), key2);
    let c0 = simplex_term(h0, SIMPLEX2_R2, x0, y0, 0.0f);
    let c1 = simplex_term(h1, SIMPLEX2_R2, x1, y1, 0.0f);
    let c2 = simplex_term(h2, SIMPLEX2_R2, x2, y2, 0.0f);
    return SIMPLEX2_SCALE * ((c0 + c1) + c2);
}

/// One corner of 3D simplex noise: cell + d, offset δ0 − d + off; `planes` the layer keys of
/// the planes k and k + 1 (`simplex3`).
fn simplex3_corner(p: Located3, x0: vec3<f32>, d: vec3<i32>, off: f32, planes: vec2<u32>) -> f32 {
    let c = wrap_add3(p.cell, d);
    // hash3(c.x, c.y, c.z, o) from the layer key of its plane, k or k + 1.
    let h = cell_hash_in_row(c.x, row_key(c.y, select(planes.x, planes.y, d.z == 1)));
    let df = vec3<f32>(d);
    return simplex_term(h, SIMPLEX3_R2, (x0.x - df.x) + off, (x0.y - df.y) + off, (x0.z - df.z) + off);
}

/// 3D simplex noise (Perlin 2001, Gustavson 2005) from the skewed cell and fraction.
fn simplex3(p: Located3, o: u32) -> f32 {
    let t = ((p.offset.x + p.offset.y) + p.offset.z) * SIMPLEX_G3;
    let x0 = p.offset - vec3<f32>(t);
    // Gustavson's ranking of x0, y0, z0, as the CPU writes it.
    let a = x0.x >= x0.y;
    let b = x0.y >= x0.z;
    let c = x0.x >= x0.z;
    let d1 = vec3<i32>(
        select(0, 1, a && (b || c)),
        select(0, 1, !a && b),
        select(0, 1, !b && (!a || !c)),
    );
    let d2 = vec3<i32>(
        select(0, 1, a || (b && c)),
        select(0, 1, b || !a),
        select(0, 1, !b || (!a && !c)),
    );
    // The layer keys of hash3's planes k and k + 1 (`hash3` is `cell_hash(i, j, o, plane)`),
    // taken once for the four corners: a corner's plane depends on the ranking, so a compiler
    // cannot share them.
    let k1 = wrap_add(p.cell.z, 1);
    let planes = vec2<u32>(
        layer_key(o, cell_hash(p.cell.z, 0, o, params.seed)),
        layer_key(o, cell_hash(k1, 0, o, params.seed)),
    );
    let c0 = simplex3_corner(p, x0, vec3<i32>(0), 0.0f, planes);
    let c1 = simplex3_corner(p, x0, d1, SIMPLEX_G3, planes);
    let c2 = simplex3_corner(p, x0, d2, 2.0f * SIMPLEX_G3, planes);
    let c3 = simplex3_corner(p, x0, vec3<i32>(1), 3.0f * SIMPLEX_G3, planes);
    return SIMPLEX3_SCALE * (((c0 + c1) + c2) + c3);
}

/// The Worley distance of the offset (dx, dy, dz) (squared for the Euclidean metric).
fn worley_distance(dx: f32, dy: f32, dz: f32) -> f32 {
    let three_d = classic_three_d() == 1u;
    var d: f32;
    switch classic_metric() {
        case 1u: {
            let m = abs(dx) + abs(dy);
            d = select(m, m + abs(dz), three_d);
        }
        case 2u: {
            let m = max(abs(dx), abs(dy));
            d = select(m, max(m, abs(dz)), three_d);
        }
        default: {
            let e = dx * dx + dy * dy;
            d = select(e, e + dz * dz, three_d);
        }
    }
    return d;
}

/// Distance from the offset u to the cells outside the (2·ring + 1)^d block around its cell.
fn worley_gap(u: vec3<f32>, ring: i32) -> f32 {
    let r = f32(ring);
    var g = min(min(u.x + r, (r + 1.0f) - u.x), min(u.y + r, (r + 1.0f) - u.y));
    if (classic_three_d() == 1u) {
        g = min(g, min(u.z + r, (r + 1.0f) - u.z));
    }
    return select(g, g * g, classic_metric() == 0u);
}

/// The number of feature points of the cell whose stream is `prng`: fixed, or a Poisson count
/// (one uniform u, the count of k with u ≥ P(N ≤ k)).
fn worley_count(prng: ptr<function, Prng>) -> u32 {
    let fixed = shape_or(CLASSIC_FIXED_COUNT, params.fixed_count);
    if (fixed != 0u) {
        return fixed;
    }
    let u = prng_next_f32(prng);
    var count = 0u;
    for (var k = 0u; k < 16u; k++) {
        count += select(0u, 1u, u >= params.cdf[k / 4u][k % 4u]);
    }
    return count;
}

/// Inserts the distance of the offset (ddx, ddy, ddz) into `f`, the four smallest distances
/// so far in ascending order: the CPU's min/max insertion network.
fn worley_insert(f: ptr<function, array<f32, 4>>, ddx: f32, ddy: f32, ddz: f32) {
    var d = worley_distance(ddx, ddy, ddz);
    for (var k = 0; k < 4; k++) {
        let a = min((*f)[k], d);
        d = max((*f)[k], d);
        (*f)[k] = a;
    }
}

/// The feature points of the neighbour `d` of p's cell, drawn from its stream and inserted
/// into `f`.
fn worley_cell(f: ptr<function, array<f32, 4>>, p: Located3, d: vec3<i32>, o: u32, octave: ClassicOctave) {
    var prng = Prng(corner_hash(wrap_add3(p.cell, d), o, octave));
    let count = worley_count(&prng);
    let u = p.offset;
    let ry = u.y - f32(d.y);
    let rz = u.z - f32(d.z);
    for (var n = 0u; n < count; n++) {
        let ox = prng_next_f32(&prng);
        let oy = prng_next_f32(&prng);
        let ddx = u.x - (f32(d.x) + ox);
        let ddy = ry - oy;
        var ddz = 0.0f;
        if (classic_three_d() == 1u) {
            ddz = rz - prng_next_f32(&prng);
        }
        worley_insert(f, ddx, ddy, ddz);
    }
}

/// Ring `ring` of the Worley search around p, drawn and inserted into `f`: ring 1 is the
/// whole 3×3(×3) block, a later ring only its shell.
fn worley_ring(f: ptr<function, array<f32, 4>>, p: Located3, o: u32, octave: ClassicOctave, ring: i32) {
    let zr = select(0, ring, classic_three_d() == 1u);
    for (var dz = -zr; dz <= zr; dz++) {
        for (var dy = -ring; dy <= ring; dy++) {
            for (var dx = -ring; dx <= ring; dx++) {
                if (ring > 1 && max(max(abs(dx), abs(dy)), abs(dz)) != ring) {
                    continue;
                }
                worley_cell(f, p, vec3<i32>(dx, dy, dz), o, octave);
            }
        }
    }
}

/// Whether a cell at per-axis gaps (gx, gy, gz) from the pixel can still change the needed F_n:
/// each of its points is at least that far (rounding is monotonic), and a distance no smaller
/// than F_n moves only the F's past it, which weigh 0.
fn worley_reaches(f: ptr<function, array<f32, 4>>, gx: f32, gy: f32, gz: f32) -> bool {
    return worley_distance(gx, gy, gz) < (*f)[shape_or(CLASSIC_NEEDED, params.needed)];
}

/// Ring 1 of a 2D Worley search: the pixel's own cell, then its 8 neighbours, each skipped
/// where `worley_reaches` says it cannot matter (the own cell's points make that common).
/// lavapipe, F2 − F1: 1.3× faster in compute, the export unchanged. In 3D the same skip (per
/// cell or per row) made the compute kernel 9% faster but the exported module 6–10% slower, so
/// 3D keeps the plain block (`worley_ring` at ring 1).
fn worley_ring1_2d(f: ptr<function, array<f32, 4>>, p: Located3, o: u32, octave: ClassicOctave) {
    worley_cell(f, p, vec3<i32>(0), o, octave);
    let u = p.offset;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            if (dx == 0 && dy == 0) {
                continue;
            }
            if (worley_reaches(f, cell_gap(u.x, dx), cell_gap(u.y, dy), 0.0f)) {
                worley_cell(f, p, vec3<i32>(dx, dy, 0), o, octave);
            }
        }
    }
}

/// Worley noise C₁F₁ + C₂F₂ + C₃F₃ + C₄F₄ at p: the CPU's search, ring 1 (the 3×3(×3) block)
/// first, then ring after ring until the needed F_n is no farther than the unsearched cells, or
/// WORLEY_MAX_RING rings. The four smallest distances of a set do not depend on the order the
/// set is visited in, so this keeps the CPU's F_1 … F_n for the needed n (the cells a 2D ring 1
/// skips hold only farther points; the F's past F_n weigh 0). Ring 1
/// has its own call, at a constant ring: a driver unrolls its cells (lavapipe ran 3D Worley
/// 2× faster than with ring 1 inside the ring loop, bit for bit the same).
fn worley(p: Located3, o: u32, octave: ClassicOctave) -> f32 {
    var f = array<f32, 4>(params.cap, params.cap, params.cap, params.cap);
    if (classic_three_d() == 1u) {
        worley_ring(&f, p, o, octave, 1);
    } else {
        worley_ring1_2d(&f, p, o, octave);
    }
    var ring = 1;
    while (ring < WORLEY_MAX_RING && !(f[shape_or(CLASSIC_NEEDED, params.needed)] <= worley_gap(p.offset, ring))) {
        ring++;
        worley_ring(&f, p, o, octave, ring);
    }
    var g = vec4<f32>(f[0], f[1], f[2], f[3]);
    if (classic_metric() == 0u) {
        g = sqrt(g);
    }
    let c = params.coefficients;
    return ((c.x * g.x + c.y * g.y) + c.z * g.z) + c.w * g.w;
}

/// The basis at pixel (column, row) for octave o.
fn basis(column: ClassicAxis, row: ClassicAxis, octave: ClassicOctave, o: u32, d: vec2<f32>) -> f32 {
    var n: f32;
    switch classic_basis() {
        case 1u: {
            let p = simplex_position(column, row, octave, d);
            if (classic_three_d() == 1u) {
                n = simplex3(p, o);
            } else {
                n = simplex2(p, octave.key2);
            }
        }
        case 2u: {
            n = lattice_noise(lattice_position(column, row, octave, d), o, octave, false);
        }
        case 3u: {
            n = worley(lattice_position(column, row, octave, d), o, octave);
        }
        case 4u: {
            n = kensler(lattice_position(column, row, octave, d), o, octave);
        }
        default: {
            n = lattice_noise(lattice_position(column, row, octave, d), o, octave, true);
        }
    }
    return n;
}

/// Octave `o`'s term at the pixel whose column and row (for this octave) are given, displaced
/// by `d` when warping, added to `acc` (with `previous`, the ridged weight chain): the
/// per-pixel evaluation, shared by `classic_main` and the exported module
/// (the export glue at the end of this file, which locates the pixel itself).
fn classic_octave(o: u32, column: ClassicAxis, row: ClassicAxis, d: vec2<f32>, acc: ptr<function, f32>, previous: ptr<function, f32>) {
    let octave = octaves[o];
    let w = octave.weight;
    var fade = vec2<f32>(0.0f);
    if (params.filtered == 1u) {
        fade = faded[o];
        if (fade.x == 0.0f) {
            // Faded out: the basis is not evaluated, its expected term stays.
            switch classic_fractal() {
                case 2u: {
                    var s = fade.y;
                    if (o > 0u) {
                        s *= min(max((*previous) * params.weight_gain, 0.0f), 1.0f);
                    }
                    (*previous) = s;
                    (*acc) += w * s;
                }
                default: {
                    (*acc) += fade.y;
                }
            }
            return;
        }
    }
    let n = basis(column, row, octave, o, d);
    switch classic_fractal() {
        case 1u: {
            if (params.filtered == 1u) {
                (*acc) += fade.x * abs(n) + fade.y;
            } else {
                (*acc) += w * abs(n);
            }
        }
        case 2u: {
            let r = params.ridge_offset - abs(n);
            var s = r * r;
            if (params.filtered == 1u) {
                s = fade.x * s + fade.y;
            }
            if (o > 0u) {
                s *= min(max((*previous) * params.weight_gain, 0.0f), 1.0f);
            }
            (*previous) = s;
            (*acc) += w * s;
        }
        default: {
            if (params.filtered == 1u) {
                (*acc) += fade.x * n + fade.y;
            } else {
                (*acc) += w * n;
            }
        }
    }
}

@compute @workgroup_size(8, 8, 1)
fn classic_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    var acc = 0.0f;
    var previous = 0.0f;
    var d = vec2<f32>(0.0f);
    if (warp_params.enabled == 1u) {
        d = warp_displacement[gid.y * params.width + gid.x];
    }
    for (var o = 0u; o < params.octaves; o++) {
        classic_octave(o, columns[o * params.width + gid.x], rows[o * params.height + gid.y], d, &acc, &previous);
    }
    output[gid.y * params.width + gid.x] = params.mean + params.amplitude * acc;
}

// ---- export glue: `spectex export --wgsl` (after export/split.wgsl) ----
// The exported entry of a classic noise (after the kernel above and
// export/split.wgsl): octave o's lattices are the export's 3o (cell side c_o: the cell and
// offset), 3o + 1 (c_o/(1 + F): simplex's own skew part p·(1 + F)) and 3o + 2 (c_o/F: the
// other part p·F); the last two are read by simplex noise only. The exporter declares
// `classic_export_halving`: 1 where every octave's lattices are the previous one's halved
// exactly (lacunarity 2), so that a coordinate is split once, on octave 0, and each further
// octave's split follows from the previous one in a compare (`export_halve`) instead of a
// split of its own.

/// A coordinate's splits on one octave's lattices (the skew ones for simplex noise only).
struct ClassicExportSplits {
    base: ExportSplit,
    own: ExportSplit,
    other: ExportSplit,
}

/// The integer coordinate `n` split on octave `o`'s lattices.
fn classic_export_splits(n: i32, o: u32) -> ClassicExportSplits {
    let l = 3u * o;
    var s = ClassicExportSplits(export_split(n, l), ExportSplit(0i, 0.0f), ExportSplit(0i, 0.0f));
    if (classic_basis() == 1u) {
        s.own = export_split(n, l + 1u);
        s.other = export_split(n, l + 2u);
    }
    return s;
}

/// Octave `o`'s splits from octave `o − 1`'s `s`, its lattices halved.
fn classic_export_halve_splits(s: ClassicExportSplits, o: u32) -> ClassicExportSplits {
    let l = 3u * o;
    var h = ClassicExportSplits(export_halve(s.base, l), s.own, s.other);
    if (classic_basis() == 1u) {
        h.own = export_halve(s.own, l + 1u);
        h.other = export_halve(s.other, l + 2u);
    }
    return h;
}

/// The `ClassicAxis` of `classic.wgsl` for the coordinate `n + u` on octave `o`, from `n`'s
/// splits `s` on its lattices: each part is the cell and the fraction `(rem + u)/side` of its
/// lattice (the CPU rounds `p − ⌊p⌋` from f64 once).
fn classic_export_axis(s: ClassicExportSplits, u: f32, o: u32) -> ClassicAxis {
    let l = 3u * o;
    let base = export_carry(s.base, u, l);
    var axis = ClassicAxis(base.cell, (base.rem + u) * export_inv_sides[l], 0i, 0.0f, 0i, 0.0f);
    if (classic_basis() == 1u) {
        let own = export_carry(s.own, u, l + 1u);
        let other = export_carry(s.other, u, l + 2u);
        axis.own_cell = own.cell;
        axis.own_frac = (own.rem + u) * export_inv_sides[l + 1u];
        axis.other_cell = other.cell;
        axis.other_frac = (other.rem + u) * export_inv_sides[l + 2u];
    }
    return axis;
}

/// Octave `o`'s term added to `acc` (and `previous`, the ridged chain) at the point `at`, the
/// coordinates' splits `sx` and `sy` moved from octave `o − 1`'s lattices to octave `o`'s.
fn classic_export_octave(o: u32, at: ExportPoint, sx: ptr<function, ClassicExportSplits>, sy: ptr<function, ClassicExportSplits>, acc: ptr<function, f32>, previous: ptr<function, f32>) {
    if (o > 0u) {
        if (classic_export_halving == 1u) {
            *sx = classic_export_halve_splits(*sx, o);
            *sy = classic_export_halve_splits(*sy, o);
        } else {
            *sx = classic_export_splits(at.n.x, o);
            *sy = classic_export_splits(at.n.y, o);
        }
    }
    let column = classic_export_axis(*sx, at.u.x, o);
    let row = classic_export_axis(*sy, at.u.y, o);
    classic_octave(o, column, row, vec2<f32>(0.0f), acc, previous);
}

/// The noise at the position `cell + offset` (pixels), octaves summed in the CPU's order. The
/// exporter writes the octaves out, `CLASSIC_EXPORT_OCTAVES` = one `classic_export_octave`
/// call per octave with its index as a literal: every table of the module is then read at a
/// constant index, which a driver folds (an octave loop's counter would keep the tables in
/// per-invocation memory, initialised per pixel).
fn classic_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> f32 {
    let at = export_normalise(cell, offset);
    var acc = 0.0f;
    var previous = 0.0f;
    var sx = classic_export_splits(at.n.x, 0u);
    var sy = classic_export_splits(at.n.y, 0u);
    CLASSIC_EXPORT_OCTAVES
    return params.mean + params.amplitude * acc;
}
