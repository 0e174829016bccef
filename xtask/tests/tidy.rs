//! Tidy checks on the workspace itself: crate dependency direction, module doc lines, members
//! inheriting lints and dependency versions from the workspace, and one integration-test binary
//! per crate.
//!
//! Each check is a function from a workspace root to a list of offences, so the negative tests at
//! the end can run it on a small fake tree and prove that it can fail.

#[path = "tidy/docs.rs"]
mod docs;
#[path = "tidy/kinds.rs"]
mod kinds;
#[path = "tidy/recipe.rs"]
mod recipe;

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// The crates under `crates/` and the project crates each may depend on (docs/ARCHITECTURE.md, "Dependency
/// direction"). A new crate is added here deliberately, with its place in the direction.
const ALLOWED_PROJECT_DEPENDENCIES: &[(&str, &[&str])] = &[
    ("spectex-model", &[]),
    ("spectex-spectrum", &["spectex-model"]),
    ("spectex-sampling", &["spectex-model", "spectex-spectrum"]),
    ("spectex-cpu", &["spectex-model"]),
    ("spectex-gpu", &["spectex-model"]),
    ("spectex-simulate", &["spectex-model", "spectex-spectrum"]),
    (
        "spectex-crosscheck",
        &[
            "spectex-model",
            "spectex-cpu",
            "spectex-gpu",
            "spectex-spectrum",
            "spectex-simulate",
        ],
    ),
    (
        "spectex-cli",
        &[
            "spectex-model",
            "spectex-spectrum",
            "spectex-sampling",
            "spectex-cpu",
            "spectex-gpu",
            "spectex-crosscheck",
            "spectex-reproduce",
            "spectex-simulate",
        ],
    ),
    (
        "spectex-reproduce",
        &[
            "spectex-model",
            "spectex-spectrum",
            "spectex-sampling",
            "spectex-cpu",
            "spectex-gpu",
        ],
    ),
    (
        "spectex-py",
        &[
            "spectex-model",
            "spectex-spectrum",
            "spectex-sampling",
            "spectex-cpu",
            "spectex-gpu",
            "spectex-simulate",
        ],
    ),
    (
        "spectex-testkit",
        &[
            "spectex-model",
            "spectex-cpu",
            "spectex-gpu",
            "spectex-spectrum",
        ],
    ),
];

/// Project crates that exist for tests only, and the crates that may take each — as a
/// dev-dependency and in no other section. Any other dependency on them is an offence, so a
/// test kit never ends up in a library's build.
const DEV_ONLY_DEPENDENCIES: &[(&str, &[&str])] = &[(
    "spectex-testkit",
    &[
        "spectex-cpu",
        "spectex-gpu",
        "spectex-cli",
        "spectex-spectrum",
        "spectex-sampling",
        "spectex-simulate",
        "spectex-model",
        "spectex-crosscheck",
    ],
)];

/// Folders of a crate whose `.rs` files are modules that must start with a `//!` line.
const SOURCE_DIRS: &[&str] = &["src", "tests", "benches", "examples"];

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives inside the workspace")
        .to_path_buf()
}

#[test]
fn crate_dependency_direction() {
    let offences = dependency_direction_offences(&workspace_root());
    assert!(
        offences.is_empty(),
        "the crate dependency direction of docs/ARCHITECTURE.md is broken:\n  {}",
        offences.join("\n  ")
    );
}

#[test]
fn every_module_has_a_doc_line() {
    let offences = modules_without_doc_line(&workspace_root());
    assert!(
        offences.is_empty(),
        "these modules do not start with a `//!` line saying what they are for:\n  {}",
        offences.join("\n  ")
    );
}

#[test]
fn workspace_members_use_workspace_lints_and_versions() {
    let offences = workspace_inheritance_offences(&workspace_root());
    assert!(
        offences.is_empty(),
        "members must say `[lints] workspace = true` and `foo.workspace = true` \
         (versions live in the root [workspace.dependencies]):\n  {}",
        offences.join("\n  ")
    );
}

