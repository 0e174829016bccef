"""The builders: Rust defaults in the signatures, fields by name, models of models."""

import inspect
import json
import pickle
import pydoc

import numpy as np
import pytest

import spectex


def fields(model):
    ((kind, f),) = json.loads(model.to_json())["model"].items()
    return kind, f


def test_signatures_carry_the_rust_defaults():
    # The values of ClassicNoise::DEFAULT_CELL_SIZE, DEFAULT_OCTAVES, GaborNoise::DEFAULT_FREQUENCY
    # and Warp::DEFAULT_STRENGTH in spectex-model.
    assert inspect.signature(spectex.noise.perlin).parameters["cell_size"].default == 32.0
    assert inspect.signature(spectex.noise.fbm).parameters["octaves"].default == 6
    assert inspect.signature(spectex.gabor).parameters["frequency"].default == 0.0625
    assert fields(spectex.warp())[1]["strength"] == 16.0


def builders():
    """Every builder of spectex.noise (the models of models, combine and warp, aside)."""
    return [getattr(spectex.noise, n) for n in spectex.noise.__all__ if n not in ("combine", "warp", "BASES")]


def test_every_builder_makes_a_valid_model_that_renders():
    assert len(builders()) == 20
    for builder in builders():
        model = builder()
        assert isinstance(model, spectex.Model)
        assert np.isfinite(model.render(8, 8)).all(), builder.__name__


def test_every_kind_has_a_builder():
    # A texture is fitted (spectex.fit with structure, or a colour exemplar); combine and warp
    # are made of other models.
    made = {b().kind for b in builders()} | {"combine", "warp"}
    made.add(spectex.fit(np.random.default_rng(0).random((16, 16, 3)), budget=4, strata=1).kind)
    # Tiling and blending is fitted too (spectex.fit_tiling).
    made.add(spectex.fit_tiling(np.random.default_rng(0).random((16, 16, 3))).kind)
    assert made == set(spectex.KIND_NAMES)


# The models `spectex-py-reference --builders` makes with the Rust builders
# (spectex_sampling::LrpFromTarget, spectex_model::MatrixTransform::builder), made here by the
# Python ones: the defaults, and every parameter given (values exact in f32).
BUILDER_CASES = {
    "ring": lambda: spectex.noise.ring(),
    "ring-options": lambda: spectex.noise.ring(radius=0.125, width=0.0078125, budget=6, strata=2, seed=3, std_dev=0.25, mean=0.0),
    "lobe": lambda: spectex.noise.lobe(),
    "lobe-options": lambda: spectex.noise.lobe(frequency=0.125, angle=-1.0, width=0.015625, budget=4, seed=7),
    "band": lambda: spectex.noise.band(),
    "fractal": lambda: spectex.noise.fractal(),
    "fractal-options": lambda: spectex.noise.fractal(beta=1.0, angle=0.5, spread=0.25, min_frequency=0.015625, budget=24, strata=6, mean=0.25),
    "matrix": lambda: spectex.matrix(),
    "matrix-options": lambda: spectex.noise.matrix(matrix=[[3, 0], [0, 7]], iterations=2, size=128, source={"rings": {"rings": 9}}, amplitude=0.5, mean=0.25),
}


@pytest.mark.parametrize("case", sorted(BUILDER_CASES))
def test_builder_makes_the_rust_builders_model_and_render(case, builder_reference):
    from test_render import CASES

    model = BUILDER_CASES[case]()
    expected = spectex.Model.load(str(builder_reference / f"{case}.json"))
    assert json.loads(model.to_json()) == json.loads(expected.to_json()), case
    assert model == expected
    for name, w, h, offset, scale, z, filt in CASES:
        got = model.render(w, h, offset=offset, scale=scale, z=z, filter=filt)
        assert got.tobytes() == (builder_reference / f"{case}.{name}.f32").read_bytes(), f"{case} {name}"


def test_target_signatures_carry_the_rust_defaults():
    # SpectralTarget::DEFAULT_RING_RADIUS, DEFAULT_LOBE_ANGLE_DEGREES (30°, in radians as f32),
    # LrpFromTarget::DEFAULT_BUDGET and FRACTAL_BUDGET, FRACTAL_STRATA, DEFAULT_STD_DEV.
    ring = inspect.signature(spectex.noise.ring).parameters
    assert (ring["radius"].default, ring["budget"].default, ring["strata"].default) == (0.0625, 10, 1)
    assert (ring["width"].default, ring["std_dev"].default, ring["mean"].default) == (0.005, 0.15, 0.5)
    angle = inspect.signature(spectex.noise.lobe).parameters["angle"].default
    assert float(np.float32(angle)) == float(np.float32(np.radians(30.0)))
    fractal = inspect.signature(spectex.noise.fractal).parameters
    assert (fractal["budget"].default, fractal["strata"].default, fractal["spread"].default) == (48, 12, None)
    matrix = inspect.signature(spectex.matrix).parameters
    assert (matrix["matrix"].default, matrix["iterations"].default) == ([[1, 1], [1, 2]], 5)


