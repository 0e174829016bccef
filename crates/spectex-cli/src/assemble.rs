//! `spectex assemble`: joins the tiles of a `--tiles C×R` render (OpenEXR files whose data
//! windows place them in one image) into one tiled OpenEXR, band by band of rows.

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use exr::block::reader::ChunksReader;
use exr::math::{RoundingMode, Vec2};
use exr::meta::attribute::{
    AttributeValue, ChannelDescription, IntegerBounds, LevelMode, LineOrder, SampleType, Text,
    TileDescription,
};
use exr::meta::header::Header;
use exr::meta::{BlockDescription, MetaData};

use crate::io::EXR_TILE;
use crate::io::{self, BitDepth, Format};
use crate::stream::{self, Band, RENDER_ATTRIBUTE};

/// Arguments of `spectex assemble`.
#[derive(Debug, Args)]
pub struct AssembleCommand {
    /// Tile files (.exr) written by `--tiles C×R --tile-index K`, in any order.
    #[arg(required = true, value_name = "TILES")]
    tiles: Vec<PathBuf>,
    /// The whole image, a tiled OpenEXR (.exr).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Rows per band, a multiple of 64 (fewer rows, less memory) [default: about 8 Mpix per
    /// band].
    #[arg(long, value_name = "N", value_parser = crate::args::parse_band_rows)]
    band_rows: Option<usize>,
}

/// What a tile file says about itself.
struct Tile {
    path: PathBuf,
    /// Where its pixels lie in the image.
    data: IntegerBounds,
    /// The image.
    display: IntegerBounds,
    /// Channel names, in the file's order.
    channels: Vec<String>,
    /// The render it belongs to ([`RENDER_ATTRIBUTE`]).
    render: Option<String>,
}

fn read_tile(path: &Path) -> Result<Tile> {
    let meta = MetaData::read_from_file(path, false).map_err(|e| {
        anyhow!(
            "cannot read tile '{}': {e}; give the .exr files that `spectex render --tiles` wrote",
            path.display()
        )
    })?;
    let [header] = meta.headers.as_slice() else {
        bail!(
            "tile '{}' has {} layers; a spectex tile has one",
            path.display(),
            meta.headers.len()
        );
    };
    if header.deep {
        bail!(
            "tile '{}' holds deep data; a spectex tile is flat",
            path.display()
        );
    }
    if let Some(c) = header
        .channels
        .list
        .iter()
        .find(|c| c.sample_type != SampleType::F32)
    {
        bail!(
            "tile '{}': channel {} is not 32-bit float; assemble joins the f32 tiles `spectex \
             render --tiles` writes",
            path.display(),
            c.name
        );
    }
    let render = match header
        .own_attributes
        .other
        .get(&Text::from(RENDER_ATTRIBUTE))
    {
        Some(AttributeValue::Text(t)) => Some(t.to_string()),
        _ => None,
    };
    Ok(Tile {
        path: path.to_path_buf(),
        data: header.data_window(),
        display: header.shared_attributes.display_window,
        channels: header
            .channels
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect(),
        render,
    })
}

/// Whether `a` and `b` share a pixel.
fn overlap(a: &IntegerBounds, b: &IntegerBounds) -> bool {
    let (a0, a1) = (a.position, a.position + a.size.to_i32());
    let (b0, b1) = (b.position, b.position + b.size.to_i32());
    a0.0 < b1.0 && b0.0 < a1.0 && a0.1 < b1.1 && b0.1 < a1.1
}

/// Whether `inner` lies within `outer`.
fn inside(inner: &IntegerBounds, outer: &IntegerBounds) -> bool {
    let (i0, i1) = (inner.position, inner.position + inner.size.to_i32());
    let (o0, o1) = (outer.position, outer.position + outer.size.to_i32());
    i0.0 >= o0.0 && i0.1 >= o0.1 && i1.0 <= o1.0 && i1.1 <= o1.1
}