#[test]
fn integration_tests_are_one_binary_per_crate() {
    let offences = extra_test_binaries(&workspace_root());
    assert!(
        offences.is_empty(),
        "integration tests live in one binary per crate, `tests/it/main.rs` with one module per \
         file (every extra binary links all the dependencies again); make these modules of \
         `tests/it/`:\n  {}",
        offences.join("\n  ")
    );
}

#[test]
fn crates_embed_only_their_own_files() {
    let offences = includes_outside_their_crate(&workspace_root());
    assert!(
        offences.is_empty(),
        "a published crate's sources embed files from outside its directory, which `cargo \
         package` and the Python sdist leave out (the crate would not compile from them); move \
         the file into the crate, or read it at run time where only the repository has it:\n  {}",
        offences.join("\n  ")
    );
}

// ---------------------------------------------------------------------------------------------
// The checks.

/// Every `include_str!`/`include_bytes!` of a literal path in the sources (`src/`, a build script)
/// of a crate that is published (no `publish = false`) whose file lies outside the crate's
/// directory.
fn includes_outside_their_crate(root: &Path) -> Vec<String> {
    let mut offences = Vec::new();
    for dir in crate_dirs(root) {
        if read(&dir.join("Cargo.toml"))
            .lines()
            .any(|line| strip_comment(line).replace(' ', "") == "publish=false")
        {
            continue;
        }
        let mut files = Vec::new();
        rust_files(&dir.join("src"), &mut files);
        if dir.join("build.rs").is_file() {
            files.push(dir.join("build.rs"));
        }
        for file in files {
            let text = read(&file);
            for path in included_paths(&text) {
                let mut target = file.parent().expect("a file has a parent").to_path_buf();
                for part in Path::new(&path).components() {
                    match part {
                        std::path::Component::ParentDir => {
                            target.pop();
                        }
                        std::path::Component::Normal(name) => target.push(name),
                        _ => {}
                    }
                }
                if !target.starts_with(&dir) {
                    offences.push(format!(
                        "{}: includes {path} ({})",
                        relative(root, &file),
                        relative(root, &target)
                    ));
                }
            }
        }
    }
    offences
}

/// The literal paths of `include_str!("…")` and `include_bytes!("…")` in `text`.
fn included_paths(text: &str) -> Vec<String> {
    let mut paths = Vec::new();
    for macro_call in ["include_str!(", "include_bytes!("] {
        let mut rest = text;
        while let Some(at) = rest.find(macro_call) {
            rest = &rest[at + macro_call.len()..];
            let Some(literal) = rest.trim_start().strip_prefix('"') else {
                continue;
            };
            if let Some(end) = literal.find('"') {
                paths.push(literal[..end].to_owned());
            }
        }
    }
    paths
}

