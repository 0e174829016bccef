//! Positions of a tile for the per-axis tables every shader receives (the f64 work done on the
//! host, so the device needs only f32 and integers; see the precision notes in
//! `shaders/lrp.wgsl`), and the (cell, offset, valid) table of the sparse-convolution grids that
//! Gabor and phasor noise share.

use spectex_model::Period;
use spectex_model::period::reduce;

use crate::kernel::{Table, TileDisplacement};
use crate::layout::wgsl_struct;
use crate::{GpuError, GpuWindow};

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
    /// `GridAxis` of `common.wgsl`, what every shader on a cell grid (Gabor, phasor, texton,
    /// Voronoi, subdivision, matrix) reads per column and row and moves by a warp's
    /// displacement (`grid_point`): a position's cell on the grid, its f32 offset in the cell,
    /// and whether it is in range (0: the kind's out-of-range value).
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

/// A tile's [`CellAxis`] tables on a grid of cells of side `side`: one record per column and
/// one per row ([`cell_axis`] at [`periodic_columns`] and [`periodic_rows`]), what every kind
/// on a cell grid binds last before its output.
#[derive(Debug, Clone)]
pub(crate) struct CellAxes {
    /// One record per column of the tile.
    pub columns: Vec<CellAxis>,
    /// One record per row of the tile.
    pub rows: Vec<CellAxis>,
    side: f64,
    period: Option<Period>,
}

impl CellAxes {
    /// The columns and rows of `tile` on the grid of side `side`, at positions reduced modulo
    /// `period` when given.
    pub(crate) fn new(side: f64, tile: &GpuWindow, period: Option<Period>) -> Self {
        Self {
            columns: cell_axis(side, tile.width, periodic_columns(tile, period)),
            rows: cell_axis(side, tile.height, periodic_rows(tile, period)),
            side,
            period,
        }
    }

    /// The two tables, columns then rows, labelled `labels`.
    pub(crate) fn tables(&self, labels: [&'static str; 2]) -> Vec<Table> {
        vec![
            Table::new(labels[0], &self.columns),
            Table::new(labels[1], &self.rows),
        ]
    }

    /// The lowest and highest cell along x and y (`None` where there is none) of the pixels of
    /// `tile` (the tile these axes were made for), located in f64 as the CPU locates them:
    /// - undisplaced: of the valid columns and rows;
    /// - with each pixel's displacement: of every pixel's reduced position plus its
    ///   displacement;
    /// - with only the displacement's range: of the lowest reduced position plus the lowest
    ///   displacement and the highest plus the highest, a box that holds every displaced
    ///   pixel's cell (locating is monotonic), at most a range's width wider than that of the
    ///   pixels themselves.
    ///
    /// # Errors
    /// [`GpuError::Window`] where a range's extreme lies beyond the cells' range (the warp's
    /// window check keeps every displaced position within it).
    pub(crate) fn cell_range(
        &self,
        tile: &GpuWindow,
        displacement: TileDisplacement<'_>,
    ) -> Result<[Option<(i32, i32)>; 2], GpuError> {
        let mut range: [Option<(i32, i32)>; 2] = [None, None];
        let mut widen = |axis: usize, c: i32| {
            let (lo, hi) = range[axis].unwrap_or((c, c));
            range[axis] = Some((lo.min(c), hi.max(c)));
        };
        let column_x = periodic_columns(tile, self.period);
        let row_y = periodic_rows(tile, self.period);
        match displacement {
            TileDisplacement::Pixels(d) => {
                for j in 0..tile.height {
                    for i in 0..tile.width {
                        let k = 2 * (j * tile.width + i);
                        let p = [
                            column_x(i) + f64::from(d[k]),
                            row_y(j) + f64::from(d[k + 1]),
                        ];
                        for (axis, &v) in p.iter().enumerate() {
                            if let Some((c, _)) = spectex_model::grid::locate_cell(v, self.side) {
                                widen(axis, c);
                            }
                        }
                    }
                }
            }
            TileDisplacement::Within(within) => {
                let extremes = |n: usize, at: &dyn Fn(usize) -> f64| {
                    (0..n)
                        .map(at)
                        .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
                            [lo.min(v), hi.max(v)]
                        })
                };
                let axes = [
                    (extremes(tile.width, &column_x), within.x, "displaced x"),
                    (extremes(tile.height, &row_y), within.y, "displaced y"),
                ];
                for (axis, ([lo, hi], [d_lo, d_hi], name)) in axes.into_iter().enumerate() {
                    for v in [lo + f64::from(d_lo), hi + f64::from(d_hi)] {
                        let (c, _) = spectex_model::grid::locate_cell(v, self.side).ok_or({
                            GpuError::Window {
                                parameter: name,
                                value: v,
                                range: "|position / cell side| < 2147483646 \
                                        (spectex_model::grid::MAX_CELL)",
                            }
                        })?;
                        widen(axis, c);
                    }
                }
            }
            TileDisplacement::OnDevice => {
                return Err(GpuError::Validation(
                    "the cell range of a tile displaced on the device by a displacement it \
                     does not read"
                        .to_owned(),
                ));
            }
            TileDisplacement::None => {
                for (axis, records) in [&self.columns, &self.rows].into_iter().enumerate() {
                    for r in records.iter().filter(|r| r.valid == 1) {
                        widen(axis, r.cell);
                    }
                }
            }
        }
        Ok(range)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::assert_matches_wgsl;

