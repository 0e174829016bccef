//! Classic noises on the host: a [`ClassicNoise`] into the words of `ClassicParams` and of the
//! octave table of `shaders/classic.wgsl`, and a tile's columns and rows into `ClassicAxis`
//! records (the f64 work: cells, f32 offsets, and the per-axis parts of simplex noise's skewed
//! coordinates).

use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, FractalKind, Metric, SIMPLEX_F2, SIMPLEX_F3,
    WORLEY_MAX_POINTS, WORLEY_MAX_RING,
};
use spectex_model::random::layer_key;

/// Bytes of one `ClassicAxis` record (cell, offset, and two skew parts as cell + fraction),
/// per octave.
pub(crate) const CLASSIC_AXIS_BYTES: u64 = 24;
/// Words of `ClassicParams`.
const PARAM_WORDS: usize = 40;

/// A classic noise as buffer words, plus what the host needs per tile.
#[derive(Debug, Clone)]
pub(crate) struct ClassicPack {
    /// The words of `ClassicParams`; words 0 and 1 (width, height) are set per tile.
    pub params: [u32; PARAM_WORDS],
    /// `ClassicOctave` records.
    pub octaves: Vec<u32>,
    /// Cell side of each octave, pixels (f64, as the CPU divides by it).
    sides: Vec<f64>,
    /// The simplex skew factor `F` of the model's dimension.
    skew: f64,
}

/// `(⌊p⌋ as i32, f32(p − ⌊p⌋))`, the CPU's split (`spectex_cpu::classic`'s `locate`): exact in
/// f64, rounded to f32 once. `|p| ≤ 2³¹` for every validated model and window, so the cell fits;
/// it wraps as the CPU's does beyond.
fn split(p: f64) -> (u32, u32) {
    let cell = p.floor();
    (cell as i64 as i32 as u32, ((p - cell) as f32).to_bits())
}

/// Words per octave of the octave table (`ClassicOctave` in `shaders/classic.wgsl`).
const OCTAVE_WORDS: usize = 9;

impl ClassicPack {
    /// Packs a validated model for the plane `z` (ignored in 2D).
    pub(crate) fn new(model: &ClassicNoise, z: f64) -> Self {
        let three_d = model.dimensions == 3;
        let skew = if three_d { SIMPLEX_F3 } else { SIMPLEX_F2 };
        let mut octaves = Vec::with_capacity(OCTAVE_WORDS * model.octaves() as usize);
        let mut sides = Vec::with_capacity(model.octaves() as usize);
        for o in 0..model.octaves() {
            let side = model.octave_cell(o);
            sides.push(side);
            let (z_cell, z_offset, z_other, z_own) = if three_d {
                let pz = z / side;
                let (cell, offset) = split(pz);
                let other = pz * skew;
                (cell, offset, split(other), split(pz + other))
            } else {
                (0, 0, (0, 0), (0, 0))
            };
            octaves.extend([
                model.octave_weight(o).to_bits(),
                z_cell,
                z_offset,
                layer_key(o, model.seed),
                z_other.0,
                z_other.1,
                z_own.0,
                z_own.1,
                ((1.0 / side) as f32).to_bits(),
            ]);
        }
        let mut params = [0u32; PARAM_WORDS];
        params[2] = model.seed;
        params[3] = model.octaves();
        params[4] = match model.basis {
            Basis::Gradient => 0,
            Basis::Simplex => 1,
            Basis::Value => 2,
            Basis::Worley(_) => 3,
        };
        params[5] = u32::from(three_d);
        let kind = model.fractal.as_ref().map(|f| f.kind);
        params[6] = match kind {
            None | Some(FractalKind::Fbm) => 0,
            Some(FractalKind::Turbulence) => 1,
            Some(FractalKind::Ridged { .. }) => 2,
        };
        if let Some(FractalKind::Ridged {
            offset,
            weight_gain,
        }) = kind
        {
            params[14] = offset.to_bits();
            params[15] = weight_gain.to_bits();
        }
        params[12] = model.amplitude.to_bits();
        params[13] = model.mean.to_bits();
        if let Basis::Worley(w) = &model.basis {
            params[7] = match w.metric {
                Metric::Euclidean => 0,
                Metric::Manhattan => 1,
                Metric::Chebyshev => 2,
            };
            params[8] = match w.points {
                FeaturePoints::Fixed(n) => n,
                FeaturePoints::Poisson(_) => 0,
            };
            params[9] = (w.needed() - 1) as u32;
            for (k, c) in w.coefficients.iter().enumerate() {
                params[16 + k] = c.to_bits();
            }
            // The CPU's cap: WORLEY_MAX_RING + 1 cells, squared for the Euclidean metric.
            let cap = (WORLEY_MAX_RING + 1) as f32;
            let cap = if w.metric == Metric::Euclidean {
                cap * cap
            } else {
                cap
            };
            params[20] = cap.to_bits();
            let cdf = w
                .points
                .poisson_cdf()
                .unwrap_or([0.0; WORLEY_MAX_POINTS as usize]);
            for (k, p) in cdf.iter().enumerate() {
                params[24 + k] = p.to_bits();
            }
        }
        Self {
            params,
            octaves,
            sides,
            skew,
        }
    }

