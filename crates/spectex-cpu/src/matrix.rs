//! Matrix transformation on the CPU ([`spectex_model::matrix`]): `A = (M⁻¹)^k mod N` is
//! computed once; a pixel takes its integer cell `q` (side 1), reduces it modulo `N` and reads
//! the source at `A·q mod N`, all in integers, so any window, tiling and thread gives the same
//! bits.

use spectex_model::Window;
use spectex_model::grid::locate_cell;
use spectex_model::matrix::MatrixTransform;

use crate::{CpuError, CpuKind, RowKernel};

/// A matrix transformation prepared for evaluation.
pub struct MatrixEvaluator {
    model: MatrixTransform,
    /// `(M⁻¹)^k mod N`.
    map: [[u32; 2]; 2],
}

impl MatrixEvaluator {
    /// Prepares a validated model (`None` if `M` is not invertible modulo `N`, which
    /// validation refuses).
    #[must_use]
    pub fn new(model: &MatrixTransform) -> Option<Self> {
        Some(Self {
            model: model.clone(),
            map: model.inverse_power()?,
        })
    }

    /// The texel of the cell `c` (per axis `⌊p⌋`) reduced modulo `N`: `q mod N`.
    fn wrap(&self, c: i32) -> u32 {
        c.rem_euclid(self.model.size as i32) as u32
    }

    /// The value at the wrapped pixel `q`: the source at `A·q mod N`.
    #[must_use]
    pub fn value(&self, q: [u32; 2]) -> f32 {
        let n = self.model.size;
        let a = &self.map;
        let s = [
            (a[0][0] * q[0] + a[0][1] * q[1]) % n,
            (a[1][0] * q[0] + a[1][1] * q[1]) % n,
        ];
        self.model.mean + self.model.amplitude * self.model.source_value(s)
    }
}

impl CpuKind for MatrixTransform {
    /// The bench case: `testdata/models/matrix-cat-rings.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("matrix-cat-rings.json")
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        match MatrixEvaluator::new(self) {
            Some(e) => Ok(Box::new(e)),
            None => Err(CpuError::Model(self.validate().err().unwrap_or(
                spectex_model::ModelError::OutOfRange {
                    field: "matrix.matrix".into(),
                    value: 0.0,
                    range: "an invertible matrix modulo size",
                },
            ))),
        }
    }

    /// The transformation itself: it repeats every `N` pixels, so with every period it accepts
    /// (multiples of `N`, `check_period`), and `Evaluator::periodic` reduces the positions.
    fn cpu_kernel_periodic(
        &self,
        z: f64,
        period: spectex_model::Period,
    ) -> Result<Box<dyn RowKernel>, CpuError> {
        spectex_model::ModelKind::check_period(self, period)?;
        self.cpu_kernel(z)
    }
}

impl RowKernel for MatrixEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        1.0
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        // Outside the usable range (never for a validated window) a pixel reads texel 0.
        let columns: Vec<u32> = (0..width)
            .map(|i| locate_cell(window.x(i), 1.0).map_or(0, |c| self.wrap(c.0)))
            .collect();
        for (r, line) in out.chunks_exact_mut(width).enumerate() {
            let qy = locate_cell(window.y(first + r), 1.0).map_or(0, |c| self.wrap(c.0));
            for (v, &qx) in line.iter_mut().zip(&columns) {
                *v = self.value([qx, qy]);
            }
        }
    }
}
