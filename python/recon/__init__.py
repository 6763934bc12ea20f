"""recon: surface reconstruction from unorganized points (Hoppe et al. 1992).

The Python face of the recon library, with the command line's defaults and
checks::

    import recon
    cloud = recon.read_points("scan.ply")              # or any n x 3 array
    mesh = recon.reconstruct(cloud.points, threads=2)
    print(mesh.stats["mesh"])                          # what --stats records
    mesh.save("mesh.ply")

Arrays go in as they are: a C-contiguous float64 n x 3 array is read in
place (float32 and other layouts are converted once), and the arrays that
come out (``mesh.vertices``, ``mesh.faces``, ``cloud.points``, ...) are views
of recon's own buffers, which they keep alive. recon releases the GIL while
it works; Ctrl-C raises KeyboardInterrupt at the next step of the phase
running (within about a second on a million points).

Errors: ``TypeError`` for an array of the wrong kind, naming it (complex,
bool or text coordinates; faces that are not integers: an index 1.7 is
never truncated to 1); ``ValueError`` for unusable data, parameters or a
malformed file (the message is the one the program prints); ``ResourceLimitError`` (a
``MemoryError``) when a run is estimated to need more memory than allowed;
``FileNotFoundError`` and other ``OSError`` subclasses for files.

Open3D: ``open3d.geometry.PointCloud(open3d.utility.Vector3dVector(cloud.points))``
makes an Open3D cloud; ``recon.reconstruct(numpy.asarray(o3d_cloud.points))``
reconstructs one; ``mesh.to_open3d()`` / ``recon.Mesh.from_open3d(m)`` convert
meshes both ways.
"""

from __future__ import annotations

import os
from typing import Any, Callable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _recon
from ._recon import ResourceLimitError

#: recon's version, the compiled library's own (recon/core/version.h): the same
#: string as ``recon --version``, the wheel's version and the "version" of
#: every stats dict, e.g. "0.1.0" or "0.1.0+g1a2b3c4" (docs/releasing.md).
__version__: str = _recon.__version__

__all__ = [
    "PointCloud",
    "Mesh",
    "ResourceLimitError",
    "read_points",
    "write_points",
    "estimate_normals",
    "reconstruct",
]

PathLike = Union[str, "os.PathLike[str]"]
Progress = Callable[[str], Any]


def _rows(points: Any) -> Optional[int]:
    """The rows of `points` when it has any (the array's checks say what is wrong otherwise)."""
    return np.shape(points)[0] if np.ndim(points) >= 1 else None


def _colors_as_bytes(colors: Any, rows: Optional[int] = None) -> Optional[np.ndarray]:
    """Colours as an n x 3 uint8 array: 0-255 integers as they are, floats
    in [0, 1] times 255. TypeError for another kind (complex, bool, text)."""
    if colors is None:
        return None
    array = np.asarray(colors)
    if array.ndim != 2 or array.shape[1] != 3 or (rows is not None and array.shape[0] != rows):
        want = f"{rows} x 3" if rows is not None else "n x 3"
        raise ValueError(f"colors must be a {want} array; got shape {array.shape}")
    if array.dtype == np.uint8:
        return array
    if np.issubdtype(array.dtype, np.floating):
        if array.size and not (np.all(np.isfinite(array)) and array.min() >= 0.0 and array.max() <= 1.0):
            raise ValueError("colors given as floats must lie in [0, 1] (or give uint8 values 0-255)")
        return np.rint(array * 255.0).astype(np.uint8)
    if np.issubdtype(array.dtype, np.integer):
        if array.size and (array.min() < 0 or array.max() > 255):
            raise ValueError("colors given as integers must lie in 0-255")
        return array.astype(np.uint8)
    raise TypeError(f"colors must be integers 0-255 or floats in [0, 1]; got dtype {array.dtype}")


class _Wraps:
    """A package object around one of the compiled module's (``_made``),
    whose arrays it hands out as they are: views of recon's buffers."""

    __slots__ = ("_made",)

    @classmethod
    def _of(cls, made: Any) -> Any:
        wrapper = cls.__new__(cls)
        wrapper._made = made
        return wrapper


def _passed_on(name: str, doc: str) -> property:
    """A read-only attribute of the wrapped object, passed on as it is."""
    return property(lambda self: getattr(self._made, name), doc=doc)


