//! Phasor noise: its own criterion ([`CheckKind::own_verdict`]), its bounds and regularity.
//! Its outputs are not all continuous functions of the complex sum `𝒢 = re + i·im` both
//! evaluators compute: the phase wraps at ±½ turn and is ill-conditioned where the intensity
//! vanishes, and square and sawtooth profiles jump. So each window is judged pixel by pixel,
//! from the renders of the model and of its Gabor, intensity and phase outputs (its
//! [`CheckKind::companions`]):
//!
//! - the Gabor (`Im 𝒢`) and intensity (`|𝒢|`) renders of the same kernels within
//!   [`complex_bound`] `E` (and `√2·E`): these check the sum itself;
//! - the phase render on the circle: `|Δφ| ≤ asin(√2·E / I)/2π + 2·ATAN_ERROR` turns, where the
//!   CPU's intensity `I > 2√2·E` (elsewhere the phase is not determined to that precision);
//! - the model's own output: where a profile is continuous, `|Δv| ≤ |amplitude|·L·Δφ + ε` for
//!   the profile's Lipschitz constant `L` (per turn); a pixel whose CPU phase lies within `Δφ`
//!   of one of the profile's jumps may take either side.
//!
//! The kernels themselves (positions, directions, frequencies, phase offsets) are drawn by the
//! same host code for both evaluators (`spectex_model::phasor_kernels`), so only the per-pixel
//! f32 arithmetic can differ, and the profile's varying fields (duty cycles, blend weight),
//! which the device reads per pixel in f32 ([`device_field_error`]): a duty cycle moves a
//! square's jump, which is then not located; the weight adds [`weight_slack`] to the bound.

use spectex_model::{
    Field, MAX_POSITION, Model, PHASOR_TRUNCATION, PhasorNoise, PhasorOutput, Profile,
};

use super::{
    COS_ABS_ERROR, CheckKind, EXP_REL_ERROR, F32_UNIT_ROUNDOFF, PHASE_ROUNDINGS, Regularity,
    SUMMATION_ROUNDINGS, Tolerance, gaussian_slope, impulse_count,
};

/// Bound on `|device − CPU|` of a profile field read per pixel on the device (clamped to
/// `[0, 1]`; spectex_gpu's `device_fields`), where the CPU evaluates it in f64 and rounds once:
/// - a constant: exact;
/// - a linear field: the column's and the row's f64 terms each split into two f32 and added as
///   two-float numbers, rounded once: an ulp of the result (`2⁻²⁴` below 1), plus the split's
///   and the low parts' roundings, `2⁻⁴⁴` of the terms' size (at most `|value| + |g|₁·2³⁰`,
///   positions being below `MAX_POSITION`);
/// - an image: the interpolation fraction rounded to f32 and the bilinear sum's six f32
///   operations on samples in `[0, 1]` (`12·2⁻²⁴` in `g`, with the fractions' rounding), times
///   the span `|max − min|`, and the map `min + g·span`'s two roundings and the CPU's own,
///   `2·2⁻²⁴·max(1, |min|, |max|)`.
#[must_use]
pub fn device_field_error(field: &Field) -> f64 {
    let u = F32_UNIT_ROUNDOFF;
    match field {
        Field::Constant { .. } => 0.0,
        Field::Linear { value, gradient } => {
            let terms = f64::from(value.abs())
                + gradient.iter().map(|g| f64::from(g.abs())).sum::<f64>() * MAX_POSITION;
            2.0 * u + terms * 2f64.powi(-44)
        }
        Field::Image { min, max, .. } => {
            let (min, max) = (f64::from(*min), f64::from(*max));
            u * (12.0 * (max - min).abs() + 2.0 * 1f64.max(min.abs()).max(max.abs()))
        }
    }
}

/// The largest magnitude of a profile leaf's value: 1 for the shapes, the samples' or the
/// harmonics' sum otherwise.
fn leaf_magnitude(profile: &Profile) -> f64 {
    match profile {
        Profile::Samples { values } => values
            .iter()
            .map(|v| f64::from(v.abs()))
            .fold(1.0, f64::max),
        Profile::Harmonics { terms } => terms.iter().map(|h| f64::from(h.weight.abs())).sum(),
        Profile::Blend { a, b, .. } => leaf_magnitude(a).max(leaf_magnitude(b)),
        _ => 1.0,
    }
}

