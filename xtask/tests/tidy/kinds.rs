//! Tidy checks that keep "a model kind is one definition per layer" true: no wildcard arm in a
//! `match` over `Model` outside spectex-model (so the compiler points at every place a new kind
//! is missed), the kinds the docs list are the kinds the enum has, and no doc or comment cites a
//! file that is not in the repository.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use super::{read, relative, rust_files, workspace_root};

/// Where the docs list the model kinds: a line `Model kinds: `a`, `b`, …` in this file.
const KINDS_DOC: &str = "docs/ARCHITECTURE.md";
/// The line prefix of that list.
const KINDS_LINE: &str = "Model kinds:";
/// File extensions whose citations in docs and comments must resolve inside the repository.
const CITED_EXTENSIONS: &[&str] = &["md", "rs", "wgsl", "toml", "py"];
/// Data outside the repository that docs may name (never `docs/ARCHITECTURE.md`): the shared
/// papers and test images, which tests skip without.
const SHARED_PREFIX: &str = "../shared/";
/// What commands write (`target/reproduce/report.md`): named by docs, never in the repository.
const OUTPUT_PREFIX: &str = "target/";

#[test]
fn no_wildcard_arm_over_model_outside_the_model_crate() {
    let offences = wildcard_model_arms(&workspace_root());
    assert!(
        offences.is_empty(),
        "wildcard arms over `Model` hide kinds the compiler would otherwise point at; name \
         every kind (or dispatch through the layer's per-kind trait):\n  {}",
        offences.join("\n  ")
    );
}

#[test]
fn docs_list_exactly_the_model_kinds() {
    let offences = kind_list_offences(&workspace_root());
    assert!(offences.is_empty(), "{}", offences.join("\n"));
}

#[test]
fn docs_and_comments_cite_only_files_in_the_repository() {
    let offences = missing_citations(&workspace_root());
    assert!(
        offences.is_empty(),
        "docs or comments cite files that are not in the repository:\n  {}",
        offences.join("\n  ")
    );
}

// ---------------------------------------------------------------------------------------------
// Wildcard arms.

/// `file:line: pattern` for every catch-all arm (`_` or a lone binding) of a `match` one of whose
/// arms names `Model::`, in every `.rs` file of every crate but spectex-model.
pub(crate) fn wildcard_model_arms(root: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for dir in crate_dirs_except_model(root) {
        rust_files(&dir, &mut files);
    }
    files.sort();
    let mut offences = Vec::new();
    for file in files {
        let code = blank_comments_and_literals(&read(&file));
        for (offset, pattern) in wildcard_arms(&code) {
            let line = code[..offset].matches('\n').count() + 1;
            offences.push(format!(
                "{}:{line}: `{pattern} =>` in a match over Model",
                relative(root, &file)
            ));
        }
    }
    offences
}

fn crate_dirs_except_model(root: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(root.join("crates")) else {
        return Vec::new();
    };
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir() && !p.ends_with("spectex-model"))
        .collect();
    dirs.sort();
    dirs
}

/// The text with comments and string/char literal contents replaced by spaces (newlines kept),
/// so braces and `Model::` inside them are not code.
pub(crate) fn blank_comments_and_literals(text: &str) -> String {
    keep_only(text, Class::Code)
}

/// The comments of a source file (everything else blanked), line structure kept.
fn comments_only(text: &str) -> String {
    keep_only(text, Class::Comment)
}

/// What a character of Rust source is part of.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Class {
    Code,
    Comment,
    /// The inside of a string or char literal (its quotes are code).
    Literal,
}

/// `text` with every character not of class `keep` replaced by a space (newlines kept).
fn keep_only(text: &str, keep: Class) -> String {
    let chars: Vec<char> = text.chars().collect();
    classify_chars(&chars)
        .into_iter()
        .zip(&chars)
        .map(|(class, &c)| if class == keep || c == '\n' { c } else { ' ' })
        .collect()
}