/// Every forbidden edge between project crates, a crate directory missing from or unknown to
/// [`ALLOWED_PROJECT_DEPENDENCIES`], and any project crate xtask depends on.
fn dependency_direction_offences(root: &Path) -> Vec<String> {
    let mut offences = Vec::new();
    let known: BTreeSet<&str> = ALLOWED_PROJECT_DEPENDENCIES
        .iter()
        .map(|(name, _)| *name)
        .collect();
    let present: BTreeSet<String> = crate_dirs(root)
        .iter()
        .filter_map(|dir| dir.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    for name in &present {
        if !known.contains(name.as_str()) {
            offences.push(format!(
                "crates/{name}: not in the dependency table of xtask/tests/tidy.rs (and docs/ARCHITECTURE.md)"
            ));
        }
    }
    for name in &known {
        if !present.contains(*name) {
            offences.push(format!("crates/{name}: in the dependency table but absent"));
        }
    }

    let mut check = |manifest: PathBuf, krate: &str, allowed: &[&str]| {
        for dep in dependencies(&manifest) {
            if let Some((_, takers)) = DEV_ONLY_DEPENDENCIES
                .iter()
                .find(|(name, _)| *name == dep.name)
            {
                if !(takers.contains(&krate) && is_dev_section(&dep.section)) {
                    offences.push(format!(
                        "{}:{}: {krate} -> {} in [{}]; {} is dev-only: only {} may take it, \
                         in [dev-dependencies]",
                        relative(root, &manifest),
                        dep.line,
                        dep.name,
                        dep.section,
                        dep.name,
                        takers.join(", "),
                    ));
                }
                continue;
            }
            // A crate's dev-dependency on itself (a feature for its own tests and benches, as
            // spectex-cpu's bench-only `relaxed`) is no edge between crates.
            if dep.name == krate && is_dev_section(&dep.section) {
                continue;
            }
            if dep.name.starts_with("spectex-") && !allowed.contains(&dep.name.as_str()) {
                let may = if allowed.is_empty() {
                    "no project crate".to_owned()
                } else {
                    allowed.join(", ")
                };
                offences.push(format!(
                    "{}:{}: {krate} -> {} in [{}]; {krate} may depend on {may}",
                    relative(root, &manifest),
                    dep.line,
                    dep.name,
                    dep.section,
                ));
            }
        }
    };
    for (name, allowed) in ALLOWED_PROJECT_DEPENDENCIES {
        let manifest = root.join("crates").join(name).join("Cargo.toml");
        if manifest.is_file() {
            check(manifest, name, allowed);
        }
    }
    check(root.join("xtask").join("Cargo.toml"), "xtask", &[]);
    offences
}

/// Every `.rs` file of the crates and xtask whose first non-empty line is not a `//!` line.
fn modules_without_doc_line(root: &Path) -> Vec<String> {
    let mut dirs: Vec<PathBuf> = crate_dirs(root)
        .iter()
        .flat_map(|krate| SOURCE_DIRS.iter().map(move |sub| krate.join(sub)))
        .collect();
    dirs.extend(["src", "tests"].map(|sub| root.join("xtask").join(sub)));

    let mut files = Vec::new();
    for dir in dirs {
        rust_files(&dir, &mut files);
    }
    files.sort();
    files
        .into_iter()
        .filter(|file| {
            let text = read(file);
            let first = text.lines().map(str::trim).find(|line| !line.is_empty());
            !first.is_some_and(|line| line.starts_with("//!"))
        })
        .map(|file| relative(root, &file))
        .collect()
}

/// Members without `[lints] workspace = true`, and member dependencies not inherited from the
/// workspace (a version, path or git of their own).
fn workspace_inheritance_offences(root: &Path) -> Vec<String> {
    let mut manifests: Vec<PathBuf> = crate_dirs(root)
        .iter()
        .map(|dir| dir.join("Cargo.toml"))
        .collect();
    manifests.push(root.join("xtask").join("Cargo.toml"));

    let mut offences = Vec::new();
    for manifest in manifests.iter().filter(|m| m.is_file()) {
        if !inherits_workspace_lints(&read(manifest)) {
            offences.push(format!(
                "{}: no `[lints]` section with `workspace = true`",
                relative(root, manifest)
            ));
        }
        for dep in dependencies(manifest) {
            if !dep.workspace {
                offences.push(format!(
                    "{}:{}: [{}] {} does not use `{}.workspace = true`",
                    relative(root, manifest),
                    dep.line,
                    dep.section,
                    dep.name,
                    dep.key,
                ));
            }
        }
    }
    offences
}

/// The integration-test targets cargo finds in the crates other than `tests/it/main.rs`: each
/// `tests/*.rs` and each other `tests/*/main.rs` is a binary of its own.
fn extra_test_binaries(root: &Path) -> Vec<String> {
    let mut offences = Vec::new();
    for krate in crate_dirs(root) {
        let tests = krate.join("tests");
        let Ok(entries) = fs::read_dir(&tests) else {
            continue;
        };
        for entry in entries {
            let path = entry
                .unwrap_or_else(|e| panic!("reading {}: {e}", tests.display()))
                .path();
            let target = if path.is_dir() {
                path.join("main.rs")
            } else {
                path.clone()
            };
            let is_target = if path.is_dir() {
                target.is_file() && path.file_name().is_none_or(|name| name != "it")
            } else {
                path.extension().is_some_and(|ext| ext == "rs")
            };
            if is_target {
                offences.push(relative(root, &target));
            }
        }
    }
    offences.sort();
    offences
}

// ---------------------------------------------------------------------------------------------
// A minimal, line-based reading of Cargo.toml: enough for the manifests of this workspace, which
// keep to the usual forms (`foo.workspace = true`, `foo = { workspace = true, ... }`,
// `foo = "1"`, `[dependencies.foo]`, `[target.'cfg(..)'.dependencies]`).

/// One dependency of a manifest, merged over all the lines that declare it in one section.
#[derive(Debug)]
struct Dependency {
    /// The package depended on (`package = "..."` when renamed, else the key).
    name: String,
    /// The key in the manifest.
    key: String,
    /// The section header, without brackets (`dev-dependencies`, `target.'cfg(unix)'.dependencies`).
    section: String,
    /// The 1-based line of its first declaration.
    line: usize,
    /// Whether it says `workspace = true`.
    workspace: bool,
}

/// What a section header opens, as far as dependencies are concerned.
enum Section {
    /// `[dependencies]` and friends: each key is a dependency.
    List(String),
    /// `[dependencies.foo]`: the keys are those of the dependency `foo`.
    Table(String, String),
    Other,
}

const DEPENDENCY_KINDS: &[&str] = &["dependencies", "dev-dependencies", "build-dependencies"];

/// Whether a dependency section header (`dev-dependencies`, `dev-dependencies.foo`,
/// `target.'cfg(unix)'.dev-dependencies`) declares dev-dependencies.
fn is_dev_section(header: &str) -> bool {
    let local = match header.strip_prefix("target.") {
        Some(rest) => match target_spec_end(rest) {
            Some(end) => &rest[end..],
            None => return false,
        },
        None => header,
    };
    local.split('.').next().map(str::trim) == Some("dev-dependencies")
}

fn classify(header: &str) -> Section {
    // The target part may itself hold dots (`cfg(target_os = "a.b")`), so strip it as a prefix.
    let local = match header.strip_prefix("target.") {
        Some(rest) => match target_spec_end(rest) {
            Some(end) => &rest[end..],
            None => return Section::Other,
        },
        None => header,
    };
    let (kind, dep) = match local.split_once('.') {
        Some((kind, dep)) => (kind, Some(dep)),
        None => (local, None),
    };
    if !DEPENDENCY_KINDS.contains(&kind.trim()) {
        return Section::Other;
    }
    match dep {
        None => Section::List(header.to_owned()),
        Some(dep) => Section::Table(header.to_owned(), unquote(dep.trim()).to_owned()),
    }
}

/// In `'cfg(..)'.dependencies` or `x86_64-unknown-linux-gnu.dependencies`, the index just past the
/// `.` that ends the target part.
fn target_spec_end(rest: &str) -> Option<usize> {
    let quote = rest.chars().next().filter(|c| matches!(c, '\'' | '"'));
    let end = match quote {
        Some(q) => rest[1..].find(q)? + 2,
        None => rest.find('.')?,
    };
    rest[end..].starts_with('.').then_some(end + 1)
}

fn unquote(s: &str) -> &str {
    s.trim_matches(|c| c == '"' || c == '\'')
}

/// The dependencies a manifest declares, in every dependency section.
fn dependencies(manifest: &Path) -> Vec<Dependency> {
    let text = read(manifest);
    let mut deps: Vec<Dependency> = Vec::new();
    let mut section = Section::Other;
    let mut open_brackets = 0i32; // inside a multi-line array value
    for (index, raw) in text.lines().enumerate() {
        let line = strip_comment(raw).trim();
        if open_brackets > 0 {
            open_brackets += bracket_balance(line);
            continue;
        }
        if line.is_empty() {
            continue;
        }
        if line.starts_with('[') && !line.starts_with("[[") {
            let header = line.trim_start_matches('[').trim_end_matches(']').trim();
            section = classify(header);
            if let Section::Table(header, key) = &section {
                merge(&mut deps, header, key, index + 1, false, None);
            }
            continue;
        }
        if line.starts_with("[[") {
            section = Section::Other;
            continue;
        }
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        let (key, value) = (key.trim(), value.trim());
        open_brackets = bracket_balance(value).max(0);
        match &section {
            Section::List(header) => {
                // `foo = ...`, `foo.workspace = true`, `foo.features = [...]`
                let (dep_key, field) = match key.split_once('.') {
                    Some((dep, field)) => (unquote(dep.trim()), Some(unquote(field.trim()))),
                    None => (unquote(key), None),
                };
                let (workspace, package) = match field {
                    Some("workspace") => (value == "true", None),
                    Some("package") => (false, Some(unquote(value).to_owned())),
                    Some(_) => (false, None),
                    None => (
                        inline_field(value, "workspace") == Some("true"),
                        inline_field(value, "package").map(|p| unquote(p).to_owned()),
                    ),
                };
                merge(&mut deps, header, dep_key, index + 1, workspace, package);
            }
            Section::Table(header, dep_key) => {
                let (workspace, package) = match unquote(key) {
                    "workspace" => (value == "true", None),
                    "package" => (false, Some(unquote(value).to_owned())),
                    _ => (false, None),
                };
                merge(&mut deps, header, dep_key, index + 1, workspace, package);
            }
            Section::Other => {}
        }
    }
    deps
}

/// Adds what one line says about the dependency `key` of `section` to `deps`.
fn merge(
    deps: &mut Vec<Dependency>,
    section: &str,
    key: &str,
    line: usize,
    workspace: bool,
    package: Option<String>,
) {
    let existing = deps
        .iter_mut()
        .find(|d| d.section == section && d.key == key);
    let dep = match existing {
        Some(dep) => dep,
        None => {
            deps.push(Dependency {
                name: key.to_owned(),
                key: key.to_owned(),
                section: section.to_owned(),
                line,
                workspace: false,
            });
            deps.last_mut().expect("just pushed")
        }
    };
    dep.workspace |= workspace;
    if let Some(package) = package {
        dep.name = package;
    }
}

/// The raw value of `field` in a one-line inline table `{ a = 1, field = value, ... }`.
fn inline_field<'a>(value: &'a str, field: &str) -> Option<&'a str> {
    let inner = value.strip_prefix('{')?.strip_suffix('}')?;
    inner.split(',').find_map(|pair| {
        let (k, v) = pair.split_once('=')?;
        (unquote(k.trim()) == field).then_some(v.trim())
    })
}

