//! Every `spectex` command line in the README and the guide (`docs/guide/*.md`) parses with the
//! command's own argument parser: a renamed flag, a removed subcommand or a value its parser
//! refuses fails here instead of in a reader's terminal.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::{Path, PathBuf};

use clap::Parser;
use spectex_cli::Cli;

/// The README and the guide's pages.
fn documents() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = vec![root.join("README.md")];
    let mut guide: Vec<PathBuf> = std::fs::read_dir(root.join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    guide.sort();
    files.extend(guide);
    files
}

/// Splits a shell command into words: whitespace outside quotes separates, single and double
/// quotes group (the documents use nothing more).
fn words(command: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quote = None;
    let mut started = false;
    for c in command.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                started = true;
            }
            (None, c) if c.is_whitespace() => {
                if started || !word.is_empty() {
                    out.push(std::mem::take(&mut word));
                }
                started = false;
            }
            (None, c) => word.push(c),
        }
    }
    if started || !word.is_empty() {
        out.push(word);
    }
    out
}

/// The `spectex …` commands of the shell blocks of `text`, with their line numbers: continued
/// lines joined, comments dropped, commands split at `&&` and `;`, `cargo run --release --`
/// read as `spectex`, and a loop's `$k` taken as 0.
fn commands(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_shell = false;
    let mut pending: Option<(usize, String)> = None;
    for (n, line) in text.lines().enumerate() {
        if let Some(fence) = line.trim_start().strip_prefix("```") {
            in_shell = !in_shell && matches!(fence.trim(), "sh" | "bash" | "shell" | "console");
            continue;
        }
        if !in_shell {
            continue;
        }
        let line = match line.find(" # ") {
            Some(i) => &line[..i],
            None if line.trim_start().starts_with('#') => "",
            None => line,
        };
        let (start, mut joined) = pending.take().unwrap_or((n + 1, String::new()));
        joined.push_str(line.trim_end().trim_end_matches('\\'));
        joined.push(' ');
        if line.trim_end().ends_with('\\') {
            pending = Some((start, joined));
            continue;
        }
        for part in joined.split("&&").flat_map(|p| p.split(';')) {
            let part = part.trim().trim_start_matches("do ");
            let part = part.replace("$k", "0");
            if let Some(rest) = part.strip_prefix("cargo run --release -- ") {
                out.push((start, format!("spectex {rest}")));
            } else if part.starts_with("spectex ") {
                out.push((start, part.clone()));
            }
        }
    }
    out
}

#[test]
fn every_documented_command_line_parses() {
    let mut checked = 0;
    let mut failures = Vec::new();
    for file in documents() {
        let text = std::fs::read_to_string(&file).unwrap();
        for (line, command) in commands(&text) {
            checked += 1;
            if let Err(e) = Cli::try_parse_from(words(&command)) {
                let first = e.to_string();
                failures.push(format!(
                    "{}:{line}: `{command}`: {}",
                    file.display(),
                    first.lines().next().unwrap_or("")
                ));
            }
        }
    }
    println!("{checked} documented command lines parsed");
    assert!(
        checked >= 40,
        "only {checked} command lines found in the docs"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn shell_words_and_commands_are_read_as_a_shell_would() {
    assert_eq!(
        words(r#"spectex noise ramp --stops '0:2b1a0e' "a b" x"#),
        [
            "spectex", "noise", "ramp", "--stops", "0:2b1a0e", "a b", "x"
        ]
    );
    let text = "```sh\nspectex a -o x.png \\\n  --size 2x2   # why\nfor k in 1; do spectex b $k; done\ncargo run --release -- rpn -o o.png\n```\nspectex not-in-a-block\n";
    assert_eq!(
        commands(text),
        [
            (2, "spectex a -o x.png    --size 2x2".to_owned()),
            (4, "spectex b 0".to_owned()),
            (5, "spectex rpn -o o.png".to_owned())
        ]
    );
}
