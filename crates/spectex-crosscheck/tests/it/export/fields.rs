//! A phasor model's varying fields through the export: a slow f64 reference of the kernel
//! process (the randomness contract's draws, replayed here and checked against
//! `PhasorKernels::draw_cell`) that says, per pixel of a window, what the export's f32 field
//! evaluation can change there, and where it can decide a discontinuous use either way.
//!
//! The export evaluates every field in f32 at the impulse position `n + r` it forms
//! (the glue of `phasor.wgsl`), the CPU in f64 at `(cell + o)·r`. Per impulse, from the CPU's
//! values:
//! - position: the export's `r` is within [`position_error`] pixels of the CPU's position;
//! - a field's value moves by [`field_error`] (its slope times that, plus its f32 roundings);
//! - thinning keeps an impulse when `v < (b/b_max)²`: where `|v − keep|` is within what `b`'s
//!   error moves `keep` by, the export may decide otherwise, and every later draw of the cell
//!   then differs: the cell is **ambiguous**, and so is every pixel whose 3×3 cells hold it;
//! - the sharpness `(b/b_min)²`, the frequency magnitude `F·r` and the direction `u` move by
//!   derived amounts, which move the term `g·e^{2πi(f·d + ψ)}` by `ln 20·Δs·|d|² + 2π|Δf|·|d|`
//!   in re and in im (`|d| < 1` inside the support): added to the pixel's complex bound;
//! - a gradient direction is `atan2` of the grey level's central differences: where their
//!   CPU magnitude `|∇|` is within twice their error `|Δ∇|` (a flat spot among them) the
//!   direction is not determined; else it moves by `asin(|Δ∇|/|∇|)`. A coherent direction
//!   normalises a sum `S` of kernels: not determined where `|S| ≤ 2|ΔS|` or where one of its
//!   kernels' support edge is within the position error (the sum jumps); else it moves by
//!   `2|ΔS|/|S|`. An impulse whose direction is not determined makes the pixels in its
//!   support **ambiguous**;
//! - an impulse whose support edge `s·|d|² = 1` is within the error of `s·|d|²` is on one side
//!   only: its pixels are left out as **edge** pixels (as for constant fields).
//!
//! Profile parameters are read at the pixel: a blend weight's error times the two profiles'
//! peaks is the output's slack; a varying duty cycle's value and error locate a square
//! profile's jump at the pixel (`judge_with_pixel_bounds`' `duties`).

use spectex_crosscheck::tolerance::{
    COS_ABS_ERROR, EXP_REL_ERROR, F32_UNIT_ROUNDOFF, SUMMATION_ROUNDINGS,
};
use spectex_model::math::{cos_turns, exp_poly, sin_turns};
use spectex_model::phasor_kernels::{DIRECTION_LAYER, Impulse, PHASOR_LAYER, PhasorKernels};
use spectex_model::random::{Prng, cell_hash};
use spectex_model::{
    Field, NEG_LN_20, PHASOR_TRUNCATION, PhasorNoise, PhasorOrientation, Profile, Window,
};

const U: f64 = F32_UNIT_ROUNDOFF;
const TAU: f64 = std::f64::consts::TAU;

/// What the export's fields change at each pixel of a window (row-major).
pub(super) struct FieldBounds {
    /// An impulse's support edge within the error: one side only (left out).
    pub(super) edge: Vec<bool>,
    /// A thinning decision or a direction the export may take otherwise (left out).
    pub(super) ambiguous: Vec<bool>,
    /// Added to the complex bound `E`.
    pub(super) extra: Vec<f64>,
    /// Added to the output's bound where the profile is continuous.
    pub(super) slack: Vec<f64>,
    /// The varying duty cycles at the pixel (the CPU's, clamped to [0, 1]) and the bound on
    /// the export's difference.
    pub(super) duties: Vec<Vec<(f64, f64)>>,
}

