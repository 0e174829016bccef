//! The docs stay readable: the README fits a screen or two and points to `docs/guide/` for the
//! reference, and `docs/ARCHITECTURE.md` stays a short map of stable facts.

use std::path::Path;

/// The README's length limit, in lines: what spectex is, the two commands, a gallery, the
/// library example and one line per command; the reference lives in `docs/guide/`.
pub(crate) const README_MAX_LINES: usize = 250;
/// `docs/ARCHITECTURE.md`'s size limit, in bytes (12 kB): volatile detail belongs in module docs.
pub(crate) const ARCHITECTURE_MAX_BYTES: usize = 12_000;

/// What is too long among the README and the architecture map under `root`.
pub(crate) fn oversized_docs(root: &Path) -> Vec<String> {
    let mut offences = Vec::new();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap_or_default();
    let lines = readme.lines().count();
    if lines > README_MAX_LINES {
        offences.push(format!(
            "README.md has {lines} lines (at most {README_MAX_LINES}); move reference text to docs/guide/"
        ));
    }
    let architecture = std::fs::read(root.join("docs/ARCHITECTURE.md")).unwrap_or_default();
    if architecture.len() > ARCHITECTURE_MAX_BYTES {
        offences.push(format!(
            "docs/ARCHITECTURE.md has {} bytes (at most {ARCHITECTURE_MAX_BYTES}); move volatile \
             detail to module docs",
            architecture.len()
        ));
    }
    if !root.join("docs/guide/README.md").is_file() {
        offences.push("docs/guide/README.md (the command reference's index) is missing".to_owned());
    }
    offences
}

#[test]
fn readme_and_architecture_stay_short() {
    let offences = oversized_docs(&crate::workspace_root());
    assert!(offences.is_empty(), "{}", offences.join("\n"));
}

#[test]
fn oversized_docs_are_reported() {
    let root = std::env::temp_dir().join(format!("spectex-tidy-docs-{}", std::process::id()));
    std::fs::create_dir_all(root.join("docs/guide")).unwrap_or_default();
    std::fs::write(
        root.join("README.md"),
        "line\n".repeat(README_MAX_LINES + 1),
    )
    .unwrap_or_default();
    std::fs::write(
        root.join("docs/ARCHITECTURE.md"),
        "x".repeat(ARCHITECTURE_MAX_BYTES + 1),
    )
    .unwrap_or_default();
    let offences = oversized_docs(&root);
    assert_eq!(offences.len(), 3, "{offences:?}");
    assert!(
        offences[0].starts_with("README.md has 251 lines"),
        "{offences:?}"
    );
    std::fs::write(root.join("README.md"), "short\n").unwrap_or_default();
    std::fs::write(root.join("docs/ARCHITECTURE.md"), "short\n").unwrap_or_default();
    std::fs::write(root.join("docs/guide/README.md"), "index\n").unwrap_or_default();
    assert_eq!(oversized_docs(&root), Vec::<String>::new());
    let _ = std::fs::remove_dir_all(&root);
}
