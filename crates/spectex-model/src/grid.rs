//! Windows: which positions a render evaluates, shared by every evaluator (`spectex-cpu`,
//! `spectex-gpu`) so that they map pixels to positions by one expression. A window is a rectangle
//! of an infinite pixel grid — pixel `(i, j)` sits at `offset + (x0 + i, y0 + j)·scale` — so any
//! tile of it evaluates exactly the same positions (tiles are invisible, DESIGN invariant 3).

/// A window parameter out of range; evaluators wrap it in their own error type.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("window {parameter} = {value} is outside its valid range {range}")]
pub struct WindowError {
    /// Which parameter.
    pub parameter: &'static str,
    /// The value given.
    pub value: f64,
    /// The accepted range.
    pub range: &'static str,
}

/// Largest side of a window, in pixels.
pub const MAX_WINDOW_SIDE: usize = 65_536;
/// Largest pixel count of one render call (1 Gpix; a 32-bit float image of that size is 4 GiB).
pub const MAX_WINDOW_PIXELS: usize = 1 << 30;
/// Largest absolute position a window may reach, in model pixels. Lattice cells are `i32`, and
/// the smallest lattice period is half a pixel, so 2³⁰ keeps every cell index representable.
pub const MAX_POSITION: f64 = 1_073_741_824.0;

/// How a render treats what its pixels cannot resolve ([`Window::footprint`]; the gains are
/// [`crate::filter`]'s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Filter {
    /// Each pixel stands for a box of `scale × scale` model pixels: a minified render
    /// (`scale > 1`) fades out the components above its Nyquist frequency (LRP §6, "Texture
    /// filtering"). Renders at `scale ≤ 1` are point samples, exactly as with [`Filter::Off`].
    /// The default.
    #[default]
    Pixel,
    /// Point samples at every scale: every component at full amplitude (`--no-filter`).
    Off,
    /// A box of this side in model pixels whatever the spacing of the pixels: to sample the
    /// filtered field more densely than its footprint (measurements), or a caller's own
    /// footprint. Must be finite and in `(0, 1e6]`; at most 1 means no filtering.
    Footprint(f64),
}

/// A rectangle of the pixel grid `position(i, j) = offset + (x0 + i, y0 + j)·scale`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// Position of grid pixel `(0, 0)`, in model pixels.
    pub offset: [f64; 2],
    /// Model pixels per output pixel.
    pub scale: f64,
    /// First grid column of the window.
    pub x0: i64,
    /// First grid row of the window.
    pub y0: i64,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// What a pixel covers when it spans more than one model pixel ([`Filter::Pixel`] from
    /// [`Window::new`]).
    pub filter: Filter,
}

impl Window {
    /// A `width × height` window at the origin, one model pixel per output pixel.
    #[must_use]
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            offset: [0.0, 0.0],
            scale: 1.0,
            x0: 0,
            y0: 0,
            width,
            height,
            filter: Filter::Pixel,
        }
    }

    /// The same window with filter `filter` (tiles inherit it).
    #[must_use]
    pub fn filtered(self, filter: Filter) -> Self {
        Self { filter, ..self }
    }

    /// The side in model pixels of the box each pixel is filtered over, when filtering applies:
    /// `scale` ([`Filter::Pixel`]) or the given side ([`Filter::Footprint`]) when above 1, else
    /// `None` (point samples, the values of an unfiltered render bit for bit).
    #[must_use]
    pub fn footprint(&self) -> Option<f64> {
        let side = match self.filter {
            Filter::Pixel => self.scale,
            Filter::Off => return None,
            Filter::Footprint(side) => side,
        };
        (side > 1.0).then_some(side)
    }

    /// The same window moved to `offset` and scaled by `scale`.
    #[must_use]
    pub fn at(self, offset: [f64; 2], scale: f64) -> Self {
        Self {
            offset,
            scale,
            ..self
        }
    }

    /// The sub-rectangle `(x, y, width, height)` of this window, in its own pixel coordinates:
    /// it evaluates exactly the positions of the matching pixels of `self`.
    #[must_use]
    pub fn tile(&self, x: usize, y: usize, width: usize, height: usize) -> Self {
        Self {
            x0: self.x0.saturating_add(x as i64),
            y0: self.y0.saturating_add(y as i64),
            width,
            height,
            ..*self
        }
    }

    /// Position of the window's column `i` (x) — the same expression for every tiling.
    #[inline]
    #[must_use]
    pub fn x(&self, i: usize) -> f64 {
        // Saturating: a corner past i64 (a window no validation accepts) must give a position
        // out of range, not an overflow panic; within range it is the plain sum.
        self.offset[0] + self.x0.saturating_add(i as i64) as f64 * self.scale
    }

    /// Position of the window's row `j` (y).
    #[inline]
    #[must_use]
    pub fn y(&self, j: usize) -> f64 {
        self.offset[1] + self.y0.saturating_add(j as i64) as f64 * self.scale
    }

    /// Checks sizes, finiteness and the reachable position range.
    ///
    /// # Errors
    /// [`WindowError`] naming the parameter and its valid range.
    pub fn validate(&self) -> Result<(), WindowError> {
        let bad = |parameter: &'static str, value: f64, range: &'static str| {
            Err(WindowError {
                parameter,
                value,
                range,
            })
        };
        if self.width == 0 || self.width > MAX_WINDOW_SIDE {
            return bad("width", self.width as f64, "1 to 65536 pixels");
        }
        if self.height == 0 || self.height > MAX_WINDOW_SIDE {
            return bad("height", self.height as f64, "1 to 65536 pixels");
        }
        if self.width * self.height > MAX_WINDOW_PIXELS {
            return bad(
                "width × height",
                (self.width * self.height) as f64,
                "at most 2^30 pixels",
            );
        }
        if !(self.scale.is_finite() && self.scale > 0.0 && self.scale <= 1e6) {
            return bad(
                "scale",
                self.scale,
                "(0, 1e6] model pixels per output pixel",
            );
        }
        if let Filter::Footprint(side) = self.filter
            && !(side.is_finite() && side > 0.0 && side <= 1e6)
        {
            return bad("filter footprint", side, "(0, 1e6] model pixels");
        }
        for (name, v) in [("offset x", self.offset[0]), ("offset y", self.offset[1])] {
            if !v.is_finite() {
                return bad(name, v, "finite numbers");
            }
        }
        let corners = [
            self.x(0),
            self.x(self.width - 1),
            self.y(0),
            self.y(self.height - 1),
        ];
        if let Some(&v) = corners.iter().find(|v| v.abs() > MAX_POSITION) {
            return bad("window position", v, "[-2^30, 2^30] model pixels");
        }
        Ok(())
    }
}

