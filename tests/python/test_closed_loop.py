"""Controller and closed_loop: the same numbers as the C++ in-process closed
loop (gimbalsim_pointing_study writes its truth pointing error per tick), and
configurations refused as the controller process refuses them."""
import csv
import pickle
import subprocess

import numpy as np
import pytest

import gimbalsim
from conftest import BIN, CONTROLLER_CONFIG, SOURCE, scene_path


def test_closed_loop_equals_the_cpp_closed_loop(tmp):
    duration, c = 1.2, 2.5e-4
    out = tmp / "study"
    out.mkdir()  # an output folder given is never created by the program
    p = subprocess.run([str(BIN / "gimbalsim_pointing_study"), "--config", str(CONTROLLER_CONFIG),
                        "--ideal-scene", str(scene_path("paper_ideal")),
                        "--clearance-scene", str(scene_path("paper_clearance")),
                        "--clearances", str(c), "--duration", str(duration), "--out", str(out)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    with open(out / "pointing_error.csv") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG)
    runs = {header[1]: gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal")), ctrl, duration),
            header[2]: gimbalsim.closed_loop(
                gimbalsim.load_scene(scene_path("paper_clearance"), {"contact.clearance": c}), ctrl, duration)}
    for j, label in enumerate(header[1:], start=1):
        run = runs[label]
        assert run.ok
        assert len(run.columns["truth_error"]) == len(body)
        assert ["%.9g" % x for x in run.columns["truth_error"]] == ["%.9g" % float(r[j]) for r in body]
    clearance = runs[header[2]].columns["truth_error"]
    assert clearance.max() > runs[header[1]].columns["truth_error"].max()  # the clearance costs pointing


def test_a_figure_over_a_window_the_run_did_not_reach_is_nan_with_its_reason():
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG)
    assert ctrl.windows == {"slew": (0.5, 2.5), "hold": (2.5, 3.5), "track": (3.5, float("inf"))}
    s = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal")), ctrl, 3.0).summary
    assert s["ok"]  # the run is ok; its missing figures are marked
    why = "track window [3.5, inf) s not reached: run ended at 3 s"
    for k in ("max_truth_error_track_rad", "rms_truth_error_track_rad", "max_joint_error_track_rad",
              "controller_limited_track_ticks"):  # (pass 42) the count over the window was a bare 0
        assert np.isnan(s[k]) and s["reasons"][k] == why, (k, s[k], s["reasons"])
    assert np.isnan(s["max_truth_error_hold_end_rad"]) and np.isnan(s["settle_time_s"])
    assert "end of the hold window [2.5, 3.5) s" in s["reasons"]["settle_time_s"]
    assert s["max_joint_error_hold_rad"] > 0.0 and "max_joint_error_hold_rad" not in s["reasons"]
    reached = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal")), ctrl, 3.6).summary
    assert reached["reasons"] == {} and reached["controller_limited_track_ticks"] == 0


def test_controller_values_overrides_pickle_and_refusals():
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG, {"azimuth.kp": 1234.5})
    v = ctrl.values()
    assert v["azimuth.kp"] == 1234.5 and ctrl.path == str(CONTROLLER_CONFIG)
    back = pickle.loads(pickle.dumps(ctrl))
    assert back.values() == v
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.Controller(CONTROLLER_CONFIG, {"azimuth.kp": -1, "control.nonsense": 1})
    assert set(e.value.keys) == {"azimuth.kp", "control.nonsense"}
    p = subprocess.run([str(BIN / "pointing_controller"), str(CONTROLLER_CONFIG), "--set",
                        "azimuth.kp=-1", "--set", "control.nonsense=1", "--print-config"],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2
    # the same problems, an override named as its dict entry rather than "--set #k"
    labels = {"azimuth.kp": ("--set #1 'azimuth.kp=-1'", "overrides['azimuth.kp'] (azimuth.kp=-1)"),
              "control.nonsense": ("--set #2 'control.nonsense=1'",
                                   "overrides['control.nonsense'] (control.nonsense=1)")}
    for prob in e.value.problems:
        cli, python = labels[prob["key"]]
        assert prob["text"].startswith(python) and prob["text"].replace(python, cli, 1) in p.stderr, prob
    keys = {k["key"] for k in gimbalsim.controller_keys()}
    assert {"azimuth.kp", "control.period", "pointing.mode"} <= keys


def test_update_is_the_law_with_memory():
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG, {"pointing.mode": "joint"})
    a = ctrl.update(0.0, 0.0, 0.0)
    b = ctrl.update(1.0e-3, 0.01, 0.0)
    assert a["tau"] != b["tau"]
    ctrl.reset()
    assert ctrl.update(0.0, 0.0, 0.0)["tau"] == a["tau"]


