//! Matrix transformation on the device against the survey's procedure run naively (every source
//! pixel moved forward `k` times by `M`), near the origin, at 10⁷ and tiled: the texel index is
//! integer work on both sides, so with amplitude 1 and mean 0 the values are equal exactly.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;
use common::gpu_or_skip;
use spectex_gpu::{GpuEvaluator, GpuWindow};
use spectex_model::Model;
use spectex_model::matrix::{MatrixSource, MatrixTransform};

/// The forward-moved image: `out[M^k·s mod N] = S(s)`.
fn forward_image(m: &MatrixTransform) -> Vec<f32> {
    let n = u64::from(m.size);
    let a = m.matrix.map(|r| r.map(u64::from));
    let mut out = vec![f32::NAN; (n * n) as usize];
    for y in 0..n {
        for x in 0..n {
            let (mut px, mut py) = (x, y);
            for _ in 0..m.iterations {
                (px, py) = (
                    (a[0][0] * px + a[0][1] * py) % n,
                    (a[1][0] * px + a[1][1] * py) % n,
                );
            }
            out[(py * n + px) as usize] = m.source_value([x as u32, y as u32]);
        }
    }
    out
}

#[test]
fn renders_are_the_forward_moved_image_near_far_and_tiled() {
    let Some(context) = gpu_or_skip("matrix transformation") else {
        return;
    };
    let cases = [
        ([[1, 1], [1, 2]], 5, 40, MatrixSource::Rings { rings: 6 }),
        (
            [[3, 0], [0, 7]],
            2,
            32,
            MatrixSource::Image {
                texels: (0..1024).map(|i| i as f32 / 1024.0).collect(),
            },
        ),
    ];
    for (matrix, k, n, source) in cases {
        let m = MatrixTransform {
            matrix,
            iterations: k,
            size: n,
            source,
            amplitude: 1.0,
            mean: 0.0,
        };
        m.validate().unwrap();
        let want = forward_image(&m);
        let (w, h) = (48usize, 40usize);
        for (offset, cells) in [
            ([3.0, -2.0], [3i64, -2i64]),
            ([1.0e7 + 0.5, -3.0e6], [10_000_000, -3_000_000]),
        ] {
            let mut gpu = GpuEvaluator::new(&context, &Model::Matrix(m.clone())).unwrap();
            let window = GpuWindow::new(w, h).at(offset, 1.0);
            let got = gpu.render(&window).unwrap();
            for j in 0..h {
                for i in 0..w {
                    let n = i64::from(n);
                    let qx = (cells[0] + i as i64).rem_euclid(n);
                    let qy = (cells[1] + j as i64).rem_euclid(n);
                    let expect = want[(qy * n + qx) as usize];
                    assert_eq!(
                        got[j * w + i].to_bits(),
                        expect.to_bits(),
                        "{matrix:?} k = {k} N = {n} at {offset:?}, pixel ({i}, {j})"
                    );
                }
            }
            let whole = got;
            gpu.set_max_tile(16, 7);
            let tiled = gpu.render(&window).unwrap();
            assert_eq!(whole, tiled, "{matrix:?}: tiles differ");
        }
    }
}