/// The [`Class`] of every character: a small lexer for comments (nested block comments too),
/// strings, raw strings and char literals (told apart from lifetimes and labels).
fn classify_chars(chars: &[char]) -> Vec<Class> {
    let mut class = vec![Class::Code; chars.len()];
    let mut i = 0;
    let ident = |k: usize| {
        chars
            .get(k)
            .is_some_and(|p| p.is_alphanumeric() || *p == '_')
    };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                class[i] = Class::Comment;
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                let pair = (chars[i], chars.get(i + 1).copied());
                if pair == ('/', Some('*')) || pair == ('*', Some('/')) {
                    depth += if pair.0 == '/' { 1 } else { -1 };
                    class[i] = Class::Comment;
                    class[i + 1] = Class::Comment;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    class[i] = Class::Comment;
                    i += 1;
                }
            }
        } else if (c == 'r' || (c == 'b' && next == Some('r')))
            && !(i > 0 && ident(i - 1))
            && raw_string_hashes(chars, if c == 'b' { i + 2 } else { i + 1 }).is_some()
        {
            let start = if c == 'b' { i + 2 } else { i + 1 };
            let hashes = raw_string_hashes(chars, start).unwrap_or(0);
            i = start + hashes + 1;
            while i < chars.len()
                && !(chars[i] == '"' && (1..=hashes).all(|h| chars.get(i + h) == Some(&'#')))
            {
                class[i] = Class::Literal;
                i += 1;
            }
            i += hashes + 1;
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                let step = if chars[i] == '\\' { 2 } else { 1 };
                for k in i..(i + step).min(chars.len()) {
                    class[k] = Class::Literal;
                }
                i += step;
            }
            i += 1;
        } else if c == '\'' {
            // A char literal ('x', '\n', '\u{…}'), or a lifetime / label ('a) left as code.
            let end = if next == Some('\\') {
                (i + 3..chars.len().min(i + 12)).find(|&k| chars[k] == '\'')
            } else if chars.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match end {
                Some(end) => {
                    for k in i + 1..end {
                        class[k] = Class::Literal;
                    }
                    i = end + 1;
                }
                None => i += 1,
            }
        } else {
            i += 1;
        }
    }
    class
}

/// The number of `#` of a raw string whose `#`s start at `at` (then a `"`), or `None`.
fn raw_string_hashes(chars: &[char], at: usize) -> Option<usize> {
    let hashes = chars[at.min(chars.len())..]
        .iter()
        .take_while(|&&c| c == '#')
        .count();
    (chars.get(at + hashes) == Some(&'"')).then_some(hashes)
}

/// `(byte offset, pattern)` of every catch-all arm of every `match` over `Model` in `code`
/// (comments and literals already blanked).
pub(crate) fn wildcard_arms(code: &str) -> Vec<(usize, String)> {
    let bytes = code.as_bytes();
    let is_ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut found = Vec::new();
    let mut search = 0;
    while let Some(pos) = code[search..].find("match") {
        let at = search + pos;
        search = at + 5;
        let before_ok = at == 0 || !is_ident(bytes[at - 1]);
        let after_ok = bytes.get(at + 5).is_none_or(|&b| !is_ident(b));
        if !(before_ok && after_ok) {
            continue;
        }
        let Some(open) = code[at..].find('{').map(|k| at + k) else {
            continue;
        };
        let arms = match_arms(code, open);
        if !arms.iter().any(|(_, p)| names_model_variant(p)) {
            continue;
        }
        for (offset, pattern) in arms {
            let p = pattern.trim();
            let binding = !p.is_empty()
                && p.starts_with(|c: char| c.is_ascii_lowercase() || c == '_')
                && p.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if binding {
                found.push((offset, p.to_owned()));
            }
        }
    }
    found
}

/// Whether an arm pattern names a variant of `Model` (`Model::Lrp`, `spectex_model::Model::…`,
/// not `PhasorModel::…`).
fn names_model_variant(pattern: &str) -> bool {
    pattern.match_indices("Model::").any(|(k, _)| {
        k == 0 || {
            let b = pattern.as_bytes()[k - 1];
            !(b.is_ascii_alphanumeric() || b == b'_')
        }
    })
}

