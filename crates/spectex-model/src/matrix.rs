//! Matrix transformation (survey Dong et al. 2020, §2.4, after its ref. [32]): a source image
//! on the `N × N` torus whose pixels are moved `k` times by an integer matrix,
//! `(x', y') = M·(x, y) mod N`.
//!
//! # Definition
//!
//! The survey's rule: the entries of `M` are Lucas (1, 3, 4, 7, 11, …) or Fibonacci (1, 1, 2,
//! 3, 5, 8, …) numbers (it writes `M` diagonal, `a₁₂ = a₂₁ = 0`; the cat map
//! `[[1, 1], [1, 2]]` of Arnold is the classic full example, so an off-diagonal entry may also
//! be 0 or such a number), and the map must be a bijection of the torus: the survey asks the
//! product `a₁₁·a₂₂` to be prime to `N = 256`, which for any `M` is `gcd(det M, N) = 1` (`M`
//! invertible modulo `N`). [`MatrixTransform::validate`] refuses anything else, naming the
//! entry.
//!
//! The transformed image `T_k` puts source pixel `s` at `M^k·s mod N`, so
//! `T_k(q) = S(A·q mod N)` with `A = (M⁻¹)^k mod N`, computed once, exactly, in integers
//! ([`MatrixTransform::inverse_power`]; `M⁻¹ = (det M)⁻¹·adj M mod N`, powers by squaring, so
//! any `k` costs `O(log k)`). A position `p` (pixels) shows the pixel `q = (⌊p_x⌋ mod N,
//! ⌊p_y⌋ mod N)` (nearest texel, no interpolation: the map scatters neighbours), so the texture
//! is pointwise, exact and repeats every `N` pixels by construction (so it has no separate
//! periodic form, `--periodic`): every evaluator computes `q` from the
//! integer cell of the position ([`crate::grid::locate_cell`] with side 1) and `A·q mod N` in
//! integers (`A`'s entries and `q` are below `N ≤ 4096`, so every product and sum fits `u32`).
//! The value is `mean + amplitude·S(s)`.
//!
//! The source `S`: an image's grey texels (row-major, top row first, stored in the model so a
//! model file stands alone; its side is `N`), or, without an image, concentric rings: with
//! `d = (2s_x + 1 − N, 2s_y + 1 − N)`, `S(s) = ⌊rings·|d|²/N²⌋ mod 2` in integers (0 or 1).

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_len, check_level, check_range};

pub(crate) mod builder;
pub use builder::MatrixTransformBuilder;

/// Largest torus side `N`, pixels.
pub const MAX_SIZE: u32 = 4096;
/// Largest side of an image source, texels.
pub const MAX_IMAGE_SIDE: u32 = 1024;
/// Most rings of the procedural source.
pub const MAX_RINGS: u32 = 64;
/// Largest entry of `M`: the Lucas and Fibonacci numbers up to it are accepted.
pub const MAX_ENTRY: u32 = 10_000;

/// The source image of a [`MatrixTransform`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum MatrixSource {
    /// Concentric rings around the torus's centre (module docs), `1..=64` of them to the
    /// corners.
    Rings {
        /// Rings from the centre to a corner.
        rings: u32,
    },
    /// An `N × N` grey image, row-major, top row first.
    Image {
        /// `N·N` texels.
        texels: Vec<f32>,
    },
}

/// A matrix transformation texture (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MatrixTransform {
    /// `M` by rows: `[[a₁₁, a₁₂], [a₂₁, a₂₂]]`.
    pub matrix: [[u32; 2]; 2],
    /// `k`, the number of times the map is applied (0: the source itself).
    pub iterations: u64,
    /// `N`, the torus side and the texture's period, pixels (`2..=4096`; an image's side).
    pub size: u32,
    /// The source image.
    pub source: MatrixSource,
    /// Factor applied to the source value.
    pub amplitude: f32,
    /// Constant added after the factor.
    pub mean: f32,
}

/// Whether `v` is a Lucas (2, 1, 3, 4, 7, …) or Fibonacci (0, 1, 1, 2, 3, 5, …) number.
#[must_use]
pub fn is_lucas_or_fibonacci(v: u32) -> bool {
    let member = |mut a: u64, mut b: u64| {
        while a <= u64::from(v) {
            if a == u64::from(v) {
                return true;
            }
            (a, b) = (b, a + b);
        }
        false
    };
    member(0, 1) || member(2, 1)
}

/// `gcd(a, b)` of non-negative integers.
#[must_use]
pub fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// A 2×2 matrix of residues modulo `n`.
type Mat = [[u64; 2]; 2];

