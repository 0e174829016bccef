"""Keyword arguments as model fields: what the generated builders share (not an API)."""

import inspect
import json
import math

#: Short names accepted for fields (the ``spectex noise`` flags' names).
ALIASES = {"cell": "cell_size", "dims": "dimensions"}


def plain(value, path):
    """``value`` as plain JSON data (numpy scalars and arrays, tuples), finite floats only."""
    if hasattr(value, "tolist"):  # numpy scalars and arrays
        value = value.tolist()
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{path} = {value} must be a finite number")
        return value
    if isinstance(value, (list, tuple)):
        return [plain(v, f"{path}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, dict):
        return {str(k): plain(v, f"{path}.{k}") for k, v in value.items()}
    raise TypeError(f"{path} = {value!r}: a {type(value).__name__} is not a model field value")


def overlay(func, fields, kwargs):
    """Sets ``kwargs`` on the kind's ``fields`` (a top-level field, or a field of a nested
    object such as a fractal sum's ``octaves``); an unknown name is a ``TypeError``."""
    for name, value in kwargs.items():
        key = ALIASES.get(name, name)
        path = f"{func}.{key}"
        if key in fields:
            fields[key] = field_value(fields[key], plain(value, path))
            continue
        for sub in nested(fields):
            if key in sub:
                sub[key] = field_value(sub[key], plain(value, path))
                break
        else:
            raise TypeError(
                f"{func}() got an unexpected keyword argument {name!r}; its fields are "
                + ", ".join(sorted(flatten(fields)))
            )


def nested(fields):
    """The nested structs of ``fields`` (objects of several fields, such as a fractal sum); a
    one-key object is an enum's variant (``{"isotropic": {…}}``), set whole."""
    return [v for v in fields.values() if isinstance(v, dict) and len(v) > 1]


def field_value(current, value):
    """A number given for a field whose default is a constant control field
    (``{"constant": {"value": x}}``, phasor noise's graded parameters) is that constant."""
    if (
        isinstance(value, (int, float))
        and not isinstance(value, bool)
        and isinstance(current, dict)
        and list(current) == ["constant"]
    ):
        return {"constant": {"value": value}}
    return value


def flatten(fields):
    """``{name: default}`` of the top-level fields and the fields of nested structs."""
    flat = dict(fields)
    for sub in nested(fields):
        for key, value in sub.items():
            flat.setdefault(key, value)
    return flat


def signature(names_and_defaults):
    """A keyword-only signature, for ``help()`` and ``inspect``."""
    return inspect.Signature(
        [
            inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=default)
            for name, default in names_and_defaults
        ]
    )


def model_fields(text):
    """``(kind, fields)`` of a model file's text."""
    data = json.loads(text)
    ((kind, fields),) = data["model"].items()
    return data, kind, fields
