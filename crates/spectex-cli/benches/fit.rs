//! Criterion bench of LRP noise by example on the top-left 256² crop of the shared gravel
//! photograph, J = 50, L = 4: the whole fit by the spectrum fit (the default) and by the
//! paper's (the paper's "under 1 s" claim, §6), the stratification alone, and each fitted
//! model's evaluation (a 256² window, one thread) in the same run, so that the Mpix/s ratio is
//! the spectrum fit's evaluation cost. Here rather than in spectex-sampling, which may not
//! depend on the evaluator.
//!
//! `cargo bench -p spectex-cli --bench fit`. Without `../shared/testdata/textures/` it prints a
//! note and fits a synthetic 256² image of oriented waves and noise instead.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ndarray::Array2;
use spectex_cpu::{Evaluator, Window};
use spectex_model::Model;
use spectex_model::random::{Prng, cell_hash};
use spectex_sampling::{FitMethod, FitOptions, fit_image, stratify};
use spectex_spectrum::{Fft2, welch_psd};

fn exemplar_256() -> Array2<f64> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/testdata/textures/skimage_gravel.png"
    );
    if let Ok(img) = spectex_testkit::image_files::open(path) {
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

fn options(method: FitMethod) -> FitOptions {
    FitOptions {
        budget: 50,
        strata: 4,
        seed: 1,
        method,
        ..FitOptions::default()
    }
}

fn bench(c: &mut Criterion) {
    let image = exemplar_256();
    let mut group = c.benchmark_group("fit");
    group.sample_size(20);
    for method in [FitMethod::Spectrum, FitMethod::Paper] {
        let options = options(method);
        group.bench_function(format!("fit_image_256_j50_l4_{}", method.name()), |b| {
            b.iter(|| fit_image(black_box(image.view()), &options));
        });
    }
    let psd = welch_psd(image.view(), &mut Fft2::new()).unwrap_or_default();
    let paper = options(FitMethod::Paper);
    group.bench_function("stratify_psd128_j50_l4", |b| {
        b.iter(|| stratify(black_box(psd.view()), &paper));
    });
    group.finish();

    let side = 256;
    let window = Window::new(side, side).at([1000.0, 2000.0], 1.0);
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let mut group = c.benchmark_group("fitted_eval");
    group.throughput(Throughput::Elements((side * side) as u64));
    group.sample_size(10);
    for method in [FitMethod::Spectrum, FitMethod::Paper] {
        let model =
            Model::Lrp(fit_image(image.view(), &options(method)).expect("the exemplar fits"));
        let eval = Evaluator::new(&model).expect("a fitted model is valid");
        group.bench_function(format!("j50_{}_1_thread", method.name()), |b| {
            b.iter(|| single.install(|| eval.render(black_box(&window))));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
