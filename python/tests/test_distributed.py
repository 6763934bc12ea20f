"""recon.distributed: the tiles as Dask tasks on a local cluster of two
worker processes (loopback) give the in-memory run's triangles
(recon.reconstruct, no tiles), and the mesh of the same tiled run made in
this process (and by `recon reconstruct --tile-size`) byte for byte, also
when a worker is killed in the middle of a tile; `python3 -m
recon.distributed` as a program, and its checks before any work. Every wait
is bounded (Dask's timeouts, the run's own, the subprocesses')."""

import json
import os
import signal
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from recon import _recon
from conftest import run_cli, sphere

distributed = pytest.importorskip("distributed", reason="Dask is not installed (python3-distributed; scripts/setup)")
import recon.distributed  # noqa: E402 - needs Dask

# Debian's Dask 2022.12 with its Tornado 6.2 starts its event loop the old way.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

TILE_SIZE = 1.0   # on the torus below (2.7 x 2.7 x 0.7): 9 tiles
TIMEOUT = 60.0    # seconds any one run may take


def cluster():
    """A local cluster of two single-threaded worker processes on the loopback address."""
    return distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                    dashboard_address=None, env={"OMP_NUM_THREADS": "1"})


def tiled_in_this_process(cloud: Path, output: Path, work_dir: Path) -> dict:
    """The single-process tiled run: the same steps, one after the other,
    here, each tile on one thread (as on the workers below)."""
    folder = str(work_dir)
    plan = _recon._tiles_plan(str(cloud), folder, tile_size=TILE_SIZE)
    orient = [_recon._tiles_orient(folder, t, threads=1) for t in range(plan["tiles"])]
    reconciliation = _recon._tiles_reconcile(folder)
    contour = [_recon._tiles_contour(folder, t, threads=1) for t in range(plan["tiles"])]
    mesh = _recon._tiles_stitch(folder, str(output))
    return {"plan": plan, "orient": orient, "reconcile": reconciliation, "contour": contour, "mesh": mesh}


@pytest.fixture(scope="module")
def torus(tmp_path_factory) -> Path:
    """A 200,000-point torus: tiles that take about 0.05-0.15 s each to orient or contour on one thread."""
    path = tmp_path_factory.mktemp("cloud") / "torus.ply"
    run_cli("generate", "torus", "-n", "200000", "-o", path, "--quiet")
    return path


@pytest.fixture(scope="module")
def reference(torus, tmp_path_factory) -> dict:
    """The single-process run's figures, and its mesh ("path"): the mesh
    of `recon reconstruct --tile-size` too."""
    folder = tmp_path_factory.mktemp("reference")
    figures = tiled_in_this_process(torus, folder / "mesh.ply", folder / "tiles")
    figures["path"] = folder / "mesh.ply"
    program = folder / "program.ply"
    run_cli("--threads", "1", "reconstruct", torus, "-o", program, "--tile-size", TILE_SIZE, "--quiet")
    assert program.read_bytes() == figures["path"].read_bytes()
    return figures


