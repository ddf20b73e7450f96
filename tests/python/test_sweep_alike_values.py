"""A dispersion whose values the configuration makes run alike is refused at
its line (pass 59): under pointing.mode joint the inertial feed-forward takes
the profile's acceleration, so accel_feedforward over inertial and profile
was recorded as a design variable that acted on nothing; with model among
its values it acts, and is taken."""
import pytest

from test_sweep_closed import DURATION, SPEC

JOINT = "controller_set: {pointing.mode: joint, profile.slew_start: 0.0,"
KEY = "controller.pointing.accel_feedforward"


def _spec(tmp_path, choice, mode=None):
    text = SPEC.replace(f"set: {{sim.duration: {DURATION}}}", "set: {sim.duration: 0.5}")
    text = text.replace("controller_set: {profile.slew_start: 0.0,", JOINT)
    text = text.replace("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
                        f"  {KEY}: {{choice: {choice}}}" + (f"\n  controller.pointing.mode: {{choice: {mode}}}"
                                                             if mode else ""))
    path = tmp_path / "s.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("mode", [None, "[joint, joint]"])  # the mode set, or dispersed over joint alone
def test_values_that_run_alike_are_refused_at_their_line(tmp_path, mode):
    from gimbalsim.sweep import SpecError, SweepSpec
    with pytest.raises(SpecError) as e:
        SweepSpec(_spec(tmp_path, "[inertial, profile]", mode))
    assert e.value.key == f"parameters.{KEY}", e.value.key
    assert "every value given runs alike" in str(e.value) and "pointing.mode joint" in str(e.value), str(e.value)


@pytest.mark.parametrize("choice,mode", [("[model, profile]", None), ("[inertial, profile]", "[joint, inertial]")])
def test_values_that_act_are_taken(tmp_path, choice, mode):
    from gimbalsim.sweep import SweepSpec
    s = SweepSpec(_spec(tmp_path, choice, mode))
    assert {s.design.draw(i)[KEY] for i in range(6)} <= {"model", "profile", "inertial"}
