//! Positions of a tile for the per-axis tables every shader receives (the f64 work done on the
//! host, so the device needs only f32 and integers; see the precision notes in
//! `shaders/lrp.wgsl`), and the (cell, offset, valid) table of the sparse-convolution grids that
//! Gabor and phasor noise share.

use spectex_model::Period;
use spectex_model::period::reduce;

use crate::GpuWindow;
use crate::layout::wgsl_struct;

/// Column positions of a window for the axis tables, reduced modulo the period's width for a periodic model
/// ([`spectex_model::period::reduce`], exact: the CPU's reduced positions).
pub(crate) fn periodic_columns(
    window: &GpuWindow,
    period: Option<Period>,
) -> impl Fn(usize) -> f64 + '_ {
    move |i| match period {
        None => window.x(i),
        Some(p) => reduce(window.x(i), f64::from(p.width)),
    }
}

/// Row positions of a window, reduced modulo the period's height for a periodic model.
pub(crate) fn periodic_rows(
    window: &GpuWindow,
    period: Option<Period>,
) -> impl Fn(usize) -> f64 + '_ {
    move |j| match period {
        None => window.y(j),
        Some(p) => reduce(window.y(j), f64::from(p.height)),
    }
}

wgsl_struct! {
    /// `GaborAxis` of `gabor.wgsl` and `PhasorAxis` of `phasor.wgsl`: a position's cell on a
    /// kernel grid, its f32 offset in the cell, and whether it is in range (0: the pixel is the
    /// model's mean).
    pub(crate) struct CellAxis {
        cell: i32,
        offset: f32,
        valid: u32,
    }
}

/// [`CellAxis`] records for `count` positions: `p = x / side`, the cell `⌊p⌋`, the offset
/// `f32(p − ⌊p⌋)` and 1, or `(0, 0, 0)` where `|p|` is out of range
/// ([`spectex_model::grid::locate_cell`], the CPU's split).
pub(crate) fn cell_axis(side: f64, count: usize, position: impl Fn(usize) -> f64) -> Vec<CellAxis> {
    (0..count)
        .map(
            |i| match spectex_model::grid::locate_cell(position(i), side) {
                Some((cell, offset)) => CellAxis {
                    cell,
                    offset,
                    valid: 1,
                },
                None => bytemuck::Zeroable::zeroed(),
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    #[test]
    fn cell_axis_splits_cells_and_rejects_out_of_range() {
        let w = cell_axis(2.0, 3, |i| [-0.5, 4.0, 1e300][i]);
        let words: &[u32] = bytemuck::cast_slice(&w);
        assert_eq!(words[0..3], [(-1i32) as u32, 0.75f32.to_bits(), 1]);
        assert_eq!(words[3..6], [2, 0, 1]);
        assert_eq!(words[6..9], [0, 0, 0]);
    }

    #[test]
    fn cell_axis_matches_both_wgsl_twins() {
        assert_matches_wgsl::<CellAxis>("gabor", "GaborAxis");
        assert_matches_wgsl::<CellAxis>("phasor", "PhasorAxis");
    }
}
