//! The view's HTTP routes: the page and its assets, the model's state and edits, tiles and
//! renders (queued for the workers), downloads, and the fit of an image.

use std::collections::{HashMap, VecDeque};
use std::io::Read as _;
use std::path::Path;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use anyhow::{Result, anyhow};
use serde_json::{Value, json};
use spectex_cpu::{Evaluator, Window};
use spectex_model::simulation::SimulationSpec;
use spectex_model::{MAX_POSITION, Model, Period};
use spectex_simulate::Simulator;

use super::fitting::{self, Exemplar, FitParams};
use super::panel;
use super::query::{HttpError, Query};
use super::queue::JobQueue;
use super::tiles::{self, Renderer};
use crate::render::filter_flag;

/// Side of a tile, pixels.
pub(crate) const TILE: usize = 256;
/// The sides a tile may ask for (`size`): [`TILE`], and the page's coarse tiles, a quarter of
/// it, each covering exactly the region of one full-resolution tile.
const TILE_SIZES: [&str; 2] = ["64", "256"];
/// Zoom levels: scale `2^-zoom` model pixels per screen pixel, from `2^19` (under the render's
/// 1e6 cap) down to `2^-24`.
const MIN_ZOOM: i64 = -19;
/// The finest zoom level.
const MAX_ZOOM: i64 = 24;
/// Largest side of a render answered from memory (PNG or OpenEXR).
const MAX_RENDER_SIDE: i64 = 4096;
/// Largest side of a streamed PNG download.
const MAX_STREAM_SIDE: i64 = 16_384;
/// Largest side of a simulation grid stepped live (a larger one from the file is kept as is).
const MAX_SIM_SIDE: u32 = 2048;
/// Bytes of encoded tiles kept.
const CACHE_BYTES: usize = 64 << 20;
/// Largest request body.
const MAX_BODY: u64 = 1 << 16;
/// A tab not heard from for this long is gone: its queued tiles are dropped.
const SESSION_TIMEOUT: Duration = Duration::from_secs(30);
/// Sessions remembered at most.
const MAX_SESSIONS: usize = 256;

/// What the view shows: a model file, or an image to fit.
pub(crate) enum Source {
    /// A model, with the period its file records and the file's name.
    Model(Box<Model>, Option<Period>, String),
    /// An image, fitted on open.
    Image(Box<Exemplar>),
    /// A simulation spec (`spectex simulate --save-params`), stepped live.
    Simulation(Box<SimulationSpec>),
}

impl Source {
    /// The model file at `path`, read and validated.
    pub(crate) fn model_file(path: &Path) -> Result<Self> {
        if let Ok(text) = std::fs::read_to_string(path)
            && let Ok(spec) = spectex_model::simulation::spec_from_json(&text)
        {
            return Ok(Self::Simulation(Box::new(spec)));
        }
        let file = crate::model_file::read_model_file(path)?;
        Ok(Self::Model(
            Box::new(file.model),
            file.period,
            path.display().to_string(),
        ))
    }

    /// The image at `path`, or the built-in exemplar.
    pub(crate) fn image(path: Option<&Path>) -> Result<Self> {
        let (loaded, name) = crate::load_input(path)?;
        Ok(Self::Image(Box::new(Exemplar::new(loaded.pixels, name)?)))
    }
}

/// What a renderer is for besides the model: the plane z (its bits) and the period.
type RendererKey = (u64, Option<[u32; 2]>);

/// The model being shown, and what is prepared for it.
struct Current {
    /// Bumped by every change; tiles name the version they are for.
    version: u64,
    /// The model (`None` while an image's first fit runs).
    model: Option<Model>,
    /// The model as JSON (`{"kind": {…}}`), what the panel edits.
    json: Value,
    /// The period the model file records.
    file_period: Option<Period>,
    /// The panel's description ([`panel::describe`]).
    panel: Value,
    /// Whether the model changes with z.
    three_d: bool,
    /// Renderers for this version by `(z bits, period)`, most recent last.
    renderers: Vec<(RendererKey, Arc<Renderer>)>,
}

/// What an image's fit is doing.
#[derive(Default)]
struct FitStatus {
    /// Its parameters.
    params: FitParams,
    /// When the running fit started.
    running: Option<Instant>,
    /// The last fit's error.
    error: Option<String>,
    /// Seconds the last fit took.
    seconds: Option<f64>,
}

/// A tab: when it was last heard from and the region it shows.
struct Session {
    /// Last request.
    seen: Instant,
    /// Closed (the tab said so).
    closed: bool,
    /// The zoom level shown and its region, `[x0, y0, x1, y1]` in model pixels, widened by a
    /// margin.
    view: Option<(i64, [f64; 4])>,
    /// When the tab said so.
    view_at: Instant,
}

/// Encoded tiles by key, dropped oldest first past [`CACHE_BYTES`].
#[derive(Default)]
struct Cache {
    /// Tiles by key.
    tiles: HashMap<String, Arc<Vec<u8>>>,
    /// Keys, oldest first.
    order: VecDeque<String>,
    /// Bytes held.
    bytes: usize,
}

impl Cache {
    /// Keeps `bytes` under `key`.
    fn put(&mut self, key: String, bytes: Arc<Vec<u8>>) {
        if self.tiles.contains_key(&key) {
            return;
        }
        self.bytes += bytes.len();
        self.order.push_back(key.clone());
        self.tiles.insert(key, bytes);
        while self.bytes > CACHE_BYTES {
            let Some(old) = self.order.pop_front() else {
                break;
            };
            if let Some(b) = self.tiles.remove(&old) {
                self.bytes -= b.len();
            }
        }
    }
}

