//! `spectex view`'s endpoints, end to end: the binary serving on a free port, asked over plain
//! HTTP/1.1. Tiles and renders must be the bytes `spectex render` writes for the same window;
//! edits must give models the validation accepts; bad parameters a 400 naming them; a burst of
//! requests a bounded memory.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::common::{s, scratch, spectex_ok};

/// A `spectex view` process, killed when dropped.
struct Server {
    child: Child,
    addr: String,
}

/// Spawns a `spectex view` command with its stdout piped and reads the `host:port` from the
/// `http://…` of its first line (`None` when that line has none).
pub(crate) fn spawn_view(mut command: Command) -> (Child, Option<String>) {
    let mut child = command.stdout(Stdio::piped()).spawn().unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .split("http://")
        .nth(1)
        .and_then(|rest| rest.split('/').next())
        .map(str::to_owned);
    (child, addr)
}

impl Server {
    /// Starts `spectex view ARGS --port 0 --workers 2` and reads the address it prints.
    fn start(args: &[&str]) -> Self {
        Self::with_workers(args, "2")
    }

    /// [`Server::start`] with `workers` render workers.
    fn with_workers(args: &[&str], workers: &str) -> Self {
        Self::with_env(args, workers, &[])
    }

    /// [`Server::with_workers`] with the environment variables `env`.
    fn with_env(args: &[&str], workers: &str, env: &[(&str, &str)]) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_spectex"));
        command
            .arg("view")
            .args(args)
            .args(["--port", "0", "--workers", workers])
            .envs(env.iter().copied())
            .stderr(Stdio::inherit());
        let (child, addr) = spawn_view(command);
        let addr = addr.unwrap_or_else(|| panic!("spectex view printed no address"));
        Self { child, addr }
    }

    /// `METHOD path` with `body`: the status and the (de-chunked) body.
    fn request(&self, method: &str, path: &str, body: Option<&str>) -> (u16, Vec<u8>) {
        request(&self.addr, method, path, body)
    }

    /// `GET path`, which must answer 200: the body.
    fn get_ok(&self, path: &str) -> Vec<u8> {
        let (status, body) = self.request("GET", path, None);
        assert_eq!(
            status,
            200,
            "GET {path}: {}",
            String::from_utf8_lossy(&body)
        );
        body
    }

    /// `GET /api/state`.
    fn state(&self) -> Value {
        serde_json::from_slice(&self.get_ok("/api/state")).unwrap()
    }

    /// The peak resident memory of the server so far, KiB (`VmHWM`), where procfs has it.
    fn peak_kib(&self) -> Option<u64> {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).ok()?;
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmHWM:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One HTTP/1.1 request on its own connection.
pub(crate) fn request(addr: &str, method: &str, path: &str, body: Option<&str>) -> (u16, Vec<u8>) {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(120)))
        .unwrap();
    let body = body.unwrap_or("");
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut raw = Vec::new();
    stream.read_to_end(&mut raw).unwrap();
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a header");
    let head = String::from_utf8_lossy(&raw[..split]).to_ascii_lowercase();
    let status: u16 = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .expect("a status");
    let mut rest = raw[split + 4..].to_vec();
    if head.contains("transfer-encoding: chunked") {
        rest = dechunk(&rest);
    }
    (status, rest)
}

/// The body of a chunked transfer.
fn dechunk(mut raw: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let eol = raw.windows(2).position(|w| w == b"\r\n").unwrap();
        let size = usize::from_str_radix(
            std::str::from_utf8(&raw[..eol])
                .unwrap()
                .split(';')
                .next()
                .unwrap()
                .trim(),
            16,
        )
        .unwrap();
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&raw[eol + 2..eol + 2 + size]);
        raw = &raw[eol + 4 + size..];
    }
}

