"""gimbalsim.tune: a short study writes trials.csv and a best.yaml that
pointing_controller loads as it is, holding the best feasible trial's gains;
tuning specs are refused naming the key."""
import csv
import subprocess
import sys

import pytest

import gimbalsim

from conftest import BIN, CONTROLLER_CONFIG, SCENES

SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
controller: {CONTROLLER_CONFIG}
duration: 3.7
trials: 5
parallel_trials: 2
seed: 3
batch: 2
objective: {{metric: max_track, percentile: 90}}
max_saturation: 0.0
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
  elevation.kd: {{uniform: [300, 3000]}}
plants:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
  sensors.star_tracker_noise: {{uniform: [0.0, 2.0e-5]}}
"""


def tune(spec, out, *args):
    return subprocess.run([sys.executable, "-m", "gimbalsim.tune", str(spec), "--out", str(out), "--no-progress",
                           *args], capture_output=True, text=True, timeout=600)


def test_a_short_study_writes_a_loadable_best_yaml_with_the_best_score(tmp_path):
    (tmp_path / "t.yaml").write_text(SPEC)
    p = tune(tmp_path / "t.yaml", tmp_path / "o", "--workers", "2")
    assert p.returncode == 0, p.stderr
    from test_csv_convention import check_convention
    check_convention(tmp_path / "o" / "trials.csv")  # the project's CSV convention, numbers included
    with open(tmp_path / "o" / "trials.csv") as f:
        trials = list(csv.DictReader(f))
    assert [int(t["trial"]) for t in trials] == list(range(5))
    complete = [t for t in trials if t["state"] == "COMPLETE"]
    feasible = [t for t in complete if float(t["constraint"]) <= 0.0]
    assert complete and all(t["plants_ok"] == "2" for t in complete)
    best = min(feasible or complete, key=lambda t: float(t["score"]))
    text = (tmp_path / "o" / "best.yaml").read_text()
    assert f"trial {best['trial']} " in text.splitlines()[0] and repr(float(best["score"])) in text.splitlines()[0]
    q = subprocess.run([str(BIN / "pointing_controller"), str(tmp_path / "o" / "best.yaml"), "--print-config"],
                       capture_output=True, text=True, timeout=60)
    assert q.returncode == 0, q.stderr
    printed = dict(line.split("=", 1) for line in q.stdout.splitlines())
    assert float(printed["azimuth.kp"]) == float(best["azimuth_kp_Nm_per_rad"])
    assert float(printed["elevation.kd"]) == float(best["elevation_kd_Nms_per_rad"])
    assert float(printed["azimuth.kd"]) == 1056.0  # untuned keys keep the base configuration's values
    assert (tmp_path / "o" / "progress.png").stat().st_size > 5000


@pytest.mark.parametrize("change,key", [
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kpp: {loguniform: [5000, 80000]}"), "gains.azimuth.kpp"),
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kp: {uniform: [-10, 80000]}"), "gains.azimuth.kp"),
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kp: {normal: {mean: 1, sd: 1}}"), "gains.azimuth.kp"),
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "contact.clearance: {uniform: [-1.0e-4, 8.0e-4]}"),
     "plants.contact.clearance"),
    (("duration: 3.7", "duration: 3.7004"), "duration"),
    # the C++ keys' whole-multiple rule (relative 1e-12), not a looser one of the spec's own
    (("duration: 3.7", "duration: 3.7000000001"), "duration"),
    (("metric: max_track", "metric: worst"), "objective.metric"),
])
def test_tuning_spec_refusals_name_the_key(change, key, tmp_path):
    (tmp_path / "t.yaml").write_text(SPEC.replace(*change))
    p = tune(tmp_path / "t.yaml", tmp_path / "o", "--workers", "1")
    assert p.returncode == 2 and f"key '{key}'" in p.stderr and "t.yaml:" in p.stderr, p.stderr


@pytest.mark.parametrize("plants,why", [
    ("plants: {}\n", "no plant key is dispersed: the 2 plants are one plant"),
    ("plants:\n  contact.clearance: {uniform: [2.0e-4, 2.0e-4]}\n", "each plant key takes one value"),
])
def test_plants_that_cannot_differ_are_refused_at_the_batch(plants, why, tmp_path):
    # (pass 78) every trial was scored over copies of one plant, its percentile counting it `batch` times
    text = SPEC.split("plants:")[0] + plants
    (tmp_path / "t.yaml").write_text(text)
    p = tune(tmp_path / "t.yaml", tmp_path / "o", "--workers", "1")
    assert p.returncode == 2 and "key 'batch'" in p.stderr and why in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("change,key,why", [
    (("metric: max_track", "metric: [max_track]"), "objective.metric", "expected a name"),
    (("max_saturation: 0.0", "max_saturation: {a: 1}"), "max_saturation", "expected a number"),
    (("max_saturation: 0.0", "controller_set: {azimuth.kd: null}"), "controller_set.azimuth.kd", "null"),
    (("max_saturation: 0.0", "controller_set: {azimuth.kq: 1.0}"), "controller_set.azimuth.kq",
     "not a key of the controller"),
    (("max_saturation: 0.0", "set: {contact.clearence: 1.0e-4}"), "set.contact.clearence", "not a key of the scene"),
    (("max_saturation: 0.0", "set: {sim.duration: [[1]]}"), "set.sim.duration", "list of numbers"),
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kp: {choice: [!!binary aGVsbG8=]}"),
     "gains.azimuth.kp.choice", "unsupported tag"),
    (("azimuth.kp: {loguniform: [5000, 80000]}", "gimbal.boresight: {choice: [[1, 0, 0], [0, 1, 0]]}"),
     "gains.gimbal.boresight", "numbers or names"),
    # a gain over one value: searched by no trial
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kp: {loguniform: [21120, 21120]}"),
     "gains.azimuth.kp", "loguniform over one value 21120.0: nothing to search; give it under controller_set"),
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kp: {choice: [21120, 21120]}"),
     "gains.azimuth.kp", "choice over one value"),
    # under the default model feed-forward the fixed-base inertia law is off: every trial the same loop
    (("azimuth.kp: {loguniform: [5000, 80000]}", "gimbal.azimuth_inertia_cos2: {uniform: [1, 9]}"),
     "gains.gimbal.azimuth_inertia_cos2", "not read by the tuned loop (the controller reads it only with "
     "pointing.accel_feedforward profile or inertial"),
    # an unknown gain is named as the controller's, not the scene's
    (("azimuth.kp: {loguniform: [5000, 80000]}", "azimuth.kpp: {loguniform: [5000, 80000]}"),
     "gains.azimuth.kpp", "not a key of the controller configuration"),
    # below the median the objective tunes for the lucky plants: [50, 100], the reason said
    (("percentile: 90", "percentile: 0"), "objective.percentile",
     "expected a number in [50.0, 100.0], got 0: a percentile below the median tunes for the lucky plants"),
    (("percentile: 90", "percentile: 1e-300"), "objective.percentile",
     "expected a number in [50.0, 100.0], got 1e-300: a percentile below the median tunes for the lucky plants"),
    (("percentile: 90", "percentile: 49.9"), "objective.percentile", "got 49.9: a percentile below the median"),
    (("percentile: 90", "percentile: 100.5"), "objective.percentile", "expected a number in [50.0, 100.0], got 100.5"),
    # the run length is the tuner's duration: key, not a sweep's set:
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "sim.duration: {uniform: [3.7, 4.0]}"),
     "plants.sim.duration", "a tuner's duration:"),
    # plants the loop never reads, as a sweep refuses them
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "torque.tau1: {uniform: [0, 1]}"),
     "plants.torque.tau1", "not read by the tuned loop (the controller commands the torque)"),
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "sensors.tracker_noise: {uniform: [0, 1.0e-5]}"),
     "plants.sensors.tracker_noise", "the scene's sensors.antenna is none: no sensor on the antenna"),
    (("max_saturation: 0.0", "max_saturation: 0.0\nset: {sensors.star_tracker_outage: [0, 1.0e9]}"),
     "plants.sensors.star_tracker_noise", "covers the whole run"),
    # (pass 112) joint pointing with the profile's feed-forward: the truth objective never reads the estimate
    (("max_saturation: 0.0", "max_saturation: 0.0\n"
      "controller_set: {pointing.mode: joint, pointing.accel_feedforward: profile}"),
     "plants.sensors.star_tracker_noise", "the attitude estimate reaches no command"),
    # the closed loop checks no invariant: a plant's tolerance acts on nothing
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "sim.momentum_tol: {choice: [0.0, 1.0e-300]}"),
     "plants.sim.momentum_tol", "not read by the tuned loop (the closed loop checks no invariant"),
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "sim.energy_tol: {choice: [0.0, 1.0e-300]}"),
     "plants.sim.energy_tol", "not read by the tuned loop (the closed loop checks no invariant"),
    # every sensor noise 0: nothing random to seed
    (("sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}", "sensors.seed: {choice: [1, 2]}"),
     "plants.sensors.seed", "nothing random to seed"),
    # joint 2's own eccentricity set equal to the shared one (the scene's values leave it out): it counts
    (("plants:\n  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}",
      "set: {initial.ecc2: [0.0, 0.0]}\nplants:\n  initial.ecc: {disk: {radius: 1.0e-4}}"),
     "plants.initial.ecc", "overridden by initial.ecc2"),
    # a gain whose switch is tuned too, over values none of which reads it
    (("elevation.kd: {uniform: [300, 3000]}", "azimuth.aw_gain: {uniform: [1, 30]}\n  "
      "control.anti_windup: {choice: [none, clamping]}"), "gains.azimuth.aw_gain",
     "for every value of controller.control.anti_windup the study gives"),
    # the plant gives no contact.clearance (journal_radius instead): a disk within it has no radius
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}\n  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}",
      "initial.ecc: {disk: {within: contact.clearance}}\nset: {contact.journal_radius: 9.0e-3}"),
     "plants.initial.ecc", "not dispersed"),
    # (pass 102) one quantity in two places, as a sweep refuses it: the set value was recorded and never acted
    (("max_saturation: 0.0", "max_saturation: 0.0\nset: {contact.journal_radius: 9.0e-3}"),
     "plants.contact.clearance", "the same quantity as set.contact.journal_radius: give it in one place"),
    (("contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "contact.clearance: {uniform: [1.0e-4, 8.0e-4]}\n  "
      "contact.journal_radius: {uniform: [9.2e-3, 9.9e-3]}"),
     "plants.contact.journal_radius", "the same quantity as plants.contact.clearance: give it in one place"),
])
def test_tuning_spec_values_that_crashed_are_refused_before_anything_runs(change, key, why, tmp_path):
    (tmp_path / "t.yaml").write_text(SPEC.replace(*change))
    p = tune(tmp_path / "t.yaml", tmp_path / "o", "--workers", "1")
    assert p.returncode == 2 and f"key '{key}'" in p.stderr and why in p.stderr and "t.yaml:" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "o").exists()


def test_a_duration_that_ends_before_the_score_window_is_refused_at_its_line(tmp_path):
    # Every trial would score a max over no tick: refused at the spec's line, nothing run.
    (tmp_path / "t.yaml").write_text(SPEC.replace("duration: 3.7", "duration: 2.0"))
    p = tune(tmp_path / "t.yaml", tmp_path / "o", "--workers", "1")
    line = SPEC.splitlines().index("duration: 3.7") + 1
    assert p.returncode == 2, p.stderr
    assert f"t.yaml:{line}:" in p.stderr and "key 'duration'" in p.stderr, p.stderr
    assert "track window [3.5, inf) s of objective.metric max_track" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()


def test_the_built_in_controller_is_named_default_as_in_a_sweep(tmp_path):
    from gimbalsim._tune_spec import TuneSpec
    (tmp_path / "t.yaml").write_text(SPEC.replace(f"controller: {CONTROLLER_CONFIG}", "controller: default"))
    spec = TuneSpec(tmp_path / "t.yaml")
    assert spec.controller_path is None  # it was refused as a file named "default"
    assert spec.controller.values() == gimbalsim.Controller(None, {}).values()


def test_a_link_under_the_study_file_is_refused_before_any_trial(tmp_path):
    (tmp_path / "t.yaml").write_text(SPEC)
    out = tmp_path / "o"
    out.mkdir()
    (out / "study.db").symlink_to(tmp_path / "victim.db")  # the study was written through it
    p = tune(tmp_path / "t.yaml", out, "--workers", "1")
    assert p.returncode == 2 and "a symbolic link" in p.stderr and "study.db" in p.stderr, p.stderr
    assert not (tmp_path / "victim.db").exists()


def test_an_empty_out_or_a_sweeps_folder_is_refused(tmp_path):
    (tmp_path / "t.yaml").write_text(SPEC)
    p = tune(tmp_path / "t.yaml", "", "--workers", "1")  # the whole study went into the current folder
    assert p.returncode == 2 and "argument --out: an empty path" in p.stderr, p.stderr
    (tmp_path / "sweep").mkdir()
    (tmp_path / "sweep" / "results.csv").write_text("sample\n")
    (tmp_path / "sweep" / "summary.json").write_text("{}")
    p = tune(tmp_path / "t.yaml", tmp_path / "sweep", "--workers", "1")
    assert p.returncode == 2 and "holds a sweep" in p.stderr, p.stderr
    assert (tmp_path / "sweep" / "summary.json").read_text() == "{}"



def test_a_plant_keeps_the_joints_own_key_set_equal_to_the_shared_one(tmp_path):
    # as a trial's task loads a plant (tune.run_plants: base.replace of its draw): joint 1 reads the drawn
    # initial.ecc, joint 2 keeps its set initial.ecc2 (equal to the shared one, so the scene's values leave it out)
    from gimbalsim.tune import TuneSpec
    (tmp_path / "t.yaml").write_text(SPEC.replace(
        "plants:\n  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}",
        "set: {structure.joint1: planar, initial.ecc2: [0.0, 0.0]}\nplants:\n  initial.ecc: {disk: {radius: 1.0e-4}}"))
    spec = TuneSpec(tmp_path / "t.yaml")
    draw = spec.plants.draw(0)
    values = spec.base.replace(draw).values()
    assert values["initial.ecc2"] == "[0, 0]", values
    assert [float(x) for x in values["initial.ecc"].strip("[]").split(",")] == list(draw["initial.ecc"])


# set: and controller_set: keys the tuned loop never reads, refused at their line as the same key dispersed
# (set: sim.duration was silently overridden by the tuner's duration:, every plant ran that long)
IDLE_SETS = [
    ("set: {sim.duration: 2.0}", "set.sim.duration", "not read by the tuned loop (every closed loop of a study "
     "runs one length: a sweep's set: sim.duration, a tuner's duration:): the value given would be recorded"),
    ("set: {torque.tau1: 2.0}", "set.torque.tau1", "not read by the tuned loop (the controller commands the torque)"),
    ("set: {sim.momentum_tol: 1.0e-3}", "set.sim.momentum_tol", "(the closed loop checks no invariant"),
    ("controller_set: {pointing.accel_feedforward: profile, plant.base_mass: 500}", "controller_set.plant.base_mass",
     "not read by the tuned loop (the controller reads it only with pointing.accel_feedforward model; it has "
     "pointing.accel_feedforward profile)"),
]


@pytest.mark.parametrize("line,key,why", IDLE_SETS)
def test_a_set_key_the_tuned_loop_never_reads_is_refused_at_its_line(line, key, why, tmp_path):
    from gimbalsim.tune import SpecError, TuneSpec
    text = SPEC.replace("max_saturation: 0.0", "max_saturation: 0.0\n" + line)
    (tmp_path / "t.yaml").write_text(text)
    with pytest.raises(SpecError) as e:
        TuneSpec(tmp_path / "t.yaml")
    assert e.value.key == key and why in str(e.value), str(e.value)
    assert e.value.line == text.split("\n").index(line) + 1, str(e.value)


def test_set_keys_the_tuned_loop_reads_are_taken(tmp_path):
    from gimbalsim.tune import TuneSpec
    (tmp_path / "t.yaml").write_text(SPEC.replace("max_saturation: 0.0", "max_saturation: 0.0\nset: {friction.mu: "
                                                  "0.2}\ncontroller_set: {azimuth.ki: 10.0}"))
    assert TuneSpec(tmp_path / "t.yaml").controller_set == {"azimuth.ki": 10.0}


OLD_SPELLINGS = f"""
scene: {SCENES}/paper_both_planar.yaml
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.05, profile.hold_time: 0.02}}
duration: 0.1
trials: 1
seed: 1
batch: 1
max_saturation: 0.5
set: {{contact1.clearance: 2.0e-4}}
gains:
  azimuth.kp: {{loguniform: [500, 80000]}}
