"""Issue 41, "Hostile and careless input" (pass 20), the programs' side: the
pointing study and the controller-floor program stop on SIGINT or SIGTERM
during a long run (they finished the run first: only SIGKILL ended a long
--duration), leaving no temporary; and an allocation resumed over a value
folder copied from another value is refused before any run (it ran value 0
again first)."""
import json
import shutil
import signal
import subprocess
import time

import pytest

from conftest import BIN, SCENES
from test_pass16_outputs import finished, tool  # noqa: F401 (finished: a fixture)

SCENE_ARGS = ["--ideal-scene", str(SCENES / "paper_ideal.yaml"), "--clearance-scene",
              str(SCENES / "paper_clearance.yaml"), "--clearances", "2.5e-4"]


def _signal_once_running(cmd, started, sig):
    """Starts cmd, waits until started() (its outputs' temporaries exist), lets
    it run into its first long run, signals it; (exit code, stderr, seconds to end)."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not started():
        if time.monotonic() > deadline or proc.poll() is not None:
            proc.kill()
            pytest.fail(f"never started: {proc.communicate()[1]}")
        time.sleep(0.02)
    time.sleep(0.5)
    proc.send_signal(sig)
    sent = time.monotonic()
    try:
        _, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("still running 60 s after the signal")
    return proc.returncode, err, time.monotonic() - sent


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_the_pointing_study_stops_within_its_run_on_a_signal(tmp_path, sig):
    out = tmp_path / "study"
    out.mkdir()
    cmd = [str(BIN / "gimbalsim_pointing_study"), "--duration", "3000", "--out", str(out), *SCENE_ARGS]
    code, err, took = _signal_once_running(cmd, lambda: any(out.iterdir()), sig)
    assert code == 128 + sig, err
    assert f"interrupted by {signal.Signals(sig).name} after 0 whole runs" in err, err
    assert took < 30, took
    assert sorted(p.name for p in out.iterdir()) == ["config.txt", "pointing_error.csv", "summary.csv"]
    assert (out / "summary.csv").read_text().count("\n") == 1, "the header only: no run was whole"


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_the_controller_floor_stops_within_its_run_on_a_signal(tmp_path, sig):
    md = tmp_path / "floor.md"
    cmd = [str(BIN / "gimbalsim_controller_floor"), "--duration", "3000", "--markdown", str(md), *SCENE_ARGS]
    code, err, took = _signal_once_running(cmd, lambda: any(tmp_path.iterdir()), sig)
    assert code == 128 + sig, err
    assert f"interrupted by {signal.Signals(sig).name}: nothing written" in err, err
    assert took < 30, took
    assert list(tmp_path.iterdir()) == [], "no page, no temporary"


def test_a_resume_over_a_value_copied_from_another_is_refused_before_any_run(tmp_path, finished):
    spec, first, code, answer = finished
    out = tmp_path / "out"
    shutil.copytree(first, out)
    values = out / "values"
    (values / "0" / "results.csv").unlink()  # value 0 must run again ...
    shutil.copy(values / "2" / "spec.json", values / "1" / "spec.json")  # ... and value 1 holds value 2's sweep
    p = tool("allocate", spec, out, "--resume")
    assert p.returncode == 2, p.stderr
    assert f"{values / '1'} holds a sweep at another value" in p.stderr, p.stderr
    assert "another build" not in p.stderr, p.stderr
    assert not (values / "0" / "results.csv").exists(), "value 0 ran before the refusal"
    assert not (values / "0" / "results.partial.csv").exists(), "value 0 ran before the refusal"
    assert json.loads((out / "allocation.json").read_text()) == answer
