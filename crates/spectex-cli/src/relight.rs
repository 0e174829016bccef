//! `spectex relight`: a height map shaded under a directional light, or its tangent-space
//! normal map (`spectex_spectrum::relief`).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use ndarray::{Array3, Axis};
use spectex_spectrum::relief::{
    DEFAULT_AMBIENT, DEFAULT_LIGHT, DEFAULT_STRENGTH, Edges, normal_map, shade,
};

use crate::io::{self, BitDepth};

/// Arguments of `spectex relight`.
#[derive(Debug, Args)]
pub struct RelightCommand {
    /// Height map (grey; a colour image's Rec. 709 luminance), values 0 to 1.
    input: PathBuf,
    /// Output image (.png or .exr).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Light direction AZIMUTH,ELEVATION in degrees (azimuth 0 = from the right, 90 = from the
    /// top of the image; elevation 0 to 90 above the surface).
    #[arg(long, value_name = "AZ,EL", default_value_t = Light(DEFAULT_LIGHT), value_parser = parse_light, allow_hyphen_values = true)]
    light: Light,
    /// Relief: a pixel value of 1 is this many pixels high (0 < S ≤ 1e6).
    #[arg(long, default_value_t = DEFAULT_STRENGTH)]
    strength: f64,
    /// Ambient light, 0 to 1.
    #[arg(long, default_value_t = DEFAULT_AMBIENT)]
    ambient: f64,
    /// Write the tangent-space normal map ((n + 1)/2, +y up, OpenGL) instead of the shading.
    #[arg(long)]
    normals: bool,
    /// The height map tiles: differences wrap around its borders (else one-sided there).
    #[arg(long)]
    periodic: bool,
    /// Bits per channel of a PNG output.
    #[arg(long, value_enum, default_value_t = BitDepth::DEFAULT)]
    bit_depth: BitDepth,
}

/// `AZIMUTH,ELEVATION` as parsed from `--light` (and written so, for a default).
#[derive(Debug, Clone, Copy)]
pub struct Light([f64; 2]);

impl std::fmt::Display for Light {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{}", self.0[0], self.0[1])
    }
}

fn parse_light(s: &str) -> Result<Light, String> {
    let err = || {
        format!(
            "'{s}' is not a light direction; write AZIMUTH,ELEVATION in degrees, for example 135,45"
        )
    };
    let (a, e) = s.split_once(',').ok_or_else(err)?;
    let a: f64 = a.trim().parse().map_err(|_| err())?;
    let e: f64 = e.trim().parse().map_err(|_| err())?;
    Ok(Light([a, e]))
}

/// `spectex relight`.
pub fn relight(cmd: &RelightCommand) -> Result<()> {
    let format = io::check_output(&cmd.output, cmd.bit_depth)?;
    let (loaded, name) = io::load_input(Some(&cmd.input))?;
    let height = io::grey(&loaded.pixels, &name);
    let edges = if cmd.periodic {
        Edges::Wrap
    } else {
        Edges::Clamp
    };
    let image = if cmd.normals {
        normal_map(height.view(), cmd.strength, edges)
            .map_err(|e| anyhow!("{e}; check --strength and the input"))?
    } else {
        let s = shade(
            height.view(),
            cmd.strength,
            edges,
            cmd.light.0[0],
            cmd.light.0[1],
            cmd.ambient,
        )
        .map_err(|e| anyhow!("{e}; check --light, --strength and --ambient"))?;
        s.insert_axis(Axis(0))
    };
    let image: Array3<f64> = image;
    let report = io::save(&cmd.output, &image, format)?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        let (_, h, w) = image.dim();
        println!(
            "wrote {} ({w}×{h}, {}{})",
            cmd.output.display(),
            if cmd.normals { "normal map" } else { "shading" },
            if cmd.periodic { ", periodic" } else { "" }
        );
    }
    crate::progress::note_clipping(report);
    Ok(())
}