/// How far the export's impulse position `n + r` lies from the CPU's `(cell + o)·r` (f64),
/// pixels: `r = (s + o)·r₃₂ − rem` with `r₃₂` the side rounded to f32 (`2u·r` for
/// `|s + o| ≤ 2`), `rem` the split's remainder (`roundings` unit roundoffs of a number below
/// `2r + 2`, the test's `POSITION_ROUNDINGS`), and two roundings of the result (below
/// `2r + 2`); the CPU's f64 position `2⁻⁵²·(far + 2r)`.
pub(super) fn position_error(side: f64, roundings: f64, far: f64) -> f64 {
    2.0 * U * side
        + (roundings + 2.0) * U * (2.0 * side + 2.0)
        + 2f64.powi(-52) * (far + 2.0 * side)
}

/// The largest difference of neighbouring grey samples (periodic): the bilinear
/// interpolation's slope per sample along either axis.
fn grey_slope(grey: &[f32], w: usize, h: usize) -> f64 {
    let mut l = 0.0f64;
    for j in 0..h {
        for i in 0..w {
            let s = f64::from(grey[j * w + i]);
            l = l
                .max((f64::from(grey[j * w + (i + 1) % w]) - s).abs())
                .max((f64::from(grey[((j + 1) % h) * w + i]) - s).abs());
        }
    }
    l
}

/// Bound on `|export − cpu|` of an image's grey level at a point the export forms within
/// `dx` pixels (per axis) and at most `reach` pixels from its integer part: per axis its
/// sample coordinate `(rem + r)·(1/size) − ½` — the split's remainder within 16 ulp of the
/// repeat `R` (`32u·R`), the sum `rem + r` (below `R + reach`), the product and the `− ½`
/// rounded once each — moves the
/// bilinear value by the grey slope per sample, plus its three lerps (8 roundings of values
/// in [0, 1]).
fn grey_error(field: &Field, dx: f64, reach: f64) -> f64 {
    let Field::Image {
        width,
        height,
        grey,
        pixel_size,
        ..
    } = field
    else {
        return 0.0;
    };
    let size = f64::from(*pixel_size);
    let l = grey_slope(grey, *width, *height);
    let along = |n: usize| {
        let r = n as f64 * size;
        (dx + 32.0 * U * r + U * (r + reach)) / size + 3.0 * U * ((r + reach) / size + 1.0)
    };
    l * (along(*width) + along(*height)) + 8.0 * U
}

/// Bound on `|export − cpu|` of `field` at `x` (pixels), the export's point within `dx`
/// pixels of the CPU's and at most `reach` pixels from its integer part: a constant is exact;
/// a ramp `((v + g_x·n_x) + g_x·r_x) + (g_y·n_y + g_y·r_y)` rounds 6 times relative to
/// `|v| + Σ|g|·(|x| + reach + 1)`, and moves by `Σ|g|·dx`; an image maps its grey level
/// ([`grey_error`]) by `min + g·(max − min)` (the span rounded to f32, then 2 roundings).
pub(super) fn field_error(field: &Field, x: [f64; 2], dx: f64, reach: f64) -> f64 {
    match field {
        Field::Constant { .. } => 0.0,
        Field::Linear { value, gradient } => {
            let g = [f64::from(gradient[0]).abs(), f64::from(gradient[1]).abs()];
            let size = f64::from(*value).abs()
                + g[0] * (x[0].abs() + reach + 1.0)
                + g[1] * (x[1].abs() + reach + 1.0);
            6.0 * U * size + (g[0] + g[1]) * dx
        }
        Field::Image { min, max, .. } => {
            let span = (f64::from(*max) - f64::from(*min)).abs();
            span * grey_error(field, dx, reach) + 3.0 * U * (f64::from(*min).abs() + span)
        }
    }
}

/// One impulse as the reference draws it.
struct Reference {
    /// Offset in its cell, cell units.
    o: [f64; 2],
    /// The CPU's sharpness `(b/b_min)²` and the bound on the export's difference.
    sharp: f64,
    dsharp: f64,
    /// Bound on `|f_export − f_cpu|`, turns per cell unit.
    df: f64,
    /// Its direction is not determined by the export's precision.
    ambiguous: bool,
}

