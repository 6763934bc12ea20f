"""Far-apart clusters (reconstruct.h): two spheres 1e9 apart, too far for one
lattice, are meshed each on a lattice of its own, by recon.reconstruct as
by the program."""

import json

import numpy as np

import recon
from conftest import run_cli, sphere

FAR = np.array([1e9, 0.0, 0.0])


def two_far_spheres() -> np.ndarray:
    """Two unit spheres of 1500 points, one at the origin, one at FAR (3000 x 3)."""
    return np.vstack([sphere(1500, seed=3), sphere(1500, seed=4) + FAR])


def test_two_spheres_a_billion_apart_are_meshed_each_on_its_own_lattice(tmp_path):
    points = two_far_spheres()
    mesh = recon.reconstruct(points)
    vertices = np.asarray(mesh.vertices)
    far = vertices[:, 0] > 5e8
    assert 0 < far.sum() < len(vertices)
    assert np.abs(np.linalg.norm(vertices[far] - FAR, axis=1) - 1.0).max() < 0.01
    assert np.abs(np.linalg.norm(vertices[~far], axis=1) - 1.0).max() < 0.01
    clusters = mesh.stats["contouring"]["clusters"]
    assert [c["points"] for c in clusters] == [1500, 1500]
    assert sum(c["triangles"] for c in clusters) == len(np.asarray(mesh.faces))

    cloud_file, mesh_file, stats_file = tmp_path / "two_far.xyz", tmp_path / "mesh.ply", tmp_path / "stats.json"
    np.savetxt(cloud_file, points, fmt="%.17g")
    run_cli("reconstruct", cloud_file, "-o", mesh_file, "--stats", stats_file, "--quiet")
    stats = json.loads(stats_file.read_text())
    assert stats["contouring"]["clusters"] == clusters
    assert stats["mesh"] == mesh.stats["mesh"]
