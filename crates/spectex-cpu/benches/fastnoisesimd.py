"""FastNoiseSIMD (through the `pyfastnoisesimd` package) on the grid of the `grid` group of
`benches/classic.rs`, for `cargo xtask bench classic`, which installs the package in a
virtual environment and runs this script right after the spectex benches.

One thread (`numWorkers=1`: the package splits a grid along z only, so a one-slice grid runs
on one thread anyway), a 2048² slice of 3D noise at z = 7 pixels, frequency 1/32 (a lattice
cell of 32 pixels, as spectex's `cell_size` 32), seed 1. FastNoiseSIMD evaluates a point at
`(start + index)·frequency` (its axis scales are 1), the positions spectex evaluates at
`(x, y, z)/cell_size`. Cases, as spectex's: Perlin (improved gradient noise, quintic fade),
value noise, simplex, cellular (distance to the nearest point, Euclidean, one jittered point
per cell), and fBm of Perlin noise, 6 octaves, lacunarity 2, gain 1/2.

Prints and writes `case<TAB>Mpix/s<TAB>SIMD level` to `--out`: the best of `--runs` grids,
each timed by the calling thread's CPU time (`time.thread_time`: with one worker the package
computes in the calling thread), as spectex's `grid` group is timed, so that other work on a
shared machine does not count.
"""

import argparse
import time

import numpy

# pyfastnoisesimd 0.4.2 calls `numpy.product`, which numpy 2 removed.
if not hasattr(numpy, "product"):
    numpy.product = numpy.prod

import pyfastnoisesimd as fns  # noqa: E402
import pyfastnoisesimd.extension as extension  # noqa: E402

SIDE = 2048
Z = 7
FREQUENCY = 1.0 / 32.0


def noise(case):
    n = fns.Noise(seed=1, numWorkers=1)
    n.frequency = FREQUENCY
    if case == "perlin":
        n.noiseType = fns.NoiseType.Perlin
    elif case == "value":
        n.noiseType = fns.NoiseType.Value
    elif case == "simplex":
        n.noiseType = fns.NoiseType.Simplex
    elif case == "cellular":
        n.noiseType = fns.NoiseType.Cellular
        n.cell.returnType = fns.CellularReturnType.Distance
        n.cell.distanceFunc = fns.CellularDistanceFunction.Euclidean
    elif case == "fbm6":
        n.noiseType = fns.NoiseType.PerlinFractal
        n.fractal.fractalType = fns.FractalType.FBM
        n.fractal.octaves = 6
        n.fractal.lacunarity = 2.0
        n.fractal.gain = 0.5
    else:
        raise ValueError(case)
    return n


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--runs", type=int, default=15)
    args = parser.parse_args()
    lines = ["case\tmpix_per_s\tsimd_level"]
    for case in ["perlin", "value", "simplex", "cellular", "fbm6"]:
        n = noise(case)
        n.genAsGrid(shape=[1, SIDE, SIDE], start=[Z, 0, 0])  # warm-up
        times = []
        for _ in range(args.runs):
            start = time.thread_time()
            n.genAsGrid(shape=[1, SIDE, SIDE], start=[Z, 0, 0])
            times.append(time.thread_time() - start)
        mpix = SIDE * SIDE / min(times) / 1e6
        lines.append(f"{case}\t{mpix:.2f}\t{extension.SIMD_LEVEL}")
        print(f"FastNoiseSIMD {case}: {mpix:.1f} Mpix/s ({extension.SIMD_LEVEL})")
    with open(args.out, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
