"""Issue 41, "Hostile and careless input" (pass 19): the closed-loop report's
CDF and Spearman lines over every unit drawn (the units without a figure
counted worst, as the budget counts them), and a tracker key refused when
the outage holds every sample instant within the run, not only the whole
run, or every sample taken outside it falls due in it or after the run.

Cheap: the report's parts on rows made by hand; the tracker keys by sweep
--check (nothing runs) and a tuner refused before its first trial."""
from types import SimpleNamespace

import numpy as np
import pytest

from test_pass16_outputs import BASE, TUNE, tool, write_spec
from test_pass18_python import TRACKER, check
from gimbalsim import _budget_report


# ---- D4 (class 1): the report's CDF and rank correlation count every unit drawn ----

def _spec():
    header = ["sample", "friction.mu", "status", "reason", "ape_track"]
    return SimpleNamespace(header=lambda: header, design=SimpleNamespace(columns=lambda: ["friction.mu"], grid_keys=[]),
                           closed=SimpleNamespace(metrics=lambda: ["ape_track"]))


# Each way a unit has no figure: crashed, refused, stopped, an ok run that missed the window.
NO_FIGURE = [("crashed", "", ""), ("refused:friction.mu", "friction.mu: out of range", ""),
             ("sim.velocity_limit", "simulation stopped at t = 0.1 s", "nan"), ("ok", "ape_track: missed", "nan")]


def _rows(figures, missing):
    """Units 0.. with friction.mu 0.1, 0.2, ...: the ones with a figure, then those without (`missing`)."""
    rows = [[str(i), f"{0.1 * (i + 1):.2f}", "ok", "", repr(v)] for i, v in enumerate(figures)]
    n = len(rows)
    return rows + [[str(n + i), f"{0.1 * (n + i + 1):.2f}", status, reason, cell]
                   for i, (status, reason, cell) in enumerate(missing)]


@pytest.mark.parametrize("missing", [[m] for m in NO_FIGURE] + [NO_FIGURE[:2]],
                         ids=[m[0].split(":")[0] for m in NO_FIGURE] + ["crashed+refused"])
def test_the_cdf_counts_every_unit_drawn_and_says_how_many_have_no_figure(tmp_path, monkeypatch, missing):
    drawn = []
    monkeypatch.setattr(_budget_report, "savefig", lambda fig, path, inputs, **kw: drawn.append(fig))
    rows = _rows([3e-5, 1e-5, 2e-5], missing)
    n, k = len(rows), len(missing)
    entries = [{"index": "ape", "phase": "track", "level": 0.5}]
    written = _budget_report.cdf_plots(_spec(), rows, entries, tmp_path)
    assert [p.name for p in written] == ["ape_track_cdf.png"] and len(drawn) == 1
    ax = drawn[0].axes[0]
    curve = ax.lines[0]
    assert list(curve.get_xdata()) == [1e-5, 2e-5, 3e-5]
    assert np.allclose(curve.get_ydata(), np.arange(1, 4) / n)  # stops at (n - k) / n, never 1.0
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert f"{n} units, {k} without a figure (counted worst)" in legend, legend


def test_the_cdf_of_units_all_with_a_figure_still_reaches_one(tmp_path, monkeypatch):
    drawn = []
    monkeypatch.setattr(_budget_report, "savefig", lambda fig, path, inputs, **kw: drawn.append(fig))
    _budget_report.cdf_plots(_spec(), _rows([3e-5, 1e-5], []), [{"index": "ape", "phase": "track", "level": 0.5}],
                             tmp_path)
    ax = drawn[0].axes[0]
    assert ax.lines[0].get_ydata()[-1] == 1.0
    assert "2 units" in [t.get_text() for t in ax.get_legend().get_texts()]


def _rank_correlation(x, ranks_y):
    rx = np.argsort(np.argsort(x)) + 1.0  # x distinct
    return float(np.corrcoef(rx, ranks_y)[0, 1])


@pytest.mark.parametrize("missing", [[m] for m in NO_FIGURE] + [NO_FIGURE[1:3], NO_FIGURE],
                         ids=[m[0].split(":")[0] for m in NO_FIGURE] + ["refused+stopped", "all-four"])