/// One cell's impulses, and whether a thinning decision in it is ambiguous.
struct Cell {
    impulses: Vec<Reference>,
    ambiguous: bool,
}

/// The reference's view of a model.
struct Process<'a> {
    m: &'a PhasorNoise,
    kernels: PhasorKernels,
    side: f64,
    threshold: f32,
    cap: u32,
    /// The export's impulse position error, pixels.
    dx: f64,
}

/// Knuth's Poisson count as the contract draws it.
fn count(prng: &mut Prng, threshold: f32, cap: u32) -> u32 {
    let mut p = 1.0f32;
    let mut n = 0;
    while n < cap {
        p *= prng.next_f32();
        if p < threshold {
            return n;
        }
        n += 1;
    }
    n
}

impl Process<'_> {
    /// The impulses of cell `c` (2D), replaying `PhasorKernels::draw_cell`'s draws; checks
    /// that the kept ones are `draw_cell`'s.
    fn draw(&self, c: [i32; 2]) -> Cell {
        let m = self.m;
        let side = self.side;
        let reach = 2.0 * side + 2.0;
        let mut prng = Prng::new(cell_hash(c[0], c[1], PHASOR_LAYER, m.seed));
        let n = count(&mut prng, self.threshold, self.cap);
        let (b_min, b_max) = m.bandwidth_range();
        let graded = b_max > b_min;
        let mut cell = Cell {
            impulses: Vec::new(),
            ambiguous: false,
        };
        let mut kept: Vec<[f32; 2]> = Vec::new();
        for _ in 0..n {
            let o = [prng.next_f32(), prng.next_f32()];
            let x = [
                (f64::from(c[0]) + f64::from(o[0])) * side,
                (f64::from(c[1]) + f64::from(o[1])) * side,
            ];
            let (mut sharp, mut dsharp) = (1.0, 0.0);
            if graded {
                let b = m.bandwidth.at(x[0], x[1], 0.0).clamp(b_min, b_max);
                let keep = (b / b_max).powi(2);
                let db = field_error(&m.bandwidth, x, self.dx, reach);
                // keep = q², q = b/b_max: moved by 2·Δb/b_max, plus b_max's rounding to f32,
                // the quotient and the square (4u of a value ≤ 1).
                let dkeep = 2.0 * db / b_max + 4.0 * U;
                let v = f64::from(prng.next_f32());
                if (v - keep).abs() <= dkeep {
                    cell.ambiguous = true;
                }
                if v >= keep {
                    continue;
                }
                sharp = (b / b_min) * (b / b_min);
                // s = (b/b_min)²: slope 2b/b_min² ≤ 2·b_max/b_min², plus b_min's rounding,
                // the quotient, the square and the CPU's rounding to f32 (6u of s).
                dsharp = 2.0 * b_max / (b_min * b_min) * db + 6.0 * U * sharp;
            }
            let (du, ambiguous) = self.direction(&mut prng, x);
            prng.next_f32(); // ψ
            let f = m.frequency.at(x[0], x[1], 0.0).clamp(0.0, 0.5);
            let fr = f * side;
            // F·r: F's error times r (F clamped in both), r rounded to f32, the product, and
            // the CPU's rounding to f32; then each component of fr·u (one rounding) and the
            // direction's error times fr.
            let dfr = side * field_error(&m.frequency, x, self.dx, reach) + 4.0 * U * fr;
            let df = dfr + fr * du + 2.0 * U * fr;
            kept.push(o);
            cell.impulses.push(Reference {
                o: [f64::from(o[0]), f64::from(o[1])],
                sharp,
                dsharp,
                df,
                ambiguous,
            });
        }
        let mut cpu: Vec<Impulse> = Vec::new();
        self.kernels.draw_cell([c[0], c[1], 0], &mut cpu);
        let theirs: Vec<[f32; 2]> = cpu.iter().map(|i| [i.o[0], i.o[1]]).collect();
        assert_eq!(
            kept, theirs,
            "the reference's draws of cell {c:?} are draw_cell's"
        );
        cell
    }

    /// Draws what the orientation draws at the impulse `x` (pixels), and returns the bound
    /// on the export's direction error `|Δu|` and whether the direction is not determined.
    fn direction(&self, prng: &mut Prng, x: [f64; 2]) -> (f64, bool) {
        let reach = 2.0 * self.side + 2.0;
        match &self.m.orientation {
            PhasorOrientation::Aligned { angle } => {
                // t = fract(a·(1/2π)): a's error over 2π, 1/2π's rounding, the product and
                // the fract (3u of |a|/2π + 1); |Δu| ≤ 2π·Δt plus cos/sin's error.
                let a = angle.at(x[0], x[1], 0.0);
                let dt =
                    field_error(angle, x, self.dx, reach) / TAU + 3.0 * U * (a.abs() / TAU + 1.0);
                (TAU * dt + 2.0 * COS_ABS_ERROR, false)
            }
            PhasorOrientation::TwoLobes { .. } => {
                prng.next_f32();
                (0.0, false)
            }
            PhasorOrientation::Isotropic => {
                // Its in-shader direction is bounded by `phasor_export_bound`.
                prng.next_f32();
                (0.0, false)
            }
            PhasorOrientation::Gradient { image, .. } => {
                let (gx, gy, dg) = gradient(image, x, self.dx, reach);
                let norm = gx.hypot(gy);
                if norm <= 2.0 * dg {
                    return (0.0, true);
                }
                // The angle moves by asin(|Δ∇|/|∇|). The export normalises the differences and
                // rotates them by the offset's cosine and sine (`phasor_export_gradient`):
                // scaled by the larger (2.5 ulp, WGSL's division), squared and summed (2u),
                // `1/sqrt` (4.5 ulp for sqrt, 2.5 for the division) and the product (u): 14u
                // per component; the rotation's constants (u each), products and sum (3u): 5u.
                // So |Δu| ≤ √2·19u < 32u.
                ((dg / norm).asin() + 32.0 * U, false)
            }
            PhasorOrientation::Coherent {
                spread,
                bandwidth_ratio,
            } => self.coherent(x, *spread, *bandwidth_ratio),
        }
    }

    /// The coherent direction's error bound at `x`, or that it is not determined (module
    /// doc): the reference sums the direction process's kernels with the CPU's f32 functions
    /// at the exact offsets `w = x/r_f − ⌊x/r_f⌋` (f64), each term within `ln 20·Δd² +
    /// EXP_REL_ERROR + COS_ABS_ERROR + 4u` per component of the export's, `Δd²` from the
    /// offsets' error `δw` (the position error, the split's 16 ulp of `r_f`, the sum and the
    /// scaling: `(dx + 32u·r_f + u·(r_f + reach))/r_f + 3u`, and the CPU's rounding of its
    /// offset to f32, `u`): `2·1.1·√2·δw + 2δw² + 6u`; both sums round within
    /// `SUMMATION_ROUNDINGS·u` per term.
    fn coherent(&self, x: [f64; 2], spread: f32, ratio: f32) -> (f64, bool) {
        let m = self.m;
        let rf = self.side / f64::from(ratio);
        let reach = 2.0 * self.side + 2.0;
        let dw = (self.dx + 32.0 * U * rf + U * (rf + reach)) / rf + 4.0 * U;
        let dd2 = 2.0 * 1.1 * std::f64::consts::SQRT_2 * dw + 2.0 * dw * dw + 6.0 * U;
        let spread_turns = (f64::from(spread) / TAU) as f32;
        let p = [x[0] / rf, x[1] / rf];
        let cell = [p[0].floor(), p[1].floor()];
        let u = [p[0] - cell[0], p[1] - cell[1]];
        let (mut sum, mut err, mut terms) = ([0.0f64; 2], 0.0f64, 0.0f64);
        for sy in -1..=1 {
            for sx in -1..=1 {
                let c = [cell[0] as i32 + sx, cell[1] as i32 + sy];
                let mut prng = Prng::new(cell_hash(c[0], c[1], DIRECTION_LAYER, m.seed));
                for _ in 0..count(&mut prng, self.threshold, self.cap) {
                    let o = [f64::from(prng.next_f32()), f64::from(prng.next_f32())];
                    let t = (2.0 * prng.next_f32() - 1.0) * spread_turns;
                    let d = [u[0] - f64::from(sx) - o[0], u[1] - f64::from(sy) - o[1]];
                    let d2 = d[0] * d[0] + d[1] * d[1];
                    // A kernel whose support edge is within the error may be in one sum
                    // only: the sum jumps by at most its value there, PHASOR_TRUNCATION per
                    // component, a bounded change (not an undetermined direction).
                    let edge = if (d2 - 1.0).abs() <= dd2 {
                        PHASOR_TRUNCATION + EXP_REL_ERROR
                    } else {
                        0.0
                    };
                    err += edge;
                    if d2 < 1.0 {
                        let g = f64::from(exp_poly(NEG_LN_20 * d2 as f32));
                        sum[0] += g * f64::from(cos_turns(t));
                        sum[1] += g * f64::from(sin_turns(t));
                        err +=
                            -f64::from(NEG_LN_20) * dd2 + EXP_REL_ERROR + COS_ABS_ERROR + 4.0 * U;
                        terms += 1.0;
                    }
                }
            }
        }
        let ds = std::f64::consts::SQRT_2 * (err + 2.0 * SUMMATION_ROUNDINGS * U * terms);
        let norm = sum[0].hypot(sum[1]);
        if norm <= 2.0 * ds {
            return (0.0, true);
        }
        (2.0 * ds / norm + 8.0 * U, false)
    }
}

