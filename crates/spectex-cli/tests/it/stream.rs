//! Streamed renders (`--stream`), batch tiles (`--tiles C×R --tile-index K` or the batch
//! engines' index variables) and `spectex assemble`: the same values as a whole render held in
//! memory, read back with the `exr` and `image` crates; and the refusals of bad grids.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::{read_exr, s, scratch, spectex_ok};

/// The models directory of the repository.
fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/models")
        .join(name)
}

/// Runs `spectex` with `env` set and the batch engines' index variables otherwise unset.
fn spectex_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_spectex"));
    cmd.args(args)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().unwrap()
}

/// Asserts `got` and `want` are the same bits, naming the first differing pixel.
fn assert_same_bits(got: &[f32], want: &[f32], width: usize, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: sizes");
    if let Some(i) = (0..got.len()).find(|&i| got[i].to_bits() != want[i].to_bits()) {
        panic!(
            "{what}: pixel ({}, {}) is {} here, {} in the whole render",
            i % width,
            i / width,
            got[i],
            want[i]
        );
    }
}

/// A 3×2 grid over a 200×130 image (sizes that do not divide), every index run in sequence —
/// by `--tile-index`, by Slurm's and by Kubernetes' variable — and assembled: the same bits
/// as the whole render held in memory.
#[test]
fn tiles_of_a_grid_assemble_into_the_whole_render() {
    let dir = scratch("stream-grid");
    let m = model("classic-perlin-fbm.json");
    let whole = dir.join("whole.exr");
    spectex_ok(&[
        "render",
        s(&m),
        "--size",
        "200x130",
        "--offset",
        "-31.5,7",
        "-o",
        s(&whole),
    ]);
    let mut tiles = Vec::new();
    for k in 0..6 {
        let tile = dir.join(format!("tile-{k}.exr"));
        let index = k.to_string();
        let mut args = vec![
            "render",
            s(&m),
            "--size",
            "200x130",
            "--offset",
            "-31.5,7",
            "--tiles",
            "3x2",
            "-o",
            s(&tile),
        ];
        let env: Vec<(&str, &str)> = match k {
            1 => vec![("SLURM_ARRAY_TASK_ID", index.as_str())],
            2 => vec![("JOB_COMPLETION_INDEX", index.as_str())],
            // The flag wins over the environment.
            3 => {
                args.extend(["--tile-index", index.as_str()]);
                vec![("SLURM_ARRAY_TASK_ID", "0")]
            }
            _ => {
                args.extend(["--tile-index", index.as_str()]);
                vec![]
            }
        };
        let out = spectex_env(&args, &env);
        assert!(
            out.status.success(),
            "tile {k}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        tiles.push(tile);
    }
    // Tiles of ⌈200/3⌉ × ⌈130/2⌉ = 67 × 65, the last column cut to 66; each records its place.
    for (k, want) in [
        (0, (0, 0, 67, 65)),
        (4, (67, 65, 67, 65)),
        (5, (134, 65, 66, 65)),
    ] {
        let t = read_exr(&tiles[k]);
        assert_eq!((t.display, t.data), ((200, 130), want), "tile {k}");
    }
    let joined = dir.join("joined.exr");
    // Any order.
    let mut args = vec!["assemble", "-o", s(&joined)];
    args.extend(tiles.iter().rev().map(|t| s(t)));
    spectex_ok(&args);
    let (got, want) = (read_exr(&joined), read_exr(&whole));
    assert_eq!((got.display, got.data), ((200, 130), (0, 0, 200, 130)));
    // The whole-image EXR holds grey as R = G = B; tiles and the assembled image hold Y.
    assert_same_bits(got.channel("Y"), want.channel("Y"), 200, "assembled 3×2");
}

/// A streamed render is the whole render: EXR values bit for bit (grey and colour), PNG 8 and
/// 16-bit pixels equal, over several bands of rows (`--band-rows`, the last one shorter).
#[test]
fn streamed_renders_equal_whole_ones() {
    let dir = scratch("stream-whole");
    let grey = model("classic-perlin-fbm.json");
    let size = "700x460";
    let whole = dir.join("whole.exr");
    let streamed = dir.join("streamed.exr");
    spectex_ok(&["render", s(&grey), "--size", size, "-o", s(&whole)]);
    let bands = ["--stream", "--band-rows", "128"];
    let mut args = vec!["render", s(&grey), "--size", size, "-o", s(&streamed)];
    args.extend(bands);
    let out = spectex_ok(&args);
    assert!(String::from_utf8_lossy(&out.stdout).contains("bands of 128 rows"));
    let want = read_exr(&whole);
    let got = read_exr(&streamed);
    // A grey model is one Y channel in every EXR, whole or streamed (it was R, G, B whole).
    assert_eq!(want.names(), ["Y"], "channels of the whole render");
    assert_eq!(got.names(), ["Y"], "channels of the streamed render");
    assert_eq!((got.display, got.data), ((700, 460), (0, 0, 700, 460)));
    assert_same_bits(got.channel("Y"), want.channel("Y"), 700, "streamed EXR");

    // A 1×2 grid of 230-row tiles, written in 64-row bands: the assembler's 128-row bands cut
    // the tiles' boundary.
    let mut tiles = Vec::new();
    for k in ["0", "1"] {
        let tile = dir.join(format!("half-{k}.exr"));
        spectex_ok(&[
            "render",
            s(&grey),
            "--size",
            size,
            "--tiles",
            "1x2",
            "--tile-index",
            k,
            "--band-rows",
            "64",
            "-o",
            s(&tile),
        ]);
        tiles.push(tile);
    }
    let joined = dir.join("joined.exr");
    spectex_ok(&[
        "assemble",
        s(&tiles[0]),
        s(&tiles[1]),
        "--band-rows",
        "128",
        "-o",
        s(&joined),
    ]);
    assert_same_bits(
        read_exr(&joined).channel("Y"),
        want.channel("Y"),
        700,
        "assembled 1×2",
    );

    for depth in ["8", "16"] {
        let a = dir.join(format!("whole-{depth}.png"));
        let b = dir.join(format!("streamed-{depth}.png"));
        spectex_ok(&[
            "render",
            s(&grey),
            "--size",
            size,
            "--bit-depth",
            depth,
            "-o",
            s(&a),
        ]);
        let mut args = vec![
            "render",
            s(&grey),
            "--size",
            size,
            "--bit-depth",
            depth,
            "-o",
            s(&b),
        ];
        args.extend(bands);
        spectex_ok(&args);
        let (a, b) = (
            spectex_testkit::image_files::open(&a).unwrap(),
            spectex_testkit::image_files::open(&b).unwrap(),
        );
        assert_eq!(a.color(), b.color(), "{depth}-bit");
        assert!(
            a.as_bytes() == b.as_bytes(),
            "{depth}-bit PNG pixels differ"
        );
    }

    let colour = model("texture-synthetic-colour.json");
    let whole = dir.join("colour.exr");
    let streamed = dir.join("colour-streamed.exr");
    spectex_ok(&["render", s(&colour), "--size", "150x90", "-o", s(&whole)]);
    spectex_ok(&[
        "render",
        s(&colour),
        "--size",
        "150x90",
        "--stream",
        "-o",
        s(&streamed),
    ]);
    let (got, want) = (read_exr(&streamed), read_exr(&whole));
    for c in ["R", "G", "B"] {
        assert_same_bits(got.channel(c), want.channel(c), 150, c);
    }
}

/// The failure contract: exit 1, one `error: …` line naming every needle, and no file in
/// `dir` but `keep`.
fn assert_refused(out: &Output, dir: &Path, keep: &[&Path], needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "exit status; stderr: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one line expected, got: {stderr}");
    assert!(lines[0].starts_with("error: "), "{stderr}");
    for n in needles {
        assert!(lines[0].contains(n), "'{n}' missing from: {stderr}");
    }
    let left: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| !keep.contains(&p.as_path()))
        .collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
}

