//! Wavelet noise on the CPU; the definition, the tile and the randomness contract are in
//! [`spectex_model::wavelet`].
//!
//! The sum order is the model's: `z` weights first (done once per band at construction, which
//! collapses a 3D tile to the `n × n` plane of the evaluator's `z`), then `y` (once per row and
//! band, over the whole plane row: `n` values), then `x` per pixel. Columns are located once per
//! band of rows with [`locate_sample`], the function the GPU's host tables use, so a pixel depends
//! only on its own position: any thread count and any tiling give the same bits. The per-pixel
//! loop is three gathers and five plain `*`/`+` per band, written without FMA.
//!
//! ```
//! use spectex_cpu::wavelet::WaveletEvaluator;
//! use spectex_model::WaveletNoise;
//!
//! let model = WaveletNoise {
//!     seed: 1,
//!     dimensions: 2,
//!     tile_size: 32,
//!     cell_size: 8.0,
//!     bands: vec![1.0],
//!     amplitude: 1.0,
//!     mean: 0.0,
//! };
//! model.validate()?;
//! let eval = WaveletEvaluator::new(&model, 0.0);
//! // The noise is periodic with the tile: n · cell_size pixels.
//! assert_eq!(eval.eval(3.25, -7.5).to_bits(), eval.eval(3.25 + 256.0, -7.5).to_bits());
//! # Ok::<(), spectex_model::ModelError>(())
//! ```

use spectex_model::Window;
use spectex_model::wavelet::{Band, WaveletNoise, locate_sample, spline_weights};

/// Columns located together (bounds the per-task tables to `bands × 512` entries).
const COLUMN_CHUNK: usize = 512;

/// A wavelet noise prepared for one plane `z`.
#[derive(Debug, Clone)]
pub struct WaveletEvaluator {
    n: usize,
    dimensions: u32,
    mean: f32,
    bands: Vec<Band>,
    /// Per band, the `n × n` plane read by `y` and `x`: the tile itself in 2D, the `z`-weighted
    /// sum of three tile layers in 3D.
    planes: Vec<Vec<f32>>,
}

impl WaveletEvaluator {
    /// Builds the tile and the planes of `model` (validated) at the plane `z` (pixels; 2D
    /// models ignore it).
    #[must_use]
    pub fn new(model: &WaveletNoise, z: f64) -> Self {
        let tile = model.tile();
        let n = tile.side;
        let bands = model.bands();
        let planes = bands.iter().map(|b| tile.plane(b, z)).collect();
        Self {
            n,
            dimensions: model.dimensions,
            mean: model.mean,
            bands,
            planes,
        }
    }

    /// Tile samples read per pixel (`3^d` per band, for reports).
    #[must_use]
    pub fn samples_per_pixel(&self) -> f64 {
        (self.bands.len() * 3usize.pow(self.dimensions)) as f64
    }

    /// The value at `(x, y)` (pixels): the same bits as a render of that pixel.
    #[must_use]
    pub fn eval(&self, x: f64, y: f64) -> f32 {
        let n = self.n as u32;
        let mut acc = 0.0f32;
        for (band, plane) in self.bands.iter().zip(&self.planes) {
            let row = self.plane_row(band, plane, y);
            let (i0, f) = locate_sample(x, band.side, band.offset[0], n);
            acc += band.amplitude * self.tap(&row, i0 as usize, spline_weights(f));
        }
        self.mean + acc
    }

    /// `R_i = Σ_j w_{y,j} P_{j,i}` over the plane row of `y`.
    fn plane_row(&self, band: &Band, plane: &[f32], y: f64) -> Vec<f32> {
        let n = self.n;
        let (j0, f) = locate_sample(y, band.side, band.offset[1], n as u32);
        let w = spline_weights(f);
        let line = |t: usize| {
            let j = (j0 as usize + t) % n;
            &plane[j * n..(j + 1) * n]
        };
        let (a, b, c) = (line(0), line(1), line(2));
        (0..n)
            .map(|i| (w[0] * a[i] + w[1] * b[i]) + w[2] * c[i])
            .collect()
    }

