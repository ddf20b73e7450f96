"""A flag that takes one value, given twice, is refused (exit 2) naming the
flag, by the Python programs and the scripts as by the C++ programs (CLI11):
pass 76 found `--out a --out b` and `--workers 1 --workers 2` taken silently
(the last one won) by gimbalsim.sweep, tune and allocate, by
run_pointing_budget.sh (which hands them to the sweep) and, for --duration
and --out, by run_hil_bench.sh. Nothing is run or written."""
import os
import pathlib
import subprocess
import sys

import pytest

from conftest import BIN, SOURCE

SPEC_TEXT = "scene: nothing.yaml\n"  # never read: the arguments are refused first


@pytest.mark.parametrize("module", ["sweep", "tune", "allocate"])
@pytest.mark.parametrize("flags,named", [(("--out", "a", "--out", "b"), "--out"),
                                         (("--out", "a", "--workers", "1", "--workers=2"), "--workers"),
                                         (("--out=a", "--out=a"), "--out")])
def test_a_python_program_refuses_a_flag_of_one_value_given_twice(tmp_path, module, flags, named):
    (tmp_path / "s.yaml").write_text(SPEC_TEXT)
    p = subprocess.run([sys.executable, "-m", f"gimbalsim.{module}", "s.yaml", *flags], cwd=tmp_path,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert f"error: {named}: given twice; it takes one value" in p.stderr, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["s.yaml"], os.listdir(tmp_path)


def test_a_flag_without_a_value_given_twice_is_still_taken(tmp_path):
    # --no-progress twice asks one thing twice: not a refusal (the sweep then refuses the missing scene)
    (tmp_path / "s.yaml").write_text(SPEC_TEXT)
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", "s.yaml", "--out", "o", "--no-progress",
                        "--no-progress"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and "given twice" not in p.stderr and "s.yaml: key" in p.stderr, p.stderr


def test_the_budget_script_hands_a_repeated_out_to_the_sweep_which_refuses_it(tmp_path):
    (tmp_path / "s.yaml").write_text(SPEC_TEXT)
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    p = subprocess.run(["bash", str(SOURCE / "tools/sweeps/run_pointing_budget.sh"), "s.yaml", "--out", "a",
                        "--out", "b"], cwd=tmp_path, capture_output=True, text=True, timeout=120, env=env)
    assert p.returncode == 2 and "--out: given twice; it takes one value" in p.stderr, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["s.yaml"], os.listdir(tmp_path)


@pytest.mark.parametrize("flags,named", [(("--duration", "1", "--duration", "2"), "--duration"),
                                         (("--out", "a", "--out", "b"), "--out"),
                                         (("--realtime", "--lockstep"), "--realtime/--lockstep")])
def test_the_bench_script_refuses_a_flag_of_one_value_given_twice(tmp_path, flags, named):
    env = {**os.environ, "GIMBALSIM_BUILD": str(BIN.parent)}
    p = subprocess.run(["bash", str(SOURCE / "tools/hil/run_hil_bench.sh"), *flags], cwd=tmp_path,
                       capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 2 and f"run_hil_bench.sh: {named}: given twice; it takes one value" in p.stderr, \
        p.stderr
    assert os.listdir(tmp_path) == [], os.listdir(tmp_path)
