//! Voronoi diagrams (survey Dong et al. 2020, §2.6): one seed point per lattice cell, jittered
//! by the randomness contract and optionally relaxed by Lloyd's algorithm, and per pixel the
//! cell's ID, the distance `F1` to its seed, the exact distance to the cell's border, `F2 − F1`,
//! or a colour (from a palette, or from an image sampled at the seed point).
//!
//! # Definition
//!
//! Lattice cell `(i, j)` of side `C` pixels holds one seed. Its PRNG,
//! `Prng::new(cell_hash(i, j, VORONOI_LAYER, seed))`, draws in order `o_x = ½ + jitter·(u − ½)`,
//! `o_y` likewise, and the cell ID `u ∈ [0, 1)` ([`Site::id`]). With Lloyd relaxation
//! ([`VoronoiNoise::lloyd_iterations`] `k > 0`) the offsets are then moved on the host, in f64,
//! per block of `B × B` cells (`B` = [`VoronoiNoise::lloyd_block`], block `(b_x, b_y)` the
//! cells `b·B ..< b·B + B`): `k` Jacobi sweeps move every seed of the block to the centroid of
//! its Voronoi cell, computed exactly (the square of half-side 2 around the seed clipped by the
//! bisector with every seed of the 7 × 7 cells around its cell), and clamp it back into its
//! jitter square `[½ − jitter/2, ½ + jitter/2]²` of its own lattice cell (so seeds of a jitter
//! below 1 stay at least `1 − jitter` apart, relaxed or not). The seeds of the cells around the block (3 cells deep) stay frozen at
//! their jittered positions while the block relaxes. So a relaxed seed is a function of its
//! block's coordinates alone: the diagram stays infinite and every tiling, window and thread
//! sees the same seeds (blocks meet along lines where the relaxation is one-sided, which is
//! invisible at `k ≤ 3` and is the price of locality). The relaxed offset is rounded to f32
//! once, clamped to `[0, 1 − 2⁻²⁴]`.
//!
//! Because every lattice cell holds exactly one seed (relaxed seeds included), every disc of
//! radius `√2` contains a seed, so a Voronoi cell lies within `√2` of its seed; from this:
//! - `F1 < √2`, and a seed outside the 5 × 5 cells around a pixel's is more than 2 away: the
//!   nearest seed is found among those 25 ([`NEAREST_REACH`] = 2);
//! - `F2 < √5` (a disc of radius √5 contains the pixel's cell and a neighbour), so the second
//!   nearest is among the 7 × 7 cells ([`BORDER_REACH`] = 3), whose outside is more than 3 away;
//! - the border distance `b ≤ √2 − F1`, and a seed `q` more than 3 away has a bisector at least
//!   `(3 − F1)/2 > √2 − F1` away: the 7 × 7 cells give the exact border distance.
//!
//! A pixel at `p` (pixels) is split per axis into its cell and an f32 offset `f`
//! ([`crate::grid::locate_cell`]); for each cell of the search, rows (`dj`) outer and columns
//! (`di`) inner, the seed is at `s = (di + o_x, dj + o_y)` relative to the pixel's cell and
//! `d = s − f`, `d² = d_x·d_x + d_y·d_y` (f32, plain `*` and `+`). The nearest seed `n` is the
//! first with the smallest `d²` (strict `<`); `F1 = √d²_n` and `F2` likewise for the second
//! smallest, both in cell units. The border distance is the exact distance to the nearest
//! bisector, `min over q ≠ n of ((d_q + d_n)·(d_q − d_n)) / (2·|d_q − d_n|)` (`|q−p|² − |n−p|²`
//! over twice the seeds' distance, written as the dot product of the sum and difference, which
//! is well conditioned), skipping a `q` with `d_q = d_n`; cell units. The colour outputs read
//! the nearest seed's [`Site::colour`]: a palette's entry `⌊id·N⌋`, or the image's texel under
//! the seed (the image repeats over the plane, one texel per model pixel, top row first; the
//! texel `(⌊x⌋ mod W, ⌊y⌋ mod H)` for the seed at `(x, y) = ((i + o_x)·C, (j + o_y)·C)` in f64).
//! The image's texels are stored in the model (a model file stands alone).
//!
//! # Three dimensions
//!
//! With [`VoronoiNoise::dimensions`] = 3 the seeds fill space, one per cubic lattice cell
//! `(i, j, k)` of side `C`, and a render is the plane `z` of the solid diagram. Cell
//! `(i, j, k)`'s PRNG, `Prng::new(cell_hash(i, j, VORONOI_LAYER, cell_hash(k, 0,
//! VORONOI_LAYER, seed)))` (the 3D convention of classic and phasor noise), draws in order
//! `o_x`, `o_y`, `o_z` (`½ + jitter·(u − ½)` each) and the ID. The 2D bounds become: every
//! ball of radius `√3` holds a whole cell, so `F1 < √3` and a Voronoi cell lies within `√3` of
//! its seed; a seed 3 cells away along an axis is more than 2 away, so the nearest is among the
//! 5 × 5 × 5 cells ([`NEAREST_REACH`]); `F2 < √6` (the pixel's cell and a neighbour), so the
//! second nearest is among the 7 × 7 × 7 ([`F2_REACH_3D`]); the border distance is below
//! `√3 − F1` and a seed more than 4 away has its bisector plane more than `(4 − F1)/2 > √3 − F1`
//! away, so the 9 × 9 × 9 cells give the exact border distance ([`BORDER_REACH_3D`]). The
//! expressions are the 2D ones with a third term (`d² = (d_x·d_x + d_y·d_y) + d_z·d_z`, the
//! border `((d_q + d_n)·(d_q − d_n))·½ / |d_q − d_n|` with three-term dot products); the
//! nearest seed is the one with the smallest `d²`, ties to the first in `(dk, dj, di)` order.
//! [`search3`] visits only the cells that can matter: the 3 × 3 × 3 around the pixel's, then
//! the others whose lower bound (below) can beat what was found, so its result is that of the
//! full search ([`search3_full`]) bit for bit. Lloyd relaxation (centroids of clipped
//! polyhedra) and the image colour output (a 2D image) are 2D only; validation refuses them in
//! 3D. A periodic 3D diagram wraps `i` and `j` only (`z` is not periodic).

use serde::{Deserialize, Serialize};

use std::sync::{Arc, Mutex};

use crate::error::{ModelError, check_image, check_len, check_level, check_range};
use crate::random::{Prng, cell_hash};

pub(crate) mod builder;
pub use builder::VoronoiNoiseBuilder;