/// State shared by the dispatcher and the workers.
pub(crate) struct Shared {
    /// The model shown.
    current: Mutex<Current>,
    /// Encoded tiles.
    cache: Mutex<Cache>,
    /// Open tabs.
    sessions: Mutex<HashMap<String, Session>>,
    /// Renders waiting for a worker.
    queue: JobQueue<Job>,
    /// The GPU, when the view renders there.
    gpu: Option<spectex_gpu::GpuContext>,
    /// The image fitted, in image mode.
    exemplar: Option<Exemplar>,
    /// The fit's state, in image mode.
    fit: Mutex<FitStatus>,
    /// The model file's name (`model.json` for an image's fit), for the command lines shown.
    name: String,
    /// Render workers.
    workers: usize,
    /// The simulation stepped live, in simulation mode.
    sim: Option<Mutex<Live>>,
}

/// A simulation being stepped, and its panel.
struct Live {
    /// The spec.
    spec: SimulationSpec,
    /// The spec as JSON, what the panel edits.
    json: Value,
    /// The panel's description.
    panel: Value,
    /// The running simulation.
    sim: Simulator,
}

impl Live {
    /// A fresh run of `spec`.
    fn new(spec: SimulationSpec) -> Result<Self, HttpError> {
        let sim = Simulator::new(&spec).map_err(|e| HttpError::bad(format!("{e}")))?;
        let json = serde_json::to_value(&spec).unwrap_or(Value::Null);
        let panel = panel::describe_with(&json, &|v| panel::check_simulation(v).map(|_| ()));
        Ok(Self {
            spec,
            json,
            panel,
            sim,
        })
    }

    /// What the page shows of it.
    fn state(&self) -> Value {
        json!({
            "spec": self.json,
            "panel": self.panel,
            "name": self.spec.simulation.name(),
            "width": self.spec.width,
            "height": self.spec.height,
            "steps_done": self.sim.steps_done(),
        })
    }
}

/// A render waiting for a worker, and the request it answers.
pub(crate) struct Job {
    /// The request.
    request: tiny_http::Request,
    /// What to render.
    work: Work,
}

/// What a job renders.
enum Work {
    /// A tile (PNG), cached under `key`.
    Tile {
        /// The window.
        window: Window,
        /// Its zoom level.
        zoom: i64,
        /// When it was asked for.
        asked: Instant,
        /// The model version it is for.
        version: u64,
        /// The plane and period.
        z: f64,
        /// The period asked for.
        period: Option<Period>,
        /// Cache key.
        key: String,
        /// The tab asking.
        session: Option<String>,
    },
    /// A window in a format, as a download or not.
    Render {
        /// The window.
        window: Window,
        /// The plane.
        z: f64,
        /// The period asked for.
        period: Option<Period>,
        /// `png` or `exr`.
        format: &'static str,
        /// Attachment file name for a download.
        download: Option<String>,
    },
    /// The synthesis's spectrum at the exemplar's size.
    Spectrum,
    /// The simulation stepped this many times, then its grey frame (PNG).
    SimFrame(u64),
}

/// Locks `m`, or answers 500 when a thread panicked holding it.
fn lock<T>(m: &Mutex<T>) -> Result<MutexGuard<'_, T>, HttpError> {
    m.lock()
        .map_err(|_| HttpError::status(500, "internal: a worker failed; restart spectex view"))
}

impl Shared {
    /// The state of a view of `source`.
    pub(crate) fn new(
        source: Source,
        gpu: Option<spectex_gpu::GpuContext>,
        workers: usize,
    ) -> Self {
        let mut sim = None;
        let (model, period, name, exemplar) = match source {
            Source::Model(model, period, name) => (Some(*model), period, name, None),
            Source::Image(ex) => (None, None, "model.json".to_owned(), Some(*ex)),
            Source::Simulation(spec) => {
                sim = Live::new(*spec).ok().map(Mutex::new);
                (None, None, "simulation.json".to_owned(), None)
            }
        };
        let shared = Self {
            current: Mutex::new(Current {
                version: 0,
                model: None,
                json: Value::Null,
                file_period: period,
                panel: Value::Null,
                three_d: false,
                renderers: Vec::new(),
            }),
            cache: Mutex::new(Cache::default()),
            sessions: Mutex::new(HashMap::new()),
            queue: JobQueue::new(),
            gpu,
            exemplar,
            fit: Mutex::new(FitStatus::default()),
            name,
            workers,
            sim,
        };
        if let Some(model) = model {
            shared.install(model);
        }
        shared
    }

    /// Shows `model` from now on (a new version), with a new panel description.
    fn install(&self, model: Model) {
        let json = serde_json::to_value(&model).unwrap_or(Value::Null);
        let panel = panel::describe(&json);
        let three_d = is_three_d(&model);
        self.install_with(model, json, Some(panel), three_d);
    }

    /// Shows `model` (its JSON `json`) from now on, with `panel` or else the panel shown now (an
    /// edit of one value or of the seeds keeps the model's shape, and probing the validation of
    /// a large model again on every slider move would cost more than the render).
    fn install_with(&self, model: Model, json: Value, panel: Option<Value>, three_d: bool) {
        if let Ok(mut current) = self.current.lock() {
            current.version += 1;
            current.model = Some(model);
            current.json = json;
            if let Some(panel) = panel {
                current.panel = panel;
            }
            current.three_d = three_d;
            current.renderers.clear();
        }
    }

