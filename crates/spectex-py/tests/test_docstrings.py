"""Every public function and method has a docstring with an example, and the examples run."""

import doctest
import inspect

import numpy as np
import pytest

import spectex


def public_objects():
    objects = [spectex, spectex.noise, spectex.simulate, spectex.fit, spectex.rpn, spectex.analyze, spectex.combine, spectex.warp, spectex.Model]
    objects += [getattr(spectex.Model, name) for name in dir(spectex.Model) if not name.startswith("_")]
    objects += [getattr(spectex.noise, name) for name in spectex.noise.__all__ if callable(getattr(spectex.noise, name))]
    objects += [getattr(spectex.simulate, name) for name in spectex.simulate.__all__]
    return objects


@pytest.mark.parametrize("obj", public_objects(), ids=lambda o: getattr(o, "__qualname__", getattr(o, "__name__", "?")))
def test_docstring_example_runs(obj):
    doc = inspect.getdoc(obj)
    assert doc, f"{obj} has no docstring"
    if isinstance(obj, property) or not callable(obj) and not inspect.ismodule(obj):
        return  # kind, channels, period: attributes, documented in one line
    examples = doctest.DocTestParser().get_examples(doc)
    assert examples, f"{obj} has no example in its docstring"
    test = doctest.DocTestParser().get_doctest(doc, {"spectex": spectex, "np": np}, str(obj), None, 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.failures == 0, f"the example of {obj} fails (see the output above)"
