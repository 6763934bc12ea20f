"""The package as users install it (pyproject.toml, setup.py), and the one
version every part of recon shows (cmake/recon_version.cmake).

Run by CTest as python_packaging, apart from python_tests: it builds the
package twice with pip's and build's own front ends, in fresh virtual
environments, offline (--no-index). setup.py's CMake build folder is
RECON_PIP_BUILD_DIR (CTest: build/<preset>/pip-package), kept between
runs, so a run after the first only relinks what changed (15-35 s here;
the first compiles the library: 2 min 40 s of CPU, without ccache).
"""

import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List

import pytest
from packaging.version import Version

from conftest import run_cli

ROOT = Path(__file__).resolve().parents[2]
VERSION_SCRIPT = ROOT / "cmake" / "recon_version.cmake"

# The Debian 12 packages the compiled module may load libraries from: the C
# and C++ runtimes, OpenMP's and zlib's, all present wherever python3 is.
# A library from a -dev package, another package or the build tree would
# make the wheel fail on a machine with only the runtime packages.
RUNTIME_PACKAGES = {"libc6", "libstdc++6", "libgcc-s1", "libgomp1", "zlib1g"}


# ---------------------------------------------------------------------------
# Helpers


def quiet_env() -> Dict[str, str]:
    """The environment for the virtual environments' programs: without CTest's
    PYTHONPATH (the build folder's package would shadow the installed one)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.setdefault("RECON_PIP_BUILD_DIR", str(ROOT / "build" / "pip"))
    env["PIP_NO_INDEX"] = "1"  # nothing is downloaded
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


def run(command: List[str]) -> subprocess.CompletedProcess:
    """Runs `command` in the temporary folder: in CTest's working folder, the
    build's python/, `python -c` would import the build's package."""
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True, env=quiet_env(), timeout=900,
                          cwd=tempfile.gettempdir())
    assert done.returncode == 0, f"{' '.join(map(str, command))} failed:\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    return done


def venv(where: Path) -> Path:
    """A fresh virtual environment that sees the system's packages (numpy,
    dask from apt); returns its python."""
    run([sys.executable, "-m", "venv", "--system-site-packages", where])
    return where / "bin" / "python"


def python_in(python: Path, code: str, *args) -> str:
    return run([python, "-c", code, *args]).stdout


def expected_version() -> str:
    """The version worked out here, apart from the build: the project's VERSION
    in CMakeLists.txt and git's commit and changes (docs/releasing.md)."""
    base = re.search(r"project\(recon VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text()).group(1)
    git = shutil.which("git")
    if git is None or not (ROOT / ".git").exists():
        return base
    ask = lambda *args: subprocess.run([git, *args], cwd=ROOT, capture_output=True, text=True,  # noqa: E731
                                       check=True).stdout.strip()
    commit = ask("rev-parse", "--short=7", "HEAD")
    dirty = ask("status", "--porcelain", "--untracked-files=no") != ""
    if not dirty and ask("tag", "--points-at", "HEAD", "--list", f"v{base}"):
        return base
    return f"{base}+g{commit}" + (".dirty" if dirty else "")


# ---------------------------------------------------------------------------
# The package built by pip and by build


@dataclass
class Packaged:
    installed: Path   # python of the environment `pip install .` went into
    wheel: Path       # the wheel made by `python3 -m build --wheel`
    from_wheel: Path  # python of a second environment the wheel went into


@pytest.fixture(scope="module")
def packaged(tmp_path_factory) -> Packaged:
    top = tmp_path_factory.mktemp("packaging")
    installed = venv(top / "pip-env")
    run([installed, "-m", "pip", "install", "--no-build-isolation", "--no-index", ROOT])
    run([sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", top / "dist", ROOT])
    (wheel,) = (top / "dist").glob("recon-*.whl")
    from_wheel = venv(top / "wheel-env")
    run([from_wheel, "-m", "pip", "install", "--no-index", wheel])
    return Packaged(installed, wheel, from_wheel)


RECONSTRUCT = """
import sys, recon, recon.distributed
assert recon.__file__.startswith(sys.prefix), recon.__file__  # the installed package, not the sources
cloud = recon.read_points(sys.argv[1])
recon.reconstruct(cloud.points, threads=2).save(sys.argv[2])
"""


def test_pip_install_gives_a_package_that_reconstructs(packaged, torus_file, tmp_path):
    by_program = tmp_path / "program.ply"
    run_cli("reconstruct", torus_file, "-o", by_program, "--threads", "2", "-q")
    for python in (packaged.installed, packaged.from_wheel):
        by_package = tmp_path / f"{python.parent.parent.name}.ply"
        python_in(python, RECONSTRUCT, torus_file, by_package)
        assert by_package.read_bytes() == by_program.read_bytes(), f"{python}: the mesh differs from the program's"


def test_the_wheel_is_tagged_for_this_python_and_platform(packaged):
    tag = f"cp{sys.version_info.major}{sys.version_info.minor}"
    assert packaged.wheel.name.endswith(f"-{tag}-{tag}-linux_x86_64.whl"), packaged.wheel.name
    with zipfile.ZipFile(packaged.wheel) as wheel:
        names = wheel.namelist()
        info = next(n for n in names if n.endswith(".dist-info/WHEEL"))
        assert "Root-Is-Purelib: false" in wheel.read(info).decode()
        metadata = wheel.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
    for part in ("__init__.py", "distributed.py", "py.typed", "_recon.pyi"):
        assert f"recon/{part}" in names, part
    assert any(re.fullmatch(r"recon/_recon\.cpython-.*\.so", n) for n in names)
    assert "Requires-Dist: numpy" in metadata
    assert "Provides-Extra: distributed" in metadata and "Requires-Dist: dask ; extra == 'distributed'" in metadata


def owning_package(library: Path) -> str:
    """The Debian package that installed `library` (dpkg knows it by the
    path it shipped: /lib or /usr/lib, before or after merged /usr)."""
    candidates = [library, Path(os.path.realpath(library.parent)) / library.name]
    for path in candidates:
        done = subprocess.run(["dpkg", "-S", str(path)], capture_output=True, text=True)
        if done.returncode == 0:
            return done.stdout.split(":")[0]
    return f"(no package: {library})"


def test_the_module_needs_only_debian_runtime_packages(packaged):
    if shutil.which("dpkg") is None or shutil.which("readelf") is None:
        pytest.skip("needs dpkg and readelf (Debian)")
    module = Path(python_in(packaged.from_wheel, "import recon._recon as m; print(m.__file__)").strip())
    dynamic = run(["readelf", "-d", module]).stdout
    assert not re.search(r"\((RPATH|RUNPATH)\)", dynamic), f"{module} looks for libraries in a fixed folder:\n{dynamic}"
    assert str(ROOT) not in dynamic
    libraries = re.findall(r"^\s*(\S+) => (\S+)", run(["ldd", module]).stdout, re.MULTILINE)
    assert any(name.startswith("libgomp") for name, _ in libraries), "OpenMP's runtime is among them (the test sees)"
    for name, path in libraries:
        assert path != "not", f"{name}: not found"
        package = owning_package(Path(path))
        assert package in RUNTIME_PACKAGES, f"{name} ({path}) comes from {package}, not a Debian 12 runtime package"


def load_setup_py():
    spec = importlib.util.spec_from_file_location("recon_setup", ROOT / "setup.py")
    setup_py = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(setup_py)  # defines its functions; setup() runs only as __main__
    return setup_py


def test_a_failed_build_step_is_one_line_naming_it():
    setup_py = load_setup_py()
    with pytest.raises(SystemExit, match=r"error: no-such-cmake is not installed \(scripts/setup"):
        setup_py.run(["no-such-cmake", "--version"])
    with pytest.raises(SystemExit, match=r"error: cmake -P /nonexistent.cmake failed with status 1"):
        setup_py.run(["cmake", "-P", "/nonexistent.cmake"])


def test_without_web_packages_the_build_leaves_the_viewer_out(tmp_path, monkeypatch):
    """Where Node.js or web/node_modules is missing, setup.py configures with
    RECON_REPORT=OFF (src/report/report_page_missing.cpp) instead of failing."""
    setup_py = load_setup_py()
    commands = []
    monkeypatch.setattr(setup_py, "run", commands.append)
    monkeypatch.setattr(setup_py, "ROOT", tmp_path)
    setup_py.configure(tmp_path / "build")
    (tmp_path / "web" / "node_modules" / "esbuild").mkdir(parents=True)
    setup_py.configure(tmp_path / "build")
    (tmp_path / "web" / "node_modules" / "three").mkdir()
    setup_py.configure(tmp_path / "build")
    viewer = [next(a for a in c if a.startswith("-DRECON_REPORT=")) for c in commands]
    with_node = shutil.which("node") is not None or shutil.which("nodejs") is not None
    assert viewer == ["-DRECON_REPORT=OFF", "-DRECON_REPORT=OFF", f"-DRECON_REPORT={'ON' if with_node else 'OFF'}"]
    assert all("-DCMAKE_BUILD_TYPE=Release" in c and "-DRECON_BUILD_TESTS=OFF" in c for c in commands)


# ---------------------------------------------------------------------------
# One version


def test_one_version_everywhere(packaged, torus_file, tmp_path):
    """Every place that shows the version shows the same string, and it is
    the one worked out from CMakeLists.txt and git here: a place that wrote
    its own (say a fixed "0.1.0") would differ from the commit's."""
    seen: Dict[str, str] = {}
    seen["recon --version"] = run_cli("--version").stdout.strip().removeprefix("recon ")
    stats, report = tmp_path / "stats.json", tmp_path / "report.html"
    made = run_cli("reconstruct", torus_file, "-o", tmp_path / "mesh.ply", "--stats", stats, "--report", report, "-q",
                   check=False)
    if made.returncode != 0 and "without the report viewer" in made.stderr:
        run_cli("reconstruct", torus_file, "-o", tmp_path / "mesh.ply", "--stats", stats, "-q")
    else:
        assert made.returncode == 0, made.stderr
        data = re.search(r'<script id="recon-data" type="application/json">(.*?)</script>', report.read_text(), re.S)
        seen["the report"] = json.loads(data.group(1))["version"]
    seen["recon --stats"] = json.loads(stats.read_text())["version"]
    code = ("import importlib.metadata, json, sys, numpy, recon;"
            "mesh = recon.reconstruct(recon.read_points(sys.argv[1]).points);"
            "print(json.dumps([recon.__version__, mesh.stats['version'], importlib.metadata.version('recon')]))")
    for where, python in (("pip install", packaged.installed), ("the wheel", packaged.from_wheel)):
        module, stats_version, metadata = json.loads(python_in(python, code, torus_file))
        seen[f"recon.__version__ ({where})"] = module
        seen[f"reconstruct().stats ({where})"] = stats_version
        seen[f"the package's metadata ({where})"] = metadata
    expected = expected_version()
    wrong = {place: v for place, v in seen.items() if v != expected}
    assert not wrong, f"expected {expected} everywhere (rebuild if the tree changed since); differs: {wrong}"
    assert str(Version(expected)) == expected, "a PEP 440 version, as written"


# ---------------------------------------------------------------------------
# cmake/recon_version.cmake alone, on repositories made here


def version_of(source: Path, out: Path, base: str = "2.3.4") -> str:
    text = out / "version.txt"
    run(["cmake", f"-DRECON_BASE_VERSION={base}", f"-DRECON_SOURCE_DIR={source}", f"-DRECON_VERSION_TEXT={text}",
         f"-DRECON_VERSION_HEADER={out / 'version.h'}", "-P", VERSION_SCRIPT])
    return text.read_text().strip()


def git(repo: Path, *args: str) -> str:
    return run(["git", "-c", "user.name=t", "-c", "user.email=t@t", "-C", repo, *args]).stdout.strip()


@pytest.fixture
def repo(tmp_path) -> Path:
    if shutil.which("git") is None:
        pytest.skip("needs git")
    repo = tmp_path / "repo"
    repo.mkdir()
    git(repo, "init", "-q")
    (repo / "a.txt").write_text("a\n")
    git(repo, "add", "a.txt")
    git(repo, "commit", "-q", "-m", "one")
    return repo


def test_the_version_follows_the_checkout(repo, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    commit = git(repo, "rev-parse", "--short=7", "HEAD")
    assert version_of(repo, out) == f"2.3.4+g{commit}"
    (repo / "untracked.txt").write_text("not recon's\n")
    assert version_of(repo, out) == f"2.3.4+g{commit}", "an untracked file changes nothing"
    (repo / "a.txt").write_text("changed\n")
    assert version_of(repo, out) == f"2.3.4+g{commit}.dirty"
    git(repo, "commit", "-q", "-am", "two")
    second = git(repo, "rev-parse", "--short=7", "HEAD")
    assert second != commit and version_of(repo, out) == f"2.3.4+g{second}", "a new commit, without configuring"
    git(repo, "tag", "v9.9.9")
    assert version_of(repo, out) == f"2.3.4+g{second}", "only the tag of this version makes a release"
    git(repo, "tag", "v2.3.4")
    assert version_of(repo, out) == "2.3.4", "the release's tag, unchanged: the plain version"
    (repo / "a.txt").write_text("after the release\n")
    assert version_of(repo, out) == f"2.3.4+g{second}.dirty"
    for v in (f"2.3.4+g{second}.dirty", f"2.3.4+g{commit}", "2.3.4"):
        assert str(Version(v)) == v


def test_a_tarball_has_the_plain_version_even_inside_another_repository_an_sdist_its_own(repo, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    tarball = repo / "unpacked" / "recon-2.3.4"  # sources without .git, inside some other checkout
    tarball.mkdir(parents=True)
    assert version_of(tarball, out) == "2.3.4"
    alone = tmp_path / "alone"
    alone.mkdir()
    assert version_of(alone, out) == "2.3.4"
    assert (out / "version.h").read_text().endswith('#define RECON_VERSION_STRING "2.3.4"\n')
    # An sdist keeps the version it was made with (its PKG-INFO), when it is this VERSION's.
    (alone / "PKG-INFO").write_text("Metadata-Version: 2.1\nName: recon\nVersion: 2.3.4+gabc1234.dirty\n")
    assert version_of(alone, out) == "2.3.4+gabc1234.dirty"
    (alone / "PKG-INFO").write_text("Metadata-Version: 2.1\nName: recon\nVersion: 2.4.0\n")
    assert version_of(alone, out) == "2.3.4", "another version's PKG-INFO is not this one's"


def test_an_unchanged_version_rewrites_nothing(repo, tmp_path):
    """The build runs the script every time; what includes the header must not rebuild."""
    out = tmp_path / "out"
    out.mkdir()
    version_of(repo, out)
    for name in ("version.h", "version.txt"):
        os.utime(out / name, (1_000_000_000, 1_000_000_000))
    version_of(repo, out)
    assert all((out / n).stat().st_mtime == 1_000_000_000 for n in ("version.h", "version.txt"))
    (repo / "a.txt").write_text("changed\n")
    version_of(repo, out)
    assert all((out / n).stat().st_mtime > 1_000_000_000 for n in ("version.h", "version.txt"))


def test_a_checkout_git_cannot_read_is_not_called_clean(repo, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    commit = git(repo, "rev-parse", "--short=7", "HEAD")
    (repo / ".git" / "index").write_bytes(b"not an index")  # `git status` fails; HEAD is still known
    assert version_of(repo, out) == f"2.3.4+g{commit}.dirty"