    /// The renderer of the current model for `version`, `z` and `period`, built on first use.
    fn renderer(
        &self,
        version: u64,
        z: f64,
        period: Option<Period>,
    ) -> Result<Arc<Renderer>, HttpError> {
        let key = (z.to_bits(), period.map(|p| p.to_array()));
        let model = {
            let current = lock(&self.current)?;
            if current.version != version {
                return Err(stale(current.version));
            }
            if let Some((_, r)) = current.renderers.iter().find(|(k, _)| *k == key) {
                return Ok(Arc::clone(r));
            }
            current
                .model
                .clone()
                .ok_or_else(|| HttpError::status(503, "the fit is still running"))?
        };
        let period = period.or(lock(&self.current)?.file_period);
        let cpu = Evaluator::with_period(&model, z, period)
            .map_err(|e| HttpError::bad(format!("{e}; check z and periodic")))?;
        let gpu = match &self.gpu {
            None => None,
            Some(context) => Some(Mutex::new(
                match period {
                    None => spectex_gpu::GpuEvaluator::new_at_z(context, &model, z),
                    Some(p) => spectex_gpu::GpuEvaluator::periodic_at_z(context, &model, z, p),
                }
                .map_err(|e| HttpError::bad(format!("{e}; check z and periodic")))?,
            )),
        };
        let renderer = Arc::new(Renderer { cpu, gpu });
        let mut current = lock(&self.current)?;
        if current.version != version {
            return Err(stale(current.version));
        }
        current.renderers.push((key, Arc::clone(&renderer)));
        if current.renderers.len() > 8 {
            current.renderers.remove(0);
        }
        Ok(renderer)
    }

    /// Whether the tab `session` still wants a tile of zoom level `zoom` covering `rect` (model
    /// pixels): one of the level it shows (or its coarse level, 2 below) within its view.
    /// A view the tab sent before `asked` says nothing of the tile: the tab may have moved.
    fn wanted(&self, session: Option<&str>, zoom: i64, rect: [f64; 4], asked: Instant) -> bool {
        let Some(id) = session else {
            return true;
        };
        let Ok(sessions) = self.sessions.lock() else {
            return true;
        };
        match sessions.get(id) {
            None => true,
            Some(s) if s.closed || s.seen.elapsed() > SESSION_TIMEOUT => false,
            Some(s) if s.view_at < asked => true,
            Some(s) => s.view.is_none_or(|(z, v)| {
                (zoom == z || zoom == z - 2)
                    && rect[0] < v[2]
                    && rect[2] > v[0]
                    && rect[1] < v[3]
                    && rect[3] > v[1]
            }),
        }
    }

    /// Notes that `session` was heard from (and what it now shows, when given).
    fn touch(&self, session: &str, view: Option<(i64, [f64; 4])>, closed: bool) {
        let Ok(mut sessions) = self.sessions.lock() else {
            return;
        };
        if !sessions.contains_key(session) && sessions.len() >= MAX_SESSIONS {
            let oldest = sessions
                .iter()
                .min_by_key(|(_, s)| s.seen)
                .map(|(k, _)| k.clone());
            if let Some(k) = oldest {
                sessions.remove(&k);
            }
        }
        let s = sessions.entry(session.to_owned()).or_insert(Session {
            seen: Instant::now(),
            closed: false,
            view: None,
            view_at: Instant::now(),
        });
        s.seen = Instant::now();
        s.closed |= closed;
        if view.is_some() {
            s.view = view;
            s.view_at = Instant::now();
        }
    }
}

/// The answer to a tile for an old model version.
fn stale(version: u64) -> HttpError {
    HttpError::status(
        409,
        format!("the model has changed; ask again with v={version}"),
    )
}

/// Whether `model` changes with z: 16 points on the planes 0 and 37.25 differ.
fn is_three_d(model: &Model) -> bool {
    let (Ok(a), Ok(b)) = (
        Evaluator::new_at_z(model, 0.0),
        Evaluator::new_at_z(model, 37.25),
    ) else {
        return false;
    };
    let points: Vec<[f64; 2]> = (0..16)
        .map(|i| [f64::from(i) * 13.7, f64::from(i) * 7.3])
        .collect();
    let n = points.len() * a.output_channels();
    let (mut va, mut vb) = (vec![0.0f32; n], vec![0.0f32; n]);
    a.eval_points(&points, &mut va);
    b.eval_points(&points, &mut vb);
    va != vb
}

/// An answer: status, content type, body and extra headers.
struct Reply {
    /// Status code.
    status: u16,
    /// Content type.
    content_type: &'static str,
    /// Body.
    body: Arc<Vec<u8>>,
    /// A download's file name.
    download: Option<String>,
    /// A `Server-Timing` header's value: where a tile's time went.
    timing: Option<String>,
}

impl Reply {
    /// 200 with `body`.
    fn ok(content_type: &'static str, body: impl Into<Vec<u8>>) -> Self {
        Self {
            status: 200,
            content_type,
            body: Arc::new(body.into()),
            download: None,
            timing: None,
        }
    }

    /// 200 JSON.
    fn json(value: &Value) -> Self {
        Self::ok("application/json", value.to_string())
    }

    /// The error's answer: its status and its message as text.
    fn error(e: &HttpError) -> Self {
        Self {
            status: e.status,
            content_type: "text/plain; charset=utf-8",
            body: Arc::new(format!("{}\n", e.message).into_bytes()),
            download: None,
            timing: None,
        }
    }
}

/// A header from two ASCII strings (`None` for anything else, never the case here).
fn header(name: &str, value: &str) -> Option<tiny_http::Header> {
    tiny_http::Header::from_bytes(name.as_bytes(), value.as_bytes()).ok()
}

/// The headers of an answer.
fn headers(content_type: &str, download: Option<&str>) -> Vec<tiny_http::Header> {
    let mut h = vec![
        header("Content-Type", content_type),
        header("Cache-Control", "no-store"),
        header("X-Content-Type-Options", "nosniff"),
    ];
    if let Some(name) = download {
        h.push(header(
            "Content-Disposition",
            &format!("attachment; filename=\"{name}\""),
        ));
    }
    h.into_iter().flatten().collect()
}

/// A shared body as a response's bytes.
struct Body(Arc<Vec<u8>>);

impl AsRef<[u8]> for Body {
    fn as_ref(&self) -> &[u8] {
        self.0.as_slice()
    }
}

/// Sends `reply` (a client gone by then is not an error of the server's).
fn respond(request: tiny_http::Request, reply: Reply) {
    let len = reply.body.len();
    let mut headers = headers(reply.content_type, reply.download.as_deref());
    headers.extend(reply.timing.and_then(|t| header("Server-Timing", &t)));
    let response = tiny_http::Response::new(
        tiny_http::StatusCode(reply.status),
        headers,
        std::io::Cursor::new(Body(reply.body)),
        Some(len),
        None,
    );
    let _ = request.respond(response);
}

