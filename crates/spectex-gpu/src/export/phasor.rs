//! Phasor noise's export (`shaders/export/phasor.wgsl`): the compute shader's uniform and
//! profile data, and the constants and field functions the glue draws kernels with in the
//! shader (the compute path's host draws them per tile instead).
//!
//! What the host derives from constant fields becomes a constant. A field that varies
//! (bandwidth, frequency, angle, duty cycle, blend weight; a `gradient` orientation's image;
//! a `coherent` orientation's direction process) is evaluated in the shader, in f32, where the
//! CPU evaluates it in f64: a constant, a linear ramp `value + g·n + g·r` from the integer
//! part `n` and a small offset `r`, or an image whose grey samples follow the profile data
//! and whose texel is located with the `(cell, offset)` split on the lattice of the image's
//! repeat (`export/split.wgsl`), so it is as precise at 10⁷ pixels as at the origin. Some uses
//! are discontinuous (thinning compares a uniform with `(b/b_max)²`) or ill-conditioned
//! (`atan2` of the gradient, normalising a sum of directions): the export test judges those
//! pixels as ambiguous where the CPU's value lies within the f32 evaluation's error of the
//! discontinuity, and the rest within a derived bound. A 3D model with a varying field is
//! refused ([`GpuError::Unsupported`] naming the feature): its fields' z and the 3D coherent
//! cap are not exported.

use std::fmt::Write as _;

use spectex_model::math::{cos_turns, sin_turns};
use spectex_model::phasor_kernels::DIRECTION_LAYER;
use spectex_model::{Field, ModelKind, PhasorNoise, PhasorOrientation, Profile};

use super::{ExportKind, ExportNode, ExportParts, float};
use crate::GpuError;
use crate::kernel::Table;

/// The unit direction at `angle` radians as `PhasorKernels` rounds it (`planar`).
fn planar(angle: f64) -> [f32; 3] {
    let t = (angle / std::f64::consts::TAU).rem_euclid(1.0) as f32;
    [cos_turns(t), sin_turns(t), 0.0]
}

/// Whether a field varies over the plane (its range is more than one value).
fn varies(field: &Field) -> bool {
    let (lo, hi) = field.range();
    lo != hi
}

/// The WGSL function `phasor_export_<name>(n, r)`: `field` at the pixel position `n + r`
/// (header of `export/phasor.wgsl`), an image's grey samples appended to `data` and its
/// repeat's lattices to `lattices`. With `grey_only`, an image's grey level (unmapped) at
/// `n + r` moved by `shift` samples (`phasor_export_steer`). An image field reads `n`'s
/// remainders on its repeat's lattices from the private `phasor_export_rem<l>_at` that
/// [`locate_fields`] declares and sets once per pixel.
fn field_function(
    name: &str,
    field: &Field,
    data: &mut Vec<f32>,
    lattices: &mut Vec<f64>,
    grey_only: bool,
) -> String {
    let signature = if grey_only {
        format!("fn phasor_export_{name}(n: vec2<i32>, r: vec2<f32>, shift: vec2<f32>) -> f32")
    } else {
        format!("fn phasor_export_{name}(n: vec2<i32>, r: vec2<f32>) -> f32")
    };
    let body = match field {
        Field::Constant { value } => format!("return {};", float(*value)),
        Field::Linear { value, gradient } => {
            let (gx, gy) = (float(gradient[0]), float(gradient[1]));
            format!(
                "return (({} + {gx} * f32(n.x)) + {gx} * r.x) + ({gy} * f32(n.y) + {gy} * r.y);",
                float(*value)
            )
        }
        Field::Image {
            width,
            height,
            grey,
            pixel_size,
            min,
            max,
        } => {
            let start = data.len();
            data.extend(grey);
            let size = f64::from(*pixel_size);
            let lx = lattices.len();
            lattices.push(*width as f64 * size);
            lattices.push(*height as f64 * size);
            let shift = if grey_only { " + shift.x" } else { "" };
            let shift_y = if grey_only { " + shift.y" } else { "" };
            // `n`'s remainders on the repeat's lattices: the pixel's, split once per pixel by
            // `phasor_export_locate_fields` (every caller passes the pixel's `n`).
            let sample = format!(
                "let x = phasor_export_rem{lx}_at + r.x;\n    \
                 let y = phasor_export_rem{}_at + r.y;\n    \
                 let g = phasor_export_bilinear({start}u, {width}i, {height}i, \
                 (x * {} - 0.5f){shift}, (y * {} - 0.5f){shift_y});",
                lx + 1,
                float((1.0 / size) as f32),
                float((1.0 / size) as f32),
            );
            if grey_only {
                format!("{sample}\n    return g;")
            } else {
                let span = (f64::from(*max) - f64::from(*min)) as f32;
                format!(
                    "{sample}\n    return {} + g * {};",
                    float(*min),
                    float(span)
                )
            }
        }
    };
    format!("{signature} {{\n    {body}\n}}\n")
}