def test_closed_loop_takes_a_fault_schedule(tmp):
    scene = gimbalsim.load_scene(scene_path("paper_clearance"))
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG)
    clean = gimbalsim.closed_loop(scene, ctrl, 2.0)
    faulty = gimbalsim.closed_loop(scene, ctrl, 2.0, faults=SOURCE / "tools" / "faults" / "demo.yaml")
    assert not clean.columns["injected_faults"].any()
    assert faulty.columns["injected_faults"].any()
    assert not np.array_equal(clean.columns["truth_error"], faulty.columns["truth_error"])
    (tmp / "bad.yaml").write_text("faults:\n  - {type: encoder_stuck, axis: 7, start: 0.1}\n")
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.closed_loop(scene, ctrl, 1.0, faults=tmp / "bad.yaml")
    assert "bad.yaml:2:" in str(e.value) and "axis" in str(e.value)
    # (pass 73) a schedule acting only after the run ran silently, ok, recorded with its faults
    (tmp / "late.yaml").write_text("faults:\n  - {type: encoder_bias, axis: azimuth, start: 50.0, end: 60.0, "
                                   "bias: 1.0e-2}\n  - {type: encoder_dropout, axis: elevation, start: 1.5}\n")
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.closed_loop(scene, ctrl, 1.0, faults=tmp / "late.yaml")
    assert ("late.yaml:3:5: fault #2 (encoder_dropout), the first to start: key 'start': 1.5 s is at or after the "
            "run's end at 1 s: every fault starts there or later, the schedule would act in no step") in str(e.value), \
        str(e.value)
    assert gimbalsim.closed_loop(scene, ctrl, 2.0, faults=tmp / "late.yaml").columns["injected_faults"].any()
    # (pass 84) a fault from the run's last tick on took no step, flagged as injected all the same
    with pytest.raises(gimbalsim.SceneError, match="key 'start': 1.5 s is at or after the run's end at 1.5 s"):
        gimbalsim.closed_loop(scene, ctrl, 1.5, faults=tmp / "late.yaml")
    assert gimbalsim.closed_loop(scene, ctrl, 1.501, faults=tmp / "late.yaml").columns["injected_faults"].any()
    # (pass 86) and so did one starting inside the last period: its first tick is the run's last
    (tmp / "last.yaml").write_text("faults:\n  - {type: encoder_bias, axis: azimuth, start: 1.4995, bias: 1.0e-2}\n")
    with pytest.raises(gimbalsim.SceneError, match=r"key 'start': 1.4995 s: its first tick is the run's last, at 1.5 s "
                                                   r"\(one every 0.001 s\), which ends the run and takes no step"):
        gimbalsim.closed_loop(scene, ctrl, 1.5, faults=tmp / "last.yaml")
    assert gimbalsim.closed_loop(scene, ctrl, 1.501, faults=tmp / "last.yaml").columns["injected_faults"].any()
    # (pass 87) a star tracker outage between two of its 10 Hz samples dropped none, flagged as injected
    (tmp / "gap.yaml").write_text("faults:\n  - {type: star_tracker_outage, start: 0.11, end: 0.19}\n")
    with pytest.raises(gimbalsim.SceneError, match=r"\[0.11, 0.19\) s takes and delivers no star tracker sample "
                                                   r"\(one every 0.1 s"):
        gimbalsim.closed_loop(scene, ctrl, 0.3, faults=tmp / "gap.yaml")
    (tmp / "gap.yaml").write_text("faults:\n  - {type: star_tracker_outage, start: 0.09, end: 0.11}\n")
    assert gimbalsim.closed_loop(scene, ctrl, 0.3, faults=tmp / "gap.yaml").columns["injected_faults"].any()


