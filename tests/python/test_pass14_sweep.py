"""Pass 14 of the sweep engine: a fixed base's joint 1 place is a key no run
reads (refused at its line, dispersed or set); a disk `within` a key is
tried on the scene at the rim that key gives, and must name a key in the
disk's unit; a resume trusts no status: each row must have the shape the
sweep writes for its status (docs/python.md "Refusals", "The journal")."""
import csv
import json
import shutil
import subprocess
import sys

import pytest

from conftest import SCENES


def sweep(*args):
    return subprocess.run([sys.executable, "-m", "gimbalsim.sweep", *map(str, args), "--no-progress"],
                          capture_output=True, text=True, timeout=600)


def run_spec(tmp_path, text, *args):
    (tmp_path / "spec.yaml").write_text(text)
    return sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", *args)


def read(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


# ---- D1: joint 1's place on a fixed base acts on nothing ----

FIXED = f"""
scene: {SCENES}/stickslip_clearance.yaml
set: {{sim.duration: 0.05}}
samples: 2
seed: 3
"""


def test_joint1_position_dispersed_on_a_fixed_base_is_refused_at_its_line(tmp_path):
    # The defect: every row came out the same, bit for bit, while applied_geometry_joint1_position_* differed.
    p = run_spec(tmp_path, FIXED + "parameters:\n  geometry.joint1_position: {ball: {radius: 500.0}}\n")
    assert p.returncode == 2, p.stderr
    assert "spec.yaml:7:3: key 'parameters.geometry.joint1_position': not read by this sweep's runs " \
           "(structure.base is fixed" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


def test_joint1_position_set_on_a_fixed_base_is_refused_at_its_line(tmp_path):
    text = FIXED.replace("{sim.duration: 0.05}", "{sim.duration: 0.05, geometry.joint1_position: [100, 0, 0]}")
    p = run_spec(tmp_path, text + "parameters:\n  contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n")
    assert p.returncode == 2, p.stderr
    assert "spec.yaml:3:" in p.stderr and "key 'set.geometry.joint1_position': not read by this sweep's runs " \
           "(structure.base is fixed" in p.stderr, p.stderr


def test_joint1_position_acts_on_a_floating_base_and_when_the_base_is_dispersed(tmp_path):
    from gimbalsim.sweep import SweepSpec
    dispersed_base = "grid: {structure.base: [fixed, floating]}\n"
    for scene, grid in (("paper_clearance", ""), ("stickslip_clearance", dispersed_base)):
        (tmp_path / "s.yaml").write_text(f"scene: {SCENES}/{scene}.yaml\nsamples: 2\nseed: 3\n"
                                         "parameters: {geometry.joint1_position: {ball: {radius: 0.2}}}\n" + grid)
        SweepSpec(tmp_path / "s.yaml")  # no refusal


# ---- D2: a disk within a key, tried on the scene ----

CLOSED = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.1}}
controller: default
samples: 3
seed: 3
phases: [{{w: [0.0, 0.1]}}]
indices: {{ape: {{}}}}
parameters:
"""


def test_a_disk_within_a_key_of_another_unit_is_refused(tmp_path):
    # The defect: within friction.mu (no length) drew eccentricities of 0.125 m; every row refused:initial.ecc.
    p = run_spec(tmp_path, CLOSED + "  initial.ecc: {disk: {within: friction.mu, fraction: 0.5}}\n")
    assert p.returncode == 2, p.stderr
    assert "spec.yaml:10:3: key 'parameters.initial.ecc': disk: within friction.mu is in -, initial.ecc in m" \
        in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


def test_a_disk_within_a_scene_value_that_reaches_past_the_clearance_is_refused(tmp_path):
    p = run_spec(tmp_path, CLOSED + "  initial.ecc: {disk: {within: contact.bearing_radius, fraction: 0.5}}\n")
    assert p.returncode == 2, p.stderr
    assert "spec.yaml:10:3: key 'parameters.initial.ecc': disk: within contact.bearing_radius, fraction 0.5 of " \
           "contact.bearing_radius 0.01 (the scene's) reaches initial.ecc" in p.stderr, p.stderr
    assert "initial eccentricity exceeds the radial clearance of joint 2" in p.stderr, p.stderr


def test_a_disk_within_a_dispersed_key_is_tried_at_each_end_of_it(tmp_path):
    from gimbalsim._errors import SpecError
    from gimbalsim.sweep import SweepSpec
    # the bearing radius 10 to 12 mm over a 9.5 mm journal: a clearance of 0.5 to 2.5 mm; 6 % of 10 mm is past it
    text = CLOSED + "  contact.bearing_radius: {uniform: [0.01, 0.012]}\n" \
                    "  initial.ecc: {disk: {within: contact.bearing_radius, fraction: 0.06}}\n"
    (tmp_path / "s.yaml").write_text(text)
    with pytest.raises(SpecError) as e:
        SweepSpec(tmp_path / "s.yaml")
    assert "key 'parameters.initial.ecc': disk: within contact.bearing_radius, fraction 0.06 of " \
           "contact.bearing_radius 0.01 reaches" in str(e.value), str(e.value)
    # at its rim, within a clearance it spans: taken (a rim of fraction 1 is no draw, and not refused)
    (tmp_path / "s.yaml").write_text(CLOSED + "  initial.ecc: {disk: {within: contact.clearance, fraction: 1.0}}\n"
                                     "grid: {contact.clearance: [1.0e-4, 3.0e-4]}\n")
    SweepSpec(tmp_path / "s.yaml")


# ---- D3: a resume trusts no status ----

STOPPING = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.2}}
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.1, profile.hold_time: 0.05}}
samples: 1
seed: 3
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
grid: {{sim.velocity_limit: [0.05, 100.0]}}
phases: [slew, track]
indices: {{ape: {{}}}}
"""


