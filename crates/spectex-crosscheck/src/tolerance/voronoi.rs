//! Voronoi diagrams: their tolerances and the criterion of their discontinuous outputs.
//!
//! Both evaluators read the same f32 sites (the host computes the GPU's table with
//! `spectex_model::voronoi`) and the same pixel offsets, and run the same f32 search
//! (`spectex_model::voronoi::search`). They differ only where the GPU rounds differently: a
//! reassociated `(di + o) − f`, a contracted `d_x·d_x + d_y·d_y`, WGSL's `sqrt` and `/` (2.5 ulp
//! instead of correctly rounded). The continuous outputs (`F1`, `F2 − F1`, the border) are then
//! within a derived bound everywhere; the cell ID and the colours are equal wherever both sides
//! pick the same nearest seed, and may differ only where the two nearest seeds are tied within
//! the rounding: a pixel whose `F2 − F1` (a companion render) is at most [`FLIP_MARGIN`].
//!
//! A 3D diagram's bounds are derived the same way with three components per vector (one more
//! product and sum per `d²` and dot product, `√3` instead of `√2`), its larger reach and
//! distances (`F1 < √3`, `F2 < √6`), and one allowance more: both sides skip the cells whose
//! bound exceeds what they found (`spectex_model::voronoi::search3`), the GPU with its own
//! rounding of the bound, so a seed it skips has a `d²` within the bound's and `d²`'s roundings
//! of the limit (`D2_ROUNDINGS_3D`); the border's skipping margin is far above any
//! rounding. The checked plane is [`CHECK_PLANE_Z`].

use spectex_model::Model;
use spectex_model::voronoi::{BORDER_REACH, BORDER_REACH_3D, VoronoiNoise, VoronoiOutput};

use super::{CheckKind, F32_UNIT_ROUNDOFF, Regularity, Tolerance};

/// Largest `|d_x|`, `|d_y|` of a searched seed, cell units: the search reaches 3 cells and an
/// offset is below 1.
const D_COMPONENT: f64 = (BORDER_REACH + 1) as f64;
/// `F1 < √2` and `F2 < √5` (`spectex_model::voronoi`'s module docs).
const F1_MAX: f64 = std::f64::consts::SQRT_2;
/// See [`F1_MAX`].
const F2_MAX: f64 = 2.236_067_977_499_79;
/// Roundings of `d² = d_x² + d_y²` relative to `d²`: two products and a sum on either side,
/// any of which a contraction may skip: 3 per side, 6 between them.
const D2_ROUNDINGS: f64 = 6.0;
/// Roundings of a square root relative to its value: 2.5 ulp in WGSL, 0.5 on the CPU.
const SQRT_ROUNDINGS: f64 = 3.0;
/// Roundings of the border term `((d_q + d_n)·(d_q − d_n))·½ / √(e²)` relative to
/// `|d_q + d_n|/2` (the sums and differences 4, the dot product 3, the square root and the
/// quotient 3 + 3 in WGSL): 13 per side, 26 between them.
const BORDER_ROUNDINGS: f64 = 26.0;

/// The plane `z` (pixels) on which a 3D diagram is checked: off the lattice planes of the
/// shipped cases' cells and far enough from 0 that the planes' cells are far from the origin.
pub const CHECK_PLANE_Z: f64 = 12_345.6;

/// The 3D counterparts of the 2D constants above (module docs).
const D_COMPONENT_3D: f64 = (BORDER_REACH_3D + 1) as f64;
/// `F1 < √3` and `F2 < √6` (`spectex_model::voronoi`'s module docs).
const F1_MAX_3D: f64 = 1.732_050_807_568_877_2;
/// See [`F1_MAX_3D`].
const F2_MAX_3D: f64 = 2.449_489_742_783_178;
/// `d² = (d_x² + d_y²) + d_z²`: three products and two sums per side (10), and as many again
/// for the pruning bound the GPU rounds its own way (a skipped seed's `d²` is within the bound's
/// and its own roundings of the limit).
const D2_ROUNDINGS_3D: f64 = 20.0;
/// The border term in 3D: sums and differences 6, the dot product 5, the square root and the
/// quotient 3 + 3 in WGSL: 17 per side, 34 between them.
const BORDER_ROUNDINGS_3D: f64 = 34.0;

