//! Periodic renders: every position reduced modulo the period, exactly, before a kind's kernel
//! sees it (`spectex_model::period`), so positions one period apart give the same bits.
//!
//! The kind's own periodic kernel (`CpuKind::cpu_kernel_periodic`) is a periodic *function*
//! (its cells hashed modulo the period); [`PeriodicKernel`] makes its evaluation exact. Two paths
//! give the same bits, since a kernel's value depends on the position only (tiles are invisible,
//! and `RowKernel::eval_points` has the bits of one-pixel windows):
//!
//! - **whole sub-windows** when every position of the window is an integer (scale 1, integer
//!   offset): a row's pixels between two wraps are the sub-window at `offset − k·period`, whose
//!   positions are exactly the reduced ones, so the kind runs its fast row path on them;
//! - **point by point** otherwise: each position reduced, then the kind's `eval_points`, or a
//!   one-pixel window carrying the render's footprint when it is minified.

use spectex_model::{Filter, Period, Window};

use crate::{CpuError, RowKernel, point_window};

/// A kind's periodic kernel evaluated at positions reduced modulo its period.
pub(crate) struct PeriodicKernel {
    /// The kind's kernel, a periodic function of the position.
    pub(crate) inner: Box<dyn RowKernel>,
    /// The period.
    pub(crate) period: Period,
}

/// Runs of equal reduction `[start, end)` of the positions `pos(0..n)` modulo `side`, each with
/// its shift `k·side` (the position minus its reduction).
fn runs(n: usize, side: f64, pos: impl Fn(usize) -> f64) -> Vec<(usize, usize, f64)> {
    let mut out: Vec<(usize, usize, f64)> = Vec::new();
    for i in 0..n {
        let p = pos(i);
        let shift = p - spectex_model::period::reduce(p, side);
        match out.last_mut() {
            Some(last) if last.2.to_bits() == shift.to_bits() => last.1 = i + 1,
            _ => out.push((i, i + 1, shift)),
        }
    }
    out
}

impl PeriodicKernel {
    /// Whether every position of `window` is an integer, so that sub-windows moved by whole
    /// periods evaluate exactly the reduced positions.
    fn integer_positions(window: &Window) -> bool {
        window.scale == 1.0 && window.offset.iter().all(|o| o.fract() == 0.0)
    }

    fn eval_rows_whole(&self, window: &Window, first: usize, out: &mut [f32]) {
        let channels = self.inner.output_channels();
        let rows = out.len() / (window.width * channels);
        let [w, h] = self.period.sides();
        let cols = runs(window.width, w, |i| window.x(i));
        let mut tmp = Vec::new();
        for (r0, r1, ky) in runs(rows, h, |r| window.y(first + r)) {
            for &(c0, c1, kx) in &cols {
                let sub = Window {
                    offset: [window.offset[0] - kx, window.offset[1] - ky],
                    ..window.tile(c0, first + r0, c1 - c0, r1 - r0)
                };
                let row_len = (c1 - c0) * channels;
                tmp.clear();
                tmp.resize(row_len * (r1 - r0), 0.0);
                self.inner.eval_rows(&sub, 0, &mut tmp);
                for (r, line) in tmp.chunks_exact(row_len).enumerate() {
                    let start = ((r0 + r) * window.width + c0) * channels;
                    out[start..start + row_len].copy_from_slice(line);
                }
            }
        }
    }

    fn eval_rows_points(&self, window: &Window, first: usize, out: &mut [f32]) {
        let channels = self.inner.output_channels();
        let footprint = window.footprint();
        for (r, line) in out.chunks_exact_mut(window.width * channels).enumerate() {
            let y = window.y(first + r);
            let points: Vec<[f64; 2]> = (0..window.width)
                .map(|i| self.period.reduce([window.x(i), y]))
                .collect();
            match footprint {
                None => self.inner.eval_points(&points, line),
                Some(side) => {
                    for (p, v) in points.iter().zip(line.chunks_exact_mut(channels)) {
                        let one = point_window(*p).filtered(Filter::Footprint(side));
                        self.inner.eval_rows(&one, 0, v);
                    }
                }
            }
        }
    }
}

impl RowKernel for PeriodicKernel {
    fn output_channels(&self) -> usize {
        self.inner.output_channels()
    }

    fn cost_per_pixel(&self) -> f64 {
        self.inner.cost_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        if Self::integer_positions(window) {
            self.eval_rows_whole(window, first, out);
        } else {
            self.eval_rows_points(window, first, out);
        }
    }

    fn eval_points(&self, points: &[[f64; 2]], out: &mut [f32]) {
        let reduced: Vec<[f64; 2]> = points.iter().map(|&p| self.period.reduce(p)).collect();
        self.inner.eval_points(&reduced, out);
    }

    /// Reduced positions lie in `[0, period)`, well inside every range; a warp's reach beyond
    /// them is bounded by its own validation.
    fn check_window(&self, _window: &Window) -> Result<(), CpuError> {
        Ok(())
    }
}