    /// Octaves of the model.
    pub(crate) fn octave_count(&self) -> usize {
        self.sides.len()
    }

    /// `ClassicAxis` records for `count` positions `position(i)`, octave-major: `p = x / c_o`
    /// split as the CPU splits it, and the skew parts `p·(1 + F)` and `p·F`, each split into an
    /// integer and an f32 fraction in f64.
    pub(crate) fn axis(&self, count: usize, position: impl Fn(usize) -> f64) -> Vec<u32> {
        let mut words = Vec::with_capacity(6 * count * self.sides.len());
        for &side in &self.sides {
            for i in 0..count {
                let p = position(i) / side;
                let (cell, offset) = split(p);
                let other = p * self.skew;
                let (own_cell, own_frac) = split(p + other);
                let (other_cell, other_frac) = split(other);
                words.extend([cell, offset, own_cell, own_frac, other_cell, other_frac]);
            }
        }
        words
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spectex_model::classic::{Fractal, Worley};

    fn model(basis: Basis, dimensions: u32) -> ClassicNoise {
        ClassicNoise {
            seed: 9,
            dimensions,
            cell_size: 16.0,
            basis,
            fractal: Some(Fractal {
                kind: FractalKind::Ridged {
                    offset: 1.0,
                    weight_gain: 2.0,
                },
                octaves: 3,
                lacunarity: 2.0,
                gain: 0.5,
            }),
            amplitude: 0.5,
            mean: 0.25,
        }
    }

    /// The skewed coordinate `X = p_x + (p_x + p_y)·F` rebuilt from the column's own part and the
    /// row's other part (integers plus fractions) is the f64 value within f32 rounding, far away.
    #[test]
    fn skew_parts_add_up_to_the_skewed_coordinate() {
        let pack = ClassicPack::new(&model(Basis::Simplex, 2), 0.0);
        let (x, y) = (1.0e7 + 0.3, -3.0e6 + 0.7);
        let cols = pack.axis(1, |_| x);
        let rows = pack.axis(1, |_| y);
        let (px, py) = (x / 16.0, y / 16.0);
        let want = px + (px + py) * SIMPLEX_F2;
        let int = f64::from(cols[2] as i32) + f64::from(rows[4] as i32);
        let frac = f64::from(f32::from_bits(cols[3])) + f64::from(f32::from_bits(rows[5]));
        assert!((int + frac - want).abs() < 2e-7, "{} vs {want}", int + frac);
        // The lattice split is the exact floor and the rounded remainder.
        assert_eq!(cols[0] as i32, px.floor() as i32);
        assert_eq!(f32::from_bits(cols[1]), (px - px.floor()) as f32);
    }

    #[test]
    fn params_and_octaves_carry_the_model() {
        let w = Worley {
            metric: Metric::Euclidean,
            coefficients: [-1.0, 1.0, 0.0, 0.0],
            points: FeaturePoints::Poisson(2.0),
        };
        let pack = ClassicPack::new(&model(Basis::Worley(w), 3), 40.0);
        assert_eq!(pack.params[3], 3);
        assert_eq!(pack.params[4], 3);
        assert_eq!(pack.params[6], 2);
        assert_eq!(pack.params[9], 1);
        assert_eq!(f32::from_bits(pack.params[20]), 49.0);
        assert_eq!(pack.octaves.len(), 3 * OCTAVE_WORDS);
        // Octave 1: side 8, z = 40 is cell 5, offset 0, weight ½.
        let o = OCTAVE_WORDS;
        assert_eq!(f32::from_bits(pack.octaves[o]), 0.5);
        assert_eq!(pack.octaves[o + 1], 5);
        assert_eq!(f32::from_bits(pack.octaves[o + 2]), 0.0);
        assert_eq!(pack.octaves[o + 3], layer_key(1, 9));
        // z·F3 = 5/3 and z·(1 + F3) = 20/3 in cells of octave 1.
        assert_eq!(pack.octaves[o + 4], 1);
        assert_eq!(pack.octaves[o + 6], 6);
        // 1/8 cell per pixel, for warping.
        assert_eq!(f32::from_bits(pack.octaves[o + 8]), 0.125);
    }
}
