"""Shared pieces of the Python package's tests (run by CTest: python_tests).

CTest sets PYTHONPATH to the build's python/ folder (the package as built,
imported for real) and RECON_CLI to the program of the same build, which
several tests compare the package with."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest


def cli_path() -> str:
    path = os.environ.get("RECON_CLI")
    if not path or not Path(path).exists():
        pytest.skip("RECON_CLI does not name the recon program (run these tests through ctest)")
    return path


def run_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the recon program with `args`; returns the finished process."""
    return subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True, check=check, timeout=300)


def sphere(n: int, seed: int = 1, radius: float = 1.0) -> np.ndarray:
    """n points drawn uniformly on a sphere of `radius` about the origin (n x 3 float64)."""
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    return radius * v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.fixture
def torus_file(tmp_path: Path) -> Path:
    """A 20,000-point torus written by `recon generate` (x y z, PLY)."""
    path = tmp_path / "torus.ply"
    run_cli("generate", "torus", "-n", "20000", "-o", path, "--quiet")
    return path