@pytest.fixture(scope="module")
def closed_ref(tmp_path_factory):
    folder = tmp_path_factory.mktemp("closed")
    (folder / "spec.yaml").write_text(STOPPING)
    p = sweep(folder / "spec.yaml", "--out", folder / "ref", "--workers", "1")
    assert p.returncode == 0, p.stderr
    rows = read(folder / "ref" / "results.csv")
    assert [r[rows[0].index("status")] for r in rows[1:]] == ["sim.velocity_limit", "ok"]
    return folder, rows


def why(spec, row, **cells):
    from gimbalsim._journal import check_row
    header, row = spec.csv_header(), list(row)
    for name, text in cells.items():
        row[header.index(name)] = text
    return check_row(spec, row, len(header))


def test_resume_drops_an_ok_row_relabelled_a_stop_and_runs_it_again(closed_ref, tmp_path):
    # The defect: "2 samples, 2 already done, 0 to run", the stop without a reason kept with its figures.
    folder, reference = closed_ref
    header, out = reference[0], tmp_path / "out"
    shutil.copytree(folder / "ref", out)
    (out / "results.csv").unlink()
    (out / "summary.json").unlink()
    rows = [list(r) for r in reference]
    rows[2][header.index("status")] = "sim.velocity_limit"
    (out / "results.partial.csv").write_text("".join(",".join(r) + "\n" for r in rows))
    p = sweep(folder / "spec.yaml", "--out", out, "--workers", "1", "--resume")
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    assert "2 samples, 1 already done, 1 to run" in p.stderr, p.stderr
    assert "dropped 1 journal row (reason is not a stopped row's" in p.stderr, p.stderr
    w = header.index("wall_time_s")
    assert [r[:w] + r[w + 1:] for r in read(out / "results.csv")] == [r[:w] + r[w + 1:] for r in reference]
    assert list(json.loads((out / "summary.json").read_text())["journal_rows_dropped"].values()) == [1]


