//! Classic noises on the device (`shaders/classic.wgsl`): a [`ClassicNoise`] into the uniform
//! and the octave table, and a tile's columns and rows into [`ClassicAxis`] records (the f64
//! work: cells, f32 offsets, and the per-axis parts of simplex noise's skewed coordinates).
//!
//! The classic noise's export (the glue of `shaders/classic.wgsl`): the compute shader's uniform
//! and octave table; per octave three lattices (the cell and, for simplex noise, the two
//! parts of the skew).

use spectex_model::Period;
use spectex_model::classic::{
    Basis, ClassicNoise, FeaturePoints, FractalKind, Metric, SIMPLEX_F2, SIMPLEX_F3,
    WORLEY_MAX_POINTS, WORLEY_MAX_RING,
};
use spectex_model::random::layer_key;

use crate::axis::{periodic_columns, periodic_rows};
use crate::export::{ExportKind, ExportNode, ExportParts};
use crate::kernel::{GpuKernel, GpuKind, ShaderKernel, Table, TileDisplacement, TileTables};
use crate::layout::wgsl_struct;
use crate::pipeline::Shaded;
use crate::shaders::{ShaderFile, kernel_and_glue};
use crate::{GpuContext, GpuError, GpuWindow};

/// `shaders/classic.wgsl`: the compute shader, then the export glue.
const WGSL: (&str, &str) = kernel_and_glue(include_str!("../shaders/classic.wgsl"));

wgsl_struct! {
    /// `ClassicParams` of `classic.wgsl`; `width` and `height` are the tile's.
    pub(crate) struct ClassicParams {
        width: u32,
        height: u32,
        seed: u32,
        octaves: u32,
        /// 0 gradient, 1 simplex, 2 value, 3 Worley.
        basis: u32,
        /// 1 for a 3D model (on the plane `z` of the octave table), 0 for 2D.
        three_d: u32,
        /// 0 none or fBm, 1 turbulence, 2 ridged.
        fractal: u32,
        /// Worley: 0 Euclidean, 1 Manhattan, 2 Chebyshev.
        metric: u32,
        /// Worley: the fixed count of points per cell, or 0 for a Poisson count.
        fixed_count: u32,
        /// Worley: `n − 1` for the largest `n` with `C_n ≠ 0`.
        needed: u32,
        /// 1: a minified render, each octave taken as the per-tile fade table says.
        filtered: u32,
        // Padding: `amplitude` starts the next 16-byte row in the WGSL struct.
        _pad1: u32,
        amplitude: f32,
        mean: f32,
        ridge_offset: f32,
        weight_gain: f32,
        /// Worley: `C₁..C₄` (a `vec4<f32>`).
        coefficients: [f32; 4],
        /// Worley: the largest distance kept (squared for the Euclidean metric).
        cap: f32,
        // Padding: `cdf` is an array of `vec4<f32>`, aligned to 16 bytes.
        _pad2: u32,
        _pad3: u32,
        _pad4: u32,
        /// Worley: the Poisson CDF `P(N ≤ k)`, `k = 0..15`, as four `vec4<f32>`.
        cdf: [[f32; 4]; 4],
    }
}

wgsl_struct! {
    /// `ClassicOctave` of `classic.wgsl`.
    pub(crate) struct ClassicOctave {
        /// `gain^o`.
        weight: f32,
        /// The plane `z`: its cell and offset (lattice bases and Worley, 3D).
        z_cell: i32,
        z_offset: f32,
        /// `layer_key(o, seed)`, for 2D hashes.
        key2: u32,
        /// The plane `z`'s parts of the skewed coordinates (simplex, 3D; zero in 2D): `pz·F`
        /// and `pz·(1 + F)`, each as cell + fraction.
        z_other_cell: i32,
        z_other_frac: f32,
        z_own_cell: i32,
        z_own_frac: f32,
        /// `1/c_o` (f32 of the f64 value), for warping.
        inv_cell: f32,
        /// Cells per period along x and y of a periodic model (0: not periodic): the
        /// lattice coordinates entering the hash wrap modulo them (`wrap_cell`).
        cells_x: i32,
        cells_y: i32,
        /// To a 16-byte stride, as a uniform array's element must be.
        _pad0: u32,
    }
}