@pytest.mark.parametrize("overrides,named", [
    ({"structure.base": "fixed", "sensors.star_tracker_outage": [0.25, 0.55]}, "on a fixed base"),
    ({"sensors.star_tracker_outage": [0.21, 0.29]}, r"\[0.21, 0.29\] s takes and delivers no star tracker sample"),
    ({"sensors.tracker_outage": [0.2, 0.3]}, "the run has no antenna sensor"),
    # (pass 97) and the boresight tracker's between two of its samples (100 Hz: 0.01 and 0.02 s)
    ({"sensors.antenna": "tracker_gyro", "sensors.tracker_rate": 100, "sensors.tracker_outage": [0.011, 0.019]},
     r"\[0.011, 0.019\] s takes and delivers no boresight tracker sample")])
def test_closed_loop_refuses_an_outage_of_the_scene_that_acts_on_nothing(overrides, named):
    # (pass 94) the scene's own outage ran silently where firmware_sim refuses the same --set (and the same window
    # as a fault, above): a fixed base with perfect sensors, a window between two samples, a tracker the run lacks
    scene = gimbalsim.load_scene(scene_path("paper_clearance"), overrides)
    with pytest.raises(gimbalsim.SceneError, match=rf"key 'sensors.(star_)?tracker_outage': .*{named}.* \(firmware_sim "
                                                   r"refuses it as a --set\)"):
        gimbalsim.closed_loop(scene, gimbalsim.Controller(None), 1.0)
    acting = gimbalsim.load_scene(scene_path("paper_clearance"), {"sensors.star_tracker_outage": [0.21, 0.31]})
    assert gimbalsim.closed_loop(acting, gimbalsim.Controller(None), 1.0).columns["star_outage"].any()


def test_closed_loop_takes_an_outage_whose_one_sample_is_at_the_last_tick(tmp):
    # (pass 116) an outage running past the run's end whose one sample (1 Hz) is at the last tick was refused as
    # changing nothing but its flag: in process the last row records the estimate that sample moves
    base = {"sensors.star_tracker_rate": 1.0, "sensors.star_tracker_noise": 1e-4}
    ctrl = gimbalsim.Controller(None)
    free = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_clearance"), base), ctrl, 1.0)
    out = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_clearance"),
                                                     {**base, "sensors.star_tracker_outage": [0.5, 1.5]}), ctrl, 1.0)
    assert out.columns["attitude_error"][-1] != free.columns["attitude_error"][-1]
    assert out.columns["attitude_error"][-2] == free.columns["attitude_error"][-2]
    (tmp / "late.yaml").write_text("faults:\n  - {type: star_tracker_outage, start: 0.5, end: 2.0}\n")
    scene = gimbalsim.load_scene(scene_path("paper_clearance"), base)
    assert gimbalsim.closed_loop(scene, ctrl, 1.0, faults=tmp / "late.yaml").columns["injected_faults"].any()


def test_closed_loop_run_to_csv_follows_the_convention_and_the_output_rules(tmp):
    from test_csv_convention import check_convention

    run = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal")), gimbalsim.Controller(None), 0.05)
    out = tmp / "ticks.csv"
    run.to_csv(out)
    check_convention(out)
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert len(data) == len(run.columns["t"]) == run.rows.shape[0]
    assert np.array_equal(data["t_s"], run.columns["t"])
    assert np.array_equal(data["tau1_cmd_Nm"], run.columns["tau1_cmd"])
    assert np.array_equal(data["truth_error_rad"], run.columns["truth_error"])
    with pytest.raises(OSError, match="does not exist"):
        run.to_csv(tmp / "missing" / "ticks.csv")
    with pytest.raises(OSError, match="folder"):
        run.to_csv(tmp)


def test_closed_loop_run_to_csv_never_writes_over_what_the_run_read(tmp):
    import shutil
    scene, ctrl, faults = tmp / "scene.yaml", tmp / "ctrl.yaml", tmp / "faults.yaml"
    shutil.copy(scene_path("paper_ideal"), scene)
    shutil.copy(CONTROLLER_CONFIG, ctrl)
    faults.write_text("faults: []\n")
    kept = {p: p.read_bytes() for p in (scene, ctrl, faults)}
    run = gimbalsim.closed_loop(gimbalsim.load_scene(scene), gimbalsim.Controller(ctrl), 0.01, faults=faults)
    for p in kept:  # the run's own inputs, without inputs= (by any spelling)
        with pytest.raises(gimbalsim.OutputError, match="the same file as the input"):
            run.to_csv(tmp / "." / p.name)
    other = tmp / "other.yaml"
    other.write_text("keep\n")
    with pytest.raises(gimbalsim.OutputError, match="the same file as the input"):
        run.to_csv(other, inputs=str(other))  # one path as a string, not its characters
    assert {p: p.read_bytes() for p in kept} == kept and other.read_text() == "keep\n"
    run.to_csv(tmp / "ticks.csv", inputs=str(other))  # another name is written
    assert (tmp / "ticks.csv").read_text().count("\n") == len(run.columns["t"]) + 1