/// The constants of a diagram's dimensions.
#[derive(Debug, Clone, Copy)]
struct Dims {
    /// Components per vector.
    axes: f64,
    /// [`D_COMPONENT`] or [`D_COMPONENT_3D`].
    d_component: f64,
    f1_max: f64,
    f2_max: f64,
    d2_roundings: f64,
    border_roundings: f64,
}

impl Dims {
    /// The plane's.
    const TWO: Self = Self {
        axes: 2.0,
        d_component: D_COMPONENT,
        f1_max: F1_MAX,
        f2_max: F2_MAX,
        d2_roundings: D2_ROUNDINGS,
        border_roundings: BORDER_ROUNDINGS,
    };
    /// Space's.
    const THREE: Self = Self {
        axes: 3.0,
        d_component: D_COMPONENT_3D,
        f1_max: F1_MAX_3D,
        f2_max: F2_MAX_3D,
        d2_roundings: D2_ROUNDINGS_3D,
        border_roundings: BORDER_ROUNDINGS_3D,
    };

    fn of(m: &VoronoiNoise) -> Self {
        if m.dimensions == 3 {
            Self::THREE
        } else {
            Self::TWO
        }
    }

    /// Difference between the two sides of one component of `d = (di + o) − f`: two roundings
    /// of values below the largest component on either side.
    fn d_component_error(self) -> f64 {
        4.0 * self.d_component * F32_UNIT_ROUNDOFF
    }

    /// The difference of a seed's vector `d` between the two sides, `|δd| ≤ √axes·δd_x`.
    fn d_error(self) -> f64 {
        self.axes.sqrt() * self.d_component_error()
    }

    /// [`FLIP_MARGIN`]'s derivation with these constants.
    fn flip_margin(self) -> f64 {
        2.0 * (2.0 * self.d_error()
            + self.d2_roundings * F32_UNIT_ROUNDOFF * (self.f1_max + self.f2_max))
    }

    /// `distance_error`'s derivation with these constants.
    fn distance_error(self, f_max: f64) -> f64 {
        self.d_error() + (self.d2_roundings / 2.0 + SQRT_ROUNDINGS) * F32_UNIT_ROUNDOFF * f_max
    }

    /// `border_error`'s derivation with these constants.
    fn border_error(self, separation: f64) -> f64 {
        let s_max = 2.0 * self.axes.sqrt() * self.d_component;
        let smooth = self.d_error() * (1.0 + 2.0 * s_max / separation)
            + self.border_roundings * F32_UNIT_ROUNDOFF * s_max / 2.0;
        let flipped = (self.f1_max + self.f2_max) * self.flip_margin() / (2.0 * separation);
        smooth.max(flipped)
    }
}

/// [`FLIP_MARGIN`] of a 3D diagram.
pub fn flip_margin_3d() -> f64 {
    Dims::THREE.flip_margin()
}

/// The largest `F2 − F1` at which the two sides may pick different nearest seeds: a flip needs
/// `|d_q|² − |d_n|² ≤ |δ(d_q²)| + |δ(d_n²)|`, each `≤ 2|d|·|δd| + D2_ROUNDINGS·u·d²`, so
/// `F2 − F1 = (F2² − F1²)/(F2 + F1) ≤ 2|δd| + D2_ROUNDINGS·u·(F1 + F2)`, doubled for the two
/// candidates.
pub const FLIP_MARGIN: f64 = 2.0
    * (2.0 * std::f64::consts::SQRT_2 * 4.0 * D_COMPONENT * F32_UNIT_ROUNDOFF
        + D2_ROUNDINGS * F32_UNIT_ROUNDOFF * (F1_MAX + F2_MAX));