/// Cells of sparse-convolution grids (Gabor, phasor) are `i32`; a coordinate whose cell, or a
/// neighbour of it, would leave that range has no cell.
pub const MAX_CELL: f64 = 2_147_483_646.0;

/// Splits a coordinate in pixels into its cell on a grid of side `side` and the offset in
/// `[0, 1]` cell units, or `None` outside the usable range (NaN included). `p = coord / side`
/// and `p − ⌊p⌋` are exact in f64 and rounded to f32 once; the rounding may give 1.0, which is
/// harmless (kernels then stay masked by their radius). Every evaluator locates points with
/// this one expression, so they agree on cells and offsets bit for bit.
#[inline]
#[must_use]
pub fn locate_cell(coord: f64, side: f64) -> Option<(i32, f32)> {
    let p = coord / side;
    if p.abs() < MAX_CELL {
        let cell = p.floor();
        Some((cell as i32, (p - cell) as f32))
    } else {
        None
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn tiles_evaluate_the_same_positions() {
        let w = Window::new(100, 50).at([1.0e7, -3.5], 0.37);
        let t = w.tile(10, 20, 5, 5);
        assert_eq!(t.x(2).to_bits(), w.x(12).to_bits());
        assert_eq!(t.y(3).to_bits(), w.y(23).to_bits());
    }

    pub fn validation_names_the_parameter() {
        let cases = [
            (Window::new(0, 5), "width"),
            (Window::new(5, 70_000), "height"),
            (Window::new(5, 5).at([0.0, 0.0], 0.0), "scale"),
            (Window::new(5, 5).at([f64::NAN, 0.0], 1.0), "offset x"),
            (
                Window::new(5, 5).filtered(Filter::Footprint(f64::INFINITY)),
                "filter footprint",
            ),
            (
                Window::new(5, 5).filtered(Filter::Footprint(-2.0)),
                "filter footprint",
            ),
            (Window::new(5, 5).at([0.0, 2e9], 1.0), "window position"),
            // Corners past i64: refused, not an overflow (found by the kit's fuzzing).
            (
                Window {
                    x0: i64::MAX - 2,
                    ..Window::new(5, 5)
                },
                "window position",
            ),
            (
                Window {
                    y0: i64::MAX - 1,
                    ..Window::new(5, 5)
                }
                .tile(0, 3, 5, 2),
                "window position",
            ),
        ];
        for (w, name) in cases {
            match w.validate() {
                Err(WindowError { parameter, .. }) => assert_eq!(parameter, name),
                other => panic!("{w:?}: {other:?}"),
            }
        }
        assert!(Window::new(65_536, 1).validate().is_ok());
    }

    pub fn footprint_is_the_pixel_box_only_when_minified() {
        let w = Window::new(4, 4);
        assert_eq!(w.at([0.0, 0.0], 1.0).footprint(), None);
        assert_eq!(w.at([0.0, 0.0], 0.3).footprint(), None);
        assert_eq!(w.at([0.0, 0.0], 4.0).footprint(), Some(4.0));
        assert_eq!(
            w.at([0.0, 0.0], 4.0).filtered(Filter::Off).footprint(),
            None
        );
        let dense = w.at([0.0, 0.0], 0.5).filtered(Filter::Footprint(4.0));
        assert_eq!(dense.footprint(), Some(4.0));
        assert_eq!(dense.tile(1, 1, 2, 2).footprint(), Some(4.0));
    }

    pub fn locate_cell_splits_exactly_and_rejects_out_of_range() {
        assert_eq!(locate_cell(-0.5, 2.0), Some((-1, 0.75)));
        assert_eq!(locate_cell(4.0, 2.0), Some((2, 0.0)));
        assert_eq!(locate_cell(f64::NAN, 2.0), None);
        assert_eq!(locate_cell(-3e9, 1.0), None);
        assert_eq!(
            locate_cell(2_147_483_645.5, 1.0),
            Some((2_147_483_645, 0.5))
        );
    }
}
