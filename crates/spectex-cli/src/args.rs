//! The command's shared arguments and their parsers: where and how to render ([`RenderArgs`],
//! [`StreamArgs`], [`Device`]) and the value parsers of sizes, offsets and band heights. The
//! ground floor of the command: it imports no other module of it but `io`.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use spectex_model::Period;

use crate::io::{BitDepth, EXR_TILE};

/// Output size, pixels, unless `--size` is given (or a periodic model's period sets it).
pub(crate) const DEFAULT_SIZE: (usize, usize) = (512, 512);

/// Model pixels per output pixel unless `--scale` is given: one.
pub(crate) const DEFAULT_SCALE: f64 = 1.0;

/// The plane z on which a 3D model is evaluated unless `--z` is given.
pub(crate) const DEFAULT_Z: f64 = 0.0;

/// Where and how to render.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Output image: .png (clamped to [0, 1]) or .exr (32-bit float, values kept).
    #[arg(short, long, value_name = "OUT")]
    pub(crate) output: PathBuf,
    /// Output size WIDTHxHEIGHT (1 to 65536 per side).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub(crate) size: Option<(usize, usize)>,
    /// Position of the top-left pixel, X,Y in model pixels (any finite values up to ±2^30).
    #[arg(long, value_name = "X,Y", value_parser = parse_offset, allow_hyphen_values = true)]
    pub(crate) offset: Option<[f64; 2]>,
    /// Model pixels per output pixel (0 < S ≤ 1e6).
    #[arg(long, default_value_t = DEFAULT_SCALE)]
    pub(crate) scale: f64,
    /// Point-sample a minified render (--scale > 1) instead of fading out what its pixels cannot
    /// resolve (the default: LRP cosines, fBm octaves … above the output's Nyquist frequency).
    #[arg(long)]
    pub(crate) no_filter: bool,
    /// Bits per channel of a PNG output.
    #[arg(long, value_enum, default_value_t = BitDepth::DEFAULT)]
    pub(crate) bit_depth: BitDepth,
    /// The plane z (model pixels) on which a 3D model is evaluated; 2D models ignore it.
    #[arg(long, default_value_t = DEFAULT_Z, allow_hyphen_values = true)]
    pub(crate) z: f64,
    /// Evaluator: the CPU reference, the GPU (wgpu; WGPU_ADAPTER_NAME picks the adapter), or
    /// auto (the GPU when an adapter exists, else the CPU; says which it used).
    #[arg(long, value_enum, default_value = "cpu")]
    pub(crate) device: Device,
    /// Make the texture exactly periodic with period WxH model pixels (seamless tiles: a
    /// 2W×2H render is the W×H one repeated 2×2, bit for bit); bare --periodic takes the
    /// output's extent (--size × --scale). Lattices are hashed modulo the period; LRP lattices
    /// are fitted to it; every fBm octave's cell must divide it. Every kind with a periodic form
    /// renders periodic on the CPU and the GPU.
    #[arg(long, value_name = "WxH", num_args = 0..=1, default_missing_value = "")]
    pub(crate) periodic: Option<String>,
    #[command(flatten)]
    pub(crate) stream: StreamArgs,
}

impl RenderArgs {
    /// The period `--periodic` asks for, for an output of `size` pixels (`None` without it).
    ///
    /// # Errors
    /// A period that is not `WxH` with whole positive sides, or a bare `--periodic` whose
    /// output extent (`--size × --scale`) is not whole.
    pub(crate) fn period(&self, size: (usize, usize)) -> Result<Option<Period>> {
        let Some(text) = self.periodic.as_deref() else {
            return Ok(None);
        };
        let period = if text.is_empty() {
            let extent = [size.0 as f64 * self.scale, size.1 as f64 * self.scale];
            if extent
                .iter()
                .any(|e| e.fract() != 0.0 || *e > f64::from(u32::MAX))
            {
                return Err(anyhow!(
                    "--periodic alone takes the output's extent --size × --scale = {}×{} model \
                     pixels, which is not whole; give the period as --periodic WxH",
                    extent[0],
                    extent[1]
                ));
            }
            Period::new(extent[0] as u32, extent[1] as u32)
        } else {
            Period::parse(text)
        };
        period
            .map(Some)
            .map_err(|e| anyhow!("--periodic: {e}; for example --periodic 256x256"))
    }
}

/// Streaming and batch tiling of a render.
#[derive(Debug, Args)]
pub struct StreamArgs {
    /// Render and write band by band, holding one band of rows in memory: a tiled OpenEXR
    /// (64×64 tiles, one Y channel for grey models) or a PNG written row band by row band.
    /// Automatic above 4096×4096 pixels.
    #[arg(long)]
    pub(crate) stream: bool,
    /// Render only one tile of a C×R grid over the --size image (batch clusters): tiles of
    /// ceil(W/C)×ceil(H/R) pixels, the last column and row cut to the image. The output (.exr)
    /// records its place; `spectex assemble` joins the tiles.
    #[arg(long, value_name = "CxR", value_parser = parse_size)]
    pub(crate) tiles: Option<(usize, usize)>,
    /// The tile --tiles renders, row-major from the top-left (0 to C·R − 1); read from
    /// SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX when absent.
    #[arg(long, value_name = "K", requires = "tiles")]
    pub(crate) tile_index: Option<usize>,
    /// Rows per band of a streamed render, a multiple of 64 (fewer rows, less memory) [default:
    /// about 8 Mpix per band, 256 rows at 32768 columns].
    #[arg(long, value_name = "N", value_parser = parse_band_rows)]
    pub(crate) band_rows: Option<usize>,
}

/// Which evaluator renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    /// spectex-cpu: same bytes for any thread count.
    Cpu,
    /// spectex-gpu: within the cross-checked tolerances of the CPU.
    Gpu,
    /// The GPU when an adapter exists, else the CPU.
    Auto,
}

/// Parses `WIDTHxHEIGHT` (also `X` or `×` as separator).
#[doc(hidden)]
pub fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let err = || format!("'{s}' is not a size; write WIDTHxHEIGHT, for example 1024x768");
    let (w, h) = s.split_once(['x', 'X', '×']).ok_or_else(err)?;
    let w: usize = w.trim().parse().map_err(|_| err())?;
    let h: usize = h.trim().parse().map_err(|_| err())?;
    Ok((w, h))
}

/// Parses `X,Y`.
fn parse_offset(s: &str) -> Result<[f64; 2], String> {
    let err = || format!("'{s}' is not an offset; write X,Y, for example 1e7,1e7 or -20.5,3");
    let (x, y) = s.split_once(',').ok_or_else(err)?;
    let x: f64 = x.trim().parse().map_err(|_| err())?;
    let y: f64 = y.trim().parse().map_err(|_| err())?;
    Ok([x, y])
}

/// Parses `--band-rows`: a multiple of [`EXR_TILE`] from 64 to 65536.
pub(crate) fn parse_band_rows(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if (EXR_TILE..=65_536).contains(&n) && n.is_multiple_of(EXR_TILE) => Ok(n),
        _ => Err(format!(
            "'{s}' is not a band height; give a multiple of 64 rows from 64 to 65536"
        )),
    }
}