#[test]
fn bad_grids_indices_and_tile_sets_are_refused() {
    let dir = scratch("stream-refused");
    let m = model("classic-perlin-fbm.json");
    let out = dir.join("t.exr");
    let render = |extra: &[&str], env: &[(&str, &str)], output: &Path| {
        let mut args = vec!["render", s(&m), "--size", "40x30", "-o", s(output)];
        args.extend(extra);
        spectex_env(&args, env)
    };
    /// Flags, environment, and what the error must name.
    type Case<'a> = (&'a [&'a str], &'a [(&'a str, &'a str)], &'a [&'a str]);
    let cases: [Case<'_>; 5] = [
        (
            &["--tiles", "2x2"],
            &[],
            &[
                "--tile-index",
                "SLURM_ARRAY_TASK_ID",
                "JOB_COMPLETION_INDEX",
            ],
        ),
        (
            &["--tiles", "2x2", "--tile-index", "4"],
            &[],
            &["tile index 4", "0 to 3"],
        ),
        (
            &["--tiles", "2x2"],
            &[("JOB_COMPLETION_INDEX", "9")],
            &["tile index 9"],
        ),
        (
            &["--tiles", "2x2"],
            &[("SLURM_ARRAY_TASK_ID", "first")],
            &["SLURM_ARRAY_TASK_ID = 'first'"],
        ),
        // ⌈40/9⌉ = 5: eight columns fill the image, the ninth would be empty.
        (
            &["--tiles", "9x1", "--tile-index", "0"],
            &[],
            &["last column", "fewer columns"],
        ),
    ];
    for (extra, env, needles) in cases {
        assert_refused(&render(extra, env, &out), &dir, &[], needles);
    }
    let png = dir.join("t.png");
    let o = render(&["--tiles", "2x2", "--tile-index", "0"], &[], &png);
    assert_refused(&o, &dir, &[], &["--tiles", ".exr"]);

    // Tiles 0, 1, 2 of a 2×2 grid, and tile 0 of another seed.
    let tiles = dir.join("tiles");
    std::fs::create_dir(&tiles).unwrap();
    let tile = |k: &str| tiles.join(format!("{k}.exr"));
    for k in ["0", "1", "2"] {
        let o = render(&["--tiles", "2x2", "--tile-index", k], &[], &tile(k));
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let other = dir.join("other.json");
    let text = std::fs::read_to_string(&m).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let seed = json.pointer_mut("/model/classic/seed");
    *seed.expect("the model has a seed") = serde_json::json!(12345);
    std::fs::write(&other, json.to_string()).unwrap();
    let foreign = tiles.join("foreign-3.exr");
    let o = spectex_env(
        &[
            "render",
            s(&other),
            "--size",
            "40x30",
            "--tiles",
            "2x2",
            "--tile-index",
            "3",
            "-o",
            s(&foreign),
        ],
        &[],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let outdir = dir.join("out");
    std::fs::create_dir(&outdir).unwrap();
    let joined = outdir.join("whole.exr");
    let assemble = |inputs: &[&Path]| {
        let mut args = vec!["assemble", "-o", s(&joined)];
        args.extend(inputs.iter().map(|p| s(p)));
        spectex_env(&args, &[])
    };
    let (t0, t1, t2) = (tile("0"), tile("1"), tile("2"));
    // Tile 3 (20×15 at (20, 15)) is missing.
    assert_refused(
        &assemble(&[&t0, &t1, &t2]),
        &outdir,
        &[],
        &["1200", "pixel (20, 15)"],
    );
    assert_refused(&assemble(&[&t0, &t1, &t2, &t1]), &outdir, &[], &["overlap"]);
    assert_refused(
        &assemble(&[&t0, &t1, &t2, &foreign]),
        &outdir,
        &[],
        &["different renders"],
    );
    assert_refused(&assemble(&[&t0, &m]), &outdir, &[], &["cannot read tile"]);
}

/// `--device gpu` streams band by band too: the same values as the GPU's whole render (tiles
/// are invisible on either evaluator). Skips loudly without an adapter unless
/// `SPECTEX_REQUIRE_GPU=1`.
#[test]
fn gpu_renders_stream_the_same_values() {
    if let Err(e) = spectex_gpu::GpuContext::new() {
        assert!(
            !std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1"),
            "SPECTEX_REQUIRE_GPU=1 but no GPU: {e}"
        );
        eprintln!("SKIPPED gpu_renders_stream_the_same_values: {e}");
        return;
    }
    let dir = scratch("stream-gpu");
    let m = model("classic-perlin-fbm.json");
    let whole = dir.join("whole.exr");
    let streamed = dir.join("streamed.exr");
    let args = ["render", s(&m), "--size", "150x140", "--offset", "1e6,-2e5"];
    let mut a = args.to_vec();
    a.extend(["--device", "gpu", "-o", s(&whole)]);
    spectex_ok(&a);
    let mut b = args.to_vec();
    b.extend([
        "--device",
        "gpu",
        "--stream",
        "--band-rows",
        "64",
        "-o",
        s(&streamed),
    ]);
    let out = spectex_ok(&b);
    assert!(String::from_utf8_lossy(&out.stdout).contains("on the GPU"));
    assert_same_bits(
        read_exr(&streamed).channel("Y"),
        read_exr(&whole).channel("Y"),
        150,
        "GPU streamed",
    );
}
