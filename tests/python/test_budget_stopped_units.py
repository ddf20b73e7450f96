"""The budget of a closed-loop sweep in which some units stop in the track,
after their slew and hold (pass 55): each cell says that the stopped units'
rows hold the slew's and hold's figures the budget did not take, not only
where the quantile falls on them, and report.md's 95 % column never prints
a bare inf."""
import json
import subprocess
import sys

from conftest import SCENES

SPEC = f"""scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 1.0}}
controller: default
controller_set: {{profile.slew_start: 0.1, profile.slew_time: 0.3, profile.hold_time: 0.2,
                 profile.slew_target: [0.01, 0.01], profile.track_rate: [0.5, 0.0], profile.track_ramp_time: 0.05}}
samples: 16
seed: 3
parameters:
  sim.velocity_limit: {{choice: [0.2, 0.2, 100.0, 100.0]}}
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
phases: [slew, hold, track]
indices:
  ape: {{level: 0.5, confidence: 0.5, requirement: 1.0}}
"""


def test_stopped_units_figures_are_said_in_every_cell_and_no_column_is_bare(tmp_path):
    (tmp_path / "s.yaml").write_text(SPEC)
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(tmp_path / "s.yaml"), "--out",
                        str(tmp_path / "o"), "--workers", "1", "--no-progress"], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    rows = (tmp_path / "o" / "results.csv").read_text().splitlines()[1:]
    stopped = [r for r in rows if ",sim.velocity_limit," in r]
    assert 0 < len(stopped) < len(rows), rows  # the case asked for: some units stop, in the track
    budget = {e["phase"]: e for e in json.loads((tmp_path / "o" / "summary.json").read_text())["budget"]}
    slew = budget["slew"]
    assert slew["estimate_rad"] is not None and slew["n_missing"] == len(stopped)
    # the slew's median is a figure, and the stopped units' slew figures were set aside: said so
    assert slew["unused_note"] == (f"{len(stopped)} of the {len(stopped)} units without a figure the budget takes "
                                   "stopped after this phase and hold its figure, not used: a unit that stopped "
                                   "counts as worst"), slew
    report = (tmp_path / "o" / "report.md").read_text()
    table = [line for line in report.splitlines() if line.startswith("| ape |")]
    assert len(table) == 3 and all(slew["unused_note"] in line for line in table[:2]), table
    assert not any("| inf |" in line or " inf " in line for line in table), table
    assert any("beyond every figure (on the" in line.split("|")[6] for line in table), table