/// The `(offset, pattern)` of each arm of the match whose arm block opens at `open`.
fn match_arms(code: &str, open: usize) -> Vec<(usize, String)> {
    let bytes = code.as_bytes();
    let mut arms = Vec::new();
    let mut depth = 0i32;
    let mut start = open + 1;
    let mut i = open + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' => depth -= 1,
            b'}' => {
                if depth == 0 {
                    break;
                }
                depth -= 1;
            }
            b'=' if depth == 0 && bytes.get(i + 1) == Some(&b'>') => {
                arms.push((start, code[start..i].to_owned()));
                i = skip_arm_body(bytes, i + 2);
                start = i;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    arms
}

/// The index just past an arm body starting at `i` (after `=>`): a block and an optional comma,
/// or an expression up to the comma (or the closing brace) at depth 0.
fn skip_arm_body(bytes: &[u8], mut i: usize) -> usize {
    while bytes.get(i).is_some_and(u8::is_ascii_whitespace) {
        i += 1;
    }
    let mut depth = 0i32;
    let block = bytes.get(i) == Some(&b'{');
    while i < bytes.len() {
        match bytes[i] {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' => depth -= 1,
            b'}' => {
                if depth == 0 {
                    return i; // the match's own closing brace
                }
                depth -= 1;
                if block && depth == 0 {
                    i += 1;
                    while bytes.get(i).is_some_and(u8::is_ascii_whitespace) {
                        i += 1;
                    }
                    if bytes.get(i) == Some(&b',') {
                        i += 1;
                    }
                    return i;
                }
            }
            b',' if depth == 0 => return i + 1,
            _ => {}
        }
        i += 1;
    }
    i
}

// ---------------------------------------------------------------------------------------------
// The docs' list of kinds.

/// Differences between the kinds `Model` has (its variants, snake_case, as in model files), the
/// names the kinds declare (`const NAME`), and the list in [`KINDS_DOC`].
pub(crate) fn kind_list_offences(root: &Path) -> Vec<String> {
    let mut offences = Vec::new();
    let mut model_files = Vec::new();
    rust_files(&root.join("crates/spectex-model/src"), &mut model_files);
    let mut variants = BTreeSet::new();
    let mut names = BTreeSet::new();
    for file in &model_files {
        let code = read(file);
        if let Some(start) = code.find("pub enum Model {") {
            variants.extend(enum_variants(&code[start..]).into_iter().map(snake_case));
        }
        for line in code.lines() {
            if let Some(rest) = line.trim().strip_prefix("const NAME: &'static str = \"")
                && let Some(name) = rest.split('"').next()
            {
                names.insert(name.to_owned());
            }
        }
    }
    if variants.is_empty() {
        offences.push("no `pub enum Model {` found in crates/spectex-model/src".to_owned());
    }
    if variants != names {
        offences.push(format!(
            "Model's variants {variants:?} differ from the kinds' `const NAME`s {names:?}"
        ));
    }
    let doc_path = root.join(KINDS_DOC);
    let doc = std::fs::read_to_string(&doc_path).unwrap_or_default();
    match doc.lines().find(|l| l.starts_with(KINDS_LINE)) {
        None => offences.push(format!(
            "{KINDS_DOC} has no line starting with `{KINDS_LINE}` listing the kinds"
        )),
        Some(line) => {
            let listed: BTreeSet<String> = line
                .split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_owned)
                .collect();
            if listed != variants {
                offences.push(format!(
                    "{KINDS_DOC} lists the kinds {listed:?}; Model has {variants:?}"
                ));
            }
        }
    }
    offences
}

/// The variant names of the enum whose body starts in `code` (after `pub enum Model {`).
fn enum_variants(code: &str) -> Vec<String> {
    let blanked = blank_comments_and_literals(code);
    let Some(open) = blanked.find('{') else {
        return Vec::new();
    };
    let mut variants = Vec::new();
    let mut depth = 0;
    let mut token = String::new();
    for c in blanked[open + 1..].chars() {
        match c {
            '(' | '{' | '[' => {
                if depth == 0 && !token.is_empty() {
                    variants.push(std::mem::take(&mut token));
                }
                depth += 1;
            }
            ')' | ']' => depth -= 1,
            '}' if depth == 0 => break,
            '}' => depth -= 1,
            c if depth == 0 && (c.is_alphanumeric() || c == '_') => token.push(c),
            ',' if depth == 0 && !token.is_empty() => {
                variants.push(std::mem::take(&mut token));
            }
            _ if depth == 0 && !token.is_empty() && !token.starts_with(char::is_uppercase) => {
                token.clear();
            }
            _ => {}
        }
    }
    if !token.is_empty() {
        variants.push(token);
    }
    variants.retain(|v| v.starts_with(char::is_uppercase));
    variants
}

