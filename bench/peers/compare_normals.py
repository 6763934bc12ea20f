#!/usr/bin/python3
"""Accuracy figures for bench/peers.sh, one JSON object on stdout.

    compare_normals.py normals TRUTH.ply RESULT.ply
        TRUTH.ply: the generated input, true outward normals nx ny nz.
        RESULT.ply: a program's normals, same points in the same order (checked).
        outward     fraction with dot(n, true) > 0: oriented as the truth is
        inward      fraction with dot(n, true) < 0
        consistent  max(outward, inward): a program that orients every normal
                    inward is consistent; one that failed is near 0.5
        line_0.9    fraction with |dot| > 0.9: the unoriented line is right
                    (within about 26 degrees), whatever its sign
        undefined   normals that are NaN or not of unit length (count as wrong)
        unoriented  points flagged `oriented = 0` (CGAL's output only)

    compare_normals.py mesh MESH.ply [--torus R r]
        vertices, unique_vertices (PCL writes one vertex per triangle corner),
        faces, and the RMS and largest distance from a vertex to the torus of
        radii R, r around the origin (recon's generated torus: 1, 0.35).
"""

import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plyio  # noqa: E402


def compare_normals(truth_path, result_path):
    truth, _ = plyio.read_vertices(truth_path)
    result, _ = plyio.read_vertices(result_path)
    if len(truth) != len(result):
        sys.exit(f"{result_path}: {len(result)} points, the input has {len(truth)}")
    p_true = plyio.columns(truth, "x", "y", "z")
    p = plyio.columns(result, "x", "y", "z")
    scale = np.ptp(p_true, axis=0).max()
    moved = np.abs(p - p_true).max() if len(p) else 0.0
    if moved > 1e-6 * scale:
        sys.exit(f"{result_path}: points differ from the input's (by up to {moved:g}): order not kept?")

    n_true = plyio.columns(truth, "nx", "ny", "nz")
    n_true /= np.linalg.norm(n_true, axis=1, keepdims=True)
    n = plyio.columns(result, "nx", "ny", "nz")
    length = np.linalg.norm(n, axis=1)
    defined = np.isfinite(length) & (np.abs(length - 1.0) < 1e-3)
    dot = np.zeros(len(n))
    dot[defined] = np.einsum("ij,ij->i", n[defined], n_true[defined]) / length[defined]
    count = len(n)
    outward = float(np.count_nonzero(dot > 0)) / count
    inward = float(np.count_nonzero(dot < 0)) / count
    figures = {
        "points": count,
        "outward": outward,
        "inward": inward,
        "consistent": max(outward, inward),
        "line_0.9": float(np.count_nonzero(np.abs(dot) > 0.9)) / count,
        "undefined": int(count - np.count_nonzero(defined)),
    }
    if "oriented" in result.dtype.names:
        figures["unoriented"] = int(np.count_nonzero(result["oriented"] == 0))
    return figures


def mesh_figures(path, major, minor):
    vertices, header = plyio.read_vertices(path)
    v = plyio.columns(vertices, "x", "y", "z")
    figures = {
        "vertices": len(v),
        "unique_vertices": int(len(np.unique(v, axis=0))) if len(v) else 0,
        "faces": header["elements"].get("face", 0),
    }
    if len(v):
        ring = np.hypot(v[:, 0], v[:, 1]) - major
        distance = np.abs(np.hypot(ring, v[:, 2]) - minor)
        figures["torus_rms"] = float(np.sqrt(np.mean(distance**2)))
        figures["torus_max"] = float(distance.max())
    return figures


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True)
    normals = commands.add_parser("normals")
    normals.add_argument("truth")
    normals.add_argument("result")
    mesh = commands.add_parser("mesh")
    mesh.add_argument("mesh")
    mesh.add_argument("--torus", nargs=2, type=float, default=(1.0, 0.35), metavar=("R", "r"))
    args = parser.parse_args()
    if args.command == "normals":
        figures = compare_normals(args.truth, args.result)
    else:
        figures = mesh_figures(args.mesh, *args.torus)
    print(json.dumps(figures))


if __name__ == "__main__":
    main()
