"""The cost of rendering through Python: a 1024² render of LRP noise with J = 50 cosines by the
Rust library (``spectex_cpu::Evaluator::render``, timed in Rust) and by ``Model.render``, both
in this process, best of five each; prints both times and their ratio, and the import time.

    python examples/python/overhead.py [--size 1024] [--repeats 5]
"""

import argparse
import subprocess
import sys
import time

import numpy as np

import spectex
from spectex import _spectex


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()

    exemplar = np.random.default_rng(0).random((128, 128))
    exemplar = np.ascontiguousarray(np.cumsum(np.cumsum(exemplar, 0), 1) % 1.0)
    model = spectex.fit(exemplar, budget=50, strata=4)
    assert model.kind == "lrp"
    text = model.to_json()
    size = args.size
    model.render(64, 64)  # warm up the pool
    # Interleaved, so that a change in the machine's load falls on both alike.
    rust = python = float("inf")
    for _ in range(args.repeats):
        rust = min(rust, _spectex.bench_rust_render(text, size, size, 1))
        start = time.perf_counter()
        model.render(size, size)
        python = min(python, time.perf_counter() - start)
    print(f"{size}² LRP J = 50: Rust {rust * 1e3:.1f} ms, Python {python * 1e3:.1f} ms, ratio {python / rust:.3f}")

    for what in ("import spectex", "import numpy, spectex"):
        code = f"import time; t = time.perf_counter(); {what}; print(time.perf_counter() - t)"
        times = [
            float(subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout)
            for _ in range(5)
        ]
        print(f"{what}: {min(times) * 1e3:.0f} ms (best of 5 fresh interpreters)")


if __name__ == "__main__":
    main()
