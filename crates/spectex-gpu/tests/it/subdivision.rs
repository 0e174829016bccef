//! Stochastic subdivision on the device: at the coarse lattice points of a model without
//! subdivision levels (mean 0) a pixel is one f32 product of the level scale and the hashed byte
//! sum, computed here from `spectex_model::random::cell_hash` directly, so the shader's hash
//! twin must match it bit for bit, near the origin and at 10⁷; and whole renders equal tiled
//! ones for both stencils.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;
use common::gpu_or_skip;
use spectex_gpu::{GpuEvaluator, GpuWindow};
use spectex_model::Model;
use spectex_model::random::cell_hash;
use spectex_model::subdivision::{Stencil, StochasticSubdivision};

fn model(stencil: Stencil, levels: u32) -> StochasticSubdivision {
    StochasticSubdivision {
        seed: 99,
        cell_size: 4.0,
        levels,
        hurst: 0.5,
        amplitude: 0.3,
        mean: 0.0,
        stencil,
    }
}

#[test]
fn coarse_lattice_values_are_the_hashes_bit_for_bit() {
    let Some(context) = gpu_or_skip("stochastic subdivision") else {
        return;
    };
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        let m = model(stencil, 0);
        m.validate().unwrap();
        let scale = (f64::from(m.amplitude) / 21_845f64.sqrt()) as f32;
        for cell in [[-3i32, 5], [2_500_000, -2_500_000]] {
            // One pixel per coarse point (cell side 4).
            let offset = [f64::from(cell[0]) * 4.0, f64::from(cell[1]) * 4.0];
            let window = GpuWindow::new(16, 8).at(offset, 4.0);
            let gpu = GpuEvaluator::new(&context, &Model::Subdivision(m.clone())).unwrap();
            let got = gpu.render(&window).unwrap();
            for j in 0..8i32 {
                for i in 0..16i32 {
                    let (cx, cy) = (cell[0] + i, cell[1] + j);
                    let bits = cell_hash(0, 0, 0x5355_4244, cell_hash(cx, cy, 0x5355_4244, 99));
                    let sum: i32 = bits.to_le_bytes().iter().map(|&b| i32::from(b)).sum();
                    let want = scale * (sum - 510) as f32;
                    let v = got[(j * 16 + i) as usize];
                    assert_eq!(
                        v.to_bits(),
                        want.to_bits(),
                        "{stencil:?} coarse point ({cx}, {cy}): {v} != {want}"
                    );
                }
            }
        }
    }
}

#[test]
fn tiles_are_invisible() {
    let Some(context) = gpu_or_skip("stochastic subdivision") else {
        return;
    };
    for stencil in [Stencil::Midpoint, Stencil::Cubic] {
        let m = model(stencil, 5);
        let mut gpu = GpuEvaluator::new(&context, &Model::Subdivision(m)).unwrap();
        let window = GpuWindow::new(40, 24).at([-7.3, 1.0e7 + 0.5], 0.7);
        let whole = gpu.render(&window).unwrap();
        gpu.set_max_tile(16, 7);
        let tiled = gpu.render(&window).unwrap();
        assert_eq!(whole, tiled, "{stencil:?}: tiles differ");
    }
}
