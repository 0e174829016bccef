//! Domain warping on the CPU ([`spectex_model::warp`]): the displacement models are rendered on
//! the window's rows like any model, then the base is evaluated pixel by pixel at the displaced
//! position `window position (f64) + displacement (f32)`, summed in f64.
//!
//! A minified render filters the displacement fields (rendered on the window) but not the base,
//! which is point-sampled at the displaced positions.
//!
//! The base is evaluated at each displaced position through a one-pixel window
//! ([`Evaluator::eval_point`]): every evaluator gives a pixel the same bits whatever window holds
//! it (tiles are invisible), so this works for every model kind — nested warps included — and a
//! pixel's value depends only on its own position: any tiling and thread count give the same
//! bits. It draws the base's random cells once per pixel instead of once per row, which is the
//! price of arbitrary positions.

use spectex_model::{Model, Warp, Window};

use crate::{CpuError, Evaluator};

/// A warp prepared for evaluation.
pub struct WarpEvaluator {
    model: Warp,
    /// [`spectex_model::warp::reach`] of the whole model.
    reach_model: Model,
    base: Evaluator,
    x: Evaluator,
    y: Evaluator,
}

impl WarpEvaluator {
    /// Prepares the three sub-models of a validated warp on the plane `z`.
    pub(crate) fn new(model: &Warp, z: f64) -> Result<Self, CpuError> {
        Ok(Self {
            model: model.clone(),
            reach_model: Model::Warp(model.clone()),
            base: Evaluator::new_at_z(&model.base, z)?,
            x: Evaluator::new_at_z(&model.x, z)?,
            y: Evaluator::new_at_z(&model.y, z)?,
        })
    }

    /// Values per pixel: the base's.
    #[must_use]
    pub fn output_channels(&self) -> usize {
        self.base.output_channels()
    }

    /// Evaluations per pixel: the base's plus the two displacement models'.
    #[must_use]
    pub fn cost_per_pixel(&self) -> f64 {
        self.base.cost_per_pixel() + self.x.cost_per_pixel() + self.y.cost_per_pixel()
    }

    /// Checks that the displaced positions of `window` stay in range
    /// ([`spectex_model::warp::check_window`]).
    pub(crate) fn check_window(&self, window: &Window) -> Result<(), CpuError> {
        Ok(spectex_model::warp::check_window(
            &self.reach_model,
            window,
        )?)
    }

    /// The pixel displacement `(D(x(p)), D(y(p)))` of every pixel of rows `first..first + rows`.
    fn displacements(&self, window: &Window, first: usize, rows: usize) -> [Vec<f32>; 2] {
        let n = rows * window.width;
        let mut dx = vec![0.0f32; n];
        let mut dy = vec![0.0f32; n];
        self.x.eval_rows(window, first, &mut dx);
        self.y.eval_rows(window, first, &mut dy);
        for d in dx.iter_mut().chain(dy.iter_mut()) {
            *d = self.model.displacement(*d);
        }
        [dx, dy]
    }

    /// Evaluates rows `first..` of `window` into `out` (whole rows of `width · channels` values).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        let nc = self.output_channels();
        if width == 0 {
            return;
        }
        let rows = out.len() / (width * nc);
        let [dx, dy] = self.displacements(window, first, rows);
        for r in 0..rows {
            let y = window.y(first + r);
            for i in 0..width {
                let k = r * width + i;
                let p = [window.x(i) + f64::from(dx[k]), y + f64::from(dy[k])];
                self.base.eval_point(p, &mut out[k * nc..(k + 1) * nc]);
            }
        }
    }
}

impl crate::CpuKind for Warp {
    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn crate::RowKernel>, CpuError> {
        Ok(Box::new(WarpEvaluator::new(self, z)?))
    }
}

impl crate::RowKernel for WarpEvaluator {
    fn output_channels(&self) -> usize {
        WarpEvaluator::output_channels(self)
    }

    fn cost_per_pixel(&self) -> f64 {
        WarpEvaluator::cost_per_pixel(self)
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        WarpEvaluator::eval_rows(self, window, first, out);
    }

    fn check_window(&self, window: &Window) -> Result<(), CpuError> {
        WarpEvaluator::check_window(self, window)
    }
}