def test_each_closed_loop_status_has_the_shape_the_sweep_writes(closed_ref):
    from gimbalsim.sweep import SweepSpec
    folder, reference = closed_ref
    spec = SweepSpec(folder / "spec.yaml")
    stopped, ok = reference[1], reference[2]
    assert why(spec, stopped) is None and why(spec, ok) is None
    message = stopped[reference[0].index("reason")]
    # a stop: its message first, every figure written
    assert "reason is not a stopped row's" in why(spec, ok, status="non_finite", reason="ape_track: x")
    assert "a figure is empty" in why(spec, stopped, max_tilt1_rad="")
    # (pass 94) a hand-edited reason with a space at its end was kept as the sweep's own
    assert "reason has white space at an end of a part" in why(spec, stopped, reason=message + " ")
    assert "reason has white space at an end of a part" in why(spec, stopped, reason=" " + message)
    # ok: the reason names only its nan indices; a stop's message is no ok row's
    assert "reason is not an ok row's" in why(spec, stopped, status="ok", reason=message, ape_slew_rad="0.1",
                                               ape_track_rad="0.1")
    assert "reason is not an ok row's" in why(spec, ok, reason="ape_slew: missed")
    # a status the sweep never writes, a crashed row with a reason
    assert "status is none the sweep writes" in why(spec, ok, status="velocity")
    blank = {h: "" for h in reference[0] if h.startswith(("applied_", "ape_", "max_tilt", "t_end"))}
    assert why(spec, ok, status="crashed", wall_time_s="nan", **blank) is None
    assert "reason is not empty in a crashed" in why(spec, ok, status="crashed", wall_time_s="nan", reason="x",
                                                     **blank)


def test_each_open_loop_status_has_the_shape_the_sweep_writes(tmp_path):
    from gimbalsim._sample import sample_alone
    from gimbalsim.sweep import SweepSpec
    (tmp_path / "s.yaml").write_text(f"scene: {SCENES}/paper_clearance.yaml\nset: {{sim.duration: 0.05}}\n"
                                     "samples: 1\nseed: 3\nparameters: {contact.clearance: {uniform: [1.0e-4, "
                                     "3.0e-4]}}\n")
    spec = SweepSpec(tmp_path / "s.yaml")
    ok = sample_alone(spec, 0)[0]
    assert why(spec, ok) is None
    assert why(spec, ok, status="sim.energy_tol") is None  # a stop's figures are over the part it ran
    assert "status is none the sweep writes" in why(spec, ok, status="stopped")
    assert "status is none the sweep writes" in why(spec, ok, status="ideal:banana")
    # the twin stopped first: no pointing error
    assert "ideal:<stop> row" in why(spec, ok, status="ideal:sim.velocity_limit")
    nan = {"pointing_error_max_rad": "nan", "pointing_error_final_rad": "nan"}
    assert why(spec, ok, status="sim.velocity_limit|ideal:sim.velocity_limit", **nan) is None


# ---- a control period the plant cannot tick: a refused row, kept by a resume ----

def test_a_control_period_off_the_scenes_step_is_a_refused_row_a_resume_keeps(tmp_path):
    # The defect: status 'refused' (no key) with figures of a run that stopped at its first tick, a reason
    # suggesting a command-line flag; and a resume then dropped the row ("the scene takes the draw").
    # A grid of periods is checked against the spec's step at its line (pass 21); a grid of steps meets the
    # controller's period only in the sample.
    p = run_spec(tmp_path, f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.7}}
controller: default
samples: 1
seed: 1
grid:
  sim.step: [0.001, 0.0007]
phases: [{{w: [0.2, 0.7]}}]
indices:
  ape: {{requirement: 1.0e-4}}