fn mat_mul(a: &Mat, b: &Mat, n: u64) -> Mat {
    let mut c = [[0u64; 2]; 2];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (a[i][0] * b[0][j] + a[i][1] * b[1][j]) % n;
        }
    }
    c
}

impl MatrixTransform {
    /// `det M` modulo `N`, in `0..N`.
    #[must_use]
    pub fn det_mod(&self) -> u64 {
        let n = i128::from(self.size);
        let [[a, b], [c, d]] = self.matrix.map(|r| r.map(i128::from));
        ((a * d - b * c).rem_euclid(n)) as u64
    }

    /// `M⁻¹ mod N` (`None` when `det M` is not invertible modulo `N`).
    #[must_use]
    pub fn inverse(&self) -> Option<[[u32; 2]; 2]> {
        let n = u64::from(self.size);
        let det = self.det_mod();
        // (det)⁻¹ mod n by the extended Euclidean algorithm.
        let (mut r0, mut r1) = (i128::from(n), i128::from(det));
        let (mut t0, mut t1) = (0i128, 1i128);
        while r1 != 0 {
            let q = r0 / r1;
            (r0, r1) = (r1, r0 - q * r1);
            (t0, t1) = (t1, t0 - q * t1);
        }
        if r0 != 1 {
            return None;
        }
        let inv = t0.rem_euclid(i128::from(n));
        let [[a, b], [c, d]] = self.matrix.map(|r| r.map(i128::from));
        let m = |v: i128| ((v * inv).rem_euclid(i128::from(n))) as u32;
        Some([[m(d), m(-b)], [m(-c), m(a)]])
    }

    /// `A = (M⁻¹)^k mod N`, by squaring (`None` when `M` is not invertible modulo `N`).
    #[must_use]
    pub fn inverse_power(&self) -> Option<[[u32; 2]; 2]> {
        let n = u64::from(self.size);
        let inv = self.inverse()?.map(|r| r.map(u64::from));
        let mut result: Mat = [[1 % n, 0], [0, 1 % n]];
        let mut base = inv;
        let mut k = self.iterations;
        while k > 0 {
            if k & 1 == 1 {
                result = mat_mul(&result, &base, n);
            }
            base = mat_mul(&base, &base, n);
            k >>= 1;
        }
        Some(result.map(|r| r.map(|v| v as u32)))
    }

    /// The source value at texel `s` (each coordinate in `0..N`).
    #[must_use]
    pub fn source_value(&self, s: [u32; 2]) -> f32 {
        let n = self.size;
        match &self.source {
            MatrixSource::Rings { rings } => rings_value(s, n, *rings),
            MatrixSource::Image { texels } => texels[(s[1] * n + s[0]) as usize],
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "matrix.size".into(),
            f64::from(self.size),
            2.0,
            f64::from(MAX_SIZE),
            "2 to 4096 pixels",
        )?;
        for (i, row) in self.matrix.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                if v > MAX_ENTRY || !is_lucas_or_fibonacci(v) {
                    return Err(ModelError::OutOfRange {
                        field: format!("matrix.matrix[{i}][{j}]"),
                        value: f64::from(v),
                        range: "a Lucas (1, 2, 3, 4, 7, 11, 18, …) or Fibonacci (0, 1, 2, 3, 5, \
                                8, 13, …) number up to 10000",
                    });
                }
            }
        }
        if gcd(self.det_mod(), u64::from(self.size)) != 1 {
            return Err(ModelError::OutOfRange {
                field: "matrix.matrix".into(),
                value: self.det_mod() as f64,
                range: "a determinant (shown modulo size) prime to size, so that the map is a \
                        bijection of the N × N torus (the survey's rule: a₁₁·a₂₂ prime to N)",
            });
        }
        check_level(|| "matrix.amplitude".into(), self.amplitude)?;
        check_level(|| "matrix.mean".into(), self.mean)?;
        match &self.source {
            MatrixSource::Rings { rings } => check_range(
                || "matrix.source.rings.rings".into(),
                f64::from(*rings),
                1.0,
                f64::from(MAX_RINGS),
                "1 to 64",
            ),
            MatrixSource::Image { texels } => {
                check_range(
                    || "matrix.size".into(),
                    f64::from(self.size),
                    2.0,
                    f64::from(MAX_IMAGE_SIDE),
                    "2 to 1024 pixels with an image source (the image's side)",
                )?;
                let n = self.size as usize;
                check_len(
                    || "matrix.source.image.texels".into(),
                    texels.len(),
                    n * n,
                    n * n,
                    "size × size texels (a square image of side size)",
                )?;
                for (k, &v) in texels.iter().enumerate() {
                    check_level(|| format!("matrix.source.image.texels[{k}]"), v)?;
                }
                Ok(())
            }
        }
    }
}

