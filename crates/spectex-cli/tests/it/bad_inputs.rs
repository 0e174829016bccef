//! Bad input, command by command, as one table: each case is the arguments and the words its
//! one `error: …` line must contain, run through [`check`]: exit status 1, exactly one line,
//! and no file left in the case's own output directory (not even a temporary one). Adding a
//! case is one row.
//!
//! Arguments may name the fixtures: `{out}` an output PNG in the case's directory, `{dir}` the
//! directory itself, `{json}` an output model file there, and `{corrupt}`, `{text}`, `{one}`
//! (1×1 PNG), `{line}` (10×1 PNG), `{grey}` (16×16 PNG), `{valid}` (a Gabor model), `{unknown}` (a field it does not
//! have), `{version}` (schema version 99), `{negative}` (a negative bandwidth), `{colour}` (a
//! colour texture model), `{phasor}` (a 3D phasor model) and `{missing}` (no such file).

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::{s, scratch, spectex};

/// One bad invocation and what its error line must say.
struct Case {
    /// The arguments, with `{fixture}` placeholders.
    args: &'static [&'static str],
    /// Words the error line contains (the field, its valid range, the flag to change).
    says: &'static [&'static str],
}

const fn case(args: &'static [&'static str], says: &'static [&'static str]) -> Case {
    Case { args, says }
}

