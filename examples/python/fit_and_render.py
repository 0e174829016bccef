"""Fit an exemplar, render the model far from the origin and zoomed out, and save a figure of
the exemplar, the syntheses and their spectra.

    python examples/python/fit_and_render.py [EXEMPLAR.png] [-o figure.png]

Without an exemplar, one is made with spectex itself (a Voronoi pattern warped by fBm), so the
script runs anywhere spectex and matplotlib are installed (``pip install ./crates/spectex-py
matplotlib``).
"""

import argparse
import time

import numpy as np

import spectex


def log_spectrum(image):
    """Centred ln(1 + |DFT|) of the grey levels, through spectex.analyze."""
    return spectex.analyze(np.ascontiguousarray(image, dtype=np.float64))["log_spectrum"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("exemplar", nargs="?", help="a PNG or JPEG texture")
    parser.add_argument("-o", "--output", default="spectex-python-example.png")
    parser.add_argument("--budget", type=int, default=50)
    args = parser.parse_args()

    if args.exemplar:
        exemplar_model = None
        source = args.exemplar
    else:
        exemplar_model = spectex.warp(spectex.noise.voronoi(output="f1", cell_size=24.0), spectex.noise.fbm(mean=0.0, amplitude=1.0), strength=6.0)
        source = exemplar_model.render(256, 256)
    start = time.perf_counter()
    model = spectex.fit(source, budget=args.budget, strata=4, seed=1)
    print(f"fitted {model!r} in {time.perf_counter() - start:.2f} s")

    if exemplar_model is not None:
        exemplar = source
    else:  # the file's pixels: periodic + smooth component (Moisan) is the image
        parts = spectex.analyze(source)
        exemplar = parts["periodic"] + parts["smooth"]
    grey = exemplar if exemplar.ndim == 2 else exemplar @ np.array([0.2126, 0.7152, 0.0722])
    start = time.perf_counter()
    far = model.render(512, 512, offset=(1.0e7, -3.0e6))
    zoomed_out = model.render(512, 512, offset=(-2.0e4, 5.0e3), scale=8.0)
    print(f"rendered 2 × 512² in {time.perf_counter() - start:.2f} s")
    show = lambda a: a if a.ndim == 2 else np.clip(a, 0, 1)
    as_grey = lambda a: a if a.ndim == 2 else a @ np.array([0.2126, 0.7152, 0.0722])

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [
        ("exemplar", exemplar, grey),
        ("synthesis at (1e7, −3e6)", far, as_grey(far)),
        ("zoomed out ×8 (filtered)", zoomed_out, as_grey(zoomed_out)),
    ]
    fig, axes = plt.subplots(2, 3, figsize=(12, 8))
    for column, (title, image, lum) in enumerate(panels):
        axes[0, column].imshow(show(image), cmap="gray", vmin=0, vmax=1)
        axes[0, column].set_title(title)
        axes[1, column].imshow(log_spectrum(lum), cmap="magma")
        axes[1, column].set_title("log spectrum")
    for ax in axes.flat:
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(args.output, dpi=80)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