/// The random layer of Voronoi seeds ("VORO").
pub const VORONOI_LAYER: u32 = 0x564F_524F;
/// Cells searched beyond a pixel's own for the nearest seed (5 × 5 cells; module docs).
pub const NEAREST_REACH: i32 = 2;
/// Cells searched beyond a pixel's own for the second nearest seed and the border (7 × 7).
pub const BORDER_REACH: i32 = 3;
/// Cells searched beyond a pixel's own for the second nearest seed in 3D (7 × 7 × 7).
pub const F2_REACH_3D: i32 = 3;
/// Cells searched beyond a pixel's own for the border in 3D (9 × 9 × 9; module docs).
pub const BORDER_REACH_3D: i32 = 4;
/// How far (cell units) a cell's lower bound on its bisector distances must exceed the border
/// found so far for [`search3`] to skip it: the bound and the computed distances differ by
/// roundings of at most `≈ 20·2⁻²⁴·|d| < 1.1·10⁻⁵` cell each (`|d| < 9` cells), so `10⁻³` keeps
/// every skipped bisector beyond the minimum and the result that of the full search.
pub const BORDER_PRUNE_MARGIN: f32 = 1e-3;
/// Most Lloyd iterations.
pub const MAX_LLOYD_ITERATIONS: u32 = 16;
/// Largest relaxation block side, cells.
pub const MAX_LLOYD_BLOCK: u32 = 16;
/// Most palette colours.
pub const MAX_PALETTE: usize = 256;
/// Largest side of a colour image, texels.
pub const MAX_IMAGE_SIDE: u32 = crate::error::MAX_IMAGE_SIDE;
/// The largest offset a seed takes in its cell, `1 − 2⁻²⁴`.
const MAX_OFFSET: f64 = 1.0 - 1.0 / 16_777_216.0;

/// What a pixel shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum VoronoiOutput {
    /// The nearest seed's ID, a uniform value in `[0, 1)` per cell.
    CellId,
    /// The distance to the nearest seed, cell units.
    F1,
    /// The exact distance to the nearest cell border (bisector), cell units.
    Border,
    /// Worley's `F2 − F1`, cell units.
    F2MinusF1,
    /// The nearest seed's colour from a palette, entry `⌊id·N⌋` (RGB output).
    Palette {
        /// `1..=256` RGB colours.
        colours: Vec<[f32; 3]>,
    },
    /// The colour of an RGB image under the nearest seed (RGB output; module docs).
    Image {
        /// Texels per row (`1..=1024`).
        width: u32,
        /// Rows (`1..=1024`).
        height: u32,
        /// `width·height` RGB texels, row-major, top row first.
        texels: Vec<[f32; 3]>,
    },
}

impl VoronoiOutput {
    /// Values per pixel: 3 for the colour outputs, else 1.
    #[must_use]
    pub fn channels(&self) -> usize {
        match self {
            Self::Palette { .. } | Self::Image { .. } => 3,
            _ => 1,
        }
    }

    /// The search reach the output needs: [`BORDER_REACH`] for the border and `F2 − F1`,
    /// [`NEAREST_REACH`] for the rest.
    #[must_use]
    pub fn reach(&self) -> i32 {
        match self {
            Self::Border | Self::F2MinusF1 => BORDER_REACH,
            _ => NEAREST_REACH,
        }
    }
}

/// A Voronoi diagram (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VoronoiNoise {
    /// Seed of the randomness contract.
    pub seed: u32,
    /// 2 (a plane of seeds) or 3 (a volume of seeds, rendered on a plane `z`; module docs).
    /// Absent in a file: 2.
    #[serde(default = "two", skip_serializing_if = "is_two")]
    pub dimensions: u32,
    /// `C`, the lattice cell side in pixels, in `[1, 4096]`.
    pub cell_size: f32,
    /// Jitter of the seeds in cells, `[0, 1]` (1: anywhere in the cell).
    pub jitter: f32,
    /// Lloyd iterations `k` (0: none), at most 16.
    pub lloyd_iterations: u32,
    /// Relaxation block side `B`, cells, in `[1, 16]`.
    pub lloyd_block: u32,
    /// What a pixel shows.
    pub output: VoronoiOutput,
}

/// The default of [`VoronoiNoise::dimensions`].
fn two() -> u32 {
    VoronoiNoise::DEFAULT_DIMENSIONS
}

/// Whether `dimensions` is the default (not written to files, so a 2D model's file is as before).
#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_two(dimensions: &u32) -> bool {
    *dimensions == VoronoiNoise::DEFAULT_DIMENSIONS
}

/// One lattice cell's seed as both evaluators read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    /// `(o_x, o_y)`, the seed's offset in its cell, cell units in `[0, 1)`.
    pub offset: [f32; 2],
    /// The cell ID in `[0, 1)`.
    pub id: f32,
    /// The colour of a colour output (zeros otherwise).
    pub colour: [f32; 3],
}

/// A rectangle of lattice cells' sites, row-major: cell `(i0 + a, j0 + b)` at `b·width + a`.
#[derive(Debug, Clone, PartialEq)]
pub struct SiteTable {
    /// First cell column.
    pub i0: i64,
    /// First cell row.
    pub j0: i64,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The sites.
    pub sites: Vec<Site>,
}

impl SiteTable {
    /// The site of cell `(i, j)`, which must lie in the table.
    #[inline]
    #[must_use]
    pub fn get(&self, i: i64, j: i64) -> &Site {
        &self.sites[(j - self.j0) as usize * self.width + (i - self.i0) as usize]
    }
}

/// Relaxed Lloyd blocks ([`VoronoiNoise::relaxed_block`]) kept across calls of
/// [`VoronoiNoise::sites_cached`], by block coordinates; shared by threads. Holds at most
/// [`BlockCache::CAPACITY`] blocks and starts again empty past that (a block is at most 16² offsets,
/// so at most 8 MiB), which changes no result: a block is recomputed the same.
#[derive(Debug, Default)]
pub struct BlockCache(Mutex<std::collections::HashMap<(i64, i64), RelaxedBlock>>);

/// One relaxed block's offsets, row-major.
type RelaxedBlock = Arc<Vec<[f32; 2]>>;

impl BlockCache {
    /// Most blocks held.
    pub const CAPACITY: usize = 4096;

    /// Block `(bx, by)` of `model`, relaxed now or earlier. The cache must only ever serve one
    /// model (an evaluator owns it). A poisoned lock only costs the cache.
    /// A periodic model's blocks are relaxed with the `cells` per period it wraps; a cache
    /// serves one evaluator, so one `cells`.
    fn get_or_relax(
        &self,
        model: &VoronoiNoise,
        bx: i64,
        by: i64,
        cells: Option<[i64; 2]>,
    ) -> RelaxedBlock {
        if let Some(hit) = self.0.lock().ok().and_then(|m| m.get(&(bx, by)).cloned()) {
            return hit;
        }
        let block = Arc::new(model.relaxed_block_in(bx, by, cells));
        if let Ok(mut map) = self.0.lock() {
            if map.len() >= Self::CAPACITY {
                map.clear();
            }
            map.insert((bx, by), Arc::clone(&block));
        }
        block
    }
}

/// What a pixel's search finds (module docs), all in cell units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest {
    /// The nearest seed's site.
    pub site: Site,
    /// `F1`.
    pub f1: f32,
    /// `F2` (`INFINITY` when the search covered only the nearest's reach).
    pub f2: f32,
    /// The border distance (`INFINITY` when not computed).
    pub border: f32,
}

