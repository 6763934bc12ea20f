"""Reading and writing files from Python, and errors as Python exceptions
with the program's messages."""

import numpy as np
import pytest

import recon
from conftest import run_cli, sphere


def program_error(*args) -> str:
    """The one-line error the program prints for `recon ARGS` (without 'recon: error: ')."""
    finished = run_cli(*args, check=False)
    assert finished.returncode != 0
    line = finished.stderr.strip().splitlines()[-1]
    assert line.startswith("recon: error: ")
    return line[len("recon: error: "):]


def test_points_round_trip_through_files(tmp_path):
    points = sphere(500)
    normals = points.copy()
    colors = (np.arange(1500) % 256).astype(np.uint8).reshape(500, 3)
    for name in ("cloud.ply", "cloud.xyz"):
        path = tmp_path / name
        recon.write_points(path, points, normals, colors)
        cloud = recon.read_points(path)
        np.testing.assert_array_equal(cloud.points, points)
        np.testing.assert_array_equal(cloud.normals, normals)
        assert len(cloud) == 500
    plain = tmp_path / "plain.ply"
    recon.write_points(plain, points)
    cloud = recon.read_points(plain)
    assert cloud.normals is None and cloud.colors is None


def test_a_cloud_made_in_python_reconstructs(tmp_path):
    cloud = recon.PointCloud(sphere(5000))
    mesh = recon.reconstruct(cloud)
    path = tmp_path / "mesh.obj"
    mesh.save(path)
    assert path.read_text().count("\nf ") == len(mesh.faces)
    again = recon.Mesh(mesh.vertices, mesh.faces)
    np.testing.assert_array_equal(again.faces, mesh.faces)
    assert again.stats == {}


def test_bad_parameters_are_value_errors():
    points = sphere(1000)
    with pytest.raises(ValueError, match="k must be between 3 and 256, got 2"):
        recon.reconstruct(points, k=2)
    with pytest.raises(ValueError, match="rho must be positive"):
        recon.reconstruct(points, rho=-1.0)
    with pytest.raises(ValueError, match="cell or resolution, not both"):
        recon.reconstruct(points, cell=0.1, resolution=10)
    with pytest.raises(ValueError, match="unknown method 'poisson'"):
        recon.reconstruct(points, method="poisson")
    with pytest.raises(ValueError, match=r"points must be an n x 3 array; got shape \(1000, 2\)"):
        recon.reconstruct(points[:, :2])
    with pytest.raises(ValueError, match="normals must have one row per point"):
        recon.reconstruct(points, normals=points[:10])
    with pytest.raises(ValueError, match="threads must be at least 1"):
        recon.reconstruct(points, threads=0)
    with pytest.raises(ValueError, match="colors given as floats must lie in"):
        recon.reconstruct(points, colors=np.full((1000, 3), 2.0))
    bad = points.copy()
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        recon.reconstruct(bad)


TRIANGLE = np.eye(3)
FACE = [[0, 1, 2]]

# Every array the package takes, given an array of a kind numpy would cast
# with a loss (a float index truncated, an imaginary part dropped) or a
# guess (bools, text, objects as numbers): each a TypeError naming it.
WRONG_KINDS = {
    "float face indices": (lambda: recon.Mesh(TRIANGLE, [[0, 1.7, 2]]), "faces must hold integer vertex indices"),
    "bool face indices": (lambda: recon.Mesh(TRIANGLE, np.ones((1, 3), bool)), "faces must hold integer"),
    "complex vertices": (lambda: recon.Mesh(TRIANGLE + 1j, FACE), "vertices must hold real numbers; got dtype complex"),
    "complex points": (lambda: recon.reconstruct(sphere(100) + 0j), "points must hold real numbers; got dtype complex"),
    "text points": (lambda: recon.PointCloud([["a", "b", "c"]]), "points must hold real numbers; got dtype <U1"),
    "object points": (lambda: recon.estimate_normals([[1, None, 2]]), "points must hold real numbers; got dtype obj"),
    "bool normals": (lambda: recon.PointCloud(TRIANGLE, normals=TRIANGLE > 0), "normals must hold real numbers"),
    "complex normals": (lambda: recon.write_points("/nowhere/n.ply", TRIANGLE, TRIANGLE + 0j), "normals must hold"),
    "complex colours": (lambda: recon.PointCloud(TRIANGLE, colors=TRIANGLE + 0j), "colors must be integers 0-255 or"),
    "bool colours": (lambda: recon.Mesh(TRIANGLE, FACE, colors=TRIANGLE > 0), "colors must be integers 0-255 or"),
    "float colours, _recon": (lambda: recon._recon.PointCloud(TRIANGLE, None, TRIANGLE), "colors must be uint8"),
    "no points": (lambda: recon.PointCloud(None), "points must hold real numbers; got dtype object"),
}