/// The procedural source: `⌊rings·|d|²/N²⌋ mod 2` with `d = 2s + 1 − N` (module docs), in
/// `u32` (`|d|² < 2N² ≤ 2²⁵`, times at most 64).
#[must_use]
pub fn rings_value(s: [u32; 2], n: u32, rings: u32) -> f32 {
    let d = |c: u32| (2 * c + 1).abs_diff(n);
    let r2 = d(s[0]) * d(s[0]) + d(s[1]) * d(s[1]);
    ((rings * r2 / (n * n)) & 1) as f32
}

impl crate::ModelKind for MatrixTransform {
    const PERIODIC: bool = true;

    const NAME: &'static str = "matrix";

    /// A period whose width and height are multiples of the torus side `N`: the texture is a
    /// function of the pixel's cell modulo `N`, so it repeats every `N` pixels.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let n = self.size;
        for (axis, p) in [("width", period.width), ("height", period.height)] {
            if n == 0 || !p.is_multiple_of(n) {
                return Err(ModelError::Period {
                    period: period.to_string(),
                    kind: "matrix",
                    requirement: format!(
                        "the period's {axis} {p} must be a multiple of matrix.size = {n} pixels,                          the torus the texture repeats on (valid: {n}, {}, {}, …)",
                        2 * u64::from(n),
                        3 * u64::from(n)
                    ),
                });
            }
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), ModelError> {
        MatrixTransform::validate(self)
    }

    /// No seed: the texture is a deterministic map of its source.
    fn visit_seeds(&mut self, _visit: &mut dyn FnMut(&mut u32)) {}
}

impl From<MatrixTransform> for crate::Model {
    fn from(m: MatrixTransform) -> Self {
        Self::Matrix(m)
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    fn cat(n: u32, k: u64) -> MatrixTransform {
        MatrixTransform {
            matrix: [[1, 1], [1, 2]],
            iterations: k,
            size: n,
            source: MatrixSource::Rings { rings: 4 },
            amplitude: 1.0,
            mean: 0.0,
        }
    }

    pub fn lucas_and_fibonacci_numbers() {
        let members = [
            0, 1, 2, 3, 4, 5, 7, 8, 11, 13, 18, 21, 29, 34, 47, 55, 76, 89, 123,
        ];
        for v in 0..130 {
            assert_eq!(is_lucas_or_fibonacci(v), members.contains(&v), "{v}");
        }
    }

    pub fn inverse_times_matrix_is_the_identity() {
        for (m, n) in [
            ([[1, 1], [1, 2]], 256),
            ([[3, 0], [0, 5]], 256),
            ([[2, 1], [1, 1]], 97),
        ] {
            let t = MatrixTransform {
                matrix: m,
                ..cat(n, 1)
            };
            let inv = t.inverse().unwrap().map(|r| r.map(u64::from));
            let m64 = m.map(|r| r.map(u64::from));
            let id = mat_mul(&m64, &inv, u64::from(n));
            assert_eq!(id, [[1, 0], [0, 1]], "{m:?} mod {n}");
        }
    }

    pub fn invalid_matrices_are_refused_by_field() {
        let mut t = cat(256, 1);
        t.matrix = [[6, 0], [0, 1]];
        match t.validate() {
            Err(ModelError::OutOfRange { field, .. }) => assert_eq!(field, "matrix.matrix[0][0]"),
            other => panic!("{other:?}"),
        }
        // All Fibonacci, but det = 2·1 − 0 = 2 is even: not a bijection of a 256 torus.
        t.matrix = [[2, 0], [0, 1]];
        match t.validate() {
            Err(ModelError::OutOfRange { field, .. }) => assert_eq!(field, "matrix.matrix"),
            other => panic!("{other:?}"),
        }
        // det [[1, 1], [1, 1]] = 0.
        t.matrix = [[1, 1], [1, 1]];
        assert!(t.validate().is_err());
        t.matrix = [[3, 0], [0, 5]];
        assert!(t.validate().is_ok());
        t.size = 15;
        assert!(t.validate().is_err(), "det 15 against N = 15");
        let mut t = cat(8, 1);
        t.source = MatrixSource::Image {
            texels: vec![0.0; 63],
        };
        assert!(matches!(t.validate(), Err(ModelError::Length { .. })));
        t.size = 1;
        assert!(t.validate().is_err());
    }

    pub fn json_round_trip() {
        let m = crate::Model::Matrix(cat(64, 3));
        let text = crate::to_json(&m).unwrap();
        assert_eq!(crate::from_json(&text).unwrap(), m);
    }
}
