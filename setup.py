"""Builds recon's Python package with the project's own CMake build.

setuptools (pyproject.toml) drives it: the extension recon._recon is not
compiled by setuptools but by CMake, configured with the release settings
(CMAKE_BUILD_TYPE=Release, no tests, no benchmarks) and built for its one
target, recon_python; the compiled module and python/recon/ (the *.py files,
py.typed, _recon.pyi) then go into the wheel. The version is the build's
own (cmake/recon_version.cmake: the project's VERSION plus the git commit),
so the wheel's version and recon.__version__ are the same string.

Environment:
  RECON_PIP_BUILD_DIR  the CMake build folder (default build/pip): kept
                       between runs, so a second install only relinks
                       what changed. CMAKE_CXX_COMPILER_LAUNCHER=ccache and
                       CMAKE_BUILD_PARALLEL_LEVEL work as for any CMake build.
The report viewer (recon --report, reconstruct(report=...)) is built in when
Node.js and web/'s npm packages are there (scripts/setup), and left out
otherwise: the build then still succeeds, and a report asked for says it is
missing (src/report/report_page_missing.cpp).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path
from typing import List

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def cmake_build_dir() -> Path:
    return Path(os.environ.get("RECON_PIP_BUILD_DIR") or ROOT / "build" / "pip").resolve()


def viewer_can_be_built(root: Path) -> bool:
    """Node.js and the npm packages the viewer is bundled from (src/report/CMakeLists.txt checks the same)."""
    modules = root / "web" / "node_modules"
    has_node = shutil.which("node") is not None or shutil.which("nodejs") is not None
    return has_node and (modules / "esbuild").exists() and (modules / "three").exists()


def run(command: List[str]) -> None:
    """Runs a CMake step; a failure ends the build with one line saying which
    step (CMake's own messages, printed above it, say why)."""
    print("recon setup.py:", " ".join(command), flush=True)
    if shutil.which(command[0]) is None:
        raise SystemExit(f"recon setup.py: error: {command[0]} is not installed (scripts/setup installs what the "
                         "build needs)")
    done = subprocess.run(command)
    if done.returncode != 0:
        raise SystemExit(f"recon setup.py: error: {' '.join(command)} failed with status {done.returncode} "
                         "(see CMake's messages above; scripts/setup installs what the build needs)")


def configure(build: Path) -> None:
    """Configures (or refreshes) the CMake build folder for the running Python."""
    viewer = viewer_can_be_built(ROOT)
    command = ["cmake", "-S", str(ROOT), "-B", str(build),
               "-DCMAKE_BUILD_TYPE=Release", "-DRECON_BUILD_TESTS=OFF", "-DRECON_BUILD_BENCH=OFF",
               "-DRECON_PYTHON=ON", f"-DRECON_REPORT={'ON' if viewer else 'OFF'}",
               # The interpreter itself, not a virtual environment's link to it: the
               # same path from every environment keeps the build folder's cache valid.
               f"-DPython3_EXECUTABLE={os.path.realpath(sys.executable)}"]
    if not (build / "CMakeCache.txt").exists() and shutil.which("ninja"):
        command += ["-G", "Ninja"]
    if not viewer:
        print("recon setup.py: Node.js or web/node_modules missing: building without the report viewer "
              "(scripts/setup installs both)", flush=True)
    run(command)


def build_target(build: Path, target: str) -> None:
    command = ["cmake", "--build", str(build), "--target", target]
    jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL")
    if jobs:
        command += ["-j", jobs]
    run(command)


def recon_version() -> str:
    """The build's version (cmake/recon_version.cmake), made by the build's own target."""
    build = cmake_build_dir()
    configure(build)
    build_target(build, "recon_version")
    return (build / "recon_version.txt").read_text().strip()


class CMakeBuild(build_ext):
    """build_ext that builds recon._recon with CMake and copies it where setuptools packs it."""

    def run(self) -> None:
        build = cmake_build_dir()
        configure(build)
        build_target(build, "recon_python")
        name = "_recon" + sysconfig.get_config_var("EXT_SUFFIX")
        built = build / "python" / "recon" / name
        if not built.exists():
            raise RuntimeError(f"{built}: the CMake build made no extension module for this Python")
        for extension in self.extensions:
            target = Path(self.get_ext_fullpath(extension.name))
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(built, target)


if __name__ == "__main__":  # as setuptools runs it (the tests import it for its functions)
    (ROOT / "build").mkdir(exist_ok=True)
    setup(
        version=recon_version(),
        # One extension, so that the wheel is tagged for this Python and platform
        # (cp311, linux_x86_64); CMake compiles it, not setuptools.
        ext_modules=[Extension("recon._recon", sources=[])],
        cmdclass={"build_ext": CMakeBuild},
        # setuptools' own staging folders, beside the CMake build (build/ is not tracked).
        options={"build": {"build_base": str(ROOT / "build" / "setuptools")},
                 "egg_info": {"egg_base": str(ROOT / "build")}},
    )
