"""Issue 41, "Hostile and careless input" (pass 21), class 3, the sensor
keys: a latency is judged as delivered (rounded up to whole ticks) against
the controller's history; sensors.seed is idle when the only noise it draws
is the star tracker's and no star tracker sample acts; an outage that every
sample taken outside it falls due in, or that holds every sample at each of
a choice's rates, is judged over every rate and period the study draws.

Cheap: every case is a sweep --check (nothing runs)."""
import pytest

from test_pass18_python import check
from test_pass19_python import NOISE, _sensor_spec


def _with(spec, old, new):
    text = spec.read_text()
    assert old in text, old
    spec.write_text(text.replace(old, new))
    return spec


# (latency [s], control period [s], refused): 0.32 s at 1 ms, 0.384 s at 2 ms; a sample arrives at the first
# tick at or after t_s + latency, so 0.3191 s arrives 0.32 s old
LATENCIES = [("0.3195", None, True), ("0.3191", None, True), ("0.319", None, False),
             ("0.3825", "0.002", True), ("0.382", "0.002", False)]


@pytest.mark.parametrize("latency,period,refused", LATENCIES, ids=[f"{lat}s-{p or 0.001}s" for lat, p, _ in LATENCIES])
def test_a_latency_is_judged_as_delivered_against_the_history(tmp_path, latency, period, refused):
    spec = _sensor_spec(tmp_path, "star_tracker", 1.0, 10.0, "[0.0, 0.0]", NOISE["star_tracker"])
    _with(spec, "_outage: [0.0, 0.0]", f"_outage: [0.0, 0.0], sensors.star_tracker_latency: {latency}")
    if period:
        _with(spec, "controller_set: {", f"controller_set: {{control.period: {period}, ")
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'parameters.sensors.star_tracker_noise'" in p.stderr, p.stderr
        assert "older than the controller's history" in p.stderr, p.stderr


@pytest.mark.parametrize("latency,refused", [("0.35", True), ("0.0", False)])
def test_the_seed_is_idle_when_its_only_noise_is_a_star_tracker_that_never_acts(tmp_path, latency, refused):
    spec = _sensor_spec(tmp_path, "star_tracker", 1.0, 10.0, "[0.0, 0.0]", {"sensors.seed": "{choice: [1, 2, 3]}"})
    _with(spec, "_outage: [0.0, 0.0]", f"_outage: [0.0, 0.0], sensors.star_tracker_latency: {latency}, "
                                       "sensors.star_tracker_noise: 1.0e-4")
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'parameters.sensors.seed'" in p.stderr and "star_tracker_noise acts on nothing" in p.stderr


# (sensor, outage, latency, rate dispersed, refused); a 2 s run
DUE = [("star_tracker", "[0.2, 1000]", "0.3", "{uniform: [1.0, 1.5]}", True),     # each falls due in the outage
       ("star_tracker", "[0.2, 1000]", "0.3", "{choice: [1.0, 1.5]}", True),
       ("star_tracker", "[0.2, 1000]", "0.1", "{uniform: [1.0, 1.5]}", False),    # sample 0 due at 0.1 s: acts
       ("tracker", "[0.02, 1000]", "0.05", "{choice: [10.0, 12.0]}", True)]


@pytest.mark.parametrize("sensor,outage,latency,rate,refused", DUE, ids=[f"{s}-{lat}-{r}" for s, _, lat, r, _ in DUE])
def test_samples_that_all_fall_due_in_the_outage_are_judged_over_every_rate(tmp_path, sensor, outage, latency, rate,
                                                                               refused):
    spec = _sensor_spec(tmp_path, sensor, 2.0, 1.0, outage, {**NOISE[sensor], f"sensors.{sensor}_rate": rate})
    _with(spec, f"_outage: {outage}", f"_outage: {outage}, sensors.{sensor}_latency: {latency}")
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert f"key 'parameters.sensors.{sensor}_noise'" in p.stderr and "falls due in it" in p.stderr, p.stderr


