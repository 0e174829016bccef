"""Every model kind's builder with the Rust defaults: ``spectex.noise.perlin(cell_size=16)``.

Each function here is generated at import from the default model that ``spectex-model``'s
builder for the kind makes (``crates/spectex-py/src/defaults.rs`` lists them), so the defaults
in each signature are the Rust ones and change with them. Keyword arguments are the model
file's field names (``help(spectex.noise.gabor)`` lists them; ``cell`` and ``dims`` are
accepted for ``cell_size`` and ``dimensions``; a fractal sum's ``octaves``, ``lacunarity`` and
``gain`` are set by name). Values are checked by the model's validation: a value out of range
is a ``ValueError`` naming the field and its valid range.

LRP noise is fitted to a spectrum rather than set field by field: ``ring``, ``lobe``, ``band``
and ``fractal`` (the ``spectex noise`` commands of the same names) take the spectral target's
parameters (frequencies in cycles per pixel, angles in radians where the command takes
degrees) and the fit's ``budget``, ``strata``, ``seed``, ``std_dev`` and ``mean``, with the
defaults of ``spectex_sampling::LrpFromTarget`` for that target.

Example::

    >>> import spectex
    >>> m = spectex.noise.fbm(octaves=4, cell_size=64.0, seed=3)
    >>> m.kind
    'classic'
    >>> spectex.noise.voronoi(cell_size=16.0).render(32, 32).shape
    (32, 32)
"""

import json

from . import _fields
from ._spectex import Model, builder_names, default_model, target_default, target_names
from ._spectex import combine as _combine
from ._spectex import lrp_from_target as _lrp_from_target
from ._spectex import warp as _warp

_BUILDERS, BASES = builder_names()
BASES = tuple(BASES)
_BUILDERS = dict(_BUILDERS)
_SUMS = ("fbm", "turbulence", "ridged")
_FRACTAL_FIELDS = ("octaves", "lacunarity", "gain")


def _build(name, kwargs):
    kwargs = dict(kwargs)
    variant = None
    if name in _SUMS:
        variant = kwargs.pop("basis", "perlin")
        if variant not in BASES:
            raise ValueError(f"{name}.basis = {variant!r} is not one of {', '.join(BASES)}")
    elif name in BASES and any(k in kwargs for k in _FRACTAL_FIELDS):
        variant = "fractal"
    data, _kind, fields = _fields.model_fields(default_model(name, variant))
    _fields.overlay(name, fields, kwargs)
    return Model.from_json(json.dumps(data))


def _make(name, description):
    _data, kind, fields = _fields.model_fields(default_model(name))
    params = list(_fields.flatten(fields).items())
    if name in _SUMS:
        params = [(k, v) for k, v in params if k != "basis"] + [("basis", "perlin")]
    elif name in BASES:
        params += [(k, None) for k in _FRACTAL_FIELDS]

    def builder(**kwargs):
        return _build(name, kwargs)

    builder.__name__ = builder.__qualname__ = name
    builder.__module__ = __name__
    builder.__signature__ = _fields.signature(params)
    extra = ""
    if name in _SUMS:
        extra = f"\n``basis`` is one of {', '.join(BASES)}."
    elif name in BASES:
        extra = "\n``octaves`` (with ``lacunarity``, ``gain``) makes the noise's fBm."
    # A kind without randomness (matrix) has no seed.
    example = "seed=1" if "seed" in dict(params) else ""
    builder.__doc__ = (
        f"A ``{kind}`` model: {description}, every field at the Rust default unless given.{extra}\n\n"
        f"Example::\n\n    >>> m = spectex.noise.{name}({example})\n    >>> m.kind\n    '{kind}'\n"
    )
    return builder


for _name, _description in _BUILDERS.items():
    globals()[_name] = _make(_name, _description)


def _make_target(name, description):
    defaults = target_default(name)
    variant, target, options = defaults["variant"], defaults["target"], defaults["options"]

    def builder(**kwargs):
        fields = dict(target)
        given = {}
        for key, value in kwargs.items():
            value = _fields.plain(value, f"{name}.{key}")
            if key in fields:
                fields[key] = value
            elif key in options:
                given[key] = value
            else:
                raise TypeError(
                    f"{name}() got an unexpected keyword argument {key!r}; its parameters are "
                    + ", ".join(sorted([*fields, *options]))
                )
        return _lrp_from_target(json.dumps({variant: fields}), **given)

    builder.__name__ = builder.__qualname__ = name
    builder.__module__ = __name__
    builder.__signature__ = _fields.signature([*target.items(), *options.items()])
    builder.__doc__ = (
        f"An ``lrp`` model: {description}, fitted as ``spectex noise {name}`` fits it, every "
        f"parameter at the Rust default unless given.\n\n"
        f"The target's parameters are in cycles per pixel, its angles in radians; ``budget`` "
        f"(cosines per lattice point J) and ``strata`` (L) shape the fit, ``std_dev`` and "
        f"``mean`` the noise's values.\n\n"
        f"Example::\n\n    >>> m = spectex.noise.{name}(seed=1)\n    >>> m.kind\n    'lrp'\n"
    )
    return builder


_TARGETS = dict(target_names())
for _name, _description in _TARGETS.items():
    globals()[_name] = _make_target(_name, _description)

__all__ = sorted([*_BUILDERS, *_TARGETS]) + ["combine", "warp", "BASES"]


def combine(op, *models, **params):
    """A pointwise combination of models: ``op`` is ``"add"``, ``"multiply"``, ``"min"``,
    ``"max"``, ``"mix"`` (``a + (b − a)·t`` of three models), ``"smoothstep"`` (``edges=``),
    ``"abs_fold"`` (``offset=, step=, folds=``), ``"sin_fold"`` (``gain=``), ``"histogram"``
    (``domain=, table=``) or ``"ramp"`` (``stops=[{"at": …, "colour": [r, g, b]}, …]``).

    Example::

        >>> a, b = spectex.noise.perlin(seed=1), spectex.noise.voronoi()
        >>> spectex.combine("max", a, b).kind
        'combine'
        >>> bool(spectex.combine("smoothstep", a, edges=(0.4, 0.6)).render(8, 8).max() <= 1.0)
        True
    """
    if not isinstance(op, str):
        raise TypeError(f"combine op must be a str such as 'add', not {type(op).__name__}")
    spec = {op: _fields.plain(params, f"combine.{op}")} if params else op
    return _combine(json.dumps(spec), list(models))


def warp(base=None, by=None, by_y=None, *, strength=None, seed=None):
    """Domain warping: ``base`` evaluated at ``p + strength·(x(p), y(p))``, with ``x`` the model
    ``by`` and ``y`` the model ``by_y`` (``by`` reseeded by one unless given). Omitted models
    are the built-in fBms; ``strength`` and ``seed`` default to the Rust builder's.

    Example::

        >>> w = spectex.warp(spectex.noise.voronoi(), spectex.noise.fbm(mean=0.0, amplitude=1.0))
        >>> w.kind
        'warp'
    """
    return _warp(base, by, by_y, strength, seed)