/// What a varying blend weight's device error adds to a profiled output's bound:
/// `|amplitude|·δw·(|A| + |B|)`, `δw` its [`device_field_error`]; 0 otherwise.
#[must_use]
pub fn weight_slack(m: &PhasorNoise) -> f64 {
    match (&m.profile, m.output) {
        (Profile::Blend { a, b, weight }, PhasorOutput::Profiled) => {
            f64::from(m.amplitude).abs()
                * device_field_error(weight)
                * (leaf_magnitude(a) + leaf_magnitude(b))
        }
        _ => 0.0,
    }
}

/// Absolute error of `atan2_turns` on either side, turns (5e-8 measured bound, spectex-model).
pub const ATAN_ERROR: f64 = 5e-8;

/// Bound `E` on `|Δre|` and `|Δim|` at any pixel: the impulse count of the 3×3 (3×3×3) cells
/// bounded as in [`super::gabor::gabor`] (`n + 6√n + 6` for a Poisson mean `n`); per impulse
/// the phase `f·d + ψ` (offsets within 2 cells per axis: `|f·d| ≤ 2√dims·F·r` turns) rounded
/// [`PHASE_ROUNDINGS`] times, [`COS_ABS_ERROR`] and [`EXP_REL_ERROR`], on each side; plus the
/// summation of up to `count` terms of magnitude ≤ 1.
#[must_use]
pub fn complex_bound(m: &PhasorNoise) -> f64 {
    let three_d = m.dimensions == 3;
    let cells = if three_d { 27.0 } else { 9.0 };
    let n = cells * m.impulses_per_cell();
    let count = n + 6.0 * n.sqrt() + 6.0;
    let reach = if three_d {
        2.0 * 3f64.sqrt()
    } else {
        2.0 * 2f64.sqrt()
    };
    let turns = reach * m.frequency.range().1.min(0.5) * m.kernel_radius() + 1.0;
    let phase = std::f64::consts::TAU * PHASE_ROUNDINGS * F32_UNIT_ROUNDOFF * turns;
    let per_term = 2.0 * (phase + COS_ABS_ERROR + EXP_REL_ERROR);
    count * per_term + SUMMATION_ROUNDINGS * F32_UNIT_ROUNDOFF * count
}

/// A profile's Lipschitz constant per turn away from its jumps, and its jumps (turns in
/// `[0, 1)`, at `duty` for a square profile; `None` stands for "any" where a per-pixel duty
/// makes the position vary).
///
/// `harmonics` > 0: a minified render, where every profile is the sum of at most that many
/// harmonics of its Fourier series (`spectex_model::filter`'s `filtered_*`), each weighted by
/// a response in `[0, 1]`: continuous, with slope at most `Σ_k 2πk·|c_k|` per turn of phase —
/// `Σ_k 2πk·(2/(πk)) = 4·harmonics` for the square and the sawtooth,
/// `Σ_{n odd} 2πn·8/(π²n²) = (16/π)·Σ_{n odd} 1/n` for the triangle, from the series itself for
/// sampled profiles; the sine and explicit harmonics keep their unfiltered bounds.
fn shape(profile: &Profile, harmonics: u32) -> (f64, Vec<Option<f64>>) {
    let h = f64::from(harmonics);
    match profile {
        Profile::Square { .. } | Profile::Sawtooth if harmonics > 0 => (4.0 * h, vec![]),
        Profile::Triangle if harmonics > 0 => (
            16.0 / std::f64::consts::PI
                * (1..=harmonics)
                    .step_by(2)
                    .map(|n| 1.0 / f64::from(n))
                    .sum::<f64>(),
            vec![],
        ),
        Profile::Samples { values } if harmonics > 0 => {
            let series = spectex_model::filter::samples_series(values);
            let slope = series[1..]
                .chunks_exact(2)
                .take(harmonics as usize)
                .enumerate()
                .map(|(i, ab)| {
                    std::f64::consts::TAU
                        * (i + 1) as f64
                        * f64::from(ab[0]).hypot(f64::from(ab[1]))
                })
                .sum();
            (slope, vec![])
        }
        Profile::Sine => (std::f64::consts::TAU, vec![]),
        Profile::Triangle => (4.0, vec![]),
        Profile::Sawtooth => (2.0, vec![Some(0.0)]),
        Profile::Square { duty } => {
            let at = match duty {
                Field::Constant { value } => Some(f64::from(*value).clamp(0.0, 1.0)),
                _ => None,
            };
            (0.0, vec![Some(0.0), at])
        }
        Profile::Samples { values } => {
            let n = values.len();
            let steepest = (0..n)
                .map(|k| (f64::from(values[(k + 1) % n]) - f64::from(values[k])).abs())
                .fold(0.0, f64::max);
            (steepest * n as f64, vec![])
        }
        Profile::Harmonics { terms } => (
            terms
                .iter()
                .map(|h| std::f64::consts::TAU * f64::from(h.k) * f64::from(h.weight).abs())
                .sum(),
            vec![],
        ),
        Profile::Blend { a, b, .. } => {
            let (la, mut ja) = shape(a, harmonics);
            let (lb, jb) = shape(b, harmonics);
            ja.extend(jb);
            (la.max(lb), ja)
        }
    }
}

