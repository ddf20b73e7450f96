"""Third round of hostile input (issue 41), the Python package: a resume
keeps only rows of the shape the sweep writes (class 2), an unbounded
normal's tails are tried on the scene (class 8), a closed-loop sweep changes
sim.step without a key it never reads (class 7), and the Python API refuses
the empty and odd inputs the command line refuses (class 8)."""

import numpy as np
import pytest

from conftest import SCENES, row_verdict, spec_of

OPEN = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.02}}
samples: 1
seed: 2
parameters:
  contact.clearance: {{uniform: [1.0e-4, 3.0e-4]}}
"""
CLOSED = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.2}}
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.1, profile.hold_time: 0.05}}
samples: 1
seed: 3
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
indices:
  ape: {{}}
"""


@pytest.fixture(scope="module")
def open_row(tmp_path_factory):
    from gimbalsim._sample import sample_alone
    spec = spec_of(tmp_path_factory.mktemp("open"), OPEN)
    return spec, sample_alone(spec, 0)[0]


@pytest.fixture(scope="module")
def closed_row(tmp_path_factory):
    from gimbalsim._sample import sample_alone
    spec = spec_of(tmp_path_factory.mktemp("closed"), CLOSED)
    return spec, sample_alone(spec, 0)[0]


# --- class 2: a resume keeps only rows of the shape the sweep writes ---------------------------------------

@pytest.mark.parametrize("status", ["ideal:ok", "ok|ideal:sim.velocity_limit", "sim.velocity_limit|ideal:ok",
                                    "ideal:ideal:sim.velocity_limit", "ok|ideal:ok"])
def test_resume_drops_an_open_loop_ideal_status_the_sweep_never_writes(open_row, status):
    spec, row = open_row
    assert row_verdict(spec, row) is None  # the row as written is trusted
    nan = {"pointing_error_max_rad": "nan", "pointing_error_final_rad": "nan"}
    assert row_verdict(spec, row, status="ideal:sim.velocity_limit", **nan) is None  # a twin's stop: a shape it writes
    assert row_verdict(spec, row, status="sim.velocity_limit|ideal:sim.max_substeps", **nan) is None
    verdict = row_verdict(spec, row, status=status, **nan)
    assert verdict is not None and verdict.startswith("status is none the sweep writes"), verdict


@pytest.mark.parametrize("index", ["00", "000", "+0", " 0", "0 "])
def test_resume_drops_a_sample_index_not_written_as_the_sweep_writes_it(open_row, closed_row, index):
    for spec, row in (open_row, closed_row):
        assert row_verdict(spec, row) is None
        assert row_verdict(spec, row, sample=index) == "sample index outside the design", (index, spec.closed)


def test_read_journal_drops_a_leading_zero_index(closed_row, tmp_path):
    from gimbalsim._journal import csv_line, read_journal
    spec, row = closed_row
    path = tmp_path / "results.partial.csv"
    path.write_text(",".join(spec.csv_header()) + "\n" + ",".join(["00"] + row[1:]) + "\n")
    done, dropped, _ = read_journal(spec, path, spec.csv_header())
    assert done == {} and dropped == {"sample index outside the design": [2]}, (done, dropped)
    assert csv_line(row)  # the writer's own row is one line


@pytest.mark.parametrize("status,reason", [
    ("stopped", "x"),
    ("refused", "x"),
    ("sim.velocity_limit", "x"),
    ("sim.velocity_limit", "simulation stopped at t = 0.1 s: contact penetration exceeded sim.penetration_limit"),
    ("non_finite", "x"),
    ("non_finite", "simulation stopped at t = 0.1 s: a velocity exceeded sim.velocity_limit (diverging)"),
])
def test_resume_drops_a_closed_loop_stop_the_writer_never_writes(closed_row, status, reason):
    spec, row = closed_row
    assert row_verdict(spec, row) is None
    verdict = row_verdict(spec, row, status=status, reason=reason)
    assert verdict is not None and verdict.startswith(("status is none", "reason is not")), verdict


def test_a_closed_loop_stop_as_the_writer_writes_it_is_kept(closed_row):
    spec, row = closed_row
    limit = "simulation stopped at t = 0.1 s: a velocity exceeded sim.velocity_limit (diverging)"
    assert row_verdict(spec, row, status="sim.velocity_limit", reason=limit) is None
    assert row_verdict(spec, row, status="non_finite", reason="non-finite truth_error at t = 0.1 s (tick 3)") is None
    # after the stop's message, the nan indices and only those
    verdict = row_verdict(spec, row, status="sim.velocity_limit", reason=limit + " | ape_slew: why")
    assert verdict is not None and verdict.startswith("reason is not"), verdict


