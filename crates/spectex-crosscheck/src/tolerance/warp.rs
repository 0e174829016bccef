//! Domain warping (`spectex_model::warp`): its tolerance from its base's, x's and y's bounds and
//! regularities (each reached through its own kind's [`CheckKind`]).

use spectex_model::{MAX_WARP, Model, ModelKind, Warp};

use super::{
    CheckKind, F32_UNIT_ROUNDOFF, MEAN_FRACTION, Regularity, Tolerance, check_kind, regularity,
};

/// The CPU–GPU bound of a model's value wherever a warp may use it
/// ([`CheckKind::value_bound`] of its kind).
fn value_bound(model: &Model) -> Option<f64> {
    check_kind(model).value_bound()
}

/// Domain warping (`spectex_model::warp`): `v(p) = b(p + d(p))`. The two sides evaluate the
/// base at points `δ` apart, where per axis
/// - the displacement differs by `|s|·E_{x,y}` (the clamp is 1-Lipschitz; `E` the x or y
///   model's own bound);
/// - `s·v` and, for a displaced warp, the f32 sum of displacements round on the GPU:
///   2 roundings of `|d| ≤ D = min(MAX_WARP, |s|·max|v|)` per warp level;
/// - the GPU relocates the point in f32 (`common.wgsl`, `warp_relocate`): offset plus
///   displacement, the cell shift and the rebuilt offsets, 4 roundings of values up to
///   `D + 3·cell`; the CPU's f64 sum rounds below that.
///
/// so `|δ| ≤ √2·(|s|·max E + 6·u·(D + 3·cell))`. The base's bound, plus its
/// [`Regularity`] over `δ` (`slope·|δ| + jump`), is the warp's largest error. `None` when a
/// sub-model has no derived bound.
///
/// The mean: a truncated kernel's jump shows only at the pixels within `|δ|` of its support's
/// circle (radius `r`, the regularity's `cell`): the annulus `2πr·2|δ|` over the disc `πr²`, a
/// share `4|δ|/r` of the pixels it covers, for kernels at random positions. As `jump` already
/// sums every kernel that can reach a pixel, the jumps add at most `jump·min(1, 4|δ|/r)` to the
/// mean, the smooth part [`MEAN_FRACTION`] of its bound as for every model.
#[must_use]
pub fn warp(w: &Warp) -> Option<Tolerance> {
    let base = value_bound(&w.base)?;
    let b = regularity(&w.base)?;
    let (ex, ey) = (value_bound(&w.x)?, value_bound(&w.y)?);
    let (x, y) = (regularity(&w.x)?, regularity(&w.y)?);
    let s = f64::from(w.strength).abs();
    let reach = f64::from(MAX_WARP) * spectex_model::warp::depth(&Model::Warp(w.clone())) as f64;
    let d = (s * x.magnitude.max(y.magnitude)).min(reach);
    let delta =
        std::f64::consts::SQRT_2 * (s * ex.max(ey) + 6.0 * F32_UNIT_ROUNDOFF * (d + 3.0 * b.cell));
    let smooth = base + b.slope * delta;
    let near = if b.cell > 0.0 {
        (4.0 * delta / b.cell).min(1.0)
    } else {
        1.0
    };
    Some(Tolerance {
        max_abs: smooth + b.jump,
        mean_abs: MEAN_FRACTION * smooth + b.jump * near,
    })
}