plants:
  friction1.mu: {{uniform: [0.15, 0.15]}}
"""


def test_plants_and_set_take_a_keys_old_spelling_as_the_sweep_does(tmp_path):
    # (docs/python.md: the tuner's plants are scene keys in the sweep's syntax, which reads either spelling)
    # friction1.mu under plants and contact1.clearance under set were "not a key of the scene", exit 2
    new = OLD_SPELLINGS.replace("contact1.", "joint1.contact.").replace("friction1.", "joint1.friction.")
    for name, text in (("old", OLD_SPELLINGS), ("new", new)):
        (tmp_path / f"{name}.yaml").write_text(text)
        p = tune(tmp_path / f"{name}.yaml", tmp_path / name, "--workers", "1")
        assert p.returncode == 0, p.stderr
    from gimbalsim.tune import TuneSpec
    old_spec = TuneSpec(tmp_path / "old.yaml")
    values = old_spec.base.replace(old_spec.plants.draw(0)).values()
    clearance = float(values["contact.bearing_radius"]) - float(values["joint1.contact.journal_radius"])
    assert clearance == pytest.approx(2.0e-4, rel=1e-9) and float(values["joint1.friction.mu"]) == 0.15
    assert values == TuneSpec(tmp_path / "new.yaml").base.replace({"joint1.friction.mu": 0.15}).values()
    with open(tmp_path / "old" / "trials.csv") as f, open(tmp_path / "new" / "trials.csv") as g:
        old_rows, new_rows = list(csv.DictReader(f)), list(csv.DictReader(g))
    assert [r["score"] for r in old_rows] == [r["score"] for r in new_rows] and old_rows[0]["plant0_status"] == "ok"


def test_plants_refuse_one_key_in_two_spellings(tmp_path):
    from gimbalsim.tune import SpecError, TuneSpec
    (tmp_path / "t.yaml").write_text(OLD_SPELLINGS + "  joint1.friction.mu: {uniform: [0.1, 0.2]}\n")
    with pytest.raises(SpecError) as e:
        TuneSpec(tmp_path / "t.yaml")
    assert e.value.key == "plants.joint1.friction.mu" and "the same key as plants.friction1.mu" in str(e.value)


@pytest.mark.parametrize("set_key,plant_key", [("joint1.contact.journal_radius: 0.0098", "contact1.clearance"),
                                               ("friction1.mu: 0.2", "joint1.friction.mu"),
                                               ("joint1.contact.clearance: 2.0e-4", "contact1.clearance")])
def test_one_quantity_under_set_and_plants_in_two_spellings_is_refused(set_key, plant_key, tmp_path):
    # (pass 102) the sweep refused these pairs, the tuner ran them: the set value recorded, the plants' acting
    lo, hi = ("0.1", "0.3") if "mu" in plant_key else ("1.0e-4", "3.0e-4")
    spec = SPEC.replace("paper_clearance.yaml", "paper_both_planar.yaml").replace(
        "  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", f"  {plant_key}: {{uniform: [{lo}, {hi}]}}") + \
        f"set: {{{set_key}}}\n"
    (tmp_path / "t.yaml").write_text(spec)
    p = tune(tmp_path / "t.yaml", tmp_path / "o", "--workers", "1")
    assert p.returncode == 2 and f"key 'plants.{plant_key}'" in p.stderr, p.stderr
    assert "give it in one place" in p.stderr and not (tmp_path / "o").exists(), p.stderr
