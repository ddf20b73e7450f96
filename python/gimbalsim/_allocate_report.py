"""An allocation's outputs, all through the one writer (_output.py): the
table of the values tried (allocation.csv), the whole answer
(allocation.json), a page (allocation.md) and the plot of the index's
quantile with its interval against the key (allocation.png)."""
import math

from . import _budget, indices
from ._csv_cells import csv_number, csv_text
from ._output import json_text, savefig, write_csv, write_text

CSV, JSON, PAGE, PLOT = "allocation.csv", "allocation.json", "allocation.md", "allocation.png"


def record(a, spec, rows, value, folder):
    """A value's evidence: the index's quantile with its bounds
    (indices.quantile_bound) and the verdict (indices.requirement_verdict)
    over every unit drawn, a unit without a figure counted as worst."""
    figures = _budget.column_values(spec, rows, f"{a.index}_{a.phase}")
    b = indices.quantile_bound(figures, a.level, a.confidence)
    v = indices.requirement_verdict(figures, a.requirement, a.level, a.confidence)
    bounds = {"estimate": b.estimate, "upper": b.upper, "low": b.low, "high": b.high}
    if b.n and b.n_missing == b.n:  # no unit has a figure: every one counts as worst, so does every bound (never NaN)
        bounds = dict.fromkeys(bounds, math.inf)
    # (pass 81) a bound beyond every figure was null with an empty note: say why beside it
    beyond = [name for name, x in (("estimate", bounds["estimate"]), ("interval end", bounds["high"]),
                                   ("upper bound", bounds["upper"])) if math.isinf(x)]
    why_beyond = (f"{', '.join(beyond)} beyond every figure: {b.n_missing} of {b.n} units have no figure "
                  f"(stopped, failed or not reached) and count as worst") if beyond else ""
    return {"value": value, "folder": folder, "n": b.n, "n_missing": b.n_missing, **bounds,
            "passed": v.passed, "n_meeting": v.n_meeting, "all_zero": bool(v.note), "fraction_lower_bound": v.lower,
            "note": "; ".join(t for t in (why_beyond, b.reason, v.reason, v.note) if t)}


def _json(x):
    """A figure for JSON: null when there is none (NaN) or it lies beyond every figure (inf)."""
    return float(x) if math.isfinite(x) else None


def _text(x):
    """A bound as text: 'beyond every figure' for inf (units without one), 'n/a' for NaN: never a bare nan."""
    return "beyond every figure" if math.isinf(x) else "n/a" if math.isnan(x) else f"{x:.4g} rad"


def header(a, csv_name):
    key = csv_name(a.key.replace(".", "_"), a.unit)
    return ["tried", key, "verdict", "n", "n_missing", "n_meeting", "fraction_lower_bound", "estimate_rad",
            "interval_low_rad", "interval_high_rad", "upper_bound_rad", "requirement_rad", "note"]


def table(a, tried):
    """The values tried in the key's order, each a row of the CSV (cells as
    text: a bound beyond every figure is inf, none is nan)."""
    out = []
    for value, r in sorted(tried.items()):
        out.append([r["folder"], a.value_text(value), "PASS" if r["passed"] else "FAIL", r["n"], r["n_missing"],
                    r["n_meeting"], csv_number(r["fraction_lower_bound"])] +
                   [csv_number(r[k]) for k in ("estimate", "low", "high", "upper")] + [csv_number(a.requirement)] +
                   [csv_text(r["note"])])
    return out


def answer_lines(a, tried, result, runs, ran):
    """The answer in words, one line each (the console and the page). ran: the runs made by this invocation
    (a resume reads the others back: a page's wall time is this invocation's)."""
    what = f"{a.index} {a.phase} <= {a.requirement:.4g} rad at {100 * a.level:.4g} % with {100 * a.confidence:.4g} %"
    unit = f" {a.unit}" if a.unit else ""
    kind = result["outcome"]
    if kind == "bracket":
        meet, fail = result["bracket"]
        lines = [f"the {a.direction} {a.key} meeting {what}: {a.value_text(meet)}{unit} meets, "
                 f"{a.value_text(fail)}{unit} fails (the limit lies between)"]
    elif kind == "every_value_meets":
        lines = [f"every value of [{a.value_text(a.lo)}, {a.value_text(a.hi)}]{unit} tried meets {what}: the "
                 f"{a.direction} {a.key} lies beyond the range (no failing value; widen it to find the limit)"]
    elif result["best"] is None:
        lines = [f"no value of [{a.value_text(a.lo)}, {a.value_text(a.hi)}]{unit} meets {what} (no bracket): "
                 f"{result['monotone_note']}"]
    else:
        b = tried[result["best"]]
        end = a.lo if a.direction == "largest" else a.hi
        opening = (f"no value of [{a.value_text(a.lo)}, {a.value_text(a.hi)}]{unit} meets {what} (no bracket)"
                   if kind == "no_value_meets" else
                   f"the favourable end {a.key} = {a.value_text(end)}{unit} fails {what}, yet a value further on "
                   "meets it (no bracket: the index is not monotone, see below)")
        lines = [f"{opening}; the best tried, {a.key} = {a.value_text(result['best'])}{unit}: {a.index} quantile "
                 f"{_text(b['estimate'])}, interval [{_text(b['low'])}, {_text(b['high'])}], upper bound "
                 f"{_text(b['upper'])}, {b['n_meeting']}/{b['n']} units meet it"]
    # (pass 70) the index does not see the key there, and its verdict answers nothing
    zero = [v for v, r in sorted(tried.items()) if r["all_zero"]]
    if zero:
        lines.append(f"every figure of {a.index} {a.phase} is exactly 0 rad at {a.key} = "
                     f"{', '.join(a.value_text(v) for v in zero)}{unit}: the index does not see the key there (no "
                     "motion in the phase? perfect sensors?), so its verdict there says nothing about the key")
    if result["breaks"]:
        lines.append("not monotone: " + "; ".join(b["text"] for b in result["breaks"]) +
                     (" (the bracket is read from the favourable end)" if kind == "bracket" else ""))
    lines.append(f"{len(tried)} values, {runs} runs ({runs // max(1, len(tried))} units each, common random numbers)" +
                 (f"; {ran} of them run by this invocation, the others read back from an earlier one" if ran < runs
                  else ""))
    return lines