/// `|δF|` of a distance `F ≤ f_max`, the smallest `d²` (or the second smallest) of candidates
/// whose `d²` differ by at most `2|d|·|δd| + D2_ROUNDINGS·u·d²`: an order statistic is
/// 1-Lipschitz in its inputs, and `√` turns the error into `|δd| + (D2_ROUNDINGS/2)·u·F` plus
/// the square roots' roundings.
#[cfg(feature = "unit-tests")]
fn distance_error(f_max: f64) -> f64 {
    Dims::TWO.distance_error(f_max)
}

/// The smallest distance between two seeds: `1 − jitter` (each seed lies in its cell's jitter
/// square, relaxed or not), `None` for a jitter of 1, where seeds can be arbitrarily close.
fn separation(m: &VoronoiNoise) -> Option<f64> {
    let s = 1.0 - f64::from(m.jitter);
    (s > 0.0).then_some(s)
}

/// The border's bound: a bisector's distance `b_q = (s·e)/(2|e|)` with `s = d_q + d_n` and
/// `e = d_q − d_n` moves by at most `|δs|/2 + |s|·|δe|/|e|` when the vectors move by `|δd|`
/// each (`|δs|, |δe| ≤ 2|δd|`, the unit vector by `2|δe|/|e|`), with `|s| ≤ 2√2·D_COMPONENT`
/// and `|e|` at least the seeds' separation, plus [`BORDER_ROUNDINGS`]; the minimum over `q`
/// keeps it. Where the nearest seed flips both sides' borders are at most
/// `(F2² − F1²)/(2|e|) ≤ (F1 + F2)·FLIP_MARGIN/(2·separation)`, which also bounds their
/// difference.
#[cfg(feature = "unit-tests")]
fn border_error(separation: f64) -> f64 {
    Dims::TWO.border_error(separation)
}

/// The largest jump of a discontinuous output: the ID's range, or the largest difference of a
/// colour component between two palette entries or texels.
fn jumps(m: &VoronoiNoise) -> Vec<f64> {
    let spread = |colours: &[[f32; 3]], c: usize| {
        let (lo, hi) = colours
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(f64::from(v[c])), hi.max(f64::from(v[c])))
            });
        hi - lo
    };
    match &m.output {
        VoronoiOutput::Palette { colours } => (0..3).map(|c| spread(colours, c)).collect(),
        VoronoiOutput::Image { texels, .. } => (0..3).map(|c| spread(texels, c)).collect(),
        _ => vec![1.0],
    }
}

impl CheckKind for VoronoiNoise {
    /// `F1`, `F2 − F1` and the border by their bounds above (the border only for a jitter
    /// below 1, `None` otherwise); the ID and colours show their largest jump, for reports,
    /// and are judged by [`own_verdict`](Self::own_verdict).
    fn tolerances(&self) -> Option<Vec<Tolerance>> {
        let dims = Dims::of(self);
        match &self.output {
            VoronoiOutput::F1 => Some(vec![Tolerance::from_max(dims.distance_error(dims.f1_max))]),
            VoronoiOutput::F2MinusF1 => Some(vec![Tolerance::from_max(
                dims.distance_error(dims.f1_max)
                    + dims.distance_error(dims.f2_max)
                    + F32_UNIT_ROUNDOFF * dims.f2_max,
            )]),
            VoronoiOutput::Border => {
                separation(self).map(|s| vec![Tolerance::from_max(dims.border_error(s))])
            }
            VoronoiOutput::CellId | VoronoiOutput::Palette { .. } | VoronoiOutput::Image { .. } => {
                Some(jumps(self).into_iter().map(Tolerance::from_max).collect())
            }
        }
    }