@pytest.mark.parametrize("rates,refused", [("[1.0, 2.0]", True), ("[1.0, 2.5]", False)])
def test_an_outage_holding_every_sample_at_each_rate_of_a_choice_is_refused(tmp_path, rates, refused):
    # outage [0, 0.5] s, a 0.95 s run: at 1 Hz the next sample is past the run's end, at 2 Hz on the outage's
    # end; at 2.5 Hz one falls at 0.8 s
    spec = _sensor_spec(tmp_path, "star_tracker", 0.95, 1.0, "[0.0, 0.5]",
                        {**NOISE["star_tracker"], "sensors.star_tracker_rate": f"{{choice: {rates}}}"})
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "one of 1.0, 2.0 Hz" in p.stderr and "sample is taken" in p.stderr, p.stderr


# ---- class 4 (F10): the allocation's plot over values none of whose units has a figure ----

@pytest.mark.parametrize("log", [True, False])
def test_the_allocation_plot_spans_its_range_when_no_value_has_a_figure(monkeypatch, tmp_path, log):
    # its x axis was matplotlib's default [0, 1], no value tried on it, the labels piled up at 0
    from types import SimpleNamespace
    from gimbalsim import _allocate_report
    figures = []
    monkeypatch.setattr(_allocate_report, "savefig", lambda fig, path, inputs, **kw: figures.append(fig))
    a = SimpleNamespace(lo=1e-5, hi=4e-5, log=log, level=0.9973, confidence=0.95, requirement=1e-4, key="k",
                        unit="m", index="ape", phase="track", direction="largest")
    nothing = {"estimate": float("inf"), "low": float("inf"), "high": float("inf"), "upper": float("inf")}
    tried = {1e-5: nothing, 2e-5: nothing, 4e-5: nothing}
    _allocate_report._plot(a, tried, {"bracket": None, "outcome": "no_value_meets"}, tmp_path / "p.png", [])
    ax = figures[0].axes[0]
    lo, hi = ax.get_xlim()
    assert lo < 1e-5 and 4e-5 < hi < 1e-4, (lo, hi)
    marks = [line for line in ax.get_lines() if line.get_label() == "values tried"]
    assert len(marks) == 1 and list(marks[0].get_xdata()) == sorted(tried)
    assert sorted(t.xy[0] for t in ax.texts) == sorted(tried)


# ---- class 4/8 (F7): a control period no sample could run at is refused at its line ----

PERIODS = [("grid", "controller.control.period: [0.001, 0.0015]", "whole multiple of the scene's step"),
           ("parameters", "controller.control.period: {choice: [0.001, 0.0015]}", "whole multiple of the scene's step"),
           ("parameters", "controller.control.period: {choice: [0.001, 0.003]}", "sim.duration 1 s with control.period"),
           ("parameters", "controller.control.period: {uniform: [0.001, 0.002]}", "a choice of whole multiples")]