/// The bytes `spectex render MODEL ARGS -o FILE` writes (`ext` the file's extension).
fn cli_render(dir: &Path, model: &str, args: &[&str], ext: &str) -> Vec<u8> {
    let out = dir.join(format!("cli.{ext}"));
    let mut all = vec!["render", model, "-o", s(&out)];
    all.extend_from_slice(args);
    spectex_ok(&all);
    std::fs::read(&out).unwrap()
}

/// A testdata model's path.
fn model(name: &str) -> String {
    format!(
        "{}/../../testdata/models/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn tiles_and_renders_are_the_bytes_of_spectex_render() {
    let dir = scratch("view-tiles");
    let lrp = model("lrp-ring.json");
    let server = Server::start(&[&lrp]);
    assert_eq!(server.state()["version"], 1);
    // (tile or render path, `spectex render` arguments, extension)
    let cases: &[(&str, &[&str], &str)] = &[
        // The origin.
        ("/tile/0/0/0.png?v=1", &["--size", "256x256"], "png"),
        // Near (1e7, 1e7): tile 39062 starts at 39062 · 256 = 9 999 872.
        (
            "/tile/0/39062/39062.png?v=1",
            &["--size", "256x256", "--offset", "9999872,9999872"],
            "png",
        ),
        (
            "/render?x=1e7&y=1e7&w=64&h=48",
            &["--size", "64x48", "--offset", "1e7,1e7"],
            "png",
        ),
        // A coarse tile: the quarter-resolution twin of the tile (0, 3, -1), 64² at scale 4.
        (
            "/tile/-2/3/-1.png?v=1&q=c&size=64",
            &["--size", "64x64", "--offset", "768,-256", "--scale", "4"],
            "png",
        ),
        // A grid anchored to the view (`ox`, `oy`: its offset in pixels of a fine tile): at
        // the origin, at 1e7 exactly (tile 39062 plus 128 pixels), and zoomed out 16× (16
        // model pixels a pixel).
        (
            "/tile/0/0/0.png?v=1&ox=44&oy=181",
            &["--size", "256x256", "--offset", "44,181"],
            "png",
        ),
        (
            "/tile/0/39062/39062.png?v=1&ox=128&oy=128",
            &["--size", "256x256", "--offset", "1e7,1e7"],
            "png",
        ),
        (
            "/tile/0/39062/39061.png?v=1&ox=129&oy=255",
            &["--size", "256x256", "--offset", "10000001,9999871"],
            "png",
        ),
        (
            "/tile/-4/-1/2.png?v=1&ox=3&oy=100",
            &[
                "--size",
                "256x256",
                "--offset",
                "-4048,9792",
                "--scale",
                "16",
            ],
            "png",
        ),
        // The coarse twin of the anchored tile (0, 3, -1), ox = 6, oy = 255: the same region,
        // (774, -1) to (1030, 255), at a quarter of the resolution.
        (
            "/tile/0/3/-1.png?v=1&ox=6&oy=255",
            &["--size", "256x256", "--offset", "774,-1"],
            "png",
        ),
        (
            "/tile/-2/3/-1.png?v=1&q=c&size=64&ox=6&oy=255",
            &["--size", "64x64", "--offset", "774,-1", "--scale", "4"],
            "png",
        ),
        // Zoomed out 16×, filtered (the default) and not.
        (
            "/tile/-4/-1/2.png?v=1",
            &[
                "--size",
                "256x256",
                "--offset",
                "-4096,8192",
                "--scale",
                "16",
            ],
            "png",
        ),
        (
            "/tile/-4/-1/2.png?v=1&filter=0",
            &[
                "--size",
                "256x256",
                "--offset",
                "-4096,8192",
                "--scale",
                "16",
                "--no-filter",
            ],
            "png",
        ),
        // Periodic, and OpenEXR.
        (
            "/tile/0/1/0.png?v=1&periodic=128x128",
            &[
                "--size",
                "256x256",
                "--offset",
                "256,0",
                "--periodic",
                "128x128",
            ],
            "png",
        ),
        (
            "/render?x=-20.5&y=3&scale=0.5&w=40&h=30&format=exr",
            &["--size", "40x30", "--offset", "-20.5,3", "--scale", "0.5"],
            "exr",
        ),
    ];
    for (path, args, ext) in cases {
        let served = server.get_ok(path);
        let cli = cli_render(&dir, &lrp, args, ext);
        assert!(
            served == cli,
            "{path}: {} bytes served, {} from spectex render {}",
            served.len(),
            cli.len(),
            args.join(" ")
        );
    }
    // A colour model (3 channels) and a 3D one at z ≠ 0.
    let colour = model("texture-synthetic-colour.json");
    let server = Server::start(&[&colour]);
    assert_eq!(
        server.get_ok("/render?x=1e7&y=-3e5&w=48&h=32&scale=2"),
        cli_render(
            &dir,
            &colour,
            &["--size", "48x32", "--offset", "1e7,-3e5", "--scale", "2"],
            "png"
        )
    );
    let slab = model("phasor-3d-harmonics.json");
    let server = Server::start(&[&slab]);
    assert_eq!(server.state()["three_d"], true);
    assert_eq!(
        server.get_ok("/tile/1/3/-2.png?v=1&z=12.5"),
        cli_render(
            &dir,
            &slab,
            &[
                "--size", "256x256", "--offset", "384,-256", "--scale", "0.5", "--z", "12.5"
            ],
            "png"
        )
    );
}

#[test]
fn a_large_download_is_streamed_with_the_pixels_of_spectex_render() {
    let dir = scratch("view-stream");
    let gabor = model("gabor-isotropic.json");
    let server = Server::start(&[&gabor]);
    // Over the 4096 rendered in memory: streamed (chunked), band by band.
    let served = server.get_ok("/render?x=1e5&y=7&w=4100&h=20&download=1");
    let cli = cli_render(
        &dir,
        &gabor,
        &["--size", "4100x20", "--offset", "1e5,7"],
        "png",
    );
    let a = spectex_testkit::image_files::load_from_memory(&served).unwrap();
    let b = spectex_testkit::image_files::load_from_memory(&cli).unwrap();
    assert_eq!((a.width(), a.height()), (4100, 20));
    assert!(a.as_bytes() == b.as_bytes(), "the streamed pixels differ");
}

#[test]
fn a_parameter_change_gives_a_model_the_validation_accepts() {
    let dir = scratch("view-set");
    let server = Server::start(&[&model("lrp-ring.json")]);
    let state = server.state();
    let mean = &state["panel"]["fields"]["/lrp/mean"];
    assert_eq!(mean["range"], "[-1e9, 1e9]", "the range validation gives");
    assert_eq!(
        state["panel"]["fields"]["/lrp/strata/0/window_width"]["min"],
        0.5
    );
    let (status, body) = server.request(
        "POST",
        "/api/set",
        Some(r#"{"pointer": "/lrp/strata/0/window_width", "value": 20.5}"#),
    );
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    let state: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(state["version"], 2);
    assert_eq!(state["model"]["lrp"]["strata"][0]["window_width"], 20.5);
    // The model file the page downloads is one `spectex render` reads and validates …
    let file = server.get_ok("/api/model.json");
    let contents = spectex_model::from_json_file(std::str::from_utf8(&file).unwrap()).unwrap();
    let spectex_model::Model::Lrp(lrp) = &contents.model else {
        panic!("an LRP model");
    };
    assert_eq!(lrp.strata[0].window_width, 20.5);
    // … whose render is the new tiles; tiles of the old version are refused.
    let path = dir.join("edited.json");
    std::fs::write(&path, &file).unwrap();
    assert_eq!(server.request("GET", "/tile/0/0/0.png?v=1", None).0, 409);
    let edited = server.get_ok("/tile/0/0/0.png?v=2");
    assert_eq!(
        edited,
        cli_render(&dir, s(&path), &["--size", "256x256"], "png")
    );
    // A new seed: another version, another texture, the same parameters.
    let (status, body) = server.request("POST", "/api/seed", Some("{}"));
    assert_eq!(status, 200);
    let reseeded: Value = serde_json::from_slice(&body).unwrap();
    assert_ne!(
        reseeded["model"]["lrp"]["seed"],
        state["model"]["lrp"]["seed"]
    );
    assert_eq!(
        reseeded["model"]["lrp"]["strata"],
        state["model"]["lrp"]["strata"]
    );
    assert_ne!(server.get_ok("/tile/0/0/0.png?v=3"), edited);
}

#[test]
fn bad_parameters_are_400_naming_the_field() {
    let server = Server::start(&[&model("lrp-ring.json")]);
    // (method, path, body, status, text the message must hold)
    let cases: &[(&str, &str, Option<&str>, u16, &str)] = &[
        ("GET", "/tile/0/0/0.png?v=1&z=NaN", None, 400, "z = NaN"),
        ("GET", "/tile/0/0/0.png?v=1&z=inf", None, 400, "z = inf"),
        (
            "GET",
            "/tile/0/0/0.png?v=1&z=1e300",
            None,
            400,
            "z = 1e300 is outside its valid range",
        ),
        (
            "GET",
            "/tile/99/0/0.png?v=1",
            None,
            400,
            "zoom = 99 is outside its valid range",
        ),
        (
            "GET",
            "/tile/0/99999999/0.png?v=1",
            None,
            400,
            "x = 99999999 is outside",
        ),
        ("GET", "/tile/0/0/0.png", None, 400, "'v' is missing"),
        (
            "GET",
            "/tile/0/0/0.png?v=1&periodic=abc",
            None,
            400,
            "periodic = 'abc'",
        ),
        (
            "GET",
            "/tile/0/0/0.png?v=1&filter=2",
            None,
            400,
            "filter = '2'",
        ),
        (
            "GET",
            "/tile/0/0/0.png?v=1&size=100",
            None,
            400,
            "size = '100' is not one of 64, 256",
        ),
        // The grid's offset: a whole number of pixels within one tile.
        (
            "GET",
            "/tile/0/0/0.png?v=1&ox=NaN",
            None,
            400,
            "ox = 'NaN' is not a whole number; give one in [0, 255]",
        ),
        (
            "GET",
            "/tile/0/0/0.png?v=1&oy=-1",
            None,
            400,
            "oy = -1 is outside its valid range [0, 255]",
        ),
        (
            "GET",
            "/tile/-2/0/0.png?v=1&q=c&size=64&ox=256",
            None,
            400,
            "ox = 256 is outside its valid range [0, 255]",
        ),
        (
            "GET",
            "/tile/0/0/0.png?v=1&oy=2.5",
            None,
            400,
            "oy = '2.5' is not a whole number",
        ),
        (
            "GET",
            "/tile/0/0/0.png?v=1&foo=1",
            None,
            400,
            "unknown parameter 'foo'",
        ),
        (
            "GET",
            "/tile/0/0/0.png?v=1&v=1",
            None,
            400,
            "'v' is given twice",
        ),
        (
            "GET",
            "/render?w=100000",
            None,
            400,
            "w = 100000 is outside its valid range",
        ),
        (
            "GET",
            "/render?w=5000&h=8",
            None,
            400,
            "w = 5000 is outside its valid range [1, 4096]",
        ),
        (
            "GET",
            "/render?scale=0",
            None,
            400,
            "scale = 0 is outside its valid range",
        ),
        (
            "GET",
            "/render?x=1e300",
            None,
            400,
            "x = 1e300 is outside its valid range",
        ),
        ("GET", "/render?y=-inf", None, 400, "y = -inf is not finite"),
        (
            "GET",
            "/render?format=gif",
            None,
            400,
            "format = 'gif' is not one of png, exr",
        ),
        ("GET", "/render?x=%zz", None, 400, "malformed %-escape"),
        ("GET", "/assets/../../Cargo.toml", None, 404, "no page"),
        ("GET", "/assets/%2e%2e/Cargo.toml", None, 404, "no page"),
        ("DELETE", "/api/state", None, 405, "only GET and POST"),
        (
            "POST",
            "/api/set",
            Some(r#"{"pointer": "/lrp/strata/0/window_width", "value": 0.1}"#),
            400,
            "lrp.strata[0].window_width = 0.1",
        ),
        (
            "POST",
            "/api/set",
            Some(r#"{"pointer": "/lrp/strata/0/window_width", "value": 0.1}"#),
            400,
            "[0.5, 1e6]",
        ),
        (
            "POST",
            "/api/set",
            Some(r#"{"pointer": "/lrp/mean", "value": "high"}"#),
            400,
            "/lrp/mean",
        ),
        (
            "POST",
            "/api/set",
            Some(r#"{"pointer": "/lrp/seed", "value": -1}"#),
            400,
            "/lrp/seed",
        ),
        (
            "POST",
            "/api/set",
            Some(r#"{"pointer": "/lrp/nope", "value": 1}"#),
            400,
            "no field /lrp/nope",
        ),
        ("POST", "/api/set", Some("{not json"), 400, "not JSON"),
        (
            "POST",
            "/api/fit",
            Some(r#"{"budget": 3}"#),
            400,
            "needs an image",
        ),
        (
            "POST",
            "/api/view?s=a&zoom=0&x0=1&y0=0&x1=0&y1=1",
            None,
            400,
            "x1 and y1",
        ),
        (
            "POST",
            "/api/close?s=../etc",
            None,
            400,
            "s = '../etc' is not a session id",
        ),
    ];
    for (method, path, body, status, text) in cases {
        let (got, reply) = server.request(method, path, *body);
        let reply = String::from_utf8_lossy(&reply);
        assert_eq!(got, *status, "{method} {path}: {reply}");
        assert!(
            reply.contains(text),
            "{method} {path}: {reply:?} lacks {text:?}"
        );
    }
    // Nothing of that changed the model or stopped the server.
    assert_eq!(server.state()["version"], 1);
}

#[test]
fn an_image_is_fitted_on_open_and_refitted_with_its_controls() {
    let server = Server::start(&[]);
    let started = Instant::now();
    let fitted = loop {
        let state = server.state();
        if state["image"]["fitting"].is_null() && state["version"] == 1 {
            break state;
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no fit: {state}"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(fitted["image"]["error"].is_null(), "{fitted}");
    // The model `spectex fit` makes with the same (default) options.
    let dir = scratch("view-fit");
    let out = dir.join("fit.json");
    spectex_ok(&["fit", "-o", s(&out)]);
    let cli = spectex_model::from_json_file(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let served = server.get_ok("/api/model.json");
    let view = spectex_model::from_json_file(std::str::from_utf8(&served).unwrap()).unwrap();
    assert!(
        cli.model == view.model,
        "the view's fit is not spectex fit's"
    );
    for path in [
        "/api/exemplar.png",
        "/api/spectrum/exemplar.png",
        "/api/spectrum/synthesis.png",
    ] {
        let png = spectex_testkit::image_files::load_from_memory(&server.get_ok(path)).unwrap();
        assert!(png.width() >= 32, "{path}");
    }
    let (status, reply) = server.request("POST", "/api/fit", Some(r#"{"structure": 7}"#));
    assert_eq!(status, 400);
    assert!(String::from_utf8_lossy(&reply).contains("structure"));
    let (status, reply) = server.request(
        "POST",
        "/api/fit",
        Some(r#"{"structure": 0.2, "budget": 12}"#),
    );
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&reply));
    let refitted = loop {
        let state = server.state();
        if state["image"]["fitting"].is_null() && state["version"] == 2 {
            break state;
        }
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no refit: {state}"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(
        refitted["kind"], "texture",
        "structure makes a texture model"
    );
    assert_eq!(refitted["image"]["params"]["budget"], 12);
}

#[test]
fn a_burst_of_200_tile_requests_stays_within_a_memory_bound() {
    let server = Server::start(&[&model("classic-perlin-fbm.json")]);
    let _ = server.get_ok("/tile/0/0/0.png?v=1");
    let Some(before) = server.peak_kib() else {
        eprintln!("SKIPPED: the memory bound needs /proc/PID/status (Linux)");
        return;
    };
    let started = Instant::now();
    let handles: Vec<_> = (0..200)
        .map(|i| {
            let addr = server.addr.clone();
            std::thread::spawn(move || {
                request(
                    &addr,
                    "GET",
                    &format!("/tile/0/{}/{}.png?v=1", i % 20, i / 20),
                    None,
                )
                .0
            })
        })
        .collect();
    let statuses: Vec<u16> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    let seconds = started.elapsed().as_secs_f64();
    let after = server.peak_kib().unwrap();
    let ok = statuses.iter().filter(|s| **s == 200).count();
    // Every request answered: rendered, or refused at once when the queue is full.
    assert!(
        statuses.iter().all(|s| *s == 200 || *s == 503),
        "{statuses:?}"
    );
    assert!(ok >= 100, "only {ok} of 200 tiles rendered");
    let grown_mib = after.saturating_sub(before) as f64 / 1024.0;
    eprintln!(
        "burst: 200 tile requests, {ok} rendered in {seconds:.2} s; peak resident memory \
         {:.1} MiB → {:.1} MiB (+{grown_mib:.1} MiB)",
        before as f64 / 1024.0,
        after as f64 / 1024.0
    );
    // Two workers hold one 256² tile each (≈ 0.3 MiB), the cache holds at most 64 MiB of
    // encoded tiles (here 200 × ≈ 60 KiB), each waiting connection a thread and its request
    // line. Unbounded work would hold 200 renders at once.
    assert!(grown_mib < 96.0, "memory grew by {grown_mib:.1} MiB");
}

#[test]
fn tiles_a_tab_no_longer_shows_are_not_rendered() {
    // One worker, held by a streamed download the client does not read: the tabs' tiles wait.
    let server = Server::with_workers(&[&model("classic-perlin-fbm.json")], "1");
    let mut busy = TcpStream::connect(&server.addr).unwrap();
    write!(
        busy,
        "GET /render?w=16384&h=16384&download=1 HTTP/1.1\r\nHost: x\r\n\r\n"
    )
    .unwrap();
    let mut status = [0u8; 12];
    busy.read_exact(&mut status).unwrap();
    assert_eq!(&status, b"HTTP/1.1 200");
    let addr = server.addr.clone();
    let ask = |path: &'static str| {
        let addr = addr.clone();
        std::thread::spawn(move || request(&addr, "GET", path, None).0)
    };
    let outside = ask("/tile/0/50/50.png?v=1&s=tab1");
    let inside = ask("/tile/0/1/0.png?v=1&s=tab1");
    let other_level = ask("/tile/-3/0/0.png?v=1&s=tab1");
    let closed = ask("/tile/0/0/0.png?v=1&s=tab2");
    std::thread::sleep(Duration::from_millis(300));
    // Then the tabs move (tab1 to the origin at zoom 0) and close (tab2) …
    let view = "/api/view?s=tab1&zoom=0&x0=0&y0=0&x1=1024&y1=768";
    assert_eq!(server.request("POST", view, None).0, 200);
    assert_eq!(server.request("POST", "/api/close?s=tab2", None).0, 200);
    // … and the download's browser goes away, which stops that render and frees the worker.
    drop(busy);
    assert_eq!(outside.join().unwrap(), 410, "a tile out of the tab's view");
    assert_eq!(
        other_level.join().unwrap(),
        410,
        "a tile of a level it left"
    );
    assert_eq!(closed.join().unwrap(), 410, "a tile of a closed tab");
    assert_eq!(inside.join().unwrap(), 200, "a tile in view");
}

#[test]
fn a_tile_stops_rendering_when_the_model_changes() {
    // One worker and one rayon thread: the tile's bands are rendered one after another, and a
    // zoomed-out LRP tile takes longer (about 0.5 s here) than the waits before the model
    // changes.
    let server = Server::with_env(
        &[&model("lrp-gravel.json")],
        "1",
        &[("RAYON_NUM_THREADS", "1")],
    );
    // The tile must have started rendering before the seed changes. Under load its request can
    // reach the server after the change (then answered 409 before any rendering, which is not
    // what this test is about): the scenario is repeated with a longer wait, a new version each
    // time, until the tile is stopped while it renders.
    for (attempt, wait_ms) in [50u64, 150, 300].into_iter().enumerate() {
        let version = attempt + 1;
        let addr = server.addr.clone();
        let asked = Instant::now();
        let path = format!("/tile/-4/0/0.png?v={version}");
        let tile = std::thread::spawn(move || request(&addr, "GET", &path, None));
        std::thread::sleep(Duration::from_millis(wait_ms));
        assert_eq!(server.request("POST", "/api/seed", Some("{}")).0, 200);
        let (status, body) = tile.join().unwrap();
        let text = String::from_utf8_lossy(&body);
        assert_eq!(status, 409, "{text}");
        let next = format!("v={}", version + 1);
        if !text.contains("changed while this tile rendered") {
            assert!(text.contains(&next), "{text}");
            eprintln!("stale tile: asked after the change (waited {wait_ms} ms); again");
            continue;
        }
        assert!(text.contains(&next), "{text}");
        eprintln!(
            "stale tile: answered 409 {:.0} ms after it was asked for",
            asked.elapsed().as_secs_f64() * 1e3
        );
        return;
    }
    panic!("the tile's request never reached the server before the seed changed");
}

#[test]
fn a_simulation_steps_live_as_spectex_simulate_runs_it() {
    let dir = scratch("view-sim");
    let spec = dir.join("gs.json");
    let cli = dir.join("cli.png");
    spectex_ok(&[
        "simulate",
        "gray-scott",
        "--size",
        "64x48",
        "--steps",
        "50",
        "-o",
        s(&cli),
        "--save-params",
        s(&spec),
    ]);
    let server = Server::start(&[s(&spec)]);
    let state = server.state();
    assert_eq!(state["simulation"]["name"], "gray-scott");
    assert_eq!(
        state["simulation"]["panel"]["fields"]["/simulation/gray_scott/feed"]["range"],
        "[0, 0.1]"
    );
    // 30 steps, then 20 more: the frame `spectex simulate` writes after 50.
    let _ = server.get_ok("/api/sim/frame.png?steps=30");
    let frame = spectex_testkit::image_files::load_from_memory(
        &server.get_ok("/api/sim/frame.png?steps=20"),
    )
    .unwrap();
    let expected = spectex_testkit::image_files::open(&cli).unwrap();
    assert_eq!((frame.width(), frame.height()), (64, 48));
    assert!(
        frame.to_luma8().as_raw() == expected.to_luma8().as_raw(),
        "the live frame differs from spectex simulate's"
    );
    for (body, text) in [
        (
            r#"{"pointer": "/simulation/gray_scott/feed", "value": 5}"#,
            "feed = 5 is outside its valid range [0, 0.1]",
        ),
        (
            r#"{"pointer": "/width", "value": 5000}"#,
            "width = 5000 is outside the view's range",
        ),
    ] {
        let (status, reply) = server.request("POST", "/api/sim/set", Some(body));
        assert_eq!(status, 400);
        assert!(String::from_utf8_lossy(&reply).contains(text), "{reply:?}");
    }
    let (status, _) = server.request(
        "POST",
        "/api/sim/set",
        Some(r#"{"pointer": "/simulation/gray_scott/feed", "value": 0.03}"#),
    );
    assert_eq!(status, 200);
    assert_eq!(server.state()["simulation"]["steps_done"], 0, "restarted");
    assert_eq!(
        server
            .request("GET", "/api/sim/frame.png?steps=99999", None)
            .0,
        400
    );
}
