"""The pointing budget of a closed-loop sweep: each index per phase over the
ensemble of units, at its level with its distribution-free confidence
interval (indices.quantile_bound), and the requirement's verdict
(indices.requirement_verdict). A quantile the sample count cannot support is
marked as such, never given bare."""
import collections
import math

from . import indices as ix

INTERPRETATION = "ensemble of units, worst time in the phase"
NO_FIGURE = "no unit has a figure the budget takes"  # a stopped unit's row may hold one: never taken


def _json(x):
    """A figure for summary.json: null when there is none (NaN, or +inf for units without one)."""
    return float(x) if math.isfinite(x) else None


def _g(x):
    return "n/a" if x is None else f"{x:.3g}"


def _pct(p):
    return f"{100 * p:.4g} %"


def column_values(spec, rows, metric):
    """A metric of every unit drawn, one value per row: NaN for a unit without
    a figure (crashed, refused, stopped, or a window it missed), which the
    budget counts as worst, never good and never left out (n is the number drawn)."""
    header = spec.header()
    col, status = header.index(metric), header.index("status")
    # A unit that did not end ok (stopped, refused, crashed) has no figure, whatever number its row holds.
    return [float(r[col]) if r[status] == "ok" and r[col] not in ("", "nan") else math.nan for r in rows]


def _missing(spec, rows, metric):
    """The units without a figure the budget takes, by why ("crashed",
    "stopped (velocity_limit)", ...): a Counter, and a Counter of those whose
    row holds a figure for this phase all the same (a stop that came after it)."""
    header = spec.header()
    col, status = header.index(metric), header.index("status")
    counts, with_figure = collections.Counter(), collections.Counter()
    for r in rows:
        s = r[status]
        has_figure = r[col] not in ("", "nan")
        if s == "ok" and has_figure:
            continue
        why = ("crashed" if s == "crashed" else "refused" if s.startswith("refused") else
               "ran without a figure over the window" if s == "ok" else f"stopped ({s})")
        counts[why] += 1
        with_figure[why] += has_figure
    return counts, with_figure


def missing_text(spec, rows, metric):
    """Why the units without a figure have none, counted: "1 crashed, 2
    stopped (velocity_limit)"; a unit that ended ok missed the window. A
    stopped unit whose row holds a figure for this phase (the stop came
    after it) is said to, so the report never reads "no figure" beside a
    row that has one (pass 54)."""
    counts, with_figure = _missing(spec, rows, metric)
    return ", ".join(f"{n} {why}" + (f", {with_figure[why]} of them with a figure over this phase before the stop, "
                                     "not used: a unit that stopped counts as worst" if with_figure[why] else "")
                     for why, n in counts.items())


def entry(spec, rows, index, phase):
    """One cell of the table: the index at its level over the units, as a dict."""
    values = column_values(spec, rows, f"{index.name}_{phase}")
    b = ix.quantile_bound(values, index.level, index.confidence)
    e = {"index": index.name, "phase": phase, "interpretation": INTERPRETATION, "level": index.level,
         "confidence": index.confidence, "n": b.n, "n_missing": b.n_missing, "min_units": b.min_units,
         "supported": b.supported, "estimate_rad": _json(b.estimate), "upper_bound_rad": _json(b.upper),
         "interval_rad": [_json(b.low), _json(b.high)], "two_sided": not math.isnan(b.low), "note": b.reason}
    if b.n and b.n_missing == b.n:  # no unit has a figure the budget takes: say why they have none
        e["note"] = f"{NO_FIGURE} (all {b.n} count as worst): {missing_text(spec, rows, f'{index.name}_{phase}')}"
    elif not b.supported:
        e["note"] = (f"not supported: n={b.n} < {b.min_units} needed for {_pct(index.level)} at "
                     f"{_pct(index.confidence)}")
    finite = [v for v in values if math.isfinite(v)]
    e["worst_with_figure_rad"] = max(finite) if finite else None
    ends = [name for name, x in (("the upper bound", b.upper), ("the interval's upper end", b.high))
            if math.isinf(x) and x > 0 and b.n_missing and b.n_missing < b.n]
    if ends:  # null in summary.json: say why, as the estimate's note does (pass 44: a bare null)
        e["bound_note"] = (f"{' and '.join(ends)} beyond every figure: on the {b.n_missing} of {b.n} units "
                           "without one, counted as worst")
    if math.isinf(b.estimate):
        # The quantile falls on units without a figure (stopped, or a window they missed): they count as
        # worst, so the quantile is unbounded; say so, with the worst figure there is, never a bare n/a.
        e["estimate_note"] = (f"beyond every figure: it falls on the {b.n_missing} of {b.n} units without one "
                              f"({missing_text(spec, rows, f'{index.name}_{phase}')}), counted as worst")
    unused = sum(_missing(spec, rows, f"{index.name}_{phase}")[1].values())  # stopped after the phase
    if unused and "estimate_note" not in e and b.n_missing < b.n:  # those notes give missing_text, which says it
        e["unused_note"] = (f"{unused} of the {b.n_missing} units without a figure the budget takes stopped after "
                            "this phase and hold its figure, not used: a unit that stopped counts as worst")
    if index.requirement is not None:
        v = ix.requirement_verdict(values, index.requirement, index.level, index.confidence)
        note = "; ".join(t for t in (v.reason, v.note) if t)
        e["requirement"] = {"requirement_rad": v.requirement, "verdict": v.text, "n_meeting": v.n_meeting,
                            "fraction_meeting": v.fraction, "fraction_lower_bound": v.lower,
                            **({"verdict_note": note} if note else {})}
    return e