/// The page and its assets: a fixed list, so no request names a path on disk.
fn asset(path: &str) -> Option<Reply> {
    let (content_type, body): (&'static str, &'static [u8]) = match path {
        "/" | "/index.html" => (
            "text/html; charset=utf-8",
            include_bytes!("assets/index.html"),
        ),
        "/assets/app.js" => (
            "text/javascript; charset=utf-8",
            include_bytes!("assets/app.js"),
        ),
        "/assets/app.css" => ("text/css; charset=utf-8", include_bytes!("assets/app.css")),
        "/assets/leaflet.js" => (
            "text/javascript; charset=utf-8",
            include_bytes!("assets/leaflet.js"),
        ),
        "/assets/leaflet.css" => (
            "text/css; charset=utf-8",
            include_bytes!("assets/leaflet.css"),
        ),
        "/assets/LICENSE-leaflet" => (
            "text/plain; charset=utf-8",
            include_bytes!("assets/LICENSE-leaflet"),
        ),
        _ => return None,
    };
    Some(Reply::ok(content_type, body))
}

/// Serves requests from `server` until it stops: the dispatcher here, renders on the workers.
pub(crate) fn serve(server: &tiny_http::Server, shared: &Arc<Shared>) {
    if shared.exemplar.is_some() {
        let params = shared.fit.lock().map(|f| f.params).unwrap_or_default();
        start_fit(shared, params);
    }
    for _ in 0..shared.workers {
        let shared = Arc::clone(shared);
        std::thread::spawn(move || {
            while let Some(job) = shared.queue.pop() {
                work(&shared, job);
            }
        });
    }
    for mut request in server.incoming_requests() {
        let url = request.url().to_owned();
        let (path, query) = url.split_once('?').unwrap_or((url.as_str(), ""));
        let method = request.method().clone();
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            route(shared, &method, path, query, &mut request)
        }));
        match outcome {
            Ok(Ok(Routed::Reply(reply))) => respond(request, reply),
            Ok(Ok(Routed::Queue(work, coarse))) => {
                if let Err(job) = shared.queue.push(Job { request, work }, coarse) {
                    respond(
                        job.request,
                        Reply::error(&HttpError::status(
                            503,
                            "busy: too many renders are waiting; ask again shortly",
                        )),
                    );
                }
            }
            Ok(Err(e)) => respond(request, Reply::error(&e)),
            Err(_) => respond(
                request,
                Reply::error(&HttpError::status(500, "internal error while routing")),
            ),
        }
    }
}

/// What the dispatcher does with a request.
enum Routed {
    /// Answer now.
    Reply(Reply),
    /// Queue for a worker (in the coarse lane when `true`).
    Queue(Work, bool),
}

