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
            fields[key] = plain(value, path)
            continue
        for sub in fields.values():
            if isinstance(sub, dict) and key in sub:
                sub[key] = plain(value, path)
                break
        else:
            raise TypeError(
                f"{func}() got an unexpected keyword argument {name!r}; its fields are "
                + ", ".join(sorted(flatten(fields)))
            )


def flatten(fields):
    """``{name: default}`` of the top-level fields and the fields of nested objects."""
    flat = {}
    for key, value in fields.items():
        flat[key] = value
        if isinstance(value, dict):
            for sub, v in value.items():
                flat.setdefault(sub, v)
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
