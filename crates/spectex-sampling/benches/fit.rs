//! Criterion bench of LRP noise by example: the whole fit of a 256² exemplar with J = 50 and
//! L = 4 by the spectrum fit (the default) and by the paper's (Welch spectrum, stratification,
//! erosion, k-means, amplitudes), as in the paper's "under 1 s" claim (§6), and the
//! stratification alone. The fitted models' evaluation speed is `spectex-cli`'s `fitted_eval`
//! bench (this crate may not depend on the evaluator).
//!
//! `cargo bench -p spectex-sampling --bench fit`. The exemplar is the top-left 256² crop of the
//! shared gravel photograph when `../shared/testdata/textures/` is present, else (with a printed
//! note) a synthetic 256² image of oriented waves and noise.

use criterion::{Criterion, criterion_group, criterion_main};
use ndarray::Array2;
use spectex_model::random::{Prng, cell_hash};
use spectex_sampling::{FitMethod, FitOptions, fit_image, stratify};
use spectex_spectrum::{Fft2, welch_psd};
use std::hint::black_box;

fn exemplar_256() -> Array2<f64> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures/skimage_gravel.png"
    );
    if let Ok(img) = image::open(path) {
        let g = img.to_luma32f();
        if g.width() >= 256 && g.height() >= 256 {
            return Array2::from_shape_fn((256, 256), |(y, x)| {
                f64::from(g.get_pixel(x as u32, y as u32).0[0])
            });
        }
    }
    eprintln!("bench: ../shared/testdata absent; fitting a synthetic 256² exemplar instead");
    let mut prng = Prng::new(cell_hash(0, 0, 0, 1));
    Array2::from_shape_fn((256, 256), |(y, x)| {
        let (x, y) = (x as f64, y as f64);
        0.5 + 0.2 * (0.31 * x + 0.17 * y).sin() + 0.2 * prng.next_f64()
    })
}

fn bench(c: &mut Criterion) {
    let image = exemplar_256();
    let options = FitOptions {
        budget: 50,
        strata: 4,
        seed: 1,
        ..FitOptions::default()
    };
    let paper = FitOptions {
        method: FitMethod::Paper,
        ..options
    };
    let mut group = c.benchmark_group("fit");
    group.sample_size(20);
    group.bench_function("fit_image_256_j50_l4", |b| {
        b.iter(|| fit_image(black_box(image.view()), &options));
    });
    group.bench_function("fit_image_256_j50_l4_paper", |b| {
        b.iter(|| fit_image(black_box(image.view()), &paper));
    });
    let psd = welch_psd(image.view(), &mut Fft2::new()).unwrap_or_default();
    group.bench_function("stratify_psd128_j50_l4", |b| {
        b.iter(|| stratify(black_box(psd.view()), &options));
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
