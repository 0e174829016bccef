//! Every command line of the README and the guide (`docs/guide/*.md`) runs here, so the docs
//! cannot rot: a renamed flag, a removed subcommand, a value a command refuses or a file a page
//! uses but never makes fails this test instead of a reader.
//!
//! The lines of a page run in order in one scratch directory, so a line's outputs are the next
//! lines' inputs. `spectex …` lines run in-process through [`spectex_cli::run`] (no process per
//! line), after the rewrites of [`REWRITES`], which make them cheap and keep them off the
//! network, the desktop and the environment; the inputs a page names but does not make come
//! from [`INPUTS`]. `spectex view` runs as a process that is asked for its state and stopped,
//! `mkdir -p` runs, and an `sbatch` array runs as its tasks. Every other shell line must match
//! [`NOT_RUN`], which says why it is not run: a line that neither runs nor has a reason fails
//! the test, and so does an entry of these lists that no line uses, so that they stay true.
//!
//! The commands run in this process install the command's SIGINT/SIGTERM watch in it: a first
//! Ctrl-C during this test stops its render with an error, a second ends the process.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use clap::{Arg, CommandFactory, Parser};
use spectex_cli::Cli;

use crate::common::scratch;

/// The side, pixels, of everything the test renders: documented sizes above it are capped.
const SIDE: usize = 64;

/// How the test changes a documented `spectex` line before running it: name, reason.
const REWRITES: &[(&str, &str)] = &[
    (
        "cargo-run",
        "`cargo run --release -- ARGS` is `spectex ARGS`, as built from this checkout",
    ),
    (
        "paths",
        "a relative path is in the page's scratch directory, `testdata/…` in the repository \
         (the docs are read from the repository's root)",
    ),
    (
        "textures",
        "`../shared/testdata/textures/NAME`, the project's photographs, is outside the \
         repository and absent in CI: a 64² grey image of that name made from the built-in \
         exemplar stands in (a `*` there matches one such image)",
    ),
    (
        "size",
        "`--size` above 64 per side is capped at 64: a 2048² or 32768² render costs seconds \
         to minutes, and a size does not rot where a flag or a file does",
    ),
    (
        "default-size",
        "a command with `--size` that gives none gets 64x64 (its default is 256² or 512², and \
         65 such layers for `slices`), except rpn and synth, whose default is their input's \
         size (64² here)",
    ),
    (
        "no-gpu",
        "without a GPU adapter `--device gpu` is `--device cpu` and `--gpu` is dropped \
         (SPECTEX_REQUIRE_GPU=1 makes a missing adapter a failure instead)",
    ),
    (
        "view",
        "`spectex view` serves until stopped: it runs as a process on 127.0.0.1 (`--host`) \
         and a free port (`--port 0`), without `--open` (a browser on the desktop), must \
         answer GET /api/state, and is stopped",
    ),
    (
        "target",
        "an output under `target/` has that folder made first: a reader who built spectex \
         from this checkout has it, the page's scratch directory does not",
    ),
    (
        "sbatch",
        "`sbatch --array=A-B SCRIPT ARGS` runs the script's `mkdir -p` and `spectex` lines \
         once per task A to B, the task's index given as `--tile-index` rather than in \
         SLURM_ARRAY_TASK_ID (the environment is this process's, shared with the tests beside)",
    ),
];

