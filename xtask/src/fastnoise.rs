//! FastNoiseSIMD for `cargo xtask bench classic`: its Python package and its figures.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};

use crate::Workspace;

/// A Python with `pyfastnoisesimd`: the virtual environment `out/fastnoisesimd-venv`, created
/// and filled on first use (the package's C++ builds against numpy's headers, without build
/// isolation).
pub(crate) fn fastnoisesimd_python(ws: &Workspace, out: &Path) -> Result<PathBuf> {
    let venv = out.join("fastnoisesimd-venv");
    let python = venv.join("bin").join("python3");
    let has_package = |python: &Path| {
        Command::new(python)
            .args([
                "-c",
                "import numpy; numpy.product = numpy.prod; import pyfastnoisesimd",
            ])
            .current_dir(&ws.root)
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if python.exists() && has_package(&python) {
        return Ok(python);
    }
    let quiet = |mut c: Command, what: &str| -> Result<()> {
        eprintln!("xtask: {what}");
        let output = c
            .output()
            .with_context(|| format!("{what}: could not start"))?;
        if !output.status.success() {
            let stderr = String::from_utf8_lossy(&output.stderr);
            let tail: Vec<&str> = stderr.lines().rev().take(5).collect();
            bail!(
                "{what} failed: {}",
                tail.into_iter().rev().collect::<Vec<_>>().join(" / ")
            );
        }
        Ok(())
    };
    let mut create = Command::new("python3");
    create.args(["-m", "venv"]).arg(&venv);
    quiet(create, "python3 -m venv target/bench/fastnoisesimd-venv")?;
    let mut base = Command::new(&python);
    base.args(["-m", "pip", "install", "-q", "wheel", "setuptools", "numpy"]);
    quiet(base, "pip install wheel setuptools numpy")?;
    let include = Command::new(&python)
        .args(["-c", "import numpy; print(numpy.get_include())"])
        .output()
        .context("asking numpy for its include directory")?;
    let include = String::from_utf8_lossy(&include.stdout).trim().to_string();
    let mut package = Command::new(&python);
    package
        .args([
            "-m",
            "pip",
            "install",
            "-q",
            "--no-build-isolation",
            "pyfastnoisesimd",
        ])
        .env("CFLAGS", format!("-I{include}"));
    quiet(
        package,
        "pip install pyfastnoisesimd (builds FastNoiseSIMD's C++, a minute or two)",
    )?;
    if !has_package(&python) {
        bail!("pyfastnoisesimd installed but does not import");
    }
    Ok(python)
}

/// `case<TAB>Mpix/s<TAB>SIMD level` lines of `fastnoisesimd.py`, after its header.
pub(crate) fn parse_fastnoise_tsv(text: &str) -> Result<Vec<(String, f64, String)>> {
    let mut rows = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let fields: Vec<&str> = line.split('\t').map(str::trim).collect();
        let [case, mpix, level] = fields[..] else {
            bail!("bad line {line:?}");
        };
        let mpix: f64 = mpix
            .parse()
            .with_context(|| format!("bad Mpix/s in {line:?}"))?;
        rows.push((case.to_string(), mpix, level.to_string()));
    }
    Ok(rows)
}
