//! The WGSL export (`spectex_gpu::export`): every model of `testdata/models/` whose kinds the
//! exporter covers gives a module that naga parses and validates, with exactly the public
//! entry points the header promises and no resource binding; the models with a feature it
//! cannot export exactly fail with a typed error naming the feature (an unexpected success
//! fails too, so the list stays true). Models whose tables exceed `MAX_TABLE_BYTES` are refused as constants and export
//! with a storage buffer: then the module declares exactly that one binding and the buffer
//! holds the tables. The rendering check (a wgpu render pipeline against the CPU) is in
//! spectex-crosscheck.

use std::path::PathBuf;

use spectex_gpu::GpuError;
use spectex_gpu::export::{
    DEFAULT_BINDING, DEFAULT_GROUP, ExportOptions, MAX_TABLE_BYTES, PORTABLE_TABLE_BYTES,
    TableStorage, export, wgsl_module,
};

/// Models `wgsl_module` refuses with `GpuError::Unsupported`, each for one feature the
/// exporter cannot export exactly (its module doc says why), with a word of the error's
/// feature: every other model exports, and each of these is refused.
const REFUSED: &[(&str, &str)] = &[
    ("combine-cracks", "Lloyd"),
    ("voronoi-border-lloyd", "Lloyd"),
    ("voronoi-palette-lloyd", "Lloyd"),
];

/// Models over `MAX_TABLE_BYTES` = 65 536 bytes of tables, counted from their files: the
/// fitted LRP models (tens of thousands of 8-byte frequencies) and wavelet-2d (a 128² tile of
/// f32: 65 536 bytes before its bands). A 3D wavelet exports one 32² plane per band (4 KiB
/// each), not its 32³ tile (131 072 bytes): wavelet-3d-multiband and the base of
/// warp-wavelet-by-fbm fit.
const TOO_LARGE: &[&str] = &["lrp-gravel", "lrp-sand", "wavelet-2d"];

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
    spectex_gpu::unit_tests::validated_module(&format!("{case}: export"), source)
}

/// The checks of a module with no binding, or (`buffer`) exactly the tables' storage buffer.
fn check_module(case: &str, model: &spectex_model::Model, source: &str, buffer: bool) {
    let module = validate(case, source);
    let bindings: Vec<_> = module
        .global_variables
        .iter()
        .filter_map(|(_, v)| v.binding.map(|b| (b, v.name.clone(), v.space)))
        .collect();
    if buffer {
        assert_eq!(bindings.len(), 1, "{case}: {bindings:?}");
        let (b, name, space) = &bindings[0];
        assert_eq!(
            (b.group, b.binding, name.as_deref()),
            (DEFAULT_GROUP, DEFAULT_BINDING, Some("spectex_tables")),
            "{case}"
        );
        assert!(
            matches!(space, naga::AddressSpace::Storage { access } if !access.contains(naga::StorageAccess::STORE)),
            "{case}: {space:?}"
        );
    } else {
        assert!(
            bindings.is_empty(),
            "{case}: the export declares a resource binding"
        );
    }
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
}

