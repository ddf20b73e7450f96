"""Issue 19: `python3 -m build --wheel --no-isolation` and `pip install
--no-build-isolation .` from the repository root, with Debian's setuptools,
wheel and build and no Python index (--no-index). Both run in one copy of the
source tree (so nothing is written into the checkout), the wheel first: pip
then reuses its CMake tree (build-pip/) and only relinks. Each goes into a
fresh venv with the system site packages (Debian's numpy), where the package
is imported from another directory with no PYTHONPATH and runs a short
simulation."""
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

import pytest

from conftest import SOURCE, scene_path

VERSION = re.search(r"project\(\s*gimbalsim\s+VERSION\s+([0-9.]+)", (SOURCE / "CMakeLists.txt").read_text()).group(1)
DURATION, INTERVAL = 0.05, 1.0e-3
FAST_BUILD = "'-DCMAKE_CXX_FLAGS_RELEASE=-O0 -DNDEBUG'"

CHECK = """
import importlib.metadata, json, sys
import gimbalsim
scene = gimbalsim.load_scene(sys.argv[1], {"sim.duration": %r, "sim.output_interval": %r})
run = gimbalsim.simulate(scene)
print(json.dumps({"file": gimbalsim.__file__, "version": importlib.metadata.version("gimbalsim"),
                  "ok": run.ok, "rows": len(run.rows), "t_last": float(run.columns["t"][-1])}))
""" % (DURATION, INTERVAL)


def env():
    e = {k: v for k, v in os.environ.items()
         if k not in ("PYTHONPATH", "PYTHONHOME", "LD_PRELOAD", "ASAN_OPTIONS") and not k.startswith("PIP_")}
    e["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    # Packaging is under test, not the optimiser: -O0 halves the build (the user's default stays -O3).
    e["GIMBALSIM_CMAKE_ARGS"] = FAST_BUILD
    return e


def sh(*cmd, cwd, timeout=1100):
    start = time.monotonic()
    p = subprocess.run([str(c) for c in cmd], cwd=cwd, env=env(), capture_output=True, text=True, timeout=timeout)
    print(f"{time.monotonic() - start:7.1f} s  {' '.join('<script>' if c == CHECK else str(c) for c in cmd)}")
    if p.returncode != 0:
        raise AssertionError(f"{' '.join(map(str, cmd))} exited {p.returncode}\n{p.stdout[-6000:]}\n{p.stderr[-6000:]}")
    return p.stdout


def venv(path):
    sh(sys.executable, "-m", "venv", "--system-site-packages", path, cwd=path.parent)
    return path / "bin" / "python"


def check_installed(python, venv_dir, elsewhere):
    out = json.loads(sh(python, "-c", CHECK, scene_path("paper_ideal"), cwd=elsewhere).splitlines()[-1])
    assert pathlib.Path(out["file"]).resolve().is_relative_to(venv_dir.resolve()), out["file"]
    assert out["version"] == VERSION
    assert out["ok"]
    assert out["rows"] == round(DURATION / INTERVAL) + 1
    assert out["t_last"] == pytest.approx(DURATION, abs=1e-12)


def copy_tree(dest):
    """The checkout without its build trees, outputs, caches and .git."""
    def ignore(d, names):
        top = pathlib.Path(d) == SOURCE
        return [n for n in names if n == "__pycache__" or n.endswith(".egg-info")
                or (top and (n.startswith("build") or n in ("dist", "out", ".git")))]
    shutil.copytree(SOURCE, dest, ignore=ignore)


def test_wheel_and_pip_install_without_an_index(tmp_path):
    src, elsewhere, wheels = tmp_path / "src", tmp_path / "elsewhere", tmp_path / "wheels"
    copy_tree(src)
    elsewhere.mkdir()
    before = {p.relative_to(src) for p in src.rglob("*")}

    # python3 -m build --wheel --no-isolation: a wheel a worker host installs.
    py_a = venv(tmp_path / "venv-wheel")
    sh(py_a, "-m", "build", "--wheel", "--no-isolation", "--outdir", wheels, cwd=src)
    built = sorted(wheels.iterdir())
    assert [w.name for w in built] == [f"gimbalsim-{VERSION}-cp{sys.version_info.major}{sys.version_info.minor}-"
                                       f"cp{sys.version_info.major}{sys.version_info.minor}-linux_x86_64.whl"]
    sh(py_a, "-m", "pip", "install", "--no-index", "--no-cache-dir", built[0], cwd=elsewhere)
    check_installed(py_a, tmp_path / "venv-wheel", elsewhere)

    # pip install --no-build-isolation . from the repository root.
    py_b = venv(tmp_path / "venv-pip")
    sh(py_b, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir", ".", cwd=src)
    check_installed(py_b, tmp_path / "venv-pip", elsewhere)

    # GIMBALSIM_CMAKE_ARGS reached CMake (one word, its quotes removed), after the defaults.
    caches = list((src / "build-pip").glob("temp.*/cmake/CMakeCache.txt"))
    assert len(caches) == 1 and "CMAKE_CXX_FLAGS_RELEASE:STRING=-O0 -DNDEBUG\n" in caches[0].read_text(), caches

    # An unclosed quote in it: one line naming the variable, before CMake runs.
    bad = subprocess.run([py_a, "setup.py", "build_ext"], cwd=src, env={**env(), "GIMBALSIM_CMAKE_ARGS": "-DX='1"},
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode != 0 and "GIMBALSIM_CMAKE_ARGS does not split into words" in bad.stderr, bad.stderr[-3000:]
    assert "CMake configure" not in bad.stdout, bad.stdout[-3000:]

    # Only build-pip/ is new in the source tree: no build/, dist/ or *.egg-info.
    new = {p for p in src.rglob("*") if p.relative_to(src) not in before}
    assert {p.relative_to(src).parts[0] for p in new} == {"build-pip"}
