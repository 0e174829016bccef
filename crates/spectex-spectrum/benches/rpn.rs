//! Criterion benches of Random Phase Noise against one 2D FFT of the same size.
//!
//! `cargo bench -p spectex-spectrum --bench rpn` (or `cargo xtask bench`). The input is the
//! shared gravel photograph when `../shared/testdata/textures/` is present (replicated to three
//! channels), else a synthetic 512² RGB image; the timing does not depend on the content.

use criterion::{Criterion, criterion_group, criterion_main};
use ndarray::{Array2, Array3};
use num_complex::Complex64;
use spectex_model::random::{Prng, cell_hash};
use spectex_spectrum::{Fft2, Rpn, RpnOptions};
use std::hint::black_box;

fn sample_rgb_512() -> Array3<f64> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures/skimage_gravel.png"
    );
    if let Ok(img) = spectex_testkit::image_files::open(path) {
        let g = img.to_luma8();
        if g.dimensions() == (512, 512) {
            return Array3::from_shape_fn((3, 512, 512), |(c, y, x)| {
                let v = f64::from(g.get_pixel(x as u32, y as u32).0[0]) / 255.0;
                v * (0.8 + 0.1 * c as f64)
            });
        }
    }
    eprintln!("bench: ../shared/testdata absent; using a synthetic 512² RGB input");
    let mut prng = Prng::new(cell_hash(0, 0, 0, 1));
    Array3::from_shape_fn((3, 512, 512), |_| prng.next_f64())
}

fn bench(c: &mut Criterion) {
    let sample = sample_rgb_512();
    let mut group = c.benchmark_group("rpn");
    group.sample_size(20);

    for n in [512usize, 2048] {
        let mut fft = Fft2::<f64>::new();
        let mut a = Array2::from_elem((n, n), Complex64::new(0.5, 0.0));
        fft.forward(&mut a); // plan once outside the timing, as the RPN engine does
        group.bench_function(format!("fft2_c64_{n}x{n}"), |b| {
            b.iter(|| fft.forward(black_box(&mut a)));
        });
    }

    let mut rpn = Rpn::new();
    let same = RpnOptions::default();
    rpn.synthesize(sample.view(), &same).ok();
    group.bench_function("rpn_rgb_512_same_size", |b| {
        b.iter(|| rpn.synthesize(black_box(sample.view()), &same));
    });
    let large = RpnOptions {
        size: Some((2048, 2048)),
        ..RpnOptions::default()
    };
    rpn.synthesize(sample.view(), &large).ok();
    group.sample_size(10);
    group.bench_function("rpn_rgb_512_to_2048", |b| {
        b.iter(|| rpn.synthesize(black_box(sample.view()), &large));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
