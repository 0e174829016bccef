"""Renders and samples from Python equal the Rust evaluator's, byte for byte."""

import concurrent.futures
import signal
import threading
import time
import _thread

import numpy as np
import pytest

import spectex
from conftest import MODELS

# The windows `src/bin/spectex-py-reference.rs` renders (name, width, height, offset, scale,
# z, filter).
CASES = [
    ("origin", 48, 40, (0.0, 0.0), 1.0, 0.0, True),
    ("far", 40, 33, (1.0e7, -3.5e6), 2.5, 7.25, True),
    ("zoomout", 32, 24, (-1234.5, 987.25), 16.0, 0.0, False),
]


def points():
    """The reference binary's points (x, y, z)."""
    i = np.arange(64, dtype=np.float64)
    return np.stack(
        [-300.0 + 17.25 * i, 1.0e5 * (np.arange(64) % 3) + 3.5 * i, np.where(np.arange(64) % 2 == 0, 0.0, 12.5)],
        axis=1,
    )


def test_there_are_testdata_models():
    assert len(MODELS) >= 40


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_testdata_model_equals_the_rust_render(path, reference_dir):
    model = spectex.Model.load(str(path))
    for name, w, h, offset, scale, z, filt in CASES:
        got = model.render(w, h, offset=offset, scale=scale, z=z, filter=filt)
        assert got.dtype == np.float32 and got.flags.c_contiguous
        shape = (h, w) if model.channels == 1 else (h, w, 3)
        assert got.shape == shape
        expected = (reference_dir / f"{path.stem}.{name}.f32").read_bytes()
        assert got.tobytes() == expected, f"{path.stem} {name} differs from the Rust render"
    sampled = model.sample(points())
    assert sampled.shape == ((64,) if model.channels == 1 else (64, 3))
    assert sampled.tobytes() == (reference_dir / f"{path.stem}.points.f32").read_bytes()


def test_two_column_points_are_the_z0_plane():
    model = spectex.Model.load(str(next(p for p in MODELS if p.stem == "classic-simplex-3d")))
    p3 = points()
    p3[:, 2] = 0.0
    assert model.sample(np.ascontiguousarray(p3[:, :2])).tobytes() == model.sample(p3).tobytes()


def test_four_threads_render_what_one_does():
    models = [spectex.Model.load(str(p)) for p in MODELS if p.stem in ("lrp-gravel", "texture-synthetic-colour", "phasor-two-lobes-phase", "warp-lrp-by-gabor")]
    windows = [dict(width=96, height=80, offset=(100.0 * k, -50.0 * k), scale=1.0 + k) for k in range(4)]
    jobs = [(m, w) for m in models for w in windows]
    serial = [m.render(**w).tobytes() for m, w in jobs]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        parallel = list(pool.map(lambda job: job[0].render(**job[1]).tobytes(), jobs))
    assert parallel == serial


def test_periodic_model_repeats_bit_for_bit():
    tile = spectex.noise.perlin(cell_size=16.0, seed=5).periodic(64, 32)
    assert tile.period == (64, 32)
    a = tile.render(128, 64)
    assert np.array_equal(a[:32, :64], a[32:, 64:]) and np.array_equal(a[:32, :64], a[:32, 64:])
    assert spectex.Model.from_json(tile.to_json()).period == (64, 32)


def test_render_returns_an_array_numpy_owns_without_a_copy():
    a = spectex.noise.voronoi().render(16, 8)
    assert a.base is not None  # the Rust vector, wrapped
    assert a.flags.writeable and a.flags.c_contiguous


def test_ctrl_c_stops_a_long_render():
    model = spectex.noise.fbm(octaves=8, cell_size=256.0)
    # Large enough that the whole render takes seconds on a loaded 2-core machine (4096² took
    # 0.7 s idle, and once finished before a late Ctrl-C was seen).
    width, height = 8192, 8192
    start = time.perf_counter()
    model.render(width, 16)  # one band of rows
    band = time.perf_counter() - start
    # The whole render is height / 16 = 512 bands; Ctrl-C (simulated) comes after 0.2 s.
    # Python's own SIGINT handler for the test: a process started with SIGINT ignored (a job
    # sent to the background by a non-interactive shell) inherits that, and interrupt_main then
    # does nothing.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        timer = threading.Timer(0.2, _thread.interrupt_main)
        start = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            model.render(width, height)
        stopped = time.perf_counter() - start
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    # Each thread ends the band it is in: a few bands' time, not the 512 of the whole render.
    assert stopped < 0.2 + 8 * band + 0.5, f"stopped after {stopped:.2f} s; one band takes {band:.3f} s"


@pytest.mark.skipif(not spectex.GPU, reason="spectex built without the gpu feature")
def test_gpu_render_agrees_with_the_cpu():
    import os

    model = spectex.noise.perlin(cell_size=16.0, seed=2)
    try:
        gpu = model.render(64, 48, offset=(1e5, -2e5), device="gpu")
    except RuntimeError as e:
        if os.environ.get("SPECTEX_REQUIRE_GPU") == "1":
            raise
        pytest.skip(f"no GPU adapter: {e}")
    cpu = model.render(64, 48, offset=(1e5, -2e5))
    assert gpu.shape == cpu.shape and gpu.dtype == np.float32
    # Within f32 rounding of the same expression (the cross-check's tolerances are tighter).
    assert np.max(np.abs(gpu - cpu)) < 1e-3
    assert "fn spectex_sample" in model.export_wgsl()