wgsl_struct! {
    /// `ClassicAxis` of `classic.wgsl`: per octave, `p = x / c_o` split as the CPU splits it,
    /// and the skew parts `p·(1 + F)` (own) and `p·F` (other), each split into an integer and an
    /// f32 fraction in f64.
    pub(crate) struct ClassicAxis {
        cell: i32,
        offset: f32,
        own_cell: i32,
        own_frac: f32,
        other_cell: i32,
        other_frac: f32,
    }
}

/// A classic noise on the device: its uniform (tile size set per tile) and what the host needs
/// per tile.
#[derive(Debug, Clone)]
pub(crate) struct ClassicKernel {
    /// The model, for the octave weights of a footprint.
    model: ClassicNoise,
    params: ClassicParams,
    /// Cell side of each octave, pixels (f64, as the CPU divides by it).
    pub(crate) sides: Vec<f64>,
    /// The simplex skew factor `F` of the model's dimension.
    pub(crate) skew: f64,
    /// The basis's statistics for a minified render's fade, measured on first use, as the CPU
    /// measures them.
    statistics: std::sync::OnceLock<spectex_model::filter::BasisStatistics>,
    /// The period of a periodic model: positions reduced modulo it.
    period: Option<Period>,
    /// No shape constants (the uniform decides every branch, as in the export): the test's
    /// reference for the specialised pipelines.
    generic: bool,
}

/// `(⌊p⌋ as i32, f32(p − ⌊p⌋))`, the CPU's split (`spectex_cpu::classic`'s `locate`): exact in
/// f64, rounded to f32 once. `|p| ≤ 2³¹` for every validated model and window, so the cell fits;
/// it wraps as the CPU's does beyond.
fn split(p: f64) -> (i32, f32) {
    let cell = p.floor();
    (cell as i64 as i32, (p - cell) as f32)
}

/// The octave records as `classic.wgsl`'s uniform table of `MAX_OCTAVES` (a validated model has
/// no more).
fn octave_table(octaves: &[ClassicOctave]) -> Result<Table, GpuError> {
    Table::uniform(
        "classic octaves",
        "octaves of a classic noise",
        octaves,
        spectex_model::classic::MAX_OCTAVES as usize,
    )
}

/// Packs a validated model for the plane `z` (ignored in 2D): the kernel and the octave table.
pub(crate) fn pack(model: &ClassicNoise, z: f64) -> (ClassicKernel, Vec<ClassicOctave>) {
    pack_periodic(model, z, None)
}

