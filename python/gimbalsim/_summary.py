"""A sweep's summary (counts per status, percentiles, the closed loop's
budget) and the open loop's plots."""
import math

import numpy as np

from . import _budget, _provenance
from ._output import savefig


def percentiles(x):
    x = np.asarray([v for v in x if v is not None and math.isfinite(v)], dtype=float)
    if not len(x):
        return None
    return {"p50": float(np.percentile(x, 50)), "p90": float(np.percentile(x, 90)),
            "p99": float(np.percentile(x, 99)), "max": float(x.max()), "n": int(len(x))}


def no_percentiles_reason(metric, samples, n_ok, status):
    """Why a metric has no percentiles (its entry null): no ok sample (the
    count per status), or no ok sample with a value of it."""
    if not n_ok:
        counts = ", ".join(f"{k} {v}" for k, v in sorted(status.items()))
        return f"no ok sample: {samples} sample{'s' * (samples != 1)}" + (f" ({counts})" if counts else "")
    return f"none of the {n_ok} ok sample{'s' * (n_ok != 1)} has a value of {metric}"


def summarize(spec, rows, engine):
    header = spec.header()
    col = {c: header.index(c) for c in header}
    status = {}
    for r in rows:
        status[r[col["status"]]] = status.get(r[col["status"]], 0) + 1
    ok = [r for r in rows if r[col["status"]] == "ok"]
    num = lambda r, c: float(r[col[c]]) if r[col[c]] not in ("", "nan") else None
    pct = {m: percentiles([num(r, m) for r in ok]) for m in spec.metrics + ["wall_time"]}
    return {"spec": str(spec.spec_path), "scene": str(spec.scene_path), "samples": len(rows), "status": status,
            "percentiles_of_ok_samples": pct,
            "percentiles_of_ok_samples_note": {m: no_percentiles_reason(m, len(rows), len(ok), status)
                                               for m, p in pct.items() if p is None},
            **({"budget": _budget.table(spec, rows)} if spec.closed else {}),
            "sampling": spec.sampling,
            "fingerprints": _provenance.fingerprints(spec),
            "applied_differs": sum(1 for r in rows if r[col[_provenance.DIFFERS]]),
            "engine": engine}


# (metric, unit, name): the distributions plotted, each into NAME_distribution.png
DISTRIBUTIONS = (("pointing_error_max", "rad", "pointing_error"), ("peak_joint2_force", "N", "peak_force"))


def _distribution_name(name):
    return f"{name}_distribution.png"


def _versus_name(column):
    return f"pointing_error_vs_{column.replace('[', '_').replace(']', '')}.png"


def plot_names(spec):
    """Every file name plot() may write into its folder: the sweep refuses a
    link or an input under any of them before a sample runs."""
    if spec.closed:
        return []
    return [_distribution_name(name) for _, _, name in DISTRIBUTIONS] + \
        [_versus_name(c) for c in spec.design.columns()]


def plot(spec, rows, out, inputs=()):
    """The open loop's distribution plots into the folder out (none of them
    one of the run's inputs); the files written."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    header = spec.header()
    col = {c: header.index(c) for c in header}
    ok = [r for r in rows if r[col["status"]] == "ok"]
    if not ok or spec.closed:  # a closed loop's plots are its budget's (report.py)
        return []
    out.mkdir(parents=True, exist_ok=True)
    written = []
    val = lambda c: np.array([float(r[col[c]]) for r in ok])
    for metric, unit, name in DISTRIBUTIONS:
        x = np.sort(val(metric))
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        ax[0].hist(x, bins=min(50, max(5, len(x) // 10)))
        ax[0].set_xlabel(f"{metric} [{unit}]")
        ax[0].set_ylabel("samples")
        ax[1].step(x, np.arange(1, len(x) + 1) / len(x), where="post")
        ax[1].set_xlabel(f"{metric} [{unit}]")
        ax[1].set_ylabel("empirical CDF")
        ax[1].axhline(0.99, ls=":", c="gray")
        fig.suptitle(f"{len(x)} samples ({spec.scene_path.name})")
        fig.tight_layout()
        written.append(out / _distribution_name(name))
        savefig(fig, written[-1], inputs, dpi=110, close=True)
    for c in spec.design.columns():
        try:
            x = val(c)
        except ValueError:  # names (a choice of strings): no axis
            continue
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(x, val("pointing_error_max"), ".", ms=3)
        ax.set_xlabel(c)
        ax.set_ylabel("pointing_error_max [rad]")
        fig.tight_layout()
        written.append(out / _versus_name(c))
        savefig(fig, written[-1], inputs, dpi=110, close=True)
    return written
