//! `spectex export`: a model over the constants limit is refused with one `error:` line that
//! names `--tables` and leaves no file; with `--tables` the module declares the storage buffer
//! at the requested (or default) group and binding, and the binary file starts with the
//! model's first table — for wavelet-2d its tile, the model crate's own values, as
//! little-endian f32 words.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use super::common::{s, scratch, spectex, spectex_ok};

const WAVELET_2D: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../testdata/models/wavelet-2d.json"
);

#[test]
fn a_large_model_needs_tables_and_gets_them_in_a_buffer() {
    let dir = scratch("export-tables");
    let wgsl = dir.join("model.wgsl");
    let bin = dir.join("model.bin");

    let refused = spectex(&["export", WAVELET_2D, "--wgsl", s(&wgsl)]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert!(
        lines.len() == 1 && lines[0].starts_with("error: ") && lines[0].contains("--tables"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "file left");

    spectex_ok(&[
        "export",
        WAVELET_2D,
        "--wgsl",
        s(&wgsl),
        "--tables",
        s(&bin),
    ]);
    let module = std::fs::read_to_string(&wgsl).unwrap();
    assert!(
        module.contains("@group(3) @binding(100) var<storage, read> spectex_tables: array<u32>;"),
        "default group and binding"
    );
    let model = spectex_model::from_json(&std::fs::read_to_string(WAVELET_2D).unwrap()).unwrap();
    let spectex_model::Model::Wavelet(wavelet) = model else {
        panic!("wavelet-2d.json is not a wavelet model");
    };
    let tile: Vec<u8> = wavelet
        .tile()
        .values
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let bytes = std::fs::read(&bin).unwrap();
    // The 128² tile (65 536 bytes) alone: the bands and the (unused) per-tile records stay
    // constants in the module, which reads them at literal indexes.
    assert_eq!(tile.len(), 65_536);
    assert!(
        bytes == tile,
        "the buffer is not the tile ({} bytes)",
        bytes.len()
    );

    spectex_ok(&[
        "export",
        WAVELET_2D,
        "--wgsl",
        s(&wgsl),
        "--tables",
        s(&bin),
        "--group",
        "1",
        "--binding",
        "5",
    ]);
    let module = std::fs::read_to_string(&wgsl).unwrap();
    assert!(
        module.contains("@group(1) @binding(5) var<storage, read> spectex_tables: array<u32>;"),
        "--group 1 --binding 5"
    );
}
