"""A figure over nothing is never a number and never bare: an open-loop
sample whose ideal-joint twin stopped is not ok and has no pointing error;
an open-loop sweep without an ok sample says why its percentiles are null
(summary.json and the console); report.md's worst units list the units
without a figure (refused ones too) with their status and reason, ranked
worst, never `nan`."""
import json
import math
import subprocess
import sys
from types import SimpleNamespace

import numpy as np

import gimbalsim
from conftest import SCENES
from gimbalsim import _budget_report, _open_sample


def sweep(spec_text, tmp, name):
    spec = tmp / f"{name}.yaml"
    spec.write_text(spec_text)
    out = tmp / name
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--workers", "1",
                        "--no-progress"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return out, p.stderr


# ---- 6: the ideal-joint twin that stopped ----

def test_a_twin_stopped_at_the_start_gives_no_pointing_error():
    # The spatial run does not check energy; its ideal-joint twin does, and at 1e-300 it stops at
    # its first step. Called directly (not through a sweep spec, which may refuse the key).
    base = gimbalsim.load_scene(SCENES / "paper_spatial2.yaml", {"sim.duration": 0.02, "sim.energy_tol": 1e-300})
    twin = gimbalsim.simulate(base.replace({"structure.joint1": "ideal", "structure.joint2": "ideal"}))
    run = gimbalsim.simulate(base)
    assert run.ok and not twin.ok and len(twin.rows) < len(run.rows)  # the trigger holds
    r = _open_sample.run_sample(base, {}, {})
    assert r["status"] == "ideal:sim.energy_tol", r["status"]
    assert math.isnan(r["pointing_error_max"]) and math.isnan(r["pointing_error_final"])
    # the figures of the run itself stay
    assert r["peak_joint2_force"] == run.summary["peak_joint2_force_N"]


class _FakeRun:
    def __init__(self, n, stop=None):
        self.rows = np.zeros((n, len(gimbalsim.COLUMNS)))
        self.rows[:, gimbalsim.COLUMNS.index("bore_x")] = 1.0
        self.ok = stop is None
        self.summary = {"stop": {"key": stop, "step_status": "ok"}, "peak_contact_force_N": 0.0,
                        "peak_joint2_force_N": 0.0, "impacts": 0, "continuous_contact_from_s": None}


def _patched(monkeypatch, run, twin):
    def simulate(scene):
        v = scene.values()
        return twin if v["structure.joint1"] == v["structure.joint2"] == "ideal" else run
    monkeypatch.setattr(_open_sample.gimbalsim, "simulate", simulate)


def test_a_twin_shorter_than_a_stopped_run_names_both(monkeypatch):
    base = gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"sim.duration": 0.02})
    _patched(monkeypatch, _FakeRun(10, "sim.penetration_limit"), _FakeRun(4, "sim.velocity_limit"))
    r = _open_sample.run_sample(base, {}, {})
    assert r["status"] == "sim.penetration_limit|ideal:sim.velocity_limit"
    assert math.isnan(r["pointing_error_max"])


def test_a_twin_that_outlived_the_stopped_run_still_gives_its_figure(monkeypatch):
    base = gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"sim.duration": 0.02})
    _patched(monkeypatch, _FakeRun(4, "sim.penetration_limit"), _FakeRun(10, "sim.velocity_limit"))
    r = _open_sample.run_sample(base, {}, {})
    assert r["status"] == "sim.penetration_limit" and r["pointing_error_max"] == 0.0


# ---- 7: percentiles over no ok sample ----

def test_no_ok_sample_gives_null_percentiles_with_a_reason(tmp_path):
    out, err = sweep(f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.05, sim.velocity_limit: 0.001}}