impl VoronoiNoise {
    /// Checks every field.
    ///
    /// # Errors
    /// The first field found outside its range.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_range(
            || "voronoi.dimensions".into(),
            f64::from(self.dimensions),
            2.0,
            3.0,
            "2 or 3",
        )?;
        if self.dimensions == 3 {
            // Module docs: features with no exact 3D form.
            check_range(
                || "voronoi.lloyd_iterations".into(),
                f64::from(self.lloyd_iterations),
                0.0,
                0.0,
                "0 when voronoi.dimensions = 3 (Lloyd relaxation is 2D only: 3D needs the \
                 centroids of clipped polyhedra)",
            )?;
            if matches!(self.output, VoronoiOutput::Image { .. }) {
                return Err(ModelError::OutOfRange {
                    field: "voronoi.dimensions".into(),
                    value: 3.0,
                    range: "2 for the image colour output (voronoi.output.image samples a 2D \
                            image under each seed)",
                });
            }
        }
        check_range(
            || "voronoi.cell_size".into(),
            f64::from(self.cell_size),
            1.0,
            4096.0,
            "[1, 4096] pixels",
        )?;
        check_range(
            || "voronoi.jitter".into(),
            f64::from(self.jitter),
            0.0,
            1.0,
            "[0, 1] cells",
        )?;
        check_range(
            || "voronoi.lloyd_iterations".into(),
            f64::from(self.lloyd_iterations),
            0.0,
            f64::from(MAX_LLOYD_ITERATIONS),
            "[0, 16] iterations",
        )?;
        check_range(
            || "voronoi.lloyd_block".into(),
            f64::from(self.lloyd_block),
            1.0,
            f64::from(MAX_LLOYD_BLOCK),
            "[1, 16] cells",
        )?;
        match &self.output {
            VoronoiOutput::Palette { colours } => {
                check_len(
                    || "voronoi.output.palette.colours".into(),
                    colours.len(),
                    1,
                    MAX_PALETTE,
                    "1 to 256 colours",
                )?;
                for (k, c) in colours.iter().enumerate() {
                    for (n, &v) in c.iter().enumerate() {
                        check_level(|| format!("voronoi.output.palette.colours[{k}][{n}]"), v)?;
                    }
                }
            }
            VoronoiOutput::Image {
                width,
                height,
                texels,
            } => {
                check_image("voronoi.output.image", *width, *height, "texels", texels)?;
            }
            _ => {}
        }
        Ok(())
    }

    /// The jittered offset and ID of cell `(i, j)` (before relaxation).
    #[must_use]
    pub fn jittered(&self, i: i64, j: i64) -> ([f32; 2], f32) {
        let mut prng = Prng::new(cell_hash(i as i32, j as i32, VORONOI_LAYER, self.seed));
        let ox = 0.5 + self.jitter * (prng.next_f32() - 0.5);
        let oy = 0.5 + self.jitter * (prng.next_f32() - 0.5);
        let id = prng.next_f32();
        ([ox, oy], id)
    }

    /// The search reach of the output in the model's dimensions ([`VoronoiOutput::reach`] in
    /// 2D; [`NEAREST_REACH`], [`F2_REACH_3D`] or [`BORDER_REACH_3D`] in 3D).
    #[must_use]
    pub fn reach(&self) -> i32 {
        if self.dimensions != 3 {
            return self.output.reach();
        }
        match self.output {
            VoronoiOutput::Border => BORDER_REACH_3D,
            VoronoiOutput::F2MinusF1 => F2_REACH_3D,
            _ => NEAREST_REACH,
        }
    }

    /// The jittered offset and ID of the 3D cell `(i, j, k)` (module docs).
    #[must_use]
    pub fn jittered3(&self, i: i64, j: i64, k: i64) -> ([f32; 3], f32) {
        let plane = cell_hash(k as i32, 0, VORONOI_LAYER, self.seed);
        let mut prng = Prng::new(cell_hash(i as i32, j as i32, VORONOI_LAYER, plane));
        let ox = 0.5 + self.jitter * (prng.next_f32() - 0.5);
        let oy = 0.5 + self.jitter * (prng.next_f32() - 0.5);
        let oz = 0.5 + self.jitter * (prng.next_f32() - 0.5);
        let id = prng.next_f32();
        ([ox, oy, oz], id)
    }

    /// The sites of the 3D cells `i0 ..< i0 + width`, `j0 ..< j0 + height`, `k0 ..< k0 +
    /// depth`; periodic in `i` and `j` with `cells` per period when given (`z` never is).
    #[must_use]
    pub fn sites3(
        &self,
        origin: [i64; 3],
        size: [usize; 3],
        cells: Option<[i64; 2]>,
    ) -> SiteTable3 {
        let [width, height, depth] = size;
        let mut sites = Vec::with_capacity(width * height * depth);
        for z in 0..depth as i64 {
            for y in 0..height as i64 {
                for x in 0..width as i64 {
                    let (i, j) = wrapped(origin[0] + x, origin[1] + y, cells);
                    let (offset, id) = self.jittered3(i, j, origin[2] + z);
                    sites.push(Site3 {
                        offset,
                        id,
                        colour: self.colour(i, j, [offset[0], offset[1]], id),
                    });
                }
            }
        }
        SiteTable3 {
            origin,
            size,
            sites,
        }
    }

    /// The relaxed offsets of block `(bx, by)`'s `B × B` cells, row-major (module docs).
    #[must_use]
    pub fn relaxed_block(&self, bx: i64, by: i64) -> Vec<[f32; 2]> {
        self.relaxed_block_in(bx, by, None)
    }

    /// [`relaxed_block`](Self::relaxed_block) of a periodic model with `cells` per period
    /// ([`sites_periodic`](Self::sites_periodic)): the frozen ring around the block reads the
    /// wrapped cells' jittered seeds, so the blocks at the period's edges relax against the
    /// other side's seeds.
    fn relaxed_block_in(&self, bx: i64, by: i64, cells: Option<[i64; 2]>) -> Vec<[f32; 2]> {
        let b = i64::from(self.lloyd_block);
        let ring = i64::from(BORDER_REACH);
        let side = b + 2 * ring;
        let (i0, j0) = (bx * b - ring, by * b - ring);
        // Seeds relative to (i0, j0), f64: the block's (moving) and the ring's (frozen).
        let mut points: Vec<[f64; 2]> = Vec::with_capacity((side * side) as usize);
        for y in 0..side {
            for x in 0..side {
                let (wi, wj) = wrapped(i0 + x, j0 + y, cells);
                let ([ox, oy], _) = self.jittered(wi, wj);
                points.push([x as f64 + f64::from(ox), y as f64 + f64::from(oy)]);
            }
        }
        let index = |x: i64, y: i64| (y * side + x) as usize;
        // The jitter square: a relaxed seed stays where a jittered one may lie.
        let half = 0.5 * f64::from(self.jitter);
        let (lo, hi) = ((0.5 - half).max(0.0), (0.5 + half).min(MAX_OFFSET));
        let mut others = Vec::with_capacity(((2 * ring + 1) * (2 * ring + 1)) as usize);
        let mut buffers = ClipBuffers::default();
        for _ in 0..self.lloyd_iterations {
            let mut moved = points.clone();
            for y in ring..ring + b {
                for x in ring..ring + b {
                    let p = points[index(x, y)];
                    others.clear();
                    for yy in y - ring..=y + ring {
                        for xx in x - ring..=x + ring {
                            if (xx, yy) != (x, y) {
                                others.push(points[index(xx, yy)]);
                            }
                        }
                    }
                    let c = voronoi_centroid_in(p, &others, &mut buffers);
                    moved[index(x, y)] = [
                        x as f64 + (c[0] - x as f64).clamp(lo, hi),
                        y as f64 + (c[1] - y as f64).clamp(lo, hi),
                    ];
                }
            }
            points = moved;
        }
        let mut out = Vec::with_capacity((b * b) as usize);
        for y in ring..ring + b {
            for x in ring..ring + b {
                let p = points[index(x, y)];
                let o = |v: f64, c: i64| ((v - c as f64) as f32).min(MAX_OFFSET as f32);
                out.push([o(p[0], x), o(p[1], y)]);
            }
        }
        out
    }

    /// The sites of the cells `i0 ..< i0 + width`, `j0 ..< j0 + height` (relaxed blocks each
    /// computed once).
    #[must_use]
    pub fn sites(&self, i0: i64, j0: i64, width: usize, height: usize) -> SiteTable {
        self.sites_cached(i0, j0, width, height, &BlockCache::default())
    }

    /// [`sites`](Self::sites) with the relaxed blocks taken from `cache` (and added to it): an
    /// evaluator that keeps one cache relaxes each block once however its pixels are asked
    /// for (bands of rows, single displaced points through a warp). Relaxation is a function
    /// of the block alone, so the sites are the same bits with or without the cache.
    #[must_use]
    pub fn sites_cached(
        &self,
        i0: i64,
        j0: i64,
        width: usize,
        height: usize,
        cache: &BlockCache,
    ) -> SiteTable {
        self.sites_in(i0, j0, width, height, cache, None)
    }

    /// [`sites_cached`](Self::sites_cached) of the model made periodic with `cells` cells per
    /// period along x and y (a model that accepts the period, `check_period`): cell `(i, j)`
    /// holds the seed, ID and colour of cell `(i mod n_x, j mod n_y)` (offsets within the cell,
    /// so the same seed one period away), and Lloyd blocks (which divide the period) are
    /// relaxed against wrapped neighbours. A `cache` must serve one `cells` only.
    #[must_use]
    pub fn sites_periodic(
        &self,
        i0: i64,
        j0: i64,
        width: usize,
        height: usize,
        cache: &BlockCache,
        cells: [i64; 2],
    ) -> SiteTable {
        self.sites_in(i0, j0, width, height, cache, Some(cells))
    }

    /// The site table, periodic with `cells` per period when given.
    fn sites_in(
        &self,
        i0: i64,
        j0: i64,
        width: usize,
        height: usize,
        cache: &BlockCache,
        cells: Option<[i64; 2]>,
    ) -> SiteTable {
        let mut sites = Vec::with_capacity(width * height);
        let b = i64::from(self.lloyd_block);
        // This table's blocks, looked up in the shared cache once each.
        let mut blocks: std::collections::HashMap<(i64, i64), RelaxedBlock> =
            std::collections::HashMap::new();
        for y in 0..height as i64 {
            for x in 0..width as i64 {
                let (i, j) = wrapped(i0 + x, j0 + y, cells);
                let (mut offset, id) = self.jittered(i, j);
                if self.lloyd_iterations > 0 {
                    let (bx, by) = (i.div_euclid(b), j.div_euclid(b));
                    let block = blocks
                        .entry((bx, by))
                        .or_insert_with(|| cache.get_or_relax(self, bx, by, cells));
                    offset = block[(j.rem_euclid(b) * b + i.rem_euclid(b)) as usize];
                }
                sites.push(Site {
                    offset,
                    id,
                    colour: self.colour(i, j, offset, id),
                });
            }
        }
        SiteTable {
            i0,
            j0,
            width,
            height,
            sites,
        }
    }

    /// The colour of a colour output for the seed of cell `(i, j)` at `offset` with `id`.
    fn colour(&self, i: i64, j: i64, offset: [f32; 2], id: f32) -> [f32; 3] {
        match &self.output {
            VoronoiOutput::Palette { colours } => {
                let n = colours.len();
                colours[((id * n as f32) as usize).min(n - 1)]
            }
            VoronoiOutput::Image {
                width,
                height,
                texels,
            } => {
                let c = f64::from(self.cell_size);
                let x = ((i as f64 + f64::from(offset[0])) * c).floor() as i64;
                let y = ((j as f64 + f64::from(offset[1])) * c).floor() as i64;
                let tx = x.rem_euclid(i64::from(*width)) as usize;
                let ty = y.rem_euclid(i64::from(*height)) as usize;
                texels[ty * *width as usize + tx]
            }
            _ => [0.0; 3],
        }
    }

    /// Cells per pixel a search visits, for costs (in 3D the 27 cells around the pixel's
    /// and, for the border, as many again: [`search3`] skips the others' sites in most pixels).
    #[must_use]
    pub fn cells_per_pixel(&self) -> f64 {
        if self.dimensions == 3 {
            return if matches!(self.output, VoronoiOutput::Border) {
                54.0
            } else {
                27.0
            };
        }
        let side = f64::from(2 * self.output.reach() + 1);
        let search = side * side;
        if matches!(self.output, VoronoiOutput::Border) {
            2.0 * search
        } else {
            search
        }
    }
}

