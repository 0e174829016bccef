//! The randomness contract: an integer hash and a `u32` PRNG, written once for the CPU.
//!
//! The definitions follow the PCG family as used for GPU hashing by Jarzynski & Olano,
//! "Hash Functions for GPU Rendering" (JCGT 2020): a 32-bit LCG step followed by the
//! RXS-M-XS output permutation. Only wrapping `u32` multiplication, addition, shifts and
//! xor are used, so WGSL (which has exactly these operations on `u32`) reproduces every bit.
//! Floats are built from integer bits by an exact conversion (no rounding can differ).
//!
//! # Layers in use
//!
//! Random Phase Noise draws its phase at DFT index `(k, l)` (row, column) from
//! `cell_hash(l, k, 0, seed)` — `θ = 2π · b/2³²`, evaluated as `e^{iθ}` by a three-table product
//! accurate to a few ulps — and ADSN draws pixel `(x, y)`'s Gaussian by Box–Muller from the PRNG
//! seeded with `cell_hash(x, y, 1, seed)`. k-means seeding in `spectex-sampling` uses
//! `kmeans::KMEANS_LAYER`.
//!
//! Each model kind specifies its draws (layers, seeds, order) in its module's docs
//! (`spectex_model::<kind>`, "Randomness contract"; phasor noise in [`crate::phasor_kernels`]):
//! layer `s` per LRP stratum or `o` per classic octave; a constant spelling the kind's name
//! (`VORONOI_LAYER = 0x564F524F`, "VORO") for wavelet, texton, Voronoi, Islamic and subdivision
//! layers; a 3D cell `(i, j, k)` hashes as `cell_hash(i, j, layer, cell_hash(k, 0, layer, seed))`.
//! A new kind does the same in its own module. Textures by example draw their placement from
//! `PLACEMENT_LAYER` ("PLAC"); their channels and turbulence are LRP noises with seeds of
//! their own. Warps, combinations and matrix transformations draw nothing of their own.

/// Multiplier of the 32-bit LCG step (PCG's default 32-bit multiplier).
pub const LCG_MULTIPLIER: u32 = 747_796_405;
/// Increment of the 32-bit LCG step.
pub const LCG_INCREMENT: u32 = 2_891_336_453;
/// Multiplier of PCG's RXS-M-XS output permutation.
pub const RXS_M_XS_MULTIPLIER: u32 = 277_803_737;

/// PCG's RXS-M-XS output permutation: a bijection of `u32` with good avalanche.
#[inline]
#[must_use]
pub const fn permute(state: u32) -> u32 {
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(RXS_M_XS_MULTIPLIER);
    (word >> 22) ^ word
}

/// One LCG step: the state transition of [`Prng`].
#[inline]
#[must_use]
pub const fn lcg_step(state: u32) -> u32 {
    state
        .wrapping_mul(LCG_MULTIPLIER)
        .wrapping_add(LCG_INCREMENT)
}

/// `pcg_hash` of Jarzynski & Olano: `permute(lcg_step(v))`. A bijection of `u32`.
#[inline]
#[must_use]
pub const fn hash(v: u32) -> u32 {
    permute(lcg_step(v))
}

/// Hash of an integer lattice cell, a layer (stratum, channel, octave…) and a seed.
///
/// Nested one-dimensional hashing: `hash(x + hash(y + hash(layer + hash(seed))))` with
/// wrapping addition. Signed cell coordinates are reinterpreted as `u32` (two's complement),
/// so cells on both sides of the origin are distinct and the lattice is unbounded in effect.
///
/// The nesting lets a loop hoist what does not change: [`layer_key`] once per layer and seed,
/// [`row_key`] once per row, then one `hash` per cell:
/// `cell_hash(x, y, layer, seed) == hash(x + row_key(y, layer_key(layer, seed)))`.
#[inline]
#[must_use]
pub const fn cell_hash(x: i32, y: i32, layer: u32, seed: u32) -> u32 {
    cell_hash_in_row(x, row_key(y, layer_key(layer, seed)))
}

/// The part of [`cell_hash`] that depends only on the layer and the seed.
#[inline]
#[must_use]
pub const fn layer_key(layer: u32, seed: u32) -> u32 {
    hash(layer.wrapping_add(hash(seed)))
}

/// The part of [`cell_hash`] that depends only on the row, given a [`layer_key`].
#[inline]
#[must_use]
pub const fn row_key(y: i32, layer_key: u32) -> u32 {
    hash((y as u32).wrapping_add(layer_key))
}

/// [`cell_hash`] of cell `x` in the row whose [`row_key`] is given.
#[inline]
#[must_use]
pub const fn cell_hash_in_row(x: i32, row_key: u32) -> u32 {
    hash((x as u32).wrapping_add(row_key))
}

/// Uniform `f32` in `[0, 1)` from the top 24 bits of `bits`: exact, identical on every device.
#[inline]
#[must_use]
pub fn unit_f32(bits: u32) -> f32 {
    // An integer below 2^24 converts to f32 exactly, and the power-of-two scale is exact.
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Uniform `f64` in `[0, 1)` from all 32 bits of `bits` (CPU-only analyses such as RPN).
#[inline]
#[must_use]
pub fn unit_f64(bits: u32) -> f64 {
    f64::from(bits) * (1.0 / 4_294_967_296.0)
}

/// Uniform `f64` in the open interval `(0, 1)`: never 0, so it is safe under `ln`.
#[inline]
#[must_use]
pub fn open_unit_f64(bits: u32) -> f64 {
    (f64::from(bits) + 0.5) * (1.0 / 4_294_967_296.0)
}

/// The Poisson CDF `P(N ≤ k)` of mean `mean` for `k < N`, summed in f64 and rounded to f32
/// once per entry: the table every evaluator compares one uniform `u` against to draw a capped
/// Poisson count (the number of `k` with `u ≥ P(N ≤ k)`), for Worley feature points and texton
/// placement alike.
#[must_use]
pub fn poisson_cdf<const N: usize>(mean: f64) -> [f32; N] {
    let mut cdf = [0.0f32; N];
    let mut term = (-mean).exp();
    let mut sum = 0.0;
    for (k, c) in cdf.iter_mut().enumerate() {
        sum += term;
        *c = sum as f32;
        term *= mean / (k + 1) as f64;
    }
    cdf
}

/// The contract's pseudo-random stream: an LCG on `u32` whose outputs are permuted.
///
/// `next_u32` returns `hash(state)` and then advances `state` by one LCG step, so the first
/// output of `Prng::new(s)` is `hash(s)`. Seed it with [`cell_hash`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Prng {
    state: u32,
}