def read_ply_mesh(path: Path) -> tuple:
    """The vertices (n x 3 float64) and triangles (f x 3) of a binary PLY mesh as recon writes it."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert "format binary_little_endian 1.0" in header
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element")}
    vertex_properties = header[header.index(f"element vertex {counts['vertex']}") + 1:]
    vertex_properties = vertex_properties[:next(i for i, line in enumerate(vertex_properties)
                                                if not line.startswith("property"))]
    types = {"double": "<f8", "float": "<f4", "uchar": "u1"}
    vertex = np.dtype([(line.split()[2], types[line.split()[1]]) for line in vertex_properties])
    face = np.dtype([("n", "u1"), ("v", "<i4", 3)])
    vertices = np.frombuffer(data, vertex, counts["vertex"], end)
    faces = np.frombuffer(data, face, counts["face"], end + vertex.itemsize * counts["vertex"])
    assert np.all(faces["n"] == 3)
    return np.column_stack([vertices["x"], vertices["y"], vertices["z"]]).astype(np.float64), faces["v"]


def canonical_triangles(faces: np.ndarray) -> np.ndarray:
    """Triangles rotated to start at their smallest index (which keeps their orientation), sorted."""
    first = np.argmin(faces, axis=1)[:, None]
    rotated = np.take_along_axis(faces, (first + np.arange(3)) % 3, axis=1)
    return rotated[np.lexsort(rotated.T[::-1])]


def assert_same_triangles(mesh: tuple, in_memory: "recon.Mesh", tolerance: float) -> None:
    """As tests/mesh_compare.h's same_mesh: each vertex has its own vertex
    of the in-memory mesh within `tolerance` (one to one), and the triangles
    are the same, oriented the same way, in any order."""
    vertices, faces = mesh
    assert (len(vertices), len(faces)) == (len(in_memory.vertices), len(in_memory.faces))
    def keys(v):
        return map(tuple, np.rint(v / tolerance).astype(np.int64))
    index = {key: i for i, key in enumerate(keys(in_memory.vertices))}
    assert len(index) == len(in_memory.vertices)
    to_memory = np.array([index.get(key, -1) for key in keys(vertices)])
    assert np.all(to_memory >= 0), f"{np.count_nonzero(to_memory < 0)} vertices are not the in-memory mesh's"
    assert len(set(to_memory.tolist())) == len(to_memory), "two vertices on one"
    np.testing.assert_array_equal(canonical_triangles(to_memory[faces]), canonical_triangles(in_memory.faces))


@pytest.fixture(scope="module")
def in_memory(torus) -> "recon.Mesh":
    """The in-memory run of the torus (recon.reconstruct, no tiles): what the
    tiled mesh must be on clean data, as the README says. The tiled and
    Dask meshes are compared with it, not only with each other (the same
    tile code), so that a logic bug in the tiles shows."""
    return recon.reconstruct(recon.read_points(torus).points, threads=2)


def in_memory_tolerance(reference: dict) -> float:
    return 1e-6 * reference["plan"]["cell"]


def test_the_tiled_run_is_the_in_memory_run(reference, in_memory):
    assert reference["plan"]["tiles"] >= 8 and reference["reconcile"]["objects"] == 1
    assert_same_triangles(read_ply_mesh(reference["path"]), in_memory, in_memory_tolerance(reference))


def test_the_steps_alone(reference, tmp_path):
    plan = reference["plan"]
    assert plan["tiles"] >= 8
    assert plan["input_points"] == 200000 and plan["statistics_points"] == 200000
    assert len(plan["tile_points"]) == plan["tiles"] and sum(plan["tile_core_points"]) == 200000
    assert all(o["inexact_samples"] == 0 for o in reference["orient"])
    assert reference["reconcile"]["disagreeing"] == 0 and reference["reconcile"]["objects"] == 1
    assert reference["mesh"]["triangles"] == sum(c["triangles"] for c in reference["contour"]) > 0
    folder = str(tmp_path / "tiles")
    small = tmp_path / "small.ply"
    run_cli("generate", "sphere", "-n", "3000", "-o", small, "--quiet")
    assert _recon._tiles_plan(str(small), folder, tile_size=0.5)["tiles"] == _recon._tiles_count(folder)
    with pytest.raises(ValueError, match="holds the plan of another tiled run"):
        _recon._tiles_plan(str(small), folder)
    with pytest.raises(ValueError, match="tile 1000 of a plan of"):
        _recon._tiles_orient(folder, 1000)
    with pytest.raises(ValueError, match="tile_size must be zero or more"):
        _recon._tiles_plan(str(small), str(tmp_path / "other"), tile_size=-1.0)
    with pytest.raises(OSError, match="plan.bin: cannot open"):
        _recon._tiles_count(str(tmp_path / "nowhere"))


def test_a_dask_run_gives_the_in_memory_mesh(torus, reference, in_memory, tmp_path):
    output = tmp_path / "mesh.ply"
    stale = tmp_path / "recon-tiles-killed"  # a run killed by SIGKILL left it: its lock is free
    stale.mkdir()
    (stale / "recon-tiles.lock").touch()
    (stale / "tile-000000.points").write_bytes(b"x")
    figures = recon.distributed.run(torus, output, workers=2, tile_size=TILE_SIZE, timeout=TIMEOUT)
    assert figures["version"] == recon.__version__  # as every stats dict (test_packaging.py compares them all)
    assert_same_triangles(read_ply_mesh(output), in_memory, in_memory_tolerance(reference))
    assert output.read_bytes() == reference["path"].read_bytes()
    assert figures["plan"] == {**reference["plan"], "seconds": figures["plan"]["seconds"]}
    assert [o["pieces"] for o in figures["orient"]] == [o["pieces"] for o in reference["orient"]]
    assert len(figures["workers"]) == 2 and figures["threads_per_task"] == max(1, len(os.sched_getaffinity(0)) // 2)
    assert sum(w["tasks"] for w in figures["workers"].values()) == 2 * figures["plan"]["tiles"]
    assert all(w["tasks"] > 0 for w in figures["workers"].values()), "both workers ran tiles"
    assert [p.name for p in tmp_path.iterdir()] == ["mesh.ply"], "the tiles' folder is removed, and the stale one"


def running_tasks(dask_worker):
    """On a worker: its pid and, per task it is running, for how long (s)."""
    now = time.time()
    return os.getpid(), {key: now - dask_worker.state.tasks[key].start_time for key in list(dask_worker.active_keys)}


def kill_a_worker_mid_tile(client, reference: dict, started: threading.Event, killed: dict) -> None:
    """Once a tile is done, SIGKILLs a worker whose task (orient or contour)
    has run for less than half of what that tile's step took in the
    single-process run (so it is surely in the middle of it); notes the pid
    and the task."""
    if not started.wait(TIMEOUT):
        return
    deadline = time.monotonic() + TIMEOUT
    while time.monotonic() < deadline:
        for pid, ages in client.run(running_tasks).values():
            for key, age in ages.items():
                _, step, _, tile = key.split("-")
                if age < 0.5 * reference[step][int(tile)]["seconds"] - 0.01:
                    os.kill(pid, signal.SIGKILL)
                    killed.update(pid=pid, key=key)
                    return
        time.sleep(0.002)


def transitions(client, key: str) -> list:
    """The scheduler's story of the task `key`: its (from, to) states."""
    story = client.run_on_scheduler(lambda dask_scheduler: dask_scheduler.story(key))
    return [(event[1], event[2]) for event in story if event[0] == key]


