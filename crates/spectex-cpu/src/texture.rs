//! Texture by example on the CPU: each channel's random-phase strata through the LRP evaluator,
//! the turbulence strata likewise (one single-stratum LRP noise per stratum and axis, so `|n_S|`
//! can be taken), then per pixel the placement taps and the structure of
//! [`spectex_model::texture`], and the colour basis. Output is interleaved: `channels` values per
//! pixel.
//!
//! A minified render (a window with a [`footprint`](Window::footprint)) filters the strata and
//! the turbulence through the LRP evaluator and the structure by
//! [`spectex_model::texture::Structure::eval_filtered`] (its cosines faded, its zero
//! frequencies from the mipmap of block means, LRP §6).

use spectex_model::grid::locate_cell;
use spectex_model::{LrpNoise, Period, TextureModel, Window};

use crate::lrp::LrpEvaluator;

/// A [`TextureModel`] prepared for evaluation.
pub struct TextureEvaluator {
    model: TextureModel,
    /// The strata of each channel (with its mean), `None` where a channel has no strata.
    strata: Vec<Option<LrpEvaluator>>,
    /// Turbulence strata per axis.
    turbulence: [Vec<LrpEvaluator>; 2],
    /// Each channel's mipmap of block means (empty without a structure).
    mipmaps: Vec<Vec<f32>>,
    /// Placement cells per period along x and y of a periodic model.
    cells: Option<[i64; 2]>,
}

impl TextureEvaluator {
    /// Prepares a validated model.
    #[must_use]
    pub fn new(model: &TextureModel) -> Self {
        Self::prepare(model, None)
    }

    /// Prepares a validated model that accepts `period` (a multiple of its `T`) made periodic:
    /// its strata and turbulence as periodic LRP noises, its placement cells wrapped.
    #[must_use]
    pub fn new_periodic(model: &TextureModel, period: Period) -> Self {
        Self::prepare(model, Some(period))
    }

    fn prepare(model: &TextureModel, period: Option<Period>) -> Self {
        let lrp = |noise: &LrpNoise| match period {
            None => LrpEvaluator::new(noise),
            Some(p) => LrpEvaluator::new_periodic(noise, p),
        };
        let strata = model
            .channels
            .iter()
            .map(|ch| {
                (!ch.strata.is_empty()).then(|| {
                    lrp(&LrpNoise {
                        seed: ch.seed,
                        mean: ch.mean,
                        strata: ch.strata.clone(),
                    })
                })
            })
            .collect();
        let turbulence = std::array::from_fn(|axis| {
            model.turbulence.as_ref().map_or_else(Vec::new, |t| {
                t.strata
                    .iter()
                    .enumerate()
                    .map(|(s, st)| {
                        lrp(&LrpNoise {
                            seed: t.seed(axis, s),
                            mean: 0.0,
                            strata: vec![st.clone()],
                        })
                    })
                    .collect()
            })
        });
        let mipmaps = model
            .channels
            .iter()
            .map(|ch| {
                ch.structure
                    .as_ref()
                    .map_or_else(Vec::new, spectex_model::texture::Structure::mean_mipmap)
            })
            .collect();
        Self {
            model: model.clone(),
            strata,
            turbulence,
            mipmaps,
            cells: period.map(|p| p.cells(model.placement_cell())),
        }
    }

    /// Values per pixel (1 or 3).
    #[must_use]
    pub fn output_channels(&self) -> usize {
        self.model.output_channels()
    }

    /// Special-function calls per pixel (see [`TextureModel::special_calls_per_pixel`]).
    #[must_use]
    pub fn calls_per_pixel(&self) -> usize {
        self.model.special_calls_per_pixel()
    }

    /// The model.
    #[must_use]
    pub fn model(&self) -> &TextureModel {
        &self.model
    }

    /// Evaluates rows `first..` of `window` into `out` (`rows · width · channels` values,
    /// interleaved).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let w = window.width;
        let nc = self.output_channels();
        let rows = out.len() / (w * nc);
        let n = rows * w;
        let mut strata: Vec<Vec<f32>> = Vec::with_capacity(nc);
        for (c, e) in self.strata.iter().enumerate() {
            let mut buf = vec![self.model.channels[c].mean; n];
            if let Some(e) = e {
                e.eval_rows(window, first, &mut buf);
            }
            strata.push(buf);
        }
        let mut disp = [vec![0.0f32; n], vec![0.0f32; n]];
        if let Some(t) = &self.model.turbulence {
            let mut tmp = vec![0.0f32; n];
            for (axis, evals) in self.turbulence.iter().enumerate() {
                let sum = &mut disp[axis];
                for e in evals {
                    e.eval_rows(window, first, &mut tmp);
                    for (s, v) in sum.iter_mut().zip(&tmp) {
                        *s += v.abs();
                    }
                }
                for s in sum.iter_mut() {
                    *s = t.displacement(*s);
                }
            }
        }
        let p = self.model.placement_cell();
        let xs: Vec<(i32, f32)> = (0..w)
            .map(|i| locate_cell(window.x(i), p).unwrap_or((0, 0.0)))
            .collect();
        let footprint = window.footprint().map(|s| s as f32);
        let mut v = [0.0f32; 3];
        for r in 0..rows {
            let (cy, sy) = locate_cell(window.y(first + r), p).unwrap_or((0, 0.0));
            for (i, &(cx, sx)) in xs.iter().enumerate() {
                let k = r * w + i;
                let taps =
                    self.model
                        .placement_in(cx, sx, cy, sy, [disp[0][k], disp[1][k]], self.cells);
                for c in 0..nc {
                    let structure = match footprint {
                        Some(s) => self
                            .model
                            .structure_at_filtered(c, &taps, s, &self.mipmaps[c]),
                        None => self.model.structure_at(c, &taps),
                    };
                    v[c] = strata[c][k] + structure;
                }
                for c in 0..nc {
                    out[k * nc + c] = self.model.colour_component(c, &v[..nc]);
                }
            }
        }
    }
}

impl crate::CpuKind for TextureModel {
    /// The bench case: `testdata/models/texture-synthetic-colour.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("texture-synthetic-colour.json")
    }

    fn cpu_kernel(&self, _z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(TextureEvaluator::new(self)))
    }

    fn cpu_kernel_periodic(
        &self,
        _z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(TextureEvaluator::new_periodic(self, period)))
    }
}

impl crate::RowKernel for TextureEvaluator {
    fn output_channels(&self) -> usize {
        TextureEvaluator::output_channels(self)
    }

    fn cost_per_pixel(&self) -> f64 {
        self.calls_per_pixel() as f64
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        TextureEvaluator::eval_rows(self, window, first, out);
    }
}