/// Routes one request.
fn route(
    shared: &Arc<Shared>,
    method: &tiny_http::Method,
    path: &str,
    query: &str,
    request: &mut tiny_http::Request,
) -> Result<Routed, HttpError> {
    use tiny_http::Method::{Get, Post};
    let reply = |r| Ok(Routed::Reply(r));
    if *method == Get
        && let Some(r) = asset(path)
    {
        Query::parse(query, &["v"])?;
        return reply(r);
    }
    match (method, path) {
        (Get, "/api/state") => {
            Query::parse(query, &[])?;
            reply(Reply::json(&state(shared)?))
        }
        (Post, "/api/set") => {
            Query::parse(query, &[])?;
            let body = read_json(request)?;
            set_field(shared, &body)?;
            reply(Reply::json(&state(shared)?))
        }
        (Post, "/api/seed") => {
            Query::parse(query, &[])?;
            let (model, three_d) = {
                let current = lock(&shared.current)?;
                let model = current
                    .model
                    .as_ref()
                    .map(|m| m.reseeded(0x9E37_79B9))
                    .ok_or_else(|| HttpError::status(503, "the fit is still running"))?;
                (model, current.three_d)
            };
            let json = serde_json::to_value(&model).unwrap_or(Value::Null);
            shared.install_with(model, json, None, three_d);
            reply(Reply::json(&state(shared)?))
        }
        (Post, "/api/fit") => {
            Query::parse(query, &[])?;
            let body = read_json(request)?;
            if shared.exemplar.is_none() {
                return Err(HttpError::bad(
                    "this view shows a model file; fitting needs an image (spectex view IMAGE)",
                ));
            }
            let params = {
                let fit = lock(&shared.fit)?;
                if fit.running.is_some() {
                    return Err(HttpError::status(409, "a fit is running; wait for it"));
                }
                fit.params.updated(&body)?
            };
            start_fit(shared, params);
            reply(Reply::json(&state(shared)?))
        }
        (Post, "/api/view") => {
            let q = Query::parse(query, &["s", "zoom", "x0", "y0", "x1", "y1"])?;
            let zoom = q.int_in("zoom", None, MIN_ZOOM, MAX_ZOOM)?;
            let session = q
                .session("s")?
                .ok_or_else(|| HttpError::bad("parameter 's' (the session) is missing"))?;
            let coord = |name| q.f64_in(name, None, -2.0 * MAX_POSITION, 2.0 * MAX_POSITION);
            let view = [coord("x0")?, coord("y0")?, coord("x1")?, coord("y1")?];
            if view[2] < view[0] || view[3] < view[1] {
                return Err(HttpError::bad("x1 and y1 must not be below x0 and y0"));
            }
            // A margin of half the view on each side: tiles just out of sight are still kept.
            let (mx, my) = ((view[2] - view[0]) / 2.0, (view[3] - view[1]) / 2.0);
            let view = [view[0] - mx, view[1] - my, view[2] + mx, view[3] + my];
            shared.touch(&session, Some((zoom, view)), false);
            reply(Reply::json(&json!({ "ok": true })))
        }
        (Post, "/api/close") => {
            let q = Query::parse(query, &["s"])?;
            let session = q
                .session("s")?
                .ok_or_else(|| HttpError::bad("parameter 's' (the session) is missing"))?;
            shared.touch(&session, None, true);
            reply(Reply::json(&json!({ "ok": true })))
        }
        (Get, "/api/model.json") => {
            Query::parse(query, &["periodic"])?;
            let current = lock(&shared.current)?;
            let model = current
                .model
                .as_ref()
                .ok_or_else(|| HttpError::status(503, "the fit is still running"))?;
            let text = spectex_model::to_json_file(model, None, current.file_period)
                .map_err(|e| HttpError::status(500, format!("internal: {e}")))?;
            let mut r = Reply::ok("application/json", text);
            r.download = Some("model.json".to_owned());
            reply(r)
        }
        (Get, "/api/model.wgsl") => {
            let q = Query::parse(query, &["z"])?;
            let z = q.f64_in("z", Some(0.0), -MAX_POSITION, MAX_POSITION)?;
            let model = lock(&shared.current)?
                .model
                .clone()
                .ok_or_else(|| HttpError::status(503, "the fit is still running"))?;
            let options = spectex_gpu::export::ExportOptions {
                z,
                tables: spectex_gpu::export::TableStorage::Constants,
            };
            let exported = spectex_gpu::export::export(&model, &options)
                .map_err(|e| HttpError::bad(format!("cannot export this model: {e}")))?;
            let mut r = Reply::ok("text/plain; charset=utf-8", exported.wgsl);
            r.download = Some("model.wgsl".to_owned());
            reply(r)
        }
        (Get, "/api/exemplar.png" | "/api/spectrum/exemplar.png") => {
            Query::parse(query, &["v"])?;
            let ex = shared
                .exemplar
                .as_ref()
                .ok_or_else(|| HttpError::status(404, "this view shows a model, not an image"))?;
            let bytes = if path.ends_with("exemplar.png") && path.contains("spectrum") {
                ex.spectrum.clone()
            } else {
                ex.png.clone()
            };
            reply(Reply::ok("image/png", bytes))
        }
        (Get, "/api/spectrum/synthesis.png") => {
            Query::parse(query, &["v"])?;
            if shared.exemplar.is_none() {
                return Err(HttpError::status(
                    404,
                    "this view shows a model, not an image",
                ));
            }
            Ok(Routed::Queue(Work::Spectrum, false))
        }
        (Get, "/favicon.ico") => Ok(Routed::Reply(Reply {
            status: 204,
            content_type: "image/x-icon",
            body: Arc::new(Vec::new()),
            download: None,
            timing: None,
        })),
        (Get, "/render") => render_request(query),
        (Get, "/api/sim/frame.png") => {
            let q = Query::parse(query, &["steps", "t"])?;
            let steps = q.int_in("steps", Some(0), 0, 10_000)? as u64;
            live(shared)?;
            Ok(Routed::Queue(Work::SimFrame(steps), true))
        }
        (Post, "/api/sim/set") => {
            Query::parse(query, &[])?;
            let body = read_json(request)?;
            let mut live = lock(live(shared)?)?;
            let pointer = body
                .get("pointer")
                .and_then(Value::as_str)
                .ok_or_else(|| HttpError::bad("the body needs \"pointer\": a JSON pointer"))?;
            let value = body
                .get("value")
                .ok_or_else(|| HttpError::bad("the body needs \"value\""))?;
            let mut json = live.json.clone();
            let slot = json
                .pointer_mut(pointer)
                .filter(|v| !v.is_object() && !v.is_array())
                .ok_or_else(|| HttpError::bad(format!("the spec has no value at {pointer}")))?;
            *slot = value.clone();
            let spec = panel::check_simulation(&json)
                .map_err(|e| HttpError::bad(format!("{pointer}: {e}")))?;
            for (name, side) in [("width", spec.width), ("height", spec.height)] {
                if side > MAX_SIM_SIDE {
                    return Err(HttpError::bad(format!(
                        "{name} = {side} is outside the view's range [1, {MAX_SIM_SIDE}] \
                         (larger grids: spectex simulate)"
                    )));
                }
            }
            let panel = std::mem::take(&mut live.panel);
            let sim = Simulator::new(&spec).map_err(|e| HttpError::bad(format!("{e}")))?;
            *live = Live {
                spec,
                json,
                panel,
                sim,
            };
            drop(live);
            reply(Reply::json(&state(shared)?))
        }
        (Post, "/api/sim/reset") => {
            let q = Query::parse(query, &["reseed"])?;
            let mut live = lock(live(shared)?)?;
            let mut spec = live.spec.clone();
            if q.flag("reseed", false)? {
                spec.seed = spec.seed.wrapping_add(1);
            }
            let panel = std::mem::take(&mut live.panel);
            let sim = Simulator::new(&spec).map_err(|e| HttpError::bad(format!("{e}")))?;
            let json = serde_json::to_value(&spec).unwrap_or(Value::Null);
            *live = Live {
                spec,
                json,
                panel,
                sim,
            };
            drop(live);
            reply(Reply::json(&state(shared)?))
        }
        (Get, _) if path.starts_with("/tile/") => tile_request(shared, path, query),
        (Get | Post, _) => Err(HttpError::status(404, format!("no page {path}"))),
        _ => Err(HttpError::status(405, "only GET and POST are served")),
    }
}

/// The request body as JSON (at most [`MAX_BODY`] bytes).
fn read_json(request: &mut tiny_http::Request) -> Result<Value, HttpError> {
    let mut body = Vec::new();
    request
        .as_reader()
        .take(MAX_BODY + 1)
        .read_to_end(&mut body)
        .map_err(|e| HttpError::bad(format!("cannot read the body: {e}")))?;
    if body.len() as u64 > MAX_BODY {
        return Err(HttpError::status(
            413,
            format!("the body is over {MAX_BODY} bytes"),
        ));
    }
    serde_json::from_slice(&body).map_err(|e| HttpError::bad(format!("the body is not JSON: {e}")))
}

