"""The builders: Rust defaults in the signatures, fields by name, models of models."""

import inspect
import json
import pickle
import pydoc

import numpy as np

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


def test_every_builder_makes_a_valid_model_that_renders():
    for name in ["perlin", "simplex", "value", "kensler", "worley", "fbm", "turbulence", "ridged", "gabor", "phasor", "wavelet", "voronoi", "texton", "islamic", "subdivision"]:
        model = getattr(spectex.noise, name)()
        assert isinstance(model, spectex.Model)
        assert np.isfinite(model.render(8, 8)).all(), name


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
