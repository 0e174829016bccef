// Whole-grid simulations on a torus, one step per dispatch, ping-pong storage buffers
// (crates/spectex-gpu/src/simulate.rs binds them with explicit layouts: each entry point uses
// only its own bindings). The CPU twins are in crates/spectex-simulate.
//
// Gray–Scott (Pearson 1993), forward Euler, 5-point Laplacian, f32, the CPU's expression in
// the CPU's order (spectex_simulate::gray_scott_cell):
//   nu = (left + right) + (up + down);  lap_u = nu − 4u;  uvv = (u·v)·v
//   u' = u + dt·((du·lap_u − uvv) + F·(1 − u))
//   v' = v + dt·((dv·lap_v + uvv) − (F + k)·v)
// A driver may fuse a·b + c; the cross-check's tolerance allows for that.
//
// Cellular automata: integer states, the same as the CPU's bit for bit.

struct SimParams {
    width: u32,
    height: u32,
    // Life: birth mask | survive mask << 16. Elementary: the rule number. Cyclic: states.
    rule: u32,
    // Cyclic: threshold | (1 << 8 for the Moore neighbourhood). Elementary: the first drawn
    // generation.
    extra: u32,
    feed: f32,
    kill: f32,
    du: f32,
    dv: f32,
    dt: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> params: SimParams;
@group(0) @binding(1) var<storage, read> u_in: array<f32>;
@group(0) @binding(2) var<storage, read> v_in: array<f32>;
@group(0) @binding(3) var<storage, read_write> u_out: array<f32>;
@group(0) @binding(4) var<storage, read_write> v_out: array<f32>;
@group(0) @binding(5) var<storage, read> cells_in: array<u32>;
@group(0) @binding(6) var<storage, read_write> cells_out: array<u32>;
// Elementary only: the drawn image and the generation counter.
@group(0) @binding(7) var<storage, read_write> image: array<u32>;
@group(0) @binding(8) var<storage, read_write> generation: array<u32>;

// The column (row) before and after `i` on a torus of side `n`: selects, not `%` (integer
// division is slow on software rasterisers such as lavapipe).
fn before(i: u32, n: u32) -> u32 {
    return select(i - 1u, n - 1u, i == 0u);
}

fn after(i: u32, n: u32) -> u32 {
    return select(i + 1u, 0u, i + 1u == n);
}

@compute @workgroup_size(16, 16, 1)
fn gray_scott_step(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = params.width;
    let h = params.height;
    if (id.x >= w || id.y >= h) {
        return;
    }
    let row = id.y * w;
    let i = row + id.x;
    let l = row + before(id.x, w);
    let r = row + after(id.x, w);
    let t = before(id.y, h) * w + id.x;
    let b = after(id.y, h) * w + id.x;
    let u = u_in[i];
    let v = v_in[i];
    let nu = (u_in[l] + u_in[r]) + (u_in[t] + u_in[b]);
    let nv = (v_in[l] + v_in[r]) + (v_in[t] + v_in[b]);
    let lap_u = nu - 4.0 * u;
    let lap_v = nv - 4.0 * v;
    let uvv = u * v * v;
    u_out[i] = u + params.dt * ((params.du * lap_u - uvv) + params.feed * (1.0 - u));
    v_out[i] = v + params.dt * ((params.dv * lap_v + uvv) - (params.feed + params.kill) * v);
}

// The 3 × 3 block around (x, y) on the torus as indices: rows[dy + 1] + cols[dx + 1].
struct Block {
    cols: vec3<u32>,
    rows: vec3<u32>,
}

fn block(x: u32, y: u32) -> Block {
    let w = params.width;
    let h = params.height;
    return Block(
        vec3<u32>(before(x, w), x, after(x, w)),
        vec3<u32>(before(y, h) * w, y * w, after(y, h) * w),
    );
}

@compute @workgroup_size(16, 16, 1)
fn life_step(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.width || id.y >= params.height) {
        return;
    }
    let k = block(id.x, id.y);
    var n = 0u;
    for (var j = 0u; j < 3u; j++) {
        for (var i = 0u; i < 3u; i++) {
            if (i != 1u || j != 1u) {
                n += cells_in[k.rows[j] + k.cols[i]];
            }
        }
    }
    let c = k.rows[1] + k.cols[1];
    var mask = params.rule & 0xffffu;
    if (cells_in[c] == 1u) {
        mask = params.rule >> 16u;
    }
    cells_out[c] = (mask >> n) & 1u;
}

@compute @workgroup_size(16, 16, 1)
fn cyclic_step(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.width || id.y >= params.height) {
        return;
    }
    let k = block(id.x, id.y);
    let c = k.rows[1] + k.cols[1];
    let state = cells_in[c];
    let succ = (state + 1u) % params.rule;
    let moore = (params.extra >> 8u) == 1u;
    var n = 0u;
    for (var j = 0u; j < 3u; j++) {
        for (var i = 0u; i < 3u; i++) {
            let counted = (i != 1u || j != 1u) && (i == 1u || j == 1u || moore);
            if (counted && cells_in[k.rows[j] + k.cols[i]] == succ) {
                n += 1u;
            }
        }
    }
    var next = state;
    if (n >= (params.extra & 0xffu)) {
        next = succ;
    }
    cells_out[c] = next;
}

// One generation of an elementary automaton: row cells_in → cells_out, drawn into `image` at
// row (generation + 1 − first drawn) when that is inside the image. Every invocation reads the
// counter; `elementary_tick` advances it in the next dispatch.
@compute @workgroup_size(64, 1, 1)
fn elementary_step(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= params.width) {
        return;
    }
    let w = params.width;
    let x = id.x;
    let l = cells_in[before(x, w)];
    let c = cells_in[x];
    let r = cells_in[after(x, w)];
    let next = (params.rule >> (4u * l + 2u * c + r)) & 1u;
    cells_out[x] = next;
    let g = generation[0] + 1u;
    if (g >= params.extra && g - params.extra < params.height) {
        image[(g - params.extra) * w + x] = next;
    }
}

@compute @workgroup_size(1, 1, 1)
fn elementary_tick() {
    generation[0] = generation[0] + 1u;
}
