//! Reproducible synthetic models shared by the benches and tests of every evaluator crate, so
//! that CPU, GPU and their comparison time and check the same model.

use crate::classic::{Basis, ClassicNoise};
use crate::random::{Prng, cell_hash};
use crate::{
    Field, GaborNoise, LrpNoise, Model, Orientation, PhasorNoise, PhasorOrientation, PhasorOutput,
    Profile, Stratum,
};

/// A 4-stratum LRP model with `budget` cosines per lattice point in all (at least one per
/// stratum), spread as evenly as possible; window widths Δ_S = 4.5, 9, 16, 28 pixels (the periods
/// a 512² exemplar's fit gives), amplitude 0.05 each, sub-strata tables of 40 frequencies drawn
/// from a fixed stream (`|f_x| ≤ ½`, `0 ≤ f_y < ½` cycles per pixel), seed 9, mean 0.5.
#[must_use]
pub fn lrp_four_strata(budget: usize) -> LrpNoise {
    let mut prng = Prng::new(cell_hash(1, 2, 3, 4));
    let strata = [4.5f32, 9.0, 16.0, 28.0]
        .iter()
        .enumerate()
        .map(|(s, &w)| {
            let j = budget / 4 + usize::from(s < budget % 4);
            Stratum {
                window_width: w,
                amplitude: 0.05,
                sub_strata: (0..j.max(1))
                    .map(|_| {
                        (0..40)
                            .map(|_| [prng.next_f32() - 0.5, prng.next_f32() * 0.5])
                            .collect()
                    })
                    .collect(),
            }
        })
        .collect();
    LrpNoise {
        seed: 9,
        mean: 0.5,
        strata,
    }
}

/// A phasor noise with a PWM profile (duty 25%): `F = 0.0625` cycles per pixel, `b = 0.02`, 32
/// impulses per kernel footprint, seed 1, in `dimensions` (2 or 3) with the given directions.
#[must_use]
pub fn phasor_pwm(dimensions: u8, orientation: PhasorOrientation) -> PhasorNoise {
    PhasorNoise {
        seed: 1,
        dimensions,
        bandwidth: Field::constant(0.02),
        frequency: Field::constant(0.0625),
        orientation,
        impulses_per_kernel: 32.0,
        profile: Profile::Square {
            duty: Field::constant(0.25),
        },
        output: PhasorOutput::Profiled,
        mean: 0.0,
        amplitude: 1.0,
    }
}

/// Isotropic Gabor noise: frequency 1/16, bandwidth 0.05, 16 impulses per kernel, amplitude 0.1
/// around 0.5, seed 3.
#[must_use]
pub fn gabor_isotropic() -> GaborNoise {
    GaborNoise {
        seed: 3,
        mean: 0.5,
        amplitude: 0.1,
        bandwidth: 0.05,
        frequency: 0.0625,
        orientation: Orientation::Isotropic { min: 0.0, max: 6.0 },
        impulses_per_kernel: 16.0,
    }
}

/// A model that is exactly `mean` everywhere: gradient noise of amplitude 0 (a warp's constant
/// displacement, for instance).
#[must_use]
pub fn constant(mean: f32) -> Model {
    Model::Classic(ClassicNoise {
        seed: 0,
        dimensions: 2,
        cell_size: 16.0,
        basis: Basis::Gradient,
        fractal: None,
        amplitude: 0.0,
        mean,
    })
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn budgets_are_spread_and_models_valid() {
        for budget in [1, 3, 10, 50] {
            let m = lrp_four_strata(budget);
            m.validate().unwrap();
            let total: usize = m.strata.iter().map(|s| s.sub_strata.len()).sum();
            assert_eq!(total, budget.max(4), "budget {budget}");
        }
        phasor_pwm(3, PhasorOrientation::Isotropic)
            .validate()
            .unwrap();
    }
}