    pub fn cell_axis_splits_cells_and_rejects_out_of_range() {
        let w = cell_axis(2.0, 3, |i| [-0.5, 4.0, 1e300][i]);
        let words: &[u32] = bytemuck::cast_slice(&w);
        assert_eq!(words[0..3], [(-1i32) as u32, 0.75f32.to_bits(), 1]);
        assert_eq!(words[3..6], [2, 0, 1]);
        assert_eq!(words[6..9], [0, 0, 0]);
    }

    /// Cells worked by hand on a grid of side 2: the columns at x = 0 and 1 are both in cell
    /// 0; displaced by (3, 0) and (−5, 1) the pixels sit at (3, 0) and (−4, 1), cells (1, 0)
    /// and (−2, 0).
    pub fn cell_range_covers_the_pixels_and_their_displacements() {
        let tile = GpuWindow::new(2, 1);
        let axes = CellAxes::new(2.0, &tile, None);
        let none = TileDisplacement::None;
        assert_eq!(
            axes.cell_range(&tile, none).unwrap(),
            [Some((0, 0)), Some((0, 0))]
        );
        let d = [3.0, 0.0, -5.0, 1.0];
        assert_eq!(
            axes.cell_range(&tile, TileDisplacement::Pixels(&d))
                .unwrap(),
            [Some((-2, 1)), Some((0, 0))]
        );
    }

    /// The same tile with only the range of those displacements, dx in [−5, 3] and dy in
    /// [0, 1]: the box runs from the lowest column plus the lowest dx, 0 − 5 = −5 (cell −3),
    /// to the highest plus the highest, 1 + 3 = 4 (cell 2), and from y = 0 (cell 0) to 1 + 0
    /// (cell 0); it holds the per-pixel box above. A range reaching past the cells' range is
    /// refused, naming the axis.
    pub fn cell_range_of_a_displacement_range_holds_every_pixel() {
        let tile = GpuWindow::new(2, 1);
        let axes = CellAxes::new(2.0, &tile, None);
        let within = |x, y| TileDisplacement::Within(crate::kernel::DisplacementRange { x, y });
        assert_eq!(
            axes.cell_range(&tile, within([-5.0, 3.0], [0.0, 1.0]))
                .unwrap(),
            [Some((-3, 2)), Some((0, 0))]
        );
        let far = axes.cell_range(&tile, within([0.0, 0.0], [0.0, 1e10]));
        assert!(
            matches!(
                far,
                Err(GpuError::Window {
                    parameter: "displaced y",
                    ..
                })
            ),
            "{far:?}"
        );
    }

    pub fn cell_axis_matches_its_wgsl_twin() {
        assert_matches_wgsl::<CellAxis>("common", "GridAxis");
    }
}