# --- class 8, the Python API: what the command line refuses is refused here too, naming the argument ------

def test_an_empty_path_is_refused_naming_the_argument():
    import gimbalsim
    scene = gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"sim.duration": 0.01})
    with pytest.raises(ValueError, match="controller configuration path: an empty path"):
        gimbalsim.Controller("")
    with pytest.raises(ValueError, match="fault schedule path: an empty path"):
        gimbalsim.closed_loop(scene, gimbalsim.Controller(), 0.01, faults="")
    with pytest.raises(ValueError, match="scene path: an empty path"):
        gimbalsim.load_scene("")
    assert gimbalsim.Controller(None).period > 0  # None: the defaults, as documented


@pytest.mark.parametrize("torques", [np.array([[1 + 500j, 2.0]]), np.array([["1", "2"]]),
                                     np.array([[True, False]]), [[1.0, None]]])
def test_simulator_run_refuses_torques_that_are_not_real_numbers(torques):
    import warnings
    import gimbalsim
    sim = gimbalsim.Simulator(gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"sim.duration": 0.01}))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's ComplexWarning is no refusal
        with pytest.raises(TypeError, match=r"torques \[N m\]: expected real numbers"):
            sim.run(torques)
    assert sim.t == 0.0  # nothing ran
    assert sim.run(np.array([[1.0, 2.0]])).shape == (1, len(gimbalsim.COLUMNS))  # real numbers still run


@pytest.mark.parametrize("args,name", [((1 + 500j, 2.0), "tau1"), ((1.0, "2"), "tau2"), ((True, 2.0), "tau1")])
def test_simulator_step_names_the_argument_it_refuses(args, name):
    import gimbalsim
    sim = gimbalsim.Simulator(gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"sim.duration": 0.01}))
    with pytest.raises(TypeError, match=rf"^{name} \[N m\]: expected a real number"):
        sim.step(*args)
    sim.step(1.0, np.float64(2.0), 2)
    assert sim.t == pytest.approx(2 * sim.step_size)


def test_indices_refuse_complex_bool_and_text_inputs():
    from gimbalsim import indices as ix
    t = np.arange(10) * 0.1
    e = np.full(10, 1e-4)
    assert ix.ape(t, e, 0.1, 0.5).value == pytest.approx(1e-4)
    for call, name in [(lambda: ix.ape(t, 1e-4j * np.ones(10), 0.1, 0.5), "e"),
                       (lambda: ix.ape(np.array([False, True]), np.ones(2), 0.0, 1.0), "t_s"),
                       (lambda: ix.ape(t.astype(str), e, 0.1, 0.5), "t_s"),
                       (lambda: ix.knowledge(t, e + 0j, e, 0.1, 0.5), "e_estimate"),
                       (lambda: ix.knowledge(t, e, [str(v) for v in e], 0.1, 0.5), "e_truth"),
                       (lambda: ix.rpe(t, e, 0.1, 0.5, 0.2 + 0j), "RPE window"),
                       (lambda: ix.pde(t, e, 0.0, 1.0, 0.2, True), "PDE separation")]:
        with pytest.raises(ValueError, match=f"^{name}"):
            call()


# --- class 8: an unbounded normal's tails are tried on the scene, as a range's ends ------------------------

def sweep_refusal(tmp_path, text):
    from gimbalsim._errors import SpecError
    with pytest.raises(SpecError) as e:
        spec_of(tmp_path, text, "n.yaml")
    return str(e.value)


