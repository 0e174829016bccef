//! The built-in exemplar (`src/exemplar.rs`, `default_exemplar.png`) against its
//! generator, which is the definition: a spot noise of a few thousand small anisotropic Gaussian
//! spots in an earthy palette over fine grain, with a gentle light gradient.
//! `SPECTEX_BLESS=1 cargo test -p spectex-cli exemplar` rewrites the file deliberately.

use ndarray::Array3;
use spectex_cli::exemplar::DEFAULT_EXEMPLAR_PNG;
use spectex_cli::io;
use spectex_model::random::{Prng, cell_hash};

#[test]
fn shipped_file_matches_the_generator() {
    let want = generate();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/default_exemplar.png");
    if std::env::var_os("SPECTEX_BLESS").is_some() {
        let format = io::Format::Png(io::BitDepth::Eight);
        io::save(std::path::Path::new(path), &want, format).unwrap();
    }
    let got = io::decode(&std::fs::read(path).unwrap(), "exemplar")
        .unwrap()
        .pixels;
    assert_eq!(got.dim(), (3, SIDE, SIDE));
    for ((idx, g), w) in got.indexed_iter().zip(want.iter()) {
        let q = (w * 255.0).round() / 255.0;
        assert!(
            (g - q).abs() < 1e-6,
            "pixel {idx:?}: file {g} generator {q}"
        );
    }
    // The embedded copy is the same file.
    let embedded = io::decode(DEFAULT_EXEMPLAR_PNG, "embedded").unwrap().pixels;
    assert_eq!(embedded, got);
}

/// The exemplar's side.
const SIDE: usize = 256;

/// The exemplar in linear `[0, 1]` RGB, `(channel, row, column)`.
fn generate() -> Array3<f64> {
    let n = SIDE;
    let mut img = Array3::<f64>::zeros((3, n, n));
    let base = [0.42, 0.37, 0.30];
    let palette = [
        [0.62, 0.52, 0.36],
        [0.25, 0.22, 0.18],
        [0.50, 0.47, 0.42],
        [0.36, 0.40, 0.27],
    ];
    for y in 0..n {
        for x in 0..n {
            let mut grain = Prng::new(cell_hash(x as i32, y as i32, 1, 2014));
            let g = 0.05 * (grain.next_f64() - 0.5);
            // A light gradient: what a real photograph of a surface shows.
            let light = 0.06 * (x as f64 / n as f64 - 0.5) - 0.04 * (y as f64 / n as f64 - 0.5);
            for c in 0..3 {
                img[[c, y, x]] = base[c] + g + light;
            }
        }
    }
    let mut prng = Prng::new(cell_hash(0, 0, 2, 2014));
    for _ in 0..2600 {
        let (cx, cy) = (prng.next_f64() * n as f64, prng.next_f64() * n as f64);
        let sigma_u = 1.0 + 3.5 * prng.next_f64();
        let sigma_v = sigma_u * (0.35 + 0.65 * prng.next_f64());
        let angle = std::f64::consts::PI * (0.15 + 0.3 * prng.next_f64()); // a preferred direction
        let colour = palette[(prng.next_u32() % 4) as usize];
        let weight = 0.35 + 0.4 * prng.next_f64();
        let (ca, sa) = (angle.cos(), angle.sin());
        let r = (3.0 * sigma_u).ceil() as i64;
        for dy in -r..=r {
            for dx in -r..=r {
                let (x, y) = (cx as i64 + dx, cy as i64 + dy);
                if x < 0 || y < 0 || x >= n as i64 || y >= n as i64 {
                    continue;
                }
                let (px, py) = (x as f64 + 0.5 - cx, y as f64 + 0.5 - cy);
                let (u, v) = (ca * px + sa * py, -sa * px + ca * py);
                let a = weight
                    * (-0.5 * (u * u / (sigma_u * sigma_u) + v * v / (sigma_v * sigma_v))).exp();
                for c in 0..3 {
                    let p = &mut img[[c, y as usize, x as usize]];
                    *p += a * (colour[c] - *p);
                }
            }
        }
    }
    img.mapv_inplace(|v| v.clamp(0.0, 1.0));
    img
}
