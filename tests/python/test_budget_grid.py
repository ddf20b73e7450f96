"""A closed-loop sweep with a grid: a budget per grid point (pass 106: every point gets the same draws, so the
pooled budget counted each unit drawn once per point: 2 units read "n=24 ... PASS"), and a gain on the grid
beside a dispersed profile key judged at the draws (pass 110)."""
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


GAIN_GRID = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 1.0}}
controller: {CONTROLLER_CONFIG}
controller_set: {{profile.slew_start: 0.1, profile.slew_time: 0.4}}
samples: 2
seed: 5
parameters:
  controller.profile.hold_time: {{uniform: [HOLD]}}
grid:
  controller.azimuth.kp: [2000.0, 4000.0]
phases: [hold, track]
"""


def test_a_gain_on_the_grid_beside_a_dispersed_profile_is_judged_at_the_draws(tmp_path):
    # (pass 110) the grid point's controller was judged at the default hold_time (1 s: the 1 s run ends inside
    # 'hold') and refused at the gain's line, though every draw (0.1 to 0.2 s) reaches both phases
    def check(hold):
        (tmp_path / "spec.yaml").write_text(GAIN_GRID.replace("HOLD", hold))
        return subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(tmp_path / "spec.yaml"), "--out",
                               str(tmp_path / "out"), "--check"], capture_output=True, text=True, timeout=120)
    p = check("0.1, 0.2")
    assert p.returncode == 0, p.stderr
    p = check("2.0, 3.0")  # no draw reaches 'track': refused at the key that decides it, never the gain's
    assert p.returncode == 2 and "key 'parameters.controller.profile.hold_time': " in p.stderr, p.stderr
    assert "grid.controller.azimuth.kp" not in p.stderr, p.stderr
