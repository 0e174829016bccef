//! The WGSL export (`spectex_gpu::export`): every model of `testdata/models/` whose kind the
//! exporter covers gives a module that naga parses and validates, with exactly the public
//! entry points the header promises and no resource binding; the kinds it does not cover yet
//! fail with a typed error (an unexpected success fails too, so the list stays true), and so
//! do the two fitted LRP models whose tables exceed `MAX_TABLE_BYTES`. The
//! rendering check (a wgpu render pipeline against the CPU) is in spectex-crosscheck.

use std::path::PathBuf;

use spectex_gpu::GpuError;
use spectex_gpu::export::{ExportOptions, MAX_TABLE_BYTES, wgsl_module};

/// Kinds `wgsl_module` refuses with `GpuError::Unsupported` today.
const NOT_EXPORTED: &[&str] = &[
    "phasor", "texture", "warp", "wavelet", "texton", "voronoi", "combine",
];

fn model_files() -> Vec<PathBuf> {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/models"
    ));
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

/// Parses and validates `source` as naga does for wgpu, panicking with the annotated source.
fn validate(case: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| {
        panic!(
            "{case}: export does not parse:\n{}",
            e.emit_to_string(source)
        )
    });
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| {
        panic!(
            "{case}: export does not validate:\n{}",
            e.emit_to_string(source)
        )
    });
    module
}

#[test]
fn every_exportable_model_validates_with_its_entry_points_and_no_binding() {
    let (mut exported, mut too_large) = (0, 0);
    for file in model_files() {
        let case = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{case}: {e}"));
        let model = spectex_model::from_json(&text).unwrap_or_else(|e| panic!("{case}: {e}"));
        let result = wgsl_module(&model, &ExportOptions::default());
        if NOT_EXPORTED.contains(&model.kind()) {
            assert!(
                matches!(result, Err(GpuError::Unsupported { .. })),
                "{case}: a {} model exported; remove the kind from NOT_EXPORTED",
                model.kind()
            );
            continue;
        }
        if let Err(GpuError::LimitsExceeded { value, limit, .. }) = &result {
            assert!(
                value > limit && *limit == MAX_TABLE_BYTES,
                "{case}: {result:?}"
            );
            println!("{case}: {value} bytes of tables, over the export's {limit}: refused");
            too_large += 1;
            continue;
        }
        let source = result.unwrap_or_else(|e| panic!("{case}: {e}"));
        let module = validate(&case, &source);
        assert!(
            module
                .global_variables
                .iter()
                .all(|(_, v)| v.binding.is_none()),
            "{case}: the export declares a resource binding"
        );
        assert!(
            module.entry_points.is_empty(),
            "{case}: the export has an entry point"
        );
        let ret = if model.output_channels() == 3 {
            "vec3<f32>"
        } else {
            "f32"
        };
        for signature in [
            format!("fn spectex_sample(p: vec2<f32>) -> {ret}"),
            format!("fn spectex_sample_cell(cell: vec2<i32>, offset: vec2<f32>) -> {ret}"),
        ] {
            assert!(source.contains(&signature), "{case}: no `{signature}`");
        }
        // Every other function is prefixed, so the module pastes into any shader.
        for (_, f) in module.functions.iter() {
            let name = f.name.as_deref().unwrap_or("");
            assert!(
                name.starts_with("spectex_"),
                "{case}: unprefixed function {name}"
            );
        }
        exported += 1;
    }
    assert!(
        exported >= 10,
        "only {exported} models exported (LRP 2, Gabor 2, classic 6 expected)"
    );
    // The fitted LRP models lrp-gravel and lrp-sand (tens of thousands of frequencies).
    assert_eq!(too_large, 2, "models refused for their size");
}

#[test]
fn bad_plane_is_a_typed_error() {
    let model = spectex_model::from_json(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../testdata/models/lrp-ring.json"
        ))
        .unwrap_or_default(),
    );
    let Ok(model) = model else {
        panic!("lrp-ring.json does not load");
    };
    let err = wgsl_module(&model, &ExportOptions { z: f64::NAN });
    assert!(
        matches!(err, Err(GpuError::Window { parameter: "z", .. })),
        "{err:?}"
    );
}
