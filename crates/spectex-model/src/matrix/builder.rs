//! The builder of [`MatrixTransform`], with the `spectex noise matrix` defaults (the cat map
//! on rings): `MatrixTransform::builder().iterations(3).build()?`.

use crate::error::ModelError;
use crate::matrix::{MatrixSource, MatrixTransform};

impl MatrixTransform {
    /// Arnold's cat map `[[1, 1], [1, 2]]` (determinant 1: a bijection on every torus).
    pub const DEFAULT_MATRIX: [[u32; 2]; 2] = [[1, 1], [1, 2]];
    /// `k`, the applications of the map: five.
    pub const DEFAULT_ITERATIONS: u64 = 5;
    /// `N`, the torus side and period, pixels.
    pub const DEFAULT_SIZE: u32 = 256;
    /// Rings of the built-in source, centre to corner.
    pub const DEFAULT_RINGS: u32 = 6;
    /// The factor: the rings' 0 and 1 as they are.
    pub const DEFAULT_AMPLITUDE: f32 = 1.0;
    /// The constant added: none, so the rings' 0 and 1 are black and white.
    pub const DEFAULT_MEAN: f32 = 0.0;

    /// A matrix transformation with every field at its default (the cat map moving
    /// [`Self::DEFAULT_RINGS`] rings [`Self::DEFAULT_ITERATIONS`] times on a 256-pixel
    /// torus); set what differs, then `build()`.
    ///
    /// ```
    /// use spectex_model::MatrixTransform;
    ///
    /// let m = MatrixTransform::builder().iterations(0).build()?;
    /// // The built-in source: rings of 0 and 1, 0 at the centre, 1 in the corner (⌊6·2·255²/256²⌋
    /// // = 11 is odd).
    /// assert_eq!((m.source_value([128, 128]), m.source_value([0, 0])), (0.0, 1.0));
    /// // A determinant (here 2) must be prime to the torus side (256).
    /// assert!(MatrixTransform::builder().matrix([[1, 1], [1, 3]]).build().is_err());
    /// # Ok::<(), spectex_model::ModelError>(())
    /// ```
    pub fn builder() -> MatrixTransformBuilder {
        MatrixTransformBuilder {
            model: Self {
                matrix: Self::DEFAULT_MATRIX,
                iterations: Self::DEFAULT_ITERATIONS,
                size: Self::DEFAULT_SIZE,
                source: MatrixSource::Rings {
                    rings: Self::DEFAULT_RINGS,
                },
                amplitude: Self::DEFAULT_AMPLITUDE,
                mean: Self::DEFAULT_MEAN,
            },
        }
    }
}

/// Builds a [`MatrixTransform`]; start from [`MatrixTransform::builder`].
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a builder makes nothing until `build()`"]
pub struct MatrixTransformBuilder {
    model: MatrixTransform,
}

impl MatrixTransformBuilder {
    /// `M` by rows: Lucas or Fibonacci numbers up to 10000 whose determinant is prime to the
    /// torus side.
    pub fn matrix(mut self, matrix: [[u32; 2]; 2]) -> Self {
        self.model.matrix = matrix;
        self
    }

    /// `k`, how many times the map is applied (0: the source itself).
    pub fn iterations(mut self, iterations: u64) -> Self {
        self.model.iterations = iterations;
        self
    }

    /// `N`, the torus side and period, `2..=4096` pixels (`..=1024` and the image's side with
    /// an image source).
    pub fn size(mut self, size: u32) -> Self {
        self.model.size = size;
        self
    }

    /// The built-in source with this many rings, `1..=64`.
    pub fn rings(mut self, rings: u32) -> Self {
        self.model.source = MatrixSource::Rings { rings };
        self
    }

    /// The source (rings or an `N × N` image).
    pub fn source(mut self, source: MatrixSource) -> Self {
        self.model.source = source;
        self
    }

    /// The factor applied to the source value, finite, `|amplitude| ≤ 1e9`.
    pub fn amplitude(mut self, amplitude: f32) -> Self {
        self.model.amplitude = amplitude;
        self
    }

    /// The constant added after the factor, finite, `|mean| ≤ 1e9`.
    pub fn mean(mut self, mean: f32) -> Self {
        self.model.mean = mean;
        self
    }

    /// The validated texture.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::Length`] naming the first field outside its
    /// range (`matrix.size`, `matrix.matrix`, …).
    pub fn build(self) -> Result<MatrixTransform, ModelError> {
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
        let m = MatrixTransform::builder()
            .build()
            .expect("defaults are valid");
        let expected = MatrixTransform {
            matrix: [[1, 1], [1, 2]],
            iterations: 5,
            size: 256,
            source: MatrixSource::Rings { rings: 6 },
            amplitude: 1.0,
            mean: 0.0,
        };
        assert_eq!(m, expected);
    }

    pub fn invalid_settings_name_the_field() {
        let b = MatrixTransform::builder;
        let cases = [
            (b().size(1).build(), "matrix.size"),
            (b().matrix([[1, 6], [1, 2]]).build(), "matrix.matrix[0][1]"),
            (b().matrix([[2, 0], [0, 1]]).build(), "matrix.matrix"),
            (b().rings(65).build(), "matrix.source.rings.rings"),
            (b().amplitude(f32::NAN).build(), "matrix.amplitude"),
            (b().mean(2e9).build(), "matrix.mean"),
        ];
        for (result, field) in cases {
            match result {
                Err(ModelError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: {other:?}"),
            }
        }
        let image = b()
            .source(MatrixSource::Image {
                texels: vec![0.0; 3],
            })
            .size(2)
            .build();
        match image {
            Err(ModelError::Length { field, .. }) => {
                assert_eq!(field, "matrix.source.image.texels")
            }
            other => panic!("{other:?}"),
        }
    }
}