/// Cell `(i, j)` wrapped into one period's `cells` when given (the cell whose seed it holds).
#[inline]
fn wrapped(i: i64, j: i64, cells: Option<[i64; 2]>) -> (i64, i64) {
    match cells {
        None => (i, j),
        Some([nx, ny]) => (
            crate::period::wrap(i, nx.max(1)),
            crate::period::wrap(j, ny.max(1)),
        ),
    }
}

/// The pixel's search (module docs): `site(di, dj)` gives the site of the cell `(di, dj)` away
/// from the pixel's, `(fx, fy)` is the pixel's offset in its cell; `reach` cells each way;
/// `border` asks for the border distance too.
#[inline]
#[must_use]
pub fn search<'a>(
    site: impl Fn(i32, i32) -> &'a Site,
    fx: f32,
    fy: f32,
    reach: i32,
    border: bool,
) -> Nearest {
    let mut best = f32::INFINITY;
    let mut second = f32::INFINITY;
    let mut nearest = (0i32, 0i32);
    let mut dn = [0.0f32; 2];
    for dj in -reach..=reach {
        for di in -reach..=reach {
            let s = site(di, dj);
            let dx = (di as f32 + s.offset[0]) - fx;
            let dy = (dj as f32 + s.offset[1]) - fy;
            let d2 = dx * dx + dy * dy;
            if d2 < best {
                second = best;
                best = d2;
                nearest = (di, dj);
                dn = [dx, dy];
            } else if d2 < second {
                second = d2;
            }
        }
    }
    let mut b = f32::INFINITY;
    if border {
        for dj in -reach..=reach {
            for di in -reach..=reach {
                let s = site(di, dj);
                let dx = (di as f32 + s.offset[0]) - fx;
                let dy = (dj as f32 + s.offset[1]) - fy;
                let ex = dx - dn[0];
                let ey = dy - dn[1];
                let e2 = ex * ex + ey * ey;
                if e2 == 0.0 {
                    continue;
                }
                let num = (dx + dn[0]) * ex + (dy + dn[1]) * ey;
                let q = num * 0.5 / e2.sqrt();
                if q < b {
                    b = q;
                }
            }
        }
    }
    Nearest {
        site: *site(nearest.0, nearest.1),
        f1: best.sqrt(),
        f2: second.sqrt(),
        border: b,
    }
}

/// One 3D lattice cell's seed as both evaluators read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site3 {
    /// `(o_x, o_y, o_z)`, the seed's offset in its cell, cell units in `[0, 1)`.
    pub offset: [f32; 3],
    /// The cell ID in `[0, 1)`.
    pub id: f32,
    /// The colour of the palette output (zeros otherwise).
    pub colour: [f32; 3],
}