/// The view's state for the page.
fn state(shared: &Shared) -> Result<Value, HttpError> {
    let current = lock(&shared.current)?;
    let image = match &shared.exemplar {
        None => Value::Null,
        Some(ex) => {
            let fit = lock(&shared.fit)?;
            let (w, h) = ex.size();
            json!({
                "name": ex.name,
                "width": w,
                "height": h,
                "params": fit.params.to_json(),
                "fitting": fit.running.map(|t| t.elapsed().as_secs_f64()),
                "error": fit.error,
                "seconds": fit.seconds,
            })
        }
    };
    Ok(json!({
        "version": current.version,
        "kind": current.model.as_ref().map(Model::kind),
        "model": current.json,
        "panel": current.panel,
        "three_d": current.three_d,
        "period": current.file_period.map(|p| p.to_string()),
        "name": shared.name,
        "device": if shared.gpu.is_some() { "GPU" } else { "CPU" },
        "workers": shared.workers,
        "tile": TILE,
        "zoom": [MIN_ZOOM, MAX_ZOOM],
        "image": image,
        "simulation": match &shared.sim {
            None => Value::Null,
            Some(live) => lock(live)?.state(),
        },
    }))
}

/// The simulation, or 404 outside simulation mode.
fn live(shared: &Shared) -> Result<&Mutex<Live>, HttpError> {
    shared.sim.as_ref().ok_or_else(|| {
        HttpError::status(
            404,
            "this view shows no simulation (spectex view SIMULATION.json)",
        )
    })
}

/// `POST /api/set {"pointer": "/lrp/mean", "value": 0.5}`: the model with that field changed,
/// if validation accepts it (else 400 naming the field and its range).
fn set_field(shared: &Shared, body: &Value) -> Result<(), HttpError> {
    let pointer = body
        .get("pointer")
        .and_then(Value::as_str)
        .ok_or_else(|| HttpError::bad("the body needs \"pointer\": a JSON pointer to a field"))?;
    let value = body
        .get("value")
        .ok_or_else(|| HttpError::bad("the body needs \"value\""))?;
    if let Some(v) = value.as_f64()
        && !v.is_finite()
    {
        return Err(HttpError::bad(format!("{pointer} = {v} is not finite")));
    }
    let (mut json, three_d) = {
        let current = lock(&shared.current)?;
        (current.json.clone(), current.three_d)
    };
    let slot = json
        .pointer_mut(pointer)
        .ok_or_else(|| HttpError::bad(format!("the model has no field {pointer}")))?;
    if slot.is_object() || slot.is_array() {
        return Err(HttpError::bad(format!(
            "{pointer} is not a single value; set its fields one by one"
        )));
    }
    *slot = value.clone();
    let model = panel::check(&json).map_err(|e| HttpError::bad(format!("{pointer}: {e}")))?;
    Evaluator::new(&model).map_err(|e| HttpError::bad(format!("{pointer}: {e}")))?;
    // A changed field can make a model 3D (a classic noise's dimensions): look again only then.
    let three_d = three_d || is_three_d(&model);
    let json = serde_json::to_value(&model).unwrap_or(Value::Null);
    shared.install_with(model, json, None, three_d);
    Ok(())
}

/// Starts a fit of the exemplar with `params` on a thread of its own.
fn start_fit(shared: &Arc<Shared>, params: FitParams) {
    if let Ok(mut fit) = shared.fit.lock() {
        fit.params = params;
        fit.running = Some(Instant::now());
        fit.error = None;
    }
    let shared = Arc::clone(shared);
    std::thread::spawn(move || {
        let Some(ex) = &shared.exemplar else {
            return;
        };
        let started = Instant::now();
        let outcome =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| fitting::fit(ex, &params)))
                .unwrap_or_else(|_| Err(anyhow!("internal: the fit panicked")));
        let seconds = started.elapsed().as_secs_f64();
        let error = match outcome {
            Ok(model) => {
                shared.install(model);
                None
            }
            Err(e) => Some(format!("{e:#}")),
        };
        if let Ok(mut fit) = shared.fit.lock() {
            fit.running = None;
            fit.seconds = Some(seconds);
            fit.error = error;
        }
    });
}

/// The plane and period parameters shared by tiles and renders.
fn plane_and_period(q: &Query) -> Result<(f64, Option<Period>, bool), HttpError> {
    let z = q.f64_in("z", Some(0.0), -MAX_POSITION, MAX_POSITION)?;
    let period = match q.text("periodic") {
        None | Some("") => None,
        Some(text) => Some(Period::parse(text).map_err(|e| {
            HttpError::bad(format!(
                "periodic = '{}': {e}; write WxH, for example 256x256",
                text.escape_default()
            ))
        })?),
    };
    let filter = q.flag("filter", true)?;
    Ok((z, period, filter))
}

