"""One version string everywhere: every C++ program's --version, the sweep's
and the tuner's, and gimbalsim.__version__ print the version of the top
CMakeLists.txt's project(... VERSION ...), and --version exits 0."""
import re
import subprocess
import sys

import pytest

from conftest import BIN, SOURCE

PROGRAMS = ["gimbalsim", "firmware_sim", "gimbalsim_record", "gimbalsim_log2csv", "pointing_controller",
            "gimbalsim_workprec", "gimbalsim_stress", "gimbalsim_pointing_study", "gimbalsim_controller_floor", "controller_sweep",
            "gimbalsim_bench"]


def project_version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    m = re.search(r"project\(\s*gimbalsim\s+VERSION\s+([0-9.]+)", text)
    assert m, "no project(gimbalsim VERSION ...) in CMakeLists.txt"
    return m.group(1)


@pytest.mark.parametrize("program", PROGRAMS)
def test_every_program_prints_the_project_version(program):
    exe = BIN / program
    if not exe.exists():
        pytest.skip(f"{program} not built in this configuration")
    p = subprocess.run([str(exe), "--version"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    assert p.stdout == f"{program} {project_version()}\n"


@pytest.mark.parametrize("module", ["gimbalsim.sweep", "gimbalsim.tune"])
def test_sweep_and_tune_print_the_project_version(module):
    p = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout == f"{module} {project_version()}\n"


def test_the_package_has_the_project_version():
    import gimbalsim
    assert gimbalsim.__version__ == project_version()