impl CheckKind for Warp {
    /// [`warp`], for every component of the base (it bounds the largest).
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        Some(vec![warp(self)?; ModelKind::output_channels(self)])
    }

    fn regularity(&self) -> Option<Regularity> {
        let w = self;
        // v(p) = b(p + d(p)): moving p by δ moves the base's point by δ + |s|·(slope of x
        // or y)·δ per axis, √2 for the two axes together.
        let b = regularity(&w.base)?;
        let (x, y) = (regularity(&w.x)?, regularity(&w.y)?);
        let s = f64::from(w.strength).abs();
        let spread = 1.0 + std::f64::consts::SQRT_2 * s * x.slope.max(y.slope);
        let jumps = std::f64::consts::SQRT_2 * s * x.jump.max(y.jump);
        Some(Regularity {
            slope: b.slope * spread,
            // A jump of x or y moves the base's point by |s|·jump at most.
            jump: b.jump + b.slope * jumps,
            magnitude: b.magnitude,
            cell: b.cell,
        })
    }

    /// The base's plane: the base, x and y are all rendered on it.
    fn check_plane(&self) -> f64 {
        check_kind(&self.base).check_plane()
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::tolerance::tolerance;
    use spectex_model::classic::{Basis, ClassicNoise};
    use spectex_model::{LrpNoise, PhasorOutput, Stratum};

    /// A phasor base's truncation jumps set the warp's largest error but only their share
    /// `4|δ|/r` of the mean: the mean bound is the smooth part's quarter plus that share.
    pub fn warp_mean_counts_jumps_only_near_kernel_boundaries() {
        let mut phasor = spectex_model::fixtures::phasor_pwm(
            2,
            spectex_model::PhasorOrientation::TwoLobes {
                angle_a: 0.4,
                angle_b: 1.2,
            },
        );
        phasor.output = PhasorOutput::Gabor;
        let lrp = Model::Lrp(LrpNoise {
            seed: 1,
            mean: 0.0,
            strata: vec![Stratum {
                window_width: 10.0,
                amplitude: 0.1,
                sub_strata: vec![vec![[0.1, 0.2]]; 4],
            }],
        });
        let w = Warp {
            base: Box::new(Model::Phasor(phasor.clone())),
            x: Box::new(lrp.clone()),
            y: Box::new(lrp),
            strength: 6.0,
        };
        let t = warp(&w).unwrap();
        let r = regularity(&Model::Phasor(phasor)).unwrap();
        let smooth = t.max_abs - r.jump;
        assert!(r.jump > 0.0 && smooth > 0.0);
        assert!(t.mean_abs > MEAN_FRACTION * smooth);
        assert!(
            t.mean_abs < MEAN_FRACTION * smooth + 0.01 * r.jump,
            "{t:?} {r:?}"
        );
    }

    /// A warp's bound is the base's at strength 0 plus the GPU's relocation roundings, and it
    /// grows with the strength.
    pub fn warp_bound_grows_with_strength() {
        let lrp = |seed| {
            Model::Lrp(LrpNoise {
                seed,
                mean: 0.0,
                strata: vec![Stratum {
                    window_width: 10.0,
                    amplitude: 0.1,
                    sub_strata: vec![vec![[0.1, 0.2]]; 4],
                }],
            })
        };
        let w = |strength| Warp {
            base: Box::new(lrp(1)),
            x: Box::new(lrp(2)),
            y: Box::new(lrp(3)),
            strength,
        };
        let base = tolerance(&lrp(1)).unwrap().max_abs;
        let at0 = warp(&w(0.0)).unwrap().max_abs;
        // At strength 0 only the GPU's relocation of the point (a few ulps of 3 cells) is left.
        assert!(at0 > base && at0 < 3.0 * base, "{at0} vs {base}");
        assert!(warp(&w(8.0)).unwrap().max_abs > at0);
        // A classic base: its own bound plus its slope (8.5·√2 per cell of 8 px) times the
        // displacement's error, so it grows with the strength.
        let perlin = Model::Classic(ClassicNoise {
            seed: 0,
            dimensions: 2,
            cell_size: 8.0,
            basis: Basis::Gradient,
            fractal: None,
            amplitude: 1.0,
            mean: 0.0,
        });
        let r = regularity(&perlin).unwrap();
        assert!((r.slope - 8.5 * std::f64::consts::SQRT_2 / 8.0).abs() < 1e-12);
        let classic = |strength| Warp {
            base: Box::new(perlin.clone()),
            ..w(strength)
        };
        let own = tolerance(&perlin).unwrap().max_abs;
        let (a, b) = (warp(&classic(1.0)).unwrap(), warp(&classic(4.0)).unwrap());
        assert!(
            own < a.max_abs && a.max_abs < b.max_abs,
            "{own} {a:?} {b:?}"
        );
    }

    /// A warp is checked on its base's plane (x and y are rendered on it too).
    pub fn a_warp_is_checked_on_its_base_plane() {
        let classic = |dimensions| {
            Model::Classic(ClassicNoise {
                seed: 0,
                dimensions,
                cell_size: 8.0,
                basis: Basis::Gradient,
                fractal: None,
                amplitude: 1.0,
                mean: 0.0,
            })
        };
        let over = |base| Warp {
            base: Box::new(base),
            x: Box::new(classic(2)),
            y: Box::new(classic(2)),
            strength: 1.0,
        };
        let three_d = check_kind(&classic(3)).check_plane();
        assert_ne!(three_d, 0.0);
        assert_eq!(over(classic(3)).check_plane(), three_d);
        assert_eq!(over(classic(2)).check_plane(), 0.0);
    }

    /// A warp over a model without a derived regularity (phasor noise's phase-based outputs),
    /// as its base or as its x, has no bound: the cross-check refuses it rather than guess.
    pub fn warp_of_a_model_without_regularity_has_no_tolerance() {
        let lrp = Model::Lrp(LrpNoise {
            seed: 1,
            mean: 0.0,
            strata: vec![Stratum {
                window_width: 10.0,
                amplitude: 0.1,
                sub_strata: vec![vec![[0.1, 0.2]]; 4],
            }],
        });
        let bounded = Warp {
            base: Box::new(lrp.clone()),
            x: Box::new(lrp.clone()),
            y: Box::new(lrp.clone()),
            strength: 6.0,
        };
        assert!(bounded.tolerances().is_some());
        for output in [PhasorOutput::Phase, PhasorOutput::Profiled] {
            let mut phasor =
                spectex_model::fixtures::phasor_pwm(2, spectex_model::PhasorOrientation::Isotropic);
            phasor.output = output;
            let phasor = Box::new(Model::Phasor(phasor));
            for w in [
                Warp {
                    base: phasor.clone(),
                    ..bounded.clone()
                },
                Warp {
                    x: phasor.clone(),
                    ..bounded.clone()
                },
            ] {
                assert_eq!(warp(&w), None, "{output:?}");
                assert_eq!(w.tolerances(), None, "{output:?}");
            }
        }
    }
}
