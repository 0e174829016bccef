//! Islamic star patterns (survey Dong et al. 2020, §2.7): star rosettes placed on the tiles of
//! a regular or semi-regular tiling, by Hankin's "polygons in contact" method as Kaplan
//! formulates it, or as star polygons `{n/d}`, shown as anti-aliased line bands, as a signed
//! distance, or as filled regions.
//!
//! # Definition
//!
//! A tiling ([`Tiling`]) is a lattice of basis `e₁, e₂` (cell units: one lattice period is
//! [`IslamicPattern::cell_size`] pixels) and the regular polygons of one lattice cell, each
//! given by its centre, its number of sides `n`, its inradius `r` and the direction `φ₀` of its
//! first edge's outward normal: square 4.4.4.4 (one square), hexagonal 6.6.6 (one hexagon of
//! width 1), 4.8.8 (an octagon of width 1 and a square in the gap) and 3.12.12 (a dodecagon of
//! width 1 and two triangles). Edge `k` of a polygon has outward normal `n_k` at angle
//! `φ₀ + 2πk/n`, tangent `t_k = (−n_k,y, n_k,x)` (counter-clockwise) and midpoint
//! `m_k = centre + r·n_k`. The motif ([`Motif`]) of a polygon is a closed polygonal line:
//!
//! - **contact** angle `θ`: from each midpoint `m_k` two rays leave at angle `θ` to the edge,
//!   inwards, one toward each corner of the edge (`cos θ·t_k − sin θ·n_k` toward corner
//!   `(k, k+1)`, `−cos θ·t_k − sin θ·n_k` toward corner `(k−1, k)`); the ray of `m_k` toward
//!   corner `(k, k+1)` and the ray of `m_{k+1}` toward the same corner are clipped where they
//!   meet, at `x_k` on the corner's bisector (computed as the first ray's crossing with it). The motif is `m₀ x₀ m₁ x₁ …`, `2n` segments: a
//!   star whose points touch the neighbouring tiles' stars at the edge midpoints (θ above
//!   `90° − 180°/n` points them at the midpoints, below it at the corners).
//! - **star** `{n/d}`: the chords `m_k → m_{k+d}` (indices mod `n`), `n` segments, with
//!   `d = min(step, ⌊(n − 1)/2⌋)` per polygon (a square takes `{4/1}`, a triangle `{3/1}`).
//!
//! All segments are computed in f64 from this definition, then rounded to f32 once (the table
//! both evaluators read, [`IslamicPattern::geometry`]): every segment of every tile whose
//! centre lies within `ρ + R_tile + R_max` of the centre of the fundamental parallelogram
//! `{s·e₁ + t·e₂ : s, t ∈ [0, 1)}` of circumradius `ρ` (`R` the polygons' circumradii). This
//! covers every tile containing a point of the parallelogram, and every motif point that can be
//! nearest to one: a point lies in some tile, and a regular polygon lies within its
//! circumradius of some edge midpoint, which its motif passes through.
//!
//! A pixel at `p` (pixels) maps to lattice coordinates `(s, t) = A·p + c` with
//! `A = B⁻¹·R(−α)/C` (`B = [e₁ e₂]`, `α` the rotation, `C` the cell size) and
//! `c = −A·o − φ` (`o` the offset in pixels, `φ` the seed's phase below). Per axis the host
//! (f64) splits the column's `A₀₀·x`, `A₁₀·x` and the row's `A₀₁·y + c₀`, `A₁₁·y + c₁` to
//! their fractional parts, rounded to f32 ([`LatticeMap`]); per pixel, in f32,
//! `s = σ_col + σ_row`, `s ← s − ⌊s⌋` (likewise `t`), and `q = s·e₁ + t·e₂`. So a window at
//! 10⁷ pixels is as precise as at the origin. For each segment `a → b` (f32 `a`, `b`,
//! `d = b − a` and `ι = 1/|d|²`, each rounded from f64), in table order:
//! `h = clamp(((q − a)·d)·ι, 0, 1)`, `e = (q − a) − d·h`, the smallest `e·e` is kept; and the
//! ray from `q` toward `+x` crosses it when `a_y ≤ q_y < b_y` with
//! `d_x·(q_y − a_y) − d_y·(q_x − a_x) > 0`, or `b_y ≤ q_y < a_y` with that cross product
//! `< 0`. The parity of the crossings is the region parity (even–odd rule: 1 inside a star,
//! alternating across every line of a star `{n/d}`). `D = √(min e·e)·C` pixels, the signed
//! distance `σ = −D` on odd parity and `D` on even. The outputs ([`IslamicOutput`]), with `f`
//! the footprint (the window's `Window::footprint` in pixels, 1 when it has none) and
//! `ι_f = f32(1/f)`:
//!
//! - `band`: the box-filtered coverage of a line band of width `w` across the nearest line,
//!   `max(min(D + f/2, w/2) − max(D − f/2, −w/2), 0)·ι_f`;
//! - `distance`: `σ` in pixels;
//! - `filled`: the box-filtered coverage of the odd regions, `clamp(½ − σ·ι_f, 0, 1)`.
//!
//! The seed draws the pattern's phase: `Prng::new(cell_hash(0, 0, ISLAMIC_LAYER, seed))`
//! draws `φ₁` then `φ₂` uniform in `[0, 1)`, translating the pattern by `φ₁e₁ + φ₂e₂` (a
//! random translation by a fraction of the period makes the periodic pattern stationary).

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_range};
use crate::random::{Prng, cell_hash};

