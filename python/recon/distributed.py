"""recon.distributed: the tiled reconstruction (include/recon/tiles/tiles.h) run as
Dask tasks, on a cluster of machines or on local worker processes::

    python3 -m recon.distributed scan.ply -o mesh.ply --workers 2
    python3 -m recon.distributed scan.ply -o mesh.ply --scheduler tcp://A:8786 --work-dir /shared/tiles

The plan (step 1: the cloud-wide measures and the binning of the points
into tiles), the reconciliation of the signs (step 3) and the stitching
(step 5) run here, on the client; orienting (step 2) and contouring (step 4)
run as one Dask task per tile on the workers. The tasks read and write
files in the work directory only, so the client and every worker must reach
it by the same path: on a real cluster, a shared filesystem.

A task is safe to run twice (its files appear whole or not at all) and
every step is deterministic, so the mesh is the same, byte for byte, as the
single-process tiled run's, whichever worker ran which tile; when a worker
dies in the middle of a tile, Dask runs the task again elsewhere and the mesh
does not change. The scheduling, the retries and the moving of results are
Dask's (Debian's python3-distributed); recon adds no scheduler of its own.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import resource
import sys
import time
import uuid
from typing import Any, Callable, Dict, Iterator, List, NoReturn, Optional, Sequence, Union

from . import _recon

__all__ = ["run", "main"]

PathLike = Union[str, "os.PathLike[str]"]
Progress = Callable[[str, int, int], Any]


# ---------------------------------------------------------------------------
# The tasks: small top-level functions, so that Dask pickles them by
# reference (the workers import recon.distributed).

def _threads_here(threads: Optional[int]) -> Optional[int]:
    """Threads for a task on this worker: `threads` when given, else this
    machine's cores shared among the worker's task slots."""
    if threads is not None:
        return threads
    from distributed import get_worker  # noqa: PLC0415 - only on a worker

    try:
        slots = get_worker().state.nthreads
    except ValueError:  # not on a worker
        return None
    return max(1, len(os.sched_getaffinity(0)) // max(1, slots))


def _ran_here(figures: Dict[str, Any], threads: Optional[int]) -> Dict[str, Any]:
    """The task's figures, with the worker that made them and its threads."""
    from distributed import get_worker  # noqa: PLC0415 - only on a worker

    figures["threads"] = threads
    with contextlib.suppress(ValueError):
        figures["worker"] = get_worker().address
    return figures


def _orient_task(work_dir: str, tile: int, threads: Optional[int]) -> Dict[str, Any]:
    """Step 2 for one tile."""
    threads = _threads_here(threads)
    return _ran_here(_recon._tiles_orient(work_dir, tile, threads), threads)


def _contour_task(work_dir: str, tile: int, threads: Optional[int]) -> Dict[str, Any]:
    """Step 4 for one tile."""
    threads = _threads_here(threads)
    return _ran_here(_recon._tiles_contour(work_dir, tile, threads), threads)


