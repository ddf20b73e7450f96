"""The Python API's arguments have the ranges the code honours (issue 41,
classes 4, 6 and 8, fourteenth pass): a torque the plant cannot take, a
step count beyond any integer the plant counts, a controller time beyond
the profile's or running back, an empty output path; and a closed loop that
ran nothing names the key that refused it."""
import math

import pytest

import gimbalsim
from conftest import CONTROLLER_CONFIG, SCENES


def simulator():
    return gimbalsim.Simulator(gimbalsim.load_scene(str(SCENES / "paper_clearance.yaml")))


def test_a_torque_beyond_the_scenes_range_is_refused_not_stepped_into_nan():
    s = simulator()
    with pytest.raises(ValueError, match=r"within \[-1e6, 1e6\] N m .*tau1 = 1e\+300"):
        s.step(1e300, 0.0)
    with pytest.raises(ValueError, match=r"torques row 1 is not finite and within \[-1e6, 1e6\] N m \(0, -2e\+06\)"):
        s.run([[0.0, 0.0], [0.0, -2e6]])
    assert s.t == 0.0  # nothing was stepped
    # The range's end is taken: the plant's own limit stops it, with its reason, never NaN. Which limit is the
    # contact's to say: 1e6 N m drives the journal 0.78 mm into a 0.5 mm bearing (sim.penetration_limit); it hit
    # sim.velocity_limit while a stage entering the bearing took the damping's v0 from no impact (MODEL.md 5.3).
    with pytest.raises(gimbalsim.SimulationStopped, match=r"\(limit: sim\.(penetration|velocity)_limit\)$") as e:
        s.step(1e6, -1e6)
    assert "nan" not in str(e.value).lower() and "non-finite" not in str(e.value), e.value


def test_a_step_count_beyond_any_integer_names_n():
    s = simulator()
    for n in (2**70, -2**70):
        with pytest.raises(ValueError, match=r"n must be in \[0, 2\^40\], got " + str(n)):
            s.step(0.0, 0.0, n=n)
    assert s.t == 0.0


def test_controller_time_has_the_profiles_range_and_runs_forward():
    c = gimbalsim.Controller(str(CONTROLLER_CONFIG))
    for t in (1e300, -1.0, 1e9 * 1.5):
        with pytest.raises(ValueError, match=r"update: t must be in \[0, 1e9\] s"):
            c.update(t, 0.0, 0.0)
    first = c.update(0.5, 0.0, 0.0)["ref"]
    c.update(1.0, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"t = 0.5 s is before the last update's 1 s: .*reset\(\)"):
        c.update(0.5, 0.0, 0.0)
    c.reset()
    assert c.update(0.5, 0.0, 0.0)["ref"] == first  # after a reset the law starts again


def test_an_empty_output_path_is_refused_before_anything_is_written(tmp_path):
    sc = gimbalsim.load_scene(str(SCENES / "paper_clearance.yaml"))
    run = gimbalsim.closed_loop(sc, gimbalsim.Controller(str(CONTROLLER_CONFIG)), duration=0.01)
    with pytest.raises(gimbalsim.OutputError, match="output path is empty"):
        run.to_csv("")


def test_a_closed_loop_that_ran_nothing_names_the_refused_key():
    sc = gimbalsim.load_scene(str(SCENES / "paper_clearance.yaml"))
    c = gimbalsim.Controller(str(CONTROLLER_CONFIG), {"control.period": 0.0007})
    s = gimbalsim.closed_loop(sc, c, duration=0.7).summary
    assert not s["ok"] and s["stop_key"] == "refused:controller.control.period", s
    # the numbers in their shortest round-trip text, and no command-line flag suggested inside a library call
    assert "control period 7e-04 s is not a whole multiple of sim.step = 0.001 s" in s["error"], s["error"]
    assert "--set" not in s["error"], s["error"]
    assert s["ticks"] == 0 and math.isnan(s["max_truth_error_track_rad"])
