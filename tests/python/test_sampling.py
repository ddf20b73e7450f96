"""A closed-loop sweep's stepping (gimbalsim/_sampling.py, docs/python.md
"Sampling"): sampling: auto steps a planar joint 2 with Coulomb friction
with its set-valued law under the adaptive policy, and keeps every figure
the sweep reads within the stated tolerance of a fine run's (a 5 us fixed
sub-step of the scene's own plain Coulomb law, an independent solution); a
spatial joint 2 with coarser fixed sub-steps, the antenna loop's median
figure within the tolerance; it never changes a scene it has no cheaper
accurate setting for, nor one whose stepping the spec gives; sampling:
scene runs the scene as written."""
import json
import math

import pytest

from conftest import SOURCE
from test_pass16_outputs import line_of, tool, write_spec
from gimbalsim import _sampling
from gimbalsim._sample import run_one
from gimbalsim._sweep_spec import SweepSpec

BUDGET = (SOURCE / "tools/sweeps/pointing_budget.yaml").read_text().replace("../scenes/", f"{SOURCE}/tools/scenes/")
FIGURES = ("ape", "rpe", "pde", "knowledge")


def _spec(tmp_path, text, name="spec.yaml"):
    return SweepSpec(write_spec(tmp_path, text, name))


def _figures(auto, fine, unit):
    """[(key, auto's figure, fine's figure)]: the 12 figures of one unit run under both specs' stepping."""
    values = auto.design.draw(unit)
    assert values == fine.design.draw(unit)
    got, ref = run_one(auto.base, auto.closed, values), run_one(fine.base, fine.closed, values)
    assert got["status"] == ref["status"] == "ok", (unit, got, ref)
    keys = [k for k in ref if k.split("_")[0] in FIGURES]
    assert len(keys) == 12 and not any(math.isnan(ref[k]) for k in keys), (unit, ref)
    return [(k, got[k], ref[k]) for k in keys]


# Units of the shipped budget whose figures moved by more than the tolerance at a looser setting
# (substep_tol 1e-7: unit 0's rpe_track by 1.4e-6 rad; 1e-3: unit 5's ape_slew by 2.6e-6 rad). Over its
# first 24 units, 1e-8 to 1e-10 kept every figure within 8.7e-7 rad, the scene's own 2e-5 s within 8.1e-7.
@pytest.mark.parametrize("unit", [0, 1, 5])
def test_auto_keeps_every_figure_within_the_tolerance_of_a_fine_run(tmp_path, unit):
    auto = _spec(tmp_path, BUDGET)
    assert auto.sampling["overrides"], auto.sampling
    fine = _spec(tmp_path, BUDGET.replace("set: {sim.duration: 5.0}", "set: {sim.duration: 5.0, sim.substep: 5.0e-6}"),
                 "fine.yaml")
    assert fine.sampling["overrides"] == {} and fine.base.values()["friction.law"] == "coulomb"
    for k, got, ref in _figures(auto, fine, unit):
        assert abs(got - ref) <= _sampling.TOLERANCE_RAD, (k, got, ref)


TRACKER = (SOURCE / "tools/sweeps/pointing_budget_spatial_tracker.yaml").read_text() \
    .replace("../scenes/", f"{SOURCE}/tools/scenes/")


