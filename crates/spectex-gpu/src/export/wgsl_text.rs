//! Rewriting WGSL text: a kind's shader stripped of its bindings and compute entry points,
//! the names it declares at module scope, and identifiers replaced (prefixed names, storage
//! buffer accessors, struct members naga would rename).

use std::collections::{HashMap, HashSet};

/// `source` without its resource bindings (lines starting `@group(`, with the `///` doc lines
/// just above them) and without its compute entry points (from `@compute` to the closing
/// brace at the start of a line), its pipeline-overridable constants made constants of their
/// defaults (lines starting `override `: the module leaves nothing for its user's pipeline to
/// set).
pub(crate) fn strip(source: &str) -> String {
    let mut kept: Vec<std::borrow::Cow<'_, str>> = Vec::new();
    let mut in_entry = false;
    for line in source.lines() {
        if in_entry {
            if line.starts_with('}') {
                in_entry = false;
            }
            continue;
        }
        if line.starts_with("@compute") {
            in_entry = true;
            drop_doc_lines(&mut kept);
            continue;
        }
        if line.starts_with("@group(") {
            drop_doc_lines(&mut kept);
            continue;
        }
        match line.strip_prefix("override ") {
            Some(rest) => kept.push(format!("const {rest}").into()),
            None => kept.push(line.into()),
        }
    }
    let mut out = kept.join("\n");
    out.push('\n');
    out
}

/// Removes the `///` lines at the end of `kept` (the doc of a removed declaration).
fn drop_doc_lines(kept: &mut Vec<std::borrow::Cow<'_, str>>) {
    while kept.last().is_some_and(|l| l.starts_with("///")) {
        kept.pop();
    }
}

/// The names a WGSL source declares at module scope (declarations start a line).
pub(crate) fn top_level_names(source: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in source.lines() {
        let rest = ["fn ", "const ", "struct ", "alias ", "override "]
            .iter()
            .find_map(|k| line.strip_prefix(k))
            .or_else(|| {
                line.strip_prefix("var")
                    .map(|r| r.split_once('>').map_or(r, |(_, after)| after))
            });
        if let Some(rest) = rest {
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                names.push(name);
            }
        }
    }
    names
}

/// The identifiers `source` uses outside comments (names, keywords and types alike).
pub(crate) fn identifiers(source: &str) -> HashSet<String> {
    let mut names = HashSet::new();
    for line in source.lines() {
        let code = line.split_once("//").map_or(line, |(code, _)| code);
        let mut word = String::new();
        for c in code.chars().chain([' ']) {
            if c.is_ascii_alphanumeric() || c == '_' {
                word.push(c);
            } else if !word.is_empty() {
                if !word.starts_with(|d: char| d.is_ascii_digit()) {
                    names.insert(std::mem::take(&mut word));
                }
                word.clear();
            }
        }
    }
    names
}

/// `source` with every struct member name that naga's namer would change on writing the
/// module back (one ending in a digit or `_`, or holding `__`: `proc::Namer` appends `_`)
/// given a letter suffix, `_m`, everywhere it appears (member accesses too; comments are
/// left alone). Bevy composes a material's imports with naga_oil, which writes each module
/// back through naga and refuses one whose struct members come back renamed ("Composable module
/// identifiers must not require substitution"), as the compute shaders' `_pad0` and `a00`
/// would; top-level names are suffixed by naga_oil itself and need nothing. Renaming an
/// identifier everywhere is a pure renaming: no value changes.
pub(super) fn composable_members(source: &str) -> String {
    let unsafe_name =
        |n: &str| n.ends_with(|c: char| c.is_ascii_digit() || c == '_') || n.contains("__");
    let mut map: HashMap<String, String> = HashMap::new();
    let mut in_struct = false;
    for line in source.lines() {
        let line = line.trim();
        if line.starts_with("struct ") {
            in_struct = true;
        } else if in_struct && line.starts_with('}') {
            in_struct = false;
        } else if in_struct {
            // A member line is `[@attr(..) ]name: type,`: the identifier before `:`.
            let code = line.split_once("//").map_or(line, |(code, _)| code);
            let decl = code
                .rsplit_once(')')
                .map_or(code, |(_, after)| after.trim());
            if let Some((field, _)) = decl.split_once(':') {
                let field = field.trim();
                if !field.is_empty()
                    && field.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                    && unsafe_name(field)
                {
                    map.insert(
                        field.to_owned(),
                        format!("{}_m", field.trim_end_matches('_')),
                    );
                }
            }
        }
    }
    if map.is_empty() {
        return source.to_owned();
    }
    replace_identifiers(source, &map, &HashSet::new(), true)
}

/// `source` with every identifier in `map` replaced, except member names: after a `.`, and
/// field declarations (an identifier followed by `:` inside a struct's braces); and every
/// indexing `name[i]` of a name in `calls` (tables in the storage buffer) turned into the
/// call `name(u32(i))` of its accessor. Comments are copied unchanged.
pub(crate) fn rename(
    source: &str,
    map: &HashMap<String, String>,
    calls: &HashSet<String>,
) -> String {
    replace_identifiers(source, map, calls, false)
}

