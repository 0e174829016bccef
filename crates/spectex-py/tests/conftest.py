"""Shared fixtures: the repository's paths and the Rust reference renders.

The reference renders come from the ``spectex-py-reference`` binary (``src/bin``), which renders
each testdata model with ``spectex_cpu::Evaluator::render`` in Rust. ``cargo xtask python``
builds it and names it in ``SPECTEX_PY_REFERENCE_BIN``; run alone, the suite looks for it in
the cargo target directory and skips the byte-equality tests with a reason when it is absent
(``SPECTEX_PY_REQUIRE_REFERENCE=1``, set by xtask, makes that a failure).
"""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
MODELS = sorted((REPO / "testdata" / "models").glob("*.json"))
# The project's shared photographs, beside the repository (as the guide's `../shared/…`).
TEXTURES = REPO.parent / "shared" / "testdata" / "textures"


def _reference_bin():
    given = os.environ.get("SPECTEX_PY_REFERENCE_BIN")
    if given:
        return pathlib.Path(given)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for profile in ("debug", "release"):
        candidate = target / profile / "spectex-py-reference"
        if candidate.exists():
            return candidate
    return None


def _reference_or_skip():
    exe = _reference_bin()
    if exe is None or not exe.exists():
        if os.environ.get("SPECTEX_PY_REQUIRE_REFERENCE") == "1":
            pytest.fail(f"the reference binary is missing ({exe}); build it with cargo xtask python")
        pytest.skip("spectex-py-reference not built (cargo build -p spectex-py --bins)")
    return exe


@pytest.fixture(scope="session")
def reference_dir(tmp_path_factory):
    exe = _reference_or_skip()
    out = tmp_path_factory.mktemp("reference")
    subprocess.run([str(exe), str(out), *map(str, MODELS)], check=True)
    return out


@pytest.fixture(scope="session")
def builder_reference(tmp_path_factory):
    """The models the Rust builders make for the builder cases (``--builders``), and the Rust
    renders of each: ``<case>.json`` and ``<case>.<window>.f32``."""
    exe = _reference_or_skip()
    out = tmp_path_factory.mktemp("builders")
    subprocess.run([str(exe), "--builders", str(out)], check=True)
    subprocess.run([str(exe), str(out), *map(str, sorted(out.glob("*.json")))], check=True)
    return out