class PointCloud(_Wraps):
    """A point cloud: ``points`` (n x 3 float64), and ``normals`` (n x 3) and
    ``colors`` (n x 3 uint8) or None. ``notes`` lists what the reader chose
    or skipped (the lines the program prints under "read"). Made from arrays,
    it holds copies of them; read from a file, its arrays are recon's."""

    __slots__ = ()

    def __init__(self, points: Any, normals: Any = None, colors: Any = None) -> None:
        self._made = _recon.PointCloud(points, normals, _colors_as_bytes(colors, _rows(points)))

    points = _passed_on("points", "n x 3 float64")
    normals = _passed_on("normals", "n x 3 float64, or None")
    colors = _passed_on("colors", "n x 3 uint8, or None")
    notes = _passed_on("notes", "what the reader chose or skipped, one line each")

    def __len__(self) -> int:
        return len(self._made)

    def __repr__(self) -> str:
        extras = [name for name in ("normals", "colors") if getattr(self, name) is not None]
        return f"recon.PointCloud({len(self)} points{' with ' + ' and '.join(extras) if extras else ''})"

    def to_open3d(self) -> Any:
        """This cloud as an ``open3d.geometry.PointCloud`` (needs python3-open3d)."""
        import open3d  # noqa: PLC0415 - optional

        o3d = open3d.geometry.PointCloud(open3d.utility.Vector3dVector(self.points))
        if self.normals is not None:
            o3d.normals = open3d.utility.Vector3dVector(self.normals)
        if self.colors is not None:
            o3d.colors = open3d.utility.Vector3dVector(self.colors / 255.0)
        return o3d


class Mesh(_Wraps):
    """A triangle mesh: ``vertices`` (m x 3 float64), ``faces`` (f x 3 int32,
    counter-clockwise seen from outside), ``colors`` (m x 3 uint8) or None,
    ``normals`` (m x 3 float64, unit, on the side the faces face) or None,
    and, for a mesh made by reconstruct(), ``stats``: what
    ``recon reconstruct --stats`` records (an empty dict otherwise). The
    arrays of a reconstructed mesh are recon's own buffers, not copies."""

    __slots__ = ()

    def __init__(self, vertices: Any, faces: Any, colors: Any = None, normals: Any = None) -> None:
        self._made = _recon.Mesh(vertices, faces, _colors_as_bytes(colors, _rows(vertices)), normals)

    vertices = _passed_on("vertices", "m x 3 float64")
    faces = _passed_on("faces", "f x 3 int32, counter-clockwise seen from outside")
    colors = _passed_on("colors", "m x 3 uint8, or None")
    normals = _passed_on("normals", "m x 3 float64 unit vertex normals, or None")
    stats = _passed_on("stats", "what recon reconstruct --stats records ({} for a mesh made from arrays)")

    def __repr__(self) -> str:
        return f"recon.Mesh({len(self.vertices)} vertices, {len(self.faces)} faces)"

    def save(self, path: PathLike, ascii: bool = False) -> None:
        """Writes the mesh as PLY, OBJ, OFF, STL or GLB (from the extension),
        atomically: a temporary file renamed into place. Its normals, when
        it has them, go into PLY (nx ny nz) and OBJ (vn); GLB always has
        normals (the faces' area-weighted ones when the mesh has none)."""
        self._made.save(os.fspath(path), ascii)

    def to_open3d(self) -> Any:
        """This mesh as an ``open3d.geometry.TriangleMesh`` (needs python3-open3d)."""
        import open3d  # noqa: PLC0415 - optional

        o3d = open3d.geometry.TriangleMesh(
            open3d.utility.Vector3dVector(self.vertices), open3d.utility.Vector3iVector(self.faces)
        )
        if self.colors is not None:
            o3d.vertex_colors = open3d.utility.Vector3dVector(self.colors / 255.0)
        return o3d

    @classmethod
    def from_open3d(cls, mesh: Any) -> "Mesh":
        """A recon Mesh from an ``open3d.geometry.TriangleMesh`` (copied)."""
        colors = np.asarray(mesh.vertex_colors) if mesh.has_vertex_colors() else None
        return cls(np.asarray(mesh.vertices), np.asarray(mesh.triangles), colors)


def read_points(
    path: PathLike,
    format: Optional[str] = None,
    *,
    columns: Optional[Sequence[str]] = None,
    skip_invalid: bool = False,
    colors: bool = True,
) -> PointCloud:
    """Reads a point cloud: PLY, XYZ/CSV/TXT text, Hoppe's .pts, OBJ, OFF, PCD
    or LAS, chosen from the extension unless ``format`` names it.

    ``columns`` names the columns of a text file without a header (as
    ``--columns``: "x", "y", "z", "nx", "ny", "nz", "r", "g", "b", "_");
    ``skip_invalid`` leaves out points with a coordinate that is not finite
    instead of refusing the file; ``colors=False`` drops the colours."""
    cloud = PointCloud._of(_recon.read_points(os.fspath(path), format, list(columns) if columns else None,
                                              skip_invalid))
    if not colors and cloud.colors is not None:
        cloud = PointCloud(cloud.points, cloud.normals)
    return cloud