@pytest.mark.parametrize("call,error,match", [
    (lambda: spectex.noise.ring(radius=0.9), ValueError, r"ring\.radius"),
    (lambda: spectex.noise.band(min=0.2, max=0.1), ValueError, r"band\.max"),
    (lambda: spectex.noise.fractal(spread=0.0), ValueError, r"fractal\.spread"),
    (lambda: spectex.noise.ring(budget=0), ValueError, "budget"),
    (lambda: spectex.noise.ring(budget=-3), ValueError, "budget"),
    (lambda: spectex.noise.ring(budget=2, strata=3), ValueError, "strata"),
    (lambda: spectex.noise.lobe(std_dev=0.0), ValueError, "std_dev"),
    (lambda: spectex.noise.lobe(width=float("nan")), ValueError, "finite"),
    (lambda: spectex.noise.ring(seed=2**32), ValueError, "seed"),
    (lambda: spectex.noise.ring(radious=0.1), TypeError, "radious.*radius"),
    (lambda: spectex.noise.band(min="low"), ValueError, "band"),
    (lambda: spectex.matrix(matrix=[[2, 0], [0, 1]]), ValueError, r"matrix\.matrix"),
    (lambda: spectex.matrix(size=1), ValueError, r"matrix\.size"),
    (lambda: spectex.matrix(rings=9), TypeError, "rings"),
])
def test_bad_target_and_matrix_parameters_name_the_parameter(call, error, match):
    with pytest.raises(error, match=match):
        call()


def test_fields_by_name_and_alias():
    kind, f = fields(spectex.noise.perlin(cell=16, dims=3, seed=7))
    assert (kind, f["cell_size"], f["dimensions"], f["seed"], f["basis"]) == ("classic", 16.0, 3, 7, "gradient")
    kind, f = fields(spectex.noise.perlin(octaves=3))
    assert f["fractal"]["octaves"] == 3 and f["fractal"]["kind"] == "fbm"
    _, f = fields(spectex.phasor(frequency=0.08, seed=9))
    assert f["frequency"] == {"constant": {"value": 0.08}} and f["seed"] == 9
    _, f = fields(spectex.noise.ridged(basis="simplex", octaves=4, gain=np.float32(0.25)))
    assert f["basis"] == "simplex" and f["fractal"]["octaves"] == 4 and f["fractal"]["gain"] == 0.25


def test_combine_and_warp():
    a, b, t = spectex.noise.perlin(seed=1), spectex.noise.voronoi(), spectex.noise.value(seed=2)
    mix = spectex.combine("mix", a, b, t)
    ra, rb, rt = (m.render(16, 16) for m in (a, b, t))
    got = mix.render(16, 16)
    assert np.allclose(got, ra + (rb - ra) * rt, atol=1e-6)
    step = spectex.combine("smoothstep", a, edges=(0.5, 0.5))
    assert set(np.unique(step.render(16, 16))) <= {0.0, 1.0}
    w = spectex.warp(b, a, strength=4.0, seed=3)
    _, f = fields(w)
    assert f["strength"] == 4.0 and list(f["base"]) == ["voronoi"]


def test_model_basics(tmp_path):
    m = spectex.noise.texton(seed=2)
    assert m.kind == "texton" and m.channels == 1
    assert "texton" in repr(m)
    path = tmp_path / "m.json"
    m.save(str(path))
    assert spectex.Model.load(str(path)) == m
    assert pickle.loads(pickle.dumps(m)) == m
    assert m.reseeded(0) == m and m.reseeded(5) != m
    colour = spectex.Model.load(str(spectex_repo_model("texture-synthetic-colour")))
    assert colour.channels == 3 and colour.render(4, 4).shape == (4, 4, 3)


def spectex_repo_model(stem):
    from conftest import MODELS
    return next(p for p in MODELS if p.stem == stem)


def test_help_reads_well():
    text = pydoc.render_doc(spectex.fit, renderer=pydoc.plaintext)
    assert "budget=50" in text and "Example" in text
    assert "cell_size=32.0" in pydoc.render_doc(spectex.noise.perlin, renderer=pydoc.plaintext)


def test_export_wgsl_is_a_module_or_says_what_it_needs():
    m = spectex.noise.perlin()
    if spectex.GPU:
        assert "fn spectex_sample" in m.export_wgsl()
    else:
        try:
            m.export_wgsl()
        except RuntimeError as e:
            assert "gpu feature" in str(e)
        else:
            raise AssertionError("export_wgsl without the gpu feature must raise")


def test_simulations():
    life = spectex.simulate.life(width=32, height=24, steps=5, seed=1)
    assert life.shape == (24, 32) and life.dtype == np.float32
    assert set(np.unique(life)) <= {0.0, 1.0}
    # Rule 30 from one cell: row k has the known pattern's 1, 3, 3, 6 live cells (drawn black).
    e = spectex.simulate.elementary(width=31, height=4, single=True, rule=30)
    assert [int((row == 0.0).sum()) for row in e] == [1, 3, 3, 6]
    gs = spectex.simulate.gray_scott(width=32, height=32, steps=20, preset="spots")
    assert gs.shape == (32, 32) and np.isfinite(gs).all()
    assert spectex.simulate.cyclic(width=16, height=16, steps=3).shape == (16, 16)
    assert spectex.simulate.swift_hohenberg(width=16, height=16, steps=3).shape == (16, 16)
