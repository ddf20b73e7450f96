"""One sample of a sweep, open or closed loop: run as a worker runs it, and
its row of results.csv. Here, not in sweep.py, because the sweep (its
tasks) and the replay (one sample alone) both use it and neither imports
the other for it."""
import time

from . import _provenance
from ._closed_sample import run_closed_sample
from ._journal import fmt
from ._open_sample import run_sample


def run_one(base, closed, overrides, cache=None, series=False):
    """One sample from its values (spec.design.draw(i)): the open loop's
    metrics, or the closed loop's indices (closed: the spec's ClosedLoopSpec);
    with series, its run too, under "run"."""
    if closed is not None:
        return run_closed_sample(base, closed, overrides, series)
    return run_sample(base, overrides, {} if cache is None else cache, series)


def row_values(spec, values, result):
    """Sample result's row (values: its drawn parameters), cells as Python values."""
    return [result["sample"]] + spec.design.row_values(values) + [result["status"]] + \
        [result.get("reason", "")] * spec.text_columns + [result.get(m) for m in spec.metrics] + \
        [result["wall_time"]] + _provenance.values(spec, result)


def sample_alone(spec, i):
    """Sample i of a checked spec run alone in this process, as a worker runs
    it (open or closed loop): its row as results.csv holds it (text) and the
    run it made (None when the scene or the controller refused the sample).
    The seam a replay uses."""
    values = spec.design.draw(i)
    t0 = time.perf_counter()
    r = run_one(spec.base, spec.closed, values, series=True)
    run = r.pop("run", None)
    r["sample"], r["wall_time"] = i, time.perf_counter() - t0
    return [fmt(v) for v in row_values(spec, values, r)], run