""")
    assert p.returncode == 0, p.stderr
    rows = read(tmp_path / "out" / "results.csv")
    h, refused = rows[0], rows[2]
    assert refused[h.index("status")] == "refused:controller.control.period", refused
    assert refused[h.index("reason")].startswith("control.period: 0.001 s must be a whole multiple of the scene's "
                                                  "step (sim.step) (7e-04 s)"), refused
    assert refused[h.index("ape_w_rad")] == "" and refused[h.index("t_end_s")] == "", refused  # nothing ran
    again = sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", "--resume")
    assert again.returncode == 0 and "2 samples, 2 already done, 0 to run" in again.stderr, again.stderr


# ---- a replay finds the files the sweep found, wherever it is run from ----

def test_a_replay_from_elsewhere_finds_a_scene_the_sweep_found_in_its_working_directory(tmp_path):
    # The defect: a scene named relative to where the sweep ran (not beside its spec) could not be replayed
    # from another directory, though inputs.json recorded it.
    work, sub, elsewhere = tmp_path / "work", tmp_path / "work" / "sub", tmp_path / "elsewhere"
    sub.mkdir(parents=True)
    elsewhere.mkdir()
    shutil.copy(SCENES / "paper_ideal.yaml", work / "myscene.yaml")
    (sub / "spec.yaml").write_text("scene: myscene.yaml\nset: {sim.duration: 0.05}\nsamples: 1\nseed: 1\n"
                                   "parameters:\n  initial.theta1: {uniform: [0.0, 0.1]}\n")
    run = lambda *a, cwd: subprocess.run([sys.executable, "-m", "gimbalsim.sweep", *map(str, a), "--no-progress"],
                                         capture_output=True, text=True, timeout=300, cwd=cwd)  # noqa: E731
    p = run(sub / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", cwd=work)
    assert p.returncode == 0, p.stderr
    assert json.loads((tmp_path / "out" / "inputs.json").read_text())["workdir"] == str(work)
    r = run(tmp_path / "out", "--replay", "0", "--out", tmp_path / "again.csv", cwd=elsewhere)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "again.csv").is_file()
    # gone from there too: the refusal says every place it looked
    (work / "myscene.yaml").rename(work / "moved.yaml")
    r = run(tmp_path / "out", "--replay", "0", "--out", tmp_path / "third.csv", cwd=elsewhere)
    assert r.returncode == 2 and f"then in {work}, the sweep's working directory, then in the current" in r.stderr, \
        r.stderr


def test_an_open_loop_run_stopped_on_a_non_finite_output_row_is_not_ok():
    # simulate.cpp stops on a non-finite output row with no step failed: key "", step status "ok"; the row's
    # status was "ok" for a run that stopped. A resume keeps the row as the sweep writes it.
    from gimbalsim import _journal, _open_sample
    summary = {"stop": {"key": "", "step_status": "ok", "time_s": 0.25}}
    assert _open_sample._stop_name(summary) == "non-finite_output"
    assert "non-finite_output" in _journal.OPEN_STOPS
    stopped = {"stop": {"key": "", "step_status": "non-finite value (NaN or Inf) in the state", "time_s": 0.25}}
    assert _open_sample._stop_name(stopped) == "non-finite_value_(NaN_or_Inf)_in_the_state"


def test_a_tuners_disk_within_a_dispersed_key_is_tried_at_that_keys_ends(tmp_path):
    # As the sweep: the rim half the bearing radius gives (4.8-5 mm) lies outside the clearance the dispersed
    # bearing radius leaves (0.1-0.6 mm): refused up front, before any trial.
    (tmp_path / "t.yaml").write_text(f"""
scene: {SCENES}/paper_clearance.yaml
controller: default
duration: 3.7
trials: 2
seed: 3
batch: 2
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
plants:
  contact.bearing_radius: {{uniform: [0.0096, 0.0101]}}
  initial.ecc: {{disk: {{within: contact.bearing_radius, fraction: 0.5}}}}
""")
    p = subprocess.run([sys.executable, "-m", "gimbalsim.tune", str(tmp_path / "t.yaml"), "--out", str(tmp_path / "o"),
                        "--no-progress"], capture_output=True, text=True, timeout=600)
    assert p.returncode == 2, p.stderr
    assert "key 'plants.initial.ecc': the scene refuses contact.bearing_radius=" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()
