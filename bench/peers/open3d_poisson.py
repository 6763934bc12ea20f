#!/usr/bin/python3
"""Open3D's Screened Poisson reconstruction, as a new user runs it on a cloud
without normals.

    /usr/bin/python3 open3d_poisson.py IN.ply -o MESH.ply [--k K] [--depth D]

estimate_normals(KDTreeSearchParamKNN(K)), orient_normals_consistent_tangent_plane(K),
create_from_point_cloud_poisson(depth=D) (Open3D's default depth is 8). The
mesh is written as Open3D returns it (no trimming by density: a user who
trims chooses a threshold per cloud). Prints one `step <name> <seconds> s`
line per step.
"""

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plyio  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--k", type=int, default=30)
    parser.add_argument("--depth", type=int, default=8)
    args = parser.parse_args()

    last = time.perf_counter()

    def step(name):
        nonlocal last
        now = time.perf_counter()
        print(f"step {name:<16} {now - last:9.3f} s", flush=True)
        last = now

    import open3d as o3d
    step("import")
    data, _ = plyio.read_vertices(args.input)
    positions = plyio.columns(data, "x", "y", "z")
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(positions))
    step("read")
    cloud.estimate_normals(search_param=o3d.geometry.KDTreeSearchParamKNN(knn=args.k))
    step("estimate_normals")
    cloud.orient_normals_consistent_tangent_plane(args.k)
    step("orient_normals")
    mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=args.depth)
    step("poisson")
    if not o3d.io.write_triangle_mesh(args.output, mesh, write_ascii=False):
        sys.exit(f"open3d_poisson: could not write {args.output}")
    step("write")
    print(f"mesh: {len(mesh.vertices)} vertices, {len(mesh.triangles)} faces")


if __name__ == "__main__":
    main()