def test_a_normal_whose_tail_the_scene_refuses_is_refused_at_its_line(tmp_path):
    text = OPEN.replace("contact.clearance: {uniform: [1.0e-4, 3.0e-4]}", "friction.mu: {normal: {mean: 0.1, sd: 0.1}}")
    why = sweep_refusal(tmp_path, text)
    assert "n.yaml:7:" in why and "parameters.friction.mu" in why and "lower tail, mean - 4.8916 sd" in why, why
    # a clearance drawn negative, and a disk within it
    text = OPEN.replace("{uniform: [1.0e-4, 3.0e-4]}", "{normal: {mean: 1.0e-4, sd: 1.0e-4}}") + \
        "  initial.ecc: {disk: {within: contact.clearance, fraction: 1.0}}\n"
    why = sweep_refusal(tmp_path, text)
    assert "n.yaml:7:" in why and "parameters.contact.clearance" in why and "lower tail" in why, why
    # min bounds the lower tail: only the ends it draws between are tried
    text = OPEN.replace("contact.clearance: {uniform: [1.0e-4, 3.0e-4]}",
                        "friction.mu: {normal: {mean: 0.3, sd: 0.1, min: 0.05}}")
    assert spec_of(tmp_path, text, "ok.yaml").parameters[0].extremes() == [0.05, pytest.approx(0.3 + 0.48916)]


def test_a_normal_never_draws_beyond_the_tails_it_tried(tmp_path):
    from gimbalsim.dispersion import TAIL_SD
    text = OPEN.replace("contact.clearance: {uniform: [1.0e-4, 3.0e-4]}",
                        "friction.mu: {normal: {mean: 0.5, sd: 0.1}}")
    spec = spec_of(tmp_path, text)
    (p,) = spec.parameters
    assert p.extremes() == [pytest.approx(0.5 - TAIL_SD * 0.1), pytest.approx(0.5 + TAIL_SD * 0.1)]

    class FarRng:  # a generator whose first normal draw lies at 6 sd: it is drawn again
        def __init__(self):
            self.draws = [0.5 + 6 * 0.1, 0.5 - 0.1]

        def normal(self, mean, sd):
            return self.draws.pop(0)
    assert p.draw(FarRng(), {}) == pytest.approx(0.4)


def test_a_tuners_plant_normal_is_tried_at_its_tails(tmp_path):
    from conftest import CONTROLLER_CONFIG
    from gimbalsim._errors import SpecError
    from gimbalsim.tune import TuneSpec
    (tmp_path / "t.yaml").write_text(f"""
scene: {SCENES}/paper_clearance.yaml
controller: {CONTROLLER_CONFIG}
duration: 3.7
trials: 2
seed: 3
batch: 2
objective: {{metric: max_track, percentile: 90}}
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
plants:
  friction.mu: {{normal: {{mean: 0.1, sd: 0.1}}}}
""")
    with pytest.raises(SpecError, match=r"t.yaml:12:.*plants.friction.mu.*lower tail, mean - 4.8916 sd"):
        TuneSpec(tmp_path / "t.yaml")


# --- class 7: a closed-loop sweep changes sim.step without the output interval it never reads ---------------

STEP = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.12, sim.substep: 2.0e-5}}
controller: default
controller_set: {{control.period: 1.2e-3, profile.slew_start: 0.0, profile.slew_time: 0.06, profile.hold_time: 0.03}}
samples: 1
seed: 3
indices:
  ape: {{}}
"""


@pytest.mark.parametrize("how", ["set", "grid"])
def test_a_closed_loop_sweep_changes_sim_step_by_set_and_grid(tmp_path, how):
    from gimbalsim._sample import sample_alone
    if how == "set":  # 3e-4 s: the period's quarter, and the scene's output interval 0.001 s no multiple of it
        text = STEP.replace("sim.substep: 2.0e-5}", "sim.substep: 2.0e-5, sim.step: 3.0e-4}") + \
            "parameters:\n  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}\n"
    else:
        text = STEP + "grid:\n  sim.step: [3.0e-4, 4.0e-4]\n"
    spec = spec_of(tmp_path, text)
    header = spec.csv_header()
    for i in range(len(spec.design)):
        row, run = sample_alone(spec, i)
        cells = dict(zip(header, row))
        assert cells["status"] == "ok" and cells["t_end_s"] == "0.12", cells
        assert run.summary["ticks"] == 101
        assert not any("output_interval" in name for name in header)  # never recorded: the run does not read it
        assert row_verdict(spec, row) is None  # a resume keeps it: the scene is loaded as the worker loads it
    # the interval itself is still a key the closed loop never reads: refused under set (a value the scene takes)
    text = STEP.replace("sim.substep: 2.0e-5}", "sim.substep: 2.0e-5, sim.output_interval: 2.0e-3}") + \
        "grid:\n  sim.step: [3.0e-4]\n"
    assert "not read by this sweep's runs" in sweep_refusal(tmp_path, text)
