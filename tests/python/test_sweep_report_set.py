"""A sweep's report (results.csv, the plots, report.md, summary.json) is one
set (issue 41, class 6): a sweep stopped while writing it leaves none of it,
only the journal, so "run again with --resume" is true, and the resume
writes the whole set."""
import csv
import json
import subprocess
import sys

from conftest import SCENES

SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.05}}
samples: 4
seed: 3
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
"""

# The sweep's own main, with its plotting followed by a SIGINT: the signal arrives after
# results.csv and the plots are under their names, before summary.json.
STOP_AFTER_PLOTS = """
import os, signal, sys
import gimbalsim.sweep as sw
real = sw.plot
def plot_then_stop(*args, **kwargs):
    written = real(*args, **kwargs)
    assert written, "the stop must come after a plot was written"
    os.kill(os.getpid(), signal.SIGINT)
    return written
sw.plot = plot_then_stop
sys.exit(sw.main(sys.argv[1:]))
"""


def files(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file())


def test_a_sweep_stopped_while_writing_its_report_leaves_none_of_it(tmp_path):
    spec = tmp_path / "spec.yaml"
    spec.write_text(SPEC)
    out = tmp_path / "out"
    args = [str(spec), "--out", str(out), "--no-progress", "--workers", "1"]
    p = subprocess.run([sys.executable, "-c", STOP_AFTER_PLOTS, *args], capture_output=True, text=True, timeout=300)
    assert p.returncode == 130, p.stderr
    assert "4 samples kept" in p.stderr and "run again with --resume" in p.stderr, p.stderr
    left = files(out)
    assert "results.csv" not in left and "summary.json" not in left, left
    assert not (out / "plots").exists(), left  # nor the folder it made for them
    assert not [f for f in left if f.endswith(".tmp")], left
    # the resume runs nothing again and writes the whole set
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", *args, "--resume"], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    assert "4 already done, 0 to run" in p.stderr, p.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["plots"] and all((out / "plots" / p.split("/")[-1]).is_file() for p in summary["plots"])
    with open(out / "results.csv") as f:
        assert len(list(csv.reader(f))) == 1 + 4