def grid_points(spec, rows):
    """[(label, rows)]: a budget per grid point, "key=value, ..." (pass 106: every point gets the same draws, so
    pooled, each unit drawn counted once per point: 2 units read n=24 and PASS); [("", rows)] for one point."""
    keys = spec.design.grid_keys
    header = spec.header()
    points = {}  # in the grid's order, as the rows come
    for r in rows:
        points.setdefault(", ".join(f"{k}={r[header.index(k)]}" for k in keys), []).append(r)
    return list(points.items()) if len(points) > 1 else [("", rows)]


def rows_of(spec, rows, e):
    """The rows of an entry's grid point (every row when it names none)."""
    return dict(grid_points(spec, rows))[e["grid_point"]] if e.get("grid_point") else rows


def table(spec, rows):
    """Every index of the spec in every phase: [entry]; per grid point, each naming it (grid_point)."""
    return [{**entry(spec, point_rows, index, phase), **({"grid_point": point} if point else {})}
            for point, point_rows in grid_points(spec, rows)
            for phase, _ in spec.closed.phases for index in spec.closed.indices]


def relative_width(e):
    """(high - low) / estimate of an entry's interval; inf when it has none;
    0 for an interval that is one point (every figure alike, 0 included)."""
    lo, hi = e["interval_rad"]
    if lo is None or hi is None:
        return math.inf
    if hi == lo:
        return 0.0
    if not e["estimate_rad"]:
        return math.inf
    return (hi - lo) / e["estimate_rad"]


def _estimate_text(e):
    """The empirical quantile as text; an unbounded one says why and gives the worst figure there is."""
    if "estimate_note" not in e:
        return f"{_g(e['estimate_rad'])} rad"
    worst = e["worst_with_figure_rad"]
    return e["estimate_note"] + ("" if worst is None else f"; the worst unit with a figure: {_g(worst)} rad")


def _bound_text(x, e):
    """An interval end: a number, or (None with units missing) beyond every figure."""
    return "beyond every figure" if x is None and e["n_missing"] else _g(x)


def cell(e):
    """The index as text: the estimate with its interval, or why there is none; and, where stopped units
    hold a figure of this phase the budget did not take, that (pass 55: said only where the quantile fell
    on them)."""
    unused = f"; {e['unused_note']}" if "unused_note" in e else ""
    if e["n_missing"] == e["n"]:
        return e["note"]  # no unit has a figure: no quantile to quote
    if not e["supported"]:
        return f"{e['note']} (empirical {_pct(e['level'])} quantile: {_estimate_text(e)}){unused}"
    lo, hi = e["interval_rad"]
    ci = f"[{_bound_text(lo, e)}, {_bound_text(hi, e)}]" if e["two_sided"] else "(one-sided only)"
    upper = e["upper_bound_rad"]
    return (f"{_estimate_text(e)}, {_pct(e['confidence'])} CI {ci}, upper bound "
            f"{_bound_text(upper, e)}{' rad' if upper is not None else ''}{unused}")


def verdict_text(e):
    r = e.get("requirement")
    if r is None:
        return ""
    return (f"{r['verdict']} against {r['requirement_rad']:.3g} rad: {r['n_meeting']}/{e['n']} units meet it, "
            + (f"P(a unit meets it) >= {r['fraction_lower_bound']:.4f}" if math.isfinite(r['fraction_lower_bound'])
               else "no bound on P(a unit meets it)") + f" at {_pct(e['confidence'])} "
            f"(needs {e['level']:.4f})" + (f"; {r['verdict_note']}" if "verdict_note" in r else ""))


def console_lines(entries):
    lines = [f"budget ({INTERPRETATION}):"]
    for e in entries:
        v = verdict_text(e)
        point = f" [{e['grid_point']}]" if e.get("grid_point") else ""
        lines.append(f"  {e['index']} {e['phase']}{point} at {_pct(e['level'])}: {cell(e)}; n={e['n']}"
                     + (f"; {v}" if v else ""))
    return lines