    #[inline(always)]
    fn tap(&self, row: &[f32], i0: usize, w: [f32; 3]) -> f32 {
        let n = self.n;
        let i1 = if i0 + 1 == n { 0 } else { i0 + 1 };
        let i2 = if i1 + 1 == n { 0 } else { i1 + 1 };
        (w[0] * row[i0] + w[1] * row[i1]) + w[2] * row[i2]
    }

    /// Evaluates row `row` of `window` into `out` (`window.width` values).
    pub fn eval_row(&self, window: &Window, row: usize, out: &mut [f32]) {
        self.eval_rows(window, row, out);
    }

    /// Evaluates the rows `first..` of `window` that `out` holds (`k · window.width` values).
    pub fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        let width = window.width;
        if width == 0 {
            return;
        }
        let n = self.n as u32;
        let rows = out.len() / width;
        // Per band, its plane row of each output row: computed once, shared by every chunk.
        let plane_rows: Vec<Vec<Vec<f32>>> = (0..rows)
            .map(|r| {
                let y = window.y(first + r);
                self.bands
                    .iter()
                    .zip(&self.planes)
                    .map(|(b, p)| self.plane_row(b, p, y))
                    .collect()
            })
            .collect();
        let mut index = vec![0u32; COLUMN_CHUNK];
        let mut weights = vec![[0.0f32; 3]; COLUMN_CHUNK];
        let mut acc = vec![0.0f32; COLUMN_CHUNK];
        for start in (0..width).step_by(COLUMN_CHUNK) {
            let len = COLUMN_CHUNK.min(width - start);
            // Located per band for this chunk: (bands × len) entries.
            let located: Vec<(Vec<u32>, Vec<[f32; 3]>)> = self
                .bands
                .iter()
                .map(|b| {
                    for c in 0..len {
                        let (i0, f) = locate_sample(window.x(start + c), b.side, b.offset[0], n);
                        index[c] = i0;
                        weights[c] = spline_weights(f);
                    }
                    (index[..len].to_vec(), weights[..len].to_vec())
                })
                .collect();
            for r in 0..rows {
                acc[..len].fill(0.0);
                for (b, band) in self.bands.iter().enumerate() {
                    let row = &plane_rows[r][b];
                    let (idx, w) = &located[b];
                    for c in 0..len {
                        acc[c] += band.amplitude * self.tap(row, idx[c] as usize, w[c]);
                    }
                }
                let line = &mut out[r * width + start..r * width + start + len];
                for (o, a) in line.iter_mut().zip(&acc[..len]) {
                    *o = self.mean + a;
                }
            }
        }
    }
}

impl crate::CpuKind for WaveletNoise {
    /// The bench case: `testdata/models/wavelet-2d.json`.
    fn bench_model() -> crate::BenchModel {
        crate::BenchModel::Testdata("wavelet-2d.json")
    }

    fn cpu_kernel(&self, z: f64) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(WaveletEvaluator::new(self, z)))
    }

    /// The plain kernel: wavelet noise repeats with its tile, which divides every period the
    /// model accepts ([`spectex_model::ModelKind::check_period`]).
    fn cpu_kernel_periodic(
        &self,
        z: f64,
        _period: spectex_model::Period,
    ) -> Result<Box<dyn crate::RowKernel>, crate::CpuError> {
        Ok(Box::new(WaveletEvaluator::new(self, z)))
    }
}

impl crate::RowKernel for WaveletEvaluator {
    fn cost_per_pixel(&self) -> f64 {
        self.samples_per_pixel()
    }

    fn eval_rows(&self, window: &Window, first: usize, out: &mut [f32]) {
        WaveletEvaluator::eval_rows(self, window, first, out);
    }
}
