//! Stochastic subdivision on the CPU ([`spectex_model::subdivision`]), in f64.
//!
//! A pixel splits its position into the coarse cell and the f32 offset
//! ([`spectex_model::grid::locate_cell`], as the GPU's tables do), finds its finest cell
//! `⌊t·2^L⌋` (exact) and the block of `W × W` lattice points each level needs
//! ([`Stencil::window`]), and computes the blocks from level 0 to `L`: each child value is the
//! stencil's sum over its parent block, first along x then along y, plus its displacement if
//! it is new. **Cost per pixel:** at most `W²·(L + 1)` lattice values (`4(L + 1)` for the
//! midpoint rule, `36(L + 1)` for the cubic), each one hash (two `cell_hash`) and at most
//! `2·4` multiply-adds per pass. Along a row the coarse blocks repeat: [`eval_rows`] keeps
//! each level's last block with its key (coarse cell, block origin), which determines it and
//! every coarser block, and recomputes only the finer levels, so most pixels compute the finest
//! one or two levels (same values: a block is a pure function of its key).
//! `eval_rows_reference` computes every level for every pixel.
//!
//! [`eval_rows`]: RowKernel::eval_rows

use spectex_model::Window;
use spectex_model::grid::locate_cell;
use spectex_model::subdivision::{
    StochasticSubdivision, centred_byte_sum, lattice_bits, normalise,
};

use crate::{CpuError, CpuKind, RowKernel};

/// The largest block side (the cubic stencil's).
const MAX_W: usize = 6;

/// One level's block: `[c_x, c_y, o_x, o_y]` (coarse cell and block origin in level units)
/// and its values, `v[row][column]`.
#[derive(Clone, Copy)]
struct Block {
    key: Option<[i32; 4]>,
    v: [[f64; MAX_W]; MAX_W],
}

const EMPTY: Block = Block {
    key: None,
    v: [[0.0; MAX_W]; MAX_W],
};

/// A stochastic subdivision prepared for evaluation.
pub struct SubdivisionEvaluator {
    model: StochasticSubdivision,
    /// `σ_ℓ/√21845` per level.
    scales: Vec<f64>,
    side: f64,
}

impl SubdivisionEvaluator {
    /// Prepares a validated model.
    #[must_use]
    pub fn new(model: &StochasticSubdivision) -> Self {
        Self {
            model: model.clone(),
            scales: model.level_scales(),
            side: f64::from(model.cell_size),
        }
    }

    /// The coarse cell and offset of one coordinate (cell 0, offset 0 outside the usable
    /// range, which a validated window never reaches).
    fn locate(&self, coord: f64) -> (i32, f32) {
        locate_cell(coord, self.side).unwrap_or((0, 0.0))
    }

    /// The texture at the located position `(x, y)`, reusing and refreshing `blocks` (one per
    /// level; any contents are valid: a block is used only where its key matches).
    fn value(&self, x: (i32, f32), y: (i32, f32), blocks: &mut [Block]) -> f32 {
        let m = &self.model;
        let levels = m.levels;
        let (w, r) = m.stencil.window();
        let fine = |t: f32| {
            let f = f64::from(t) * f64::from(1u32 << levels);
            let k = f.floor();
            (k as i32, f - k)
        };
        let (kx, ux) = fine(x.1);
        let (ky, uy) = fine(y.1);
        // Block origins, finest first.
        let mut origins = [[0i32; 2]; spectex_model::subdivision::MAX_LEVELS as usize + 1];
        origins[levels as usize] = [kx - r, ky - r];
        for l in (1..=levels as usize).rev() {
            let [ox, oy] = origins[l];
            origins[l - 1] = [(ox >> 1) - r, (oy >> 1) - r];
        }
        let key = |l: usize| Some([x.0, y.0, origins[l][0], origins[l][1]]);
        // The finest level whose block is cached; every coarser one then is too.
        let start = (0..=levels as usize)
            .rev()
            .find(|&l| blocks[l].key == key(l))
            .map_or(0, |l| l + 1);
        for l in start..=levels as usize {
            let block = if l == 0 {
                self.coarse_block(x.0, y.0, origins[0], w)
            } else {
                self.child_block(
                    &blocks[l - 1].v,
                    (x.0, y.0),
                    [origins[l - 1], origins[l]],
                    l as u32,
                )
            };
            blocks[l] = Block {
                key: key(l),
                v: block,
            };
        }
        let v = &blocks[levels as usize].v;
        let (wx, nx) = m.stencil.final_weights(ux);
        let (wy, ny) = m.stencil.final_weights(uy);
        let mut sum = 0.0;
        for (w_row, v_row) in wy.iter().zip(v).take(ny) {
            let mut row = 0.0;
            for (w, value) in wx.iter().zip(v_row).take(nx) {
                row += w * value;
            }
            sum += w_row * row;
        }
        (f64::from(m.mean) + sum) as f32
    }

