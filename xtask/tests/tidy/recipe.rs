//! The "Adding a model kind" recipe of `docs/ARCHITECTURE.md` stays the list of what a kind
//! is: every file it names exists for every kind of `for_each_kind!`, every layer that declares
//! one module per kind through that macro is in it, and it names at most [`MAX_KIND_FILES`]
//! files outside `testdata/` and `docs/`.

use std::collections::BTreeSet;
use std::path::Path;

use super::kinds::blank_comments_and_literals;
use super::{read, relative, rust_files};

/// Where the recipe is.
const RECIPE_DOC: &str = "docs/ARCHITECTURE.md";
/// Its heading; the section runs to the next `## ` heading.
const RECIPE_HEADING: &str = "## Adding a model kind";
/// The file holding the one list of kinds (the `@kinds` arm of `for_each_kind!`).
const KIND_LIST: &str = "crates/spectex-model/src/kind.rs";
/// The start of the list's arm in that file.
const KIND_LIST_ARM: &str = "(@kinds $form:tt) =>";
/// The placeholder the recipe writes for a kind's module name.
const KIND: &str = "<kind>";
/// Most files a new kind may create or edit outside `testdata/` and `docs/`.
pub(crate) const MAX_KIND_FILES: usize = 8;

#[test]
fn the_recipe_lists_every_layer_and_every_kind_has_its_files() {
    let offences = recipe_offences(&super::workspace_root());
    assert!(
        offences.is_empty(),
        "the \"Adding a model kind\" recipe of {RECIPE_DOC} and the kinds disagree:\n  {}",
        offences.join("\n  ")
    );
}

/// The module names of the kinds, in the order of `for_each_kind!`'s list (`module Variant
/// Struct,` lines).
pub(crate) fn kind_modules(root: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(root.join(KIND_LIST)).unwrap_or_default();
    let Some(start) = text.find(KIND_LIST_ARM) else {
        return Vec::new();
    };
    let mut modules = Vec::new();
    for line in text[start..].lines().skip(1) {
        let line = line.trim();
        if line.starts_with('}') {
            break;
        }
        let words: Vec<&str> = line.trim_end_matches(',').split_whitespace().collect();
        let is_entry = line.ends_with(',')
            && words.len() == 3
            && words[0].chars().all(|c| c.is_ascii_lowercase() || c == '_')
            && words[1..].iter().all(|w| w.starts_with(char::is_uppercase));
        if is_entry {
            modules.push(words[0].to_owned());
        }
    }
    modules
}

/// The file paths the recipe names (backquoted, with a `/` and a file extension), in order,
/// each once.
pub(crate) fn recipe_paths(root: &Path) -> Vec<String> {
    let doc = std::fs::read_to_string(root.join(RECIPE_DOC)).unwrap_or_default();
    let Some(start) = doc.find(RECIPE_HEADING) else {
        return Vec::new();
    };
    let section = &doc[start + RECIPE_HEADING.len()..];
    let section = section.find("\n## ").map_or(section, |end| &section[..end]);
    let mut paths = Vec::new();
    for span in section.split('`').skip(1).step_by(2) {
        let is_path = span.contains('/')
            && !span.contains(' ')
            && [".rs", ".wgsl", ".json"].iter().any(|e| span.ends_with(e));
        if is_path && !paths.iter().any(|p| p == span) {
            paths.push(span.to_owned());
        }
    }
    paths
}

/// The per-kind layers the code declares: for every `.rs` file under `crates/*/src` calling
/// `for_each_kind!(… mod)` or `for_each_kind!(list: …)`, the path of its kinds' modules
/// (`crates/x/src/<kind>.rs` beside a `lib.rs`, `mod.rs` or `main.rs`, else in the folder named
/// after the file), relative to `root`.
pub(crate) fn per_kind_layers(root: &Path) -> BTreeSet<String> {
    let mut files = Vec::new();
    for krate in std::fs::read_dir(root.join("crates"))
        .into_iter()
        .flatten()
        .flatten()
    {
        rust_files(&krate.path().join("src"), &mut files);
    }
    let mut layers = BTreeSet::new();
    for file in files {
        let code = blank_comments_and_literals(&read(&file));
        let declares = code.match_indices("for_each_kind!(").any(|(at, m)| {
            let args = &code[at + m.len()..];
            let args = args.split(')').next().unwrap_or_default().trim();
            args.ends_with("mod") || args.starts_with("list:")
        });
        if !declares {
            continue;
        }
        let stem = file
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default();
        let Some(parent) = file.parent() else {
            continue;
        };
        let dir = if matches!(stem, "lib" | "main" | "mod") {
            parent.to_path_buf()
        } else {
            parent.join(stem)
        };
        layers.insert(format!("{}/{KIND}.rs", relative(root, &dir)));
    }
    layers
}

/// Whether `path` (a kind's file, `<kind>` replaced) exists: a module may also be
/// `<kind>/mod.rs`, and a `*` in the file name matches any text.
fn kind_file_exists(root: &Path, path: &str) -> bool {
    if let Some((dir, name)) = path.rsplit_once('/')
        && let Some((head, tail)) = name.split_once('*')
    {
        return std::fs::read_dir(root.join(dir))
            .into_iter()
            .flatten()
            .flatten()
            .any(|entry| {
                let file = entry.file_name().to_string_lossy().into_owned();
                file.len() >= head.len() + tail.len()
                    && file.starts_with(head)
                    && file.ends_with(tail)
            });
    }
    root.join(path).is_file()
        || path
            .strip_suffix(".rs")
            .is_some_and(|module| root.join(module).join("mod.rs").is_file())
}