/// What stands in for an input that a page names but does not make.
#[derive(Debug, Clone, Copy)]
enum Input {
    /// A 64² grey crop of the built-in exemplar, in the format of the file's extension.
    Image,
    /// A copy of this file of `testdata/models/`.
    Model(&'static str),
    /// What this `spectex` command (arguments after `spectex`) writes, run in the directory.
    Spectex(&'static str),
}

/// Inputs named in the docs and made by none of their page's lines: file name, what stands in,
/// why the page does not make it.
const INPUTS: &[(&str, Input, &str)] = &[
    ("gravel.png", Input::Image, "the reader's exemplar"),
    ("photo.png", Input::Image, "the reader's photograph"),
    ("grey.png", Input::Image, "the reader's grey control image"),
    ("sample.jpg", Input::Image, "the reader's sample"),
    (
        "model.json",
        Input::Model("classic-perlin-fbm.json"),
        "the reader's model file",
    ),
    (
        "ring.json",
        Input::Model("lrp-ring.json"),
        "an LRP ring's model, as `spectex noise ring --model` writes it",
    ),
    (
        "gabor.json",
        Input::Model("gabor-isotropic.json"),
        "written on another page (fit.md's `spectex noise gabor … --model gabor.json`)",
    ),
    (
        "gs.json",
        Input::Spectex(
            "simulate gray-scott --size 16x16 --steps 5 -o gs.png --save-params gs.json",
        ),
        "a simulation's parameters, as `spectex simulate … --save-params` writes them",
    ),
];

/// A check of what a line that is not run names, in the repository at the given root.
type Check = fn(&str, &Path) -> Result<(), String>;

/// Shell lines that are not run, by how they start: the reason, and what is checked instead.
const NOT_RUN: &[(&str, &str, Check)] = &[
    (
        "cargo xtask ",
        "the project's own tasks (CI, the papers' reproductions) take minutes; CI is \
         `cargo xtask ci` itself",
        |_, _| Ok(()),
    ),
    (
        "cargo run --example ",
        "a numbered example: `cargo xtask ci` runs every one (checked here: it exists)",
        example_exists,
    ),
    (
        "pip install ",
        "builds the Python wheel (minutes): `cargo xtask ci` builds the same module and runs \
         its pytest suite (checked here: the package exists)",
        package_exists,
    ),
    (
        "MATURIN_PEP517_ARGS=",
        "builds the CPU-only Python wheel (minutes): as `pip install` (checked here: the \
         package exists)",
        package_exists,
    ),
];

/// `cargo run --example NAME`: the CLI crate has that example's source file.
fn example_exists(command: &str, repo: &Path) -> Result<(), String> {
    let name = words(command)
        .into_iter()
        .skip_while(|w| w != "--example")
        .nth(1)
        .ok_or("no example name")?;
    let file = repo.join(format!("crates/spectex-cli/examples/{name}.rs"));
    file.exists()
        .then_some(())
        .ok_or_else(|| format!("there is no example {name} ({})", file.display()))
}

/// `pip install ./DIR`: `DIR` holds a `pyproject.toml`.
fn package_exists(command: &str, repo: &Path) -> Result<(), String> {
    let dir = words(command)
        .into_iter()
        .find(|w| w.starts_with("./"))
        .ok_or("no ./ path to install")?;
    let file = repo.join(&dir).join("pyproject.toml");
    file.exists()
        .then_some(())
        .ok_or_else(|| format!("{dir} is not a Python package ({})", file.display()))
}

/// The repository's root.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// The README and the guide's pages.
fn documents() -> Vec<PathBuf> {
    let root = repo();
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

/// The commands of the shell blocks of `text`, with their line numbers: continued lines
/// joined, comments dropped, a `for V in $(seq A B); do …; done` loop unrolled, and commands
/// split at `&&` and `;`.
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
        out.extend(split_commands(&joined).into_iter().map(|c| (start, c)));
    }
    out
}

/// One shell line as its commands: a `for V in $(seq A B); do BODY; done` loop as BODY once
/// for each V, otherwise the line split at `&&` and `;`.
fn split_commands(line: &str) -> Vec<String> {
    if let Some(unrolled) = seq_loop(line) {
        return unrolled;
    }
    line.split("&&")
        .flat_map(|p| p.split(';'))
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(str::to_owned)
        .collect()
}

/// `for V in $(seq A B); do BODY; done` unrolled, or `None` for another line.
fn seq_loop(line: &str) -> Option<Vec<String>> {
    let rest = line.trim().strip_prefix("for ")?;
    let (var, rest) = rest.split_once(" in $(seq ")?;
    let (range, rest) = rest.split_once(')')?;
    let (a, b) = range.trim().split_once(' ')?;
    let (a, b): (u32, u32) = (a.parse().ok()?, b.trim().parse().ok()?);
    let body = rest.trim().strip_prefix(';')?.trim().strip_prefix("do ")?;
    let body = body.trim().strip_suffix("done")?.trim().strip_suffix(';')?;
    Some(
        (a..=b)
            .flat_map(|k| {
                let k = k.to_string();
                split_commands(
                    &body
                        .replace(&format!("${{{var}}}"), &k)
                        .replace(&format!("${var}"), &k),
                )
            })
            .collect(),
    )
}

/// Where a page's lines run, and what the run has used so far.
struct Page {
    /// The page's scratch directory (the lines' working directory).
    dir: PathBuf,
    repo: PathBuf,
    /// Whether a GPU adapter is there.
    gpu: bool,
    /// The rewrites, inputs and not-run rules used, by name.
    used: BTreeSet<&'static str>,
    /// Those the current line used.
    line: BTreeSet<&'static str>,
}

/// A `spectex` line's words after the rewrites, and the files or directories it must write.
struct Rewritten {
    words: Vec<String>,
    outputs: Vec<PathBuf>,
}

/// What [`Reader`] read: a word the command does not define (left to its parser), a flag
/// without a value, or an argument's value (after its flag, if any).
enum Read<'a> {
    Word(String),
    Switch(String),
    Value(&'a Arg, Option<String>, String),
}

/// Reads a command's words after its subcommands with the command's own definitions, as its
/// parser would: a flag's value, a positional argument.
struct Reader<'a> {
    cmd: &'a clap::Command,
    words: &'a [String],
    next: usize,
    /// The next positional argument.
    positional: usize,
}

