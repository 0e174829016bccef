//! Phasor noise's export (`shaders/export/phasor.wgsl`): the compute shader's uniform and
//! profile data, and the constants the glue draws kernels with in the shader (the compute
//! path's host draws them per tile instead).
//!
//! What the host derives from the model's fields becomes a constant, so the export supports
//! models whose fields are constant (the default): a field that varies would be evaluated in
//! the shader in f32 where the host evaluates it in f64, and three of those uses are not
//! continuous in the field's value, so no tolerance bounds them — a varying bandwidth thins
//! impulses by comparing a uniform with `(b/b_max)^dims` (an impulse present on the CPU may be
//! absent in the export), a `gradient` orientation takes `atan2` of the image's central
//! differences and a `coherent` one normalises a sum of directions (both ill-conditioned where
//! the gradient or the sum vanishes). Those, a varying frequency or angle, and per-pixel duty
//! cycles and blend weights give [`GpuError::Unsupported`] naming the feature.

use spectex_model::math::{cos_turns, sin_turns};
use spectex_model::{Field, ModelKind, PhasorNoise, PhasorOrientation};

use super::{ExportKind, ExportNode, ExportParts, float};
use crate::GpuError;
use crate::kernel::Table;

/// The value of a field that is the same everywhere (its range is one value), else
/// [`GpuError::Unsupported`] naming `what`.
fn constant(field: &Field, what: &str) -> Result<f64, GpuError> {
    let (lo, hi) = field.range();
    if lo == hi {
        Ok(lo)
    } else {
        Err(GpuError::Unsupported {
            kind: PhasorNoise::NAME,
            feature: format!(
                "WGSL export of a varying {what} (spectex export supports constant fields)"
            ),
        })
    }
}

/// The unit direction at `angle` radians as `PhasorKernels` rounds it (`planar`).
fn planar(angle: f64) -> [f32; 3] {
    let t = (angle / std::f64::consts::TAU).rem_euclid(1.0) as f32;
    [cos_turns(t), sin_turns(t), 0.0]
}

impl ExportKind for PhasorNoise {
    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        constant(&self.bandwidth, "bandwidth (impulse thinning)")?;
        let frequency = constant(&self.frequency, "frequency")?;
        let (kernel, profile) = crate::phasor::pack(self, z, None)?;
        if kernel.per_pixel {
            return Err(GpuError::Unsupported {
                kind: PhasorNoise::NAME,
                feature: "WGSL export of a varying duty cycle or blend weight (spectex export \
                          supports constant fields)"
                    .into(),
            });
        }
        // The directions as `PhasorKernels::new` and `direction` make them.
        let (mode, a, b) = match &self.orientation {
            PhasorOrientation::Aligned { angle } => {
                let a = planar(constant(angle, "angle")?);
                (0u32, a, a)
            }
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
            PhasorOrientation::Gradient { .. } | PhasorOrientation::Coherent { .. } => {
                return Err(GpuError::Unsupported {
                    kind: PhasorNoise::NAME,
                    feature: "WGSL export of the gradient and coherent orientations (their \
                              directions are ill-conditioned functions of f64 field values)"
                        .into(),
                });
            }
        };
        let side = self.kernel_radius();
        let lambda = self.impulses_per_cell();
        // `PhasorKernels`' grid and frequency magnitude (`F.clamp(0, ½)·r` rounded once).
        let threshold = (-lambda).exp() as f32;
        let cap = (4.0 * lambda + 32.0).floor().clamp(1.0, 4096.0) as u32;
        let fr = (frequency.clamp(0.0, 0.5) * side) as f32;
        let vec3 = |d: [f32; 3]| {
            format!(
                "vec3<f32>({}, {}, {})",
                float(fr * d[0]),
                float(fr * d[1]),
                float(fr * d[2])
            )
        };
        let constants = format!(
            "const phasor_export_seed: u32 = {}u;\n\
             const phasor_export_threshold: f32 = {};\n\
             const phasor_export_cap: u32 = {cap}u;\n\
             const phasor_export_mode: u32 = {mode}u;\n\
             const phasor_export_fr: f32 = {};\n\
             const phasor_export_f_a: vec3<f32> = {};\n\
             const phasor_export_f_b: vec3<f32> = {};\n",
            self.seed,
            float(threshold),
            float(fr),
            vec3(a),
            vec3(b),
        );
        // The kernel grid is the export's lattice 0 (export/phasor.wgsl).
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("phasor profile", &profile)],
            vec![side],
            "phasor",
        )?
        .with_constants(constants))
    }
}
