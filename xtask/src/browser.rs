//! The real-browser test of `spectex view` (part of `cargo xtask ci`): headless Chromium
//! (Debian's `chromium`, installed with apt-get when missing and root) driven by playwright-core
//! from npm (`browser_view.cjs`) against the `spectex` binary the test step built. Where
//! Chromium, Node or the npm package cannot be had, it says so loudly and skips. The same
//! script measures redraws for `cargo xtask view-bench` ([`view_bench`]).
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
    /// Starts `spectex view ARGS` (2 workers) on a free port and reads its address.
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

/// What driving a browser needs: Chromium, and the driver's npm package in `dir`.
struct Tools {
    /// The browser.
    chromium: PathBuf,
    /// The playwright-core package's directory.
    package: PathBuf,
    /// The scratch directory the package is installed in.
    dir: PathBuf,
    /// Seconds spent finding or installing Chromium, then npm.
    setup: (f64, f64),
}

/// Finds Chromium (installing Debian's package when missing and root), Node and npm, and
/// installs the driver; `Ok(Err(why))` when one of them cannot be had.
fn tools(ws: &Workspace) -> Result<Result<Tools, String>> {
    let started = Instant::now();
    let chromium = match find_chromium() {
        Some(path) => path,
        None => {
            if let Err(e) =
                apt_install(&["chromium"], "Chromium (the browser test of spectex view)")
            {
                return Ok(Err(format!("{e:#}")));
            }
            match find_chromium() {
                Some(path) => path,
                None => {
                    return Ok(Err(
                        "apt-get installed chromium, but /usr/bin/chromium is missing".into(),
                    ));
                }
            }
        }
    };
    let installed = started.elapsed().as_secs_f64();
    for tool in ["node", "npm"] {
        if !runs(Command::new(tool).arg("--version")) {
            return Ok(Err(format!(
                "`{tool}` is not installed (apt-get install nodejs npm)"
            )));
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
            return Ok(Err(format!("cannot install {PLAYWRIGHT} from npm: {e:#}")));
        }
    }
    Ok(Ok(Tools {
        chromium,
        package,
        dir,
        setup: (installed, started.elapsed().as_secs_f64() - installed),
    }))
}

/// The browser test; `Ok` also when it skips (saying why).
pub(crate) fn view_check(ws: &Workspace) -> Result<()> {
    let started = Instant::now();
    let Tools {
        chromium,
        package,
        dir,
        setup: (installed, npm),
    } = match tools(ws)? {
        Ok(tools) => tools,
        Err(why) => {
            skip(&why);
            return Ok(());
        }
    };
    let npm_done = installed + npm;
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

/// The help line of `cargo xtask view-bench`.
pub(crate) const VIEW_BENCH_USAGE: &str = "`cargo xtask view-bench [MODEL.json] [--redraws N] \
     [--pan X,Y] [--zoom K]`";

/// `cargo xtask view-bench`: the release `spectex view` of MODEL (default
/// `testdata/models/lrp-gravel.json`) with 2 workers in headless Chromium, a 1024 × 1024 map,
/// redrawn N times (default 8) after "new seed": each redraw's coarse and full times, the
/// server's per-step times summed over its tiles, the CPU the browser and the server used, then
/// best and median. A measurement, not a test: nothing is asserted.
pub(crate) fn view_bench(ws: &Workspace, args: &[std::ffi::OsString]) -> Result<()> {
    let mut model = ws.root.join("testdata/models/lrp-gravel.json");
    let (mut redraws, mut pan, mut zoom) = ("8".to_owned(), None, None);
    let mut args = args.iter().map(|a| a.to_string_lossy().into_owned());
    while let Some(arg) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .with_context(|| format!("{name} needs a value; {VIEW_BENCH_USAGE}"))
        };
        match arg.as_str() {
            "--redraws" => redraws = value("--redraws")?,
            "--pan" => pan = Some(value("--pan")?),
            "--zoom" => zoom = Some(value("--zoom")?),
            other if other.starts_with("--") => bail!("unknown option {other}; {VIEW_BENCH_USAGE}"),
            other => model = env::current_dir()?.join(other),
        }
    }
    if !redraws.parse::<u32>().is_ok_and(|n| n > 0) {
        bail!("--redraws {redraws}: a whole number above 0");
    }
    let tools = tools(ws)?.map_err(|why| anyhow::anyhow!("cannot drive a browser: {why}"))?;
    run_command(&mut ws.cargo(&["build", "--release", "-p", "spectex-cli"]))?;
    let spectex = target_dir(ws)
        .join("release")
        .join(format!("spectex{}", env::consts::EXE_SUFFIX));
    let server = Server::start(&spectex, &[&model])?;
    let script = tools.dir.join("browser_view.cjs");
    fs::write(&script, SCRIPT)?;
    eprintln!(
        "xtask: view-bench of {} (load average: {})",
        model.display(),
        load_average()
    );
    let mut node = Command::new("node");
    node.arg(&script)
        .env("BENCH", "1")
        .env("PLAYWRIGHT_CORE", &tools.package)
        .env("CHROMIUM", &tools.chromium)
        .env("VIEW_URL", &server.url)
        .env("SERVER_PID", server.child.id().to_string())
        .env("REDRAWS", &redraws)
        .env("MAP_W", "1024")
        .env("MAP_H", "1024");
    if let Some(pan) = &pan {
        node.env("PAN", pan);
    }
    if let Some(zoom) = &zoom {
        node.env("ZOOM", zoom);
    }
    run_command(&mut node)?;
    eprintln!("xtask: load average after: {}", load_average());
    Ok(())
}

/// `/proc/loadavg`'s three averages, or "unknown".
fn load_average() -> String {
    fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".to_owned())
}
