"""spectex: spectral procedural texture synthesis — numpy in, numpy out.

Random Phase Noise, Local Random-Phase noise fitted to an exemplar, phasor, Gabor, wavelet,
Voronoi and the classic noises, evaluated at any continuous position by the Rust evaluators
(the same values bit for bit as the ``spectex`` command on the CPU).

Example::

    >>> import numpy as np, spectex
    >>> exemplar = np.random.default_rng(0).random((64, 64))
    >>> model = spectex.fit(exemplar, budget=16, strata=2)
    >>> model.render(256, 128, offset=(1e7, 1e7), scale=2.0).shape
    (128, 256)
    >>> spectex.noise.perlin(cell_size=16.0).render(32, 32).dtype
    dtype('float32')
"""

from ._spectex import GPU, KIND_NAMES, Model, analyze, fit, fit_tiling, rpn
from . import noise, simulate
from .noise import combine, warp

# The builders of the kinds that are not "noises" by name, at the top level too.
gabor = noise.gabor
phasor = noise.phasor
wavelet = noise.wavelet
voronoi = noise.voronoi
texton = noise.texton
islamic = noise.islamic
subdivision = noise.subdivision
matrix = noise.matrix

__all__ = [
    "GPU",
    "KIND_NAMES",
    "Model",
    "analyze",
    "combine",
    "fit",
    "fit_tiling",
    "gabor",
    "islamic",
    "matrix",
    "noise",
    "phasor",
    "rpn",
    "simulate",
    "subdivision",
    "texton",
    "voronoi",
    "warp",
    "wavelet",
]