/// The grey level's central differences `(g_x, g_y)` at `x` (one sample apart, the CPU's
/// `gradient_angle`) and the bound on `|Δ∇|` of the export's. The export interpolates the
/// samples' own central differences, rounded once from f64 (`phasor_export_differences`):
/// their interpolant's slope is at most twice the grey level's, and with values in [−1, 1] it
/// rounds as a grey level does, so each component is within twice [`grey_error`]'s slope term
/// plus its roundings, and the table's rounding (u): below `2·grey_error + u`.
fn gradient(image: &Field, x: [f64; 2], dx: f64, reach: f64) -> (f64, f64, f64) {
    let Field::Image {
        width,
        height,
        grey,
        pixel_size,
        ..
    } = image
    else {
        return (0.0, 0.0, f64::INFINITY);
    };
    let unit = Field::Image {
        width: *width,
        height: *height,
        grey: grey.clone(),
        pixel_size: *pixel_size,
        min: 0.0,
        max: 1.0,
    };
    let h = f64::from(*pixel_size);
    let g = |x: f64, y: f64| unit.at(x, y, 0.0);
    let gx = g(x[0] + h, x[1]) - g(x[0] - h, x[1]);
    let gy = g(x[0], x[1] + h) - g(x[0], x[1] - h);
    let e = grey_error(image, dx, reach);
    (gx, gy, std::f64::consts::SQRT_2 * (2.0 * e + U))
}