impl<'a> Reader<'a> {
    fn next(&mut self) -> Option<Read<'a>> {
        let word = self.words.get(self.next)?.clone();
        self.next += 1;
        let found = if let Some(long) = word.strip_prefix("--") {
            let (flag, inline) = match long.split_once('=') {
                Some((f, v)) => (f, Some(v.to_owned())),
                None => (long, None),
            };
            self.cmd
                .get_arguments()
                .find(|a| a.get_long() == Some(flag))
                .map(|a| (a, format!("--{flag}"), inline))
        } else if word.len() == 2 && word.starts_with('-') {
            let short = word.chars().nth(1);
            self.cmd
                .get_arguments()
                .find(|a| a.get_short() == short)
                .map(|a| (a, word.clone(), None))
        } else {
            let positionals: Vec<&Arg> = self.cmd.get_positionals().collect();
            let Some(arg) = positionals.get(self.positional).or(positionals.last()) else {
                return Some(Read::Word(word));
            };
            if !matches!(arg.get_action(), clap::ArgAction::Append) {
                self.positional += 1;
            }
            return Some(Read::Value(arg, None, word));
        };
        let Some((arg, flag, inline)) = found else {
            return Some(Read::Word(word));
        };
        if !arg.get_action().takes_values() {
            return Some(Read::Switch(flag));
        }
        // `--periodic [WxH]`: a value that may be left out is not taken from the next flag.
        let optional = arg.get_num_args().is_some_and(|r| r.min_values() == 0);
        let value = match inline {
            Some(v) => v,
            None => match self.words.get(self.next) {
                Some(v) if !(optional && v.starts_with('-')) => {
                    self.next += 1;
                    v.clone()
                }
                _ => return Some(Read::Switch(flag)),
            },
        };
        Some(Read::Value(arg, Some(flag), value))
    }
}

/// The flags whose paths a command writes (it reads the other paths).
const OUTPUT_FLAGS: &[&str] = &["output", "model", "wgsl", "save-params", "frames"];

impl Page {
    /// Records that the current line used `rule`.
    fn note(&mut self, rule: &'static str) {
        self.used.insert(rule);
        self.line.insert(rule);
    }

