//! `noise warp --by M` without `--by-y` displaces along y by M with every seed plus one: the same
//! render as `--by M --by-y M'`, M' written here by editing M's JSON (every `seed` and every
//! entry of `seeds`, nested models' too), for every grey model in `testdata/models/`.

use std::path::Path;

use crate::common::{s, scratch, spectex_ok};

/// `value` with every number under a `seed` key and every entry of a `seeds` array plus one
/// (wrapping at 2³²), at any depth: an edit of the file, independent of `Model::reseeded`.
fn seeds_plus_one(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Object(map) => {
            for (key, v) in map.iter_mut() {
                match (key.as_str(), &mut *v) {
                    ("seed", serde_json::Value::Number(n)) => *v = plus_one(n),
                    ("seeds", serde_json::Value::Array(list)) => {
                        for entry in list.iter_mut() {
                            if let serde_json::Value::Number(n) = entry {
                                *entry = plus_one(n);
                            }
                        }
                    }
                    _ => seeds_plus_one(v),
                }
            }
        }
        serde_json::Value::Array(list) => list.iter_mut().for_each(seeds_plus_one),
        _ => {}
    }
}

fn plus_one(n: &serde_json::Number) -> serde_json::Value {
    let seed = n.as_u64().expect("seeds are u32");
    serde_json::Value::from((seed + 1) % (1 << 32))
}

#[test]
fn warp_by_alone_reseeds_every_kind_for_y() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/models");
    let dir = scratch("warp-reseed");
    let mut files: Vec<_> = std::fs::read_dir(&models)
        .expect("testdata/models")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut checked = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).expect("model file");
        let model = spectex_model::from_json(&text).expect("valid model");
        let name = file
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        if model.output_channels() != 1 {
            println!("warp reseed: {name} skipped (colour: --by takes a grey model)");
            continue;
        }
        let mut json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        seeds_plus_one(&mut json);
        let next = dir.join(format!("{name}-next.json"));
        std::fs::write(&next, serde_json::to_string(&json).expect("JSON")).expect("write");
        let alone = dir.join(format!("{name}-alone.exr"));
        let both = dir.join(format!("{name}-both.exr"));
        let common = ["--size", "24x20", "--offset", "3.5,-7", "--strength", "3"];
        let mut a = vec!["noise", "warp", "--by", s(file), "-o", s(&alone)];
        a.extend(common);
        spectex_ok(&a);
        let mut b = vec![
            "noise",
            "warp",
            "--by",
            s(file),
            "--by-y",
            s(&next),
            "-o",
            s(&both),
        ];
        b.extend(common);
        spectex_ok(&b);
        let (va, vb) = (
            std::fs::read(&alone).expect("exr"),
            std::fs::read(&both).expect("exr"),
        );
        assert!(
            va == vb,
            "{name}: `--by M` differs from `--by M --by-y M'` (M' = every seed plus one)"
        );
        checked.push(name);
    }
    println!(
        "warp reseed: {} grey models checked: {}",
        checked.len(),
        checked.join(", ")
    );
    assert!(checked.len() >= 20, "only {} models checked", checked.len());
}
