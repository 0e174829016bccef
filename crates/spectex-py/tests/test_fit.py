"""Fitting, RPN and the analyses from arrays and from files."""

import struct
import zlib

import numpy as np
import pytest

import spectex
from conftest import TEXTURES


def write_png(path, array):
    """A PNG of a uint8/uint16 (H, W) or (H, W, 3) array, written with the standard library
    only (so the file does not come from the code under test)."""
    h, w = array.shape[:2]
    colour = 2 if array.ndim == 3 else 0
    depth = 16 if array.dtype == np.uint16 else 8
    rows = array.astype(">u2" if depth == 16 else "u1").reshape(h, -1)
    raw = b"".join(b"\x00" + row.tobytes() for row in rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", w, h, depth, colour, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def exemplar(shape, dtype, seed=0):
    rng = np.random.default_rng(seed)
    top = np.iinfo(dtype).max
    # A smooth random field plus noise: a spectrum with structure to fit.
    y, x = np.mgrid[0 : shape[0], 0 : shape[1]]
    base = 0.5 + 0.25 * np.sin(x / 3.0 + 0.5 * y / 5.0)
    if len(shape) == 3:
        base = base[..., None] * np.array([1.0, 0.8, 0.6])
    values = np.clip(base + 0.2 * rng.random(shape), 0, 1)
    return np.round(values * top).astype(dtype)


@pytest.mark.parametrize(
    "shape,dtype,options",
    [
        ((48, 40), np.uint8, {}),
        ((48, 40), np.uint16, {"budget": 24, "strata": 3}),
        ((40, 40, 3), np.uint8, {"budget": 12, "strata": 2}),
        ((48, 48), np.uint8, {"budget": 16, "structure": 0.2, "seed": 4}),
    ],
)
def test_fit_of_an_array_equals_fit_of_its_png(tmp_path, shape, dtype, options):
    image = exemplar(shape, dtype)
    path = tmp_path / "exemplar.png"
    write_png(path, image)
    from_array = spectex.fit(image, **options)
    from_file = spectex.fit(str(path), **options)
    assert from_array.to_json() == from_file.to_json()
    assert from_array.kind == ("lrp" if len(shape) == 2 and "structure" not in options else "texture")


def test_float_exemplars_are_values_in_0_1():
    image = exemplar((32, 32), np.uint8)
    as_f64 = spectex.fit(image.astype(np.float64) / 255.0, budget=8, strata=2)
    as_f32 = spectex.fit((image.astype(np.float32) / np.float32(255.0)), budget=8, strata=2)
    from_u8 = spectex.fit(image, budget=8, strata=2)
    # uint8 goes through the PNG decoder's v / 255 in f32, as float32 input does.
    assert as_f32.to_json() == from_u8.to_json()
    assert as_f64.kind == "lrp"


def test_fit_records_its_method_and_renders_far_away():
    model = spectex.fit(exemplar((32, 32), np.uint8), budget=10, strata=2, method="paper")
    assert '"fit": "paper"' in model.to_json()
    far = model.render(32, 16, offset=(1e7, 1e7), scale=8.0)
    assert far.shape == (16, 32) and np.isfinite(far).all()


@pytest.mark.skipif(not TEXTURES.is_dir(), reason=f"{TEXTURES} is absent (the shared real textures)")
def test_fit_of_a_real_texture_file():
    files = sorted(TEXTURES.glob("*.png"))
    if not files:
        pytest.skip(f"no PNG in {TEXTURES}")
    model = spectex.fit(str(files[0]), budget=20, strata=4)
    assert model.kind in ("lrp", "texture")
    assert np.isfinite(model.render(64, 64)).all()


def test_rpn_keeps_mean_and_shape():
    image = exemplar((32, 24, 3), np.uint8).astype(np.float64) / 255.0
    out = spectex.rpn(image, size=(40, 36), seed=3)
    assert out.shape == (36, 40, 3) and out.dtype == np.float64
    assert np.allclose(out.mean(axis=(0, 1)), image.mean(axis=(0, 1)), atol=1e-9)
    assert spectex.rpn(image[..., 0].copy(), seed=1).shape == (32, 24)
    assert spectex.rpn(image, adsn=True).shape == (32, 24, 3)


def test_analyze_gives_every_analysis():
    image = exemplar((32, 40, 3), np.uint8)
    a = spectex.analyze(image)
    assert set(a) == {"periodic", "smooth", "log_spectrum", "log_spectrum_periodic", "welch_psd", "variance_spectrum", "radial_profile"}
    assert a["periodic"].shape == (32, 40, 3)
    assert a["log_spectrum"].shape == (32, 40)
    rp = a["radial_profile"]
    assert rp["radius"].shape == rp["power"].shape == rp["count"].shape
    assert rp["power_channels"].shape == (rp["radius"].shape[0], 3)
    # periodic + smooth is the image (Moisan's decomposition), in [0, 1] units.
    assert np.allclose(a["periodic"] + a["smooth"], image / 255.0, atol=1e-9)