/// Harmonics of a profile filtered at `u = F·s` at most (the terms of
/// `spectex_model::filter`'s `filtered_*` with `k·u < FADE_END`, at most
/// `MAX_SQUARE_HARMONICS`), for the smallest `u` of a window.
fn square_harmonics(u_min: f64) -> u32 {
    use spectex_model::filter::{FADE_END, MAX_SQUARE_HARMONICS};
    (1..=MAX_SQUARE_HARMONICS)
        .take_while(|&k| f64::from(k) * u_min < FADE_END)
        .count() as u32
}

/// Circular distance of two phases in turns.
fn circular(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(1.0);
    d.min(1.0 - d)
}

/// The reasons a window fails (empty when it passes), from the renders `(cpu, gpu)` of the
/// model's own output, then its Gabor, intensity and phase variants, for the complex bound `e`.
fn judge_pixels(
    m: &PhasorNoise,
    e: f64,
    renders: &[(Vec<f32>, Vec<f32>)],
    footprint: Option<f64>,
) -> Vec<String> {
    judge_pixels_at(m, &|_| e, &|_| 0.0, &|_| None, renders, footprint)
}

/// [`judge_pixels`] with the complex bound `e(k)` of pixel `k`, `slack(k)` added to its
/// output's bound where a profile is continuous, and `duties(k)`: where known, the varying
/// duty cycles' values at pixel `k` each with a bound on the evaluator's error, so that a
/// square profile's jump there is located (else it may be anywhere and the output is not
/// judged).
fn judge_pixels_at(
    m: &PhasorNoise,
    e: &dyn Fn(usize) -> f64,
    slack: &dyn Fn(usize) -> f64,
    duties: &dyn Fn(usize) -> Option<Vec<(f64, f64)>>,
    renders: &[(Vec<f32>, Vec<f32>)],
    footprint: Option<f64>,
) -> Vec<String> {
    // A minified render filters profiles to `harmonics` terms of their Fourier series.
    let harmonics = footprint.map_or(0, |s| square_harmonics(m.frequency.range().0 * s));
    let (lipschitz, jumps) = shape(&m.profile, harmonics);
    let amplitude = f64::from(m.amplitude).abs();
    let (gabor, intensity, phase) = (&renders[1], &renders[2], &renders[3]);
    let mut why = Vec::new();
    let mut count = |name: &str, bad: usize| {
        if bad > 0 {
            why.push(format!("{bad} {name} pixels outside their bound"));
        }
    };
    let over = |pair: &(Vec<f32>, Vec<f32>), bound: &dyn Fn(usize) -> f64| {
        pair.0
            .iter()
            .zip(&pair.1)
            .enumerate()
            .filter(|(k, (a, b))| (f64::from(**a) - f64::from(**b)).abs() > bound(*k))
            .count()
    };
    count("Gabor", over(gabor, e));
    count(
        "intensity",
        over(intensity, &|k| std::f64::consts::SQRT_2 * e(k)),
    );
    // Per pixel: the phase tolerance where the phase is determined.
    let dphi: Vec<Option<f64>> = intensity
        .0
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let i = f64::from(i);
            let r = std::f64::consts::SQRT_2 * e(k);
            (i > 2.0 * r).then(|| (r / i).asin() / std::f64::consts::TAU + 2.0 * ATAN_ERROR)
        })
        .collect();
    let bad_phase = phase
        .0
        .iter()
        .zip(&phase.1)
        .zip(&dphi)
        .filter(|((a, b), d)| d.is_some_and(|d| circular(f64::from(**a), f64::from(**b)) > d))
        .count();
    count("phase", bad_phase);
    let own = &renders[0];
    // A filtered square's series adds each harmonic's rounding (a few f32 ulps of 1, the device
    // dividing within 2.5 ulps): 1e-6 per harmonic.
    let value_bound = |d: f64| {
        amplitude * (lipschitz * d + 1e-6 * (1.0 + harmonics as f64)) + 4.0 * F32_UNIT_ROUNDOFF
    };
    let bad_own = match m.output {
        PhasorOutput::Gabor => over(own, &|k| amplitude * e(k) + 1e-6),
        PhasorOutput::Intensity => {
            over(own, &|k| amplitude * std::f64::consts::SQRT_2 * e(k) + 1e-6)
        }
        PhasorOutput::Phase | PhasorOutput::Profiled => own
            .0
            .iter()
            .zip(&own.1)
            .enumerate()
            .filter(|(k, (a, b))| {
                let Some(d) = dphi[*k] else {
                    return false;
                };
                let diff = f64::from(**a) - f64::from(**b);
                if m.output == PhasorOutput::Phase {
                    // Both are mean + amplitude·φ: compare φ on the circle.
                    return amplitude > 0.0 && circular(diff / amplitude, 0.0) > d;
                }
                let t = f64::from(phase.0[*k]).rem_euclid(1.0);
                let varying = duties(*k);
                let near_jump = jumps.iter().any(|j| match (j, &varying) {
                    (Some(j), _) => circular(t, *j) <= d,
                    // A varying duty: near any of the pixel's duties, by the phase's tolerance
                    // plus the duty's own error.
                    (None, Some(at)) => at.iter().any(|(v, dv)| circular(t, *v) <= d + dv),
                    (None, None) => true,
                });
                !near_jump && diff.abs() > value_bound(d) + slack(*k)
            })
            .count(),
    };
    count("output", bad_own);
    why
}