    /// Level 0's block from origin `o` in coarse cell `(cx, cy)`.
    fn coarse_block(&self, cx: i32, cy: i32, o: [i32; 2], w: usize) -> [[f64; MAX_W]; MAX_W] {
        let mut v = [[0.0; MAX_W]; MAX_W];
        for (j, row) in v.iter_mut().enumerate().take(w) {
            let (py, _) = normalise(cy, o[1] + j as i32, 0);
            for (i, value) in row.iter_mut().enumerate().take(w) {
                let (px, _) = normalise(cx, o[0] + i as i32, 0);
                let bits = lattice_bits(self.model.seed, 0, [px, py], [0, 0]);
                *value = self.scales[0] * f64::from(centred_byte_sum(bits));
            }
        }
        v
    }

    /// Level `l`'s block at origin `o` in coarse cell `(cx, cy)` from its parent block (origin
    /// `po`).
    fn child_block(
        &self,
        parent: &[[f64; MAX_W]; MAX_W],
        (cx, cy): (i32, i32),
        [po, o]: [[i32; 2]; 2],
        l: u32,
    ) -> [[f64; MAX_W]; MAX_W] {
        let stencil = self.model.stencil;
        let (w, _) = stencil.window();
        // Along x, for every parent row.
        let mut tmp = [[0.0; MAX_W]; MAX_W];
        for i in 0..w {
            let (first, wt, n) = stencil.taps(o[0] + i as i32);
            let a = (first - po[0]) as usize;
            for (t_row, p_row) in tmp.iter_mut().zip(parent).take(w) {
                let mut s = 0.0;
                for (w, p) in wt.iter().zip(&p_row[a..]).take(n) {
                    s += w * p;
                }
                t_row[i] = s;
            }
        }
        // Along y, then the displacement of the new points.
        let mut v = [[0.0; MAX_W]; MAX_W];
        for (j, row) in v.iter_mut().enumerate().take(w) {
            let qy = o[1] + j as i32;
            let (first, wt, n) = stencil.taps(qy);
            let b = (first - po[1]) as usize;
            for (i, value) in row.iter_mut().enumerate().take(w) {
                let qx = o[0] + i as i32;
                let mut s = 0.0;
                for (w, t_row) in wt.iter().zip(&tmp[b..]).take(n) {
                    s += w * t_row[i];
                }
                if (qx | qy) & 1 == 1 {
                    let (px, kx) = normalise(cx, qx, l);
                    let (py, ky) = normalise(cy, qy, l);
                    let bits = lattice_bits(self.model.seed, l, [px, py], [kx, ky]);
                    s += self.scales[l as usize] * f64::from(centred_byte_sum(bits));
                }
                *value = s;
            }
        }
        v
    }

    fn rows(&self, window: &Window, first: usize, out: &mut [f32], cached: bool) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let columns: Vec<(i32, f32)> = (0..width).map(|i| self.locate(window.x(i))).collect();
        let mut blocks = vec![EMPTY; self.model.levels as usize + 1];
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let y = self.locate(window.y(first + r));
            for (v, &x) in line.iter_mut().zip(&columns) {
                if !cached {
                    blocks.fill(EMPTY);
                }
                *v = self.value(x, y, &mut blocks);
            }
        }
    }
}

impl CpuKind for StochasticSubdivision {
    /// The bench case: `testdata/models/subdivision-midpoint.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("subdivision-midpoint.json")
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        self.validate()?;
        Ok(Box::new(SubdivisionEvaluator::new(self)))
    }
}

impl RowKernel for SubdivisionEvaluator {
    /// Lattice values computed per pixel at most, `W²·(L + 1)` (module docs).
    fn cost_per_pixel(&self) -> f64 {
        let (w, _) = self.model.stencil.window();
        (w * w) as f64 * f64::from(self.model.levels + 1)
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.rows(window, first, out, true);
    }

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.rows(window, first, out, false);
    }
}
