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


# (pass 99) one value that runs as another: inertial in joint mode runs as profile, recorded as inertial
@pytest.mark.parametrize("choice", ["[inertial, model]", "[inertial]"])
def test_a_dispersion_holding_inertial_in_joint_mode_is_refused(tmp_path, choice):
    from gimbalsim.sweep import SpecError, SweepSpec
    with pytest.raises(SpecError) as e:
        SweepSpec(_spec(tmp_path, choice))
    assert e.value.key == f"parameters.{KEY}" and "inertial runs as profile" in str(e.value), str(e.value)


def test_inertial_set_in_joint_mode_is_refused_at_its_line(tmp_path):
    from gimbalsim.sweep import SpecError, SweepSpec
    path = _spec(tmp_path, "[model, profile]")
    text = path.read_text().replace(f"  {KEY}: {{choice: [model, profile]}}",
                                    "  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}")
    path.write_text(text.replace(JOINT, JOINT + " pointing.accel_feedforward: inertial,"))
    with pytest.raises(SpecError) as e:
        SweepSpec(path)
    assert e.value.key == "controller_set.pointing.accel_feedforward", e.value.key
    assert "inertial runs as profile" in str(e.value), str(e.value)


@pytest.mark.parametrize("mode_in_file,where", [(True, "controller"), (False, "controller_set.pointing.mode")])
def test_a_controller_file_holding_inertial_in_joint_mode_is_refused(tmp_path, mode_in_file, where):
    from gimbalsim.sweep import SpecError, SweepSpec
    from test_sweep_closed import CONTROLLER_CONFIG
    config = tmp_path / "c.yaml"
    text = open(CONTROLLER_CONFIG).read().replace("accel_feedforward: model", "accel_feedforward: inertial")
    config.write_text(text.replace("mode: inertial", "mode: joint", 1) if mode_in_file else text)
    path = _spec(tmp_path, "[model, profile]")
    path.write_text(path.read_text().replace(f"controller: {CONTROLLER_CONFIG}", f"controller: {config}")
                    .replace(JOINT, JOINT if not mode_in_file else "controller_set: {profile.slew_start: 0.0,")
                    .replace(f"  {KEY}: {{choice: [model, profile]}}",
                             "  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}"))
    with pytest.raises(SpecError) as e:
        SweepSpec(path)
    assert e.value.key == where and "inertial runs as profile" in str(e.value), str(e.value)


def test_inertial_set_with_the_mode_dispersed_is_taken(tmp_path):
    from gimbalsim.sweep import SweepSpec
    path = _spec(tmp_path, "[model, profile]", "[joint, inertial]")
    text = path.read_text().replace(f"  {KEY}: {{choice: [model, profile]}}\n", "")
    path.write_text(text.replace(JOINT, "controller_set: {pointing.accel_feedforward: inertial, "
                                        "profile.slew_start: 0.0,"))
    s = SweepSpec(path)
    assert {s.design.draw(i)["controller.pointing.mode"] for i in range(6)} == {"joint", "inertial"}


def test_closed_loop_refuses_inertial_in_joint_mode_a_study_runs_it():
    import gimbalsim
    from test_sweep_closed import SCENES
    scene = gimbalsim.load_scene(f"{SCENES}/paper_ideal.yaml")
    joint = gimbalsim.Controller(None, {"pointing.mode": "joint", "pointing.accel_feedforward": "inertial"})
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.closed_loop(scene, joint, 0.01)
    assert "pointing.accel_feedforward inertial runs as profile" in str(e.value), str(e.value)
    assert gimbalsim.closed_loop(scene, joint, 0.01, _study=True).summary["ticks"] > 0
    # (pass 106) named where it was given: the later override (it named the built-in configuration, no field set)
    assert str(e.value).startswith("overrides['pointing.accel_feedforward']: key 'pointing.accel_feedforward': "), \
        str(e.value)
    assert (e.value.problems[0]["key"], e.value.problems[0]["set_index"]) == ("pointing.accel_feedforward", 2)


def test_closed_loop_names_the_controller_files_line_for_inertial_in_joint_mode(tmp_path):
    import gimbalsim
    from test_sweep_closed import SCENES
    config = tmp_path / "c.yaml"
    config.write_text("pointing:\n  mode: joint\n  accel_feedforward: inertial\n")
    with pytest.raises(gimbalsim.SceneError) as e:  # (pass 106) it named the file with no line
        gimbalsim.closed_loop(gimbalsim.load_scene(f"{SCENES}/paper_ideal.yaml"), gimbalsim.Controller(config), 0.01)
    assert str(e.value).startswith(f"{config}:3:3: key 'pointing.accel_feedforward': "), str(e.value)
    assert (e.value.problems[0]["file"], e.value.problems[0]["line"]) == (str(config), 3)


def test_the_tuner_refuses_inertial_in_joint_mode_at_its_line(tmp_path):
    from gimbalsim.tune import SpecError, TuneSpec
    from test_refused_up_front import TUNE, SCENE, spec_file
    from conftest import CONTROLLER_CONFIG
    text = TUNE + "controller_set: {{pointing.mode: joint, pointing.accel_feedforward: inertial}}\n"
    with pytest.raises(SpecError) as e:
        TuneSpec(spec_file(tmp_path / "t.yaml", text, SCENE, CONTROLLER_CONFIG))
    assert e.value.key == "controller_set.pointing.accel_feedforward", e.value.key
    assert "inertial runs as profile" in str(e.value), str(e.value)