pub(crate) mod builder;
pub use builder::IslamicPatternBuilder;

/// The random layer of the pattern's phase ("ISLM").
pub const ISLAMIC_LAYER: u32 = 0x4953_4C4D;
/// Largest star step `d`.
pub const MAX_STAR_STEP: u32 = 5;
/// Floats per segment in [`IslamicGeometry::segments`]: `a_x, a_y, b_x, b_y, d_x, d_y, ι`.
pub const SEGMENT_FLOATS: usize = 7;
/// The most segments a table holds over every tiling and motif (tested).
pub const MAX_SEGMENTS: usize = 1024;
/// Largest `|coordinate|` of a table's segment endpoints, cell units (tested).
pub const MAX_COORDINATE: f64 = 4.0;

/// A tiling of the plane by regular polygons, with its lattice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Tiling {
    /// Squares (4.4.4.4), one per lattice cell.
    Square,
    /// Hexagons (6.6.6) of width one period on the hexagonal lattice.
    Hexagonal,
    /// Octagons and squares (4.8.8, the truncated square tiling).
    #[serde(rename = "4.8.8")]
    OctagonSquare,
    /// Dodecagons and triangles (3.12.12, the truncated hexagonal tiling).
    #[serde(rename = "3.12.12")]
    DodecagonTriangle,
}

/// The motif drawn in each tile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Motif {
    /// Hankin's rays at a contact angle, clipped where they meet (module docs).
    Contact {
        /// `θ`, degrees, in `[1, 89]`.
        angle: f32,
    },
    /// The star polygon `{n/d}` on the edge midpoints (module docs).
    Star {
        /// `d`, in `[1, 5]` (each polygon takes at most `⌊(n − 1)/2⌋`).
        step: u32,
    },
}

/// What a pixel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IslamicOutput {
    /// Anti-aliased line bands of [`IslamicPattern::line_width`], in `[0, 1]`.
    Band,
    /// The signed distance to the lines, pixels, negative in odd regions.
    Distance,
    /// Anti-aliased odd regions (inside the stars), in `[0, 1]`.
    Filled,
}