#[test]
fn every_exportable_model_validates_with_its_entry_points_and_no_binding() {
    let (mut exported, mut too_large, mut refused) = (0, Vec::new(), Vec::new());
    for file in model_files() {
        let case = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{case}: {e}"));
        let model = spectex_model::from_json(&text).unwrap_or_else(|e| panic!("{case}: {e}"));
        let result = wgsl_module(&model, &ExportOptions::default());
        if let Err(GpuError::Unsupported { feature, .. }) = &result {
            assert!(
                REFUSED
                    .iter()
                    .any(|(m, word)| *m == case && feature.contains(word)),
                "{case}: {result:?}"
            );
            refused.push(case);
            continue;
        }
        let buffer = ExportOptions {
            tables: TableStorage::Buffer {
                group: DEFAULT_GROUP,
                binding: DEFAULT_BINDING,
            },
            ..ExportOptions::default()
        };
        if let Err(GpuError::LimitsExceeded { value, limit, .. }) = &result {
            assert!(
                value > limit && *limit == MAX_TABLE_BYTES,
                "{case}: {result:?}"
            );
            println!("{case}: {value} bytes of tables, over the export's {limit}: a buffer");
            let exported = export(&model, &buffer).unwrap_or_else(|e| panic!("{case}: {e}"));
            // The buffer holds the tables (the lattice split's few words, and the small
            // tables a glue reads at literal indexes, such as LRP's strata, stay constants).
            // Kept constant: at most a few KiB (wavelet-2d's tile alone is the 64 KiB limit).
            let buffered = exported.tables.len() as u64;
            assert!(
                buffered <= *value && *value - buffered <= 4096,
                "{case}: {buffered} bytes in the buffer for {value} bytes of tables"
            );
            check_module(&case, &model, &exported.wgsl, true);
            too_large.push(case);
            continue;
        }
        let source = result.unwrap_or_else(|e| panic!("{case}: {e}"));
        check_module(&case, &model, &source, false);
        // The same model through a buffer validates too.
        let buffered = export(&model, &buffer).unwrap_or_else(|e| panic!("{case}: {e}"));
        check_module(&case, &model, &buffered.wgsl, true);
        exported += 1;
    }
    assert!(
        exported >= 33,
        "only {exported} models exported as constants (LRP 2, Gabor 2, classic 8, texton 3, \
         texture 3, warps of classic, Gabor, phasor and texture models 4, phasor 2, matrix 2, \
         Islamic 3, Voronoi 2, combinations 2 expected)"
    );
    assert_eq!(too_large, TOO_LARGE, "models over MAX_TABLE_BYTES");
    assert_eq!(
        refused,
        REFUSED.iter().map(|(m, _)| *m).collect::<Vec<_>>(),
        "refused models"
    );
}

/// A table only the compute path reads (a tile's records: a glue draws its own) is declared
/// with one zero element instead of its bytes. A 3D Voronoi tile's 9 × 9 × 9 cells of sites
/// (5103 f32, 20 KiB, over the WGSL portable limit) and a phasor tile's impulses are not
/// carried, and the modules' tables fit the 8192 bytes of private memory WGSL guarantees.
#[test]
fn tables_only_the_compute_path_reads_are_not_carried() {
    for (case, table) in [
        ("voronoi-3d-border", "sites"),
        ("phasor-two-lobes-phase", "impulses"),
        ("phasor-3d-harmonics", "cells"),
    ] {
        let text = std::fs::read_to_string(format!(
            "{}/../../testdata/models/{case}.json",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap_or_else(|e| panic!("{case}: {e}"));
        let model = spectex_model::from_json(&text).unwrap_or_else(|e| panic!("{case}: {e}"));
        let source = wgsl_module(&model, &ExportOptions::default())
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        let declaration = format!("var<private> spectex_m0_{table}: array<");
        let line = source
            .lines()
            .find(|l| l.starts_with(&declaration))
            .unwrap_or_else(|| panic!("{case}: no `{declaration}`"));
        assert!(
            line.ends_with(", 1>;"),
            "{case}: {}",
            &line[..line.len().min(120)]
        );
        let bytes: usize = source
            .split_once("// Size: ")
            .and_then(|(_, rest)| rest.split_once(' '))
            .and_then(|(n, _)| n.parse().ok())
            .unwrap_or_else(|| panic!("{case}: no size in the header"));
        assert!(
            bytes <= PORTABLE_TABLE_BYTES,
            "{case}: {bytes} bytes of tables"
        );
    }
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
    let err = wgsl_module(
        &model,
        &ExportOptions {
            z: f64::NAN,
            ..ExportOptions::default()
        },
    );
    assert!(
        matches!(err, Err(GpuError::Window { parameter: "z", .. })),
        "{err:?}"
    );
}
