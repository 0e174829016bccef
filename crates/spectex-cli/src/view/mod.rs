//! `spectex view`: a local web server showing a model (or the fit of an image) as an infinite,
//! zoomable texture with a parameter panel, tiles rendered on demand.
//!
//! The page (`assets/`) uses Leaflet (vendored, BSD-2-Clause, `assets/LICENSE-leaflet`) with a
//! simple coordinate system: map point `(x, y)` at zoom 0 is model pixel `(x, y)`, and tile
//! `(tx, ty)` at zoom `k` is the 256 × 256 window at offset `256 · 2^-k · (tx, ty)`, scale
//! `2^-k`: the bytes `spectex render --size 256x256 --offset X,Y --scale S -o tile.png` writes.
//! A coarse tile (`size=64`) is the 64 × 64 window at offset `64 · 2^-k · (tx, ty)`: the region
//! of the fine tile `(tx, ty)` of zoom `k + 2`, at a quarter of its resolution.
//!
//! Requests are handled by one dispatcher thread that answers the cheap ones itself and queues
//! renders for a fixed pool of workers ([`queue`]): the queue is bounded (a burst beyond it gets
//! 503), and each worker holds one render's memory at a time, so memory does not grow with the
//! number of requests. Renders for a model version that is no longer current, or for a tab that
//! has closed or has moved its view elsewhere, are dropped from the queue unrendered.

mod fitting;
mod panel;
mod query;
mod queue;
mod routes;
mod tiles;

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Result, anyhow};
use clap::Args;

use crate::device::Device;

/// Arguments of `spectex view`.
#[derive(Debug, Args)]
pub struct ViewCommand {
    /// A model file (.json) or an example image (PNG, JPEG) to fit; the built-in exemplar if
    /// omitted.
    input: Option<PathBuf>,
    /// Port to listen on (0: any free port, printed).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// Address to listen on; only this machine can connect unless you change it.
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
    /// Open the page in the default browser.
    #[arg(long)]
    open: bool,
    /// Evaluator of the tiles: the CPU reference, the GPU, or auto (the GPU when present).
    #[arg(long, value_enum, default_value = "cpu")]
    device: Device,
    /// Render workers (default: the machine's cores, at most 8).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=64))]
    workers: Option<u16>,
}

/// `spectex view`: serves the page until interrupted.
pub fn view(cmd: &ViewCommand) -> Result<()> {
    let source = match &cmd.input {
        Some(path) if is_model_file(path) => routes::Source::model_file(path)?,
        other => routes::Source::image(other.as_deref())?,
    };
    let gpu = crate::device::gpu_for(cmd.device)?;
    let workers = cmd.workers.map_or_else(
        || {
            std::thread::available_parallelism()
                .map_or(2, std::num::NonZero::get)
                .min(8)
        },
        usize::from,
    );
    let addr = format!("{}:{}", cmd.host, cmd.port);
    let listener = std::net::TcpListener::bind(&addr)
        .map_err(|e| anyhow!("cannot listen on {addr}: {e}; choose another --port"))?;
    send_at_once(&listener);
    let server = tiny_http::Server::from_listener(listener, None)
        .map_err(|e| anyhow!("cannot listen on {addr}: {e}; choose another --port"))?;
    let bound: SocketAddr = server
        .server_addr()
        .to_ip()
        .ok_or_else(|| anyhow!("internal: the server has no IP address"))?;
    let url = format!("http://{bound}/");
    #[allow(clippy::print_stdout)] // reason: the address is the command's result
    {
        println!("spectex view: serving {url} (Ctrl-C stops)");
    }
    use std::io::Write as _;
    let _ = std::io::stdout().flush();
    if cmd.open {
        open_browser(&url);
    }
    let shared = Arc::new(routes::Shared::new(source, gpu, workers));
    routes::serve(&server, &shared);
    Ok(())
}

/// Turns Nagle's algorithm off (TCP_NODELAY) for the connections `listener` accepts, which
/// inherit it on Linux. tiny_http writes a response's header and body separately; with Nagle on,
/// the body waited for the browser's delayed acknowledgement of the header, 40 ms on Linux: a
/// 4 KiB tile took 45 ms from its first byte to its last. A failure is a note: the view works,
/// only slower.
fn send_at_once(listener: &std::net::TcpListener) {
    #[cfg(unix)]
    if let Err(e) = rustix::net::sockopt::set_tcp_nodelay(listener, true) {
        eprintln!("note: cannot set TCP_NODELAY ({e}); tiles may arrive up to 40 ms late");
    }
    #[cfg(not(unix))]
    let _ = listener;
}

/// Whether `path` names a model file (`.json`) rather than an image.
fn is_model_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Asks the desktop to open `url`; a failure is a note, the server goes on.
fn open_browser(url: &str) {
    let mut command = if cfg!(target_os = "macos") {
        std::process::Command::new("open")
    } else if cfg!(target_os = "windows") {
        let mut c = std::process::Command::new("cmd");
        c.args(["/C", "start", ""]);
        c
    } else {
        std::process::Command::new("xdg-open")
    };
    if let Err(e) = command.arg(url).spawn() {
        eprintln!("note: cannot open a browser ({e}); open {url} yourself");
    }
}
