//! Domain warping on the CPU ([`spectex_model::warp`]): the displacement models are rendered on
//! the window's rows like any model, then the base is evaluated pixel by pixel at the displaced
//! position `window position (f64) + displacement (f32)`, summed in f64.
//!
//! A minified render filters the displacement fields (rendered on the window) but not the base,
//! which is point-sampled at the displaced positions.
//!
//! The base is evaluated at the displaced positions of a whole band of rows at once
//! ([`Evaluator::eval_points`]), with the same bits as a one-pixel window at each
//! ([`Evaluator::eval_point`]): every evaluator gives a pixel the same bits whatever window holds
//! it (tiles are invisible), so this works for every model kind — nested warps included — and a
//! pixel's value depends only on its own position: any tiling and thread count give the same
//! bits. Kinds whose pixels are independent (classic noises, warps) evaluate the points in
//! their lanes; the others go point by point, drawing their random cells once per pixel, which
//! is the price of arbitrary positions. [`WarpEvaluator::eval_rows_reference`] keeps the point
//! by point definition.

use spectex_model::{Model, Period, Warp, Window};

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
    /// Prepares the three sub-models of a validated warp on the plane `z`, each periodic with
    /// `period` when given (then the warp `base(p + d(p))` is periodic: `d` is, and the base
    /// evaluated at positions one period apart is too).
    pub(crate) fn new(model: &Warp, z: f64, period: Option<Period>) -> Result<Self, CpuError> {
        Ok(Self {
            model: model.clone(),
            reach_model: Model::Warp(model.clone()),
            base: Evaluator::with_period(&model.base, z, period)?,
            x: Evaluator::with_period(&model.x, z, period)?,
            y: Evaluator::with_period(&model.y, z, period)?,
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

    /// The pixel displacement `(D(x(p)), D(y(p)))` of every pixel of rows `first..first + rows`,
    /// through the displacement models' fast paths or (`reference`) their reference paths.
    fn displacements(
        &self,
        window: &Window,
        first: usize,
        rows: usize,
        reference: bool,
    ) -> [Vec<f32>; 2] {
        let n = rows * window.width;
        let mut dx = vec![0.0f32; n];
        let mut dy = vec![0.0f32; n];
        if reference {
            self.x.eval_rows_reference(window, first, &mut dx);
            self.y.eval_rows_reference(window, first, &mut dy);
        } else {
            self.x.eval_rows(window, first, &mut dx);
            self.y.eval_rows(window, first, &mut dy);
        }
        for d in dx.iter_mut().chain(dy.iter_mut()) {
            *d = self.model.displacement(*d);
        }
        [dx, dy]
    }

    /// The displaced positions of rows `first..` of `window` (`rows · width` of them).
    fn displaced(&self, window: &Window, first: usize, rows: usize) -> Vec<[f64; 2]> {
        let width = window.width;
        let [dx, dy] = self.displacements(window, first, rows, false);
        let mut points = Vec::with_capacity(rows * width);
        for r in 0..rows {
            let y = window.y(first + r);
            for i in 0..width {
                let k = r * width + i;
                points.push([window.x(i) + f64::from(dx[k]), y + f64::from(dy[k])]);
            }
        }
        points
    }

    /// Evaluates rows `first..` of `window` into `out` (whole rows of `width · channels` values):
    /// the base at every displaced position of the band at once.
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        let nc = self.output_channels();
        if width == 0 {
            return;
        }
        let rows = out.len() / (width * nc);
        let points = self.displaced(window, first, rows);
        self.base.eval_points(&points, out);
    }

    /// [`eval_rows`](Self::eval_rows) by the definition: the base at each displaced position
    /// through its own one-pixel window, every sub-model by its reference path.
    #[doc(hidden)]
    pub fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        let nc = self.output_channels();
        if width == 0 {
            return;
        }
        let rows = out.len() / (width * nc);
        let [dx, dy] = self.displacements(window, first, rows, true);
        for r in 0..rows {
            let y = window.y(first + r);
            for i in 0..width {
                let k = r * width + i;
                let p = [window.x(i) + f64::from(dx[k]), y + f64::from(dy[k])];
                self.base.eval_rows_reference(
                    &crate::point_window(p),
                    0,
                    &mut out[k * nc..(k + 1) * nc],
                );
            }
        }
    }

    /// The warp at each of `points`: the displacement models at the points, then the base at
    /// the displaced positions, all in batches; the same bits as one-pixel windows.
    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let n = points.len();
        let mut dx = vec![0.0f32; n];
        let mut dy = vec![0.0f32; n];
        self.x.eval_points(points, &mut dx);
        self.y.eval_points(points, &mut dy);
        let displaced: Vec<[f64; 2]> = points
            .iter()
            .zip(dx.iter().zip(&dy))
            .map(|(p, (&dx, &dy))| {
                // The one-pixel window's pixel position (`crate::point_window`), displaced.
                let w = crate::point_window(*p);
                [
                    w.x(0) + f64::from(self.model.displacement(dx)),
                    w.y(0) + f64::from(self.model.displacement(dy)),
                ]
            })
            .collect();
        self.base.eval_points(&displaced, out);
    }
}

impl crate::CpuKind for Warp {
    /// The bench case: the `spectex noise warp` defaults.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Built(Model::Warp(
            Warp::builder()
                .build()
                .expect("the builder's defaults are valid"),
        ))
    }

    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn crate::RowKernel>, CpuError> {
        Ok(Box::new(WarpEvaluator::new(self, z, None)?))
    }

    fn cpu_kernel_periodic(
        &self,
        z: f64,
        period: Period,
    ) -> Result<Box<dyn crate::RowKernel>, CpuError> {
        Ok(Box::new(WarpEvaluator::new(self, z, Some(period))?))
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

    fn eval_rows_reference(&self, window: &Window, first: usize, out: &mut [f32]) {
        WarpEvaluator::eval_rows_reference(self, window, first, out);
    }

    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        WarpEvaluator::eval_points(self, points, out);
    }

    fn check_window(&self, window: &Window) -> Result<(), CpuError> {
        WarpEvaluator::check_window(self, window)
    }
}
