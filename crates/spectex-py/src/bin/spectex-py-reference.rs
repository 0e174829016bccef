//! The Rust side of the Python suite's bit-for-bit checks: renders every model file given with
//! `spectex_cpu::Evaluator::render` (the library's own parallel render, not the Python module's
//! banded one) and evaluates a fixed set of points with `Evaluator::eval_point` one by one,
//! writing the raw little-endian f32 values the Python renders and samples must equal.
//!
//! `spectex-py-reference OUT_DIR MODEL.json…` writes `OUT_DIR/<stem>.<case>.f32` for each case
//! of [`CASES`] and `OUT_DIR/<stem>.points.f32` for [`points`].
//!
//! `spectex-py-reference --builders OUT_DIR` writes `OUT_DIR/<case>.json`, the models of
//! [`builder_cases`] made by the Rust builders themselves (`spectex_sampling::LrpFromTarget`,
//! `MatrixTransform::builder`), which the Python builders' models must equal.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use spectex_cpu::{Evaluator, Filter, Window};
use spectex_model::{MatrixTransform, Model, SpectralTarget};
use spectex_sampling::LrpFromTarget;

/// One window rendered: `(name, width, height, offset, scale, z, filter)`.
type Case = (&'static str, usize, usize, [f64; 2], f64, f64, bool);

/// The windows rendered; the suite (`tests/test_render.py`) renders the same.
const CASES: &[Case] = &[
    ("origin", 48, 40, [0.0, 0.0], 1.0, 0.0, true),
    ("far", 40, 33, [1.0e7, -3.5e6], 2.5, 7.25, true),
    ("zoomout", 32, 24, [-1234.5, 987.25], 16.0, 0.0, false),
];

/// The points sampled (x, y, z): 64 positions spread near and far from the origin, on two
/// planes. The suite builds the same list.
fn points() -> Vec<[f64; 3]> {
    (0..64)
        .map(|i| {
            let t = f64::from(i);
            [
                -300.0 + 17.25 * t,
                1.0e5 * f64::from(i % 3) + 3.5 * t,
                if i % 2 == 0 { 0.0 } else { 12.5 },
            ]
        })
        .collect()
}

fn write(path: &Path, values: &[f32]) -> Result<(), String> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn reference(out: &Path, file: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let contents =
        spectex_model::from_json_file(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    let stem = file
        .file_stem()
        .and_then(|s| s.to_str())
        .ok_or_else(|| format!("{}: no file name", file.display()))?;
    let (model, period) = (&contents.model, contents.period);
    for &(case, width, height, offset, scale, z, filter) in CASES {
        let eval = Evaluator::with_period(model, z, period).map_err(|e| format!("{stem}: {e}"))?;
        let window = Window::new(width, height)
            .at(offset, scale)
            .filtered(if filter { Filter::Pixel } else { Filter::Off });
        let pixels = eval
            .render(&window)
            .map_err(|e| format!("{stem} {case}: {e}"))?;
        write(&out.join(format!("{stem}.{case}.f32")), &pixels)?;
    }
    let mut values = Vec::new();
    for p in points() {
        let eval =
            Evaluator::with_period(model, p[2], period).map_err(|e| format!("{stem}: {e}"))?;
        let mut v = vec![0.0f32; eval.output_channels()];
        eval.eval_point([p[0], p[1]], &mut v);
        values.extend(v);
    }
    write(&out.join(format!("{stem}.points.f32")), &values)
}

/// The builder cases (file stem, model): every target and the matrix builder at their
/// defaults, and with every option given (values exact in f32). The suite
/// (`tests/test_builders.py`) makes the same through Python.
fn builder_cases() -> Result<Vec<(&'static str, Model)>, String> {
    type T = SpectralTarget;
    let lrp = |target: T| LrpFromTarget::new(target);
    let targets = [
        (
            "ring",
            lrp(T::Ring {
                radius: T::DEFAULT_RING_RADIUS,
                width: T::DEFAULT_RING_WIDTH,
            }),
        ),
        (
            "ring-options",
            lrp(T::Ring {
                radius: 0.125,
                width: 0.0078125,
            })
            .budget(6)
            .strata(2)
            .seed(3)
            .std_dev(0.25)
            .mean(0.0),
        ),
        (
            "lobe",
            lrp(T::Lobes {
                frequency: T::DEFAULT_LOBE_FREQUENCY,
                angle: T::DEFAULT_LOBE_ANGLE_DEGREES.to_radians(),
                width: T::DEFAULT_LOBE_WIDTH,
            }),
        ),
        (
            "lobe-options",
            lrp(T::Lobes {
                frequency: 0.125,
                angle: -1.0,
                width: 0.015625,
            })
            .budget(4)
            .seed(7),
        ),
        (
            "band",
            lrp(T::Band {
                min: T::DEFAULT_BAND_MIN,
                max: T::DEFAULT_BAND_MAX,
            }),
        ),
        (
            "fractal",
            lrp(T::Fractal {
                beta: T::DEFAULT_FRACTAL_BETA,
                angle: T::DEFAULT_FRACTAL_ANGLE_DEGREES.to_radians(),
                spread: None,
                min_frequency: T::DEFAULT_FRACTAL_MIN_FREQUENCY,
            }),
        ),
        (
            "fractal-options",
            lrp(T::Fractal {
                beta: 1.0,
                angle: 0.5,
                spread: Some(0.25),
                min_frequency: 0.015625,
            })
            .budget(24)
            .strata(6)
            .mean(0.25),
        ),
    ];
    let mut cases = Vec::new();
    for (stem, builder) in targets {
        let noise = builder.build().map_err(|e| format!("{stem}: {e}"))?;
        cases.push((stem, Model::from(noise)));
    }
    let matrices = [
        ("matrix", MatrixTransform::builder()),
        (
            "matrix-options",
            MatrixTransform::builder()
                .matrix([[3, 0], [0, 7]])
                .iterations(2)
                .size(128)
                .rings(9)
                .amplitude(0.5)
                .mean(0.25),
        ),
    ];
    for (stem, builder) in matrices {
        let matrix = builder.build().map_err(|e| format!("{stem}: {e}"))?;
        cases.push((stem, Model::from(matrix)));
    }
    Ok(cases)
}

/// Writes the models of [`builder_cases`] into `out`.
fn builders(out: &Path) -> Result<(), String> {
    for (stem, model) in builder_cases()? {
        let text = spectex_model::to_json(&model).map_err(|e| format!("{stem}: {e}"))?;
        let path = out.join(format!("{stem}.json"));
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let mut args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let making_builders = args.first().is_some_and(|a| a.as_os_str() == "--builders");
    if making_builders {
        args.remove(0);
    }
    let Some((out, files)) = args.split_first() else {
        eprintln!(
            "usage: spectex-py-reference OUT_DIR MODEL.json… | spectex-py-reference --builders OUT_DIR"
        );
        return ExitCode::FAILURE;
    };
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!("cannot create {}: {e}", out.display());
        return ExitCode::FAILURE;
    }
    if making_builders {
        if let Err(e) = builders(out) {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
        return ExitCode::SUCCESS;
    }
    for file in files {
        if let Err(e) = reference(out, file) {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