/// An Islamic star pattern (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IslamicPattern {
    /// Seed of the pattern's phase.
    pub seed: u32,
    /// The tiling.
    pub tiling: Tiling,
    /// The motif in each tile.
    pub motif: Motif,
    /// `C`, the lattice period in pixels, in `[4, 4096]`.
    pub cell_size: f32,
    /// `w`, the line band width in pixels, in `[0, cell_size]`.
    pub line_width: f32,
    /// What a pixel shows.
    pub output: IslamicOutput,
    /// `α`, the pattern's rotation in degrees, in `[−360, 360]`.
    pub rotation: f32,
    /// `o`, the pattern's offset in pixels, each in `[−1e9, 1e9]`.
    pub offset: [f32; 2],
}

/// One regular polygon of a tiling's lattice cell (cell units, f64).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tile {
    /// Its centre.
    pub centre: [f64; 2],
    /// Its number of sides `n`.
    pub sides: u32,
    /// Its inradius `r`.
    pub inradius: f64,
    /// `φ₀`, the direction of its first edge's outward normal, radians.
    pub normal0: f64,
}

impl Tile {
    /// Its circumradius `r / cos(π/n)`.
    #[must_use]
    pub fn circumradius(&self) -> f64 {
        self.inradius / (std::f64::consts::PI / f64::from(self.sides)).cos()
    }
}

const SQRT3: f64 = 1.732_050_807_568_877_2;

impl Tiling {
    /// The lattice basis `e₁, e₂`, cell units.
    #[must_use]
    pub fn basis(self) -> [[f64; 2]; 2] {
        match self {
            Self::Square | Self::OctagonSquare => [[1.0, 0.0], [0.0, 1.0]],
            Self::Hexagonal | Self::DodecagonTriangle => [[1.0, 0.0], [0.5, SQRT3 / 2.0]],
        }
    }

    /// The polygons of one lattice cell.
    #[must_use]
    pub fn tiles(self) -> Vec<Tile> {
        use std::f64::consts::FRAC_PI_4;
        let tile = |centre, sides, inradius, normal0| Tile {
            centre,
            sides,
            inradius,
            normal0,
        };
        match self {
            Self::Square => vec![tile([0.5, 0.5], 4, 0.5, 0.0)],
            Self::Hexagonal => vec![tile([0.0, 0.0], 6, 0.5, 0.0)],
            Self::OctagonSquare => vec![
                tile([0.0, 0.0], 8, 0.5, 0.0),
                // The gap's square faces the four octagons diagonally: its inradius is the
                // half-diagonal of the cell less the octagon's inradius.
                tile(
                    [0.5, 0.5],
                    4,
                    std::f64::consts::SQRT_2 / 2.0 - 0.5,
                    FRAC_PI_4,
                ),
            ],
            Self::DodecagonTriangle => {
                // Each triangle's centre is 1/√3 from the three dodecagons it faces.
                let r = 1.0 / SQRT3 - 0.5;
                let deg = std::f64::consts::PI / 180.0;
                vec![
                    tile([0.0, 0.0], 12, 0.5, 0.0),
                    tile([0.5, SQRT3 / 6.0], 3, r, 90.0 * deg),
                    tile([1.0, SQRT3 / 3.0], 3, r, 30.0 * deg),
                ]
            }
        }
    }
}