/// [`pack`], periodic with `period` (every octave's cell divides it: `check_period`).
fn pack_periodic(
    model: &ClassicNoise,
    z: f64,
    period: Option<Period>,
) -> (ClassicKernel, Vec<ClassicOctave>) {
    let three_d = model.dimensions == 3;
    let skew = if three_d { SIMPLEX_F3 } else { SIMPLEX_F2 };
    let mut octaves = Vec::with_capacity(model.octaves() as usize);
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
            (0, 0.0, (0, 0.0), (0, 0.0))
        };
        octaves.push(ClassicOctave {
            weight: model.octave_weight(o),
            z_cell,
            z_offset,
            key2: layer_key(o, model.seed),
            z_other_cell: z_other.0,
            z_other_frac: z_other.1,
            z_own_cell: z_own.0,
            z_own_frac: z_own.1,
            inv_cell: (1.0 / side) as f32,
            cells_x: period.map_or(0, |p| p.cells(side)[0] as i32),
            cells_y: period.map_or(0, |p| p.cells(side)[1] as i32),
            _pad0: 0,
        });
    }
    let kind = model.fractal.as_ref().map(|f| f.kind);
    let mut params = ClassicParams {
        seed: model.seed,
        octaves: model.octaves(),
        basis: match model.basis {
            Basis::Gradient => 0,
            Basis::Simplex => 1,
            Basis::Value => 2,
            Basis::Worley(_) => 3,
            Basis::Kensler => 4,
        },
        three_d: u32::from(three_d),
        fractal: match kind {
            None | Some(FractalKind::Fbm) => 0,
            Some(FractalKind::Turbulence) => 1,
            Some(FractalKind::Ridged { .. }) => 2,
        },
        amplitude: model.amplitude,
        mean: model.mean,
        ..bytemuck::Zeroable::zeroed()
    };
    if let Some(FractalKind::Ridged {
        offset,
        weight_gain,
    }) = kind
    {
        params.ridge_offset = offset;
        params.weight_gain = weight_gain;
    }
    if let Basis::Worley(w) = &model.basis {
        params.metric = match w.metric {
            Metric::Euclidean => 0,
            Metric::Manhattan => 1,
            Metric::Chebyshev => 2,
        };
        params.fixed_count = match w.points {
            FeaturePoints::Fixed(n) => n,
            FeaturePoints::Poisson(_) => 0,
        };
        params.needed = (w.needed() - 1) as u32;
        params.coefficients = w.coefficients;
        // The CPU's cap: WORLEY_MAX_RING + 1 cells, squared for the Euclidean metric.
        let cap = (WORLEY_MAX_RING + 1) as f32;
        params.cap = if w.metric == Metric::Euclidean {
            cap * cap
        } else {
            cap
        };
        let cdf = w
            .points
            .poisson_cdf()
            .unwrap_or([0.0; WORLEY_MAX_POINTS as usize]);
        params.cdf = bytemuck::cast(cdf);
    }
    (
        ClassicKernel {
            model: model.clone(),
            params,
            sides,
            skew,
            statistics: std::sync::OnceLock::new(),
            period,
            generic: false,
        },
        octaves,
    )
}

impl ClassicKernel {
    /// [`ClassicAxis`] records for `count` positions `position(i)`, octave-major.
    fn axis(&self, count: usize, position: impl Fn(usize) -> f64) -> Vec<ClassicAxis> {
        let mut records = Vec::with_capacity(count * self.sides.len());
        for &side in &self.sides {
            for i in 0..count {
                let p = position(i) / side;
                let (cell, offset) = split(p);
                let other = p * self.skew;
                let (own_cell, own_frac) = split(p + other);
                let (other_cell, other_frac) = split(other);
                records.push(ClassicAxis {
                    cell,
                    offset,
                    own_cell,
                    own_frac,
                    other_cell,
                    other_frac,
                });
            }
        }
        records
    }
}

impl GpuKind for ClassicNoise {
    const SHADER: Option<ShaderFile> = Some(ShaderFile {
        name: "classic",
        source: WGSL.0,
        needs_common: true,
        entry_points: &["classic_main"],
    });

    fn kernel_with_period(
        &self,
        context: &GpuContext,
        z: f64,
        period: Option<Period>,
    ) -> Result<Box<dyn GpuKernel>, GpuError> {
        let (kernel, octaves) = pack_periodic(self, z, period);
        Shaded::boxed(context, kernel, &[octave_table(&octaves)?])
    }
}

impl ShaderKernel for ClassicKernel {
    const SHADER: &'static str = "classic";
    const ENTRY_POINT: &'static str = "classic_main";