/// Whether the manifest has a `[lints]` section saying `workspace = true`.
fn inherits_workspace_lints(text: &str) -> bool {
    let mut in_lints = false;
    for raw in text.lines() {
        let line = strip_comment(raw).trim();
        if line.starts_with('[') {
            in_lints = line == "[lints]";
        } else if in_lints
            && let Some((key, value)) = line.split_once('=')
            && key.trim() == "workspace"
            && value.trim() == "true"
        {
            return true;
        }
    }
    false
}

/// `line` without a trailing `# comment` (a `#` inside a string is kept).
fn strip_comment(line: &str) -> &str {
    let mut quote = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, '#') => return &line[..i],
            _ => {}
        }
    }
    line
}

/// Opening minus closing brackets outside strings.
fn bracket_balance(text: &str) -> i32 {
    let mut quote = None;
    let mut balance = 0;
    for c in text.chars() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, '[') => balance += 1,
            (None, ']') => balance -= 1,
            _ => {}
        }
    }
    balance
}

// ---------------------------------------------------------------------------------------------
// Files.

/// The directories directly under `root/crates`, sorted.
fn crate_dirs(root: &Path) -> Vec<PathBuf> {
    let crates = root.join("crates");
    let entries =
        fs::read_dir(&crates).unwrap_or_else(|e| panic!("reading {}: {e}", crates.display()));
    let mut dirs: Vec<PathBuf> = entries
        .map(|entry| {
            entry
                .unwrap_or_else(|e| panic!("reading {}: {e}", crates.display()))
                .path()
        })
        .filter(|path| path.is_dir())
        .collect();
    dirs.sort();
    dirs
}