    /// The words of the `spectex` command `words` after the rewrites of [`REWRITES`], read
    /// with the command's own argument definitions: which words are paths (read or written),
    /// sizes, devices.
    fn rewrite(&mut self, words: &[String]) -> Result<Rewritten, String> {
        let mut root = Cli::command();
        root.build();
        let mut cmd = &root;
        let mut out = vec![words[0].clone()];
        let mut i = 1;
        while let Some(sub) = words.get(i).and_then(|w| cmd.find_subcommand(w)) {
            cmd = sub;
            out.push(words[i].clone());
            i += 1;
        }
        let name = out[1..].join(" ");
        let view = name == "view";
        let mut reader = Reader {
            cmd,
            words,
            next: i,
            positional: 0,
        };
        let mut outputs = Vec::new();
        let mut sized = false;
        while let Some(read) = reader.next() {
            let (arg, flag, value) = match read {
                Read::Word(word) => {
                    out.push(word);
                    continue;
                }
                Read::Switch(flag) => {
                    if view && flag == "--open" {
                        self.note("view");
                    } else if flag == "--gpu" && !self.gpu {
                        self.note("no-gpu");
                    } else {
                        out.push(flag);
                    }
                    continue;
                }
                Read::Value(arg, flag, value) => (arg, flag, value),
            };
            let long = arg.get_long().unwrap_or("");
            let values = if long == "size" {
                sized = true;
                vec![self.capped(&value)?]
            } else if long == "device" && value == "gpu" && !self.gpu {
                self.note("no-gpu");
                vec!["cpu".to_owned()]
            } else if view && long == "port" {
                self.note("view");
                continue;
            } else if view && long == "host" {
                self.note("view");
                vec!["127.0.0.1".to_owned()]
            } else if arg.get_value_parser().type_id() == std::any::TypeId::of::<PathBuf>() {
                let output = OUTPUT_FLAGS.contains(&long);
                let paths = self.path(&value, output)?;
                if output {
                    outputs.extend(paths.iter().cloned());
                }
                paths
                    .iter()
                    .map(|p| p.to_str().unwrap().to_owned())
                    .collect()
            } else {
                vec![value]
            };
            out.extend(flag);
            out.extend(values);
        }
        let has_size = cmd.get_arguments().any(|a| a.get_long() == Some("size"));
        if has_size && !sized && !matches!(name.as_str(), "rpn" | "synth") {
            self.note("default-size");
            out.extend(["--size".to_owned(), format!("{SIDE}x{SIDE}")]);
        }
        if view {
            self.note("view");
            out.extend(["--port".to_owned(), "0".to_owned()]);
        }
        Ok(Rewritten {
            words: out,
            outputs,
        })
    }

    /// A `--size WxH` capped at [`SIDE`] per side.
    fn capped(&mut self, size: &str) -> Result<String, String> {
        let (w, h) = spectex_cli::args::parse_size(size)?;
        if w <= SIDE && h <= SIDE {
            return Ok(size.to_owned());
        }
        self.note("size");
        Ok(format!("{}x{}", w.min(SIDE), h.min(SIDE)))
    }

    /// The files a path argument names, as a shell in the repository's root would see them:
    /// in the page's directory, `testdata/` in the repository, the shared photographs by
    /// stand-ins, an input of [`INPUTS`] put there first, a `*` matched.
    fn path(&mut self, value: &str, output: bool) -> Result<Vec<PathBuf>, String> {
        if let Some(name) = value.strip_prefix("../shared/testdata/textures/") {
            self.note("textures");
            let dir = self.dir.join("textures");
            std::fs::create_dir_all(&dir).unwrap();
            let pattern = dir.join(name);
            if !pattern.exists() && glob(&pattern) == [pattern.clone()] {
                stand_in_image(&dir.join(name.replace('*', "exemplar")));
            }
            return Ok(glob(&pattern));
        }
        let path = if value.starts_with("testdata/") {
            self.repo.join(value)
        } else if Path::new(value).is_absolute() {
            PathBuf::from(value)
        } else {
            self.note("paths");
            self.dir.join(value)
        };
        if output && value.starts_with("target/") {
            self.note("target");
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        }
        let stand_in = INPUTS.iter().find(|(name, ..)| *name == value);
        if let Some(&(name, input, _)) = stand_in.filter(|_| !output && !path.exists()) {
            self.provide(input, &path)?;
            self.note(name);
        }
        Ok(glob(&path))
    }

