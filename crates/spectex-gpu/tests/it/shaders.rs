//! Shader tidy checks that need no GPU: every registered module, as composed, parses and
//! validates with naga; the registry and the files in `shaders/` match exactly; and the float
//! constants of `common.wgsl` (and the Gabor, texture and classic shaders) have the bits of the CPU's
//! constants.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use crate::common;

use common::{ATAN_TURNS, COS_TURNS, KB_POLY};
use spectex_gpu::export::EXPORT_SHADERS;
use spectex_gpu::shaders::GLUE_MARKER;
use spectex_gpu::{SHADERS, wgsl_source};

fn shaders_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("shaders")
}

/// Parses and validates one composed module, panicking with naga's annotated source excerpt.
fn validate(name: &str) -> naga::Module {
    let source = wgsl_source(name).unwrap();
    spectex_gpu::unit_tests::validated_module(&format!("{name}.wgsl (composed)"), &source)
}

#[test]
fn every_module_parses_and_validates_as_composed() {
    for file in SHADERS.iter() {
        let module = validate(file.name);
        let entries: Vec<&str> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        assert_eq!(
            entries, file.entry_points,
            "{}.wgsl: entry points in the file vs the registry",
            file.name
        );
    }
}

/// Each file of `shaders/` is what the registries hold of it: its compute shader in
/// [`SHADERS`], then (a kind's file) its export glue in `EXPORT_SHADERS`, from the glue line on.
#[test]
fn registry_matches_the_files_in_shaders() {
    let mut on_disk = BTreeMap::new();
    for entry in std::fs::read_dir(shaders_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            on_disk.insert(name, std::fs::read_to_string(&path).unwrap());
        }
    }
    let compute: BTreeMap<&str, &str> = SHADERS.iter().map(|f| (f.name, f.source)).collect();
    let glue: BTreeMap<&str, &str> = EXPORT_SHADERS
        .iter()
        .filter(|(name, _)| *name != "split")
        .copied()
        .collect();
    let registered: BTreeSet<&str> = compute.keys().chain(glue.keys()).copied().collect();
    let missing: Vec<_> = on_disk
        .keys()
        .filter(|k| !registered.contains(k.as_str()))
        .collect();
    let extra: Vec<_> = registered
        .iter()
        .filter(|k| !on_disk.contains_key(**k))
        .collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "shaders/ and spectex_gpu::SHADERS / EXPORT_SHADERS differ: files not registered \
         {missing:?}, registered names without a file {extra:?}"
    );
    for (name, text) in &on_disk {
        let glue = glue.get(name.as_str()).copied().unwrap_or_default();
        assert!(
            glue.is_empty() || glue.starts_with(GLUE_MARKER),
            "{name}.wgsl: the glue starts at its `{GLUE_MARKER}` line"
        );
        let registered = format!(
            "{}{glue}",
            compute.get(name.as_str()).copied().unwrap_or_default()
        );
        assert_eq!(
            &registered, text,
            "{name}.wgsl: the registries' text differs from the file"
        );
    }
}

/// The `f32` value(s) of a constant of `module`: a literal or an array of literals.
fn constant_values(module: &naga::Module, name: &str) -> Vec<f32> {
    let constant = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("common.wgsl has no constant {name}"))
        .1;
    let literal = |h: naga::Handle<naga::Expression>| match module.global_expressions[h] {
        naga::Expression::Literal(naga::Literal::F32(v)) => v,
        ref other => panic!("{name}: not an f32 literal: {other:?}"),
    };
    match &module.global_expressions[constant.init] {
        naga::Expression::Compose { components, .. } => {
            components.iter().map(|&h| literal(h)).collect()
        }
        _ => vec![literal(constant.init)],
    }
}

/// The constants of `spectex_model::math` (the polynomials' coefficients) and the others as that
/// file writes them; Rust rounds each expression to f32 exactly once.
#[test]
#[allow(
    clippy::excessive_precision,
    reason = "written as spectex-model's math.rs writes them"
)]
fn float_constants_have_the_cpu_bits() {
    let module = validate("common");
    let mut expected: Vec<(String, Vec<f32>)> = vec![
        ("KB_INV_SUPPORT2".into(), vec![1.0 / 2.25]),
        ("KB_SUPPORT2".into(), vec![2.25]),
        ("EXP_LN2_HI".into(), vec![0.693_145_75]),
        ("EXP_LN2_LO".into(), vec![1.428_606_8e-6]),
        ("EXP_LOG2_E".into(), vec![std::f32::consts::LOG2_E]),
        ("EXP_TAYLOR_2".into(), vec![0.5]),
        ("EXP_TAYLOR_3".into(), vec![1.0 / 6.0]),
        ("EXP_TAYLOR_4".into(), vec![1.0 / 24.0]),
        ("EXP_TAYLOR_5".into(), vec![1.0 / 120.0]),
        ("EXP_TAYLOR_6".into(), vec![1.0 / 720.0]),
        ("EXP_TAYLOR_7".into(), vec![1.0 / 5040.0]),
    ];
    for (k, &c) in COS_TURNS.iter().enumerate() {
        expected.push((format!("COS_TURNS_{k}"), vec![c]));
    }
    for (k, &c) in KB_POLY.iter().enumerate() {
        expected.push((format!("KB_POLY_{k}"), vec![c]));
    }
    for (k, &c) in ATAN_TURNS.iter().enumerate() {
        expected.push((format!("ATAN_TURNS_{k}"), vec![c]));
    }
    for (name, want) in &expected {
        let got = constant_values(&module, name);
        let (got, want): (Vec<u32>, Vec<u32>) = (
            got.iter().map(|v| v.to_bits()).collect(),
            want.iter().map(|v| v.to_bits()).collect(),
        );
        assert_eq!(got, want, "{name}: WGSL bits vs CPU bits");
    }
    // The Gabor constant −ln 20 = ln 0.05 rounded to f32 (the CPU's NEG_LN_20).
    let gabor = validate("gabor");
    assert_eq!(
        constant_values(&gabor, "NEG_LN_20"),
        [spectex_model::GABOR_TRUNCATION.ln() as f32]
    );
    // The classic noises' simplex constants (the CPU's f64 unskew factors rounded to f32).
    let classic = validate("classic");
    for (name, want) in [
        ("SIMPLEX_G2", spectex_model::classic::SIMPLEX_G2 as f32),
        ("SIMPLEX_G3", spectex_model::classic::SIMPLEX_G3 as f32),
        ("SIMPLEX_F2", spectex_model::classic::SIMPLEX_F2 as f32),
        ("SIMPLEX_F3", spectex_model::classic::SIMPLEX_F3 as f32),
        ("SIMPLEX2_R2", spectex_model::classic::SIMPLEX2_R2),
        ("SIMPLEX2_SCALE", spectex_model::classic::SIMPLEX2_SCALE),
        ("SIMPLEX3_R2", spectex_model::classic::SIMPLEX3_R2),
        ("SIMPLEX3_SCALE", spectex_model::classic::SIMPLEX3_SCALE),
    ] {
        assert_eq!(
            constant_values(&classic, name)[0].to_bits(),
            want.to_bits(),
            "classic.wgsl {name}"
        );
    }
    // The texture's placement cross-fade half-width.
    let texture = validate("texture");
    assert_eq!(
        constant_values(&texture, "PLACEMENT_BLEND"),
        [spectex_model::texture::PLACEMENT_BLEND]
    );
}
