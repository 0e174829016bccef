//! Local Random-Phase noise (Gilet et al. 2014, Eqs. 1–2): a sum over strata of windowed sums
//! of cosines on a regular lattice, with random phases and frequencies drawn per lattice point.
//!
//! # Randomness contract (layers = strata)
//!
//! Stratum `s` seeds lattice point `(i, j)`'s PRNG with `cell_hash(i, j, s, seed)` and draws,
//! per sub-stratum in order, the table index (`next_u32 % len`) then the phase (`unit_f32`).

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_level, check_range};

pub(crate) mod builder;
pub use builder::LrpNoiseBuilder;

/// Most strata in one model.
pub const MAX_STRATA: usize = 64;
/// Most cosines per cell in one stratum (`J_S`).
pub const MAX_COSINES: usize = 1024;
/// Most frequencies in one sub-stratum table.
pub const MAX_TABLE: usize = 1 << 20;

/// An LRP noise: `n(x) = mean + Σ_S n_S(x)` (Eq. 2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LrpNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// Constant added to the noise (the exemplar's mean for noise by example).
    pub mean: f32,
    /// The strata, with disjoint spectra.
    pub strata: Vec<Stratum>,
}

/// One stratum `S`: its own lattice period, amplitude and cosine tables (Eq. 1 with `J = J_S`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stratum {
    /// `Δ_S`, the window width and lattice period, in pixels (§4.3:
    /// `Δ_S = T·√J_S / √(2|S|)`).
    pub window_width: f32,
    /// `A_S`, the amplitude of every cosine of the stratum (Eq. 3).
    pub amplitude: f32,
    /// One table per cosine `j < J_S`: the frequencies of sub-stratum `j`, in cycles per pixel
    /// `[f_x, f_y]`, on one half of the spectrum. Each lattice point draws one entry of each
    /// table uniformly.
    pub sub_strata: Vec<Vec<[f32; 2]>>,
}

impl Stratum {
    /// `J_S`, the number of cosines per lattice point.
    #[must_use]
    pub fn cosines(&self) -> usize {
        self.sub_strata.len()
    }
}

impl LrpNoise {
    /// Checks every number and list length.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_level(|| "lrp.mean".into(), self.mean)?;
        check_len(
            || "lrp.strata".into(),
            self.strata.len(),
            1,
            MAX_STRATA,
            "1 to 64 strata",
        )?;
        validate_strata("lrp.strata", &self.strata)
    }

    /// Total cosines per lattice point over all strata, `Σ_S J_S`.
    #[must_use]
    pub fn budget(&self) -> usize {
        self.strata.iter().map(Stratum::cosines).sum()
    }
}

/// Checks the numbers and list lengths of each stratum; field names start with `prefix`.
pub(crate) fn validate_strata(prefix: &str, strata: &[Stratum]) -> Result<(), ModelError> {
    for (s, stratum) in strata.iter().enumerate() {
        check_range(
            || format!("{prefix}[{s}].window_width"),
            f64::from(stratum.window_width),
            0.5,
            1e6,
            "[0.5, 1e6] pixels",
        )?;
        check_range(
            || format!("{prefix}[{s}].amplitude"),
            f64::from(stratum.amplitude),
            0.0,
            1e9,
            "[0, 1e9]",
        )?;
        check_len(
            || format!("{prefix}[{s}].sub_strata"),
            stratum.sub_strata.len(),
            1,
            MAX_COSINES,
            "1 to 1024 sub-strata (cosines per cell)",
        )?;
        for (j, table) in stratum.sub_strata.iter().enumerate() {
            check_len(
                || format!("{prefix}[{s}].sub_strata[{j}]"),
                table.len(),
                1,
                MAX_TABLE,
                "1 to 1048576 frequencies",
            )?;
            for (k, f) in table.iter().enumerate() {
                for (axis, &v) in f.iter().enumerate() {
                    check_range(
                        || format!("{prefix}[{s}].sub_strata[{j}][{k}][{axis}]"),
                        f64::from(v),
                        -0.5,
                        0.5,
                        "[-0.5, 0.5] cycles per pixel",
                    )?;
                }
            }
        }
    }
    Ok(())
}

impl crate::ModelKind for LrpNoise {
    const PERIODIC: bool = true;

    const NAME: &'static str = "lrp";

    /// Any period: each stratum's lattice is fitted to it ([`crate::Period::fit_lattice`]).
    fn check_period(&self, _period: crate::Period) -> Result<(), ModelError> {
        Ok(())
    }

    fn validate(&self) -> Result<(), ModelError> {
        LrpNoise::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}
