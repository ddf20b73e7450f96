"""The report of a closed-loop sweep (OUT/report.md and OUT/plots/): the
budget's table per phase, a CDF of each index with its requirement line, and
the parameters that drive the worst units (Spearman rank correlation of each
dispersed parameter with the index, and the worst five units' parameters).
tools/sweeps/run_pointing_budget.sh stamps it into docs/results/."""
import math

import pathlib

import numpy as np

from . import _budget
from ._output import savefig
from . import indices as ix

SUPPORTED_LEVEL = 0.95  # a second column every budget of 59 units or more supports (at 95 %)


def _numeric_columns(spec, rows):
    """{design column: values} of the dispersed numbers (a choice of names has no rank)."""
    header = spec.header()
    out = {}
    for c in spec.design.columns():
        try:
            out[c] = np.array([float(r[header.index(c)]) for r in rows])
        except ValueError:
            continue
    return out


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def cdf_name(metric, prefix=""):
    return f"{prefix}{metric}_cdf.png"


def cdf_names(spec):
    """Every file name cdf_plots() may write for the spec's budget (one per
    index and phase): refused up front when a link or an input holds one."""
    return [cdf_name(m) for m in spec.closed.metrics()]


def cdf_plots(spec, rows, entries, out_dir, prefix="", inputs=()):
    """One PNG per index and phase: the units' empirical CDF, the level, the
    requirement line (none of them one of the run's inputs). Returns the files written."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for e in entries:
        metric = f"{e['index']}_{e['phase']}"
        if cdf_name(metric, prefix) in (w.name for w in written):  # one plot per metric, a curve per grid point
            continue
        curves = []  # one per grid point, its own budget's units
        for point, point_rows in _budget.grid_points(spec, rows):
            values = np.array(_budget.column_values(spec, point_rows, metric))
            x = np.sort(values[np.isfinite(values)])
            # Over every unit drawn, as the budget: the k without a figure count worst; the curve stops at (n-k)/n.
            n, k = len(values), len(values) - len(x)
            label = (f"{point}: " if point else "") + f"{n} units" + (f", {k} without a figure (counted worst)"
                                                                     if k else "")
            curves += [(x, n, label)] if len(x) else []
        if not curves:
            continue
        fig, ax = plt.subplots(figsize=(6, 4))
        for x, n, label in curves:
            ax.step(x, np.arange(1, len(x) + 1) / n, where="post", label=label)
        x = np.sort(np.concatenate([c[0] for c in curves]))
        ax.axhline(e["level"], ls=":", c="gray", label=f"level {100 * e['level']:.4g} %")
        if "requirement" in e:
            ax.axvline(e["requirement"]["requirement_rad"], c="r", ls="--", label="requirement" if len(curves) > 1
                       else f"requirement ({e['requirement']['verdict']})")
        ax.set_xscale("log" if x[0] > 0 else "linear")
        ax.set_xlabel(f"{metric} [rad] (worst time in the phase, per unit)")
        ax.set_ylabel("fraction of units")
        ax.legend(loc="lower right")
        fig.tight_layout()
        written.append(out_dir / cdf_name(metric, prefix))
        savefig(fig, written[-1], inputs, dpi=100, close=True)
    return written


def drivers(spec, rows, metric):
    """[(parameter, Spearman rho)] by |rho|, the largest first, over every unit
    drawn; the units without a figure rank worst (ties share the average rank)."""
    from scipy import stats

    # Every unit drawn (refused and crashed too, as the budget counts them): those without a figure are +inf,
    # the worst rank, ties among them sharing the average rank.
    y = np.array(_budget.column_values(spec, rows, metric))
    y = np.where(np.isfinite(y), y, np.inf)
    out = []
    for c, x in _numeric_columns(spec, rows).items():
        ranked = ~np.isnan(x)  # a unit whose value is no number has no place on the parameter's axis
        x, yc = x[ranked], y[ranked]
        if len(x) < 3 or np.all(x == x[0]) or np.all(yc == yc[0]):
            continue
        rho = float(stats.spearmanr(x, yc).statistic)
        out.append((c, rho))
    return sorted(out, key=lambda p: -abs(p[1]) if math.isfinite(p[1]) else 0.0)


def _why_none(spec, row, metric):
    """Why a unit has no figure of metric: its status, and the parts of its
    reason (closed loop) that are the run's own or name this metric."""
    header = spec.header()
    status = row[header.index("status")]
    reason = row[header.index("reason")] if "reason" in header else ""
    others = tuple(f"{m}:" for m in spec.closed.metrics() if m != metric) if spec.closed else ()
    parts = [p for p in reason.split(" | ") if p and not p.startswith(others)]
    return f"{status}: " + " | ".join(parts) if parts else status


def worst_units(spec, rows, metric, k=5):
    """The k worst units by metric: [(sample, value or None, why, parameters)].
    Every unit drawn takes part (refused and crashed ones too); the units
    without a figure (value None, why their status and reason) rank worst, as
    the budget counts them, in sample order; then the largest figures, ties in
    sample order."""
    header = spec.header()
    y = _budget.column_values(spec, rows, metric)
    sample = lambda i: int(rows[i][0]) if rows[i][0].isdigit() else math.inf
    order = sorted(range(len(rows)), key=lambda i: (math.isfinite(y[i]), -y[i] if math.isfinite(y[i]) else 0.0,
                                                     sample(i)))[:k]
    cols = spec.design.columns()
    return [(rows[i][0], y[i] if math.isfinite(y[i]) else None,
             "" if math.isfinite(y[i]) else _why_none(spec, rows[i], metric),
             [rows[i][header.index(c)] for c in cols]) for i in order]