/// Appends every `.rs` file under `dir` (recursively) to `out`; a missing `dir` adds nothing.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries {
        let path = entry
            .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
            .path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            out.push(path);
        }
    }
}

/// `path` relative to the workspace `root`, for messages.
fn relative(root: &Path, path: &Path) -> String {
    path.strip_prefix(root)
        .unwrap_or(path)
        .display()
        .to_string()
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()))
}

// ---------------------------------------------------------------------------------------------
// The checks on fake trees: each must report what is planted, and nothing on a clean tree.

/// A fake workspace in the temporary directory, removed on drop (also when a test panics).
struct FakeTree {
    root: PathBuf,
}

impl FakeTree {
    /// A tree with all seven crates (each with a documented lib.rs, inheriting everything, and
    /// no project dependencies) and an xtask.
    fn new(test: &str) -> Self {
        let root = std::env::temp_dir().join(format!("spectex-tidy-{}-{test}", std::process::id()));
        if root.exists() {
            fs::remove_dir_all(&root).expect("removing a stale fake tree");
        }
        let tree = Self { root };
        for (name, _) in ALLOWED_PROJECT_DEPENDENCIES {
            tree.write(&format!("crates/{name}/Cargo.toml"), &manifest(name, ""));
            tree.write(&format!("crates/{name}/src/lib.rs"), "//! A crate.\n");
        }
        tree.write(
            "xtask/Cargo.toml",
            &manifest("xtask", "[dependencies]\nanyhow.workspace = true\n"),
        );
        tree.write("xtask/src/main.rs", "\n//! Automation.\nfn main() {}\n");
        tree
    }