fn snake_case(name: String) -> String {
    let mut out = String::new();
    for (k, c) in name.chars().enumerate() {
        if c.is_uppercase() {
            if k > 0 {
                out.push('_');
            }
            out.extend(c.to_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Citations.

/// `file:line: cited` for every file name with a [`CITED_EXTENSIONS`] extension that a Markdown
/// file, or a comment of a `.rs`/`.wgsl` file, names and that is not in the repository.
pub(crate) fn missing_citations(root: &Path) -> Vec<String> {
    let mut sources = Vec::new();
    collect_files(root, root, &mut sources);
    let known: Vec<String> = sources.iter().map(|p| relative(root, p)).collect();
    let mut offences = Vec::new();
    for file in &sources {
        let ext = file.extension().and_then(|e| e.to_str()).unwrap_or("");
        let text = match ext {
            "md" => read(file),
            "rs" | "wgsl" => comments_only(&read(file)),
            _ => continue,
        };
        let rel = relative(root, file);
        let in_architecture = rel == KINDS_DOC;
        for (n, line) in text.lines().enumerate() {
            for cited in cited_files(line) {
                let ok = if let Some(rest) = cited.strip_prefix(SHARED_PREFIX) {
                    !in_architecture && !rest.is_empty()
                } else if let Some(rest) = cited.strip_prefix(OUTPUT_PREFIX) {
                    !rest.is_empty()
                } else {
                    resolves(&cited, file, root, &known)
                };
                if !ok {
                    offences.push(format!("{rel}:{}: {cited}", n + 1));
                }
            }
        }
    }
    offences
}

/// Every file of the repository (no `target/`, no hidden directories), recursively.
fn collect_files(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with('.') && name != ".ci" && name != ".cargo" {
            continue;
        }
        if path.is_dir() {
            if dir == root && name == "target" {
                continue;
            }
            collect_files(root, &path, out);
        } else {
            out.push(path);
        }
    }
}

/// The file names with a cited extension in `line` (a path, a `../shared/` path or a bare name);
/// URLs are skipped.
fn cited_files(line: &str) -> Vec<String> {
    let is_path_char = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-');
    let mut found = Vec::new();
    let words = line.split_whitespace().filter(|w| !w.contains("://"));
    for token in words.flat_map(|w| w.split(move |c: char| !is_path_char(c))) {
        let token = token.trim_end_matches(['.', '/']);
        let Some((stem, ext)) = token.rsplit_once('.') else {
            continue;
        };
        if !CITED_EXTENSIONS.contains(&ext)
            || stem.is_empty()
            || !stem.ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            || !token.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '.' || c == '_')
        {
            continue;
        }
        found.push(token.to_owned());
    }
    found
}

/// Whether `cited` (named in `from`) is a file of the repository: relative to the root, to the
/// citing file's folder, or as the tail of a known path (`lrp.rs`, `src/lrp.rs`).
fn resolves(cited: &str, from: &Path, root: &Path, known: &[String]) -> bool {
    let cited = cited.trim_start_matches("./");
    if root.join(cited).exists() || from.parent().is_some_and(|d| d.join(cited).exists()) {
        return true;
    }
    let tail = format!("/{cited}");
    known.iter().any(|k| k == cited || k.ends_with(&tail))
}

// ---------------------------------------------------------------------------------------------
// The checks on planted text: each must find what is planted and nothing else.

#[test]
fn wildcard_arms_are_found_and_exhaustive_matches_pass() {
    let planted = r#"
fn a(m: &Model) -> usize {
    match m {
        Model::Lrp(x) => 1, // a comment with _ => and { braces
        Model::Gabor(_) => { "string with } and _ =>"; 2 }
        _ => 3,
    }
}
fn b(m: &spectex_model::Model) -> u32 {
    match m { spectex_model::Model::Warp(w) => 0, other => 1 }
}
fn c(x: Option<u8>) -> u8 {
    match x { Some(v) => v, _ => 0 }
}
fn d(m: &Model) -> u8 {
    match m {
        Model::Lrp(_) | Model::Gabor(_) => match 3 { 3 => 1, _ => 2 },
        Model::Phasor(p) if p.seed == 1 => 4,
        Model::Phasor(_) => 5,
    }
}
fn e(p: &PhasorModel) -> u8 {
    match p { PhasorModel::A => 1, _ => 2 }
}
"#;
    let code = blank_comments_and_literals(planted);
    assert_eq!(code.len(), planted.len());
    let found: Vec<String> = wildcard_arms(&code).into_iter().map(|(_, p)| p).collect();
    assert_eq!(found, vec!["_".to_owned(), "other".to_owned()]);
}

#[test]
fn literals_and_comments_are_blanked_but_lifetimes_kept() {
    let text =
        "let c = '{'; let s = r#\"Model::X }\"#; /* a /* nested */ { */ fn f<'a>(x: &'a u8) {}";
    let code = blank_comments_and_literals(text);
    assert!(!code.contains("Model::"), "{code}");
    assert_eq!(code.matches('{').count(), 1, "{code}");
    assert!(code.contains("<'a>"), "{code}");
}

#[test]
fn citations_resolve_by_tail_and_missing_ones_are_reported() {
    assert_eq!(
        cited_files(
            "see DESIGN.md, `crates/a/src/lrp.rs` and https://x.org/y.md or ../shared/p.md."
        ),
        vec!["DESIGN.md", "crates/a/src/lrp.rs", "../shared/p.md"]
    );
    let root = workspace_root();
    let known = vec!["crates/a/src/lrp.rs".to_owned()];
    let from = root.join("README.md");
    assert!(resolves("lrp.rs", &from, &root, &known));
    assert!(resolves("src/lrp.rs", &from, &root, &known));
    assert!(!resolves("rp.rs", &from, &root, &known));
    assert!(!resolves("DESIGN.md", &from, &root, &known));
}

#[test]
fn enum_variants_become_file_tags() {
    let code = "pub enum Model {\n    /// Doc (with parens).\n    Lrp(LrpNoise),\n    #[serde(x)]\n    SpotNoise(Box<T>),\n}\n";
    let v: Vec<String> = enum_variants(code).into_iter().map(snake_case).collect();
    assert_eq!(v, vec!["lrp", "spot_noise"]);
}
