//! Rendering a window and sampling points on the CPU with the GIL released: the evaluator's
//! own bands of rows, in parallel on its rayon pool, with Ctrl-C checked between bands.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use rayon::prelude::*;
use spectex_cpu::{Evaluator, Window};

use crate::errors::{guard, panic_error, value_error};

/// Rows evaluated together (`spectex_cpu`'s own band, whose rows share their lattice rows; the
/// values do not depend on it). Ctrl-C stops a render within one band on each thread.
const BAND_ROWS: usize = 16;

/// How often the waiting thread looks for a signal (Ctrl-C) while a render runs.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// Renders `window` with `eval` into a new buffer (`output_channels` interleaved values per
/// pixel, row-major): the bits of [`Evaluator::render`], with the GIL released and Python's
/// signal handlers run every [`SIGNAL_POLL`]. A `KeyboardInterrupt` (or any exception a handler
/// raises) stops the bands not yet started and is returned once the running ones end.
pub(crate) fn render_window(
    py: Python<'_>,
    eval: &Evaluator,
    window: &Window,
) -> PyResult<Vec<f32>> {
    eval.check_window(window).map_err(value_error)?;
    let channels = eval.output_channels();
    let row = window.width * channels;
    let mut out = zeroed(row * window.height)?;
    if out.is_empty() {
        return Ok(out);
    }
    let cancel = AtomicBool::new(false);
    let (done_tx, done_rx) = mpsc::channel::<Result<(), PyErr>>();
    // A receiver is not `Sync`; the wait below borrows it from a closure that must be `Send`.
    let done_rx = std::sync::Mutex::new(done_rx);
    let mut interrupted = None;
    std::thread::scope(|scope| {
        let (out, cancel) = (&mut out, &cancel);
        scope.spawn(move || {
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                out.par_chunks_mut(row * BAND_ROWS)
                    .enumerate()
                    .for_each(|(band, lines)| {
                        if !cancel.load(Ordering::Relaxed) {
                            eval.eval_rows(window, band * BAND_ROWS, lines);
                        }
                    });
            }))
            .map_err(|payload| panic_error(&*payload));
            // The receiver waits until this is sent; it cannot be gone.
            let _ = done_tx.send(result);
        });
        loop {
            let received = py.detach(|| match done_rx.lock() {
                Ok(rx) => rx.recv_timeout(SIGNAL_POLL),
                Err(_) => Err(mpsc::RecvTimeoutError::Disconnected),
            });
            match received {
                // A Ctrl-C that came while the last bands finished is still the caller's:
                // the render is dropped and KeyboardInterrupt raised, as if it came earlier.
                Ok(result) => {
                    if interrupted.is_none()
                        && let Err(e) = py.check_signals()
                    {
                        interrupted = Some(e);
                    }
                    return result;
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    return Err(pyo3::exceptions::PyRuntimeError::new_err(
                        "internal error in spectex: the render thread ended without a result",
                    ));
                }
            }
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                interrupted = Some(e);
            }
        }
    })?;
    match interrupted {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// `len` zeros, or a `MemoryError` when they cannot be allocated (a window of up to 2³⁰
/// pixels passes validation; an allocation failure must not abort the interpreter).
pub(crate) fn zeroed(len: usize) -> PyResult<Vec<f32>> {
    let mut out = Vec::new();
    out.try_reserve_exact(len).map_err(|_| {
        pyo3::exceptions::PyMemoryError::new_err(format!(
            "cannot allocate {len} float32 values ({:.1} GB) for the render",
            len as f64 * 4e-9
        ))
    })?;
    out.resize(len, 0.0);
    Ok(out)
}

/// Evaluates `eval` at `points` (pixels) with the GIL released: the bits of
/// [`Evaluator::eval_points`] (a one-pixel window at each point), in parallel over chunks.
pub(crate) fn sample_points(
    py: Python<'_>,
    eval: &Evaluator,
    points: &[[f64; 2]],
) -> PyResult<Vec<f32>> {
    for (i, p) in points.iter().enumerate() {
        eval.check_window(&spectex_cpu::point_window(*p))
            .map_err(|e| value_error(format!("points[{i}] = ({}, {}): {e}", p[0], p[1])))?;
    }
    let channels = eval.output_channels();
    let mut out = vec![0.0f32; points.len() * channels];
    py.detach(|| {
        guard(|| {
            const CHUNK: usize = 4096;
            out.par_chunks_mut(CHUNK * channels)
                .zip(points.par_chunks(CHUNK))
                .for_each(|(values, chunk)| eval.eval_points(chunk, values));
            Ok(())
        })
    })?;
    Ok(out)
}

/// The overhead measurement's Rust side: `repeats` renders of `model_json` at `width × height`
/// by [`Evaluator::render`] in this process, returning the fastest one's seconds. (A bench
/// helper for `examples/python/overhead.py`, not an API.)
#[pyfunction]
#[pyo3(signature = (model_json, width, height, repeats = 1))]
pub(crate) fn bench_rust_render(
    py: Python<'_>,
    model_json: &str,
    width: usize,
    height: usize,
    repeats: usize,
) -> PyResult<f64> {
    let model = spectex_model::from_json(model_json).map_err(value_error)?;
    let eval = Evaluator::new(&model).map_err(value_error)?;
    let window = Window::new(width, height);
    py.detach(|| {
        guard(|| {
            let mut best = f64::INFINITY;
            for _ in 0..repeats.max(1) {
                let start = Instant::now();
                let pixels = eval.render(&window).map_err(value_error)?;
                best = best.min(start.elapsed().as_secs_f64());
                std::hint::black_box(pixels);
            }
            Ok(best)
        })
    })
}