    fn write(&self, relative: &str, text: &str) {
        let path = self.root.join(relative);
        fs::create_dir_all(path.parent().expect("a file has a parent"))
            .unwrap_or_else(|e| panic!("creating the parent of {}: {e}", path.display()));
        fs::write(&path, text).unwrap_or_else(|e| panic!("writing {}: {e}", path.display()));
    }
}

impl Drop for FakeTree {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.root);
    }
}

fn manifest(name: &str, dependencies: &str) -> String {
    format!(
        "[package]\nname = \"{name}\"\nversion.workspace = true\n\n{dependencies}\n\
         [lints]\nworkspace = true\n"
    )
}

/// Asserts that some offence mentions every one of `needles`, and prints them all otherwise.
fn assert_reported(offences: &[String], needles: &[&str]) {
    assert!(
        offences
            .iter()
            .any(|o| needles.iter().all(|needle| o.contains(needle))),
        "expected an offence mentioning {needles:?}; got:\n  {}",
        offences.join("\n  ")
    );
}

#[test]
fn checks_pass_on_a_clean_fake_tree_in_every_manifest_form() {
    let tree = FakeTree::new("clean");
    tree.write(
        "crates/spectex-crosscheck/Cargo.toml",
        &manifest(
            "spectex-crosscheck",
            "[dependencies]\n\
             spectex-cpu.workspace = true # a comment with [brackets] and spectex-cli\n\
             spectex-gpu = { workspace = true, features = [\"x\"] }\n\
             image = { workspace = true }\n\
             \n\
             [dependencies.spectex-spectrum]\n\
             workspace = true\n\
             features = [\n  \"a\",\n  \"spectex-cli = 1\",\n]\n\
             \n\
             [target.'cfg(target_os = \"linux\")'.dev-dependencies]\n\
             spectex-model.workspace = true\n\
             \n\
             [[bench]]\nname = \"b\"\nharness = false\n",
        ),
    );
    tree.write(
        "crates/spectex-cpu/Cargo.toml",
        &manifest(
            "spectex-cpu",
            "[dev-dependencies]\n\
             spectex-cpu = { workspace = true, features = [\"relaxed\"] }\n",
        ),
    );
    tree.write("crates/spectex-cpu/tests/deep/nested.rs", "//! Nested.\n");
    tree.write(
        "crates/spectex-cpu/tests/it/main.rs",
        "//! Tests.\nmod lrp;\n",
    );
    tree.write("crates/spectex-cpu/tests/it/lrp.rs", "//! LRP.\n");
    assert_eq!(
        dependency_direction_offences(&tree.root),
        Vec::<String>::new()
    );
    assert_eq!(modules_without_doc_line(&tree.root), Vec::<String>::new());
    assert_eq!(
        workspace_inheritance_offences(&tree.root),
        Vec::<String>::new()
    );
    assert_eq!(extra_test_binaries(&tree.root), Vec::<String>::new());
}

