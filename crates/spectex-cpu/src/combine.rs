//! Combinations on the CPU ([`spectex_model::combine`]): each band of rows renders every
//! operand's rows through its own kernel (fast paths included), then applies
//! [`CombineOp::apply`](spectex_model::combine::CombineOp::apply) per pixel and channel.

use spectex_model::combine::Combine;
use spectex_model::{Model, ModelKind, Period, Window};

use crate::{CpuError, CpuKind, RowKernel, kind_kernel, kind_kernel_periodic};

/// A combination prepared for evaluation.
pub struct CombineEvaluator {
    model: Combine,
    operands: Vec<Box<dyn RowKernel>>,
    channels: usize,
    /// The whole model, for the window check of warps inside the operands.
    whole: Model,
}

impl CpuKind for Combine {
    /// The bench case: `testdata/models/combine-bark.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("combine-bark.json")
    }

    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn RowKernel>, CpuError> {
        let operands = self
            .operands
            .iter()
            .map(|m| kind_kernel(m, z))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(evaluator(self, operands))
    }

    /// Every operand's periodic kernel (each accepts `period`: the combination's
    /// `check_period`), combined pixel by pixel: a periodic function.
    fn cpu_kernel_periodic(&self, z: f64, period: Period) -> Result<Box<dyn RowKernel>, CpuError> {
        let operands = self
            .operands
            .iter()
            .map(|m| kind_kernel_periodic(m, z, period))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(evaluator(self, operands))
    }
}

/// The evaluator of `model` from its operands' kernels.
fn evaluator(model: &Combine, operands: Vec<Box<dyn RowKernel>>) -> Box<dyn RowKernel> {
    Box::new(CombineEvaluator {
        model: model.clone(),
        operands,
        channels: model.output_channels(),
        whole: Model::Combine(model.clone()),
    })
}

impl CombineEvaluator {
    /// Applies the operation to every pixel of the operands' values `values` (one buffer per
    /// operand, its channels interleaved) into `out`.
    fn combine(&self, values: &[Vec<f32>], out: &mut [f32]) {
        let widths: Vec<usize> = self.operands.iter().map(|k| k.output_channels()).collect();
        let mut pixel: Vec<&[f32]> = Vec::with_capacity(values.len());
        for (p, o) in out.chunks_exact_mut(self.channels).enumerate() {
            pixel.clear();
            pixel.extend(
                values
                    .iter()
                    .zip(&widths)
                    .map(|(v, &w)| &v[p * w..p * w + w]),
            );
            for (c, value) in o.iter_mut().enumerate() {
                *value = self.model.op.apply(&pixel, c);
            }
        }
    }

    fn eval(&self, window: &Window, first: usize, out: &mut [f32], reference: bool) {
        let pixels = out.len() / self.channels;
        let values: Vec<Vec<f32>> = self
            .operands
            .iter()
            .map(|k| {
                let mut v = vec![0.0f32; pixels * k.output_channels()];
                if reference {
                    k.eval_rows_reference(window, first, &mut v);
                } else {
                    k.eval_rows(window, first, &mut v);
                }
                v
            })
            .collect();
        self.combine(&values, out);
    }
}

impl RowKernel for CombineEvaluator {
    fn output_channels(&self) -> usize {
        self.channels
    }

    fn cost_per_pixel(&self) -> f64 {
        self.operands.iter().map(|k| k.cost_per_pixel()).sum()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval(window, first, out, false);
    }

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        self.eval(window, first, out, true);
    }

    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let values: Vec<Vec<f32>> = self
            .operands
            .iter()
            .map(|k| {
                let mut v = vec![0.0f32; points.len() * k.output_channels()];
                k.eval_points(points, &mut v);
                v
            })
            .collect();
        self.combine(&values, out);
    }

    fn check_window(&self, window: &Window) -> Result<(), CpuError> {
        spectex_model::warp::check_window(&self.whole, window)?;
        for k in &self.operands {
            k.check_window(window)?;
        }
        Ok(())
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::Evaluator;
    use spectex_model::combine::{CombineOp, RampStop};
    use spectex_model::{ClassicNoise, VoronoiNoise};

    fn render(m: &Model, w: &Window) -> Vec<f32> {
        Evaluator::new(m).expect("valid").render(w).expect("window")
    }

    pub fn combinations_are_their_operation_of_the_operands_renders() {
        let a = Model::Classic(ClassicNoise::fbm().build().expect("valid"));
        let b = Model::Voronoi(VoronoiNoise {
            output: spectex_model::voronoi::VoronoiOutput::F1,
            ..VoronoiNoise::default()
        });
        let w = Window::new(33, 7).at([1.0e7, -12.5], 0.7);
        let (va, vb) = (render(&a, &w), render(&b, &w));
        let ops = [
            CombineOp::Add,
            CombineOp::Multiply,
            CombineOp::Min,
            CombineOp::Max,
            CombineOp::SinFold { gain: 2.0 },
        ];
        for op in ops {
            let operands = if op.arity().0 == 1 {
                vec![a.clone()]
            } else {
                vec![a.clone(), b.clone()]
            };
            let m = Model::Combine(Combine {
                op: op.clone(),
                operands,
            });
            let got = render(&m, &w);
            for (k, g) in got.iter().enumerate() {
                // Independent of CombineOp::apply: the operation written out per case.
                let want = match op {
                    CombineOp::Add => va[k] + vb[k],
                    CombineOp::Multiply => va[k] * vb[k],
                    CombineOp::Min => va[k].min(vb[k]),
                    CombineOp::Max => va[k].max(vb[k]),
                    _ => (std::f64::consts::TAU * 2.0 * f64::from(va[k])).sin() as f32,
                };
                assert!((g - want).abs() < 1e-5, "{op:?} pixel {k}: {g} vs {want}");
            }
        }
        let ramp = Model::Combine(Combine {
            op: CombineOp::Ramp {
                stops: vec![
                    RampStop {
                        at: -1.0,
                        colour: [0.0, 0.0, 1.0],
                    },
                    RampStop {
                        at: 1.0,
                        colour: [1.0, 0.0, 0.0],
                    },
                ],
            },
            operands: vec![a.clone()],
        });
        let rgb = render(&ramp, &w);
        for (k, &v) in va.iter().enumerate() {
            let t = ((v + 1.0) / 2.0).clamp(0.0, 1.0);
            assert!((rgb[3 * k] - t).abs() < 1e-6 && (rgb[3 * k + 2] - (1.0 - t)).abs() < 1e-6);
        }
    }
}