def test_the_rank_correlation_ranks_every_unit_without_a_figure_worst(missing):
    # figures falling with friction.mu, then the units without one (the largest mu): counted worst, the
    # correlation is no longer -1 over the units with a figure alone
    figures = [4e-5, 3e-5, 2e-5, 1e-5]
    rows = _rows(figures, missing)
    k = len(missing)
    ranks_y = list(np.arange(len(figures), 0, -1, dtype=float)) + [len(figures) + (k + 1) / 2.0] * k  # ties: average
    x = [float(r[1]) for r in rows]
    (name, rho), = _budget_report.drivers(_spec(), rows, "ape_track")
    assert name == "friction.mu"
    assert rho == pytest.approx(_rank_correlation(x, ranks_y)), (rho, k)
    assert rho > -0.99


# ---- D3 (class 3): an outage over every sample instant within the run takes every sample ----

STAR = BASE.replace("  sensors.seed: {choice: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}\n", "")
assert "sensors.seed" not in STAR and "{sim.duration: 0.3}" in STAR and "{sim.duration: 0.3, " in TRACKER


def _sensor_spec(tmp_path, sensor, duration, rate, outage, dispersed):
    text = STAR if sensor == "star_tracker" else TRACKER.replace("samples: 2", "samples: 3")
    old = "{sim.duration: 0.3}" if sensor == "star_tracker" else "{sim.duration: 0.3, sensors.tracker_outage: [0, 5]}"
    text = text.replace(old, f"{{sim.duration: {duration}, sensors.{sensor}_rate: {rate}, "
                             f"sensors.{sensor}_outage: {outage}}}")
    text = text.replace("parameters:\n", "parameters:\n" + "".join(f"  {k}: {v}\n" for k, v in dispersed.items()))
    return write_spec(tmp_path, text)


NOISE = {"star_tracker": {"sensors.star_tracker_noise": "{uniform: [0.0, 1.0e-3]}"},
         "tracker": {"sensors.tracker_noise": "{uniform: [0.0, 1.0e-3]}"}}
LATENCY = {"star_tracker": {"sensors.star_tracker_latency": "{uniform: [0.0, 0.005]}"},
           "tracker": {"sensors.tracker_latency": "{uniform: [0.0, 0.005]}"}}
# (duration, rate, outage): sample j at j / rate, taken at the first tick at or after it; the outage's ends inclusive
TAKES_NONE = [(1.0, 0.5, "[0.0, 0.5]"),     # samples at 0 (in the outage) and 2 (past the run)
              (1.0, 0.9, "[0.0, 0.5]"),     # the next at 1.11 s, past the run
              (1.5, 1.0, "[0.0, 1.0]"),     # the sample at 1.0 s on the outage's end: taken in it
              (0.95, 1.0, "[0.0, 0.5]"),    # the next at 1.0 s, past the run
              (1.0, 1.0, "[0.0, 0.5]")]     # the next at 1.0 s, the run's last tick: no phase [t0, t1) holds it
TAKES_ONE = [(1.2, 1.0, "[0.0, 0.5]"),      # the sample at 1.0 s, before the run's end
             (1.0, 2.0, "[0.001, 0.5]"),    # tick 0 before the outage takes sample 0 (0.5 s is lost in it)
             (1.2, 4.0, "[0.0, 0.74]")]     # the sample at 0.75 s