/// The reasons a window fails [`CheckKind::own_verdict`]'s criterion with the complex sum
/// bounded by `e` instead of [`complex_bound`]: for evaluators that add their own, derived
/// error to the sum's (the WGSL export's position rounding). `renders` as `own_verdict`'s.
#[must_use]
pub fn judge_with_bound(
    m: &PhasorNoise,
    e: f64,
    renders: &[(Vec<f32>, Vec<f32>)],
    footprint: Option<f64>,
) -> Vec<String> {
    judge_pixels(m, e, renders, footprint)
}

/// [`judge_with_bound`] with a bound per pixel: `e[k]` bounds pixel `k`'s complex sum, and
/// `slack[k]` adds to its output's bound where the profile is continuous (what an evaluator
/// that computes a profile parameter, such as a blend weight, in its own precision adds), and
/// `duties[k]` (empty, or one entry per pixel) lists the varying duty cycles' values at pixel
/// `k` with a bound on the evaluator's error in each: a square profile's jump is then judged
/// there rather than anywhere. For
/// evaluators whose added error varies over the window (the WGSL export's fields, evaluated
/// in f32 at each impulse). `renders` as `own_verdict`'s, `e` and `slack` one per pixel.
#[must_use]
pub fn judge_with_pixel_bounds(
    m: &PhasorNoise,
    e: &[f64],
    slack: &[f64],
    duties: &[Vec<(f64, f64)>],
    renders: &[(Vec<f32>, Vec<f32>)],
    footprint: Option<f64>,
) -> Vec<String> {
    judge_pixels_at(
        m,
        &|k| e[k],
        &|k| slack[k],
        &|k| duties.get(k).cloned(),
        renders,
        footprint,
    )
}

/// `m` rendering `output` at zero mean and unit amplitude: one of its companions.
fn variant(m: &PhasorNoise, output: PhasorOutput) -> Model {
    Model::Phasor(PhasorNoise {
        output,
        mean: 0.0,
        amplitude: 1.0,
        ..m.clone()
    })
}

