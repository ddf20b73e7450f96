"""The extension gimbalsim._gimbalsim for pip and `python3 -m build`: CMake
configures the whole project (Release, no tests) and builds only the target
_gimbalsim and what it links; setuptools adds the pure-Python modules of
python/gimbalsim/. The metadata is in pyproject.toml; the version is the one in
CMakeLists.txt's project(). Everything setuptools writes goes to build-pip/
(the CMake tree in build-pip/temp.*/cmake, kept: a second install rebuilds
only what changed; build_py empties build-pip/lib.*/gimbalsim first, so a
module deleted from python/gimbalsim/ never ships). CMake's parallel jobs:
CMAKE_BUILD_PARALLEL_LEVEL (default 2); more CMake configure arguments:
GIMBALSIM_CMAKE_ARGS (shell words, e.g. "-DGIMBALSIM_NATIVE=ON")."""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py
from setuptools.errors import ExecError, SetupError

ROOT = pathlib.Path(__file__).resolve().parent
BUILD_BASE = "build-pip"
TARGET = "_gimbalsim"


def cmake_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    m = re.search(r"project\(\s*gimbalsim\s+VERSION\s+([0-9][0-9.]*)", text)
    if not m:
        raise SetupError("gimbalsim: no 'project(gimbalsim VERSION x.y.z' in CMakeLists.txt")
    return m.group(1)


def run(step, cmd, hint):
    print(f"gimbalsim: {step}: {shlex.join(cmd)}", flush=True)
    try:
        subprocess.run(cmd, check=True)
    except FileNotFoundError as e:
        raise ExecError(f"gimbalsim: {step}: cannot run {cmd[0]!r} ({e.strerror})") from None
    except subprocess.CalledProcessError as e:
        raise ExecError(f"gimbalsim: {step} failed (exit {e.returncode}): {hint}") from None


def extra_cmake_args():
    """GIMBALSIM_CMAKE_ARGS as words: after the defaults, so a -D there wins."""
    text = os.environ.get("GIMBALSIM_CMAKE_ARGS", "")
    try:
        return shlex.split(text)
    except ValueError as e:  # an unclosed quote: said once, not a traceback from deep in setuptools
        raise SetupError(f"gimbalsim: GIMBALSIM_CMAKE_ARGS does not split into words ({e}): {text!r}") from None


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        cmake = shutil.which("cmake")
        if cmake is None:
            raise ExecError("gimbalsim: cmake not found on PATH (Debian: apt-get install cmake, "
                            "or bash tools/bootstrap.sh for every build dependency)")
        tree = pathlib.Path(self.build_temp).resolve() / "cmake"
        run("CMake configure", [
            cmake, "-S", str(ROOT), "-B", str(tree),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DGIMBALSIM_TESTS=OFF", "-DGIMBALSIM_PYTHON=ON",
            f"-DPython3_EXECUTABLE={sys.executable}",  # the interpreter installing the package
            *extra_cmake_args(),
        ], "CMake's messages are above; a missing package? bash tools/bootstrap.sh installs every one")
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or "2"
        run("CMake build", [cmake, "--build", str(tree), "--target", TARGET, "-j", jobs],
            "the compiler's errors are above")
        dest = pathlib.Path(self.get_ext_fullpath(ext.name))
        built = tree / "python" / "gimbalsim" / dest.name  # python/CMakeLists.txt's output directory
        if not built.is_file():
            found = sorted(p.name for p in built.parent.glob(f"{TARGET}*"))
            raise SetupError(f"gimbalsim: CMake did not build {built} for {sys.executable} (found: {found})")
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, dest)


class CleanBuildPy(build_py):
    def run(self):
        shutil.rmtree(os.path.join(self.build_lib, "gimbalsim"), ignore_errors=True)
        super().run()


os.makedirs(ROOT / BUILD_BASE, exist_ok=True)
setup(
    version=cmake_version(),
    ext_modules=[Extension(f"gimbalsim.{TARGET}", sources=[])],
    cmdclass={"build_py": CleanBuildPy, "build_ext": CMakeBuild},
    options={"build": {"build_base": BUILD_BASE}, "egg_info": {"egg_base": BUILD_BASE}},
)
