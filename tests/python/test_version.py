"""One version string everywhere: every C++ program's --version, the sweep's
and the tuner's, and gimbalsim.__version__ print the version of the top
CMakeLists.txt's project(... VERSION ...), and --version exits 0."""
import os
import re
import subprocess
import sys

import pytest

from conftest import BIN, SOURCE

# Every program in bin/ (the tests' own binaries and helpers live elsewhere or end in _test): a list kept
# by hand had missed some, and two test helpers there answered --help with exit 2.
CORE = {"gimbalsim", "firmware_sim", "gimbalsim_record", "gimbalsim_log2csv", "pointing_controller",
        "gimbalsim_workprec", "gimbalsim_stress", "gimbalsim_pointing_study", "gimbalsim_controller_floor",
        "controller_sweep", "torque_replay"}
PROGRAMS = sorted(p.name for p in BIN.iterdir() if p.is_file() and os.access(p, os.X_OK)
                  and not p.name.endswith("_test")) if BIN.is_dir() else []


def test_bin_holds_the_programs():
    assert CORE <= set(PROGRAMS), sorted(CORE - set(PROGRAMS))


def project_version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    m = re.search(r"project\(\s*gimbalsim\s+VERSION\s+([0-9.]+)", text)
    assert m, "no project(gimbalsim VERSION ...) in CMakeLists.txt"
    return m.group(1)


@pytest.mark.parametrize("program", PROGRAMS)
def test_every_program_prints_the_project_version(program):
    p = subprocess.run([str(BIN / program), "--version"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert p.stdout == f"{program} {project_version()}\n"


@pytest.mark.parametrize("program", PROGRAMS)
def test_every_program_answers_help_and_runs_nothing(program):
    p = subprocess.run([str(BIN / program), "--help"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout.strip(), (program, p.stderr)


@pytest.mark.parametrize("module", ["gimbalsim.sweep", "gimbalsim.tune"])
def test_sweep_and_tune_print_the_project_version(module):
    p = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout == f"{module} {project_version()}\n"


def test_the_package_has_the_project_version():
    import gimbalsim
    assert gimbalsim.__version__ == project_version()
