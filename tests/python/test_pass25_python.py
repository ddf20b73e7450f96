"""Issue 41, "Hostile and careless input" (pass 25), class 3: keys a
study's closed loop never reads are refused at their line. The estimator's
gains act from the second star tracker sample on (the first sets the
estimate); the play offset's rate only once a boresight tracker sample has
measured it; the fault monitor's stale counts never (a study's loop answers
every status at once and injects no fault). A window that ends past
sim.duration holds the run's last tick, whose estimate knowledge reads.
Each refusal is checked against the runs themselves."""
import numpy as np
import pytest

import gimbalsim
from conftest import scene_path
from test_pass16_outputs import tool, write_spec
from test_pass18_python import check

SPEC = """scene: {scene}
set: {{{set}}}
controller: default
controller_set: {{profile.slew_start: 0.05, profile.slew_time: 0.2, profile.hold_time: 0.1}}
samples: 2
seed: 1
parameters:
  sensors.gyro_bias: {{ball: {{radius: 1.0e-5}}}}
{extra}
phases: {phases}
indices: {{ape: {{}}, knowledge: {{}}}}
"""


def _spec(tmp_path, settings, extra, phases="[slew, hold, track]", scene="paper_ideal"):
    return write_spec(tmp_path, SPEC.format(scene=scene_path(scene), set=settings, extra=extra, phases=phases))


# (set:, refused): the star tracker at 1 Hz in 0.9 s delivers sample 0 alone; at 2 Hz also the one at 0.5 s;
# an outage [0, 0.45] leaves the one at 0.5 s alone; in 0.7 s, a latency past 0.2 s carries it past the last tick
GAINS = [("sim.duration: 0.9, sensors.star_tracker_rate: 1", True),
         ("sim.duration: 0.9, sensors.star_tracker_rate: 2", False),
         ("sim.duration: 0.9, sensors.star_tracker_rate: 2, sensors.star_tracker_outage: [0.0, 0.45]", True),
         ("sim.duration: 0.7, sensors.star_tracker_rate: 2, sensors.star_tracker_latency: 0.2", False),
         ("sim.duration: 0.7, sensors.star_tracker_rate: 2, sensors.star_tracker_latency: 0.201", True)]


@pytest.mark.parametrize("settings,refused", GAINS, ids=[str(i) for i in range(len(GAINS))])
def test_the_estimators_gains_need_a_second_star_sample(tmp_path, settings, refused):
    extra = "grid:\n  controller.estimator.k_p: [0.05, 50]\n  controller.estimator.k_i: [0.0, 40]"
    p = check(_spec(tmp_path, settings + ", sensors.star_tracker_noise: 1.0e-5", extra), tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'grid.controller.estimator.k_p'" in p.stderr and "at most one star tracker sample" in p.stderr


def _truth_and_estimate(settings, controller):
    scene = gimbalsim.load_scene(scene_path("paper_ideal"), {"sensors.star_tracker_noise": 1.0e-5, **settings})
    ctrl = gimbalsim.Controller(None, {"profile.slew_start": 0.05, "profile.slew_time": 0.2,
                                       "profile.hold_time": 0.1, **controller})
    c = gimbalsim.closed_loop(scene, ctrl, settings["sim.duration"]).columns
    return np.column_stack([c[k] for k in ("los_error_x", "los_error_y", "los_error_z", "los_error_est_x",
                                           "los_error_est_y", "los_error_est_z")])


@pytest.mark.parametrize("rate,same", [(1.0, True), (2.0, False)])
def test_the_gains_refused_change_nothing_and_those_accepted_do(rate, same):
    settings = {"sim.duration": 0.9, "sensors.star_tracker_rate": rate}
    low, high = (_truth_and_estimate(settings, {"estimator.k_p": kp, "estimator.k_i": ki})
                 for kp, ki in ((0.05, 0.0), (50.0, 40.0)))
    assert np.array_equal(low, high) is same


TRACKER = "sim.duration: 0.5, sensors.antenna: tracker_gyro, sensors.tracker_bias: [1.0e-4, 0.0]"


# (pass 26) at 2 Hz with the outage to 0.01 s, the only sample that acts falls on the last tick, whose
# estimate knowledge reads but whose command (all the offset's rate shapes there) is never applied
@pytest.mark.parametrize("outage,refused", [(", sensors.tracker_outage: [0, 1.0e9]", True), ("", False),
                                            (", sensors.tracker_rate: 2, sensors.tracker_outage: [0, 0.01]", True)])
def test_the_play_offsets_rate_needs_a_boresight_tracker_sample(tmp_path, outage, refused):
    p = check(_spec(tmp_path, TRACKER + outage, "grid:\n  controller.antenna.offset_rate: [0.05, 10.0]"),
              tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'grid.controller.antenna.offset_rate'" in p.stderr and "no boresight tracker sample" in p.stderr


@pytest.mark.parametrize("key", ["monitor.stale_ticks", "monitor.hold_ticks"])
def test_the_monitors_stale_counts_are_refused_in_a_study(tmp_path, key):
    p = check(_spec(tmp_path, "sim.duration: 0.5", f"grid:\n  controller.{key}: [1, 100000]"), tmp_path / "out")
    assert p.returncode == 2 and f"key 'grid.controller.{key}'" in p.stderr and "no status is stale" in p.stderr


def test_a_tuner_refuses_a_stale_count_among_its_gains(tmp_path):
    text = f"""scene: {scene_path("paper_ideal")}
controller: default
controller_set: {{profile.slew_start: 0.05, profile.slew_time: 0.2, profile.hold_time: 0.1}}
duration: 0.5
trials: 3
parallel_trials: 1
seed: 1
batch: 2
max_saturation: 1.0
objective: {{metric: max_track, percentile: 99}}
gains:
  monitor.stale_ticks: {{choice: [1, 40, 1000]}}
"""
    p = tool("tune", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and "key 'gains.monitor.stale_ticks'" in p.stderr, p.stderr


def test_the_stale_counts_change_nothing_in_a_studys_loop():
    settings = {"sim.duration": 0.5}
    runs = [_truth_and_estimate(settings, {"monitor.stale_ticks": s, "monitor.hold_ticks": h})
            for s, h in ((1, 0), (100000, 200))]
    assert np.array_equal(*runs)


# 2 Hz, outage to 0.45 s: the sample at 0.5 s is taken and delivered at the run's last tick
@pytest.mark.parametrize("window,refused", [("[0.35, 0.5]", True), ("[0.35, 0.500000001]", False)])
def test_a_window_past_the_runs_end_holds_its_last_tick(tmp_path, window, refused):
    text = _spec(tmp_path, "sim.duration: 0.5, sensors.star_tracker_rate: 2, sensors.star_tracker_outage: [0, 0.45]",
                 "  sensors.star_tracker_noise: {choice: [1.0e-5, 1.0e-3]}",
                 phases=f"[slew, hold, {{tail: {window}}}]")
    p = check(text, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'parameters.sensors.star_tracker_noise'" in p.stderr, p.stderr