def _peak_memory() -> Dict[str, Any]:
    """This process's id and its peak resident memory so far (MiB). On Linux
    from VmHWM: ru_maxrss would count what the parent held when it forked
    (Dask starts its workers by fork and exec, after the plan)."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            kib = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
    except (OSError, StopIteration):
        kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"pid": os.getpid(), "peak_rss_mib": kib / 1024.0}


# ---------------------------------------------------------------------------
# The run

class _Deadline:
    """What is left of `timeout` seconds (None: no limit)."""

    def __init__(self, timeout: Optional[float]) -> None:
        self.end = None if timeout is None else time.monotonic() + timeout

    def left(self) -> Optional[float]:
        return None if self.end is None else max(0.0, self.end - time.monotonic())


@contextlib.contextmanager
def _connected(scheduler: Optional[str], workers: int, threads: Optional[int], client: Any,
               deadline: _Deadline) -> Iterator[Any]:
    """A Dask client: `client` as it is, one connected to `scheduler` (by
    the deadline, if any), or one of a local cluster of `workers` processes
    on the loopback address (closed at the end)."""
    if client is not None:
        yield client
        return
    from distributed import Client, LocalCluster  # noqa: PLC0415 - Dask only for a run

    if scheduler is not None:
        wait = {} if deadline.left() is None else {"timeout": deadline.left()}
        with Client(scheduler, set_as_default=False, **wait) as connected:
            yield connected
        return
    # One task slot per process; each task's OpenMP threads share the cores.
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, env={"OMP_NUM_THREADS": str(threads)}) as cluster:
        with Client(cluster, set_as_default=False) as connected:
            yield connected


def _run_tasks(client: Any, task: Callable[..., Dict[str, Any]], step: str, work_dir: str, tiles: int,
               threads: Optional[int], deadline: _Deadline, progress: Optional[Progress]) -> List[Dict[str, Any]]:
    """`task(work_dir, tile, threads)` for every tile as Dask tasks; their
    figures in tile order. Dask reruns a task whose worker died (and up to
    twice one that failed); tasks still pending are cancelled on an error."""
    run_id = uuid.uuid4().hex[:12]
    futures = [client.submit(task, work_dir, t, threads, key=f"recon-{step}-{run_id}-{t:06d}", pure=False, retries=2)
               for t in range(tiles)]
    try:
        figures = []
        for future in futures:
            figures.append(future.result(timeout=deadline.left()))
            if progress is not None:
                progress(step, len(figures), tiles)
        return figures
    finally:
        client.cancel(futures)


def _worker_figures(client: Any, orientations: List[Dict[str, Any]], contours: List[Dict[str, Any]]) -> Dict[str, Any]:
    """Per worker: its process, its peak memory so far, and the tasks of this run it ran."""
    workers = {address: dict(figures, tasks=0) for address, figures in client.run(_peak_memory).items()}
    for figures in orientations + contours:
        if figures.get("worker") in workers:
            workers[figures["worker"]]["tasks"] += 1
    return workers


def _same_file(a: str, b: str) -> bool:
    """Whether `a` and `b` name one file, decided as the program decides
    (app/commands.cpp): when both exist, by device and inode (so through
    hard links and symlinks); otherwise by their resolved paths."""
    if os.path.exists(a) and os.path.exists(b):
        return os.path.samefile(a, b)
    return os.path.realpath(a) == os.path.realpath(b)


def _check_outputs(input: str, outputs: Sequence[str]) -> None:
    """The program's checks of its outputs, made before any work so that a
    run that cannot write its results fails at once and destroys nothing:
    no output is the input or another output, and each one's folder exists.
    Cost: a few stat calls. Throws ValueError (the input, or one file named
    twice), FileNotFoundError (no such folder), IsADirectoryError."""
    for i, output in enumerate(outputs):
        if _same_file(input, output):
            raise ValueError(f"refusing to overwrite the input file {input}; choose another output")
        if any(_same_file(earlier, output) for earlier in outputs[:i]):
            raise ValueError(f"{output} is named for two outputs; give each its own file")
        folder = os.path.dirname(output) or "."
        if not os.path.isdir(folder):
            raise FileNotFoundError(f"{output}: cannot write: folder '{folder}' does not exist")
        if os.path.isdir(output):
            raise IsADirectoryError(f"{output}: cannot write: it is a folder")


PROCESSES_PER_CORE = 4
"""The bound on --workers and --threads-per-task on a local cluster, per
core of this machine: past a few per core they only take turns, while each
worker process costs its own memory (1000 workers once started 368
processes and took 14 GB on 2 cores)."""


def _check_count(name: str, value: int, bound: Optional[int]) -> None:
    """ValueError unless 1 <= value (<= bound, when given), naming the bound."""
    if value < 1 or (bound is not None and value > bound):
        limit = (f"between 1 and {bound} ({PROCESSES_PER_CORE} per core; this machine gives "
                 f"{bound // PROCESSES_PER_CORE} cores)" if bound is not None else "at least 1")
        raise ValueError(f"{name} must be {limit}, got {value}")


def _check_run(local: bool, workers: int, threads_per_task: Optional[int], counts: Dict[str, Optional[int]],
               timeout: Optional[float]) -> None:
    """The run's counts and limits, checked before any work (ValueError).
    `counts` (k, resolution, ...) need only fit the compiled module's
    64-bit integers here: the library checks their ranges and says them."""
    bound = PROCESSES_PER_CORE * len(os.sched_getaffinity(0)) if local else None
    if local:
        _check_count("workers", workers, bound)
    if threads_per_task is not None:  # on a cluster, the workers' library bounds it by their machine
        _check_count("threads_per_task", threads_per_task, bound)
    for name, count in counts.items():
        if count is not None and not -2**63 <= count < 2**63:
            raise ValueError(f"{name} is far out of range, got {count}")
    if counts["statistics_points"] < 0:
        raise ValueError(f"statistics_points must be zero or more, got {counts['statistics_points']}")
    if timeout is not None and not timeout > 0:
        raise ValueError(f"timeout must be a positive number of seconds, got {timeout}")


def _check_address(scheduler: str) -> None:
    """ValueError unless `scheduler` reads as a Dask address with a port.
    Checked before Dask's Client sees it: a Client that fails on a bad
    address hangs the interpreter's exit (Debian's Dask 2022.12)."""
    from distributed.comm.addressing import get_address_host_port  # noqa: PLC0415 - Dask only for a run

    try:
        get_address_host_port(scheduler)
    except ValueError as error:
        raise ValueError(f"scheduler: {error} (give it as tcp://host:8786)") from None


def _work_folder(work_dir: Optional[PathLike], output: str) -> Any:
    """A fresh folder for the run's files inside `work_dir` (or beside the
    output), the program's own (include/recon/tiles/tiles.h, TileWorkspace): made
    by mkdtemp and locked for the run, so that two runs never share one, and
    removed when closed; stale ones there (their lock free: a run killed
    with SIGKILL) are removed first."""
    parent = os.path.abspath(os.fspath(work_dir) if work_dir is not None else os.path.dirname(output) or ".")
    if not os.path.isdir(parent):
        raise FileNotFoundError(f"{parent}: no such directory for the tiles' files")
    return _recon._TileWorkspace(parent)


def _tile_steps(dask: Any, folder: str, output: str, tiles: int, threads: Optional[int], deadline: _Deadline,
                progress: Optional[Progress], seconds: Dict[str, float]) -> Dict[str, Any]:
    """Steps 2 to 5 of the run planned in `folder`: the tiles on the workers, the rest here."""
    lap = time.perf_counter()
    orientations = _run_tasks(dask, _orient_task, "orient", folder, tiles, threads, deadline, progress)
    seconds["orient"] = time.perf_counter() - lap
    reconciliation = _recon._tiles_reconcile(folder)
    seconds["reconcile"] = reconciliation["seconds"]
    lap = time.perf_counter()
    contours = _run_tasks(dask, _contour_task, "contour", folder, tiles, threads, deadline, progress)
    seconds["contour"] = time.perf_counter() - lap
    mesh = _recon._tiles_stitch(folder, output)
    seconds["stitch"] = mesh["seconds"]
    return {"orient": orientations, "reconcile": reconciliation, "contour": contours, "mesh": mesh,
            "workers": _worker_figures(dask, orientations, contours)}


def run(input: PathLike, output: PathLike, *, scheduler: Optional[str] = None, workers: int = 2,
        tile_size: float = 0.0, work_dir: Optional[PathLike] = None, method: str = "refined",
        k: Optional[int] = None, rho: Optional[float] = None, delta: Optional[float] = None,
        cell: Optional[float] = None, resolution: Optional[int] = None, max_memory: Union[None, int, str] = None,
        statistics_points: int = 0, threads_per_task: Optional[int] = None, format: Optional[str] = None,
        columns: Optional[Sequence[str]] = None, skip_invalid: bool = False, client: Any = None,
        timeout: Optional[float] = None, progress: Optional[Progress] = None,
        vertex_normals: bool = False) -> Dict[str, Any]:
    """Reconstructs the cloud in the file `input` tile by tile, the tiles as
    Dask tasks, into the binary PLY file `output`; returns the run's figures.

    Where the tasks run: on the workers of `client` when given, else of the
    cluster whose scheduler is at `scheduler` ("tcp://host:8786"), else of
    a local cluster of `workers` processes on 127.0.0.1, started and closed
    here. ``work_dir`` is where the tiles' files go (a fresh folder inside
    it, removed at the end, also on errors): by default the output's
    folder; on a cluster it must be shared storage that every worker
    reaches by the same path. ``tile_size`` is the edge of a tile's core (a
    length; 0: the largest that fits ``max_memory``, which bounds each
    tile's run: a machine running several tiles at once needs that much for
    each). ``method``, ``k``, ``rho``, ``delta``, ``cell`` and
    ``resolution`` mean what recon.reconstruct's options mean;
    ``statistics_points`` caps the points one phase I takes the cloud-wide
    measures on (0: what fits a quarter of ``max_memory``; a larger cloud
    is measured over its tiles, in this process, and the measures are the
    same); ``format``, ``columns``
    and ``skip_invalid`` are read_points'. ``threads_per_task`` is each
    task's thread count (default: the cores of the worker's machine shared
    among the worker's task slots; on a local cluster, this machine's cores
    shared among the workers). The scheduler must answer and the tasks be
    done within ``timeout`` seconds of the start (TimeoutError, OSError). ``progress(step, done, total)`` is
    called as tiles finish ("orient", "contour"). ``vertex_normals`` writes
    the mesh's vertex normals (nx ny nz), as recon.reconstruct's.

    Checked before any work, as the program checks them (ValueError, or
    FileNotFoundError for a missing folder): ``output`` is not the input
    (by inode: not through a hard link or symlink either) and its folder
    exists; on a local cluster, ``workers`` and ``threads_per_task`` are
    at most PROCESSES_PER_CORE per core of this machine.

    The figures: "version" (recon.__version__), "plan" (tiles, points, tile_size, halo, per-tile points,
    ...), "orient" and "contour" (one dict per tile: its seconds, the
    worker that ran it, the threads it used, ...), "reconcile", "mesh"
    (vertices, triangles, ...), "seconds" per step ("connect": reaching or
    starting the cluster) and in total, and "workers": per worker address,
    its pid, its peak memory so far (MiB) and the tasks of this run it ran.
    """
    output = os.path.abspath(os.fspath(output))
    if not output.lower().endswith(".ply"):
        raise ValueError(f"{output}: a tiled run writes binary PLY; name the output .ply")
    _check_outputs(os.fspath(input), [output])
    if client is not None and scheduler is not None:
        raise ValueError("give a client or a scheduler address, not both")
    local = client is None and scheduler is None
    if scheduler is not None:
        _check_address(scheduler)
    _check_run(local, workers, threads_per_task,
               {"k": k, "resolution": resolution, "statistics_points": statistics_points}, timeout)
    if local and threads_per_task is None:
        threads_per_task = max(1, len(os.sched_getaffinity(0)) // workers)
    deadline = _Deadline(timeout)
    seconds: Dict[str, float] = {}
    started = time.perf_counter()
    workspace = _work_folder(work_dir, output)
    folder = os.fspath(workspace.path)
    try:
        plan = _recon._tiles_plan(os.fspath(input), folder, method, k, rho, delta, cell, resolution, tile_size,
                                  max_memory, statistics_points, format, list(columns) if columns else None,
                                  skip_invalid, vertex_normals)
        seconds["plan"] = time.perf_counter() - started
        lap = time.perf_counter()
        with _connected(scheduler, workers, threads_per_task, client, deadline) as dask:
            seconds["connect"] = time.perf_counter() - lap
            figures = _tile_steps(dask, folder, output, plan["tiles"], threads_per_task, deadline, progress, seconds)
    finally:
        workspace.close()
    seconds["total"] = time.perf_counter() - started
    return {"version": _recon.__version__, "plan": plan, **figures, "seconds": seconds, "threads_per_task": threads_per_task,
            "client_peak_rss_mib": _peak_memory()["peak_rss_mib"]}


# ---------------------------------------------------------------------------
# The command line

class _Arguments(argparse.ArgumentParser):
    """argparse, with a wrong argument said in one line, as every other error."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"recon.distributed: error: {message}\n")