/// The declarations of `phasor_export_rem<l>_at` for the image fields' repeat lattices (from
/// lattice 2 on: every lattice after the kernel and direction grids), and
/// `phasor_export_locate_fields(n)`, which `phasor_sample_cell` calls first: it splits the
/// pixel's integer position on each of them once, where the fields, read per impulse and per
/// steering sample, would otherwise split the same `n` every time (a 32-step table loop each).
fn locate_fields(lattices: usize) -> String {
    let mut out = String::new();
    let mut body = String::new();
    for l in 2..lattices {
        let axis = if l % 2 == 0 { "x" } else { "y" };
        let _ = writeln!(
            out,
            "/// The pixel's `n.{axis}` split on lattice {l}: its remainder (set per pixel).\n\
             var<private> phasor_export_rem{l}_at: f32;"
        );
        let _ = write!(
            body,
            "\n    phasor_export_rem{l}_at = export_split(n.{axis}, {l}u).rem;"
        );
    }
    let _ = writeln!(
        out,
        "/// Splits the pixel's integer position `n` on the image fields' lattices, once per pixel.\n\
         fn phasor_export_locate_fields(n: vec2<i32>) {{{body}\n}}"
    );
    out
}

impl ExportKind for PhasorNoise {
    const GLUE: &'static str = include_str!("../../../../shaders/export/phasor.wgsl");

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, mut profile) = crate::phasor::pack(self, z, None)?;
        let side = self.kernel_radius();
        let lambda = self.impulses_per_cell();
        let three_d = self.dimensions == 3;
        let graded = varies(&self.bandwidth);
        let varying_f = varies(&self.frequency);
        let duty = |p: &Profile| match p {
            Profile::Square { duty } => Some(duty.clone()),
            _ => None,
        };
        let (duty_a, duty_b, weight) = match &self.profile {
            Profile::Blend { a, b, weight } => (duty(a), duty(b), Some(weight.clone())),
            other => (duty(other), None, None),
        };
        let varying_angle =
            matches!(&self.orientation, PhasorOrientation::Aligned { angle } if varies(angle));
        let steered = matches!(
            self.orientation,
            PhasorOrientation::Gradient { .. } | PhasorOrientation::Coherent { .. }
        );
        if three_d && (graded || varying_f || varying_angle || steered || kernel.per_pixel) {
            return Err(GpuError::Unsupported {
                kind: PhasorNoise::NAME,
                feature: "WGSL export of a 3D model with a varying field or a gradient or \
                          coherent orientation (spectex export evaluates 2D fields)"
                    .into(),
            });
        }
        // Lattice 0: the kernel grid; 1: the coherent direction grid (or a copy of 0); then
        // the image fields' repeats.
        let mut lattices = vec![side];
        // The directions as `PhasorKernels::new` and `direction` make them.
        let mut coherent = (1.0f32, 1u32, 0.0f32, 1.0f32, side);
        let mut offset_turns = 0.0f32;
        let (mode, a, b) = match &self.orientation {
            PhasorOrientation::Aligned { angle } if !varies(angle) => {
                let a = planar(angle.range().0);
                (0u32, a, a)
            }
            PhasorOrientation::Aligned { .. } => (3, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            PhasorOrientation::TwoLobes { angle_a, angle_b } => {
                let turn = |a: f32| (f64::from(a) / std::f64::consts::TAU) as f32;
                let (ta, tb) = (turn(*angle_a), turn(*angle_b));
                let a = [cos_turns(ta), sin_turns(ta), 0.0];
                let mut b = [cos_turns(tb), sin_turns(tb), 0.0];
                if a[0] * b[0] + a[1] * b[1] < 0.0 {
                    b = [-b[0], -b[1], 0.0];
                }
                (1, a, b)
            }
            PhasorOrientation::Isotropic => (2, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            PhasorOrientation::Gradient { offset, .. } => {
                offset_turns = (f64::from(*offset) / std::f64::consts::TAU) as f32;
                (4, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            }
            PhasorOrientation::Coherent {
                spread,
                bandwidth_ratio,
            } => {
                // `PhasorKernels::new`'s direction grid: side r/ratio, the same density.
                let spread_turns = (f64::from(*spread) / std::f64::consts::TAU) as f32;
                coherent = (
                    (-lambda).exp() as f32,
                    (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32,
                    spread_turns,
                    cos_turns(spread_turns),
                    side / f64::from(*bandwidth_ratio),
                );
                (5, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0])
            }
        };
        lattices.push(coherent.4);
        let mut functions = String::new();
        let constant = Field::constant(0.0);
        for (name, field) in [
            ("bandwidth", &self.bandwidth),
            ("frequency_field", &self.frequency),
            (
                "angle",
                match &self.orientation {
                    PhasorOrientation::Aligned { angle } => angle,
                    _ => &constant,
                },
            ),
            ("duty_a", duty_a.as_ref().unwrap_or(&constant)),
            ("duty_b", duty_b.as_ref().unwrap_or(&constant)),
            ("weight", weight.as_ref().unwrap_or(&constant)),
        ] {
            // A constant field's function is never called (the glue reads the constants
            // then): it returns the value all the same.
            functions.push_str(&field_function(
                name,
                field,
                &mut profile,
                &mut lattices,
                false,
            ));
        }
        let steer = match &self.orientation {
            PhasorOrientation::Gradient { image, .. } => image,
            _ => &constant,
        };
        functions.push_str(&field_function(
            "steer",
            steer,
            &mut profile,
            &mut lattices,
            true,
        ));
        let (b_min, b_max) = self.bandwidth_range();
        // `PhasorKernels`' grid and frequency magnitude (`F.clamp(0, ½)·r` rounded once).
        let threshold = (-lambda).exp() as f32;
        let cap = (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32;
        let frequency = self.frequency.range().0;
        let fr = (frequency.clamp(0.0, 0.5) * side) as f32;
        let vec3 = |d: [f32; 3]| {
            format!(
                "vec3<f32>({}, {}, {})",
                float(fr * d[0]),
                float(fr * d[1]),
                float(fr * d[2])
            )
        };
        let unit = |d: [f32; 3]| {
            format!(
                "vec3<f32>({}, {}, {})",
                float(d[0]),
                float(d[1]),
                float(d[2])
            )
        };
        functions.push_str(&locate_fields(lattices.len()));
        let constants = format!(
            "const phasor_export_seed: u32 = {}u;\n\
             const phasor_export_threshold: f32 = {};\n\
             const phasor_export_cap: u32 = {cap}u;\n\
             const phasor_export_mode: u32 = {mode}u;\n\
             const phasor_export_fr: f32 = {};\n\
             const phasor_export_f_a: vec3<f32> = {};\n\
             const phasor_export_f_b: vec3<f32> = {};\n\
             const phasor_export_u_a: vec3<f32> = {};\n\
             const phasor_export_u_b: vec3<f32> = {};\n\
             const phasor_export_graded: u32 = {}u;\n\
             const phasor_export_b_min: f32 = {};\n\
             const phasor_export_b_max: f32 = {};\n\
             const phasor_export_varying_f: u32 = {}u;\n\
             const phasor_export_side: f32 = {};\n\
             const phasor_export_offset_turns: f32 = {};\n\
             const phasor_export_dir_threshold: f32 = {};\n\
             const phasor_export_dir_cap: u32 = {}u;\n\
             const phasor_export_spread_turns: f32 = {};\n\
             const phasor_export_cap_cos: f32 = {};\n\
             const phasor_export_per_pixel: u32 = {}u;\n\
             {functions}",
            self.seed,
            float(threshold),
            float(fr),
            vec3(a),
            vec3(b),
            unit(a),
            unit(b),
            u32::from(graded),
            float(b_min as f32),
            float(b_max as f32),
            u32::from(varying_f),
            float(side as f32),
            float(offset_turns),
            float(coherent.0),
            coherent.1,
            float(coherent.2),
            float(coherent.3),
            u32::from(kernel.per_pixel),
        );
        debug_assert_eq!(DIRECTION_LAYER, 1, "export/phasor.wgsl hashes layer 1");
        // The kernel grid is the export's lattice 0 (export/phasor.wgsl).
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("phasor profile", &profile)],
            lattices,
            "phasor",
        )?
        .with_constants(constants))
    }
}