def test_a_bearing_tighter_than_its_load_presses_in_stops_saying_why():
    # 10 um of play in paper_spatial2: the azimuth torque's couple presses an
    # end in deeper than the play (docs/MODEL.md 2.7), within 0.7 s.
    scene = gimbalsim.load_scene(scene_path("paper_spatial2"), {"contact.clearance": 1e-5})
    run = gimbalsim.closed_loop(scene, gimbalsim.Controller(CONTROLLER_CONFIG), duration=2.0)
    s = run.summary
    assert not s["ok"] and s["stop_key"] == "sim.penetration_limit" and s["t_end_s"] < 2.0
    assert "in joint 2's bearing, clearance 1e-05 m" in s["error"], s["error"]
    assert 'docs/MODEL.md 2.7 "Where the play model holds"' in s["error"]
    model_doc = (SOURCE / "docs" / "MODEL.md").read_text()
    assert "**Where the play model holds.**" in model_doc  # the section the message names
    # With a limit of its own the message says so, and nothing about the default.
    tight = gimbalsim.load_scene(scene_path("paper_spatial2"),
                                 {"contact.clearance": 1e-5, "sim.penetration_limit": 5e-6})
    s = gimbalsim.closed_loop(tight, gimbalsim.Controller(CONTROLLER_CONFIG), duration=2.0).summary
    assert not s["ok"] and "sim.penetration_limit 5e-06 m)" in s["error"] and "MODEL.md" not in s["error"]


def test_the_reference_integrator_refuses_plain_coulomb_at_once():
    scene = gimbalsim.load_scene(scene_path("paper_clearance"), {"sim.duration": 0.2})
    with pytest.raises(ValueError, match="joint 2's bearing has friction.law coulomb"):
        gimbalsim.simulate(scene, integrator="reference")


def test_the_antenna_tracker_is_recorded_only_when_the_scene_has_one():
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG)
    none = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal")), ctrl, 0.2)
    assert none.ok, none.summary["error"]  # the NaN of "no tracker" is no numerical trouble
    assert np.isnan(none.columns["tracker_u"]).all() and np.isnan(none.columns["tracker_v"]).all()
    run = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_spatial2_tracker")), ctrl, 1.0)
    assert run.ok, run.summary["error"]
    size = np.hypot(run.columns["tracker_u"], run.columns["tracker_v"])
    assert run.columns["truth_error"].max() > 1e-4
    assert np.abs(size - run.columns["truth_error"]).max() < 1e-12  # perfect, 1 kHz: the pointing error


@pytest.mark.parametrize("limit,refused", [(60, True), (50, True), (40, False)])
def test_a_torque_limit_fault_at_or_above_the_controllers_own_is_refused(tmp_path, limit, refused):
    # (pass 104) a 60 N m (or 50) motor limit on an axis the controller holds at 50 N m clipped nothing, flagged
    # as injected in 800 ticks
    fault = f"{{type: torque_limit, axis: azimuth, start: 0.1, end: 0.3, limit: {limit}}}"
    (tmp_path / "f.yaml").write_text(f"seed: 1\nfaults:\n  - {fault}\n")
    scene, ctrl = gimbalsim.load_scene(scene_path("paper_clearance")), gimbalsim.Controller()
    if not refused:
        assert gimbalsim.closed_loop(scene, ctrl, 0.4, faults=tmp_path / "f.yaml").summary["ok"]
        return
    with pytest.raises(gimbalsim.SceneError, match="not below the controller's own azimuth.torque_limit") as e:
        gimbalsim.closed_loop(scene, ctrl, 0.4, faults=tmp_path / "f.yaml")
    # (pass 108) at its line and column, as every other fault refusal: the limit's value, after "  - "
    column = len("  - ") + fault.index("limit:") + len("limit: ") + 1
    assert str(e.value).startswith(f"{tmp_path / 'f.yaml'}:3:{column}: fault #1 (torque_limit): key 'limit'"), \
        str(e.value)