/// The motif of `tile` as segments `(a, b)` in f64 (module docs).
#[must_use]
pub fn tile_motif(tile: &Tile, motif: Motif) -> Vec<([f64; 2], [f64; 2])> {
    let n = tile.sides as usize;
    let step = std::f64::consts::TAU / n as f64;
    let normal = |k: usize| {
        let phi = tile.normal0 + step * (k % n) as f64;
        [phi.cos(), phi.sin()]
    };
    let midpoint = |k: usize| {
        let v = normal(k);
        [
            tile.centre[0] + tile.inradius * v[0],
            tile.centre[1] + tile.inradius * v[1],
        ]
    };
    match motif {
        Motif::Star { step: d } => {
            let d = (d as usize).min((n - 1) / 2).max(1);
            (0..n).map(|k| (midpoint(k), midpoint(k + d))).collect()
        }
        Motif::Contact { angle } => {
            let theta = f64::from(angle).to_radians();
            let (c, s) = (theta.cos(), theta.sin());
            let mut out = Vec::with_capacity(2 * n);
            let half = std::f64::consts::PI / n as f64;
            for k in 0..n {
                let nk = normal(k);
                let tk = [-nk[1], nk[0]];
                let (mk, ml) = (midpoint(k), midpoint(k + 1));
                // The ray of m_k toward corner (k, k+1), and that corner's bisector through
                // the centre: by the polygon's mirror symmetry across the bisector, the ray of
                // m_{k+1} toward the same corner meets the first one there. Crossing the ray
                // with the bisector (never parallel for 0 < θ < 90°) stays well conditioned
                // where the two rays are collinear (θ = 90° − 180°/n).
                let u = [c * tk[0] - s * nk[0], c * tk[1] - s * nk[1]];
                let beta = tile.normal0 + step * k as f64 + half;
                let w = [beta.cos(), beta.sin()];
                let r = [tile.centre[0] - mk[0], tile.centre[1] - mk[1]];
                let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
                let lambda = cross(r, w) / cross(u, w);
                let x = [mk[0] + lambda * u[0], mk[1] + lambda * u[1]];
                out.push((mk, x));
                out.push((x, ml));
            }
            out
        }
    }
}

/// The f32 segment table and lattice both evaluators read (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct IslamicGeometry {
    /// `e₁, e₂` rounded to f32.
    pub basis: [[f32; 2]; 2],
    /// [`SEGMENT_FLOATS`] floats per segment: `a_x, a_y, b_x, b_y, d_x, d_y, ι`.
    pub segments: Vec<f32>,
}

impl IslamicGeometry {
    /// The number of segments.
    #[must_use]
    pub fn len(&self) -> usize {
        self.segments.len() / SEGMENT_FLOATS
    }

    /// Whether the table is empty (never, for a valid model).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// The squared distance (cell units²) from the point at lattice fractions `(s, t)` to the
    /// nearest segment, and the parity of the segments the ray toward `+x` crosses.
    #[inline]
    #[must_use]
    pub fn nearest(&self, s: f32, t: f32) -> (f32, bool) {
        let [e1, e2] = self.basis;
        let qx = s * e1[0] + t * e2[0];
        let qy = s * e1[1] + t * e2[1];
        let mut best = f32::INFINITY;
        let mut odd = false;
        for g in self.segments.chunks_exact(SEGMENT_FLOATS) {
            let (ax, ay, by, dx, dy, inv) = (g[0], g[1], g[3], g[4], g[5], g[6]);
            let px = qx - ax;
            let py = qy - ay;
            let h = ((px * dx + py * dy) * inv).clamp(0.0, 1.0);
            let ex = px - dx * h;
            let ey = py - dy * h;
            let d2 = ex * ex + ey * ey;
            if d2 < best {
                best = d2;
            }
            let up = ay <= qy;
            if up != (by <= qy) {
                let cross = dx * py - dy * px;
                if (up && cross > 0.0) || (!up && cross < 0.0) {
                    odd = !odd;
                }
            }
        }
        (best, odd)
    }
}

/// The split of pixel positions into lattice fractions (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeMap {
    /// `A`, row-major: `s = a[0][0]·x + a[0][1]·y + c[0]`.
    pub a: [[f64; 2]; 2],
    /// `c`.
    pub c: [f64; 2],
}

/// The fractional part of `v`, rounded to f32 (it may round to 1).
#[inline]
fn frac32(v: f64) -> f32 {
    (v - v.floor()) as f32
}

impl LatticeMap {
    /// A column's fractions `(frac(A₀₀·x), frac(A₁₀·x))`.
    #[inline]
    #[must_use]
    pub fn column(&self, x: f64) -> [f32; 2] {
        [frac32(self.a[0][0] * x), frac32(self.a[1][0] * x)]
    }