    /// Makes `input` at `path`.
    fn provide(&mut self, input: Input, path: &Path) -> Result<(), String> {
        match input {
            Input::Image => stand_in_image(path),
            Input::Model(file) => {
                std::fs::copy(self.repo.join("testdata/models").join(file), path).unwrap();
            }
            Input::Spectex(args) => {
                let words: Vec<String> = std::iter::once("spectex".to_owned())
                    .chain(words(args))
                    .collect();
                let rewritten = self.rewrite(&words)?;
                run_in_process(&rewritten)?;
            }
        }
        Ok(())
    }

    /// Runs one documented command; what was done, for the log.
    fn run(&mut self, command: &str) -> Result<String, String> {
        if let Some(rest) = command.strip_prefix("cargo run --release -- ") {
            self.note("cargo-run");
            return self.spectex(&words(&format!("spectex {rest}")));
        }
        if command.starts_with("spectex ") || command == "spectex" {
            return self.spectex(&words(command));
        }
        if let Some(dirs) = command.strip_prefix("mkdir -p ") {
            for dir in words(dirs) {
                std::fs::create_dir_all(self.dir.join(dir)).unwrap();
            }
            return Ok("made".to_owned());
        }
        if command.starts_with("sbatch ") {
            return self.sbatch(command);
        }
        for &(start, reason, check) in NOT_RUN {
            if command.starts_with(start) {
                self.note(start);
                check(command, &self.repo)?;
                return Ok(format!("not run: {reason}"));
            }
        }
        Err(
            "no rule runs this line or says why not: make it a `spectex` line, or add its \
             start to NOT_RUN with the reason"
                .to_owned(),
        )
    }

    /// A `spectex` command, rewritten and run.
    fn spectex(&mut self, words: &[String]) -> Result<String, String> {
        let rewritten = self.rewrite(words)?;
        if rewritten.words.get(1).is_some_and(|w| w == "view") {
            return serve(&rewritten.words);
        }
        run_in_process(&rewritten)?;
        Ok(rewritten.words.join(" "))
    }

    /// `sbatch --array=A-B SCRIPT ARGS`: the script's `mkdir -p` and `spectex` lines once per
    /// task (its variables expanded: `${N:-D}` as D, `${1:?…}` as the first argument), each
    /// `spectex` line given the task's index as `--tile-index`.
    fn sbatch(&mut self, command: &str) -> Result<String, String> {
        self.note("sbatch");
        let w = words(command);
        let (a, b) = w
            .get(1)
            .and_then(|a| a.strip_prefix("--array="))
            .and_then(|r| r.split_once('-'))
            .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
            .ok_or("an sbatch line takes --array=A-B first")?;
        let script = w.get(2).ok_or("an sbatch line names its script")?;
        let text = std::fs::read_to_string(self.repo.join(script))
            .map_err(|e| format!("{script}: {e}"))?;
        let mut vars: BTreeMap<String, String> = BTreeMap::new();
        let mut lines = Vec::new();
        for (_, line) in commands(&format!("```sh\n{text}\n```")) {
            if line.starts_with("set ") || line.starts_with("export ") {
                continue; // shell options and the thread count: nothing to run
            }
            if let Some((name, value)) = assignment(&line) {
                let value = match value.strip_prefix("${").and_then(|v| v.strip_suffix('}')) {
                    Some(inner) if inner.starts_with("1:?") => w
                        .get(3)
                        .cloned()
                        .ok_or_else(|| format!("{script} needs an argument"))?,
                    Some(inner) => inner
                        .split_once(":-")
                        .map(|(_, d)| d.to_owned())
                        .ok_or_else(|| format!("{script}: cannot read `{line}`"))?,
                    None => value,
                };
                vars.insert(name, value);
            } else if line.starts_with("mkdir -p ") || line.starts_with("spectex ") {
                lines.push(line);
            } else {
                return Err(format!("{script}: no rule runs `{line}`"));
            }
        }
        let mut ran = 0;
        for task in a..=b {
            vars.insert("SLURM_ARRAY_TASK_ID".to_owned(), task.to_string());
            for line in &lines {
                let line = expand(line, &vars);
                if line.starts_with("spectex ") {
                    let mut words = words(&line);
                    words.extend(["--tile-index".to_owned(), task.to_string()]);
                    self.spectex(&words)?;
                    ran += 1;
                } else {
                    self.run(&line)?;
                }
            }
        }
        Ok(format!("{ran} array tasks of {script}"))
    }
}