/// The topmost, then leftmost pixel of `image` that no tile covers, if any: it lies on the
/// image's first row or column or just past a tile's right or bottom edge.
fn uncovered(tiles: &[Tile], image: &IntegerBounds) -> Option<(i32, i32)> {
    let edge = |axis: usize| -> Vec<i32> {
        let mut v: Vec<i32> = std::iter::once(if axis == 0 {
            image.position.0
        } else {
            image.position.1
        })
        .chain(tiles.iter().map(|t| {
            let end = t.data.position + t.data.size.to_i32();
            if axis == 0 { end.0 } else { end.1 }
        }))
        .collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let end = image.position + image.size.to_i32();
    for &y in edge(1).iter().filter(|&&y| y < end.1) {
        for &x in edge(0).iter().filter(|&&x| x < end.0) {
            let pixel = IntegerBounds::new(Vec2(x, y), Vec2(1, 1));
            if !tiles.iter().any(|t| overlap(&t.data, &pixel)) {
                return Some((x, y));
            }
        }
    }
    None
}

/// Checks that `tiles` are of one render and cover its image exactly once.
fn check_grid(tiles: &[Tile]) -> Result<()> {
    let Some(first) = tiles.first() else {
        bail!("no tiles given");
    };
    for t in tiles {
        if t.display != first.display {
            bail!(
                "tiles '{}' and '{}' belong to images of different sizes ({}×{} and {}×{}); \
                 give the tiles of one render",
                first.path.display(),
                t.path.display(),
                first.display.size.0,
                first.display.size.1,
                t.display.size.0,
                t.display.size.1
            );
        }
        if t.channels != first.channels {
            bail!(
                "tiles '{}' and '{}' have different channels ({} and {}); give the tiles of \
                 one render",
                first.path.display(),
                t.path.display(),
                first.channels.join(","),
                t.channels.join(",")
            );
        }
        if t.render != first.render {
            bail!(
                "tiles '{}' and '{}' are of different renders (model or window differ: '{}' and \
                 '{}'); give the tiles of one render",
                first.path.display(),
                t.path.display(),
                first.render.as_deref().unwrap_or("unnamed"),
                t.render.as_deref().unwrap_or("unnamed")
            );
        }
        if !inside(&t.data, &t.display) {
            bail!(
                "tile '{}' lies outside its image; it is not a spectex tile",
                t.path.display()
            );
        }
    }
    for (i, a) in tiles.iter().enumerate() {
        if let Some(b) = tiles[i + 1..].iter().find(|b| overlap(&a.data, &b.data)) {
            bail!(
                "tiles '{}' and '{}' overlap (at ({}, {})); give each tile of the grid once",
                a.path.display(),
                b.path.display(),
                a.data.position.0.max(b.data.position.0),
                a.data.position.1.max(b.data.position.1)
            );
        }
    }
    let covered: usize = tiles.iter().map(|t| t.data.size.area()).sum();
    let total = first.display.size.area();
    if covered != total {
        let (x, y) = uncovered(tiles, &first.display).unwrap_or((0, 0));
        bail!(
            "the tiles cover {covered} of the image's {total} pixels ({}×{}): pixel ({x}, {y}) is \
             in none; render the missing tiles and give them all",
            first.display.size.0,
            first.display.size.1
        );
    }
    Ok(())
}

/// Copies the rows `y0..y0 + rows` (image rows, from the display window's top) of `tile`
/// into `band`'s planes, whose rows are the display window's width.
fn read_rows(tile: &Tile, image: &IntegerBounds, y0: i32, band: &mut Band) -> Result<()> {
    let file = File::open(&tile.path)
        .with_context(|| format!("cannot open tile '{}'", tile.path.display()))?;
    let rows = band.rows as i32;
    let (tx, ty) = (tile.data.position.0, tile.data.position.1);
    let width = image.size.0;
    let fail = |e: exr::error::Error| anyhow!("cannot read tile '{}': {e}", tile.path.display());
    exr::block::read(BufReader::new(file), false)
        .map_err(fail)?
        .filter_chunks(false, |_, _, block| {
            let top = ty + block.pixel_position.1 as i32;
            top < y0 + rows && y0 < top + block.pixel_size.1 as i32
        })
        .map_err(fail)?
        .decompress_sequential(false, |meta, block| {
            for line in block.lines(&meta.headers[0].channels) {
                let y = ty + line.location.position.1 as i32;
                if y < y0 || y >= y0 + rows {
                    continue;
                }
                let x = (tx - image.position.0) as usize + line.location.position.0;
                let start = (y - y0) as usize * width + x;
                let plane = &mut band.planes[line.location.channel];
                line.read_samples_into_slice(
                    &mut plane[start..start + line.location.sample_count],
                )?;
            }
            Ok(())
        })
        .map_err(fail)
}

/// `spectex assemble`.
pub fn assemble(cmd: &AssembleCommand) -> Result<()> {
    if io::check_output(&cmd.output, BitDepth::Eight)? != Format::Exr {
        bail!(
            "assemble writes OpenEXR: give -o a .exr name, e.g. -o whole.exr ('{}')",
            cmd.output.display()
        );
    }
    let tiles = cmd
        .tiles
        .iter()
        .map(PathBuf::as_path)
        .map(read_tile)
        .collect::<Result<Vec<_>>>()?;
    check_grid(&tiles)?;
    let first = &tiles[0];
    let image = first.display;
    let (width, height) = (image.size.0, image.size.1);

    let list = first
        .channels
        .iter()
        .map(|n| ChannelDescription::new(n.as_str(), SampleType::F32, false))
        .collect::<Vec<_>>();
    let mut header = Header::new(Text::from("spectex"), (width, height), list.into())
        .with_encoding(
            stream::EXR_COMPRESSION,
            BlockDescription::Tiles(TileDescription {
                tile_size: Vec2(EXR_TILE, EXR_TILE),
                level_mode: LevelMode::Singular,
                rounding_mode: RoundingMode::Down,
            }),
            LineOrder::Increasing,
        )
        .with_display_window(image)
        .with_position(image.position);
    header.own_attributes.layer_name = None;
    header.own_attributes.software_name = Some(Text::from("spectex"));
    if let Some(render) = &first.render {
        header.own_attributes.other.insert(
            Text::from(RENDER_ATTRIBUTE),
            AttributeValue::Text(Text::from(render.as_str())),
        );
    }

    let tmp = io::temporary_beside(&cmd.output)?;
    let rows = cmd.band_rows.unwrap_or_else(|| stream::band_rows(width));
    let bar = crate::progress::progress_bar(height as u64, "assembling");
    let mut failure = None;
    let mut y = 0;
    let spare: std::cell::RefCell<Option<Band>> = std::cell::RefCell::new(None);
    {
        let mut out = BufWriter::with_capacity(1 << 20, tmp.as_file());
        let next_band = || -> Option<Band> {
            if y >= height || failure.is_some() {
                return None;
            }
            let n = rows.min(height - y);
            let mut band = spare.borrow_mut().take().unwrap_or(Band {
                y: 0,
                rows: 0,
                planes: vec![Vec::new(); first.channels.len()],
            });
            band.y = y;
            band.rows = n;
            for plane in &mut band.planes {
                plane.clear();
                plane.resize(n * width, 0.0);
            }
            let y0 = image.position.1 + y as i32;
            for tile in &tiles {
                let (top, bottom) = (
                    tile.data.position.1,
                    tile.data.position.1 + tile.data.size.1 as i32,
                );
                if top < y0 + n as i32
                    && y0 < bottom
                    && let Err(e) = read_rows(tile, &image, y0, &mut band)
                {
                    failure = Some(e);
                    return None;
                }
            }
            y += n;
            bar.inc(n as u64);
            Some(band)
        };
        let written = stream::write_tiled_exr(&mut out, header, next_band, |band| {
            *spare.borrow_mut() = Some(band);
        });
        if let Some(e) = failure {
            return Err(e);
        }
        written.with_context(|| format!("cannot write '{}'", cmd.output.display()))?;
        out.flush()
            .with_context(|| format!("cannot write '{}'", cmd.output.display()))?;
    }
    bar.finish_and_clear();
    io::finish(tmp, &cmd.output)?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "wrote {} ({width}×{height} from {} tiles)",
            cmd.output.display(),
            tiles.len()
        );
    }
    Ok(())
}