def write_points(path: PathLike, points: Any, normals: Any = None, colors: Any = None, *, ascii: bool = False) -> None:
    """Writes a cloud as PLY (binary, or ``ascii``) or XYZ text, atomically."""
    _recon.write_points(os.fspath(path), points, normals, _colors_as_bytes(colors, _rows(points)), ascii)


def _cloud_arrays(points: Any, normals: Any, colors: Any) -> Tuple[Any, Any, Any]:
    if isinstance(points, PointCloud):
        if normals is None:
            normals = points.normals
        if colors is None:
            colors = points.colors
        points = points.points
    return points, normals, colors


def estimate_normals(
    points: Any,
    k: Optional[int] = None,
    rho: Optional[float] = None,
    threads: Optional[int] = None,
    *,
    max_memory: Union[None, int, str] = None,
    progress: Optional[Progress] = None,
    method: str = "refined",
) -> Tuple[np.ndarray, dict]:
    """Phases I and II (``recon normals``): consistently oriented normals.

    ``points``: (n, 3) float64. Returns ``(normals, info)``: an (n, 3)
    float64 array of unit normals in the order of ``points``, and the
    phases' statistics (``info["method"]``, ``info["tangent_planes"]``,
    ``info["orientation"]``: as ``--stats`` records them).

    ``method="refined"`` (the default) gives the normals
    ``reconstruct(method="refined")`` orients, bit for bit: second-order
    fits, each piece's side decided at its best extreme; ``"hoppe92"`` the
    1992 paper's phases I and II exactly. Another name raises ValueError.
    ``k`` defaults to 20, raised for noisy data; ``rho`` is estimated per
    point unless given; ``threads`` defaults to all cores;
    ``progress(phase)`` is called as each phase starts."""
    points, _, _ = _cloud_arrays(points, None, None)
    return _recon.estimate_normals(points, k, rho, threads, max_memory, progress, method)


def reconstruct(
    points: Any,
    normals: Any = None,
    *,
    colors: Any = None,
    k: Optional[int] = None,
    rho: Optional[float] = None,
    delta: Optional[float] = None,
    cell: Optional[float] = None,
    resolution: Optional[int] = None,
    method: str = "refined",
    keep_fragments: bool = False,
    max_memory: Union[None, int, str] = None,
    threads: Optional[int] = None,
    report: Optional[PathLike] = None,
    progress: Optional[Progress] = None,
    vertex_normals: bool = False,
    simplify: Union[None, int, float] = None,
    max_error: Optional[float] = None,
) -> Mesh:
    """Phases I-IV (and V for the refined method): a triangle mesh of the
    surface the points sample, as ``recon reconstruct`` makes it.

    ``points`` is an n x 3 array or a PointCloud (whose normals and colours
    are then used). Given ``normals`` are used instead of estimating them
    (``--use-normals``); given ``colors`` (n x 3, uint8 or floats in [0, 1])
    colour the mesh's vertices. ``k``, ``rho``, ``delta``, ``cell`` /
    ``resolution``, ``method`` ("refined" or "hoppe92"), ``keep_fragments``
    and ``max_memory`` (bytes, or "8G") mean what the program's options of
    the same names mean, with the same defaults. ``report`` writes the HTML
    report of every phase. ``progress(phase)`` is called as each phase
    starts. ``simplify`` (an int: a triangle count; a float below 1: a
    ratio) and ``max_error`` (a multiple of rho) simplify the mesh keeping
    creases, corners, boundaries and separate objects, as ``--simplify`` and
    ``--max-error`` do. The result's ``stats`` holds what ``--stats`` records.
    ``vertex_normals=True`` gives the mesh unit vertex normals
    (``mesh.normals``, as ``--normals``: the fitted surface's where phase V
    has one, the faces' area-weighted mean elsewhere); ``normals`` is the
    input's own normals, not these."""
    points, normals, colors = _cloud_arrays(points, normals, colors)
    made = _recon.reconstruct(points, normals, _colors_as_bytes(colors, _rows(points)), k, rho, delta, cell, resolution,
                              method, keep_fragments, max_memory, threads,
                              None if report is None else os.fspath(report), progress, vertex_normals, simplify, max_error)
    return Mesh._of(made)

