//! The builder of [`IslamicPattern`], with the `spectex noise islamic` defaults:
//! `IslamicPattern::builder().tiling(Tiling::Hexagonal).star(2).build()?`.

use crate::defaults::DEFAULT_SEED;
use crate::error::ModelError;
use crate::islamic::{IslamicOutput, IslamicPattern, Motif, Tiling};

impl IslamicPattern {
    /// Seed unless [`IslamicPatternBuilder::seed`] is given.
    pub const DEFAULT_SEED: u32 = DEFAULT_SEED;
    /// Octagons and squares (4.8.8): eight-pointed stars, the classic pattern.
    pub const DEFAULT_TILING: Tiling = Tiling::OctagonSquare;
    /// Hankin's contact angle, degrees: 67.5° closes regular eight-pointed stars in the
    /// octagons of the default tiling.
    pub const DEFAULT_CONTACT_ANGLE: f32 = 67.5;
    /// `C`, the lattice period, pixels.
    pub const DEFAULT_CELL_SIZE: f32 = 96.0;
    /// `w`, the line band width, pixels.
    pub const DEFAULT_LINE_WIDTH: f32 = 3.0;
    /// Anti-aliased line bands.
    pub const DEFAULT_OUTPUT: IslamicOutput = IslamicOutput::Band;
    /// `α`, the rotation, degrees: none.
    pub const DEFAULT_ROTATION: f32 = 0.0;
    /// `o`, the offset, pixels: none (the seed's phase still moves the pattern).
    pub const DEFAULT_OFFSET: [f32; 2] = [0.0, 0.0];

    /// An Islamic star pattern with every field at its default ([`Self::default`]); set what
    /// differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::IslamicPattern;
    /// use spectex_model::islamic::{Motif, Tiling};
    ///
    /// let p = IslamicPattern::builder().tiling(Tiling::Hexagonal).star(2).build()?;
    /// assert_eq!(p.motif, Motif::Star { step: 2 });
    /// // A band wider than the period is refused, naming the field.
    /// let wide = IslamicPattern::builder().line_width(200.0).build().unwrap_err();
    /// assert!(wide.to_string().contains("islamic.line_width"));
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> IslamicPatternBuilder {
        IslamicPatternBuilder {
            model: Self::default(),
        }
    }
}

impl Default for IslamicPattern {
    /// Every field at its `DEFAULT_` constant: the 4.8.8 tiling with contact angle 67.5°
    /// (eight-pointed stars in the octagons), a 96 px period, 3 px line bands, no rotation or
    /// offset, seed 0. Valid as it is.
    fn default() -> Self {
        Self {
            seed: Self::DEFAULT_SEED,
            tiling: Self::DEFAULT_TILING,
            motif: Motif::Contact {
                angle: Self::DEFAULT_CONTACT_ANGLE,
            },
            cell_size: Self::DEFAULT_CELL_SIZE,
            line_width: Self::DEFAULT_LINE_WIDTH,
            output: Self::DEFAULT_OUTPUT,
            rotation: Self::DEFAULT_ROTATION,
            offset: Self::DEFAULT_OFFSET,
        }
    }
}

/// Builds an [`IslamicPattern`]; start from [`IslamicPattern::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct IslamicPatternBuilder {
    model: IslamicPattern,
}

impl IslamicPatternBuilder {
    /// The seed of the pattern's phase (a translation within one period).
    pub fn seed(mut self, seed: u32) -> Self {
        self.model.seed = seed;
        self
    }

    /// The tiling.
    pub fn tiling(mut self, tiling: Tiling) -> Self {
        self.model.tiling = tiling;
        self
    }

    /// Hankin's rays at this contact angle, `[1, 89]` degrees.
    pub fn contact_angle(mut self, angle: f32) -> Self {
        self.model.motif = Motif::Contact { angle };
        self
    }

    /// The star polygon `{n/step}` on each n-gon's edge midpoints, `step` in `[1, 5]`.
    pub fn star(mut self, step: u32) -> Self {
        self.model.motif = Motif::Star { step };
        self
    }

    /// The motif in each tile.
    pub fn motif(mut self, motif: Motif) -> Self {
        self.model.motif = motif;
        self
    }

    /// `C`, the lattice period, `[4, 4096]` pixels.
    pub fn cell_size(mut self, cell_size: f32) -> Self {
        self.model.cell_size = cell_size;
        self
    }

    /// `w`, the line band width, `[0, cell_size]` pixels.
    pub fn line_width(mut self, line_width: f32) -> Self {
        self.model.line_width = line_width;
        self
    }

    /// What a pixel shows.
    pub fn output(mut self, output: IslamicOutput) -> Self {
        self.model.output = output;
        self
    }

    /// `α`, the rotation, `[-360, 360]` degrees.
    pub fn rotation(mut self, rotation: f32) -> Self {
        self.model.rotation = rotation;
        self
    }

    /// `o`, the offset, pixels, each in `[-1e9, 1e9]`.
    pub fn offset(mut self, offset: [f32; 2]) -> Self {
        self.model.offset = offset;
        self
    }

    /// The validated pattern.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the first field outside its range
    /// (`islamic.cell_size`, …).
    pub fn build(self) -> Result<IslamicPattern, ModelError> {
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
        let p = IslamicPattern::builder()
            .build()
            .expect("defaults are valid");
        let expected = IslamicPattern {
            seed: 0,
            tiling: Tiling::OctagonSquare,
            motif: Motif::Contact { angle: 67.5 },
            cell_size: 96.0,
            line_width: 3.0,
            output: IslamicOutput::Band,
            rotation: 0.0,
            offset: [0.0, 0.0],
        };
        assert_eq!(p, expected);
    }

    pub fn invalid_settings_name_the_field() {
        let b = IslamicPattern::builder;
        let cases = [
            (b().cell_size(2.0).build(), "islamic.cell_size"),
            (b().line_width(-1.0).build(), "islamic.line_width"),
            (b().rotation(400.0).build(), "islamic.rotation"),
            (b().offset([0.0, f32::NAN]).build(), "islamic.offset[1]"),
            (
                b().contact_angle(90.0).build(),
                "islamic.motif.contact.angle",
            ),
            (b().star(6).build(), "islamic.motif.star.step"),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