/// The largest `|value|` of a profile (sine, triangle and sawtooth within [−1, 1], a square
/// within [0, 1], samples their largest, harmonics the sum of their weights).
fn profile_peak(p: &Profile) -> f64 {
    match p {
        Profile::Sine | Profile::Triangle | Profile::Sawtooth | Profile::Square { .. } => 1.0,
        Profile::Samples { values } => values
            .iter()
            .map(|v| f64::from(*v).abs())
            .fold(0.0, f64::max),
        Profile::Harmonics { terms } => terms.iter().map(|h| f64::from(h.weight).abs()).sum(),
        Profile::Blend { a, b, .. } => profile_peak(a).max(profile_peak(b)),
    }
}

/// Per pixel of `window`: the edge and ambiguous pixels, the complex bound's and the
/// output's additions (module doc), for a 2D phasor model whose export's positions are within
/// `delta` cell units (`phasor_delta`) and whose impulse positions within `dx` pixels
/// ([`position_error`]); `eta` bounds either evaluator's `|d|²` error (`phasor_edge_mask`'s).
pub(super) fn field_bounds(m: &PhasorNoise, window: &Window, dx: f64, eta: f64) -> FieldBounds {
    let kernels = PhasorKernels::new(m);
    let side = kernels.side();
    let lambda = m.impulses_per_cell();
    let process = Process {
        m,
        side,
        threshold: (-lambda).exp() as f32,
        cap: (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32,
        dx,
        kernels,
    };
    let slack_of = |x: [f64; 2]| match &m.profile {
        Profile::Blend { a, b, weight } => {
            // (1 − w)·A + w·B: w's error times |A| + |B|.
            f64::from(m.amplitude).abs()
                * field_error(weight, x, 0.0, 1.0)
                * (profile_peak(a) + profile_peak(b))
        }
        _ => 0.0,
    };
    fn square(p: &Profile) -> Option<&Field> {
        match p {
            Profile::Square { duty } if duty.range().0 != duty.range().1 => Some(duty),
            _ => None,
        }
    }
    let duty_fields: Vec<&Field> = {
        match &m.profile {
            Profile::Blend { a, b, .. } => [square(a), square(b)].into_iter().flatten().collect(),
            other => square(other).into_iter().collect(),
        }
    };
    // The duty at the pixel: the field within its error (the pixel's position is exact), the
    // clamp to [0, 1] (no larger), the CPU's rounding to f32 (u).
    let duties_of = |x: [f64; 2]| -> Vec<(f64, f64)> {
        duty_fields
            .iter()
            .map(|f| {
                (
                    f.at(x[0], x[1], 0.0).clamp(0.0, 1.0),
                    field_error(f, x, 0.0, 1.0) + U,
                )
            })
            .collect()
    };
    let mut cells: std::collections::HashMap<[i32; 2], Cell> = std::collections::HashMap::new();
    let n = window.width * window.height;
    let mut out = FieldBounds {
        edge: Vec::with_capacity(n),
        ambiguous: Vec::with_capacity(n),
        extra: Vec::with_capacity(n),
        slack: Vec::with_capacity(n),
        duties: Vec::with_capacity(n),
    };
    let ln20 = -f64::from(NEG_LN_20);
    for j in 0..window.height {
        for i in 0..window.width {
            let (x, y) = (window.x(i), window.y(j));
            let (px, py) = (x / side, y / side);
            let (cx, cy) = (px.floor(), py.floor());
            let (ux, uy) = (px - cx, py - cy);
            let (mut edge, mut ambiguous, mut extra) = (false, false, 0.0);
            for sy in -1..=1 {
                for sx in -1..=1 {
                    let c = [cx as i32 + sx, cy as i32 + sy];
                    let cell = cells.entry(c).or_insert_with(|| process.draw(c));
                    ambiguous |= cell.ambiguous;
                    for imp in &cell.impulses {
                        let d = [ux - f64::from(sx) - imp.o[0], uy - f64::from(sy) - imp.o[1]];
                        let r2 = d[0] * d[0] + d[1] * d[1];
                        let d2 = r2 * imp.sharp;
                        // s·|d|² moves by s·η and Δs·|d|² (|d|² ≤ 1.1 near the edge, s ≥ 1).
                        if (d2 - 1.0).abs() <= imp.sharp * eta + imp.dsharp * 1.1 {
                            edge = true;
                        } else if d2 < 1.0 {
                            if imp.ambiguous {
                                ambiguous = true;
                            }
                            extra += ln20 * imp.dsharp * r2 + TAU * imp.df * r2.sqrt();
                        }
                    }
                }
            }
            out.edge.push(edge);
            out.ambiguous.push(ambiguous && !edge);
            out.extra.push(extra);
            out.slack.push(slack_of([x, y]));
            out.duties.push(duties_of([x, y]));
        }
    }
    out
}