    /// `F1` and the border are 1-Lipschitz (a distance to a set), `F2 − F1` 2-Lipschitz, per
    /// cell unit: per pixel `1/C` and `2/C`. The ID and colours jump at every border: none.
    fn regularity(&self) -> Option<Regularity> {
        let cell = f64::from(self.cell_size);
        let dims = Dims::of(self);
        let (slope, magnitude) = match self.output {
            VoronoiOutput::F1 => (1.0, dims.f1_max),
            VoronoiOutput::Border => (1.0, dims.f1_max),
            VoronoiOutput::F2MinusF1 => (2.0, dims.f2_max),
            _ => return None,
        };
        Some(Regularity {
            slope: slope / cell,
            jump: 0.0,
            magnitude,
            cell,
        })
    }

    /// The same diagram's `F2 − F1` for the discontinuous outputs.
    fn companions(&self) -> Vec<Model> {
        match self.output {
            VoronoiOutput::CellId | VoronoiOutput::Palette { .. } | VoronoiOutput::Image { .. } => {
                vec![Model::Voronoi(VoronoiNoise {
                    output: VoronoiOutput::F2MinusF1,
                    ..self.clone()
                })]
            }
            _ => Vec::new(),
        }
    }

    /// A 3D diagram's plane [`CHECK_PLANE_Z`].
    fn check_plane(&self) -> f64 {
        if self.dimensions == 3 {
            CHECK_PLANE_Z
        } else {
            0.0
        }
    }

    /// The ID and colours: every pixel equal on both sides unless its `F2 − F1` on the CPU is
    /// at most [`FLIP_MARGIN`] (the two nearest seeds tied within the rounding; in 3D
    /// [`flip_margin_3d`]).
    fn own_verdict(
        &self,
        renders: &[(Vec<f32>, Vec<f32>)],
        footprint: Option<f64>,
    ) -> Option<Vec<String>> {
        let _ = footprint;
        let [(cpu, gpu), (margin, _)] = renders else {
            return None;
        };
        let channels = self.output.channels();
        let flip = Dims::of(self).flip_margin();
        let bad = cpu
            .chunks_exact(channels)
            .zip(gpu.chunks_exact(channels))
            .zip(margin)
            .filter(|((a, b), m)| a != b && f64::from(**m) > flip)
            .count();
        Some(if bad == 0 {
            Vec::new()
        } else {
            vec![format!(
                "{bad} pixels differ where the nearest seed is unambiguous (F2 − F1 > {flip:.1e})"
            )]
        })
    }
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn bounds_are_small_against_a_cell() {
        // A few hundred unit roundoffs of cell units: far below anything visible.
        const { assert!(FLIP_MARGIN < 1e-5) };
        assert!(distance_error(F2_MAX) < 1e-5);
        // Seeds 0.1 cell apart: the border's bound stays below 1e-3 cell.
        assert!(border_error(0.1) < 1e-3, "{}", border_error(0.1));
        assert!(separation(&VoronoiNoise::default()).is_none());
        // The 2D derivation through `Dims` is the constant's.
        assert!((Dims::TWO.flip_margin() - FLIP_MARGIN).abs() <= 1e-6 * FLIP_MARGIN);
        // 3D: more roundings and larger vectors (|d_x| up to 5 cells: the 9×9×9 border
        // search), about 306 unit roundoffs, still tiny against a cell.
        assert!(flip_margin_3d() > FLIP_MARGIN && flip_margin_3d() < 2e-5);
        assert!(Dims::THREE.distance_error(F2_MAX_3D) < 1e-5);
        assert!(Dims::THREE.border_error(0.1) < 1e-3);
        // √3 and √6.
        assert!((F1_MAX_3D - 3f64.sqrt()).abs() < 1e-15 && (F2_MAX_3D - 6f64.sqrt()).abs() < 1e-15);
    }

    pub fn the_verdict_excuses_only_ambiguous_pixels() {
        let m = VoronoiNoise::default();
        let renders = |margin: f32| {
            vec![
                (vec![0.25f32, 0.5], vec![0.25f32, 0.75]),
                (vec![1.0f32, margin], vec![1.0f32, margin]),
            ]
        };
        assert_eq!(m.own_verdict(&renders(0.0), None), Some(Vec::new()));
        assert_eq!(m.own_verdict(&renders(0.5), None).map(|w| w.len()), Some(1));
    }
}