samples: 4
seed: 3
parameters: {{contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}}}
""", tmp_path, "none_ok")
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == {"sim.velocity_limit": 4}
    assert s["percentiles_of_ok_samples"]["pointing_error_max"] is None
    note = s["percentiles_of_ok_samples_note"]
    assert set(note) == set(s["percentiles_of_ok_samples"])  # every null has its reason
    assert note["pointing_error_max"] == "no ok sample: 4 samples (sim.velocity_limit 4)"
    assert "nan" not in err
    assert "pointing_error_max n/a (no ok sample: 4 samples (sim.velocity_limit 4))" in err, err


def test_ok_samples_give_an_empty_note(tmp_path):
    out, err = sweep(f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.05}}
samples: 2
seed: 3
parameters: {{contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}}}
""", tmp_path, "all_ok")
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == {"ok": 2}
    # ok runs that never reach continuous contact: no value of it, and the note says so
    assert s["percentiles_of_ok_samples"]["pointing_error_max"]["n"] == 2
    assert "pointing_error_max" not in s["percentiles_of_ok_samples_note"]
    assert s["percentiles_of_ok_samples"]["continuous_contact_from"] is None
    assert s["percentiles_of_ok_samples_note"]["continuous_contact_from"] == \
        "none of the 2 ok samples has a value of continuous_contact_from"
    for m, p in s["percentiles_of_ok_samples"].items():
        assert (p is None) == (m in s["percentiles_of_ok_samples_note"]), m
    assert "pointing_error_max p50 " in err and "n/a" not in err.split("pointing_error_max")[1].split(";")[0]


# ---- 8: report.md's worst units ----

def _spec():
    header = ["sample", "contact.clearance", "status", "reason", "ape_track", "knowledge_track"]
    return SimpleNamespace(header=lambda: header,
                           design=SimpleNamespace(columns=lambda: ["contact.clearance"], grid_keys=[]),
                           closed=SimpleNamespace(metrics=lambda: ["ape_track", "knowledge_track"]))


MIXED = [["0", "1e-4", "ok", "", "2e-5", "1e-6"],
         ["1", "-1", "refused:contact.clearance", "contact.clearance: must be >= 0", "", ""],
         ["2", "8e-4", "ok", "", "9e-5", "1e-6"],
         ["3", "-2", "refused:contact.clearance", "contact.clearance: must be >= 0", "", ""],
         ["4", "5e-4", "sim.velocity_limit", "simulation stopped at t = 0.1 s | knowledge_track: x | "
          "ape_track: the run never reached the phase", "nan", "nan"],
         ["5", "3e-4", "crashed", "", "", ""],
         ["6", "2e-4", "ok", "knowledge_track: missed", "5e-5", "nan"]]


def test_worst_units_rank_refused_stopped_and_crashed_first_with_why():
    got = _budget_report.worst_units(_spec(), MIXED, "ape_track", k=6)
    assert [g[0] for g in got] == ["1", "3", "4", "5", "2", "6"]
    assert [g[1] for g in got] == [None, None, None, None, 9e-5, 5e-5]
    assert got[0][2] == "refused:contact.clearance: contact.clearance: must be >= 0"
    # the run's own reason and this index's, not the other index's
    assert got[2][2] == "sim.velocity_limit: simulation stopped at t = 0.1 s | ape_track: the run never reached the phase"
    assert got[3][2] == "crashed"
    assert got[4][3] == ["8e-4"]


def test_an_ok_unit_that_missed_the_phase_is_worst_with_its_reason():
    rows = [["0", "1e-4", "ok", "", "2e-5", "1e-6"],
            ["1", "2e-4", "ok", "ape_track: the run ended at 0.3 s | knowledge_track: same", "nan", "nan"]]
    got = _budget_report.worst_units(_spec(), rows, "ape_track")
    assert [(g[0], g[1], g[2]) for g in got] == [("1", None, "ok: ape_track: the run ended at 0.3 s"),
                                                  ("0", 2e-5, "")]


def test_the_report_of_a_sweep_whose_every_unit_stopped_lists_why(tmp_path):
    out, _ = sweep(f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.4, sim.velocity_limit: 0.05}}
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.1, profile.hold_time: 0.1}}
samples: 4
seed: 3
parameters:
  contact.clearance: {{choice: [1.0e-4, 8.0e-4]}}
phases: [slew, hold, track]
indices: {{ape: {{}}, knowledge: {{}}}}
""", tmp_path, "all_stopped")
    text = (out / "report.md").read_text()
    worst = text[text.index("Worst five units"):].splitlines()
    rows = [line for line in worst if line.startswith("| ") and not line.startswith("| sample")]
    assert [r.split(" | ")[0] for r in rows] == ["| 0", "| 1", "| 2", "| 3"], rows
    for r in rows:
        assert "nan" not in r, r
        assert "| no figure (sim.velocity_limit: simulation stopped at t = " in r, r
        assert "ape_track: the run" in r and "knowledge_track" not in r, r
        assert len(r.split(" | ")) == 3, r  # the reason's '|' is escaped: the table keeps its columns