def test_a_worker_killed_mid_tile_changes_nothing(torus, reference, tmp_path):
    output = tmp_path / "mesh.ply"
    with cluster() as local, distributed.Client(local, set_as_default=False) as client:
        client.wait_for_workers(2, timeout=TIMEOUT)
        before = set(client.run(os.getpid).values())
        started, killed = threading.Event(), {}
        killer = threading.Thread(target=kill_a_worker_mid_tile, args=(client, reference, started, killed))
        killer.start()
        recon.distributed.run(torus, output, client=client, tile_size=TILE_SIZE, threads_per_task=1,
                              timeout=TIMEOUT, progress=lambda step, done, total: started.set())
        killer.join(TIMEOUT)
        assert killed, "no worker was caught in the middle of a tile"
        assert killed["pid"] in before
        story = transitions(client, killed["key"])
        # Taken from the dead worker without a result, then run again, to the end.
        assert ("processing", "released") in story and story.count(("processing", "memory")) == 1, story
        assert story.index(("processing", "released")) < story.index(("processing", "memory")), story
        client.wait_for_workers(2, timeout=TIMEOUT)  # the nanny has started a new worker process
        after = set(client.run(os.getpid).values())
        assert killed["pid"] not in after and len(after) == 2
    assert output.read_bytes() == reference["path"].read_bytes()


def run_module(*args, timeout: float = 2 * TIMEOUT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "recon.distributed", *map(str, args)], capture_output=True,
                          text=True, timeout=timeout)


def test_the_program(torus, reference, tmp_path):
    output = tmp_path / "mesh.ply"
    stats = tmp_path / "stats.json"
    finished = run_module(torus, "-o", output, "--workers", "2", "--tile-size", TILE_SIZE, "--timeout", TIMEOUT,
                          "--stats", stats)
    assert finished.returncode == 0, finished.stderr
    assert f"{reference['plan']['tiles']} tiles on 2 workers" in finished.stdout
    assert output.read_bytes() == reference["path"].read_bytes()
    assert json.loads(stats.read_text())["mesh"]["triangles"] == reference["mesh"]["triangles"]
    stats.unlink()
    missing = tmp_path / "missing.ply"
    finished = run_module(missing, "-o", tmp_path / "out.ply", "--workers", "2")
    assert finished.returncode == 1
    assert finished.stderr.startswith("recon.distributed: error: ") and "missing.ply" in finished.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mesh.ply"], "no output, no tiles' folder left"
    finished = run_module(torus, "-o", tmp_path / "mesh.obj")
    assert finished.returncode == 1 and "binary PLY" in finished.stderr


