"""Issue 41, "Hostile and careless input" (pass 20), the Python side: a
tracker key refused when every rate or control period the study draws
leaves each sample in the outage (not only when both are fixed), and an
allocation that never tries a value outside its range, however narrow.

Cheap: the tracker keys by sweep --check (nothing runs); the allocation's
scan on its own and by a refused spec."""
from types import SimpleNamespace

import pytest

from test_pass19_python import NOISE, _sensor_spec
from test_pass18_python import check
from gimbalsim import _allocate_search


# ---- class 3: the sample instants judged over every rate and period the study draws ----

# (dispersed, refused): outage [0, 2] s, a 2.5 s run; a sample every 1/rate s from 0, the one at 0 in the outage
RATES = [("sensors.{s}_rate: {{uniform: [0.3, 0.39]}}", True),     # the next after 2.5 s: past the run
         ("sensors.{s}_rate: {{uniform: [0.3, 0.4]}}", True),      # at 0.4 Hz at 2.5 s: the last tick, in no phase
         ("sensors.{s}_rate: {{choice: [0.3, 0.35]}}", True),
         ("sensors.{s}_rate: {{uniform: [0.3, 0.45]}}", False),     # at 0.45 Hz the next is at 2.22 s
         ("sensors.{s}_rate: {{uniform: [0.3, 0.9]}}", False),      # at 0.9 Hz the one at 2.22 s
         ("controller.control.period: {{choice: [0.001, 0.002]}}", True)]


@pytest.mark.parametrize("sensor", ["star_tracker", "tracker"])
@pytest.mark.parametrize("dispersed,refused", RATES, ids=[f"{d.split(':')[0]}-{d.split(': ', 1)[1]}"
                                                          for d, _ in RATES])
def test_a_tracker_key_is_judged_over_every_rate_and_period_drawn(tmp_path, sensor, dispersed, refused):
    key, value = dispersed.format(s=sensor).split(": ", 1)
    spec = _sensor_spec(tmp_path, sensor, 2.5, 0.3, "[0.0, 2.0]", {**NOISE[sensor], key: value})
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert f"key 'parameters.sensors.{sensor}_noise'" in p.stderr and "sample is taken" in p.stderr, p.stderr
        assert "for every" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("sensor", ["star_tracker", "tracker"])
def test_a_dispersed_rate_that_never_acts_is_refused_itself(tmp_path, sensor):
    key = f"sensors.{sensor}_rate"
    p = check(_sensor_spec(tmp_path, sensor, 2.5, 0.3, "[0.0, 2.0]", {key: "{uniform: [0.3, 0.39]}"}),
              tmp_path / "out")
    assert p.returncode == 2 and f"key 'parameters.{key}'" in p.stderr, p.stderr


# A sample j at j/rate is taken within a period after it: (start, end, duration, rate range, period range).
SPANS = [((0.0, 2.0, 2.5, 0.3, 0.39, 0.001, 0.001), True),
         ((0.0, 2.0, 2.5, 0.3, 0.4, 0.001, 0.001), False),  # 0.4 Hz: at 2.5 s, the run's last tick
         ((0.0, 2.0, 2.5, 0.3, 0.39, 0.001, 0.5), True),    # taken at 2.56 s at the earliest: past the run
         ((0.0, 2.0, 2.5, 0.2, 0.401, 0.001, 0.001), False),  # 1/0.401 = 2.494 s: before the last tick
         ((0.0, 2.0, 2.5, 0.51, 0.6, 0.001, 0.001), True),  # 1.67-1.96 s in the outage, 3.3 s past the run
         ((0.0, 1.9, 2.5, 0.51, 0.6, 0.001, 0.1), False),   # 1.96 s + a tick of up to 0.1 s: maybe past 1.9
         ((0.001, 2.0, 2.5, 0.3, 0.4, 0.001, 0.001), False)]  # sample 0 before the outage


@pytest.mark.parametrize("args,holds", SPANS, ids=[str(a) for a, _ in SPANS])
def test_the_outage_holds_every_span_only_when_every_sample_is_sure(args, holds):
    from gimbalsim._idle_sensors import _every_sample_lost
    start, end, duration, r_lo, r_hi, t_lo, t_hi = args
    assert _every_sample_lost(start, end, duration, (r_lo, r_hi), (t_lo, t_hi), None, 0) is holds


# ---- class 8/4: the allocation's values stay inside the range ----

def _key(lo, hi, values, log=False, is_int=False, direction="largest"):
    return SimpleNamespace(lo=lo, hi=hi, values=values, log=log, is_int=is_int, direction=direction)


@pytest.mark.parametrize("lo,hi,log", [(0.90000000000001, 0.90000000000004, False),
                                       (0.90000000000001, 0.90000000000004, True),
                                       (1.0000000000001e-4, 1.0000000000004e-4, False),
                                       (1.0e-5, 3.0e-4, True)])
def test_every_value_the_scan_or_the_bisection_tries_lies_in_the_range(lo, hi, log):
    a = _key(lo, hi, 9, log)
    xs = _allocate_search.scan_values(a)
    assert xs and all(lo <= x <= hi for x in xs), xs
    assert xs[0] == lo and xs[-1] == hi
    between = _allocate_search._between(lo, hi, log, False)
    assert lo <= between <= hi, between


# ---- class 3: a latency beyond the controller's history drops every sample ----

# (sensor, rate [Hz], latency, refused): the attitude estimator keeps 0.32 s at a 1 ms period, the tracker 64 ticks
HISTORY = [("star_tracker", 10.0, "0.4", True), ("star_tracker", 10.0, "0.32", True),
           ("star_tracker", 10.0, "0.3", False),
           ("tracker", 100.0, "0.064", True), ("tracker", 100.0, "0.063", False)]


@pytest.mark.parametrize("sensor,rate,latency,refused", HISTORY, ids=[f"{s}-{lat}" for s, _, lat, _ in HISTORY])
def test_a_sample_key_is_refused_when_every_sample_arrives_older_than_the_controller_keeps(
        tmp_path, sensor, rate, latency, refused):
    spec = _sensor_spec(tmp_path, sensor, 1.0, rate, "[0.0, 0.0]", NOISE[sensor])
    spec.write_text(spec.read_text().replace("_outage: [0.0, 0.0]", f"_outage: [0.0, 0.0], "
                                             f"sensors.{sensor}_latency: {latency}"))
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert f"key 'parameters.sensors.{sensor}_noise'" in p.stderr, p.stderr
        assert "older than the controller's history" in p.stderr, p.stderr


@pytest.mark.parametrize("lo,refused", [(0.35, True), (0.3, False)])
def test_a_dispersed_latency_beyond_the_history_is_refused_itself(tmp_path, lo, refused):
    key = "sensors.star_tracker_latency"
    p = check(_sensor_spec(tmp_path, "star_tracker", 1.0, 10.0, "[0.0, 0.0]", {key: f"{{uniform: [{lo}, 0.5]}}"}),
              tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert f"key 'parameters.{key}'" in p.stderr and f"{key} {lo} s or more" in p.stderr, p.stderr


def test_a_budget_whose_figures_are_all_alike_has_converged():
    # every figure 0: the interval [0, 0] is as narrow as an interval gets (0/0 was read as inf: run to the cap)
    from gimbalsim import _budget
    assert _budget.relative_width({"interval_rad": [0.0, 0.0], "estimate_rad": 0.0}) == 0.0
    assert _budget.relative_width({"interval_rad": [0.0, 1e-6], "estimate_rad": 0.0}) == float("inf")
    assert _budget.relative_width({"interval_rad": [1.0, 1.5], "estimate_rad": 1.0}) == 0.5
