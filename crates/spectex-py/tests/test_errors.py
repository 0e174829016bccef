"""Bad inputs raise ValueError or TypeError naming the parameter, never crash."""

import numpy as np
import pytest

import spectex

GOOD = np.random.default_rng(0).random((16, 16))


@pytest.mark.parametrize("bad,match", [
    (np.full((16, 16), np.nan), "finite"),
    (np.where(np.eye(16) > 0, np.inf, 0.5), "finite"),
    (np.full((16, 16), np.nan, dtype=np.float32), "finite"),
])
def test_non_finite_images_are_refused(bad, match):
    for call in (spectex.fit, spectex.rpn, spectex.analyze):
        with pytest.raises(ValueError, match=match):
            call(bad)


@pytest.mark.parametrize("bad,error,match", [
    (GOOD.astype(np.complex128), TypeError, "dtype complex128"),
    (GOOD.astype(np.int64), TypeError, "dtype int64"),
    (GOOD.ravel(), ValueError, "1 dimensions"),
    (GOOD[None, None], ValueError, "4 dimensions"),
    (np.zeros((16, 16, 4)), ValueError, "4 channels"),
    (np.zeros((16, 16, 2)), ValueError, r"\(H, W, 3\)"),
    (GOOD[:, ::2], ValueError, "C-contiguous"),
    (GOOD.T, ValueError, "C-contiguous"),
    (np.zeros((1, 16)), ValueError, "2 to 16384"),
    ([[0.5, 0.5], [0.5, 0.5]], TypeError, "numpy array"),
])
def test_bad_images_are_refused(bad, error, match):
    with pytest.raises(error, match=match):
        spectex.fit(bad)


@pytest.mark.parametrize("kwargs,match", [
    (dict(budget=0), "budget"),
    (dict(budget=5000), "budget"),
    (dict(strata=0), "strata"),
    (dict(structure=2.0), "structure"),
    (dict(turbulence=-1.0), "turbulence"),
    (dict(method="magic"), "magic"),
    (dict(seed=-1), "seed"),
])
def test_bad_fit_options_name_the_option(kwargs, match):
    with pytest.raises(ValueError, match=match):
        spectex.fit(GOOD, **kwargs)


def test_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError, match="cannot open"):
        spectex.fit(str(tmp_path / "absent.png"))
    (tmp_path / "not.png").write_bytes(b"hello")
    with pytest.raises(ValueError, match="not a PNG"):
        spectex.fit(str(tmp_path / "not.png"))
    with pytest.raises(OSError):
        spectex.Model.load(str(tmp_path / "absent.json"))


@pytest.mark.parametrize("args,kwargs,match", [
    ((0, 16), {}, "width = 0"),
    ((16, 0), {}, "height = 0"),
    ((-5, 16), {}, "width = -5"),
    ((10**9, 16), {}, "width"),
    ((65536, 65536), {}, "2\\^30 pixels"),
    ((16, 16), dict(scale=0.0), "scale"),
    ((16, 16), dict(scale=float("nan")), "scale"),
    ((16, 16), dict(offset=(float("inf"), 0.0)), "offset x"),
    ((16, 16), dict(offset=(3e9, 0.0)), "2\\^30"),
    ((16, 16), dict(z=float("nan")), "z"),
    ((16, 16), dict(device="tpu"), "device"),
])
def test_bad_windows_are_refused(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        spectex.noise.perlin().render(*args, **kwargs)


def test_wrong_argument_types_are_type_errors():
    with pytest.raises(TypeError):
        spectex.noise.perlin().render("wide", 16)
    with pytest.raises(TypeError):
        spectex.noise.perlin().render(16, 16, offset=3.0)


@pytest.mark.parametrize("points,error,match", [
    (np.zeros((4, 4)), ValueError, r"\(N, 2\)"),
    (np.zeros(4), ValueError, r"\(N, 2\)"),
    (np.zeros((4, 2), dtype=np.int32), TypeError, "float64"),
    (np.zeros((4, 3))[:, :2], ValueError, "C-contiguous"),
    (np.array([[np.nan, 0.0]]), ValueError, "points\\[0, 0\\]"),
    (np.array([[0.0, 5e9]]), ValueError, "points\\[0\\]"),
    ([[0.0, 0.0]], TypeError, "numpy array"),
])
def test_bad_points_are_refused(points, error, match):
    with pytest.raises(error, match=match):
        spectex.noise.perlin().sample(points)


def test_unknown_kinds_and_fields_are_named():
    with pytest.raises(ValueError, match="unknown variant `fancy`"):
        spectex.Model.from_json('{"schema_version": 1, "model": {"fancy": {}}}')
    text = spectex.noise.perlin().to_json().replace('"seed"', '"sead"')
    with pytest.raises(ValueError, match="sead"):
        spectex.Model.from_json(text)
    with pytest.raises(ValueError, match="schema_version"):
        spectex.Model.from_json('{"model": {}}')
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        spectex.noise.perlin(colour=3)
    with pytest.raises(ValueError, match=r"classic\.cell_size.*range"):
        spectex.noise.perlin(cell_size=-4.0)
    with pytest.raises(ValueError, match="must be a finite number"):
        spectex.noise.gabor(frequency=float("nan"))
    with pytest.raises(ValueError, match="basis"):
        spectex.noise.fbm(basis="plaid")
    with pytest.raises(ValueError, match="unknown variant `blend`"):
        spectex.combine("blend", spectex.noise.perlin(), spectex.noise.perlin(seed=1))
    with pytest.raises(ValueError, match="period"):
        spectex.noise.perlin().periodic(0, 64)
    with pytest.raises(ValueError, match=r"\.json"):
        spectex.noise.perlin().save("model.txt")
    with pytest.raises(ValueError, match="width = 0"):
        spectex.simulate.life(width=0)
    with pytest.raises(ValueError, match="rule"):
        spectex.simulate.life(rule="B9/S23", width=8, height=8, steps=1)


def test_rpn_sizes_are_checked():
    with pytest.raises(ValueError, match="output size"):
        spectex.rpn(GOOD, size=(8, 8))
    with pytest.raises(ValueError, match="size width = 0"):
        spectex.rpn(GOOD, size=(0, 8))
