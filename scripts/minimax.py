#!/usr/bin/env python3
"""Fits the f32 polynomials of spectex-cpu's math.rs (and shaders/common.wgsl).

Both are minimax (equioscillating absolute error) fits, found by Lawson's iteratively
reweighted least squares on a dense grid, in f64; the printed coefficients are rounded once to
f32 and the error of their f32 Horner evaluation is measured on a finer grid.

- cos(2*pi*b) on b in [0, 1/4] as a degree-4 polynomial in x = b^2, constant pinned to 1.
- The Kaiser-Bessel window w(r) of spectex-model (I3 series, alpha = 3*pi, support 1.5) as
  u^(3/2) * P(u), u = 1 - r^2/2.25 in [0, 1], P of degree 7.
- atan(a) / (2*pi) on a in [0, 1] (phasor noise's phase in turns) as a * P(a^2), P of degree 7.

Needs numpy. Usage: python3 scripts/minimax.py
"""
import math

import numpy as np


def lawson(design, target, iterations):
    weights = np.ones(len(target))
    for _ in range(iterations):
        root = np.sqrt(weights)
        coeffs, *_ = np.linalg.lstsq(design * root[:, None], target * root, rcond=None)
        err = np.abs(design @ coeffs - target)
        weights = weights * err + 1e-300
        weights /= weights.sum()
    return coeffs, err.max()


def horner32(coeffs, x):
    c = np.asarray(coeffs, dtype=np.float32)
    p = np.full_like(x, c[-1])
    for k in range(len(c) - 2, -1, -1):
        p = (p * x).astype(np.float32) + c[k]
    return p


def cosine():
    b = np.linspace(0.0, 0.25, 200_001)
    x = b * b
    f = np.cos(2 * np.pi * b)
    design = np.vstack([x**k for k in range(1, 5)]).T
    rest, err = lawson(design, f - 1.0, 500)
    coeffs = np.concatenate([[1.0], rest])
    bb = np.linspace(0.0, 0.25, 4_000_001).astype(np.float32)
    got = horner32(coeffs, bb * bb).astype(np.float64)
    err32 = np.abs(got - np.cos(2 * np.pi * bb.astype(np.float64))).max()
    return coeffs, err, err32


def window():
    q_max = (1.5 * math.pi) ** 2
    terms = [1.0 / (math.factorial(m) * math.factorial(m + 3)) for m in range(40)]

    def series(q):
        return sum(c * q**m for m, c in enumerate(terms))

    norm = series(q_max)
    u = np.linspace(0.0, 1.0, 100_001)
    # w = I3(z)/I3(3 pi) = (q^(3/2) series(q)) / (q_max^(3/2) series(q_max)), q = q_max u.
    w = u**1.5 * np.array([series(q_max * t) for t in u]) / norm
    design = np.vstack([u**k * u**1.5 for k in range(8)]).T
    coeffs, err = lawson(design, w, 300)
    uu = u.astype(np.float32)
    got = (uu * np.sqrt(uu)).astype(np.float32) * horner32(coeffs, uu)
    err32 = np.abs(got.astype(np.float64) - w).max()
    return coeffs, err, err32


def show(name, fit):
    coeffs, err, err32 = fit
    print(f"{name}: f64 minimax error {err:.3e}, f32 Horner error {err32:.3e}")
    print("  " + ", ".join(str(np.float32(c)) for c in coeffs))




def atan_turns(degree=7):
    """atan(a) / (2 pi) on a in [0, 1] as a * P(a^2), P of the given degree."""
    a = np.linspace(0.0, 1.0, 200_001)
    f = np.arctan(a) / (2 * np.pi)
    design = np.vstack([a * a ** (2 * k) for k in range(degree + 1)]).T
    coeffs, err = lawson(design, f, 500)
    aa = np.linspace(0.0, 1.0, 2_000_001).astype(np.float32)
    got = (aa * horner32(coeffs, (aa * aa).astype(np.float32))).astype(np.float32)
    err32 = np.abs(got.astype(np.float64) - np.arctan(aa.astype(np.float64)) / (2 * np.pi)).max()
    return coeffs, err, err32


if __name__ == "__main__":
    show("cos(2 pi b) in b^2", cosine())
    show("Kaiser-Bessel u^1.5 P(u)", window())
    show("atan(a)/(2 pi) = a P(a^2)", atan_turns())