def body(spec, rows, entries, plots, engine):
    """The report's Markdown (image links relative to the report)."""
    c = spec.closed
    controller = pathlib.Path(c.controller_path).name if c.controller_path else "default (built in)"
    lines = [f"Closed-loop sweep of `{spec.scene_path.name}` with the controller `{controller}`"
             f" ({c.duration_s:g} s per run), {len(rows)} units; statistical interpretation: "
             f"**{_budget.INTERPRETATION}** (ECSS-E-ST-60-10C). Each index is the quantile at its level of the "
             "units' worst value in the phase; its interval comes from order statistics (distribution-free). "
             "A unit without a figure (a run that crashed, was refused or stopped, or missed a window) counts as worst.", "",
             f"Stepping (sampling: {spec.sampling['mode']}): {spec.sampling['why']}.", ""]
    lines += ["| index | phase | level | n | value [rad] (CI at confidence) | "
              f"at {100 * SUPPORTED_LEVEL:.4g} % [rad] (CI) | requirement |", "|---|---|---|---|---|---|---|"]
    for e in entries:
        values = _budget.column_values(spec, _budget.rows_of(spec, rows, e), f"{e['index']}_{e['phase']}")
        b = ix.quantile_bound(values, SUPPORTED_LEVEL, e["confidence"])
        # its own quantile (95 %), whose support is not the level's: said so, with its own count
        lower = (_budget.NO_FIGURE if b.n and b.n_missing == b.n
                 else f"beyond every figure (on the {b.n_missing} of {b.n} units without one, counted as worst)"
                 if b.supported and math.isinf(b.estimate)  # it printed a bare inf (pass 55)
                 else f"{b.estimate:.3g} [{b.low:.3g}, {b.high:.3g}]" if b.supported and math.isfinite(b.high)
                 else f"not supported at {100 * SUPPORTED_LEVEL:.4g} % (n={b.n} < {b.min_units})"
                 if not b.supported else f"{b.estimate:.3g} (the interval's upper end beyond every figure)")
        phase = e["phase"] + (f" ({e['grid_point']})" if e.get("grid_point") else "")  # a budget per grid point
        lines.append(f"| {e['index']} | {phase} | {100 * e['level']:.4g} % | {e['n']} | {_budget.cell(e)} | "
                     f"{lower} | {_budget.verdict_text(e) or '-'} |")
    unsupported = [e for e in entries if not e["supported"]]
    if unsupported:
        need = max(e["min_units"] for e in unsupported)
        lines += ["", f"Some quantiles are not supported by {unsupported[0]['n']} units: `samples: {need}` in the spec "
                  f"(or `--until INDEX:PHASE:WIDTH --max-samples {need}`) would support them."]
    if engine.get("samples_per_s"):
        lines += ["", f"Speed: {engine['ran_this_invocation']} samples in {engine['elapsed_s']:.1f} s on "
                  f"{engine['workers']} worker{'s' * (engine['workers'] != 1)} ({engine['samples_per_s']:.2f} "
                  "samples/s)."]
    lines += ["", "## Distributions", ""]
    lines += [f"![{p.stem}]({p.name})" if p.parent.name != "plots" else f"![{p.stem}](plots/{p.name})"
              for p in plots]
    lines += ["", "## What drives the worst units", ""]
    ranked = 0
    for e in entries:
        metric = f"{e['index']}_{e['phase']}"
        d = drivers(spec, _budget.rows_of(spec, rows, e), metric)
        if not d:
            continue
        ranked += 1
        lines.append(f"- {metric}" + (f" ({e['grid_point']})" if e.get("grid_point") else "") +
                     ": Spearman rank correlation " +
                     ", ".join(f"{name} {rho:+.2f}" for name, rho in d))
    if not ranked:  # said, never an empty section
        lines.append("- no rank correlation: it needs a dispersed column with at least 3 units holding different "
                     "numbers, and an index that differs between them")
    track = next((e for e in entries if e["index"] == "ape" and e["phase"] == "track"), entries[0] if entries else None)
    if track is not None:
        metric = f"{track['index']}_{track['phase']}"
        cols = spec.design.columns()
        lines += ["", f"Worst five units by {metric} (every unit drawn; those without a figure rank worst, "
                  "as the budget counts them, in sample order; then the largest figure first):", "",
                  "| sample | " + metric + " [rad] | " + " | ".join(cols) + " |",
                  "|---|---|" + "---|" * len(cols)]
        for sample, value, why, params in worst_units(spec, rows, metric):
            shown = [f"{float(v):.3g}" if _is_number(v) else v for v in params]
            cell = f"{value:.3g}" if value is not None else "no figure (" + why.replace("|", "\\|") + ")"
            lines.append(f"| {sample} | {cell} | " + " | ".join(shown) + " |")
    return "\n".join(lines) + "\n"
