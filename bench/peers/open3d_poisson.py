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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import steps  # noqa: E402
from open3d_normals import read_and_orient  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--k", type=int, default=30)
    parser.add_argument("--depth", type=int, default=8)
    args = parser.parse_args()

    step = steps.printer()

    import open3d as o3d
    step("import")
    _, cloud = read_and_orient(o3d, args.input, args.k, step)
    mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=args.depth)
    step("poisson")
    if not o3d.io.write_triangle_mesh(args.output, mesh, write_ascii=False):
        sys.exit(f"open3d_poisson: could not write {args.output}")
    step("write")
    print(f"mesh: {len(mesh.vertices)} vertices, {len(mesh.triangles)} faces")


if __name__ == "__main__":
    main()
