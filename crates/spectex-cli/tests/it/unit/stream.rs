//! Tiles, tile indices and bands of the streamed renders (`src/stream.rs`).

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected Ok or Err"
)]

use anyhow::Result;
use spectex_cli::io::EXR_TILE;
use spectex_cli::stream::*;

/// Every pixel of the image in exactly one tile, tiles of ⌈W/C⌉ × ⌈H/R⌉ pixels at most:
/// counted pixel by pixel, the slow obvious way.
#[test]
fn tiles_cover_the_image_once() {
    for (image, grid) in [
        ((200, 130), (3, 2)),
        ((7, 5), (7, 5)),
        ((10, 10), (4, 3)),
        ((1, 1), (1, 1)),
        ((65, 64), (2, 1)),
    ] {
        let mut hits = vec![0u8; image.0 * image.1];
        for k in 0..grid.0 * grid.1 {
            let t = tile_region(image, grid, k)
                .unwrap_or_else(|e| panic!("{image:?} {grid:?} {k}: {e}"));
            assert!(
                t.width >= 1 && t.height >= 1,
                "{image:?} {grid:?} {k}: empty"
            );
            assert!(t.width <= image.0.div_ceil(grid.0) && t.height <= image.1.div_ceil(grid.1));
            for y in t.y..t.y + t.height {
                for x in t.x..t.x + t.width {
                    hits[y * image.0 + x] += 1;
                }
            }
        }
        assert!(
            hits.iter().all(|&h| h == 1),
            "{image:?} {grid:?}: not covered once"
        );
    }
    // The 3×2 grid of a 200×130 image: tiles of 67×65, the last column 66 wide.
    let t = tile_region((200, 130), (3, 2), 5).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((t.x, t.y, t.width, t.height), (134, 65, 66, 65));
}

#[test]
fn bad_grids_and_indices_are_refused() {
    let err = |r: Result<Region>| r.map(|_| ()).unwrap_err().to_string();
    assert!(err(tile_region((10, 10), (0, 2), 0)).contains("no tiles"));
    // ⌈10/6⌉ = 2: columns at 0, 2, 4, 6, 8 and an empty sixth at 10.
    assert!(err(tile_region((10, 10), (6, 1), 0)).contains("last column"));
    assert!(err(tile_region((10, 10), (1, 6), 0)).contains("last row"));
    assert!(err(tile_region((10, 10), (2, 2), 4)).contains("0 to 3"));
}

#[test]
fn the_index_comes_from_the_flag_then_slurm_then_kubernetes() {
    let env = |vars: &'static [(&'static str, &'static str)]| {
        move |name: &str| {
            vars.iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| (*v).to_owned())
        }
    };
    let both = env(&[("SLURM_ARRAY_TASK_ID", "3"), ("JOB_COMPLETION_INDEX", "5")]);
    assert_eq!(tile_index(Some(1), both).ok(), Some(1));
    assert_eq!(tile_index(None, both).ok(), Some(3));
    assert_eq!(
        tile_index(None, env(&[("JOB_COMPLETION_INDEX", "5")])).ok(),
        Some(5)
    );
    let none = tile_index(None, env(&[])).unwrap_err().to_string();
    assert!(none.contains("--tile-index") && none.contains("SLURM_ARRAY_TASK_ID"));
    let bad = tile_index(None, env(&[("SLURM_ARRAY_TASK_ID", "x")])).unwrap_err();
    assert!(bad.to_string().contains("SLURM_ARRAY_TASK_ID = 'x'"));
}

#[test]
fn bands_are_whole_tile_rows() {
    for width in [1, 63, 64, 200, 4096, 32768, 65536] {
        let rows = band_rows(width);
        assert!(
            rows >= EXR_TILE && rows.is_multiple_of(EXR_TILE),
            "{width}: {rows}"
        );
        assert!(
            rows * width >= BAND_PIXELS.min(EXR_TILE * width),
            "{width}: {rows}"
        );
    }
}