/// A box of 3D lattice cells' sites: cell `origin + (a, b, c)` at `(c·height + b)·width + a`.
#[derive(Debug, Clone, PartialEq)]
pub struct SiteTable3 {
    /// The first cell `(i0, j0, k0)`.
    pub origin: [i64; 3],
    /// Cells along `i`, `j`, `k`.
    pub size: [usize; 3],
    /// The sites.
    pub sites: Vec<Site3>,
}

impl SiteTable3 {
    /// The site of cell `(i, j, k)`, which must lie in the table.
    #[inline]
    #[must_use]
    pub fn get(&self, i: i64, j: i64, k: i64) -> &Site3 {
        let [w, h, _] = self.size;
        let a = (i - self.origin[0]) as usize;
        let b = (j - self.origin[1]) as usize;
        let c = (k - self.origin[2]) as usize;
        &self.sites[(c * h + b) * w + a]
    }
}

/// What a pixel's 3D search finds (module docs), all in cell units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest3 {
    /// The nearest seed's site.
    pub site: Site3,
    /// `F1`.
    pub f1: f32,
    /// `F2` (`INFINITY` unless asked for).
    pub f2: f32,
    /// The border distance (`INFINITY` unless asked for).
    pub border: f32,
}

/// The largest 3D reach [`search3`] takes.
const MAX_REACH_3D: i32 = BORDER_REACH_3D;

/// The state of a 3D search.
struct Search3 {
    /// Smallest and second smallest `d²`.
    best: f32,
    second: f32,
    /// The nearest's `(dk, dj, di)` and its `d`.
    key: (i32, i32, i32),
    dn: [f32; 3],
    /// The border found so far and the `d²` beyond which no cell's bisector can beat it.
    border: f32,
    border_limit: f32,
}

/// `d = (di + o) − f` per axis and `d² = (d_x·d_x + d_y·d_y) + d_z·d_z`.
#[inline]
fn delta3(s: &Site3, di: i32, dj: i32, dk: i32, f: [f32; 3]) -> ([f32; 3], f32) {
    let dx = (di as f32 + s.offset[0]) - f[0];
    let dy = (dj as f32 + s.offset[1]) - f[1];
    let dz = (dk as f32 + s.offset[2]) - f[2];
    ([dx, dy, dz], dx * dx + dy * dy + dz * dz)
}

impl Search3 {
    fn new() -> Self {
        Self {
            best: f32::INFINITY,
            second: f32::INFINITY,
            key: (i32::MAX, i32::MAX, i32::MAX),
            dn: [0.0; 3],
            border: f32::INFINITY,
            border_limit: f32::INFINITY,
        }
    }

    /// A seed at `d` with `d²` from cell `(di, dj, dk)`: the smallest `d²` wins, ties to the
    /// first cell in `(dk, dj, di)` order.
    #[inline]
    fn nearest(&mut self, d: [f32; 3], d2: f32, key: (i32, i32, i32)) {
        if d2 < self.best || (d2 == self.best && key < self.key) {
            self.second = self.best;
            self.best = d2;
            self.key = key;
            self.dn = d;
        } else if d2 < self.second {
            self.second = d2;
        }
    }

    /// A seed at `d`: its bisector with the nearest (skipped where it is the nearest).
    #[inline]
    fn bisector(&mut self, d: [f32; 3], f1: f32) {
        let n = self.dn;
        let e = [d[0] - n[0], d[1] - n[1], d[2] - n[2]];
        let e2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        if e2 == 0.0 {
            return;
        }
        let num = (d[0] + n[0]) * e[0] + (d[1] + n[1]) * e[1] + (d[2] + n[2]) * e[2];
        let q = num * 0.5 / e2.sqrt();
        if q < self.border {
            self.border = q;
            let reach = 2.0 * (q + BORDER_PRUNE_MARGIN) + f1;
            self.border_limit = reach * reach;
        }
    }
}

/// The lower bound of `|d|` along one axis over the sites of cell offset `d` from a pixel at
/// offset `f`, rounded as the search rounds `d`, so it is at most the computed `|d|`: `d − f`
/// for `d > 0` (as `(d + o) − f` with `o ≥ 0` rounds to at least it), `f − (d + 1)` for
/// `d < 0`, 0 for the pixel's own column.
#[inline]
fn gap(d: i32, f: f32) -> f32 {
    if d > 0 {
        (d as f32 - f).max(0.0)
    } else if d < 0 {
        (f - (d + 1) as f32).max(0.0)
    } else {
        0.0
    }
}

/// Visits the cells within `reach` whose sites can have a `d²` of at most `limit(state)`:
/// the 3 × 3 × 3 around the pixel's, then the others, each in `(dk, dj, di)` order. A cell is
/// skipped when its bound `(g_x² + g_y²) + g_z²` (the gaps' squares, summed as `d²` is, so
/// never above any of its sites' `d²`) exceeds the limit, a plane or a row when the part of
/// the bound it fixes already does.
#[inline]
fn walk3(
    state: &mut Search3,
    reach: i32,
    g2: &[[f32; (2 * MAX_REACH_3D + 1) as usize]; 3],
    limit: impl Fn(&Search3) -> f32,
    mut visit: impl FnMut(&mut Search3, i32, i32, i32),
) {
    let at = |axis: usize, d: i32| g2[axis][(d + MAX_REACH_3D) as usize];
    for pass in 0..2 {
        let r = if pass == 0 { reach.min(1) } else { reach };
        if pass == 1 && r <= 1 {
            break;
        }
        for dk in -r..=r {
            let gz = at(2, dk);
            if gz > limit(state) {
                continue;
            }
            for dj in -r..=r {
                if at(1, dj) + gz > limit(state) {
                    continue;
                }
                for di in -r..=r {
                    if pass == 1 && di.abs() <= 1 && dj.abs() <= 1 && dk.abs() <= 1 {
                        continue;
                    }
                    let bound = at(0, di) + at(1, dj) + gz;
                    if bound > limit(state) {
                        continue;
                    }
                    visit(state, di, dj, dk);
                }
            }
        }
    }
}

/// The 3D pixel's search (module docs): `site(di, dj, dk)` gives the site of the cell
/// `(di, dj, dk)` away from the pixel's, `f` is the pixel's offset in its cell; `reach` cells
/// each way (at most [`BORDER_REACH_3D`]); `second` asks for `F2`, `border` for the border
/// distance. Only the cells that can hold the nearest (second nearest) seeds, or a nearer
/// bisector, are visited: the result is [`search3_full`]'s bit for bit.
#[inline]
#[must_use]
pub fn search3<'a>(
    site: impl Fn(i32, i32, i32) -> &'a Site3,
    f: [f32; 3],
    reach: i32,
    second: bool,
    border: bool,
) -> Nearest3 {
    let reach = reach.min(MAX_REACH_3D);
    let mut g2 = [[0.0f32; (2 * MAX_REACH_3D + 1) as usize]; 3];
    for (axis, row) in g2.iter_mut().enumerate() {
        for (k, v) in row.iter_mut().enumerate() {
            let g = gap(k as i32 - MAX_REACH_3D, f[axis]);
            *v = g * g;
        }
    }
    let mut state = Search3::new();
    let limit = |s: &Search3| if second { s.second } else { s.best };
    walk3(&mut state, reach, &g2, limit, |s, di, dj, dk| {
        let (d, d2) = delta3(site(di, dj, dk), di, dj, dk, f);
        s.nearest(d, d2, (dk, dj, di));
    });
    let f1 = state.best.sqrt();
    if border {
        walk3(
            &mut state,
            reach,
            &g2,
            |s| s.border_limit,
            |s, di, dj, dk| {
                let (d, _) = delta3(site(di, dj, dk), di, dj, dk, f);
                s.bisector(d, f1);
            },
        );
    }
    let (i, j, k) = (state.key.2, state.key.1, state.key.0);
    Nearest3 {
        site: *site(i, j, k),
        f1,
        f2: if second {
            state.second.sqrt()
        } else {
            f32::INFINITY
        },
        border: if border { state.border } else { f32::INFINITY },
    }
}