/// [`rename`], member names included where `members` (accesses after a `.` and field
/// declarations are then replaced too).
fn replace_identifiers(
    source: &str,
    map: &HashMap<String, String>,
    calls: &HashSet<String>,
    members: bool,
) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len() + source.len() / 4);
    let mut i = 0;
    let mut depth = 0usize;
    let mut struct_depth: Option<usize> = None;
    let mut pending_struct = false;
    let mut last_significant = ' ';
    // Per open `[`: whether it opened an accessor call (closed by `))`).
    let mut brackets: Vec<bool> = Vec::new();
    let mut call_pending = false;
    while i < chars.len() {
        let c = chars[i];
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                out.push(chars[i]);
                i += 1;
            }
            continue;
        }
        if c == '/' && chars.get(i + 1) == Some(&'*') {
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                out.push(chars[i]);
                i += 1;
            }
            out.push_str("*/");
            i += 2;
            continue;
        }
        if c.is_ascii_digit() {
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric() || matches!(chars[i], '_' | '.'))
            {
                out.push(chars[i]);
                i += 1;
            }
            last_significant = '0';
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let mut j = i;
            while j < chars.len() && chars[j].is_whitespace() {
                j += 1;
            }
            let is_field = struct_depth == Some(depth)
                && chars.get(j) == Some(&':')
                && chars.get(j + 1) != Some(&':');
            if word == "struct" {
                pending_struct = true;
            }
            match map.get(&word) {
                Some(new) if members || (last_significant != '.' && !is_field) => {
                    out.push_str(new);
                }
                _ => out.push_str(&word),
            }
            call_pending =
                last_significant != '.' && calls.contains(&word) && chars.get(j) == Some(&'[');
            last_significant = 'a';
            continue;
        }
        match c {
            '[' if call_pending => {
                brackets.push(true);
                // Drop the blanks between the name and the bracket.
                while out.ends_with(char::is_whitespace) {
                    out.pop();
                }
                out.push_str("(u32(");
                call_pending = false;
                last_significant = '(';
                i += 1;
                continue;
            }
            '[' => brackets.push(false),
            ']' if brackets.last() == Some(&true) => {
                brackets.pop();
                out.push_str("))");
                last_significant = ')';
                i += 1;
                continue;
            }
            ']' => {
                brackets.pop();
            }
            '{' => {
                depth += 1;
                if pending_struct {
                    struct_depth = Some(depth);
                    pending_struct = false;
                }
            }
            '}' => {
                if struct_depth == Some(depth) {
                    struct_depth = None;
                }
                depth = depth.saturating_sub(1);
            }
            _ => {}
        }
        if !c.is_whitespace() {
            last_significant = c;
        }
        out.push(c);
        i += 1;
    }
    out
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn members_naga_would_rename_get_a_letter_suffix_everywhere() {
        let src = "struct P {\n    a00: f32,\n    @align(16) _pad0: u32,\n    key: u32, // key2\n}\n\
                   fn f(p: P) -> f32 { let a00 = p.a00; return a00 + f32(p.key); } // a00\n";
        assert_eq!(
            composable_members(src),
            "struct P {\n    a00_m: f32,\n    @align(16) _pad0_m: u32,\n    key: u32, // key2\n}\n\
             fn f(p: P) -> f32 { let a00_m = p.a00_m; return a00_m + f32(p.key); } // a00\n"
        );
    }

    pub fn rename_skips_members_fields_and_comments() {
        let map: HashMap<String, String> = [("strata", "p_strata"), ("S", "p_S")]
            .map(|(a, b)| (a.to_owned(), b.to_owned()))
            .into();
        let src = "struct S {\n    strata: u32,\n    s: S,\n}\n// strata\nfn f() { let a = strata[params.strata]; }\n";
        let out = rename(src, &map, &HashSet::new());
        assert_eq!(
            out,
            "struct p_S {\n    strata: u32,\n    s: p_S,\n}\n// strata\nfn f() { let a = p_strata[params.strata]; }\n"
        );
    }

    pub fn rename_turns_buffer_tables_into_accessor_calls() {
        let map: HashMap<String, String> = [("t", "p_t"), ("u", "p_u")]
            .map(|(a, b)| (a.to_owned(), b.to_owned()))
            .into();
        let calls: HashSet<String> = ["t".to_owned()].into();
        let src = "let a = t [u[i] + t[j].x] + s.t[2];\nfn t(i: u32) {}\n";
        assert_eq!(
            rename(src, &map, &calls),
            "let a = p_t(u32(p_u[i] + p_t(u32(j)).x)) + s.t[2];\nfn p_t(i: u32) {}\n"
        );
    }

    pub fn strip_removes_bindings_and_entry_points() {
        let src = "const A: u32 = 1u;\n/// doc\n@group(0) @binding(0) var<uniform> p: P;\n@compute @workgroup_size(8, 8, 1)\nfn main() {\n    let x = 1;\n}\nfn g() {}\noverride B: u32 = 7u;\n";
        assert_eq!(
            strip(src),
            "const A: u32 = 1u;\nfn g() {}\nconst B: u32 = 7u;\n"
        );
        assert_eq!(
            top_level_names("fn a(x: u32) {}\nconst B = 1;\nvar<private> c: u32;\nstruct D {}\n"),
            ["a", "B", "c", "D"]
        );
        let mut seen: Vec<String> = identifiers("let x = f(y2, 3u); // g(z)\nh[0]")
            .into_iter()
            .collect();
        seen.sort();
        assert_eq!(seen, ["f", "h", "let", "x", "y2"]);
    }
}