/// `GET /tile/{zoom}/{tx}/{ty}.png?v&filter&z&periodic&s&q&size&ox&oy`.
fn tile_request(shared: &Shared, path: &str, query: &str) -> Result<Routed, HttpError> {
    let q = Query::parse(
        query,
        &["v", "filter", "z", "periodic", "s", "q", "size", "ox", "oy"],
    )?;
    let parts: Vec<&str> = path["/tile/".len()..].split('/').collect();
    let [zoom, tx, ty] = parts.as_slice() else {
        return Err(HttpError::bad("a tile is /tile/ZOOM/X/Y.png"));
    };
    let ty = ty
        .strip_suffix(".png")
        .ok_or_else(|| HttpError::bad("a tile is /tile/ZOOM/X/Y.png"))?;
    let int = |name: &str, text: &str, min: i64, max: i64| -> Result<i64, HttpError> {
        let v: i64 = text.parse().map_err(|_| {
            HttpError::bad(format!(
                "{name} = '{}' is not a whole number",
                text.escape_default()
            ))
        })?;
        if (min..=max).contains(&v) {
            Ok(v)
        } else {
            Err(HttpError::bad(format!(
                "{name} = {v} is outside its valid range [{min}, {max}]"
            )))
        }
    };
    let zoom = int("zoom", zoom, MIN_ZOOM, MAX_ZOOM)?;
    let scale = (-zoom as f64).exp2();
    let size: usize = q
        .choice("size", "256", &TILE_SIZES)?
        .parse()
        .map_err(|_| HttpError::status(500, "internal: a tile size is not a number"))?;
    // Tiles whose corner stays within ±2^30 model pixels (also with an offset, under a tile).
    let max_tile = (MAX_POSITION / (size as f64 * scale)).floor() as i64 - 1;
    let tx = int("x", tx, -max_tile, max_tile)?;
    let ty = int("y", ty, -max_tile, max_tile)?;
    let version = q.int_in("v", None, 0, i64::MAX)? as u64;
    let (z, period, filter) = plane_and_period(&q)?;
    let session = q.session("s")?;
    let coarse = q.choice("q", "f", &["c", "f"])? == "c";
    let current = lock(&shared.current)?.version;
    if version != current {
        return Err(stale(current));
    }
    // The grid's offset, in pixels of a full-resolution tile: the page anchors its grid to
    // the view (so an unaligned view needs no more tiles than an aligned one). A coarse tile
    // takes its fine twin's offset in those same pixels, so the two cover one region.
    let max_offset = TILE as i64 - 1;
    let ox = q.int_in("ox", Some(0), 0, max_offset)?;
    let oy = q.int_in("oy", Some(0), 0, max_offset)?;
    let side = size as f64 * scale;
    // A power of two times a whole number of pixels: the corner is exact, as `--offset` of the
    // same numbers is.
    let pixel = side / TILE as f64;
    let window = Window::new(size, size)
        .at(
            [
                tx as f64 * side + ox as f64 * pixel,
                ty as f64 * side + oy as f64 * pixel,
            ],
            scale,
        )
        .filtered(filter_flag(!filter));
    let key = format!(
        "{version}/{zoom}/{size}/{tx}/{ty}/{ox}/{oy}/{filter}/{}/{:?}",
        z.to_bits(),
        period.map(|p| p.to_array())
    );
    if let Some(id) = &session {
        shared.touch(id, None, false);
    }
    if let Some(bytes) = lock(&shared.cache)?.tiles.get(&key) {
        return Ok(Routed::Reply(Reply {
            status: 200,
            content_type: "image/png",
            body: Arc::clone(bytes),
            download: None,
            timing: Some("cache;desc=hit".to_owned()),
        }));
    }
    let asked = Instant::now();
    Ok(Routed::Queue(
        Work::Tile {
            window,
            zoom,
            asked,
            version,
            z,
            period,
            key,
            session,
        },
        coarse,
    ))
}

/// `GET /render?x&y&scale&w&h&filter&z&periodic&format&download&v`: a window as `spectex
/// render` writes it.
fn render_request(query: &str) -> Result<Routed, HttpError> {
    let q = Query::parse(
        query,
        &[
            "x", "y", "scale", "w", "h", "filter", "z", "periodic", "format", "download", "v",
        ],
    )?;
    let x = q.f64_in("x", Some(0.0), -MAX_POSITION, MAX_POSITION)?;
    let y = q.f64_in("y", Some(0.0), -MAX_POSITION, MAX_POSITION)?;
    let scale = q.f64_in("scale", Some(1.0), 1e-9, 1e6)?;
    if scale <= 0.0 {
        return Err(HttpError::bad("scale must be above 0"));
    }
    let format = q.choice("format", "png", &["png", "exr"])?;
    let download = q.flag("download", false)?;
    let max = match format {
        "png" if download => MAX_STREAM_SIDE,
        "exr" => MAX_RENDER_SIDE / 2,
        _ => MAX_RENDER_SIDE,
    };
    let w = q.int_in("w", Some(TILE as i64), 1, max)? as usize;
    let h = q.int_in("h", Some(TILE as i64), 1, max)? as usize;
    let (z, period, filter) = plane_and_period(&q)?;
    let window = Window::new(w, h)
        .at([x, y], scale)
        .filtered(filter_flag(!filter));
    window
        .validate()
        .map_err(|e| HttpError::bad(format!("{e}; check x, y, scale, w and h")))?;
    Ok(Routed::Queue(
        Work::Render {
            window,
            z,
            period,
            format,
            download: download.then(|| format!("spectex-view-{w}x{h}.{format}")),
        },
        false,
    ))
}

