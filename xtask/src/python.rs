//! The Python bindings (`crates/spectex-py`): CI's steps, which build the extension module in the
//! test build's environment (so nothing the test step compiled is compiled again), install
//! numpy and pytest in a virtual environment under the target directory and run the pytest
//! suite; and `cargo xtask python [wheel]`, the same steps alone, or the release wheel built by
//! maturin with its size, the import time and the render overhead measured.
//!
//! CI does not build the wheel: maturin builds in its own cargo invocation (a test-profile
//! build of it is a test harness, and its environment rebuilds pyo3), so a wheel there would
//! compile the dependencies a second time. The suite imports the module cargo built, staged
//! with the package's Python files in `target/py-stage/`. CI installs maturin for the source
//! distribution: `maturin sdist`, then a check that every file its Rust sources include is in
//! it (a file outside a crate's directory is not, and the sdist would not compile).

use std::env;
use std::path::PathBuf;
use std::process::Command;

use anyhow::{Context, Result, bail};

use super::{Step, Workspace, run_command, run_steps, target_dir};

/// The virtual environment's directory under the target directory.
const VENV: &str = "py-venv";

/// The packages CI's steps need, from PyPI as wheels only: the suite's, and maturin for the
/// source distribution.
const TEST_PACKAGES: &[&str] = &["numpy", "pytest", "maturin"];

/// Checks the sdist maturin wrote into `DIR` (argv[1]): every `include_str!`/`include_bytes!`
/// of a literal path in its crates' sources (`src/`, build scripts) names a file the sdist holds, and it holds the Python
/// package; prints what it found. A path dependency's files outside its crate's directory are
/// not packed (maturin takes each crate's `cargo package --list`), so such an include would
/// fail the compilation `pip install` runs from the sdist.
const CHECK_SDIST: &str = r#"import pathlib, posixpath, re, sys, tarfile
archives = sorted(pathlib.Path(sys.argv[1]).glob('*.tar.gz'))
if len(archives) != 1:
    sys.exit(f'expected one sdist in {sys.argv[1]}, found {len(archives)}')
with tarfile.open(archives[0]) as tar:
    members = {m.name: m for m in tar.getmembers() if m.isfile()}
    names = set(members)
    pattern = re.compile(r'include_(?:str|bytes)!\(\s*"([^"]+)"\s*\)')
    missing, includes = [], 0
    # What a build compiles: the crates' sources and build scripts (not tests or benches).
    built = (n for n in names if n.endswith('.rs') and ('/src/' in n or n.endswith('/build.rs')))
    for name in sorted(built):
        text = tar.extractfile(members[name]).read().decode('utf-8', 'replace')
        for path in pattern.findall(text):
            includes += 1
            target = posixpath.normpath(posixpath.join(posixpath.dirname(name), path))
            if target not in names:
                missing.append(f'{name}: include of {path} ({target} is not in the sdist)')
root = archives[0].name[:-len('.tar.gz')]
if f'{root}/python/spectex/__init__.py' not in names:
    missing.append('the Python package (python/spectex/__init__.py) is not in the sdist')
if missing:
    sys.exit('the sdist would not build:\n' + '\n'.join(missing))
print(f'{archives[0].name}: {len(names)} files, {includes} includes, every one in it')
"#;

/// The Python package's source, relative to the workspace root.
const PACKAGE: &str = "crates/spectex-py/python/spectex";

/// The suite, relative to the workspace root.
const TESTS: &str = "crates/spectex-py/tests";

/// Copies the package's Python files and the built module into `DEST/spectex/` (what
/// `pip install` would put in site-packages), run by the venv's Python.
const STAGE: &str = "import pathlib, shutil, sys
src, module, dest = map(pathlib.Path, sys.argv[1:4])
package = dest / 'spectex'
shutil.rmtree(package, ignore_errors=True)
shutil.copytree(src, package, ignore=shutil.ignore_patterns('*.so', '*.pyd', '__pycache__'))
shutil.copy2(module, package / '_spectex.abi3.so')";

/// The venv's Python interpreter.
fn venv_python(ws: &Workspace) -> PathBuf {
    target_dir(ws).join(VENV).join("bin").join("python")
}

/// CI's Python steps. `ci_env` gives a command the test step's environment
/// (`RUSTC_WORKSPACE_WRAPPER=clippy-driver`, `RUSTFLAGS=-D warnings`, lavapipe): with it and
/// the same profile the build reuses every dependency the test step compiled and compiles
/// pyo3, numpy and spectex-py alone, linted by clippy with `-D warnings` like every other
/// crate, and the suite's GPU test renders on lavapipe.
pub(super) fn ci_steps(ws: &Workspace, ci_env: &dyn Fn(&mut Command)) -> Result<Vec<Step>> {
    steps(ws, ci_env)
}

