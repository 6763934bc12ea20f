#!/usr/bin/python3
"""Writes a scan-like terrain of N points to a binary PLY file, a million
points at a time, never holding the cloud whole: the input of the scaling
benchmark (bench/tiled.sh, docs/scaling.md).

The surface is recon's terrain (shapes.h): z = 0.15 sin 2x cos 3y + 0.05
sin(5x + 4y) over [-1, 1]^2, sampled row by row on a grid of ceil(sqrt N)
columns with 15 % jitter, as a scanner's rows; its own random numbers (not
`recon generate terrain`'s).

    bench/terrain_stream.py 100000000 /scratch/terrain100m.ply
"""

import sys

import numpy as np


def header(n: int) -> bytes:
    return (
        "ply\nformat binary_little_endian 1.0\ncomment scan-like terrain (bench/terrain_stream.py)\n"
        f"element vertex {n}\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
    ).encode()


def write(n: int, path: str, chunk: int = 1_000_000, seed: int = 1) -> None:
    columns = int(np.ceil(np.sqrt(n)))
    side = 2.0 / columns
    rng = np.random.default_rng(seed)
    with open(path, "wb") as out:
        out.write(header(n))
        for first in range(0, n, chunk):
            i = np.arange(first, min(n, first + chunk), dtype=np.int64)
            x = -1.0 + (i % columns + 0.5) * side + rng.uniform(-0.15 * side, 0.15 * side, i.size)
            y = -1.0 + (i // columns + 0.5) * side + rng.uniform(-0.15 * side, 0.15 * side, i.size)
            z = 0.15 * np.sin(2 * x) * np.cos(3 * y) + 0.05 * np.sin(5 * x + 4 * y)
            out.write(np.column_stack((x, y, z)).astype("<f8").tobytes())


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: terrain_stream.py POINTS OUTPUT.ply")
    write(int(sys.argv[1]), sys.argv[2])