    /// A row's fractions `(frac(A₀₁·y + c₀), frac(A₁₁·y + c₁))`.
    #[inline]
    #[must_use]
    pub fn row(&self, y: f64) -> [f32; 2] {
        [
            frac32(self.a[0][1] * y + self.c[0]),
            frac32(self.a[1][1] * y + self.c[1]),
        ]
    }

    /// The lattice fractions `(s, t)` of a pixel from its column's and row's.
    #[inline]
    #[must_use]
    pub fn fractions(column: [f32; 2], row: [f32; 2]) -> (f32, f32) {
        let s = column[0] + row[0];
        let t = column[1] + row[1];
        (s - s.floor(), t - t.floor())
    }
}

/// The output's value from the squared distance `d2` (cell units²), the parity `odd`, the cell
/// size `cell` and line width `width` (pixels) and `inv_footprint = f32(1/f)` (module docs).
#[inline]
#[must_use]
pub fn output_value(
    output: IslamicOutput,
    d2: f32,
    odd: bool,
    cell: f32,
    width: f32,
    footprint: f32,
    inv_footprint: f32,
) -> f32 {
    let d = d2.sqrt() * cell;
    match output {
        IslamicOutput::Band => {
            let half = 0.5 * width;
            let hi = (d + 0.5 * footprint).min(half);
            let lo = (d - 0.5 * footprint).max(-half);
            (hi - lo).max(0.0) * inv_footprint
        }
        IslamicOutput::Distance => {
            if odd {
                -d
            } else {
                d
            }
        }
        IslamicOutput::Filled => {
            let sd = if odd { -d } else { d };
            (0.5 - sd * inv_footprint).clamp(0.0, 1.0)
        }
    }
}

/// The footprint `f` of a window (pixels, 1 without one) and `f32(1/f)`.
#[must_use]
pub fn footprint(window_footprint: Option<f64>) -> (f32, f32) {
    let f = window_footprint.unwrap_or(1.0);
    (f as f32, (1.0 / f) as f32)
}