/// Every case.
const CASES: &[Case] = &[
    // Images in and out.
    case(
        &["rpn", "/nonexistent/x.png", "-o", "{out}"],
        &["cannot open input", "check the path"],
    ),
    case(
        &["rpn", "{corrupt}", "-o", "{out}"],
        &["cannot decode", "corrupt"],
    ),
    case(&["rpn", "{text}", "-o", "{out}"], &["not a PNG or JPEG"]),
    case(&["rpn", "{one}", "-o", "{out}"], &["1×1", "at least 2×2"]),
    case(&["rpn", "{line}", "-o", "{out}"], &["10×1"]),
    case(&["analyze", "{one}", "-o", "{dir}/an"], &["1×1"]),
    case(
        &["rpn", "-o", "{out}", "--size", "0x0"],
        &["output size is 0×0", "--size"],
    ),
    case(
        &["rpn", "-o", "{out}", "--size", "100x100"],
        &["at least 256×256"],
    ),
    case(
        &["rpn", "-o", "{out}", "--size", "100000x300"],
        &["16384", "smaller --size"],
    ),
    case(
        &["rpn", "-o", "{out}", "--size", "9000x9000"],
        &["67108864"],
    ),
    case(&["rpn", "-o", "{out}", "--size", "12"], &["WIDTHxHEIGHT"]),
    case(&["rpn", "-o", "{out}", "--seed", "4294967296"], &["--seed"]),
    case(&["rpn", "-o", "{out}", "--bogus"], &["--bogus"]),
    case(
        &["rpn", "-o", "/nonexistent-dir/out.png"],
        &["not accessible", "create it"],
    ),
    case(&["rpn", "-o", "{dir}/out.jpg"], &[".jpg", ".png", ".exr"]),
    case(&["rpn", "-o", "{dir}"], &["extension"]),
    // Fitting and texture by example.
    case(&["fit", "-o", "{json}", "--budget", "0"], &["budget"]),
    case(
        &["fit", "-o", "{json}", "--budget", "2", "--strata", "4"],
        &["strata"],
    ),
    case(
        &["fit", "-o", "{json}", "--structure", "NaN"],
        &["structure"],
    ),
    case(
        &["synth", "-o", "{out}", "--structure", "1.5"],
        &["structure", "[0, 1]", "--structure"],
    ),
    case(
        &["synth", "-o", "{out}", "--turbulence=-1"],
        &["turbulence", "pixels"],
    ),
    case(
        &["sheet", "-o", "{dir}/sheets", "--ratios", "0,2"],
        &["--ratios", "[0, 1]"],
    ),
    // Model files and windows.
    case(
        &["render", "/nonexistent/m.json", "-o", "{out}"],
        &["cannot open model"],
    ),
    case(&["render", "{unknown}", "-o", "{out}"], &["colour"]),
    case(&["render", "{version}", "-o", "{out}"], &["schema_version"]),
    case(&["render", "{negative}", "-o", "{out}"], &["bandwidth"]),
    case(
        &["render", "{valid}", "-o", "{out}", "--scale", "0"],
        &["scale"],
    ),
    case(
        &["render", "{valid}", "-o", "{out}", "--size", "0x0"],
        &["size"],
    ),
    case(
        &["render", "{valid}", "-o", "{out}", "--device", "tpu"],
        &["tpu"],
    ),
    case(
        &["render", "{valid}", "-o", "{out}", "--offset", "nan,3"],
        &["offset"],
    ),
    // Phasor noise and its slices.
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--frequency",
            "0.9",
        ],
        &["phasor.frequency"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--bandwidth",
            "0",
        ],
        &["phasor.bandwidth"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--impulses",
            "0",
        ],
        &["impulses_per_kernel"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--profile",
            "square",
            "--duty",
            "1.5",
        ],
        &["duty"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--profile",
            "square",
            "--duty-image",
            "{missing}",
        ],
        &["missing.png"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--harmonics",
            "0:1",
        ],
        &["harmonics"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--harmonics",
            "x",
        ],
        &["harmonic"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--two-lobes",
            "10",
        ],
        &["pair"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--three-d",
            "--z",
            "NaN",
        ],
        &["z"],
    ),
    case(
        &[
            "phasor",
            "-o",
            "{out}",
            "--size",
            "16x16",
            "--bandwidth-image",
            "{missing}",
            "--bandwidth-max",
            "0.2",
        ],
        &["missing.png"],
    ),
    case(
        &[
            "slices",
            "{phasor}",
            "-o",
            "{dir}/layers",
            "--layers",
            "0",
            "--z-range",
            "0,1",
        ],
        &["--layers"],
    ),
    case(
        &[
            "slices",
            "{phasor}",
            "-o",
            "{dir}/layers",
            "--layers",
            "2",
            "--z-range",
            "0",
        ],
        &["pair"],
    ),
    case(
        &[
            "slices",
            "{phasor}",
            "-o",
            "{dir}/layers",
            "--layers",
            "2",
            "--z-range",
            "0,inf",
        ],
        &["finite"],
    ),
    // Classic noises and textons.
    case(
        &["noise", "perlin", "--cell", "0.5", "-o", "{out}"],
        &["--cell", "[1, 1e6]"],
    ),
    case(
        &["noise", "simplex", "--dims", "4", "-o", "{out}"],
        &["--dims", "2 or 3"],
    ),
    case(
        &[
            "noise",
            "fbm",
            "--cell",
            "32",
            "--octaves",
            "7",
            "-o",
            "{out}",
        ],
        &["--octaves", "at least 1 pixel"],
    ),
    case(
        &["noise", "fbm", "--gain", "3", "-o", "{out}"],
        &["--gain", "[0, 2]"],
    ),
    case(
        &[
            "noise",
            "fbm",
            "--sum",
            "ridged",
            "--weight-gain",
            "20",
            "-o",
            "{out}",
        ],
        &["--weight-gain", "[0, 16]"],
    ),
    case(
        &["noise", "worley", "--poisson", "9", "-o", "{out}"],
        &["--poisson", "[0.5, 4]"],
    ),
    case(
        &["noise", "worley", "--points", "0", "-o", "{out}"],
        &["--points", "1 to 16"],
    ),
    case(
        &[
            "noise",
            "worley",
            "--coefficients",
            "1,nan,0,0",
            "-o",
            "{out}",
        ],
        &["--coefficients", "[-1000, 1000]"],
    ),
    case(
        &["noise", "texton", "--radii", "200,3", "-o", "{out}"],
        &["texton.radii", "--radii", "3·cell_size"],
    ),
    case(
        &["noise", "texton", "--density", "9", "-o", "{out}"],
        &["--density", "(0, 8]"],
    ),
    case(
        &["noise", "texton", "--texton-scale", "0,1", "-o", "{out}"],
        &["--texton-scale", "[0.001, 16]"],
    ),
    case(
        &["noise", "texton", "--radii", "1", "-o", "{out}"],
        &["--radii", "A,B"],
    ),
    // Voronoi, combinations, matrix transformation, subdivision, Islamic patterns.
    case(
        &["noise", "voronoi", "--jitter", "2", "-o", "{out}"],
        &["voronoi.jitter", "--jitter", "[0, 1]"],
    ),
    case(
        &["noise", "voronoi", "--lloyd", "17", "-o", "{out}"],
        &["voronoi.lloyd_iterations", "--lloyd"],
    ),
    case(
        &[
            "noise", "voronoi", "--dims", "3", "--lloyd", "2", "-o", "{out}",
        ],
        &["voronoi.lloyd_iterations", "2D only", "--lloyd"],
    ),
    case(
        &["noise", "combine", "--operand", "{valid}", "-o", "{out}"],
        &["combine.operands", "--operand"],
    ),
    case(
        &[
            "noise",
            "combine",
            "smoothstep",
            "--edges",
            "1,0",
            "-o",
            "{out}",
        ],
        &["combine.op.smoothstep.edges[1]"],
    ),
    case(
        &["noise", "matrix", "--matrix", "6,0,0,1", "-o", "{out}"],
        &["matrix.matrix[0][0]", "--matrix", "Lucas"],
    ),
    case(
        &["noise", "matrix", "--matrix", "2,0,0,1", "-o", "{out}"],
        &["matrix.matrix", "prime to size", "--matrix"],
    ),
    case(
        &["noise", "matrix", "--torus", "1", "-o", "{out}"],
        &["matrix.size", "--torus"],
    ),
    case(
        &["noise", "subdivision", "--levels", "17", "-o", "{out}"],
        &["subdivision.levels", "0 to 16", "--levels"],
    ),
    case(
        &["noise", "subdivision", "--hurst", "1.5", "-o", "{out}"],
        &["subdivision.hurst", "[0, 1]", "--hurst"],
    ),
    case(
        &["noise", "subdivision", "--cell", "0.5", "-o", "{out}"],
        &["subdivision.cell_size", "--cell"],
    ),
    case(
        &["noise", "islamic", "--angle", "95", "-o", "{out}"],
        &["islamic.motif.contact.angle", "--angle", "[1, 89]"],
    ),
    case(
        &["noise", "islamic", "--star", "9", "-o", "{out}"],
        &["islamic.motif.star.step", "--star", "[1, 5]"],
    ),
    case(
        &["noise", "islamic", "--cell", "2", "-o", "{out}"],
        &["islamic.cell_size", "--cell", "[4, 4096]"],
    ),
    // Warps.
    case(
        &["noise", "warp", "--strength", "1e6", "-o", "{out}"],
        &["warp.strength", "--strength"],
    ),
    case(
        &["noise", "warp", "--strength", "nan", "-o", "{out}"],
        &["warp.strength"],
    ),
    case(
        &["noise", "warp", "--by", "{colour}", "-o", "{out}"],
        &["warp.x", "--by"],
    ),
    case(
        &["noise", "warp", "--by-y", "{colour}", "-o", "{out}"],
        &["warp.y", "--by-y"],
    ),
    case(
        &["noise", "warp", "--base", "{missing}", "-o", "{out}"],
        &["cannot open model"],
    ),
    case(
        &["noise", "warp", "--offset", "1073741000,0", "-o", "{out}"],
        &["window position"],
    ),
    // Wavelet noise.
    case(
        &["noise", "wavelet", "-o", "{out}", "--tile", "33"],
        &["--tile", "even number from 16 to 256"],
    ),
    case(
        &[
            "noise", "wavelet", "-o", "{out}", "--tile", "128", "--dims", "3",
        ],
        &["--tile", "16 to 64 (3D)"],
    ),
    case(
        &["noise", "wavelet", "-o", "{out}", "--cell", "0.5"],
        &["--cell", "[1, 1e6]"],
    ),
    case(
        &[
            "noise", "wavelet", "-o", "{out}", "--cell", "4", "--bands", "1,1,1,1",
        ],
        &["--bands", "at least 1 pixel"],
    ),
    case(
        &["noise", "wavelet", "-o", "{out}", "--bands", "0,0"],
        &["--bands", "not 0"],
    ),
    case(
        &["noise", "wavelet", "-o", "{out}", "--bands", "1,x"],
        &["--bands", "W1,W2"],
    ),
    case(
        &["noise", "wavelet", "-o", "{out}", "--dims", "4"],
        &["--dims", "2 or 3"],
    ),
    case(
        &["noise", "wavelet", "-o", "{out}", "--amplitude", "inf"],
        &["--amplitude"],
    ),
    // Height maps.
    case(
        &["relight", "{grey}", "-o", "{out}", "--light", "0,95"],
        &["elevation", "[0, 90]"],
    ),
    case(&["relight", "{missing}", "-o", "{out}"], &["missing.png"]),
    // Periods.
    case(
        &[
            "noise",
            "fbm",
            "--cell",
            "32",
            "--periodic",
            "100x64",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "100x64", "divide"],
    ),
    case(
        &[
            "noise",
            "simplex",
            "--periodic",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "simplex"],
    ),
    case(
        &[
            "noise",
            "ring",
            "--periodic",
            "0x4",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "period.width", "1 to"],
    ),
    case(
        &[
            "noise",
            "ring",
            "--periodic",
            "axb",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "WxH"],
    ),
    case(
        &[
            "noise",
            "ring",
            "--periodic",
            "--scale",
            "0.3",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "not whole"],
    ),
    // The default kernel radius, 48.8 px, would move by 31% to divide 64.
    case(
        &[
            "phasor",
            "--periodic",
            "64x64",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "phasor", "kernel radius", "divisor"],
    ),
    case(
        &[
            "noise",
            "voronoi",
            "--cell",
            "16",
            "--lloyd",
            "1",
            "--periodic",
            "48x48",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "voronoi.lloyd_block", "64"],
    ),
    case(
        &[
            "noise",
            "islamic",
            "--tiling",
            "hexagonal",
            "--periodic",
            "64x64",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "islamic.tiling"],
    ),
    case(
        &[
            "noise",
            "matrix",
            "--torus",
            "32",
            "--periodic",
            "48x64",
            "-o",
            "{out}",
            "--size",
            "64x64",
        ],
        &["--periodic", "matrix.size = 32", "64, 96"],
    ),
];