#[test]
fn checks_report_what_a_broken_fake_tree_plants() {
    let tree = FakeTree::new("broken");
    // Forbidden edges, in three manifest forms, and a project crate in xtask.
    tree.write(
        "crates/spectex-cpu/Cargo.toml",
        &manifest(
            "spectex-cpu",
            "[dev-dependencies]\nspectex-gpu.workspace = true\n",
        ),
    );
    tree.write(
        "crates/spectex-model/Cargo.toml",
        &manifest(
            "spectex-model",
            "[target.x86_64-unknown-linux-gnu.dependencies.evaluator]\n\
             package = \"spectex-cpu\"\nworkspace = true\n",
        ),
    );
    tree.write(
        "crates/spectex-gpu/Cargo.toml",
        "[package]\nname = \"spectex-gpu\"\n\n[build-dependencies]\n\
         spectex-spectrum = { path = \"../spectex-spectrum\" }\nrand = \"0.9\"\n",
    );
    tree.write(
        "xtask/Cargo.toml",
        &manifest("xtask", "[dependencies]\nspectex-model.workspace = true\n"),
    );
    // A crate missing from the table, and modules without a doc line.
    tree.write(
        "crates/spectex-extra/Cargo.toml",
        &manifest("spectex-extra", ""),
    );
    tree.write("crates/spectex-extra/src/lib.rs", "//! Extra.\n");
    tree.write(
        "crates/spectex-cpu/src/eval.rs",
        "// A plain comment.\n//! Too late.\n",
    );
    tree.write(
        "crates/spectex-sampling/examples/01_fit/main.rs",
        "fn main() {}\n",
    );
    tree.write("xtask/tests/tidy.rs", "/// An item doc.\n");
    // Integration-test binaries besides `tests/it/main.rs`.
    tree.write("crates/spectex-gpu/tests/it/main.rs", "//! Tests.\n");
    tree.write(
        "crates/spectex-gpu/tests/extra.rs",
        "//! A second binary.\n",
    );
    tree.write("crates/spectex-cli/tests/other/main.rs", "//! A third.\n");

    let edges = dependency_direction_offences(&tree.root);
    let cpu = Path::new("crates/spectex-cpu/Cargo.toml")
        .display()
        .to_string();
    assert_reported(&edges, &[&cpu, "[dev-dependencies]", "spectex-gpu"]);
    assert_reported(
        &edges,
        &["spectex-model", "dependencies.evaluator", "spectex-cpu"],
    );
    assert_reported(
        &edges,
        &["spectex-gpu", "[build-dependencies]", "spectex-spectrum"],
    );
    assert_reported(&edges, &["xtask", "spectex-model"]);
    assert_reported(
        &edges,
        &["crates/spectex-extra", "not in the dependency table"],
    );
    assert_eq!(edges.len(), 5, "{edges:#?}");

    let undocumented = modules_without_doc_line(&tree.root);
    assert_reported(&undocumented, &["eval.rs"]);
    assert_reported(&undocumented, &["01_fit", "main.rs"]);
    assert_reported(&undocumented, &["tidy.rs"]);
    assert_eq!(undocumented.len(), 3, "{undocumented:#?}");

    let inheritance = workspace_inheritance_offences(&tree.root);
    assert_reported(&inheritance, &["spectex-gpu", "no `[lints]` section"]);
    assert_reported(
        &inheritance,
        &["spectex-gpu", "spectex-spectrum does not use"],
    );
    assert_reported(&inheritance, &["spectex-gpu", "rand does not use"]);
    assert_eq!(inheritance.len(), 3, "{inheritance:#?}");

    let binaries = extra_test_binaries(&tree.root);
    assert_reported(&binaries, &["spectex-gpu", "extra.rs"]);
    assert_reported(&binaries, &["spectex-cli", "other", "main.rs"]);
    assert_eq!(binaries.len(), 2, "{binaries:#?}");

    let root = tree.root.clone();
    drop(tree);
    assert!(!root.exists(), "{} was not removed", root.display());
}