/// [`search3`] over every cell within `reach`, in `(dk, dj, di)` order: the definition, slow.
#[must_use]
pub fn search3_full<'a>(
    site: impl Fn(i32, i32, i32) -> &'a Site3,
    f: [f32; 3],
    reach: i32,
    second: bool,
    border: bool,
) -> Nearest3 {
    let mut state = Search3::new();
    for dk in -reach..=reach {
        for dj in -reach..=reach {
            for di in -reach..=reach {
                let (d, d2) = delta3(site(di, dj, dk), di, dj, dk, f);
                state.nearest(d, d2, (dk, dj, di));
            }
        }
    }
    let f1 = state.best.sqrt();
    if border {
        for dk in -reach..=reach {
            for dj in -reach..=reach {
                for di in -reach..=reach {
                    let (d, _) = delta3(site(di, dj, dk), di, dj, dk, f);
                    state.bisector(d, f1);
                }
            }
        }
    }
    let (i, j, k) = (state.key.2, state.key.1, state.key.0);
    Nearest3 {
        site: *site(i, j, k),
        f1,
        f2: if second {
            state.second.sqrt()
        } else {
            f32::INFINITY
        },
        border: if border { state.border } else { f32::INFINITY },
    }
}

/// The centroid of the Voronoi cell of `p` among `others` (f64, exact up to rounding): the
/// square of half-side 2 around `p` clipped by the half-plane nearer `p` than each other seed
/// (Sutherland–Hodgman), then the polygon's area-weighted centroid.
#[must_use]
pub fn voronoi_centroid(p: [f64; 2], others: &[[f64; 2]]) -> [f64; 2] {
    voronoi_centroid_in(p, others, &mut ClipBuffers::default())
}

/// The polygons of [`voronoi_centroid`], kept between calls.
#[derive(Debug, Default)]
struct ClipBuffers {
    poly: Vec<[f64; 2]>,
    out: Vec<[f64; 2]>,
    /// The clip's `(v − m)·n` of each vertex.
    sides: Vec<f64>,
}

