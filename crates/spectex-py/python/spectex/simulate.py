"""Whole-grid simulations as arrays: Gray–Scott and Swift–Hohenberg reaction–diffusion,
Life-like, elementary and cyclic cellular automata, on a torus (``spectex-simulate``).

Each function is generated from the Rust presets and ``DEFAULT_STEPS`` (the ``spectex
simulate`` defaults): ``width``, ``height`` (256), ``steps``, ``seed`` and the simulation's own
parameters by name. Returns the final state's grey image, float32 of shape (height, width).
The GIL is released while stepping and Ctrl-C stops the run.

Example::

    >>> import spectex
    >>> spectex.simulate.life(width=32, height=32, steps=10).shape
    (32, 32)
"""

import json

from . import _fields
from ._spectex import simulate as _simulate
from ._spectex import simulation_defaults

_SIMULATIONS = {
    "gray_scott": "Gray–Scott reaction–diffusion (Pearson 1993); shows u. preset: spots, stripes, mazes, holes",
    "swift_hohenberg": "the Swift–Hohenberg equation, semi-implicit spectral steps",
    "life": "a Life-like cellular automaton given by a B/S rule",
    "elementary": "an elementary cellular automaton (Wolfram rule), rows over time",
    "cyclic": "a cyclic cellular automaton (Griffeath)",
}
_SPEC_FIELDS = ("width", "height", "steps", "seed")


def _run(name, kwargs):
    kwargs = dict(kwargs)
    preset = kwargs.pop("preset", None) if name == "gray_scott" else None
    spec = json.loads(simulation_defaults(name, preset))
    ((tag, params),) = spec["simulation"].items()
    for key in _SPEC_FIELDS:
        if key in kwargs:
            spec[key] = _fields.plain(kwargs.pop(key), key)
    if name == "gray_scott" and "patches" not in kwargs:
        # `spectex simulate`'s density of patches: one per 32² pixels, at least one.
        params["patches"] = max(1, min(65536, int(spec["width"]) * int(spec["height"]) // 1024))
    _fields.overlay(name, params, kwargs)
    return _simulate(json.dumps(spec))


def _make(name, description):
    spec = json.loads(simulation_defaults(name))
    ((_tag, params),) = spec["simulation"].items()
    names = [(k, spec[k]) for k in _SPEC_FIELDS] + list(params.items())
    if name == "gray_scott":
        names = [(k, v) for k, v in names if k not in ("feed", "kill")]
        names += [("preset", "mazes"), ("feed", None), ("kill", None)]

    def run(**kwargs):
        if name == "gray_scott":
            kwargs = {k: v for k, v in kwargs.items() if not (k in ("feed", "kill") and v is None)}
        return _run(name, kwargs)

    run.__name__ = run.__qualname__ = name
    run.__module__ = __name__
    run.__signature__ = _fields.signature(names)
    run.__doc__ = (
        f"Runs {description}; returns the grey image, float32 (height, width).\n\n"
        f"Example::\n\n    >>> spectex.simulate.{name}(width=16, height=16, steps=2).shape\n    (16, 16)\n"
    )
    return run


for _name, _description in _SIMULATIONS.items():
    globals()[_name] = _make(_name, _description)

__all__ = sorted(_SIMULATIONS)