impl Prng {
    /// A stream starting at `state`.
    #[must_use]
    pub const fn new(state: u32) -> Self {
        Self { state }
    }

    /// The next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.state = lcg_step(self.state);
        permute(self.state)
    }

    /// The next uniform `f32` in `[0, 1)` (see [`unit_f32`]).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        unit_f32(self.next_u32())
    }

    /// The next uniform `f64` in `[0, 1)` (see [`unit_f64`]).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        unit_f64(self.next_u32())
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    /// Reference values from an independent Python transcription of Jarzynski & Olano's
    /// `pcg_hash` (arbitrary-precision integers masked to 32 bits), not from this code.
    pub fn hash_matches_independent_reference() {
        assert_eq!(hash(0), 0x07bb_2fe2);
        assert_eq!(hash(1), 0xa8be_ea3c);
        assert_eq!(hash(2), 0x7a7e_cc88);
        assert_eq!(hash(u32::MAX), 0xe62a_4902);
        assert_eq!(cell_hash(0, 0, 0, 0), 0x8d32_4821);
        assert_eq!(cell_hash(1, 2, 3, 4), 0xade9_6895);
        assert_eq!(cell_hash(-5, 7, 1, 42), 0xae24_4374);
    }

    pub fn prng_stream_matches_independent_reference() {
        let mut prng = Prng::new(cell_hash(1, 2, 3, 4));
        let got: Vec<u32> = (0..4).map(|_| prng.next_u32()).collect();
        assert_eq!(got, [0x7a60_1af0, 0xec03_c058, 0xdf6d_3a0e, 0xba6b_5704]);
    }

    pub fn permute_is_a_bijection_on_a_window() {
        // A bijection restricted to 2^20 consecutive inputs has no collisions there.
        let mut seen: Vec<u32> = (0..1u32 << 20).map(permute).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 1 << 20);
    }

    pub fn uniform_floats_are_in_range_and_exact() {
        assert_eq!(unit_f32(0), 0.0);
        assert_eq!(unit_f32(u32::MAX), 1.0 - 1.0 / 16_777_216.0);
        assert!(unit_f32(u32::MAX) < 1.0);
        assert!(unit_f64(u32::MAX) < 1.0);
        assert!(open_unit_f64(0) > 0.0 && open_unit_f64(u32::MAX) < 1.0);
    }

    /// Chi-square test of uniformity over 256 bins, for neighbouring cells (the hardest case
    /// for a weak hash). With 255 degrees of freedom the 99.99th percentile is about 340.
    pub fn neighbouring_cells_are_uniform() {
        let mut bins = [0u32; 256];
        let n = 256 * 1024;
        for y in -256..256 {
            for x in -256..256 {
                bins[(cell_hash(x, y, 0, 7) >> 24) as usize] += 1;
            }
        }
        let expected = f64::from(n) / 256.0;
        let chi2: f64 = bins
            .iter()
            .map(|&b| (f64::from(b) - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 340.0, "chi-square {chi2} over 256 bins");
    }

    /// Strict avalanche: flipping one input bit flips each output bit with probability ½.
    pub fn hash_avalanche() {
        let samples = 4096u32;
        for bit in 0..32 {
            let mut flips = [0u32; 32];
            for i in 0..samples {
                let v = hash(i.wrapping_mul(2_654_435_761));
                let d = hash(v) ^ hash(v ^ (1 << bit));
                for (o, f) in flips.iter_mut().enumerate() {
                    *f += (d >> o) & 1;
                }
            }
            for (o, &f) in flips.iter().enumerate() {
                let p = f64::from(f) / f64::from(samples);
                assert!(
                    (0.4..0.6).contains(&p),
                    "input bit {bit} -> output bit {o}: {p}"
                );
            }
        }
    }

    pub fn hoisted_keys_compose_to_the_cell_hash() {
        let mut prng = Prng::new(99);
        for _ in 0..10_000 {
            let (x, y) = (prng.next_u32() as i32, prng.next_u32() as i32);
            let (layer, seed) = (prng.next_u32() % 8, prng.next_u32());
            let key = row_key(y, layer_key(layer, seed));
            assert_eq!(cell_hash_in_row(x, key), cell_hash(x, y, layer, seed));
            // and the nested definition, written out
            let nested = hash((x as u32).wrapping_add(hash(
                (y as u32).wrapping_add(hash(layer.wrapping_add(hash(seed)))),
            )));
            assert_eq!(nested, cell_hash(x, y, layer, seed));
        }
    }

    pub fn seeds_layers_and_axes_decorrelate() {
        assert_ne!(cell_hash(1, 0, 0, 0), cell_hash(0, 1, 0, 0));
        assert_ne!(cell_hash(0, 0, 1, 0), cell_hash(0, 0, 0, 1));
        assert_ne!(cell_hash(-1, 0, 0, 0), cell_hash(1, 0, 0, 0));
    }
}