/// `NAME=VALUE` (quotes removed), or `None`.
fn assignment(line: &str) -> Option<(String, String)> {
    let (name, value) = line.split_once('=')?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_uppercase() || c == '_') {
        return None;
    }
    Some((name.to_owned(), words(value).concat()))
}

/// `line` with `${NAME}` and `$NAME` replaced by `vars` (longer names first).
fn expand(line: &str, vars: &BTreeMap<String, String>) -> String {
    let mut names: Vec<&String> = vars.keys().collect();
    names.sort_by_key(|n| std::cmp::Reverse(n.len()));
    let mut out = line.to_owned();
    for name in names {
        out = out
            .replace(&format!("${{{name}}}"), &vars[name])
            .replace(&format!("${name}"), &vars[name]);
    }
    out
}

/// The files matching `path`, whose file name may hold one `*`, sorted; the pattern itself when
/// none does (as a shell leaves it).
fn glob(path: &Path) -> Vec<PathBuf> {
    let name = path.file_name().unwrap().to_str().unwrap();
    let Some((head, tail)) = name.split_once('*') else {
        return vec![path.to_owned()];
    };
    let dir = path.parent().unwrap();
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .map(|e| e.unwrap().path())
                .filter(|p| {
                    let n = p.file_name().unwrap().to_str().unwrap();
                    n.len() >= head.len() + tail.len() && n.starts_with(head) && n.ends_with(tail)
                })
                .collect()
        })
        .unwrap_or_default();
    found.sort();
    if found.is_empty() {
        vec![path.to_owned()]
    } else {
        found
    }
}

