#!/usr/bin/python3
"""Open3D's answer to recon's phases I and II.

    /usr/bin/python3 open3d_normals.py IN.ply -o OUT.ply [--k K]

estimate_normals(KDTreeSearchParamKNN(K)), a plane per K-neighbourhood (the
point itself among the K, as recon's --k), then
orient_normals_consistent_tangent_plane(K), Open3D's Hoppe-style propagation.
The cloud is built from the positions alone: Open3D's estimate_normals flips
new normals to agree with any normals the cloud already has, which would hand
it the true answer. OUT.ply holds the input's points in the input's order with
Open3D's normals. Prints one `step <name> <seconds> s` line per step.
Threads: Open3D's OpenMP default (all cores; OMP_NUM_THREADS limits it).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plyio  # noqa: E402
import steps  # noqa: E402


def read_and_orient(o3d, path, k, step):
    """Reads the cloud's positions alone and gives it Open3D's oriented normals,
    steps read, estimate_normals and orient_normals: (positions, cloud).
    open3d_poisson.py's first steps too."""
    positions = plyio.positions(path)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(positions))
    step("read")
    cloud.estimate_normals(search_param=o3d.geometry.KDTreeSearchParamKNN(knn=k))
    step("estimate_normals")
    cloud.orient_normals_consistent_tangent_plane(k)
    step("orient_normals")
    return positions, cloud


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--k", type=int, default=15)
    args = parser.parse_args()

    step = steps.printer()

    import open3d as o3d  # timed: importing Open3D is part of what a user pays
    print(f"open3d {o3d.__version__}; threads: OpenMP, "
          f"{os.environ.get('OMP_NUM_THREADS', f'all {os.cpu_count()} cores')}", flush=True)
    step("import")

    positions, cloud = read_and_orient(o3d, args.input, args.k, step)
    normals = np.asarray(cloud.normals)
    if len(normals) != len(positions) or not np.array_equal(np.asarray(cloud.points), positions):
        sys.exit("open3d_normals: Open3D changed the points or their order")
    plyio.write_points(args.output, positions, normals)
    step("write")


if __name__ == "__main__":
    main()