/// Phasor noise's Gabor (`Im 𝒢`) and intensity (`|𝒢|`) outputs: each kernel changes at most
/// by `2π F_max + gaussian slope` per pixel and jumps by [`PHASOR_TRUNCATION`] at its radius.
fn phasor_regularity(m: &PhasorNoise) -> Option<Regularity> {
    if !matches!(m.output, PhasorOutput::Gabor | PhasorOutput::Intensity) {
        return None;
    }
    let cells = if m.dimensions == 3 { 27.0 } else { 9.0 };
    let terms = f64::from(m.amplitude).abs() * impulse_count(cells, m.impulses_per_cell());
    let slope = std::f64::consts::TAU * m.frequency.range().1.min(0.5)
        + gaussian_slope(m.bandwidth_range().1);
    Some(Regularity {
        slope: terms * slope,
        jump: terms * PHASOR_TRUNCATION,
        magnitude: terms + f64::from(m.mean).abs(),
        cell: m.kernel_radius(),
    })
}

/// The companions' outputs, in the order [`judge_pixels`] reads their renders.
const COMPANIONS: [PhasorOutput; 3] = [
    PhasorOutput::Gabor,
    PhasorOutput::Intensity,
    PhasorOutput::Phase,
];

impl CheckKind for PhasorNoise {
    /// The complex sum's bound ([`complex_bound`]) times the amplitude: what reports show. It
    /// bounds no output by itself (the intensity's bound is `√2` of it, and phases and profiles
    /// may wrap or flip); the criterion is [`own_verdict`](CheckKind::own_verdict).
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        let amplitude = f64::from(self.amplitude).abs();
        Some(vec![Tolerance::from_max(amplitude * complex_bound(self))])
    }

    fn regularity(&self) -> Option<Regularity> {
        phasor_regularity(self)
    }

    /// For the Gabor and intensity outputs, the complex sum's bound ([`complex_bound`], `√2` of
    /// it for the intensity) times the amplitude; none for the phase-based outputs.
    fn value_bound(&self) -> Option<f64> {
        let e = complex_bound(self) * f64::from(self.amplitude).abs();
        match self.output {
            PhasorOutput::Gabor => Some(e),
            PhasorOutput::Intensity => Some(std::f64::consts::SQRT_2 * e),
            PhasorOutput::Phase | PhasorOutput::Profiled => None,
        }
    }

    fn companions(&self) -> Vec<Model> {
        COMPANIONS
            .iter()
            .map(|&output| variant(self, output))
            .collect()
    }

    fn own_verdict(
        &self,
        renders: &[(Vec<f32>, Vec<f32>)],
        footprint: Option<f64>,
    ) -> Option<Vec<String>> {
        let (e, slack) = (complex_bound(self), weight_slack(self));
        Some(judge_pixels_at(
            self,
            &|_| e,
            &|_| slack,
            &|_| None,
            renders,
            footprint,
        ))
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use spectex_model::PhasorOrientation;

    fn pwm(output: PhasorOutput) -> PhasorNoise {
        PhasorNoise {
            seed: 0,
            dimensions: 2,
            bandwidth: Field::constant(0.02),
            frequency: Field::constant(0.06),
            orientation: PhasorOrientation::Isotropic,
            impulses_per_kernel: 10.0,
            profile: Profile::Square {
                duty: Field::constant(0.25),
            },
            output,
            mean: 0.0,
            amplitude: 1.0,
        }
    }

    /// One pixel: (own output, Gabor, intensity, phase), each (cpu, gpu).
    /// A minified render's square profile is a continuous series: no pixel is excused as near
    /// a jump, and a difference within its slope bound times the phase tolerance passes.
    pub fn filtered_squares_are_judged_by_their_slope() {
        let m = pwm(PhasorOutput::Profiled);
        // F = 0.06 at a footprint of 4: u = 0.24, harmonics 1 and 2 (2·0.24 < 0.55 ≤ 3·0.24).
        assert_eq!(square_harmonics(0.24), 2);
        let (lipschitz, jumps) = shape(&m.profile, 2);
        assert_eq!((lipschitz, jumps.len()), (8.0, 0));
        // Phase 0.0 (at the unfiltered profile's jump), a phase error well inside the bound.
        let ok = renders([0.5, 0.5 + 1e-6], [0.0; 2], [1.0; 2], [0.0, 0.0]);
        assert!(judge_pixels(&m, E, &ok, Some(4.0)).is_empty());
        let off = renders([0.5, 0.6], [0.0; 2], [1.0; 2], [0.0, 0.0]);
        assert_eq!(judge_pixels(&m, E, &off, Some(4.0)).len(), 1);
        // Unfiltered, the same pixel sits on a jump and is excused.
        assert!(judge_pixels(&m, E, &off, None).is_empty());
    }

    fn renders(
        own: [f32; 2],
        gabor: [f32; 2],
        intensity: [f32; 2],
        phase: [f32; 2],
    ) -> Vec<(Vec<f32>, Vec<f32>)> {
        [own, gabor, intensity, phase]
            .iter()
            .map(|p| (vec![p[0]], vec![p[1]]))
            .collect()
    }

    const E: f64 = 1e-4;

    /// A varying duty cycle: without its value at the pixel the output is not judged (the
    /// jump may be anywhere); with it, a flip far from that duty fails and one within the
    /// duty's error of it passes.
    pub fn a_located_varying_duty_judges_the_output() {
        let mut m = pwm(PhasorOutput::Profiled);
        m.profile = Profile::Square {
            duty: Field::Linear {
                value: 0.4,
                gradient: [1e-5, 0.0, 0.0],
            },
        };
        let flip = renders([1.0, 0.0], [0.3, 0.3], [1.0, 1.0], [0.1, 0.1]);
        let judge = |duties: &[Vec<(f64, f64)>]| {
            judge_with_pixel_bounds(&m, &[E], &[0.0], duties, &flip, None).len()
        };
        assert_eq!(judge(&[]), 0, "not located: not judged");
        assert_eq!(
            judge(&[vec![(0.4, 1e-6)]]),
            1,
            "a flip 0.3 turns from the duty"
        );
        assert_eq!(
            judge(&[vec![(0.1 + 1e-3, 2e-3)]]),
            0,
            "within the duty's error"
        );
    }

    pub fn a_profile_may_flip_only_next_to_its_jump() {
        let m = pwm(PhasorOutput::Profiled);
        // Phase tolerance at I = 1: asin(√2·1e-4)/2π + 1e-7 ≈ 2.26e-5 turns.
        let near = renders([1.0, 0.0], [0.3, 0.3], [1.0, 1.0], [0.249_99, 0.250_01]);
        assert!(judge_pixels(&m, E, &near, None).is_empty());
        let far = renders([1.0, 0.0], [0.3, 0.3], [1.0, 1.0], [0.249, 0.249]);
        assert_eq!(
            judge_pixels(&m, E, &far, None).len(),
            1,
            "a flip 1e-3 turns from the jump"
        );
    }

    pub fn phases_are_compared_on_the_circle_where_they_are_determined() {
        let m = pwm(PhasorOutput::Phase);
        let wrap = renders(
            [0.499_99, -0.499_99],
            [0.3, 0.3],
            [1.0, 1.0],
            [0.499_99, -0.499_99],
        );
        assert!(
            judge_pixels(&m, E, &wrap, None).is_empty(),
            "±½ turn is one angle"
        );
        let off = renders([0.2, 0.3], [0.3, 0.3], [1.0, 1.0], [0.2, 0.3]);
        assert_eq!(
            judge_pixels(&m, E, &off, None).len(),
            2,
            "phase and output both off"
        );
        // Near a singularity (I < 2√2·E) the phase is not determined: not judged.
        let singular = renders([0.2, 0.3], [0.0, 0.0], [1e-4, 1e-4], [0.2, 0.3]);
        assert!(judge_pixels(&m, E, &singular, None).is_empty());
    }

    pub fn the_complex_sum_is_held_to_its_bound() {
        let m = pwm(PhasorOutput::Profiled);
        let gabor = renders([1.0, 1.0], [0.3, 0.3 + 2e-4], [1.0, 1.0], [0.1, 0.1]);
        assert_eq!(judge_pixels(&m, E, &gabor, None).len(), 1);
        let intensity = renders([1.0, 1.0], [0.3, 0.3], [1.0, 1.0 + 2e-4], [0.1, 0.1]);
        assert_eq!(judge_pixels(&m, E, &intensity, None).len(), 1);
        assert!(
            complex_bound(&m) > 0.0 && complex_bound(&m) < 1e-2,
            "{}",
            complex_bound(&m)
        );
    }
}