impl IslamicPattern {
    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "islamic.cell_size".into(),
            f64::from(self.cell_size),
            4.0,
            4096.0,
            "[4, 4096] pixels",
        )?;
        check_range(
            || "islamic.line_width".into(),
            f64::from(self.line_width),
            0.0,
            f64::from(self.cell_size),
            "[0, cell_size] pixels",
        )?;
        check_range(
            || "islamic.rotation".into(),
            f64::from(self.rotation),
            -360.0,
            360.0,
            "[-360, 360] degrees",
        )?;
        for (k, &v) in self.offset.iter().enumerate() {
            check_range(
                || format!("islamic.offset[{k}]"),
                f64::from(v),
                -1e9,
                1e9,
                "[-1e9, 1e9] pixels",
            )?;
        }
        match self.motif {
            Motif::Contact { angle } => check_range(
                || "islamic.motif.contact.angle".into(),
                f64::from(angle),
                1.0,
                89.0,
                "[1, 89] degrees",
            ),
            Motif::Star { step } => check_range(
                || "islamic.motif.star.step".into(),
                f64::from(step),
                1.0,
                f64::from(MAX_STAR_STEP),
                "[1, 5]",
            ),
        }
    }

    /// The seed's phase `(φ₁, φ₂)` in lattice units (module docs).
    #[must_use]
    pub fn phase(&self) -> [f64; 2] {
        let mut prng = Prng::new(cell_hash(0, 0, ISLAMIC_LAYER, self.seed));
        let a = prng.next_f32();
        let b = prng.next_f32();
        [f64::from(a), f64::from(b)]
    }

    /// The map from pixels to lattice coordinates (module docs).
    #[must_use]
    pub fn lattice_map(&self) -> LatticeMap {
        let [e1, e2] = self.tiling.basis();
        let det = e1[0] * e2[1] - e2[0] * e1[1];
        // B⁻¹ for B = [e₁ e₂] (columns).
        let binv = [[e2[1] / det, -e2[0] / det], [-e1[1] / det, e1[0] / det]];
        let alpha = f64::from(self.rotation).to_radians();
        let (ca, sa) = (alpha.cos(), alpha.sin());
        // R(−α) = [[cos, sin], [−sin, cos]].
        let rot = [[ca, sa], [-sa, ca]];
        let inv_c = 1.0 / f64::from(self.cell_size);
        let mut a = [[0.0; 2]; 2];
        for (i, row) in a.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = (binv[i][0] * rot[0][j] + binv[i][1] * rot[1][j]) * inv_c;
            }
        }
        let o = [f64::from(self.offset[0]), f64::from(self.offset[1])];
        let phase = self.phase();
        let c = [
            -(a[0][0] * o[0] + a[0][1] * o[1]) - phase[0],
            -(a[1][0] * o[0] + a[1][1] * o[1]) - phase[1],
        ];
        LatticeMap { a, c }
    }

    /// The segment table (module docs).
    #[must_use]
    pub fn geometry(&self) -> IslamicGeometry {
        let [e1, e2] = self.tiling.basis();
        let tiles = self.tiling.tiles();
        let centre = [(e1[0] + e2[0]) / 2.0, (e1[1] + e2[1]) / 2.0];
        let half_diagonal = |v: [f64; 2]| (v[0] * v[0] + v[1] * v[1]).sqrt() / 2.0;
        let rho = half_diagonal([e1[0] + e2[0], e1[1] + e2[1]])
            .max(half_diagonal([e1[0] - e2[0], e1[1] - e2[1]]));
        let r_max = tiles.iter().map(Tile::circumradius).fold(0.0, f64::max);
        let mut segments = Vec::new();
        for j in -3i32..=3 {
            for i in -3i32..=3 {
                for tile in &tiles {
                    let moved = Tile {
                        centre: [
                            tile.centre[0] + f64::from(i) * e1[0] + f64::from(j) * e2[0],
                            tile.centre[1] + f64::from(i) * e1[1] + f64::from(j) * e2[1],
                        ],
                        ..*tile
                    };
                    let dc = ((moved.centre[0] - centre[0]).powi(2)
                        + (moved.centre[1] - centre[1]).powi(2))
                    .sqrt();
                    if dc > rho + tile.circumradius() + r_max {
                        continue;
                    }
                    for (a, b) in tile_motif(&moved, self.motif) {
                        let d = [b[0] - a[0], b[1] - a[1]];
                        let len2 = d[0] * d[0] + d[1] * d[1];
                        if len2 < 1e-18 {
                            continue;
                        }
                        segments.extend(
                            [a[0], a[1], b[0], b[1], d[0], d[1], 1.0 / len2].map(|v| v as f32),
                        );
                    }
                }
            }
        }
        IslamicGeometry {
            basis: [e1, e2].map(|e| e.map(|v| v as f32)),
            segments,
        }
    }
}

impl From<IslamicPattern> for crate::Model {
    fn from(model: IslamicPattern) -> Self {
        Self::Islamic(model)
    }
}

impl crate::ModelKind for IslamicPattern {
    const PERIODIC: bool = true;

    const NAME: &'static str = "islamic";

    /// A translation period of the pattern: a square lattice (`square` or `4.8.8` tilings)
    /// turned by a multiple of 90°, whose period's width and height are multiples of the cell
    /// `C` (the pattern repeats every `C` pixels along both axes). A hexagonal lattice has no
    /// axis-aligned period of whole pixels (its rows are `C·√3/2` apart, irrational for a
    /// rational `C`), nor has a lattice turned by another angle.
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let refuse = |requirement: String| {
            Err(ModelError::Period {
                period: period.to_string(),
                kind: "islamic",
                requirement,
            })
        };
        if !matches!(self.tiling, Tiling::Square | Tiling::OctagonSquare) {
            return refuse(
                "islamic.tiling must be \"square\" or \"4.8.8\" for a periodic pattern (the                  hexagonal lattices of \"hexagonal\" and \"3.12.12\" repeat every C·√3/2                  pixels vertically, never a whole number of pixels)"
                    .into(),
            );
        }
        if self.rotation % 90.0 != 0.0 {
            return refuse(format!(
                "islamic.rotation is {}°; a periodic pattern's rotation must be a multiple of                  90° (−360, −270, …, 360) so that its lattice stays axis-aligned",
                self.rotation
            ));
        }
        let cell = f64::from(self.cell_size);
        for (axis, p) in [("width", period.width), ("height", period.height)] {
            if f64::from(p) % cell != 0.0 {
                return refuse(format!(
                    "the period's {axis} {p} must be a multiple of islamic.cell_size = {cell}                      pixels, the pattern's translation period (valid: {cell}, {}, {}, …)",
                    2.0 * cell,
                    3.0 * cell
                ));
            }
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), ModelError> {
        IslamicPattern::validate(self)
    }