/// A 64² grey crop of the built-in exemplar at `path`, in its extension's format.
fn stand_in_image(path: &Path) {
    let exemplar =
        spectex_testkit::image_files::open(repo().join("crates/spectex-cli/default_exemplar.png"))
            .unwrap();
    let crop = exemplar
        .crop_imm(0, 0, SIDE as u32, SIDE as u32)
        .into_luma8();
    spectex_testkit::image_files::save(&image::DynamicImage::from(crop), path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

/// Parses and runs a rewritten command in this process; every output it names must exist
/// afterwards.
fn run_in_process(command: &Rewritten) -> Result<(), String> {
    let cli = Cli::try_parse_from(&command.words).map_err(|e| {
        let text = e.to_string();
        text.lines().next().unwrap_or("").to_owned()
    })?;
    spectex_cli::run(cli).map_err(|e| format!("error: {e:#}"))?;
    match command.outputs.iter().find(|p| !p.exists()) {
        Some(missing) => Err(format!("ran, but wrote no {}", missing.display())),
        None => Ok(()),
    }
}

/// Runs `spectex view` (rewritten words) as a process, asks it for `/api/state` and stops it.
fn serve(words: &[String]) -> Result<String, String> {
    let mut command = Command::new(env!("CARGO_BIN_EXE_spectex"));
    command.args(&words[1..]).stderr(Stdio::piped());
    let (mut child, addr) = crate::view::spawn_view(command);
    let answer = addr
        .as_deref()
        .map(|a| crate::view::request(a, "GET", "/api/state", None));
    let _ = child.kill();
    let out = child.wait_with_output().unwrap();
    match answer {
        Some((200, _)) => Ok(format!("{} (served, answered, stopped)", words.join(" "))),
        Some((status, body)) => Err(format!(
            "GET /api/state answered {status}: {}",
            String::from_utf8_lossy(&body)
        )),
        None => Err(format!(
            "did not serve: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )),
    }
}

#[test]
fn every_documented_command_line_runs() {
    let repo = repo();
    let gpu = match spectex_gpu::GpuContext::new() {
        Ok(_) => true,
        Err(e) => {
            assert!(
                !std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1"),
                "SPECTEX_REQUIRE_GPU=1 but no GPU: {e}"
            );
            false
        }
    };
    let mut used = BTreeSet::new();
    let mut failures = Vec::new();
    let mut spectex_lines = 0;
    let start = Instant::now();
    for file in documents() {
        let name = file.strip_prefix(&repo).unwrap().display().to_string();
        let mut page = Page {
            dir: scratch(&format!("docs-{}", name.replace(['/', '.'], "-"))),
            repo: repo.clone(),
            gpu,
            used: BTreeSet::new(),
            line: BTreeSet::new(),
        };
        let text = std::fs::read_to_string(&file).unwrap();
        for (line, command) in commands(&text) {
            let t = Instant::now();
            spectex_lines += usize::from(
                command.starts_with("spectex") || command.starts_with("cargo run --release"),
            );
            page.line.clear();
            let result = page.run(&command);
            let seconds = t.elapsed().as_secs_f64();
            let rules: Vec<&str> = page.line.iter().copied().collect();
            match result {
                Ok(done) => {
                    println!("{name}:{line} ({seconds:.2} s) `{command}` {rules:?}: {done}")
                }
                Err(e) => failures.push(format!("{name}:{line}: `{command}`: {e}")),
            }
        }
        used.extend(page.used);
    }
    println!(
        "{spectex_lines} documented spectex lines in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert!(
        spectex_lines >= 40,
        "only {spectex_lines} spectex lines found in the docs"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let rules = REWRITES.iter().map(|r| r.0);
    let rules = rules
        .chain(INPUTS.iter().map(|i| i.0))
        .chain(NOT_RUN.iter().map(|n| n.0));
    // With an adapter, nothing is rewritten for the lack of one.
    let unused: Vec<&str> = rules
        .filter(|r| !(used.contains(r) || gpu && *r == "no-gpu"))
        .collect();
    assert!(
        unused.is_empty(),
        "rules that no documented line uses any more (remove them): {unused:?}"
    );
}

#[test]
fn shell_words_and_commands_are_read_as_a_shell_would() {
    assert_eq!(
        words(r#"spectex noise ramp --stops '0:2b1a0e' "a b" x"#),
        [
            "spectex", "noise", "ramp", "--stops", "0:2b1a0e", "a b", "x"
        ]
    );
    let text = "```sh\nspectex a -o x.png \\\n  --size 2x2   # why\nfor k in $(seq 1 2); do spectex b $k; done\nmkdir -p t && cargo run --release -- rpn -o o.png\n```\nspectex not-in-a-block\n";
    assert_eq!(
        commands(text),
        [
            (2, "spectex a -o x.png    --size 2x2".to_owned()),
            (4, "spectex b 1".to_owned()),
            (4, "spectex b 2".to_owned()),
            (5, "mkdir -p t".to_owned()),
            (5, "cargo run --release -- rpn -o o.png".to_owned())
        ]
    );
    let vars = BTreeMap::from([
        ("OUT".to_owned(), "a".to_owned()),
        ("OUT_DIR".to_owned(), "b".to_owned()),
    ]);
    assert_eq!(expand("$OUT_DIR/${OUT}-$OUT", &vars), "b/a-a");
    assert_eq!(
        assignment(r#"SIZE="${SIZE:-65536x65536}""#),
        Some(("SIZE".to_owned(), "${SIZE:-65536x65536}".to_owned()))
    );
}