/// The input fixtures, by placeholder name.
fn fixtures() -> BTreeMap<&'static str, PathBuf> {
    let dir = scratch("bad-inputs-fixtures");
    let mut files = BTreeMap::new();
    let mut put = |name: &'static str, file: &str, bytes: &[u8]| {
        let path = dir.join(file);
        std::fs::write(&path, bytes).unwrap();
        files.insert(name, path);
    };
    put(
        "corrupt",
        "c.png",
        b"\x89PNG\r\n\x1a\n this is not really a png",
    );
    put("text", "t.png", b"hello");
    let valid = r#"{"schema_version": 1, "model": {"gabor": {"seed": 1, "mean": 0.5,
        "amplitude": 0.2, "bandwidth": 0.05, "frequency": 0.06,
        "orientation": {"anisotropic": {"angle": 0.5}}, "impulses_per_kernel": 8.0}}}"#;
    put("valid", "ok.json", valid.as_bytes());
    put(
        "unknown",
        "unknown.json",
        valid
            .replace("\"seed\"", "\"colour\": 1, \"seed\"")
            .as_bytes(),
    );
    put(
        "version",
        "version.json",
        valid
            .replace("\"schema_version\": 1", "\"schema_version\": 99")
            .as_bytes(),
    );
    put(
        "negative",
        "negative.json",
        valid
            .replace("\"bandwidth\": 0.05", "\"bandwidth\": -1.0")
            .as_bytes(),
    );
    for (name, file, (w, h)) in [("one", "one.png", (1, 1)), ("line", "line.png", (10, 1))] {
        let path = dir.join(file);
        spectex_testkit::image_files::save(
            &image::DynamicImage::from(image::RgbImage::from_fn(w, h, |x, y| {
                image::Rgb([(x * 7) as u8, (y * 3) as u8, ((x + y) * 5) as u8])
            })),
            &path,
        )
        .unwrap();
        files.insert(name, path);
    }
    let grey = dir.join("grey.png");
    spectex_testkit::image_files::save(
        &image::DynamicImage::from(image::GrayImage::from_fn(16, 16, |x, y| {
            image::Luma([(x * 9 + y * 5) as u8])
        })),
        &grey,
    )
    .unwrap();
    files.insert("grey", grey);
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models");
    files.insert("colour", models.join("texture-synthetic-colour.json"));
    files.insert("phasor", models.join("phasor-3d-harmonics.json"));
    files.insert("missing", dir.join("missing.png"));
    files
}