    fn visit_seeds(&mut self, visit: &mut dyn FnMut(&mut u32)) {
        visit(&mut self.seed);
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    const TILINGS: [Tiling; 4] = [
        Tiling::Square,
        Tiling::Hexagonal,
        Tiling::OctagonSquare,
        Tiling::DodecagonTriangle,
    ];

    pub fn defaults_validate() {
        IslamicPattern::default().validate().expect("valid");
    }

    pub fn validation_names_the_field_and_range() {
        let d = IslamicPattern::default;
        let cases: Vec<(IslamicPattern, &str)> = vec![
            (
                IslamicPattern {
                    cell_size: 2.0,
                    ..d()
                },
                "islamic.cell_size",
            ),
            (
                IslamicPattern {
                    line_width: 200.0,
                    ..d()
                },
                "islamic.line_width",
            ),
            (
                IslamicPattern {
                    rotation: f32::NAN,
                    ..d()
                },
                "islamic.rotation",
            ),
            (
                IslamicPattern {
                    offset: [0.0, 2e9],
                    ..d()
                },
                "islamic.offset[1]",
            ),
            (
                IslamicPattern {
                    motif: Motif::Contact { angle: 90.0 },
                    ..d()
                },
                "islamic.motif.contact.angle",
            ),
            (
                IslamicPattern {
                    motif: Motif::Star { step: 0 },
                    ..d()
                },
                "islamic.motif.star.step",
            ),
        ];
        for (model, field) in cases {
            let err = model.validate().expect_err(field);
            assert!(err.to_string().starts_with(field), "{field}: {err}");
            assert!(
                err.to_string().contains('['),
                "{field}: {err} names no range"
            );
        }
    }

    /// The tiles of each tiling meet edge to edge: every edge midpoint of every polygon is
    /// also an edge midpoint of exactly one other polygon (of this cell or a neighbour), and
    /// the polygons' areas add up to the cell's.
    pub fn the_tilings_are_edge_to_edge_and_cover_the_cell() {
        for tiling in TILINGS {
            let [e1, e2] = tiling.basis();
            let area: f64 = tiling
                .tiles()
                .iter()
                .map(|t| {
                    let n = f64::from(t.sides);
                    n * t.inradius * t.inradius * (std::f64::consts::PI / n).tan()
                })
                .sum();
            let cell = (e1[0] * e2[1] - e2[0] * e1[1]).abs();
            assert!((area - cell).abs() < 1e-12, "{tiling:?}: {area} vs {cell}");
            let mut mids = Vec::new();
            for j in -2i32..=2 {
                for i in -2i32..=2 {
                    for t in tiling.tiles() {
                        for k in 0..t.sides {
                            let phi = t.normal0
                                + std::f64::consts::TAU * f64::from(k) / f64::from(t.sides);
                            mids.push([
                                t.centre[0]
                                    + f64::from(i) * e1[0]
                                    + f64::from(j) * e2[0]
                                    + t.inradius * phi.cos(),
                                t.centre[1]
                                    + f64::from(i) * e1[1]
                                    + f64::from(j) * e2[1]
                                    + t.inradius * phi.sin(),
                            ]);
                        }
                    }
                }
            }
            for t in tiling.tiles() {
                for k in 0..t.sides {
                    let phi = t.normal0 + std::f64::consts::TAU * f64::from(k) / f64::from(t.sides);
                    let m = [
                        t.centre[0] + t.inradius * phi.cos(),
                        t.centre[1] + t.inradius * phi.sin(),
                    ];
                    let shared = mids
                        .iter()
                        .filter(|p| (p[0] - m[0]).hypot(p[1] - m[1]) < 1e-9)
                        .count();
                    assert_eq!(shared, 2, "{tiling:?} edge {k} of {t:?}");
                }
            }
        }
    }

    /// The square's contact star by hand: for the unit square centred at the origin the rays
    /// of the midpoints (½, 0) and (0, ½) toward the corner (½, ½) meet on the diagonal at
    /// `x = y = cos θ / (2(sin θ + cos θ))`.
    pub fn the_square_contact_points_are_the_closed_form() {
        for angle in [10.0f32, 45.0, 67.5, 80.0] {
            let tile = Tile {
                centre: [0.0, 0.0],
                sides: 4,
                inradius: 0.5,
                normal0: 0.0,
            };
            let segs = tile_motif(&tile, Motif::Contact { angle });
            let th = f64::from(angle).to_radians();
            let m = th.cos() / (2.0 * (th.sin() + th.cos()));
            let (a, x) = segs[0];
            assert!((a[0] - 0.5).abs() < 1e-15 && a[1].abs() < 1e-15, "{a:?}");
            assert!(
                (x[0] - m).abs() < 1e-12 && (x[1] - m).abs() < 1e-12,
                "{angle}: {x:?} vs {m}"
            );
            assert_eq!(segs.len(), 8);
        }
    }

    pub fn tables_stay_within_their_bounds() {
        for tiling in TILINGS {
            for motif in [
                Motif::Contact { angle: 1.0 },
                Motif::Contact { angle: 89.0 },
                Motif::Star { step: 5 },
            ] {
                let g = IslamicPattern {
                    tiling,
                    motif,
                    ..IslamicPattern::default()
                }
                .geometry();
                assert!(g.len() <= MAX_SEGMENTS, "{tiling:?} {motif:?}: {}", g.len());
                assert!(!g.is_empty());
                for s in g.segments.chunks_exact(SEGMENT_FLOATS) {
                    for &v in &s[..4] {
                        assert!(f64::from(v.abs()) <= MAX_COORDINATE, "{tiling:?}: {v}");
                    }
                }
            }
        }
    }

    /// The lattice map of an unrotated square pattern at the origin is `p/C − φ`.
    pub fn the_lattice_map_is_the_inverse_of_the_basis() {
        let m = IslamicPattern {
            tiling: Tiling::Hexagonal,
            rotation: 30.0,
            offset: [5.0, -7.0],
            ..IslamicPattern::default()
        };
        let map = m.lattice_map();
        let [e1, e2] = m.tiling.basis();
        let (s, t) = (0.25, 0.625);
        let phase = m.phase();
        // The pattern point (s + φ₁)e₁ + (t + φ₂)e₂, rotated by α, scaled and offset.
        let u = [
            (s + phase[0]) * e1[0] + (t + phase[1]) * e2[0],
            (s + phase[0]) * e1[1] + (t + phase[1]) * e2[1],
        ];
        let al = 30f64.to_radians();
        let c = f64::from(m.cell_size);
        let p = [
            c * (al.cos() * u[0] - al.sin() * u[1]) + 5.0,
            c * (al.sin() * u[0] + al.cos() * u[1]) - 7.0,
        ];
        let got = [
            map.a[0][0] * p[0] + map.a[0][1] * p[1] + map.c[0],
            map.a[1][0] * p[0] + map.a[1][1] * p[1] + map.c[1],
        ];
        assert!(
            (got[0] - s).abs() < 1e-12 && (got[1] - t).abs() < 1e-12,
            "{got:?}"
        );
    }
}