@pytest.mark.parametrize("case", WRONG_KINDS)
def test_arrays_of_the_wrong_kind_are_type_errors(case):
    call, message = WRONG_KINDS[case]
    with pytest.raises(TypeError, match=message.replace("(", r"\(")):
        call()


def test_arrays_of_a_right_kind_are_converted():
    for faces in ([[0, 1, 2]], np.array(FACE, np.uint16), np.array(FACE, np.int64)):
        np.testing.assert_array_equal(recon.Mesh(TRIANGLE, faces).faces, FACE)
    np.testing.assert_array_equal(recon.PointCloud(np.eye(3, dtype=np.int32)).points, TRIANGLE)
    np.testing.assert_array_equal(recon.PointCloud(TRIANGLE.astype(np.float32)).points, TRIANGLE)


def test_file_errors_carry_the_programs_message(tmp_path):
    bad = tmp_path / "bad.xyz"
    bad.write_text("1 2 3\n4 5 abc\n")
    with pytest.raises(ValueError) as caught:
        recon.read_points(bad)
    assert str(caught.value) == program_error("info", bad)
    missing = tmp_path / "missing.ply"
    with pytest.raises(FileNotFoundError) as caught:
        recon.read_points(missing)
    assert str(caught.value) == program_error("info", missing)
    folder = tmp_path / "folder.xyz"
    folder.mkdir()
    with pytest.raises(IsADirectoryError):
        recon.read_points(folder)
    with pytest.raises(OSError, match="cannot write"):
        recon.write_points(tmp_path / "no-such-folder" / "out.ply", sphere(10))


def test_too_much_work_is_a_resource_limit_error(tmp_path):
    points = sphere(20000)
    with pytest.raises(recon.ResourceLimitError) as caught:
        recon.reconstruct(points, method="hoppe92", max_memory="1M")
    assert isinstance(caught.value, MemoryError)
    path = tmp_path / "s.ply"
    recon.write_points(path, points)
    # The same words as the program's refusal where it refuses in memory
    # (recon normals --method hoppe92, which needs what hoppe92's phases I-II
    # need); recon reconstruct would try tiles first.
    assert str(caught.value) == program_error("normals", path, "-o", tmp_path / "n.ply", "--method", "hoppe92",
                                              "--max-memory", "1M")
    with pytest.raises(ValueError, match="max_memory: unknown size unit"):
        recon.reconstruct(points, max_memory="3 parsecs")


def test_open3d_conversions():
    o3d = pytest.importorskip("open3d", reason="python3-open3d is not installed")
    cloud = recon.PointCloud(sphere(8000, seed=2))
    as_o3d = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(cloud.points))
    np.testing.assert_array_equal(np.asarray(as_o3d.points), cloud.points)
    mesh = recon.reconstruct(np.asarray(as_o3d.points))
    tm = mesh.to_open3d()
    assert len(tm.triangles) == len(mesh.faces)
    assert tm.is_watertight() and tm.is_orientable()
    assert tm.get_volume() == pytest.approx(4.0 / 3.0 * np.pi, rel=0.02)
    back = recon.Mesh.from_open3d(tm)
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.faces, mesh.faces)
    np.testing.assert_array_equal(np.asarray(cloud.to_open3d().points), cloud.points)


def test_reader_options_and_notes(tmp_path):
    seven = tmp_path / "seven.txt"
    seven.write_text("0 0 0 7 1 2 3\n1 0 0 7 4 5 6\n0 1 0 7 7 8 9\n0 0 1 7 1 2 3\n")
    with pytest.raises(ValueError, match="--columns"):
        recon.read_points(seven)
    cloud = recon.read_points(seven, columns=["x", "y", "z", "_", "r", "g", "b"])
    np.testing.assert_array_equal(cloud.colors[1], [4, 5, 6])
    assert any("from --columns" in note for note in cloud.notes)
    assert recon.read_points(seven, columns="x y z _ r g b".split(), colors=False).colors is None
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y,z\n0,0,0\n1,nan,0\n2,2,2\n")
    with pytest.raises(ValueError, match="not finite"):
        recon.read_points(bad)
    kept = recon.read_points(bad, skip_invalid=True)
    np.testing.assert_array_equal(kept.points, [[0, 0, 0], [2, 2, 2]])
    assert any("skipped" in note for note in kept.notes)
