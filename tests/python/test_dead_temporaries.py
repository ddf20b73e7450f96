"""A writer killed by SIGKILL leaves its temporary (.NAME.<pid>.<n>.tmp) beside the name; a --resume kept it
for ever (pass 72). The sweep or tuner holding its folder removes the temporaries of processes no longer
running, and says so; a live process's temporary, a link and any other file stay."""
import os
import subprocess
import sys

import pytest

from test_sweep_journal import SPEC, sweep_cmd


@pytest.fixture
def spec(tmp_path):
    (tmp_path / "spec.yaml").write_text(SPEC)
    return tmp_path / "spec.yaml"


def dead_pid():
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_a_resume_removes_what_a_killed_writer_left_and_nothing_else(spec, tmp_path):
    out = tmp_path / "o"
    p = subprocess.run(sweep_cmd(spec, out), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    (out / "runs").mkdir(exist_ok=True)
    dead = dead_pid()
    left = [out / f".results.csv.{dead}.1.tmp", out / "runs" / f".sample_3.csv.{dead}.2.tmp"]
    for f in left:
        f.write_text("half a file")
    kept = [out / f".results.csv.{os.getpid()}.1.tmp",  # a live writer's
            out / "notes.tmp", out / f".results.csv.{dead}.tmp"]  # not our temporaries' names
    for f in kept:
        f.write_text("keep")
    link = out / f".summary.txt.{dead}.3.tmp"
    link.symlink_to(tmp_path / "spec.yaml")
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert not any(f.exists() for f in left), sorted(os.listdir(out))
    assert all(f.exists() for f in kept) and link.is_symlink(), sorted(os.listdir(out))
    assert (f"removed 2 temporary file(s) a killed writer left: .results.csv.{dead}.1.tmp, "
            f"runs/.sample_3.csv.{dead}.2.tmp") in p.stderr, p.stderr