# At the antenna the spatial budget's figures are defined but no sub-step holds every one to the tolerance:
# its stated tolerance is the median's. Units 0-7 (AMD EPYC VM), figures within 1e-6 rad of the 5 us run's:
# 60 % at 8e-5 s (56 % over the budget's 13308), 47 % at 1.6e-4 s and 42 % at 3.2e-4 s (its median 1.7e-6).
def test_auto_keeps_the_median_antenna_loop_figure_within_the_tolerance_of_a_fine_run(tmp_path):
    auto = _spec(tmp_path, TRACKER)
    assert auto.sampling["overrides"] == {"sim.substep": _sampling.SPATIAL_SUBSTEP_S}, auto.sampling
    fine = _spec(tmp_path, TRACKER.replace("tracker_gyro}", "tracker_gyro, sim.substep: 5.0e-6}"), "fine.yaml")
    assert fine.sampling["overrides"] == {} and fine.base.values()["sim.substep"] == "5e-06"
    distances = [abs(got - ref) for unit in range(8) for _, got, ref in _figures(auto, fine, unit)]
    within = sum(d <= _sampling.TOLERANCE_RAD for d in distances)
    assert within > len(distances) / 2, (within, len(distances), sorted(distances)[len(distances) // 2])


def test_auto_chooses_the_adaptive_set_valued_law_only_for_a_planar_joint_2_with_coulomb(tmp_path):
    auto = _spec(tmp_path, BUDGET).base.values()
    assert (auto["friction.law"], auto["sim.substep_policy"]) == ("coulomb_stick", "adaptive")
    assert float(auto["sim.substep_tol"]) == float(_sampling.ADAPTIVE_TOL)
    # the scene as written, a spec that gives the stepping, an open loop: the scene's own
    for name, text in [("scene", BUDGET + "sampling: scene\n"),
                       ("given", BUDGET.replace("set: {sim.duration: 5.0}", "set: {sim.duration: 5.0, sim.substep: 2.0e-5}")),
                       ("dispersed", BUDGET.replace("parameters:\n", "parameters:\n  friction.law: {choice: [coulomb, ambrosio]}\n"))]:
        spec = _spec(tmp_path, text, f"{name}.yaml")
        assert spec.sampling["overrides"] == {}, name
        values = spec.base.values()
        assert (values["friction.law"], values["sim.substep_policy"], values["sim.substep"]) == \
            ("coulomb", "fixed", "2e-05"), (name, spec.sampling)
    assert _sampling.choose("auto", auto, set(), closed=False)[0] == {}
    # ideal joints: the scene's own 1 ms RK4 step, nothing cheaper judged
    ideal = "\n".join(line for line in BUDGET.replace("paper_clearance.yaml", "paper_ideal.yaml").split("\n")
                      if not line.lstrip().startswith(("contact.", "friction.", "initial.")))
    spec = _spec(tmp_path, ideal, "ideal.yaml")
    assert spec.sampling["overrides"] == {} and "joints ideal/ideal" in spec.sampling["why"], spec.sampling


def test_auto_coarsens_a_spatial_joint_2_on_the_encoders_and_at_the_antenna(tmp_path):
    spatial = BUDGET.replace("paper_clearance.yaml", "paper_spatial2.yaml")
    tracker = spatial.replace("set: {sim.duration: 5.0}", "set: {sim.duration: 5.0, sensors.antenna: tracker_gyro}")
    for name, text in [("encoders", spatial), ("tracker", tracker),
                       ("either", spatial + "grid:\n  sensors.antenna: [none, tracker_gyro]\n")]:
        spec = _spec(tmp_path, text, f"{name}.yaml")
        assert spec.sampling["overrides"] == {"sim.substep": _sampling.SPATIAL_SUBSTEP_S}, (name, spec.sampling)
        assert spec.base.values()["sim.substep"] == "8e-05" and spec.base.values()["friction.law"] == "coulomb"
    # not judged: a bearing in joint 1; a scene finer than asked is not made finer
    for name, text in [("joint1", BUDGET.replace("paper_clearance.yaml", "paper_spatial1.yaml")),
                       # (pass 37) a step finer than the sub-step auto would take: refused as no file's value
                       ("step", spatial.replace("set: {sim.duration: 5.0}",
                                                "set: {sim.duration: 5.0, sim.step: 5.0e-5}")),
                       ("coarse", spatial + "sampling: scene\n")]:
        assert _spec(tmp_path, text, f"{name}.yaml").sampling["overrides"] == {}, name
    coarser = spec.base.values() | {"sim.substep": "1e-4"}
    assert _sampling.choose("auto", coarser, set(), closed=True)[0] == {}


def test_a_spatial_step_the_spec_gives_is_judged_by_its_value(tmp_path):
    # (pass 38) any spec naming sim.step kept the scene's 2e-5 s sub-step, its scene's own 1e-3 s included, and
    # said "no cheaper setting has been judged there": its value decides, and the reason says what decided
    spatial = BUDGET.replace("paper_clearance.yaml", "paper_spatial2.yaml")
    for name, step, overrides, why in [
            ("own", "1.0e-3", {"sim.substep": "8e-05"}, "steps with fixed sub-steps of 8e-05 s"),
            ("coarse", "5.0e-4", {"sim.substep": "8e-05"}, "steps with fixed sub-steps of 8e-05 s"),
            ("fine", "5.0e-5", {}, "its sim.step is finer than the 8e-05 s sub-step")]:
        text = spatial.replace("set: {sim.duration: 5.0}", f"set: {{sim.duration: 5.0, sim.step: {step}}}")
        sampling = _spec(tmp_path, text, f"{name}.yaml").sampling
        assert sampling["overrides"] == overrides and why in sampling["why"], (name, sampling)
    text = spatial + "grid:\n  sim.step: [5.0e-4, 1.0e-3]\n"
    sampling = _spec(tmp_path, text, "grid.yaml").sampling
    assert sampling["overrides"] == {} and "the spec disperses sim.step" in sampling["why"], sampling
    text = spatial.replace("set: {sim.duration: 5.0}",
                           "set: {sim.duration: 5.0, sim.step: 5.0e-5, sensors.antenna: tracker_gyro}")
    sampling = _spec(tmp_path, text, "tracker.yaml").sampling
    assert sampling["overrides"] == {} and "finer than the 8e-05 s sub-step" in sampling["why"], sampling


def test_a_sampling_mode_not_known_is_refused_at_its_line(tmp_path):
    text = BUDGET + "sampling: fast\n"
    spec = write_spec(tmp_path, text)
    p = tool("sweep", spec, tmp_path / "out", "--check")
    assert p.returncode == 2, p.stderr
    assert f"{spec}:{line_of(text, 'sampling:')}:" in p.stderr and "expected auto or scene, got 'fast'" in p.stderr


def test_the_report_and_summary_say_how_the_samples_stepped(tmp_path):
    text = BUDGET.replace("samples: 1109", "samples: 2").replace("set: {sim.duration: 5.0}", "set: {sim.duration: 0.6}") \
        .replace("phases: [slew, hold, track]", "phases: [{late: [0.3, 0.6]}]")
    text = text[:text.index("indices:")] + "indices:\n  ape: {}\n"
    p = tool("sweep", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 0, p.stderr
    summary = json.loads((tmp_path / "out/summary.json").read_text())
    assert summary["sampling"]["mode"] == "auto" and summary["sampling"]["overrides"]["friction.law"] == "coulomb_stick"
    assert "Stepping (sampling: auto): a planar joint 2 with Coulomb friction" in \
        (tmp_path / "out/report.md").read_text()
    assert "sweep: stepping (sampling: auto)" in p.stderr


def test_a_tuners_plants_step_as_a_sweeps_samples(tmp_path):
    from gimbalsim._tune_spec import TuneSpec
    text = (SOURCE / "tools/tuning/clearance_gains.yaml").read_text().replace("../scenes/", f"{SOURCE}/tools/scenes/") \
        .replace("../../controllers/", f"{SOURCE}/controllers/")
    auto = TuneSpec(write_spec(tmp_path, text))
    assert auto.sampling["overrides"].get("friction.law") == "coulomb_stick", auto.sampling
    assert auto.base.values()["sim.substep_policy"] == "adaptive"
    assert TuneSpec(write_spec(tmp_path, text + "sampling: scene\n", "scene.yaml")).sampling["overrides"] == {}