@pytest.mark.parametrize("section,line,why", PERIODS, ids=[f"{s}-{i}" for i, (s, _, _) in enumerate(PERIODS)])
def test_a_control_period_every_sample_would_refuse_is_refused_at_its_line(tmp_path, section, line, why):
    spec = _sensor_spec(tmp_path, "star_tracker", 1.0, 10.0, "[0.0, 0.0]", NOISE["star_tracker"])
    if section == "grid":
        _with(spec, "parameters:\n", f"grid:\n  {line}\nparameters:\n")
    else:
        _with(spec, "parameters:\n", f"parameters:\n  {line}\n")
    p = check(spec, tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"key '{section}.controller.control.period'" in p.stderr and why in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


def test_an_allocation_over_the_control_period_refuses_a_scan_value_no_sample_runs_at(tmp_path):
    from test_pass16_outputs import ALLOCATE, BASE, line_of, tool, write_spec
    text = (BASE + ALLOCATE).replace("key: sensors.star_tracker_noise", "key: controller.control.period") \
        .replace("range: [1.0e-5, 3.0e-4]", "range: [0.001, 0.002]") \
        .replace("{sim.duration: 0.3}", "{sim.duration: 0.3, sensors.star_tracker_noise: 1.0e-4}")  # the seed acts
    assert "star_tracker_noise: 1.0e-4}" in text
    spec = write_spec(tmp_path, text)
    p = tool("allocate", spec, tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"{spec}:{line_of(text, 'range:')}:" in p.stderr and "controller.control.period = 0.0015" in p.stderr
    assert not (tmp_path / "out").exists()


# ---- class 3 (F5): the fixed policy's impact check under the adaptive policy ----

@pytest.mark.parametrize("policy,refused", [("adaptive", True), ("fixed", False)])
def test_min_substeps_per_impact_is_idle_under_the_adaptive_policy(tmp_path, policy, refused):
    from test_pass16_outputs import write_spec
    from conftest import SCENES
    spec = write_spec(tmp_path, f"""scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.2, sim.substep_policy: {policy}, friction.law: coulomb_stick}}
samples: 2
seed: 1
parameters:
  sim.min_substeps_per_impact: {{uniform: [1.0, 4.0]}}
""")
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'parameters.sim.min_substeps_per_impact'" in p.stderr and "policy is adaptive" in p.stderr


def test_a_five_ms_control_period_loads_where_its_rate_filter_is_not_read(tmp_path):
    # (F8) the default controller refused control.period 0.005 for its rate filter (100 Hz, not below the
    # 100 Hz Nyquist frequency) that the firmware's rates never use; the override making it load was refused as idle
    spec = _sensor_spec(tmp_path, "star_tracker", 1.0, 10.0, "[0.0, 0.0]", NOISE["star_tracker"])
    _with(spec, "controller_set: {", "controller_set: {control.period: 0.005, ")
    p = check(spec, tmp_path / "out")
    assert p.returncode == 0, p.stderr


# ---- pass 22: a period judged against every step the study gives; a refused list shown as values ----

STEPS = [("grid:\n  sim.step: [1.0e-3, 5.0e-4]\n  controller.control.period: [0.0025]\n", None),  # 5e-4 s runs
         ("grid:\n  sim.step: [8.0e-4]\n", "parameters.controller.control.period"),
         ("", "controller_set.control.period")]


@pytest.mark.parametrize("grid,refused_at", STEPS, ids=["a-step-fits", "no-step-fits", "fixed-period"])
def test_a_control_period_is_judged_against_every_step_the_study_gives(tmp_path, grid, refused_at):
    spec = _sensor_spec(tmp_path, "star_tracker", 0.8 if refused_at else 1.0, 10.0, "[0.0, 0.0]",
                        NOISE["star_tracker"])
    if refused_at == "parameters.controller.control.period":
        _with(spec, "parameters:\n", f"{grid}parameters:\n  controller.control.period: {{choice: [0.002]}}\n")
    elif refused_at:
        _with(spec, "controller_set: {", "controller_set: {control.period: 0.0025, ")
        _with(spec, "{sim.duration: 0.8,", "{sim.duration: 1.0,")
    else:
        _with(spec, "parameters:\n", f"{grid}parameters:\n")
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused_at else 0), p.stderr
    if refused_at:
        assert f"key '{refused_at}'" in p.stderr and "every sample would be refused" in p.stderr, p.stderr


def test_a_refused_list_is_shown_by_its_values(tmp_path):
    from test_pass16_outputs import BASE, write_spec
    p = check(write_spec(tmp_path, BASE + "sampling: [auto]\n"), tmp_path / "out")
    assert p.returncode == 2 and "key 'sampling': expected a name, got ['auto']" in p.stderr, p.stderr
    assert "object at 0x" not in p.stderr


def test_a_spec_giving_the_fixed_policys_impact_check_keeps_the_scenes_stepping(tmp_path):
    # sampling: auto chose the adaptive policy, then refused the user's sim.min_substeps_per_impact under it
    from test_pass16_outputs import write_spec
    from conftest import SCENES
    spec = write_spec(tmp_path, f"""scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.3, sim.min_substeps_per_impact: 20}}
controller: default
samples: 2
seed: 1
parameters:
  friction.mu: {{uniform: [0.15, 0.35]}}
phases: [{{w: [0.1, 0.3]}}]
indices:
  ape: {{}}
""")
    p = check(spec, tmp_path / "out")
    assert p.returncode == 0, p.stderr


def test_a_report_without_rank_correlations_says_why(tmp_path):
    # (pass 23) "What drives the worst units" was left empty when no column could be ranked
    from test_pass16_outputs import BASE, tool, write_spec
    text = BASE.replace("samples: 4", "samples: 2").replace("{sim.duration: 0.3}",
                                                            "{sim.duration: 0.3, sensors.star_tracker_noise: 1.0e-4}")
    p = tool("sweep", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 0, p.stderr
    report = (tmp_path / "out" / "report.md").read_text()
    drives = report[report.index("## What drives the worst units"):]
    assert "- no rank correlation: it needs a dispersed column with at least 3 units" in drives, drives