#[test]
fn a_dev_only_crate_is_taken_only_as_a_dev_dependency_by_its_takers() {
    let tree = FakeTree::new("dev-only");
    // Allowed: the takers, in [dev-dependencies] (plain, table and target-specific forms).
    tree.write(
        "crates/spectex-cpu/Cargo.toml",
        &manifest(
            "spectex-cpu",
            "[dev-dependencies]\nspectex-testkit.workspace = true\n",
        ),
    );
    tree.write(
        "crates/spectex-gpu/Cargo.toml",
        &manifest(
            "spectex-gpu",
            "[dev-dependencies.spectex-testkit]\nworkspace = true\n",
        ),
    );
    tree.write(
        "crates/spectex-cli/Cargo.toml",
        &manifest(
            "spectex-cli",
            "[target.'cfg(unix)'.dev-dependencies]\n\
             spectex-testkit = { workspace = true, features = [\"cpu\"] }\n",
        ),
    );
    assert_eq!(
        dependency_direction_offences(&tree.root),
        Vec::<String>::new()
    );
    // Offences: a taker's normal or build dependency, and a crate that is not a taker.
    tree.write(
        "crates/spectex-cpu/Cargo.toml",
        &manifest(
            "spectex-cpu",
            "[dependencies]\nspectex-testkit.workspace = true\n",
        ),
    );
    tree.write(
        "crates/spectex-gpu/Cargo.toml",
        &manifest(
            "spectex-gpu",
            "[build-dependencies.kit]\npackage = \"spectex-testkit\"\nworkspace = true\n",
        ),
    );
    tree.write(
        "crates/spectex-reproduce/Cargo.toml",
        &manifest(
            "spectex-reproduce",
            "[dev-dependencies]\nspectex-testkit.workspace = true\n",
        ),
    );
    let edges = dependency_direction_offences(&tree.root);
    assert_reported(&edges, &["spectex-cpu", "[dependencies]", "dev-only"]);
    assert_reported(
        &edges,
        &["spectex-gpu", "build-dependencies.kit", "dev-only"],
    );
    assert_reported(
        &edges,
        &["spectex-reproduce", "[dev-dependencies]", "dev-only"],
    );
    assert_eq!(edges.len(), 3, "{edges:#?}");
}

#[test]
fn an_include_from_outside_a_published_crate_is_reported() {
    let tree = FakeTree::new("include");
    tree.write(
        "crates/spectex-gpu/src/lib.rs",
        "//! A crate.\nconst A: &str = include_str!(\"../shaders/a.wgsl\");\n\
         const B: &str = include_str!(\n    \"../../../shaders/b.wgsl\"\n);\n",
    );
    tree.write(
        "crates/spectex-cpu/src/deep/kind.rs",
        "//! A module.\nconst M: &[u8] = include_bytes!(\"../../../../testdata/m.json\");\n",
    );
    // A crate that is not published may embed the repository's files.
    tree.write(
        "crates/spectex-crosscheck/Cargo.toml",
        &format!("{}publish = false\n", manifest("spectex-crosscheck", "")),
    );
    tree.write(
        "crates/spectex-crosscheck/src/lib.rs",
        "//! A crate.\nconst C: &str = include_str!(\"../../../testdata/c.json\");\n",
    );
    let offences = includes_outside_their_crate(&tree.root);
    assert_eq!(offences.len(), 2, "{offences:#?}");
    assert_reported(
        &offences,
        &["crates/spectex-gpu/src/lib.rs", "../../../shaders/b.wgsl"],
    );
    assert_reported(
        &offences,
        &["crates/spectex-cpu/src/deep/kind.rs", "testdata/m.json"],
    );
}
