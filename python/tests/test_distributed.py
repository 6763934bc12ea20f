"""recon.distributed: the tiles as Dask tasks on a local cluster of two
worker processes (loopback) give the mesh of the same tiled run made in
this process (and by `recon reconstruct --tile-size`), byte for byte, also
when a worker is killed in the middle of a tile; `python3 -m
recon.distributed` as a program. Every wait is bounded
(Dask's timeouts, the run's own, the subprocesses')."""

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from recon import _recon
from conftest import run_cli

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


def test_a_dask_run_gives_the_single_process_mesh(torus, reference, tmp_path):
    output = tmp_path / "mesh.ply"
    figures = recon.distributed.run(torus, output, workers=2, tile_size=TILE_SIZE, timeout=TIMEOUT)
    assert output.read_bytes() == reference["path"].read_bytes()
    assert figures["plan"] == {**reference["plan"], "seconds": figures["plan"]["seconds"]}
    assert [o["pieces"] for o in figures["orient"]] == [o["pieces"] for o in reference["orient"]]
    assert len(figures["workers"]) == 2 and figures["threads_per_task"] == max(1, len(os.sched_getaffinity(0)) // 2)
    assert sum(w["tasks"] for w in figures["workers"].values()) == 2 * figures["plan"]["tiles"]
    assert all(w["tasks"] > 0 for w in figures["workers"].values()), "both workers ran tiles"
    assert [p.name for p in tmp_path.iterdir()] == ["mesh.ply"], "the tiles' folder is removed"


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
    finished = run_module(torus, "-o", output, "--workers", "2", "--tile-size", TILE_SIZE, "--timeout", TIMEOUT)
    assert finished.returncode == 0, finished.stderr
    assert f"{reference['plan']['tiles']} tiles on 2 workers" in finished.stdout
    assert output.read_bytes() == reference["path"].read_bytes()
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