def _arguments() -> argparse.ArgumentParser:
    parser = _Arguments(
        prog="python3 -m recon.distributed",
        description="Reconstruct a cloud tile by tile, the tiles run as Dask tasks: on an existing cluster "
                    "(--scheduler) or on a local cluster of worker processes (--workers). The plan, the "
                    "reconciliation of the signs and the stitching run here; each tile's orientation and "
                    "contouring run on the workers.")
    parser.add_argument("input", help="point cloud (.ply .xyz .txt .csv .pts .obj .off .pcd .las)")
    parser.add_argument("-o", "--output", required=True, help="mesh to write (binary .ply)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="the Dask scheduler of a running cluster (tcp://host:8786)")
    where.add_argument("--workers", type=int, metavar="N",
                       help="start a local cluster of N worker processes on 127.0.0.1 (default 2)")
    parser.add_argument("--tile-size", type=float, default=0.0, metavar="L",
                        help="edge of a tile's core, a length (default: the largest that fits --max-memory)")
    parser.add_argument("--work-dir", "--tmpdir", metavar="DIR", dest="work_dir",
                        help="where the tiles' files go (a fresh folder inside DIR, removed at the end; default: "
                             "the output's folder). With --scheduler it must be shared storage that the workers "
                             "reach by the same path")
    parser.add_argument("--method", choices=("refined", "hoppe92"), default="refined", help="default refined")
    parser.add_argument("-k", "--k", type=int, help="neighbourhood size (default 20, raised for noisy data)")
    parser.add_argument("--rho", type=float, help="sampling density, a length (default: estimated per point)")
    parser.add_argument("--delta", type=float, help="noise level, a length (default: estimated)")
    parser.add_argument("--cell", type=float, help="lattice cube side, a length (default: rho)")
    parser.add_argument("--resolution", type=int, help="lattice cubes along the longest side of the bounding box")
    parser.add_argument("--max-memory", metavar="SIZE",
                        help="memory for one tile's run and for the plan, as 8G or 512M (default: half the "
                             "physical memory); a machine running several tiles at once needs it for each")
    parser.add_argument("--statistics-points", type=int, default=0, metavar="N",
                        help="points the cloud-wide measures are taken on (default: what fits a quarter of "
                             "--max-memory)")
    parser.add_argument("--threads-per-task", type=int, metavar="N",
                        help="threads of each tile's task (default: the cores shared among a machine's task slots)")
    parser.add_argument("--format", help="input format, when the extension does not say")
    parser.add_argument("--columns", help="what the columns of a text file hold, as x,y,z,_,r,g,b")
    parser.add_argument("--skip-invalid", action="store_true", help="skip points with a coordinate that is not finite")
    parser.add_argument("--normals", action="store_true", help="write vertex normals (nx ny nz)")
    parser.add_argument("--timeout", type=float, metavar="SECONDS",
                        help="give up when the scheduler or the tiles have not answered this long after the start")
    parser.add_argument("--stats", metavar="FILE",
                        help="also write the run's figures as JSON to this file (as the program writes its "
                             "outputs: whole or not at all)")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    return parser


def _summary(figures: Dict[str, Any], output: str) -> str:
    s = figures["seconds"]
    steps = ", ".join(f"{step} {s[step]:.2f}"
                      for step in ("plan", "connect", "orient", "reconcile", "contour", "stitch"))
    return (f"{figures['plan']['tiles']} tiles on {len(figures['workers'])} workers in {s['total']:.2f} s ({steps}): "
            f"{figures['mesh']['vertices']} vertices, {figures['mesh']['triangles']} triangles -> {output}")


def main(argv: Optional[Sequence[str]] = None) -> int:
    """`python3 -m recon.distributed ...`; returns the exit status."""
    a = _arguments().parse_args(argv)
    try:
        _check_outputs(a.input, [os.path.abspath(a.output)] + ([a.stats] if a.stats else []))
        figures = run(a.input, a.output, scheduler=a.scheduler, workers=2 if a.workers is None else a.workers,
                      tile_size=a.tile_size, work_dir=a.work_dir, method=a.method, k=a.k, rho=a.rho, delta=a.delta,
                      cell=a.cell, resolution=a.resolution, max_memory=a.max_memory,
                      statistics_points=a.statistics_points, threads_per_task=a.threads_per_task, format=a.format,
                      columns=a.columns.split(",") if a.columns else None, skip_invalid=a.skip_invalid,
                      timeout=a.timeout, vertex_normals=a.normals)
        if a.stats:
            _recon._write_text(a.stats, json.dumps(figures, indent=1))
    except (OSError, ValueError, MemoryError, TimeoutError) as error:
        print(f"recon.distributed: error: {error}", file=sys.stderr)
        return 1
    except Exception as error:  # Dask's own: a tile that kept killing its workers (KilledWorker), ...
        if not type(error).__module__.startswith("distributed"):
            raise
        print(f"recon.distributed: error: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("recon.distributed: interrupted", file=sys.stderr)
        return 130
    if not a.quiet:
        print(_summary(figures, a.output))
    return 0


if __name__ == "__main__":
    # Run as the module recon.distributed, not as __main__: the tasks then
    # pickle as recon.distributed's functions, which the workers import.
    from recon.distributed import main as _main

    sys.exit(_main())
