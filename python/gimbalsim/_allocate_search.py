"""The allocation's search over one key and what its data say: which value to
try next (a scan of the range, then bisection of the bracket), the bracket
read from the favourable end, and where the index is not monotone.

A value's verdict is PASS when, at the stated confidence, at least `level`
of the units meet the requirement (indices.requirement_verdict); that is the
same as the index's one-sided upper bound (indices.quantile_bound) lying at
or below the requirement. "Favourable end": the range's low end when the
largest value is sought (a larger clearance points worse), its high end when
the smallest is.
"""
import math

REL_TOL = 1e-9  # two figures this close are equal (what doubles computed two ways can differ by)


def scan_count(budget):
    """Values of the scan: about half the budget, at least three (both ends
    and one between); the rest bisect the bracket."""
    return min(budget, max(3, budget // 2))


def _round(x, is_int):
    """A value to try as a short number (12 digits: 4.05e-4, not 0.00040500000000000003)."""
    return int(round(x)) if is_int else float(f"{x:.12g}")


def _round_within(x, lo, hi, is_int):
    """x rounded (_round), kept inside [lo, hi]: rounding must never try a value
    outside the range (ends that agree to 12 digits round to a value beyond them)."""
    return min(max(_round(x, is_int), lo), hi)


def _between(a, b, log, is_int):
    """The point between a and b (kept between them): arithmetic, or geometric on a log spacing."""
    return _round_within(math.sqrt(a * b) if log else 0.5 * (a + b), min(a, b), max(a, b), is_int)


def scan_values(a):
    """The scan's values, favourable end first."""
    g = scan_count(a.values)
    if a.log:
        xs = [math.exp(math.log(a.lo) + (math.log(a.hi) - math.log(a.lo)) * k / (g - 1)) for k in range(g)]
    else:
        xs = [a.lo + (a.hi - a.lo) * k / (g - 1) for k in range(g)]
    xs = [a.lo] + [_round_within(x, a.lo, a.hi, a.is_int) for x in xs[1:-1]] + [a.hi]  # ends exactly as given
    xs = sorted(set(xs))  # a short range (whole numbers, or ends alike to 12 digits) repeats values
    return xs if a.direction == "largest" else xs[::-1]


def favourable_first(a, tried):
    """tried ({value: record}) as a list of (value, record), favourable end first."""
    return sorted(tried.items(), key=lambda kv: kv[0], reverse=a.direction == "smallest")


def bracket(a, tried):
    """(last value meeting, first value failing) read from the favourable end:
    every value tried on the favourable side of the first meets. None for
    either when every value, or none from the favourable end, meets."""
    last_pass = None
    for value, rec in favourable_first(a, tried):
        if not rec["passed"]:
            return last_pass, value
        last_pass = value
    return last_pass, None


def next_value(a, tried):
    """The next value to try, or None when the search is done: the scan's
    next value, then the point between the bracket's ends while the budget
    lasts. No bracket (every value meets, or the favourable end fails): done."""
    if len(tried) >= a.values:
        return None
    for v in scan_values(a):
        if v not in tried:
            return v
    meet, fail = bracket(a, tried)
    if meet is None or fail is None:
        return None
    v = _between(meet, fail, a.log, a.is_int)
    return None if v in tried or v in (meet, fail) else v  # whole-number keys: nothing left between


def _worse(x, y):
    """x is worse (larger) than y beyond rounding; inf (no figure) is the worst."""
    if math.isinf(x) or math.isinf(y):
        return x > y
    return x > y + REL_TOL * max(abs(x), abs(y))


def monotonicity(a, tried):
    """Where the data break monotonicity, from the favourable end outwards:
    a verdict PASS after a FAIL, and the index's quantile (estimate, upper
    bound) getting better as the key moves away from the favourable end.
    [{statistic, from, to, ...}], empty when monotone."""
    rows = favourable_first(a, tried)
    breaks = []
    failed_at = None
    for value, rec in rows:
        if not rec["passed"] and failed_at is None:
            failed_at = value
        elif rec["passed"] and failed_at is not None:
            breaks.append({"statistic": "verdict", "from": failed_at, "to": value,
                           "text": f"FAIL at {a.value_text(failed_at)} but PASS at {a.value_text(value)}"})
    for stat in ("estimate", "upper"):
        for (v1, r1), (v2, r2) in zip(rows, rows[1:]):
            x1, x2 = r1[stat], r2[stat]
            if math.isnan(x1) or math.isnan(x2):  # no figure to compare (never a bound: never in a break)
                continue
            if _worse(x1, x2):
                breaks.append({"statistic": stat, "from": v1, "to": v2, "from_rad": x1, "to_rad": x2,
                               "text": f"{stat} {x1:.6g} rad at {a.value_text(v1)} but {x2:.6g} rad at "
                                       f"{a.value_text(v2)} (better away from the favourable end)"})
    return breaks


def best(a, tried):
    """The value closest to meeting: the lowest upper bound (no figure is
    worst), then the highest lower bound of the fraction meeting, then the
    favourable-most."""
    rows = favourable_first(a, tried)
    order = {v: k for k, (v, _) in enumerate(rows)}
    key = lambda kv: (kv[1]["upper"] if not math.isnan(kv[1]["upper"]) else math.inf,  # noqa: E731
                      -kv[1]["fraction_lower_bound"], order[kv[0]])
    return min(rows, key=key)[0]


NO_FIGURE_ANYWHERE = ("no unit at any value tried has a figure (each was refused, stopped, crashed or missed its "
                      "window): no value is better than another, and monotonicity has nothing to judge")


def outcome(a, tried):
    """The search's answer: {"outcome", "bracket", "answer", "best", "breaks"}.
    outcome: "bracket" (a last meeting and a first failing value), "every_value_meets"
    (the answer is the range's far end: the limit lies beyond it), "no_value_meets"
    (no bracket, the best value tried) or "favourable_end_fails" (no bracket: the
    favourable end fails, yet a value further on meets; the index is not monotone).
    Where no unit at any value has a figure, best and monotone are None
    (with monotone_note): a pick from a tie over nothing is no answer."""
    meet, fail = bracket(a, tried)
    if all(r["n_missing"] == r["n"] for r in tried.values()):  # every value ties at "no figure": nothing to compare
        return {"outcome": "no_value_meets", "bracket": None, "answer": None, "best": None, "breaks": [],
                "monotone": None, "monotone_note": NO_FIGURE_ANYWHERE}
    breaks = monotonicity(a, tried)
    if meet is None:  # the favourable end fails; a value that meets elsewhere is a break of monotonicity
        kind = "favourable_end_fails" if any(r["passed"] for r in tried.values()) else "no_value_meets"
        answer = None
    elif fail is None:
        kind, answer = "every_value_meets", meet
    else:
        kind, answer = "bracket", meet
    return {"outcome": kind, "bracket": None if kind != "bracket" else [meet, fail], "answer": answer,
            "best": best(a, tried), "breaks": breaks, "monotone": not breaks}