/// A worker's handling of one job.
fn work(shared: &Shared, job: Job) {
    let Job { request, work } = job;
    if let Work::Render {
        window,
        z,
        period,
        format: "png",
        download: Some(name),
    } = &work
        && (window.width as i64 > MAX_RENDER_SIDE || window.height as i64 > MAX_RENDER_SIDE)
    {
        stream_download(shared, request, window, *z, *period, name);
        return;
    }
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match work {
        Work::Tile {
            window,
            zoom,
            asked,
            version,
            z,
            period,
            key,
            session,
        } => {
            let rect = [
                window.x(0),
                window.y(0),
                window.x(window.width),
                window.y(window.height),
            ];
            let gone = || HttpError::status(410, "the tab no longer shows this tile; not rendered");
            if !shared.wanted(session.as_deref(), zoom, rect, asked) {
                return Err(gone());
            }
            let mut timing = TileTiming::new(asked);
            let renderer = shared.renderer(version, z, period)?;
            timing.lap("renderer");
            // A tile for a model version or a region no longer shown stops between bands: a
            // new seed or a slider's next step does not wait for the last one's tiles.
            let unwanted = || {
                shared.current.lock().map_or(true, |c| c.version != version)
                    || !shared.wanted(session.as_deref(), zoom, rect, asked)
            };
            let Some(samples) = renderer
                .samples_unless(&window, tiles::TILE_FORMAT, &unwanted)
                .map_err(|e| HttpError::bad(format!("{e:#}")))?
            else {
                let current = lock(&shared.current)?.version;
                return Err(if current == version {
                    gone()
                } else {
                    HttpError::status(
                        409,
                        format!(
                            "the model changed while this tile rendered (stopped); ask again \
                             with v={current}"
                        ),
                    )
                });
            };
            timing.lap("eval");
            let bytes = Arc::new(
                tiles::encode(samples, tiles::TILE_FORMAT)
                    .map_err(|e| HttpError::bad(format!("{e:#}")))?,
            );
            timing.lap("png");
            if let Ok(mut cache) = shared.cache.lock() {
                cache.put(key, Arc::clone(&bytes));
            }
            Ok(Some(Reply {
                status: 200,
                content_type: "image/png",
                body: bytes,
                download: None,
                timing: Some(timing.header()),
            }))
        }
        Work::Render {
            window,
            z,
            period,
            format,
            download,
        } => {
            let version = lock(&shared.current)?.version;
            let renderer = shared.renderer(version, z, period)?;
            let (bytes, content_type) = match format {
                "exr" => (renderer.exr(&window), "image/x-exr"),
                _ => (renderer.png(&window), "image/png"),
            };
            let mut reply = Reply::ok(
                content_type,
                bytes.map_err(|e| HttpError::bad(format!("{e:#}")))?,
            );
            reply.download = download;
            Ok(Some(reply))
        }
        Work::Spectrum => {
            let ex = shared
                .exemplar
                .as_ref()
                .ok_or_else(|| HttpError::status(404, "no image"))?;
            let version = lock(&shared.current)?.version;
            let renderer = shared.renderer(version, 0.0, None)?;
            let (w, h) = ex.size();
            let (w, h) = (w.min(tiles::MAX_SPECTRUM), h.min(tiles::MAX_SPECTRUM));
            let window = Window::new(w, h);
            let values = renderer
                .cpu
                .render(&window)
                .map_err(|e| HttpError::bad(format!("{e}")))?;
            let c = renderer.channels();
            let pixels = ndarray::Array3::from_shape_fn((c, h, w), |(ch, y, x)| {
                f64::from(values[(y * w + x) * c + ch])
            });
            let png = tiles::spectrum_png(&pixels).map_err(|e| HttpError::bad(format!("{e:#}")))?;
            Ok(Some(Reply::ok("image/png", png)))
        }
        Work::SimFrame(steps) => {
            let mut live = lock(live(shared)?)?;
            // At most a second of stepping per frame, whatever was asked.
            let started = Instant::now();
            for _ in 0..steps {
                live.sim.step();
                if started.elapsed() > Duration::from_secs(1) {
                    break;
                }
            }
            let (w, h) = (live.spec.width as usize, live.spec.height as usize);
            let grey = live.sim.grey();
            let levels =
                ndarray::Array2::from_shape_fn((h, w), |(y, x)| f64::from(grey[y * w + x]));
            let png = tiles::grey_png(&levels).map_err(|e| HttpError::bad(format!("{e:#}")))?;
            Ok(Some(Reply::ok("image/png", png)))
        }
    }));
    match outcome {
        Ok(Ok(Some(reply))) => respond(request, reply),
        Ok(Ok(None)) => {}
        Ok(Err(e)) => respond(request, Reply::error(&e)),
        Err(_) => respond(
            request,
            Reply::error(&HttpError::status(500, "internal error while rendering")),
        ),
    }
}

/// Where a tile's time went, as a `Server-Timing` header (the browser's resource timings show
/// it, `curl -D -` too): waiting in the queue, then each step a worker took.
struct TileTiming {
    /// The end of the last step.
    at: Instant,
    /// `name;dur=MS` of each step.
    steps: Vec<String>,
}

impl TileTiming {
    /// Timing of a tile asked for at `asked`, starting now with its wait in the queue.
    fn new(asked: Instant) -> Self {
        let at = Instant::now();
        let mut timing = Self {
            at,
            steps: Vec::new(),
        };
        timing.push("queue", at - asked);
        timing
    }

    /// Ends the step `name`.
    fn lap(&mut self, name: &str) {
        let now = Instant::now();
        self.push(name, now - self.at);
        self.at = now;
    }

    /// Notes `name` took `time`.
    fn push(&mut self, name: &str, time: Duration) {
        self.steps
            .push(format!("{name};dur={:.1}", time.as_secs_f64() * 1e3));
    }

    /// The header's value.
    fn header(self) -> String {
        self.steps.join(", ")
    }
}

/// A large PNG download, rendered band by band while it is sent (chunked): memory holds a band,
/// and the render stops when the browser goes away (a write fails).
fn stream_download(
    shared: &Shared,
    request: tiny_http::Request,
    window: &Window,
    z: f64,
    period: Option<Period>,
    name: &str,
) {
    let renderer = match lock(&shared.current)
        .map(|c| c.version)
        .and_then(|v| shared.renderer(v, z, period))
    {
        Ok(r) => r,
        Err(e) => return respond(request, Reply::error(&e)),
    };
    if let Err(e) = renderer.cpu.check_window(window) {
        return respond(request, Reply::error(&HttpError::bad(format!("{e}"))));
    }
    let (writer, reader) = tiles::channel();
    std::thread::scope(|scope| {
        let renderer = &renderer;
        scope.spawn(move || {
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                renderer.stream_png(window, writer)
            }));
            if let Ok(Err(e)) = outcome {
                eprintln!("note: a streamed download stopped: {e:#}");
            }
        });
        let response = tiny_http::Response::new(
            tiny_http::StatusCode(200),
            headers("image/png", Some(name)),
            reader,
            None,
            None,
        );
        let _ = request.respond(response);
    });
}