def test_ctrl_c_removes_the_tiles(torus, tmp_path):
    output = tmp_path / "mesh.ply"
    program = subprocess.Popen([sys.executable, "-m", "recon.distributed", torus, "-o", output, "--workers", "2",
                                "--tile-size", str(TILE_SIZE)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    try:
        deadline = time.monotonic() + TIMEOUT
        while not list(tmp_path.glob("recon-tiles-*/tile-*.orient")) and time.monotonic() < deadline:
            time.sleep(0.01)
        program.send_signal(signal.SIGINT)  # as Ctrl-C, to the client alone: the tiles are being oriented
        _, stderr = program.communicate(timeout=TIMEOUT)
    finally:
        program.kill()
    assert program.returncode == 130, stderr
    assert stderr.endswith("recon.distributed: interrupted\n")
    assert list(tmp_path.iterdir()) == [], "neither the mesh nor the tiles' folder is left"


# ---------------------------------------------------------------------------
# The program's checks, made before any work: they refuse what would destroy
# a file or overload the machine, in one line, without starting a cluster.

def program(capsys, *args) -> tuple:
    """`python3 -m recon.distributed ARGS` run here: its exit status and what it printed on stderr."""
    try:
        status = recon.distributed.main([str(a) for a in args])
    except SystemExit as exit:  # argparse's
        status = exit.code
    return status, capsys.readouterr().err


def one_line_error(status: int, stderr: str, expected: str) -> None:
    assert status != 0
    assert stderr.startswith("recon.distributed: error: ") and stderr.count("\n") == 1, stderr
    assert expected in stderr, stderr


@pytest.fixture
def no_cluster(monkeypatch):
    """Fails a run that gets as far as starting or reaching a cluster (so
    that a check that is missing fails the test instead of starting 1000
    workers or writing over the input)."""
    def refused(*args, **options):
        raise AssertionError("the run went on to start a cluster")
    monkeypatch.setattr(recon.distributed, "_connected", refused)


@pytest.fixture
def small_cloud(tmp_path) -> Path:
    path = tmp_path / "in.ply"
    recon.write_points(path, sphere(200))
    return path


def test_an_output_that_is_the_input_is_refused(small_cloud, tmp_path, capsys, no_cluster):
    before = small_cloud.read_bytes()
    (tmp_path / "hard.ply").hardlink_to(small_cloud)
    (tmp_path / "soft.ply").symlink_to(small_cloud)
    for output in (small_cloud, tmp_path / "." / "in.ply", tmp_path / "hard.ply", tmp_path / "soft.ply"):
        one_line_error(*program(capsys, small_cloud, "-o", output), "refusing to overwrite the input file")
        with pytest.raises(ValueError, match="refusing to overwrite the input file"):
            recon.distributed.run(small_cloud, output)
    assert small_cloud.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hard.ply", "in.ply", "soft.ply"], "no tiles' folder"


def test_stats_naming_the_input_the_output_or_no_folder_is_refused_first(small_cloud, tmp_path, capsys, monkeypatch):
    runs = []
    monkeypatch.setattr(recon.distributed, "run", lambda *args, **options: runs.append(args))
    output = tmp_path / "mesh.ply"
    output.write_bytes(b"an earlier mesh")
    cases = {small_cloud: "refusing to overwrite the input file",
             output: "mesh.ply is named for two outputs",
             tmp_path / "missing" / "s.json": "cannot write: folder '" + str(tmp_path / "missing") + "' does not exist",
             tmp_path: "cannot write: it is a folder"}
    for stats, message in cases.items():
        one_line_error(*program(capsys, small_cloud, "-o", output, "--stats", stats), message)
    assert runs == [], "refused before the run"
    assert output.read_bytes() == b"an earlier mesh"
    one_line_error(*program(capsys, small_cloud, "-o", tmp_path / "missing" / "m.ply"), "does not exist")


FIGURES = {"plan": {"tiles": 3}, "seconds": {"total": 1.5}}


@pytest.fixture
def stats_run(monkeypatch):
    """The program with a run that only returns FIGURES: its --stats writing alone."""
    monkeypatch.setattr(recon.distributed, "run", lambda *args, **options: FIGURES)


def write_stats(capsys, cloud: Path, stats: Path) -> None:
    status, stderr = program(capsys, cloud, "-o", cloud.parent / "mesh.ply", "--stats", stats, "-q")
    assert status == 0, stderr


def test_stats_replace_a_file_whole(small_cloud, tmp_path, capsys, stats_run):
    stats = tmp_path / "stats.json"
    stats.write_text("the previous run's figures")
    before = stats.stat().st_ino
    write_stats(capsys, small_cloud, stats)
    assert json.loads(stats.read_text()) == FIGURES
    assert stats.stat().st_ino != before, "a finished file renamed into place, not the old one cut and rewritten"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.ply", "stats.json"], "no temporary file left"


# The special outputs' behaviour is io::AtomicFile's (recon_module.cpp's
# _write_text writes through it): the mode kept, a symlink written
# through, a FIFO streamed to.
def test_stats_keep_the_files_mode(small_cloud, tmp_path, capsys, stats_run):
    stats = tmp_path / "stats.json"
    stats.write_text("{}")
    stats.chmod(0o600)
    write_stats(capsys, small_cloud, stats)
    assert stats.stat().st_mode & 0o777 == 0o600


def test_stats_go_through_a_symlink(small_cloud, tmp_path, capsys, stats_run):
    target, link = tmp_path / "target.json", tmp_path / "link.json"
    target.write_text("{}")
    link.symlink_to(target)
    write_stats(capsys, small_cloud, link)
    assert link.is_symlink() and json.loads(target.read_text()) == FIGURES


def test_stats_stream_into_a_fifo(small_cloud, tmp_path, capsys, stats_run):
    fifo = tmp_path / "stats.fifo"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # open first, so the writer's open does not wait
    try:
        write_stats(capsys, small_cloud, fifo)
        received = os.read(reader, 1 << 16)
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(fifo.stat().st_mode), "the FIFO itself is not replaced"
    assert json.loads(received) == FIGURES


def test_workers_and_threads_are_bounded_by_the_machine(small_cloud, tmp_path, capsys, no_cluster):
    bound = recon.distributed.PROCESSES_PER_CORE * len(os.sched_getaffinity(0))
    output = tmp_path / "mesh.ply"
    for option, value in (("--workers", 1000), ("--workers", 0), ("--threads-per-task", 100000),
                          ("--threads-per-task", 0)):
        name = option[2:].replace("-", "_")
        one_line_error(*program(capsys, small_cloud, "-o", output, option, value),
                       f"{name} must be between 1 and {bound} (4 per core")
    with pytest.raises(ValueError, match=f"workers must be between 1 and {bound}"):
        recon.distributed.run(small_cloud, output, workers=bound + 1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.ply"], "nothing started, nothing written"


def test_wrong_arguments_are_one_line(small_cloud, tmp_path, capsys, no_cluster):
    output = tmp_path / "mesh.ply"
    cases = {("--workers", "two"): "argument --workers: invalid int value: 'two'",
             ("--scheduler", "tcp://127.0.0.1:8786", "--workers", "2"): "not allowed with argument",
             ("--scheduler", "somewhere"): "scheduler: missing port number in address 'somewhere'",
             ("--statistics-points", "-1"): "statistics_points must be zero or more",
             ("--statistics-points", str(10**20)): "statistics_points is far out of range",
             ("--k", str(10**11)): "k must be between 3 and 256, got 100000000000",
             ("--resolution", str(10**30)): "resolution is far out of range",
             ("--timeout", "nan"): "timeout must be a positive number of seconds",
             ("--tile-size", "nan"): "tile_size must be zero or more",
             ("--method", "poisson"): "invalid choice: 'poisson'"}
    for extra, message in cases.items():
        one_line_error(*program(capsys, small_cloud, "-o", output, *extra), message)
    one_line_error(*program(capsys, small_cloud), "the following arguments are required: -o/--output")


def test_a_dask_run_gives_the_in_memory_normals(tmp_path):
    """Vertex normals through Dask: phase V's fitted ones travel in the
    tiles' files, the stitch fills the rest from the faces; compared with
    the in-memory run's (as floats, the file's precision)."""
    cloud = tmp_path / "box.ply"
    run_cli("generate", "box", "-n", "12000", "-o", cloud, "--quiet")
    output = tmp_path / "mesh.ply"
    recon.distributed.run(cloud, output, workers=2, tile_size=0.45, timeout=TIMEOUT, vertex_normals=True)
    data = output.read_bytes()
    header = data[:data.index(b"end_header\n")].decode("ascii")
    assert "property float nx\nproperty float ny\nproperty float nz\n" in header
    count = int(header.split("element vertex ")[1].split()[0])
    records = np.frombuffer(data, np.dtype([("p", "<f8", 3), ("n", "<f4", 3)]), count,
                            data.index(b"end_header\n") + len(b"end_header\n"))
    in_memory = recon.reconstruct(recon.read_points(cloud).points, vertex_normals=True)
    assert_same_triangles(read_ply_mesh(output), in_memory, 1e-9)
    keys = {tuple(v): i for i, v in enumerate(np.rint(in_memory.vertices / 1e-9).astype(np.int64))}
    order = [keys[tuple(v)] for v in np.rint(records["p"] / 1e-9).astype(np.int64)]
    expected = in_memory.normals[order].astype(np.float32)
    assert np.max(np.abs(records["n"] - expected)) < 1e-6
    assert np.count_nonzero(np.all(records["n"] == expected, axis=1)) > 0.9 * count
