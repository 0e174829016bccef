//! The builder of [`VoronoiNoise`], with the `spectex noise voronoi` defaults:
//! `VoronoiNoise::builder().lloyd_iterations(2).output(VoronoiOutput::Border).build()?`.

use crate::defaults::DEFAULT_SEED;
use crate::error::ModelError;
use crate::voronoi::{VoronoiNoise, VoronoiOutput};

impl VoronoiNoise {
    /// Seed unless [`VoronoiNoiseBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// A plane of seeds (2) unless [`VoronoiNoiseBuilder::dimensions`] is given (also the value
    /// of a model file without `dimensions`).
    pub const DEFAULT_DIMENSIONS: u32 = 2;
    /// `C`, the lattice cell side, pixels: one seed per 32 px cell.
    pub const DEFAULT_CELL_SIZE: f32 = 32.0;
    /// Seed jitter, cells: anywhere in the cell.
    pub const DEFAULT_JITTER: f32 = 1.0;
    /// Lloyd iterations: none (the raw jittered diagram).
    pub const DEFAULT_LLOYD_ITERATIONS: u32 = 0;
    /// Relaxation block side, cells, when relaxed: 16 seeds move together, and a pixel's
    /// block neighbourhood stays small.
    pub const DEFAULT_LLOYD_BLOCK: u32 = 4;
    /// The cell ID.
    pub const DEFAULT_OUTPUT: VoronoiOutput = VoronoiOutput::CellId;
    /// The palette of [`VoronoiNoiseBuilder::palette`] without colours (`spectex noise voronoi
    /// --show palette`): five colours of a mosaic, RGB in `[0, 1]`.
    pub const DEFAULT_PALETTE: [[f32; 3]; 5] = [
        [0.149, 0.275, 0.325],
        [0.165, 0.616, 0.561],
        [0.914, 0.769, 0.416],
        [0.957, 0.635, 0.380],
        [0.906, 0.435, 0.310],
    ];

    /// A Voronoi diagram with every field at its default ([`Self::default`]); set what
    /// differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::VoronoiNoise;
    /// use spectex_model::voronoi::VoronoiOutput;
    ///
    /// let v = VoronoiNoise::builder().output(VoronoiOutput::F1).jitter(0.0).build()?;
    /// // No jitter: every seed at its cell's centre.
    /// assert_eq!(v.jittered(3, -2).0, [0.5, 0.5]);
    /// let colours = VoronoiNoise::builder().palette(Vec::new()).build()?;
    /// assert_eq!(colours.output.channels(), 3);
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> VoronoiNoiseBuilder {
        VoronoiNoiseBuilder {
            model: Self::default(),
        }
    }
}

impl Default for VoronoiNoise {
    /// Every field at its `DEFAULT_` constant: fully jittered seeds on a 32 px lattice in the
    /// plane, no relaxation (blocks of 4 when relaxed), the cell ID. Valid as it is.
    fn default() -> Self {
        Self {
            seed: Self::DEFAULT_SEED,
            dimensions: Self::DEFAULT_DIMENSIONS,
            cell_size: Self::DEFAULT_CELL_SIZE,
            jitter: Self::DEFAULT_JITTER,
            lloyd_iterations: Self::DEFAULT_LLOYD_ITERATIONS,
            lloyd_block: Self::DEFAULT_LLOYD_BLOCK,
            output: Self::DEFAULT_OUTPUT,
        }
    }
}

/// Builds a [`VoronoiNoise`]; start from [`VoronoiNoise::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct VoronoiNoiseBuilder {
    model: VoronoiNoise,
}

impl VoronoiNoiseBuilder {
    /// The seed of the randomness contract.
    pub fn seed(mut self, seed: u32) -> Self {
        self.model.seed = seed;
        self
    }

    /// 2 (seeds in the plane) or 3 (seeds in space, sliced at `z`; no Lloyd relaxation and no
    /// image output).
    pub fn dimensions(mut self, dimensions: u32) -> Self {
        self.model.dimensions = dimensions;
        self
    }

    /// `C`, the lattice cell side, `[1, 4096]` pixels.
    pub fn cell_size(mut self, cell_size: f32) -> Self {
        self.model.cell_size = cell_size;
        self
    }

    /// Seed jitter, `[0, 1]` cells (0: a regular grid).
    pub fn jitter(mut self, jitter: f32) -> Self {
        self.model.jitter = jitter;
        self
    }

    /// Lloyd relaxation iterations, `0..=16` (0 in 3D).
    pub fn lloyd_iterations(mut self, lloyd_iterations: u32) -> Self {
        self.model.lloyd_iterations = lloyd_iterations;
        self
    }

    /// Side of a relaxation block, `1..=16` cells.
    pub fn lloyd_block(mut self, lloyd_block: u32) -> Self {
        self.model.lloyd_block = lloyd_block;
        self
    }

    /// What a pixel shows (a palette of 1 to 256 finite colours, an image of at most 1024
    /// per side).
    pub fn output(mut self, output: VoronoiOutput) -> Self {
        self.model.output = output;
        self
    }

    /// A colour per cell from `colours` (1 to 256 RGB colours), or from
    /// [`VoronoiNoise::DEFAULT_PALETTE`] when `colours` is empty.
    pub fn palette(mut self, colours: Vec<[f32; 3]>) -> Self {
        let colours = if colours.is_empty() {
            VoronoiNoise::DEFAULT_PALETTE.to_vec()
        } else {
            colours
        };
        self.model.output = VoronoiOutput::Palette { colours };
        self
    }

    /// The validated diagram.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first field outside its
    /// range (`voronoi.cell_size`, …).
    pub fn build(self) -> Result<VoronoiNoise, ModelError> {
        self.model.validate()?;
        Ok(self.model)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn defaults_are_the_documented_constants() {
        let v = VoronoiNoise::builder().build().expect("defaults are valid");
        let expected = VoronoiNoise {
            seed: 0,
            dimensions: 2,
            cell_size: 32.0,
            jitter: 1.0,
            lloyd_iterations: 0,
            lloyd_block: 4,
            output: VoronoiOutput::CellId,
        };
        assert_eq!(v, expected);
        let p = VoronoiNoise::builder().palette(Vec::new()).build();
        match p.expect("valid").output {
            VoronoiOutput::Palette { colours } => {
                assert_eq!((colours.len(), colours[1]), (5, [0.165, 0.616, 0.561]));
            }
            other => panic!("{other:?}"),
        }
    }

    pub fn invalid_settings_name_the_field() {
        let b = VoronoiNoise::builder;
        let cases = [
            (b().dimensions(4).build(), "voronoi.dimensions"),
            (
                b().dimensions(3).lloyd_iterations(1).build(),
                "voronoi.lloyd_iterations",
            ),
            (b().cell_size(0.0).build(), "voronoi.cell_size"),
            (b().jitter(-0.1).build(), "voronoi.jitter"),
            (b().lloyd_iterations(17).build(), "voronoi.lloyd_iterations"),
            (b().lloyd_block(0).build(), "voronoi.lloyd_block"),
            (
                b().palette(vec![[0.0, f32::NAN, 0.0]]).build(),
                "voronoi.output.palette.colours[0][1]",
            ),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