def _plot(a, tried, result, path, inputs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs = sorted(tried)
    rec = [tried[x] for x in xs]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    finite = [(x, r) for x, r in zip(xs, rec) if math.isfinite(r["estimate"])]
    if finite:
        fx = [x for x, _ in finite]
        est = [r["estimate"] for _, r in finite]
        low = [e - r["low"] if math.isfinite(r["low"]) else 0.0 for e, (_, r) in zip(est, finite)]
        high = [r["high"] - e if math.isfinite(r["high"]) else 0.0 for e, (_, r) in zip(est, finite)]
        ax.errorbar(fx, est, yerr=[low, high], fmt="o", capsize=4, color="C0",
                    label=f"{100 * a.level:.4g} % quantile, {100 * a.confidence:.4g} % interval")
        up = [(x, r["upper"]) for x, r in finite if math.isfinite(r["upper"])]
        ax.plot([x for x, _ in up], [u for _, u in up], "v", color="C1", label="upper bound (the verdict's)")
    # every value tried, on the axis: one without a figure shows there too, never only as an empty plot
    ax.plot(xs, [0.0] * len(xs), "|", ms=12, color="0.4", transform=ax.get_xaxis_transform(), label="values tried")
    for x, r in zip(xs, rec):  # no quantile among the figures: marked, never plotted as a number
        if not math.isfinite(r["estimate"]):
            ax.annotate("beyond every\nfigure", (x, 0.95), xycoords=ax.get_xaxis_transform(), ha="center",
                        va="top", fontsize=7, color="C3")
    ax.axhline(a.requirement, color="k", ls="--", lw=1, label=f"requirement {a.requirement:.3g} rad")
    if result["bracket"]:
        ax.axvspan(*sorted(result["bracket"]), color="C2", alpha=0.15, label="bracket")
    positive = [r[k] for r in rec for k in ("estimate", "low", "high", "upper") if math.isfinite(r[k])]
    if positive and min(positive) > 0:
        ax.set_yscale("log")
    if a.log:
        ax.set_xscale("log")
        ax.set_xlim(a.lo / (a.hi / a.lo) ** 0.05, a.hi * (a.hi / a.lo) ** 0.05)  # the range, whatever has a figure
    else:
        pad = 0.05 * (a.hi - a.lo) or 0.05 * abs(a.lo) or 1.0
        ax.set_xlim(a.lo - pad, a.hi + pad)
    ax.set_xlabel(f"{a.key} [{a.unit or '-'}]")
    ax.set_ylabel(f"{a.index} {a.phase} [rad]")
    ax.set_title(f"{a.direction} {a.key}: {result['outcome'].replace('_', ' ')}", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    savefig(fig, path, inputs, dpi=110, close=True)


def write(a, tried, result, runs, ran, out, inputs, csv_name):
    """Every output of the allocation into out (call inside an output_set)."""
    rows = [header(a, csv_name)] + table(a, tried)
    write_csv(out / CSV, rows, inputs)
    _plot(a, tried, result, out / PLOT, inputs)
    lines = answer_lines(a, tried, result, runs, ran)
    plain = {"allocation": a.plain(), "outcome": result["outcome"], "bracket": result["bracket"],
             "answer": result["answer"], "best": result["best"], "monotone": result["monotone"],
             **({"monotone_note": result["monotone_note"]} if "monotone_note" in result else {}),
             "breaks": [{k: (_json(v) if isinstance(v, float) else v) for k, v in b.items()} for b in result["breaks"]],
             "runs_used": runs, "ran_this_invocation": ran, "summary": lines,
             "values": [{"value": v, "folder": f"values/{r['folder']}", "verdict": "PASS" if r["passed"] else "FAIL",
                         "n": r["n"], "n_missing": r["n_missing"], "n_meeting": r["n_meeting"],
                         "fraction_lower_bound": r["fraction_lower_bound"], "estimate_rad": _json(r["estimate"]),
                         "interval_rad": [_json(r["low"]), _json(r["high"])], "upper_bound_rad": _json(r["upper"]),
                         "note": r["note"]} for v, r in sorted(tried.items())],
             "csv": str(out / CSV), "plot": str(out / PLOT)}
    page = [f"# Allocation: the {a.direction} {a.key}", "", *[f"- {line}" for line in lines], "",
            f"Spec `{a.path}`; each value's sweep (its results.csv, report.md) in `values/<tried>/`.", "",
            "| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])]
    # The CSV's cells as written; the page says n/a with its reason where the CSV holds nan (never a bare nan).
    page += ["| " + " | ".join("n/a" if c == "nan" else str(c) for c in r) + " |" for r in rows[1:]]
    reasons = sorted({r["note"] or "no figure" for r in tried.values()
                      if any(math.isnan(r[k]) for k in ("fraction_lower_bound", "estimate", "low", "high", "upper"))})
    if reasons:
        page += ["", "n/a: " + "; ".join(reasons) + "."]
    page += ["", f"![the index's quantile against {a.key}]({PLOT})", ""]
    write_text(out / PAGE, "\n".join(page), inputs)
    write_text(out / JSON, json_text(plain), inputs)
    return lines
