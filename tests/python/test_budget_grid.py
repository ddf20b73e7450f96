"""A closed-loop sweep with a grid: a budget per grid point (pass 106: every point gets the same draws, so the
pooled budget counted each unit drawn once per point: 2 units read "n=24 ... PASS")."""
import json
import subprocess
import sys

from conftest import CONTROLLER_CONFIG, SCENES

SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.3}}
controller: {CONTROLLER_CONFIG}
samples: 3
seed: 5
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
grid:
  contact.restitution: [0.8, 0.9]
phases: [{{w: [0.1, 0.3]}}]
indices:
  ape: {{requirement: 1.0, level: 0.5, confidence: 0.5}}
"""


def test_a_grid_gets_a_budget_per_point_over_the_units_drawn(tmp_path):
    (tmp_path / "spec.yaml").write_text(SPEC)
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(tmp_path / "spec.yaml"), "--out",
                        str(tmp_path / "out"), "--no-progress", "--workers", "1"], capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr
    budget = json.loads((tmp_path / "out" / "summary.json").read_text())["budget"]
    assert [(e["grid_point"], e["n"]) for e in budget] == [("contact.restitution=0.8", 3),
                                                           ("contact.restitution=0.9", 3)], budget
    assert "ape w [contact.restitution=0.9] at 50 %:" in p.stderr and "n=6" not in p.stderr, p.stderr
    report = (tmp_path / "out" / "report.md").read_text()
    assert "| ape | w (contact.restitution=0.8) | 50 % | 3 |" in report, report