@pytest.mark.parametrize("sensor", ["star_tracker", "tracker"])
@pytest.mark.parametrize("keys", ["noise", "latency"])
@pytest.mark.parametrize("case", TAKES_NONE, ids=[f"{d}s-{r}Hz-{o}" for d, r, o in TAKES_NONE])
def test_a_tracker_key_under_an_outage_over_every_sample_instant_is_refused(tmp_path, sensor, keys, case):
    dispersed = (NOISE if keys == "noise" else LATENCY)[sensor]
    key = next(iter(dispersed))
    p = check(_sensor_spec(tmp_path, sensor, *case, dispersed), tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"key 'parameters.{key}'" in p.stderr and f"sensors.{sensor}_outage" in p.stderr, p.stderr
    assert "sample is taken" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("case", TAKES_ONE, ids=[f"{d}s-{r}Hz-{o}" for d, r, o in TAKES_ONE])
def test_a_tracker_key_with_one_sample_outside_the_outage_is_accepted(tmp_path, case):
    p = check(_sensor_spec(tmp_path, "star_tracker", *case, NOISE["star_tracker"]), tmp_path / "out")
    assert p.returncode == 0, p.stderr


# (latency, refused): outage [0.5, 1.0] s, a sample every 2 s: the one at 0 falls due at the latency
DELIVERED = [(0.6, True),    # in the outage: dropped; the next is past the run
             (0.5, True),    # on the outage's start (inclusive)
             (0.3, False)]   # before the outage: delivered (the estimator's history holds 0.32 s)


@pytest.mark.parametrize("sensor", ["star_tracker", "tracker"])
@pytest.mark.parametrize("latency,refused", DELIVERED, ids=[f"latency-{lat}" for lat, _ in DELIVERED])
def test_a_tracker_key_whose_samples_all_fall_due_in_the_outage_is_refused(tmp_path, sensor, latency, refused):
    spec = _sensor_spec(tmp_path, sensor, 1.0, 0.5, "[0.5, 1.0]", NOISE[sensor])
    spec.write_text(spec.read_text().replace("_outage: [0.5, 1.0]", f"_outage: [0.5, 1.0], "
                                             f"sensors.{sensor}_latency: {latency}"))
    p = check(spec, tmp_path / "out")
    # the boresight tracker's fusion keeps 64 ticks (0.064 s): a latency beyond drops every sample (pass 20)
    too_old = sensor == "tracker" and not refused
    # (pass 93) the star tracker's sample falls due before the outage, the next after the run: the outage itself
    # takes and drops none, and its set is refused
    idle_outage = sensor == "star_tracker" and not refused
    assert p.returncode == (2 if refused or too_old or idle_outage else 0), p.stderr
    if idle_outage:
        assert "key 'set.sensors.star_tracker_outage'" in p.stderr and "takes and drops no sample" in p.stderr
    if refused:
        assert f"key 'parameters.sensors.{sensor}_noise'" in p.stderr and "sample is delivered" in p.stderr, p.stderr
    if too_old:
        assert "older than the controller's history" in p.stderr, p.stderr


@pytest.mark.parametrize("phases,latency,refused", [("track", 0.2, False), ("track", 0.201, True),
                                                    ("window", 0.2, True), ("track-ape", 0.2, True)])
def test_a_sample_due_at_the_runs_last_tick_acts_where_a_phase_holds_it(tmp_path, phases, latency, refused):
    # the next sample after the outage is taken at 0.8 s: due at 1.0 s, the run's last tick, which the track
    # phase holds (the knowledge index reads its estimate: pass 22 saw knowledge_track move 500-fold) and a
    # window [t0, t1) never does (pass 23), or after it; APE reads the truth, never that tick's estimate (pass 24)
    spec = _sensor_spec(tmp_path, "star_tracker", 1.0, 1.25, "[0.0, 0.5]", NOISE["star_tracker"])
    spec.write_text(spec.read_text().replace("_outage: [0.0, 0.5]", "_outage: [0.0, 0.5], "
                                             f"sensors.star_tracker_latency: {latency}"))
    if phases.startswith("track"):
        spec.write_text(spec.read_text().replace("phases: [{late: [0.2, 0.3]}]", "phases: [track]"))
    if phases == "track":
        spec.write_text(spec.read_text().replace("  ape: {}\n", "  ape: {}\n  knowledge: {}\n"))
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "sample is delivered" in p.stderr, p.stderr


def test_a_tuners_plant_noise_under_an_outage_over_every_sample_instant_is_refused(tmp_path):
    # duration 3.6 s, a sample every 4 s: the one at 0 in the outage, the next past the run
    text = TUNE.replace("controller: default", "set: {sensors.star_tracker_rate: 0.25, "
                        "sensors.star_tracker_outage: [0, 1]}\ncontroller: default") + \
        "  sensors.star_tracker_noise: {uniform: [0.0, 1.0e-3]}\n"
    p = tool("tune", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert "key 'plants.sensors.star_tracker_noise'" in p.stderr and "sample is taken" in p.stderr, p.stderr
