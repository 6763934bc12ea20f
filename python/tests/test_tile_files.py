"""A tiled run's damaged files from Python, as recon.distributed meets them:
the step that reads one raises ValueError naming the file and the tile (in
the client for the reconciliation; from a Dask task for a tile's step),
never a crash that takes the interpreter or the Dask client with it. And
the workspace the package can make for its tasks (_TileWorkspace)."""

import os
from pathlib import Path

import numpy as np
import pytest

from recon import _recon
from conftest import sphere


def planned(tmp_path: Path) -> str:
    """A 12,000-point sphere planned in 8 tiles, each oriented; the folder."""
    cloud = tmp_path / "sphere.xyz"
    np.savetxt(cloud, sphere(12000))
    folder = str(tmp_path / "work")
    plan = _recon._tiles_plan(str(cloud), folder, method="hoppe92", tile_size=0.8)
    assert plan["tiles"] > 1
    for tile in range(plan["tiles"]):
        _recon._tiles_orient(folder, tile, threads=1)
    return folder


def flip_a_bit(path: str, at: int) -> None:
    data = bytearray(Path(path).read_bytes())
    data[at] ^= 0x08
    Path(path).write_bytes(bytes(data))


def test_a_flipped_bit_in_an_orientation_is_a_value_error_in_the_client(tmp_path):
    folder = planned(tmp_path)
    orient = os.path.join(folder, "tile-000001.orient")
    flip_a_bit(orient, os.path.getsize(orient) // 2)
    with pytest.raises(ValueError, match=r"tile-000001\.orient: damaged: its CRC-32"):
        _recon._tiles_reconcile(folder)


def orient_task(folder: str, tile: int) -> dict:
    """Step 2 of one tile, as recon.distributed's task runs it (a Python
    function: Dask pickles tasks, and a compiled function is not picklable)."""
    return _recon._tiles_orient(folder, tile, threads=1)


@pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")
def test_a_damaged_tile_fails_its_dask_task_naming_the_tile(tmp_path):
    distributed = pytest.importorskip("distributed", reason="Dask is not installed (python3-distributed)")
    folder = planned(tmp_path)
    flip_a_bit(os.path.join(folder, "tile-000002.points"), 100)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        failed = client.submit(orient_task, folder, 2, pure=False)
        with pytest.raises(ValueError, match=r"orienting tile 2: .*tile-000002\.points: damaged"):
            failed.result(timeout=60)
        # The client lives on: the other tiles' tasks still run.
        assert client.submit(orient_task, folder, 1, pure=False).result(timeout=60)["points"] > 0


def test_workspaces_are_exclusive_locked_and_stale_ones_removed(tmp_path):
    stale = tmp_path / "recon-tiles-killed"
    stale.mkdir()
    (stale / "recon-tiles.lock").touch()
    (stale / "tile-000000.points").write_bytes(b"x")
    kept = tmp_path / "recon-tiles-not-ours"
    kept.mkdir()
    with _recon._TileWorkspace(str(tmp_path)) as a, _recon._TileWorkspace(str(tmp_path)) as b:
        assert a.path != b.path
        assert os.path.basename(a.path).startswith("recon-tiles-")
        assert not stale.exists(), "a workspace with a free lock is stale"
        assert kept.exists(), "a folder without the lock file is not recon's to remove"
        assert _recon._tiles_remove_stale_workspaces(str(tmp_path)) == 0, "live workspaces are not stale"
        path = a.path
    assert not os.path.exists(path)
