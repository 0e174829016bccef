//! The checks outside CI: `export-check`, `bevy-check` and `reproduce` (the papers).

use std::env;
use std::ffi::OsString;
use std::fs;
use std::path::PathBuf;
use std::process::Command;

use anyhow::{Context, Result, bail};

use crate::system::{ensure_lavapipe, private_runtime_dir};
use crate::{Step, Workspace, run_steps, target_dir};

/// `cargo xtask export-check`: the export render test over every exportable model on lavapipe.
pub(crate) fn export_check(ws: &Workspace) -> Result<()> {
    let lavapipe = ensure_lavapipe(ws)?;
    let mut command = ws.cargo(&[
        "test",
        "--workspace",
        "--test",
        "it",
        "export::exported_modules",
        "--",
        "--nocapture",
    ]);
    lavapipe.apply(&mut command);
    command.env("SPECTEX_EXPORT_ALL", "1");
    run_steps(
        "export-check",
        vec![Step {
            title: "the export render test over every exportable model (lavapipe)".to_owned(),
            command,
        }],
    )
}

/// The model, window and frame of `cargo xtask bevy-check`; the window is the one
/// `crates/spectex-crosscheck/tests/it/export.rs` compares the frame on (`BEVY_WINDOW`).
const BEVY_MODEL: &str = "testdata/models/lrp-ring.json";
const BEVY_WINDOW: [&str; 5] = ["128", "96", "-37.25", "81.5", "0.75"];

/// `cargo xtask bevy-check`: export a model, run the Bevy example headlessly on lavapipe (one
/// frame into a file), and compare the frame with the CPU in the cross-check test binary.
pub(crate) fn bevy_check(ws: &Workspace) -> Result<()> {
    let lavapipe = ensure_lavapipe(ws)?;
    let out = target_dir(ws).join("bevy-check");
    fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let module = out.join("model.wgsl");
    let frame = out.join("frame.f32");
    let _ = fs::remove_file(&frame);
    // The test profile, as the comparison's `cargo test` builds: one build of the workspace.
    let mut export = ws.cargo(&[
        "run",
        "--profile",
        "test",
        "-p",
        "spectex-cli",
        "--",
        "export",
        BEVY_MODEL,
        "--wgsl",
    ]);
    export.arg(&module);
    let example = ws.root.join("examples/bevy-material");
    let mut bevy = Command::new(&ws.cargo);
    bevy.current_dir(&example).args(["run", "--"]);
    bevy.arg(&module).arg(&frame).args(BEVY_WINDOW);
    bevy.env(
        "CARGO_TARGET_DIR",
        env::var_os("BEVY_TARGET_DIR").map_or_else(|| target_dir(ws).join("bevy"), PathBuf::from),
    );
    lavapipe.apply(&mut bevy);
    let mut compare = ws.cargo(&[
        "test",
        "-p",
        "spectex-crosscheck",
        "--test",
        "it",
        "export::bevy_frame",
        "--",
        "--nocapture",
    ]);
    compare.env("SPECTEX_BEVY_FRAME", &frame);
    run_steps(
        "bevy-check",
        vec![
            Step {
                title: format!("export {BEVY_MODEL}"),
                command: export,
            },
            Step {
                title: "build and run examples/bevy-material (one headless frame)".to_owned(),
                command: bevy,
            },
            Step {
                title: "compare the frame with the CPU render".to_owned(),
                command: compare,
            },
        ],
    )
}

/// The papers `cargo xtask reproduce` knows (spectex-reproduce's `Paper::ALL`).
const PAPERS: &[&str] = &["lrp", "rpn", "phasor", "survey", "gabor-example", "tiling"];

/// `cargo xtask reproduce [PAPER…] [--quick] [--no-gpu]`: builds spectex-reproduce in release
/// and runs it into `target/reproduce/`. The arguments are checked here first, so a typo costs
/// no build.
pub(crate) fn reproduce(ws: &Workspace, args: &[OsString]) -> Result<()> {
    for arg in args {
        let arg = arg.to_string_lossy();
        if arg.starts_with('-') {
            if !["--quick", "--no-gpu"].contains(&arg.as_ref()) {
                bail!(
                    "unknown option `{arg}` of `cargo xtask reproduce`; options: --quick, --no-gpu"
                );
            }
        } else if !PAPERS.contains(&arg.to_ascii_lowercase().as_str()) {
            bail!("unknown paper `{arg}`; valid papers: {}", PAPERS.join(", "));
        }
    }
    let out = target_dir(ws).join("reproduce");
    let mut command = ws.cargo(&["run", "--release", "-p", "spectex-reproduce", "--"]);
    command.arg("--out").arg(&out).args(args);
    private_runtime_dir(ws, &mut command)?;
    run_steps(
        "reproduce",
        vec![Step {
            title: format!(
                "spectex-reproduce{} into {}",
                args.iter()
                    .map(|a| format!(" {}", a.to_string_lossy()))
                    .collect::<String>(),
                out.display()
            ),
            command,
        }],
    )
}