/// Runs `case` in its own empty directory `dir` and checks the failure contract.
fn check(
    case: &Case,
    dir: &Path,
    fixtures: &BTreeMap<&'static str, PathBuf>,
) -> Result<(), String> {
    let args: Vec<String> = case
        .args
        .iter()
        .map(|a| {
            let mut a = a
                .replace("{out}", s(&dir.join("out.png")))
                .replace("{json}", s(&dir.join("m.json")))
                .replace("{dir}", s(dir));
            for (name, path) in fixtures {
                a = a.replace(&format!("{{{name}}}"), s(path));
            }
            a
        })
        .collect();
    let words: Vec<&str> = args.iter().map(String::as_str).collect();
    failure_contract(&spectex(&words), dir, case.says)
        .map_err(|wrong| format!("spectex {}: {wrong}", case.args.join(" ")))
}

/// The failure contract of every command: exit status 1, exactly one line on stderr, starting
/// `error: ` and containing each of `says`, and no file left in `dir`.
///
/// # Errors
/// What is wrong, with the stderr.
pub fn failure_contract(out: &Output, dir: &Path, says: &[&str]) -> Result<(), String> {
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    let mut wrong = Vec::new();
    if out.status.code() != Some(1) {
        wrong.push(format!("exit status {:?}", out.status.code()));
    }
    if lines.len() != 1 || !lines[0].starts_with("error: ") {
        wrong.push("not one `error: …` line".to_owned());
    }
    for word in says {
        if !stderr.contains(word) {
            wrong.push(format!("no '{word}'"));
        }
    }
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    if !left.is_empty() {
        wrong.push(format!("files left behind: {left:?}"));
    }
    if wrong.is_empty() {
        Ok(())
    } else {
        Err(format!("{}; stderr: {}", wrong.join(", "), stderr.trim()))
    }
}

#[test]
fn bad_inputs_fail_cleanly() {
    let fixtures = fixtures();
    let failures: Vec<String> = CASES
        .iter()
        .enumerate()
        .filter_map(|(i, case)| check(case, &scratch(&format!("bad-input-{i}")), &fixtures).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} cases:\n{}",
        failures.len(),
        CASES.len(),
        failures.join("\n")
    );
}
