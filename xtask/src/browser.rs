//! The real-browser test of `spectex view` (part of `cargo xtask ci`): headless Chromium
//! (Debian's `chromium`, installed with apt-get when missing and root) driven by playwright-core
//! from npm (`browser_view.cjs`) against the `spectex` binary the test step built. Where
//! Chromium, Node or the npm package cannot be had, it says so loudly and skips.
//!
//! `SPECTEX_VIEW_SHOTS=DIR` also writes the README's two screenshots into DIR (`view-model.png` of
//! `testdata/models/combine-bark.json`, `view-image.png` of
//! `../shared/testdata/textures/skimage_gravel.png` when present, else of the built-in exemplar).

use std::env;
use std::fs;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Instant;

use anyhow::{Context, Result, bail};

use crate::system::apt_install;
use crate::{Workspace, run_command, runs, target_dir};

/// The driver's npm package, pinned.
const PLAYWRIGHT: &str = "playwright-core@1.65.1";
/// The driver script.
const SCRIPT: &str = include_str!("browser_view.cjs");
/// The model the test shows, the field whose slider it moves, and the map's size: cheap at
/// every zoom level (fBm octaves above the pixels' Nyquist frequency are filtered out).
const MODEL: &str = "testdata/models/classic-perlin-fbm.json";
/// The slider moved.
const SLIDER: &str = "/classic/cell_size";
/// Map width and height, pixels.
const MAP: (u32, u32) = (640, 480);

/// Prints a loud skip notice.
fn skip(reason: &str) {
    eprintln!(
        "xtask: ************************************************************************\n\
         xtask: SKIPPED the browser test of spectex view: {reason}\n\
         xtask: ************************************************************************"
    );
}

/// The system's Chromium, if installed.
fn find_chromium() -> Option<PathBuf> {
    if let Some(path) = env::var_os("CHROMIUM") {
        return Some(PathBuf::from(path));
    }
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
}

/// A `spectex view` server, killed when dropped.
struct Server {
    child: Child,
    url: String,
}

impl Server {
    /// Starts `spectex view ARGS` on a free port and reads its address.
    fn start(spectex: &Path, args: &[&Path]) -> Result<Self> {
        let mut child = Command::new(spectex)
            .arg("view")
            .args(args)
            .args(["--port", "0", "--workers", "2"])
            .stdout(Stdio::piped())
            .spawn()
            .with_context(|| format!("starting {} view", spectex.display()))?;
        let mut line = String::new();
        if let Some(out) = child.stdout.take() {
            BufReader::new(out).read_line(&mut line)?;
        }
        let Some(url) = line.split_whitespace().find(|w| w.starts_with("http://")) else {
            let _ = child.kill();
            bail!("spectex view printed no address: {line:?}");
        };
        Ok(Self {
            url: url.to_owned(),
            child,
        })
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The browser test; `Ok` also when it skips (saying why).
pub(crate) fn view_check(ws: &Workspace) -> Result<()> {
    let started = Instant::now();
    let chromium = match find_chromium() {
        Some(path) => path,
        None => {
            if let Err(e) =
                apt_install(&["chromium"], "Chromium (the browser test of spectex view)")
            {
                skip(&format!("{e:#}"));
                return Ok(());
            }
            match find_chromium() {
                Some(path) => path,
                None => {
                    skip("apt-get installed chromium, but /usr/bin/chromium is missing");
                    return Ok(());
                }
            }
        }
    };
    let installed = started.elapsed().as_secs_f64();
    for tool in ["node", "npm"] {
        if !runs(Command::new(tool).arg("--version")) {
            skip(&format!(
                "`{tool}` is not installed (apt-get install nodejs npm)"
            ));
            return Ok(());
        }
    }
    let dir = target_dir(ws).join("browser-test");
    fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let package = dir.join("node_modules").join("playwright-core");
    let version = PLAYWRIGHT.rsplit('@').next().unwrap_or_default();
    let have = fs::read_to_string(package.join("package.json")).unwrap_or_default();
    if !have.contains(&format!("\"version\": \"{version}\"")) {
        let npm = run_command(
            Command::new("npm")
                .args([
                    "install",
                    "--no-audit",
                    "--no-fund",
                    "--no-save",
                    "--prefix",
                ])
                .arg(&dir)
                .arg(PLAYWRIGHT),
        );
        if let Err(e) = npm {
            skip(&format!("cannot install {PLAYWRIGHT} from npm: {e:#}"));
            return Ok(());
        }
    }
    let npm_done = started.elapsed().as_secs_f64();
    let spectex = target_dir(ws)
        .join("debug")
        .join(format!("spectex{}", env::consts::EXE_SUFFIX));
    if !spectex.exists() {
        bail!(
            "{} is missing: the test step builds it (cargo test --workspace)",
            spectex.display()
        );
    }
    let model = ws.root.join(MODEL);
    let server = Server::start(&spectex, &[&model])?;
    let shots = env::var_os("SPECTEX_VIEW_SHOTS").map(|d| ws.root.join(d));
    let shot_servers = match &shots {
        None => None,
        Some(_) => {
            let bark = ws.root.join("testdata/models/combine-bark.json");
            let bark = Server::start(&spectex, &[&bark])?;
            let gravel = ws
                .root
                .join("../shared/testdata/textures/skimage_gravel.png");
            let image = if gravel.exists() {
                Server::start(&spectex, &[&gravel])?
            } else {
                eprintln!("xtask: {} absent; the built-in exemplar", gravel.display());
                Server::start(&spectex, &[])?
            };
            Some((bark, image))
        }
    };
    let out = dir.join("out");
    let _ = fs::remove_dir_all(&out);
    fs::create_dir_all(&out)?;
    let script = dir.join("browser_view.cjs");
    fs::write(&script, SCRIPT)?;
    let mut node = Command::new("node");
    node.arg(&script)
        .env("PLAYWRIGHT_CORE", &package)
        .env("CHROMIUM", &chromium)
        .env("SPECTEX", &spectex)
        .env("VIEW_URL", &server.url)
        .env("MODEL", &model)
        .env("SLIDER", SLIDER)
        .env("MAP_W", MAP.0.to_string())
        .env("MAP_H", MAP.1.to_string())
        .env("OUT", &out);
    if let (Some(shots), Some((model, image))) = (&shots, &shot_servers) {
        fs::create_dir_all(shots)?;
        node.env("SHOTS", shots)
            .env("MODEL_SHOT_URL", &model.url)
            .env("IMAGE_URL", &image.url);
    }
    run_command(&mut node).with_context(|| {
        format!(
            "the browser test of spectex view failed; screenshots and renders in {}",
            out.display()
        )
    })?;
    eprintln!(
        "xtask: browser test of spectex view passed in {:.1} s (Chromium present or installed \
         {installed:.1} s, npm {:.1} s, test {:.1} s)",
        started.elapsed().as_secs_f64(),
        npm_done - installed,
        started.elapsed().as_secs_f64() - npm_done
    );
    Ok(())
}