/// [`voronoi_centroid`] with its polygons in `buffers`.
///
/// A half-plane that holds the whole polygon is skipped: every vertex `v` has
/// `(v − m)·n = (v − p)·n − |n|²/2 ≤ |n|·(|v − p| − |n|/2)`, below 0 when the polygon's
/// farthest vertex from `p` is nearer than `|n|/2`, and the clip would then keep every vertex
/// and add none, returning the polygon as it was. The test keeps a margin (`|n|² > 4r²(1 +
/// 10⁻⁶) + 10⁻⁶`, so that the exact `(v − m)·n` is below −2.5·10⁻⁷) far above the roundings
/// of the clip's `side` (about 10⁻¹³ for a block's coordinates), so the result is the same bits
/// as clipping by every plane. Seeds are visited in the caller's order; most of the far ones
/// no longer cut once the near ones have.
fn voronoi_centroid_in(p: [f64; 2], others: &[[f64; 2]], buffers: &mut ClipBuffers) -> [f64; 2] {
    let h = 2.0;
    let ClipBuffers { poly, out, sides } = buffers;
    poly.clear();
    poly.extend([
        [p[0] - h, p[1] - h],
        [p[0] + h, p[1] - h],
        [p[0] + h, p[1] + h],
        [p[0] - h, p[1] + h],
    ]);
    let farthest2 = |poly: &[[f64; 2]]| {
        poly.iter()
            .map(|v| (v[0] - p[0]) * (v[0] - p[0]) + (v[1] - p[1]) * (v[1] - p[1]))
            .fold(0.0, f64::max)
    };
    let mut reach2 = farthest2(poly);
    for q in others {
        // Keep x with (x − m)·(q − p) ≤ 0, m the midpoint.
        let n = [q[0] - p[0], q[1] - p[1]];
        if n[0] * n[0] + n[1] * n[1] > 4.0 * reach2 * (1.0 + 1e-6) + 1e-6 {
            continue;
        }
        let m = [(q[0] + p[0]) * 0.5, (q[1] + p[1]) * 0.5];
        // Each vertex's side once (the same expression for either end of an edge).
        sides.clear();
        sides.extend(
            poly.iter()
                .map(|v| (v[0] - m[0]) * n[0] + (v[1] - m[1]) * n[1]),
        );
        if sides.iter().all(|&s| s <= 0.0) {
            // Every vertex kept and no edge crossing: the clip's output is the polygon.
            continue;
        }
        out.clear();
        let len = poly.len();
        for k in 0..len {
            let next = if k + 1 == len { 0 } else { k + 1 };
            let (a, b) = (poly[k], poly[next]);
            let (sa, sb) = (sides[k], sides[next]);
            if sa <= 0.0 {
                out.push(a);
            }
            if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
                let t = sa / (sa - sb);
                out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
        std::mem::swap(poly, out);
        if poly.is_empty() {
            return p;
        }
        reach2 = farthest2(poly);
    }
    polygon_centroid(poly, p)
}

/// The area-weighted centroid of the polygon `poly` (vertices in order), `p` for a degenerate
/// one.
fn polygon_centroid(poly: &[[f64; 2]], p: [f64; 2]) -> [f64; 2] {
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..poly.len() {
        let a = poly[k];
        let b = poly[(k + 1) % poly.len()];
        let cross = a[0] * b[1] - b[0] * a[1];
        area += cross;
        cx += (a[0] + b[0]) * cross;
        cy += (a[1] + b[1]) * cross;
    }
    if area.abs() < 1e-300 {
        return p;
    }
    [cx / (3.0 * area), cy / (3.0 * area)]
}

impl From<VoronoiNoise> for crate::Model {
    fn from(model: VoronoiNoise) -> Self {
        Self::Voronoi(model)
    }
}

impl crate::ModelKind for VoronoiNoise {
    const PERIODIC: bool = true;

    const NAME: &'static str = "voronoi";

    /// A period that is a whole number of cells along x and y (the cells wrap,
    /// [`VoronoiNoise::sites_periodic`]) and, with Lloyd relaxation, of blocks of `B × B`
    /// cells (the blocks wrap too).
    fn check_period(&self, period: crate::Period) -> Result<(), ModelError> {
        let cell = f64::from(self.cell_size);
        let (side, what) = if self.lloyd_iterations > 0 {
            (
                cell * f64::from(self.lloyd_block),
                format!(
                    "its Lloyd block of voronoi.lloyd_block × voronoi.cell_size = {} × {cell} \
                     pixels",
                    self.lloyd_block
                ),
            )
        } else {
            (
                cell,
                format!("its cell of voronoi.cell_size = {cell} pixels"),
            )
        };
        if period.sides().iter().all(|&p| p % side == 0.0) {
            return Ok(());
        }
        Err(ModelError::Period {
            period: period.to_string(),
            kind: "voronoi",
            requirement: format!(
                "{what} must divide the period's width and height (valid sides: {side}, {}, {}, \
                 …)",
                2.0 * side,
                3.0 * side
            ),
        })
    }

    fn validate(&self) -> Result<(), ModelError> {
        VoronoiNoise::validate(self)
    }

    fn output_channels(&self) -> usize {
        self.output.channels()
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

    pub fn defaults_validate() {
        VoronoiNoise::default().validate().expect("valid");
    }

    pub fn validation_names_the_field_and_range() {
        let cases: Vec<(VoronoiNoise, &str)> = vec![
            (
                VoronoiNoise {
                    cell_size: 0.5,
                    ..VoronoiNoise::default()
                },
                "voronoi.cell_size",
            ),
            (
                VoronoiNoise {
                    jitter: 1.5,
                    ..VoronoiNoise::default()
                },
                "voronoi.jitter",
            ),
            (
                VoronoiNoise {
                    lloyd_iterations: 17,
                    ..VoronoiNoise::default()
                },
                "voronoi.lloyd_iterations",
            ),
            (
                VoronoiNoise {
                    lloyd_block: 0,
                    ..VoronoiNoise::default()
                },
                "voronoi.lloyd_block",
            ),
            (
                VoronoiNoise {
                    output: VoronoiOutput::Palette { colours: vec![] },
                    ..VoronoiNoise::default()
                },
                "voronoi.output.palette.colours",
            ),
            (
                VoronoiNoise {
                    output: VoronoiOutput::Image {
                        width: 2,
                        height: 1,
                        texels: vec![[0.0; 3], [f32::NAN, 0.0, 0.0]],
                    },
                    ..VoronoiNoise::default()
                },
                "voronoi.output.image.texels[1][0]",
            ),
        ];
        for (model, field) in cases {
            let err = model.validate().expect_err(field);
            assert!(err.to_string().starts_with(field), "{field}: {err}");
        }
    }

    pub fn three_dimensions_validate_with_field_paths() {
        let three = VoronoiNoise {
            dimensions: 3,
            output: VoronoiOutput::Border,
            ..VoronoiNoise::default()
        };
        three.validate().expect("3D border is valid");
        let cases = [
            (
                VoronoiNoise {
                    dimensions: 4,
                    ..VoronoiNoise::default()
                },
                "voronoi.dimensions",
            ),
            (
                VoronoiNoise {
                    lloyd_iterations: 1,
                    ..three.clone()
                },
                "voronoi.lloyd_iterations",
            ),
            (
                VoronoiNoise {
                    output: VoronoiOutput::Image {
                        width: 1,
                        height: 1,
                        texels: vec![[0.0; 3]],
                    },
                    ..three.clone()
                },
                "voronoi.dimensions",
            ),
        ];
        for (model, field) in cases {
            let err = model.validate().expect_err(field);
            assert!(err.to_string().starts_with(field), "{field}: {err}");
        }
    }

    pub fn a_file_without_dimensions_is_2d_and_2d_files_are_unchanged() {
        let json = r#"{"seed":3,"cell_size":8.0,"jitter":1.0,"lloyd_iterations":0,"lloyd_block":4,"output":"f1"}"#;
        let m: VoronoiNoise = serde_json::from_str(json).expect("parses");
        assert_eq!(m.dimensions, 2);
        assert_eq!(serde_json::to_string(&m).expect("serialises"), json);
        let three = VoronoiNoise { dimensions: 3, ..m };
        let text = serde_json::to_string(&three).expect("serialises");
        assert!(text.contains(r#""dimensions":3"#), "{text}");
    }

    pub fn the_3d_draw_follows_the_contract() {
        // Cell (i, j, k): PRNG seeded with cell_hash(i, j, VORO, cell_hash(k, 0, VORO, seed)),
        // drawing o_x, o_y, o_z and the ID, each ½ + jitter·(u − ½).
        let m = VoronoiNoise {
            dimensions: 3,
            seed: 11,
            jitter: 0.75,
            ..VoronoiNoise::default()
        };
        for (i, j, k) in [(0i64, 0i64, 0i64), (-5, 7, 100_000), (1 << 20, -3, -9)] {
            let plane = cell_hash(k as i32, 0, VORONOI_LAYER, 11);
            let mut prng = Prng::new(cell_hash(i as i32, j as i32, VORONOI_LAYER, plane));
            let u: Vec<f32> = (0..4).map(|_| prng.next_f32()).collect();
            let (o, id) = m.jittered3(i, j, k);
            for a in 0..3 {
                assert_eq!(
                    o[a],
                    0.5 + 0.75 * (u[a] - 0.5),
                    "cell ({i}, {j}, {k}) axis {a}"
                );
            }
            assert_eq!(id, u[3]);
        }
    }

    pub fn the_pruned_3d_search_is_the_full_search() {
        // Jitter 0 puts seeds on a regular lattice, where ties between cells are everywhere;
        // jitter 1 lets seeds come arbitrarily close.
        let mut prng = Prng::new(77);
        for jitter in [1.0f32, 0.6, 0.0] {
            let m = VoronoiNoise {
                dimensions: 3,
                jitter,
                seed: 4,
                ..VoronoiNoise::default()
            };
            let origin = [-6i64, 1000 - 6, -40_000 - 6];
            let table = m.sites3(origin, [13, 13, 13], None);
            let at = |di: i32, dj: i32, dk: i32| {
                table.get(i64::from(di), 1000 + i64::from(dj), -40_000 + i64::from(dk))
            };
            for n in 0..400 {
                let f = if jitter == 0.0 && n % 2 == 0 {
                    // Points on the lattice's bisector planes and their crossings.
                    [
                        [0.0, 0.5, 0.5],
                        [0.5, 0.0, 0.0],
                        [0.0, 0.0, 0.25],
                        [0.75, 0.0, 0.5],
                    ][(n / 2) % 4]
                } else {
                    [prng.next_f32(), prng.next_f32(), prng.next_f32()]
                };
                for (reach, second, border) in [
                    (NEAREST_REACH, false, false),
                    (F2_REACH_3D, true, false),
                    (BORDER_REACH_3D, false, true),
                ] {
                    let fast = search3(at, f, reach, second, border);
                    let full = search3_full(at, f, reach, second, border);
                    assert_eq!(
                        (
                            fast.site,
                            fast.f1.to_bits(),
                            fast.f2.to_bits(),
                            fast.border.to_bits()
                        ),
                        (
                            full.site,
                            full.f1.to_bits(),
                            full.f2.to_bits(),
                            full.border.to_bits()
                        ),
                        "jitter {jitter}, point {f:?}, reach {reach}"
                    );
                }
            }
        }
    }

    pub fn the_centroid_of_a_regular_grid_cell_is_its_seed() {
        // Seeds on the integer lattice: each Voronoi cell is the unit square around its seed.
        let p = [0.5, 0.5];
        let others: Vec<[f64; 2]> = (-3..=3)
            .flat_map(|y| (-3..=3).map(move |x| [0.5 + f64::from(x), 0.5 + f64::from(y)]))
            .filter(|q| *q != p)
            .collect();
        let c = voronoi_centroid(p, &others);
        assert!(
            (c[0] - 0.5).abs() < 1e-12 && (c[1] - 0.5).abs() < 1e-12,
            "{c:?}"
        );
        // Move one neighbour: the cell is the square cut at x = 0.5 + 0.3 (bisector of 0.5 and
        // 1.1), so [0, 0.8] × [0, 1], centroid (0.4, 0.5).
        let moved: Vec<[f64; 2]> = others
            .iter()
            .map(|&q| if q == [1.5, 0.5] { [1.1, 0.5] } else { q })
            .collect();
        let c = voronoi_centroid(p, &moved);
        assert!(
            (c[0] - 0.4).abs() < 1e-12 && (c[1] - 0.5).abs() < 1e-12,
            "{c:?}"
        );
    }

    /// The centroid by dense sampling: the mean of the grid points nearer `p` than any other.
    fn sampled_centroid(p: [f64; 2], others: &[[f64; 2]]) -> [f64; 2] {
        let n = 400;
        let (mut sx, mut sy, mut count) = (0.0, 0.0, 0.0);
        for a in 0..n {
            for b in 0..n {
                let x = p[0] - 2.0 + 4.0 * (f64::from(a) + 0.5) / f64::from(n);
                let y = p[1] - 2.0 + 4.0 * (f64::from(b) + 0.5) / f64::from(n);
                let d = |q: &[f64; 2]| (x - q[0]).powi(2) + (y - q[1]).powi(2);
                if others.iter().all(|q| d(&p) < d(q)) {
                    sx += x;
                    sy += y;
                    count += 1.0;
                }
            }
        }
        [sx / count, sy / count]
    }

    /// Cell `(cx, cy)`'s jittered seed and its 48 neighbours', in the relaxation's order.
    fn neighbourhood(m: &VoronoiNoise, cx: i64, cy: i64) -> ([f64; 2], Vec<[f64; 2]>) {
        let seed = |i: i64, j: i64| {
            let (o, _) = m.jittered(i, j);
            [i as f64 + f64::from(o[0]), j as f64 + f64::from(o[1])]
        };
        let mut others = Vec::new();
        for j in cy - 3..=cy + 3 {
            for i in cx - 3..=cx + 3 {
                if (i, j) != (cx, cy) {
                    others.push(seed(i, j));
                }
            }
        }
        (seed(cx, cy), others)
    }

    pub fn clipped_centroids_match_dense_sampling() {
        let m = VoronoiNoise::default();
        for (cx, cy) in [(0i64, 0i64), (5, -3), (-40, 17)] {
            let (p, others) = neighbourhood(&m, cx, cy);
            let exact = voronoi_centroid(p, &others);
            let sampled = sampled_centroid(p, &others);
            // 400² samples over 4 × 4 cells: a sample spacing of 0.01, the centroid's error
            // well below it.
            for k in 0..2 {
                assert!(
                    (exact[k] - sampled[k]).abs() < 5e-3,
                    "cell ({cx}, {cy}): {exact:?} vs {sampled:?}"
                );
            }
        }
    }

    /// Sutherland–Hodgman by every half-plane, none skipped (then the same polygon centroid):
    /// the reference the clip's skip must reproduce bit for bit.
    fn centroid_by_every_plane(p: [f64; 2], others: &[[f64; 2]]) -> [f64; 2] {
        let h = 2.0;
        let mut poly = vec![
            [p[0] - h, p[1] - h],
            [p[0] + h, p[1] - h],
            [p[0] + h, p[1] + h],
            [p[0] - h, p[1] + h],
        ];
        for q in others {
            let n = [q[0] - p[0], q[1] - p[1]];
            let m = [(q[0] + p[0]) * 0.5, (q[1] + p[1]) * 0.5];
            let side = |v: &[f64; 2]| (v[0] - m[0]) * n[0] + (v[1] - m[1]) * n[1];
            let mut out = Vec::new();
            for k in 0..poly.len() {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                let (sa, sb) = (side(&a), side(&b));
                if sa <= 0.0 {
                    out.push(a);
                }
                if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
                    let t = sa / (sa - sb);
                    out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
                }
            }
            poly = out;
            if poly.is_empty() {
                return p;
            }
        }
        polygon_centroid(&poly, p)
    }

    /// The clip that skips half-planes holding the whole polygon gives the bits of the clip by
    /// every plane: jittered seeds at every jitter (1 puts seeds on shared cell borders), their
    /// neighbourhoods in the relaxation's order, and seeds that coincide or nearly do.
    pub fn skipped_half_planes_change_no_centroid() {
        let mut checked = 0;
        for jitter in [0.0, 0.3, 1.0] {
            let m = VoronoiNoise {
                jitter,
                ..VoronoiNoise::default()
            };
            let mut buffers = ClipBuffers::default();
            for cy in -12..12i64 {
                for cx in -12..12i64 {
                    let (p, mut others) = neighbourhood(&m, cx, cy);
                    // A seed on p, and one a rounding away from it.
                    if (cx + cy) % 5 == 0 {
                        others[10] = p;
                        others[30] = [p[0] + 1e-12, p[1] - 3e-13];
                    }
                    let fast = voronoi_centroid_in(p, &others, &mut buffers);
                    let slow = centroid_by_every_plane(p, &others);
                    assert!(
                        fast[0].to_bits() == slow[0].to_bits()
                            && fast[1].to_bits() == slow[1].to_bits(),
                        "jitter {jitter}, cell ({cx}, {cy}): {fast:?} against {slow:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 3 * 24 * 24);
    }

    pub fn relaxation_stays_in_the_cells_and_evens_the_spacing() {
        let m = VoronoiNoise {
            lloyd_iterations: 4,
            lloyd_block: 6,
            ..VoronoiNoise::default()
        };
        let raw = VoronoiNoise::default().sites(-6, -6, 18, 18);
        let relaxed = m.sites(-6, -6, 18, 18);
        let spread = |t: &SiteTable| {
            // The variance of the nearest-neighbour distance: Lloyd relaxation evens it out.
            let mut ds = Vec::new();
            for j in 1..17i64 {
                for i in 1..17i64 {
                    let s = t.get(-6 + i, -6 + j);
                    let mut best = f64::INFINITY;
                    for (a, b) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1), (1, 1), (-1, -1)] {
                        let q = t.get(-6 + i + a, -6 + j + b);
                        let dx = a as f64 + f64::from(q.offset[0] - s.offset[0]);
                        let dy = b as f64 + f64::from(q.offset[1] - s.offset[1]);
                        best = best.min((dx * dx + dy * dy).sqrt());
                    }
                    ds.push(best);
                }
            }
            let mean = ds.iter().sum::<f64>() / ds.len() as f64;
            ds.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / ds.len() as f64
        };
        for s in &relaxed.sites {
            assert!((0.0..1.0).contains(&s.offset[0]) && (0.0..1.0).contains(&s.offset[1]));
        }
        assert!(
            spread(&relaxed) < 0.5 * spread(&raw),
            "{} vs {}",
            spread(&relaxed),
            spread(&raw)
        );
        // A window's sites do not depend on where the table starts.
        let part = m.sites(-1, 2, 3, 4);
        assert_eq!(part.get(0, 3), relaxed.get(0, 3));
    }
}
