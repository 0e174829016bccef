//! Hand-made models the CPU and the GPU tests of one kind both use, written once: LRP noise with
//! three strata of different periods, table sizes and budgets, and Gabor noise of given
//! parameters (their values are chosen for the tests, not defaults; the builders' defaults are
//! `spectex_model`'s).

use spectex_model::random::{Prng, cell_hash};
use spectex_model::{GaborNoise, LrpNoise, Orientation, Stratum};

/// LRP noise of three strata of different periods (window widths 9.5, 23 and 3.25 pixels),
/// table sizes (5 × 7, 12 × 3 and 1 × 1) and amplitudes, its frequencies drawn from `seed`: small
/// `J`, so a software GPU renders it quickly.
#[must_use]
pub fn lrp_three_strata(seed: u32) -> LrpNoise {
    let mut prng = Prng::new(cell_hash(0, 0, 77, seed));
    let mut f = |spread: f32| {
        [
            (prng.next_f32() - 0.5) * spread,
            prng.next_f32() * 0.5 * spread,
        ]
    };
    LrpNoise {
        seed,
        mean: 0.25,
        strata: vec![
            Stratum {
                window_width: 9.5,
                amplitude: 0.2,
                sub_strata: (0..5).map(|_| (0..7).map(|_| f(0.6)).collect()).collect(),
            },
            Stratum {
                window_width: 23.0,
                amplitude: 0.05,
                sub_strata: (0..12).map(|_| (0..3).map(|_| f(0.2)).collect()).collect(),
            },
            Stratum {
                window_width: 3.25,
                amplitude: 0.5,
                sub_strata: vec![vec![f(1.0)]],
            },
        ],
    }
}

/// Gabor noise of mean 0.25 and kernel magnitude 1.5 with the given seed, impulses per kernel
/// `ipk`, bandwidth, frequency and orientation.
///
/// # Panics
/// If the parameters are invalid: a test's fixture must be a valid model.
#[must_use]
pub fn gabor(
    seed: u32,
    ipk: f32,
    bandwidth: f32,
    frequency: f32,
    orientation: Orientation,
) -> GaborNoise {
    let m = GaborNoise {
        seed,
        mean: 0.25,
        amplitude: 1.5,
        bandwidth,
        frequency,
        orientation,
        impulses_per_kernel: ipk,
    };
    if let Err(e) = m.validate() {
        panic!("test fixture: {e}");
    }
    m
}