/// The steps: venv, pip, the module (with the `gpu` feature: spectex-gpu is in the test
/// build already) and the reference binary, staging, pytest.
fn steps(ws: &Workspace, ci_env: &dyn Fn(&mut Command)) -> Result<Vec<Step>> {
    let mut found = Command::new("python3");
    found.arg("--version");
    if !super::runs(&mut found) {
        bail!(
            "the Python step needs python3 (3.9 or later, with its venv module) on PATH to \
             test crates/spectex-py"
        );
    }
    let target = target_dir(ws);
    let python = venv_python(ws);
    let mut steps = Vec::new();
    if !python.exists() {
        let mut venv = Command::new("python3");
        venv.args(["-m", "venv"]).arg(target.join(VENV));
        steps.push(Step {
            title: format!("python3 -m venv {}", target.join(VENV).display()),
            command: venv,
        });
    }
    let mut pip = Command::new(&python);
    pip.args([
        "-m",
        "pip",
        "install",
        "-q",
        "--disable-pip-version-check",
        "--only-binary=:all:",
    ])
    .args(TEST_PACKAGES);
    steps.push(Step {
        title: format!("pip install {} (wheels)", TEST_PACKAGES.join(" ")),
        command: pip,
    });
    // Features resolved as for the test and examples steps: `--workspace` (with `-p spectex-py`
    // they would be resolved for this crate alone), and `--examples` (already built by the
    // examples step), which brings in the dev-dependencies' features as the tests do; without
    // it spectex-cpu, -spectrum, -sampling … were compiled again with fewer features.
    // The source distribution `pip install` builds from where no wheel fits: maturin packs the
    // crate and its path dependencies; the check reads it (no compilation).
    let sdist = target.join("py-sdist");
    if sdist.exists() {
        std::fs::remove_dir_all(&sdist).with_context(|| format!("removing {}", sdist.display()))?;
    }
    let mut maturin = Command::new(target.join(VENV).join("bin").join("maturin"));
    maturin
        .args(["sdist", "-m", "crates/spectex-py/Cargo.toml", "-o"])
        .arg(&sdist)
        .current_dir(&ws.root);
    steps.push(Step {
        title: "maturin sdist (crates/spectex-py)".into(),
        command: maturin,
    });
    let mut check = Command::new(&python);
    check.args(["-c", CHECK_SDIST]).arg(&sdist);
    steps.push(Step {
        title: "check the sdist: every file its Rust sources include is in it".into(),
        command: check,
    });
    let mut build = ws.cargo(&[
        "build",
        "--workspace",
        "--examples",
        "--lib",
        "--bin",
        "spectex-py-reference",
        "--features",
        "spectex-py/gpu",
        "--profile",
        "test",
    ]);
    ci_env(&mut build);
    build.env("PYO3_PYTHON", &python);
    steps.push(Step {
        title: "cargo build spectex-py's module and reference binary (test profile)".into(),
        command: build,
    });
    let module = target.join("debug").join(format!(
        "{}_spectex{}",
        env::consts::DLL_PREFIX,
        env::consts::DLL_SUFFIX
    ));
    let stage = target.join("py-stage");
    let mut copy = Command::new(&python);
    copy.args(["-c", STAGE])
        .arg(ws.root.join(PACKAGE))
        .arg(&module)
        .arg(&stage);
    steps.push(Step {
        title: format!("stage the spectex package in {}", stage.display()),
        command: copy,
    });
    let mut pytest = Command::new(&python);
    pytest
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(ws.root.join(TESTS))
        .current_dir(&ws.root)
        .env("PYTHONPATH", &stage)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .env(
            "SPECTEX_PY_REFERENCE_BIN",
            target.join("debug").join("spectex-py-reference"),
        )
        .env("SPECTEX_PY_REQUIRE_REFERENCE", "1");
    ci_env(&mut pytest);
    steps.push(Step {
        title: "pytest crates/spectex-py/tests".into(),
        command: pytest,
    });
    Ok(steps)
}

/// `cargo xtask python`: the CI steps alone; `cargo xtask python wheel [--no-default-features]`:
/// the release wheel, its size, `import spectex`'s time and the render overhead.
pub(super) fn python(ws: &Workspace, args: &[std::ffi::OsString]) -> Result<()> {
    let args: Vec<String> = args
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    match args.first().map(String::as_str) {
        None => run_steps("python", steps(ws, &|_| {})?),
        Some("wheel") => wheel(ws, &args[1..]),
        Some(other) => bail!("`cargo xtask python` takes nothing or `wheel` (got `{other}`)"),
    }
}

/// Builds the release wheel with maturin (extra arguments go to `maturin build`, e.g.
/// `--no-default-features` for the CPU-only one), installs it in the venv and runs
/// `examples/python/overhead.py`.
fn wheel(ws: &Workspace, extra: &[String]) -> Result<()> {
    let target = target_dir(ws);
    let python = venv_python(ws);
    if !python.exists() {
        let mut venv = Command::new("python3");
        venv.args(["-m", "venv"]).arg(target.join(VENV));
        run_command(&mut venv)?;
    }
    let mut pip = Command::new(&python);
    pip.args(["-m", "pip", "install", "-q", "--only-binary=:all:"])
        .args(TEST_PACKAGES);
    run_command(&mut pip)?;
    let out = target.join("py-wheels");
    if out.exists() {
        std::fs::remove_dir_all(&out).with_context(|| format!("removing {}", out.display()))?;
    }
    let mut build = Command::new(target.join(VENV).join("bin").join("maturin"));
    build
        .args([
            "build",
            "--release",
            "-m",
            "crates/spectex-py/Cargo.toml",
            "-o",
        ])
        .arg(&out)
        .arg("-i")
        .arg(&python)
        .args(extra)
        .current_dir(&ws.root);
    run_command(&mut build)?;
    let wheel = std::fs::read_dir(&out)
        .with_context(|| format!("reading {}", out.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .with_context(|| format!("maturin wrote no wheel into {}", out.display()))?;
    let size = std::fs::metadata(&wheel)?.len();
    let mut install = Command::new(&python);
    install
        .args([
            "-m",
            "pip",
            "install",
            "-q",
            "--force-reinstall",
            "--no-deps",
        ])
        .arg(&wheel);
    run_command(&mut install)?;
    let mut overhead = Command::new(&python);
    overhead
        .arg(ws.root.join("examples/python/overhead.py"))
        .current_dir(&target);
    run_command(&mut overhead)?;
    eprintln!(
        "xtask: wheel {} is {:.2} MB",
        wheel.display(),
        size as f64 / 1e6
    );
    Ok(())
}