/// Every disagreement between the recipe, the kinds and the code's per-kind layers.
pub(crate) fn recipe_offences(root: &Path) -> Vec<String> {
    let mut offences = Vec::new();
    let kinds = kind_modules(root);
    if kinds.is_empty() {
        offences.push(format!(
            "{KIND_LIST}: no kinds found in the `{KIND_LIST_ARM}` arm of `for_each_kind!`"
        ));
    }
    let paths = recipe_paths(root);
    if paths.is_empty() {
        offences.push(format!(
            "{RECIPE_DOC}: no `{RECIPE_HEADING}` section naming files"
        ));
    }
    let counted: Vec<&String> = paths
        .iter()
        .filter(|p| !p.starts_with("testdata/") && !p.starts_with("docs/"))
        .collect();
    if counted.len() > MAX_KIND_FILES {
        offences.push(format!(
            "{RECIPE_DOC}: a kind is {} files outside testdata/ and docs/, more than \
             {MAX_KIND_FILES}: {}",
            counted.len(),
            counted
                .iter()
                .map(|p| p.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    for layer in per_kind_layers(root) {
        if !paths.contains(&layer) {
            offences.push(format!(
                "{layer}: a layer declares one module per kind (`for_each_kind!`), but the \
                 recipe in {RECIPE_DOC} does not name it"
            ));
        }
    }
    for path in &paths {
        if path.contains(KIND) {
            for kind in &kinds {
                let file = path.replace(KIND, kind);
                if !kind_file_exists(root, &file) {
                    offences.push(format!("{file}: the recipe's `{path}` for kind {kind}"));
                }
            }
        } else if !kind_file_exists(root, path) {
            offences.push(format!(
                "{path}: named by the recipe, not in the repository"
            ));
        }
    }
    offences
}

// ---------------------------------------------------------------------------------------------
// The check on a planted tree: it must find what is planted and nothing on the clean tree.

#[test]
fn recipe_offences_are_found_in_a_planted_tree() {
    let root = std::env::temp_dir().join(format!("spectex-tidy-recipe-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let write = |relative: &str, text: &str| {
        let path = root.join(relative);
        std::fs::create_dir_all(path.parent().unwrap_or(&root)).unwrap_or_default();
        std::fs::write(&path, text).unwrap_or_default();
    };
    write(
        KIND_LIST,
        "macro_rules! for_each_kind {\n    (@kinds $form:tt) => {\n        \
         $crate::for_each_kind! { @each $form\n            alpha Alpha AlphaNoise,\n            \
         beta Beta BetaNoise,\n        }\n    };\n}\n",
    );
    let recipe = |files: &[&str]| {
        let items: String = files.iter().map(|f| format!("1. `{f}`: x.\n")).collect();
        format!(
            "# A\n\n{RECIPE_HEADING}\n\nSee `for_each_kind!`.\n\n{items}\n## Next\n\n`a/b.rs`\n"
        )
    };
    write(
        RECIPE_DOC,
        &recipe(&[
            KIND_LIST,
            "crates/spectex-cpu/src/<kind>.rs",
            "testdata/models/<kind>*.json",
        ]),
    );
    write(
        "crates/spectex-cpu/src/lib.rs",
        "//! A crate.\nspectex_model::for_each_kind!(pub mod);\n",
    );
    write("crates/spectex-cpu/src/alpha.rs", "//! Alpha.\n");
    write("crates/spectex-cpu/src/beta/mod.rs", "//! Beta.\n");
    write("testdata/models/alpha-one.json", "{}");
    write("testdata/models/beta.json", "{}");
    assert_eq!(kind_modules(&root), ["alpha", "beta"]);
    assert_eq!(recipe_offences(&root), Vec::<String>::new());

    // A kind's file missing, a layer the recipe leaves out, a kind without a test model.
    std::fs::remove_file(root.join("crates/spectex-cpu/src/beta/mod.rs")).unwrap_or_default();
    write(
        "crates/spectex-gpu/src/kinds.rs",
        "//! A layer.\n// for_each_kind!(mod) in a comment is no layer.\n\
         spectex_model::for_each_kind!(list: callback);\n",
    );
    std::fs::remove_file(root.join("testdata/models/beta.json")).unwrap_or_default();
    let offences = recipe_offences(&root);
    assert_eq!(offences.len(), 3, "{offences:?}");
    assert!(offences[0].starts_with("crates/spectex-gpu/src/kinds/<kind>.rs: a layer"));
    assert!(offences[1].starts_with("crates/spectex-cpu/src/beta.rs: the recipe's"));
    assert!(offences[2].starts_with("testdata/models/beta*.json: the recipe's"));

    // Nine files outside testdata/ and docs/.
    let nine: Vec<String> = (0..9)
        .map(|k| format!("crates/c{k}/src/<kind>.rs"))
        .collect();
    let nine: Vec<&str> = nine.iter().map(String::as_str).collect();
    write(RECIPE_DOC, &recipe(&nine));
    let offences = recipe_offences(&root);
    assert!(
        offences[0].contains("a kind is 9 files outside testdata/ and docs/, more than 8"),
        "{offences:?}"
    );
    let _ = std::fs::remove_dir_all(&root);
}