    const SHAPE: &'static [&'static str] = &[
        "CLASSIC_BASIS",
        "CLASSIC_THREE_D",
        "CLASSIC_FRACTAL",
        "CLASSIC_METRIC",
        "CLASSIC_PERIODIC",
        "CLASSIC_FIXED_COUNT",
        "CLASSIC_NEEDED",
    ];

    /// The model's basis, dimension, fractal and Worley metric, and whether it is periodic.
    fn shape(&self) -> Vec<u32> {
        let p = &self.params;
        if self.generic {
            return Vec::new();
        }
        vec![
            p.basis,
            p.three_d,
            p.fractal,
            p.metric,
            u32::from(self.period.is_some()),
            p.fixed_count,
            p.needed,
        ]
    }

    fn axis_bytes(&self) -> u64 {
        (size_of::<ClassicAxis>() * self.sides.len()) as u64
    }

    fn tile_tables(
        &self,
        tile: &GpuWindow,
        _displacement: TileDisplacement<'_>,
        _limit: u64,
    ) -> Result<TileTables, GpuError> {
        // The CPU's (scale, constant) per octave, from the same function; an unused pair when
        // unfiltered (a binding holds at least one element).
        let faded: Option<Vec<[f32; 2]>> = tile
            .footprint()
            .map(|side| {
                let statistics = self.statistics.get_or_init(|| {
                    spectex_model::filter::basis_statistics(
                        &self.model.basis,
                        self.model.dimensions,
                    )
                });
                spectex_model::filter::classic_fade(&self.model, side, statistics)
            })
            .map(|f| {
                f.scale
                    .into_iter()
                    .zip(f.constant)
                    .map(|(a, c)| [a, c])
                    .collect()
            });
        let params = ClassicParams {
            width: tile.width as u32,
            height: tile.height as u32,
            filtered: u32::from(faded.is_some()),
            ..self.params
        };
        Ok(TileTables::new(
            &params,
            vec![
                Table::new(
                    "classic columns",
                    &self.axis(tile.width, periodic_columns(tile, self.period)),
                ),
                Table::new(
                    "classic rows",
                    &self.axis(tile.height, periodic_rows(tile, self.period)),
                ),
                Table::new(
                    "classic octave fade",
                    &faded.unwrap_or_else(|| vec![[0.0; 2]]),
                ),
            ],
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Export (`spectex export --wgsl`).

impl ExportKind for ClassicNoise {
    const GLUE: &'static str = WGSL.1;

    fn export_parts(&self, z: f64) -> Result<ExportNode, GpuError> {
        let (kernel, octaves) = pack(self, z);
        // Octave o: lattices 3o (c_o), 3o + 1 (c_o/(1 + F)) and 3o + 2 (c_o/F) of
        // the glue of classic.wgsl; the skew lattices only matter to simplex noise (F > 0).
        let lattices: Vec<f64> = kernel
            .sides
            .iter()
            .flat_map(|&c| {
                let f = kernel.skew;
                if f > 0.0 {
                    [c, c / (1.0 + f), c / f]
                } else {
                    [c, c, c]
                }
            })
            .collect();
        let halving = u32::from(halving(&lattices));
        Ok(ExportParts::of(
            &kernel,
            &[Table::new("classic octaves", &octaves)],
            lattices,
            "classic",
        )?
        .with_constants(format!(
            "/// 1: every octave's lattices are the previous octave's halved exactly (split once).\n\
             const classic_export_halving: u32 = {halving}u;\n"
        ))
        .with_unrolled("CLASSIC_EXPORT_OCTAVES", octaves.len(), |o| {
            format!("classic_export_octave({o}u, at, &sx, &sy, &acc, &previous);")
        }))
    }
}

/// Whether each octave's three lattices are exactly half the previous octave's, in f64 and as
/// the f32 sides the glue reads (lacunarity 2): then `export_halve` derives octave o + 1's
/// splits from octave o's, exactly where the sides are f32.
fn halving(lattices: &[f64]) -> bool {
    lattices
        .chunks_exact(3)
        .zip(lattices.chunks_exact(3).skip(1))
        .all(|(coarse, fine)| {
            coarse.iter().zip(fine).all(|(&c, &f)| {
                c == 2.0 * f && f > 0.0 && (c as f32) == 2.0 * (f as f32) && (f as f32) > 0.0
            })
        })
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;
    use crate::layout::check::{assert_fills_uniform_array, assert_matches_wgsl, context_or_skip};
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

    /// The shape constants the host sets are the shader's overrides, every one of them, for
    /// every kind with a shape (whether their values are the model's, in `SHAPE`'s order, is
    /// `specialised_pipelines_render_the_generic_bits`'s to tell).
    pub fn shape_constants_are_the_shaders_overrides() {
        use crate::layout::check::assert_shape_is_the_overrides;
        assert_shape_is_the_overrides::<ClassicKernel>();
        assert_shape_is_the_overrides::<crate::phasor::PhasorKernel>();
        assert_shape_is_the_overrides::<crate::gabor::GaborKernel>();
        assert_shape_is_the_overrides::<crate::voronoi::VoronoiKernel>();
        assert_shape_is_the_overrides::<crate::texton::TextonKernel>();
        assert_shape_is_the_overrides::<crate::tiling::TilingKernel>();
        assert_shape_is_the_overrides::<crate::islamic::IslamicKernel>();
        assert_shape_is_the_overrides::<crate::subdivision::SubdivisionKernel>();
        assert_shape_is_the_overrides::<crate::matrix::MatrixKernel>();
        assert_shape_is_the_overrides::<crate::wavelet::WaveletKernel>();
    }

    /// A pipeline specialised to a model's shape renders the bits of the generic one (no
    /// constants: every branch decided by the uniform), for every basis, 2D and 3D, every
    /// fractal and Worley metric, far away and minified. Skips without a GPU (fails when
    /// `SPECTEX_REQUIRE_GPU=1`).
    pub fn specialised_pipelines_render_the_generic_bits() {
        let Some(context) = context_or_skip("specialised_pipelines_render_the_generic_bits") else {
            return;
        };
        let worley = |metric| {
            Basis::Worley(Worley {
                metric,
                coefficients: [-1.0, 1.0, 0.0, 0.0],
                points: FeaturePoints::Poisson(2.0),
            })
        };
        let mut models = Vec::new();
        for basis in [
            Basis::Gradient,
            Basis::Simplex,
            Basis::Value,
            Basis::Kensler,
            worley(Metric::Euclidean),
            worley(Metric::Manhattan),
            worley(Metric::Chebyshev),
        ] {
            for dimensions in [2, 3] {
                models.push(model(basis.clone(), dimensions));
            }
        }
        for kind in [FractalKind::Fbm, FractalKind::Turbulence] {
            let mut m = model(Basis::Gradient, 2);
            if let Some(f) = m.fractal.as_mut() {
                f.kind = kind;
            }
            models.push(m);
        }
        let tiles = [
            GpuWindow::new(23, 17).at([1.0e6, -3.0e5], 1.0),
            GpuWindow::new(19, 13).at([-40.5, 7.25], 3.5),
        ];
        for m in &models {
            for tile in &tiles {
                let render = |generic: bool| {
                    let (mut kernel, octaves) = pack(m, 12.5);
                    kernel.generic = generic;
                    let table = [octave_table(&octaves).unwrap()];
                    Shaded::boxed(&context, kernel, &table)
                        .unwrap()
                        .render_tile(tile, None)
                        .unwrap()
                };
                let bits = |v: Vec<f32>| v.into_iter().map(f32::to_bits).collect::<Vec<_>>();
                assert_eq!(bits(render(true)), bits(render(false)), "{m:?} {tile:?}");
            }
        }
    }

    pub fn records_match_the_wgsl() {
        assert_matches_wgsl::<ClassicParams>("classic", "ClassicParams");
        assert_matches_wgsl::<ClassicOctave>("classic", "ClassicOctave");
        assert_matches_wgsl::<ClassicAxis>("classic", "ClassicAxis");
    }

    /// The skewed coordinate `X = p_x + (p_x + p_y)·F` rebuilt from the column's own part and the
    /// row's other part (integers plus fractions) is the f64 value within f32 rounding, far away.
    pub fn skew_parts_add_up_to_the_skewed_coordinate() {
        let (kernel, _) = pack(&model(Basis::Simplex, 2), 0.0);
        let (x, y) = (1.0e7 + 0.3, -3.0e6 + 0.7);
        let col = kernel.axis(1, |_| x)[0];
        let row = kernel.axis(1, |_| y)[0];
        let (px, py) = (x / 16.0, y / 16.0);
        let want = px + (px + py) * SIMPLEX_F2;
        let int = f64::from(col.own_cell) + f64::from(row.other_cell);
        let frac = f64::from(col.own_frac) + f64::from(row.other_frac);
        assert!((int + frac - want).abs() < 2e-7, "{} vs {want}", int + frac);
        // The lattice split is the exact floor and the rounded remainder.
        assert_eq!(col.cell, px.floor() as i32);
        assert_eq!(col.offset, (px - px.floor()) as f32);
    }

    pub fn params_and_octaves_carry_the_model() {
        let w = Worley {
            metric: Metric::Euclidean,
            coefficients: [-1.0, 1.0, 0.0, 0.0],
            points: FeaturePoints::Poisson(2.0),
        };
        let (kernel, octaves) = pack(&model(Basis::Worley(w.clone()), 3), 40.0);
        let p = kernel.params;
        assert_eq!((p.octaves, p.basis, p.fractal, p.needed), (3, 3, 2, 1));
        assert_eq!(p.cap, 49.0);
        let cdf = FeaturePoints::Poisson(2.0)
            .poisson_cdf()
            .unwrap_or_default();
        assert_eq!(bytemuck::cast::<_, [f32; 16]>(p.cdf), cdf);
        assert_eq!(octaves.len(), 3);
        // Octave 1: side 8, z = 40 is cell 5, offset 0, weight ½.
        let o = octaves[1];
        assert_eq!((o.weight, o.z_cell, o.z_offset), (0.5, 5, 0.0));
        assert_eq!(o.key2, layer_key(1, 9));
        // z·F3 = 5/3 and z·(1 + F3) = 20/3 in cells of octave 1.
        assert_eq!((o.z_other_cell, o.z_own_cell), (1, 6));
        // 1/8 cell per pixel, for warping.
        assert_eq!(o.inv_cell, 0.125);
        // The bytes the device receives: the CDF starts at word 24, the octave's cell at word 1.
        let words: &[u32] = bytemuck::cast_slice(std::slice::from_ref(&p));
        assert_eq!(words[24..40], cdf.map(f32::to_bits));
        // Octaves are twelve words (a uniform array's 16-byte stride): octave 1's plane cell
        // is word 12 + 1.
        assert_eq!(bytemuck::cast_slice::<_, u32>(&octaves)[12 + 1], 5);
        assert_eq!((o.cells_x, o.cells_y), (0, 0));
        // Periodic with 64 × 32: octave 1's cells of 8 pixels, 8 × 4 per period.
        let (_, periodic) = pack_periodic(
            &model(Basis::Worley(w), 3),
            40.0,
            Some(Period::new(64, 32).unwrap()),
        );
        assert_eq!((periodic[1].cells_x, periodic[1].cells_y), (8, 4));
        // The uniform table is the shader's whole array, whatever the model's octaves.
        let table = octave_table(&octaves).unwrap();
        assert_fills_uniform_array("classic", "octaves", &table.bytes);
    }

    pub fn halving_needs_every_lattice_halved_exactly() {
        assert!(halving(&[
            32.0, 20.0, 80.0, 16.0, 10.0, 40.0, 8.0, 5.0, 20.0
        ]));
        assert!(halving(&[32.0, 32.0, 32.0]));
        // Lacunarity 1.9, or one skew lattice off by an ulp.
        assert!(!halving(&[32.0, 32.0, 32.0, 16.842, 16.842, 16.842]));
        let off = 10.0f64.next_up();
        assert!(!halving(&[32.0, 20.0, 80.0, 16.0, off, 40.0]));
    }
}
