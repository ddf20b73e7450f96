"""Every script of tools/ finds its build folder one way: GIMBALSIM_BUILD=DIR,
read where the user stands, already configured for a script that builds; the
checkout's build/ otherwise. run_workprec.sh, run_stress.sh and run_bench.sh
ignored it (each built build/ in the checkout), the pointing study and the
controller floor read BUILD_DIR instead."""
import os
import subprocess

import pytest

from conftest import BIN, SOURCE

SCRIPTS = {  # script: the program it runs
    "tools/workprec/run_workprec.sh": "gimbalsim_workprec",
    "tools/stress/run_stress.sh": "gimbalsim_stress",
    "tools/pointing_study/run_pointing_study.sh": "gimbalsim_pointing_study",
    "tools/pointing_study/run_controller_floor.sh": "gimbalsim_controller_floor",
}


def _run(script, cwd, env, *args):
    return subprocess.run(["bash", str(SOURCE / script), *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=120)


@pytest.mark.parametrize("script", [*SCRIPTS, "tools/run_paper.sh", "tools/bench/run_bench.sh"])
def test_a_named_build_that_is_not_configured_is_refused_before_anything(tmp_path, script):
    name = os.path.basename(script)
    p = _run(script, tmp_path, dict(os.environ, GIMBALSIM_BUILD="mybuild"), *([] if "bench" in script else ["--x"]))
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert p.stderr.startswith(f"{name}: GIMBALSIM_BUILD=mybuild: {tmp_path}/mybuild is not a configured build "
                               "(no CMakeCache.txt)"), p.stderr
    assert "nothing run" in p.stderr and os.listdir(tmp_path) == [], os.listdir(tmp_path)


@pytest.mark.parametrize("script", list(SCRIPTS))
def test_a_named_build_is_read_where_the_user_stands(tmp_path, script):
    program = SCRIPTS[script]
    work, fake = tmp_path / "work", tmp_path / "fakebin"
    build = work / "mybuild"
    for d in (build / "bin", fake):
        d.mkdir(parents=True)
    (build / "CMakeCache.txt").write_text("")
    (build / "bin" / program).symlink_to(BIN / program)
    (fake / "cmake").write_text("#!/bin/sh\necho \"cmake $*\" >> \"$CMAKE_LOG\"\n")  # built already: nothing to do
    (fake / "cmake").chmod(0o755)
    env = dict(os.environ, GIMBALSIM_BUILD="mybuild", PATH=f"{fake}:{os.environ['PATH']}",
               CMAKE_LOG=str(tmp_path / "cmake.log"))
    p = _run(script, work, env, "--help")
    # the program's usage names it as the script ran it: from the named build, as the user named it
    assert p.returncode == 0 and f"Usage: {build}/bin/{program} " in p.stdout, (p.returncode, p.stdout[:300], p.stderr)
    # the one cmake call built the named build's program, never the checkout's build/
    assert (tmp_path / "cmake.log").read_text() == f"cmake --build {build} -j2 --target {program}\n"


def test_the_python_scripts_read_gimbalsim_build_too(tmp_path):
    # (pass 83, 84) py_bench.py imported the package before reading a flag (a traceback, exit 1), tune_sweep.py
    # and the --build of the others took the checkout's build/ whatever GIMBALSIM_BUILD said
    env = dict(os.environ, GIMBALSIM_BUILD="nowhere")
    env.pop("PYTHONPATH", None)
    for script, said in (("tools/bench/py_bench.py", f"py_bench.py: error: no gimbalsim package in {tmp_path}/nowhere/"
                                                      "python: cmake --build"),
                         ("tools/hil/tune_sweep.py", f"tune_sweep: error: controller_sweep not built in {tmp_path}/"
                                                      "nowhere/bin")):
        args = ["--in-process", "--omega", "20", "--duration", "4"] if "tune" in script else ["--repeats", "1"]
        p = subprocess.run(["/usr/bin/python3", str(SOURCE / script), *args], cwd=tmp_path, env=env,
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and p.stderr.startswith(said), (script, p.returncode, p.stderr)
    env["GIMBALSIM_BUILD"] = str(BIN.parent)  # the tests' build: its package runs
    p = subprocess.run(["/usr/bin/python3", str(SOURCE / "tools/bench/py_bench.py"), "--repeats", "1", "--steps", "2"],
                       cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "paper_clearance" in p.stdout, (p.returncode, p.stderr)
